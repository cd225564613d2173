/* test_statics.c -- static equilibrium (csrc/analyze/statics.c, docs/method.md section 7.3): a
 * cantilever rolled up into a full circle by an end moment (the exact solution has constant
 * strain, docs/method.md section 8), whose Newton iterations (tangents) the chain retraction, the
 * tangent predictor and the simplified corrections keep at about one per load step for any
 * number of elements and axial stiffness; steps = 0, Newton at the full load from the start,
 * which leaves an equilibrium where it is; and the mechanisms without an equilibrium
 * (csrc/analyze/static_free.c): the pair table's fixed axes, the motions found, a solve that stops
 * at once, and the free motions without load that leave an equilibrium in place. */
#include "check.h"
#include "model.h"

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
  const double k[6] = {stiff, 1.0, stiff, stiff, stiff, stiff};
  straight_beam(n, 1.0, k, car, el, &pair);
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

/* steps = 0 (and -1, Newton alone) from an equilibrium at the full load: one tangent, whose step
 * is below the tolerance, and the poses as given (with load steps the solve would unload it
 * first). */
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
  /* steps = -1: Newton alone, the same from an equilibrium */
  if (CHECK(phm_static(m, P, 0.0, -1, 1e-10, P2, lam, &it, &err) == PHM_OK, "%s", err.msg)) {
    check("poses kept (steps = -1)", maxdiff(16 * (n + 1), P, P2), 1e-12);
    CHECK(it == 1, "%d Newton iterations (steps = -1)", it);
  }
  check_refused("steps = -2", phm_static(m, P, 0.0, -2, 1e-10, P2, lam, &it, &err), PHM_EINVAL,
                &err, "load steps must be >= -1");
  free(P);
  phm_model_free(m);
}

/* psi_c of a pair type at relative pose h: W^C^T psi = 0, Phi^T psi = e_c (Gaussian elimination
 * with partial pivoting on [W^C Phi]^T, written out here apart from static_free.c's). */
static void allowed_twist(int type, double pitch, const double h[16], int c, double psi[6]) {
  double W[36], Phi[36], A[6][7];
  int m = phm_pair_type(type)->m;
  phm_pair_kin(type, pitch, h, NULL, NULL, W, Phi, NULL);
  for (int i = 0; i < 6; i++) {
    for (int q = 0; q < 6; q++) A[i][q] = i < m ? W[6 * q + i] : Phi[6 * q + i - m];
    A[i][6] = i == m + c;
  }
  for (int k = 0; k < 6; k++) {
    int p = k;
    for (int i = k + 1; i < 6; i++)
      if (fabs(A[i][k]) > fabs(A[p][k])) p = i;
    for (int q = 0; q < 7; q++) {
      double t = A[k][q];
      A[k][q] = A[p][q];
      A[p][q] = t;
    }
    for (int i = 0; i < 6; i++)
      if (i != k) {
        double f = A[i][k] / A[k][k];
        for (int q = k; q < 7; q++) A[i][q] -= f * A[k][q];
      }
  }
  for (int i = 0; i < 6; i++) psi[i] = A[i][6] / A[i][i];
}

/* The unit direction of a twist: its rotation axis, or its translation when it has none. */
static void twist_direction(const double t[6], double d[3]) {
  int rot = fabs(t[0]) + fabs(t[1]) + fabs(t[2]) > 1e-12;
  const double *u = rot ? t : t + 3;
  double n = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (int i = 0; i < 3; i++) d[i] = u[i] / n;
}

/* The pair table's axes_a, axes_b (bit c: psi_c's direction fixed in F_a, in F_b at every
 * relative pose), which let static_free.c count a dead load's work as the same everywhere: at
 * random joint coordinates of every type, psi_c's direction in F_b (psi_c) and in F_a (Ad_h
 * psi_c) against its direction at other random coordinates. */
static void pair_table_axes_are_fixed(void) {
  rand_seed(7);
  for (int type = 0; type < phm_pair_type_count(); type++) {
    const phm_pair_type_info *ti = phm_pair_type(type);
    double pitch = strcmp(ti->name, "helical") == 0 ? 0.2 : 0.0, worst = 0;
    for (int c = 0; c < 6 - ti->m; c++)
      for (int side = 0; side < 2; side++) {
        if (!((side ? ti->axes_b : ti->axes_a) >> c & 1)) continue;
        double d0[3] = {0};
        for (int trial = 0; trial < 20; trial++) {
          double x[6], h[16], psi[6], Ad[36], t[6], d[3];
          rand_joint_coordinates(type, 0, x);
          phm_pair_type_pose(type, pitch, x, h);
          allowed_twist(type, pitch, h, c, psi);
          phm_se3_Ad(h, Ad);
          for (int i = 0; i < 6; i++) {
            t[i] = side ? psi[i] : 0.0;
            for (int q = 0; !side && q < 6; q++) t[i] += Ad[6 * i + q] * psi[q];
          }
          twist_direction(t, d);
          if (trial == 0) memcpy(d0, d, sizeof d);
          for (int i = 0; i < 3; i++) worst = fmax(worst, fabs(d[i] - d0[i]));
        }
      }
    char name[64];
    snprintf(name, sizeof name, "%s: fixed directions", ti->name);
    check(name, worst, 1e-12);
  }
}

/* A unit carrier (carrier_unit) with centre of mass com, on a pair from the ground of type
 * `type` whose frames turn local z to world `zaxis` (0, 1, 2), with an effort actuator of
 * `effort` on its first coordinate (0: none), under gravity g (NULL: none). */
static phm_model *one_body(const char *type, int zaxis, const double com[3], double effort,
                           const double *g) {
  phm_carrier_desc car;
  phm_pair_desc pr;
  phm_actuator_desc act;
  carrier_unit(&car);
  memcpy(car.com, com, sizeof car.com);
  memset(&pr, 0, sizeof pr);
  memset(&act, 0, sizeof act);
  pr.type = type ? pair_code(type) : 0;
  pr.a = -1;
  pr.b = 0;
  for (int i = 0; i < 3; i++) /* the rotation whose z column is e_zaxis: a cyclic permutation */
    pr.Ta[4 * i + (i - zaxis + 5) % 3] = pr.Tb[4 * i + (i - zaxis + 5) % 3] = 1.0;
  pr.Ta[15] = pr.Tb[15] = 1.0;
  act.pair = 0;
  act.kind = PHM_ACT_EFFORT;
  act.vec[0] = 1.0;
  act.law = (phm_law){.kind = PHM_LAW_CONSTANT, .amplitude = effort};
  phm_model_desc d = {.ncarriers = 1, .carriers = &car, .npairs = type ? 1 : 0, .pairs = &pr,
                      .nactuators = type && effort != 0, .actuators = &act};
  if (g) memcpy(d.gravity, g, sizeof d.gravity);
  return create_model(&d);
}

/* The motions phm_static_free finds, with the numbers the loads give by hand: a revolute about
 * world z turned by 0.3 N m (force 0.3, twist about z); a body held by nothing under gravity
 * (force m |g| = 9.81 N, a translation along g); a slider along z under gravity along z (-9.81 N
 * per m). None for a pendulum (gravity across its axis: it hangs) nor for a revolute about z
 * without load. phm_static stops with them at once (at most the unloaded start's tangent and
 * the first load step's 12), and solves the free body and the revolute without load in place. */
static void free_motions_are_found_and_refused(void) {
  const double g[3] = {0, 0, -9.81}, o[3] = {0, 0, 0}, off[3] = {0.2, 0, 0};
  struct {
    const char *type;
    int zaxis;
    const double *com, *g;
    double effort, force, twist[6];
    int n;
  } cases[] = {
      {"revolute", 2, o, NULL, 0.3, 0.3, {0, 0, 1, 0, 0, 0}, 1},
      {NULL, 2, o, g, 0.0, 9.81, {0, 0, 0, 0, 0, -1}, 1},
      {"prismatic", 2, o, g, 0.0, -9.81, {0, 0, 0, 0, 0, 1}, 1},
      {"revolute", 1, off, g, 0.0, 0, {0}, 0},
      {"revolute", 2, off, NULL, 0.0, 0, {0}, 0},
      {NULL, 2, o, NULL, 0.0, 0, {0}, 0},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    phm_model *m = one_body(cases[k].type, cases[k].zaxis, cases[k].com, cases[k].effort, cases[k].g);
    if (!m) return;
    phm_free_motion fm[4];
    unsigned char moving[4];
    int n = -1, it = 0;
    double P[16], lam[6], reached = -1;
    phm_error err;
    if (CHECK(phm_static_free(m, NULL, 0.0, 4, fm, moving, NULL, &n, &err) == PHM_OK, "%s", err.msg) &&
        CHECK(n == cases[k].n, "case %zu: %d motions, expected %d", k, n, cases[k].n) && n == 1) {
      check("generalized force", fabs(fm[0].force - cases[k].force), 1e-12);
      check("twist", maxdiff(6, fm[0].twist, cases[k].twist), 1e-12);
      CHECK(moving[0] == 1 && fm[0].carrier == 0 && fm[0].pair == (cases[k].type ? 0 : -1),
            "case %zu: moving %d, carrier %d, pair %d", k, moving[0], fm[0].carrier, fm[0].pair);
    }
    phm_status st = phm_static_monitored(m, NULL, 0.0, 10, 1e-10, NULL, NULL, P, lam, &it,
                                         &reached, &err);
    if (cases[k].n) {
      CHECK(st == PHM_ESOLVER && strstr(err.msg, "no static equilibrium"), "case %zu: %s", k, err.msg);
      CHECK(it <= 13 && reached == 0, "case %zu: %d iterations, load factor %g", k, it, reached);
    } else if (CHECK(st == PHM_OK, "case %zu: %s", k, err.msg) && !cases[k].g) {
      CHECK(maxdiff(16, P, m->car[0].H0) < 1e-14, "case %zu: moved %g", k, maxdiff(16, P, m->car[0].H0));
    }
    phm_model_free(m);
  }
}

CHECK_MAIN(CHECK_CASE(pair_table_axes_are_fixed), CHECK_CASE(free_motions_are_found_and_refused),
           CHECK_CASE(rollup_takes_at_most_two_tangents_per_load_step),
           CHECK_CASE(tip_load_reuses_its_factorizations),
           CHECK_CASE(zero_steps_leave_an_equilibrium_in_place))
