/* test_statics.c -- static equilibrium (csrc/solve/statics.c, docs/method.md section 7.3): a
 * cantilever rolled up into a full circle by an end moment (the exact solution has constant
 * strain, docs/method.md section 8), whose Newton iterations (tangents) the chain retraction, the
 * tangent predictor and the simplified corrections keep at about one per load step for any
 * number of elements and axial stiffness; and steps = 0, Newton at the full load from the start,
 * which leaves an equilibrium where it is. */
#include "check.h"

/* A straight cantilever of n elements along x, clamped at node 0 (EI = 1, L = 1; axial, shear
 * and torsional stiffness `stiff` times EI/L^2, the second bending stiffness too, so that it
 * stays planar), bent about y: by the body-frame end moment 2 pi EI/L (`tip` 0: a follower
 * moment, which in the plane has the potential -M theta; it rolls the beam up into a circle), or
 * by the dead tip force P = 3 EI/L^2 along z (`tip` 1). */
static phm_model *cantilever_model(int n, double stiff, int tip) {
  phm_carrier_desc *car = calloc((size_t)n + 1, sizeof *car);
  phm_element_desc *el = calloc((size_t)n, sizeof *el);
  phm_pair_desc pair;
  phm_load_desc load;
  memset(&pair, 0, sizeof pair);
  double h = 1.0 / n, ks = stiff * 1.0;
  for (int c = 0; c <= n; c++) {
    carrier_unit(&car[c]);
    car[c].H0[3] = c * h;
  }
  for (int e = 0; e < n; e++) {
    el[e].a = e;
    el[e].b = e + 1;
    el[e].h = h;
    double k[6] = {ks, 1.0, ks, ks, ks, ks};
    for (int i = 0; i < 6; i++) el[e].K[7 * i] = k[i];
    el[e].eps_hat[3] = 1.0;
  }
  for (int i = 0; i < 4; i++) pair.Ta[5 * i] = pair.Tb[5 * i] = 1.0;
  pair.type = pair_code("fixed");
  pair.a = -1;
  pair.b = 0;
  load = (phm_load_desc){.carrier = n, .reaction = -1, .w = {0, -2.0 * CHECK_PI, 0, 0, 0, 0},
                         .world = 0, .law = {.kind = PHM_LAW_CONSTANT, .amplitude = 1.0}};
  if (tip) {
    load.w[1] = 0.0;
    load.w[5] = 3.0;
    load.world = 1;
  }
  phm_model_desc d = {.ncarriers = n + 1, .carriers = car, .nelements = n, .elements = el,
                      .npairs = 1, .pairs = &pair, .nloads = 1, .loads = &load};
  phm_model *m = create_model(&d);
  free(car);
  free(el);
  return m;
}

/* Under H exp(delta) per carrier the tangent step of a bending beam stretches its elements at
 * second order, and the stiff roll-up took 1158 iterations in 8 load steps (benchmarks/
 * statics_newton.py); the chain retraction moves the strains by their linear prediction, and
 * the roll-up's strains are constant: measured 9 iterations for 8 load steps, the unloaded
 * start's included, soft and stiff 1e4, N = 10 and 40 (the chain retraction alone 9 to 16; 33
 * and 194 under H exp(delta)). */
static void rollup_takes_at_most_two_tangents_per_load_step(void) {
  const int steps = 8, ns[2] = {10, 40};
  const double stiffs[2] = {1.0, 1e4};
  for (int is = 0; is < 2; is++)
    for (int in = 0; in < 2; in++) {
      int n = ns[in], it = 0;
      phm_model *m = cantilever_model(n, stiffs[is], 0);
      if (!m) return;
      double *P = malloc(sizeof(double) * 16 * (size_t)(n + 1)), lam[6];
      phm_error err;
      phm_status st = phm_static(m, NULL, 0.0, steps, 1e-10, P, lam, &it, &err);
      if (CHECK(st == PHM_OK, "stiffness x%g, N = %d: %s", stiffs[is], n, err.msg)) {
        /* the tip back at the root, turned by 2 pi */
        const double *T = P + 16 * n;
        double dp = fmax(fabs(T[3]), fmax(fabs(T[7]), fabs(T[11])));
        double dr = fmax(fabs(T[0] - 1.0), fmax(fabs(T[2]), fabs(T[8])));
        CHECK(dp < 1e-9 && dr < 1e-9, "stiffness x%g, N = %d: tip %.3g m, %.3g from its start",
              stiffs[is], n, dp, dr);
        CHECK(it <= 2 * steps, "stiffness x%g, N = %d: %d Newton iterations for %d load steps",
              stiffs[is], n, it, steps);
      }
      free(P);
      phm_model_free(m);
    }
}

/* The dead tip load in 10 load steps: each starts with the tangent predictor (the last
 * factorization on the new load's residual) and goes on with simplified corrections while they
 * contract, a new tangent only when they do not: measured 11 iterations (tangents) for N = 20
 * and 200 with axial stiffness 1e2 EI/L^2, 20 with 1e4 (31 to 36 with a tangent per
 * correction and no predictor). */
static void tip_load_reuses_its_factorizations(void) {
  const int steps = 10, ns[2] = {20, 200};
  const double stiffs[2] = {1e2, 1e4};
  for (int is = 0; is < 2; is++)
    for (int in = 0; in < 2; in++) {
      int n = ns[in], it = 0;
      phm_model *m = cantilever_model(n, stiffs[is], 1);
      if (!m) return;
      double *P = malloc(sizeof(double) * 16 * (size_t)(n + 1)), lam[6];
      phm_error err;
      phm_status st = phm_static(m, NULL, 0.0, steps, 1e-10, P, lam, &it, &err);
      if (CHECK(st == PHM_OK, "stiffness x%g, N = %d: %s", stiffs[is], n, err.msg))
        CHECK(it <= 2 * steps + 1, "stiffness x%g, N = %d: %d Newton iterations for %d load steps",
              stiffs[is], n, it, steps);
      free(P);
      phm_model_free(m);
    }
}

/* steps = 0 from an equilibrium at the full load: one tangent, whose step is below the
 * tolerance, and the poses as given (with load steps the solve would unload it first). */
static void zero_steps_leave_an_equilibrium_in_place(void) {
  int n = 12, it = 0;
  phm_model *m = cantilever_model(n, 1.0, 0);
  if (!m) return;
  double *P = malloc(sizeof(double) * 32 * (size_t)(n + 1)), *P2 = P + 16 * (n + 1), lam[6];
  phm_error err;
  if (CHECK(phm_static(m, NULL, 0.0, 8, 1e-10, P, lam, &it, &err) == PHM_OK, "%s", err.msg) &&
      CHECK(phm_static(m, P, 0.0, 0, 1e-10, P2, lam, &it, &err) == PHM_OK, "%s", err.msg)) {
    check("poses kept", maxdiff(16 * (n + 1), P, P2), 1e-12);
    CHECK(it == 1, "%d Newton iterations", it);
  }
  check_refused("steps = -1", phm_static(m, P, 0.0, -1, 1e-10, P2, lam, &it, &err), PHM_EINVAL,
                &err, "load steps must be >= 0");
  free(P);
  phm_model_free(m);
}

CHECK_MAIN(CHECK_CASE(rollup_takes_at_most_two_tangents_per_load_step),
           CHECK_CASE(tip_load_reuses_its_factorizations),
           CHECK_CASE(zero_steps_leave_an_equilibrium_in_place))
