/* test_initial.c -- csrc/dae/initial.c, the consistent initial values: after dae_consistent_ic
 * the DAE's residual F(t, y, y') vanishes (kinematic, momentum and constraint rows), at random
 * poses and twists of a chain of se3 elements with lumped or consistent masses (the consistent
 * ones solved by projected conjugate gradients), free or held by a fixed pair to the ground and
 * a revolute pair closing a loop. Tolerance 1e-10 of the rows' scale. */
#include "check.h"
#include "dae.h"

enum { NC = 6 };

static void ic_meets_the_residual(const char *name, int consistent, int pairs) {
  phm_carrier_desc car[NC];
  phm_element_desc el[NC - 1];
  phm_pair_desc pr[2];
  memset(el, 0, sizeof el);
  memset(pr, 0, sizeof pr);
  double H[16], E[16], x[6] = {0.1, -0.2, 0.15, 0.3, 0.02, -0.01};
  rand_pose(H, 0.5);
  pose_expm(x, E);
  for (int c = 0; c < NC; c++) {
    carrier_unit(&car[c]);
    rand_spd6(car[c].M, 0.5);
    car[c].mass = car[c].M[21];
    memcpy(car[c].H0, H, sizeof H);
    for (int i = 0; i < 6; i++) car[c].t0[i] = rand11();
    double Hn[16];
    phm_se3_compose(H, E, Hn);
    memcpy(H, Hn, sizeof H);
  }
  for (int e = 0; e < NC - 1; e++) {
    el[e].a = e;
    el[e].b = e + 1;
    el[e].h = 0.3;
    rand_spd6(el[e].K, 50.0);
    rand_spd6(el[e].D, 0.5);
    memcpy(el[e].eps_hat, x, sizeof x);
    for (int i = 0; i < 6; i++) el[e].eps_hat[i] /= el[e].h;
    el[e].mass = consistent ? PHM_MASS_CONSISTENT : PHM_MASS_LUMPED;
    rand_spd6(el[e].Ms, 3.0);
  }
  /* a clamp of node 0 where it is, and a revolute from node 2 to node 5 (a loop the projection
   * closes) */
  pr[0].type = pair_code("fixed");
  pr[0].a = -1;
  pr[0].b = 0;
  memcpy(pr[0].Ta, car[0].H0, sizeof H);
  for (int i = 0; i < 4; i++) pr[0].Tb[5 * i] = 1.0;
  pr[1].type = pair_code("revolute");
  pr[1].a = 2;
  pr[1].b = 5;
  rand_pose(pr[1].Ta, 0.3);
  rand_pose(pr[1].Tb, 0.3);
  phm_model_desc d = {.ncarriers = NC, .carriers = car, .nelements = NC - 1, .elements = el,
                      .npairs = pairs, .pairs = pr, .gravity = {0.3, -1.0, -9.81}};
  phm_model *m = create_model(&d);
  if (!m) return;
  dae_t dae;
  phm_error err;
  if (dae_init(&dae, m, &err)) {
    check_fail("%s: dae_init: %s", name, err.msg);
    phm_model_free(m);
    return;
  }
  int n = dae.n;
  double *y = calloc((size_t)n * 3, sizeof(double)), *yp = y + n, *F = yp + n;
  double Hs[16 * NC], tw[6 * NC];
  for (int c = 0; c < NC; c++) {
    memcpy(Hs + 16 * c, car[c].H0, sizeof H);
    memcpy(tw + 6 * c, car[c].t0, 6 * sizeof(double));
  }
  dae.tref = phm_model_tref(m, 0.0, NULL);
  if (dae_consistent_ic(&dae, 0.0, Hs, tw, NULL, m->xref0, 0, y, yp, &err)) {
    check_fail("%s: dae_consistent_ic: %s", name, err.msg);
  } else {
    dae_residual(&dae, 0.0, y, yp, F);
    double worst = 0, scale = 1.0;
    for (int i = 0; i < dae.ie; i++) scale = fmax(scale, fabs(yp[i]));
    for (int i = 0; i < n; i++)
      if (i < dae.ie || i >= dae.il) worst = fmax(worst, fabs(F[i]));
    check_worst(name, worst / scale, 1e-10);
  }
  free(y);
  dae_free(&dae);
  phm_model_free(m);
}

static void consistent_initial_values_meet_the_residual(void) {
  for (int trial = 0; trial < 5; trial++) {
    ic_meets_the_residual("F(y0, y0') = 0: free chain, lumped mass", 0, 0);
    ic_meets_the_residual("F(y0, y0') = 0: free chain, consistent mass", 1, 0);
    ic_meets_the_residual("F(y0, y0') = 0: clamped chain with a loop, lumped mass", 0, 2);
    ic_meets_the_residual("F(y0, y0') = 0: clamped chain with a loop, consistent mass", 1, 2);
  }
}

CHECK_MAIN(CHECK_CASE(consistent_initial_values_meet_the_residual))
