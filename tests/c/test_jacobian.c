/* test_jacobian.c -- the values of the DAE Jacobian dF/dy + cj dF/dy' (csrc/dae/jacobian.c)
 * against central differences of the residual (csrc/dae/residual.c), column by column, at random
 * bent, twisted and moving states with quaternions off the unit sphere (the residual normalizes
 * them). Per component: carriers alone (their kinematic and gyroscopic rows, in closed form), se3
 * elements (closed form: the elastic, geometric and damping parts through the quaternion chart;
 * consistent masses), every pair type (closed form: rows, G^T lambda, G^T mu, joint rates; driven,
 * with driven coordinates, with a dropped row), and a model with a spring-damper, an interaction
 * and a PD actuator too (phm_applied_tangent); each with the kinematic rows in the world frame and
 * in the body frames of the pairs' carriers (dae_body_kinematics, IDA's). Reference step 1e-6 (x
 * max(1, |y_j|)): truncation ~ 1e-12 and round-off ~ 1e-10 relative to entries of order 1..1e3, so
 * the closed form is held to 1e-7 relative. The constraint rows alone (dae_constraint_rows) are
 * held to the residual's bit for bit, and the dense matrix the dense LUs take
 * (dae_jacobian_to_dense) to the sparse one entry by entry. */
#include "check.h"
#include "dae.h"

enum { MAXC = 6 };

typedef struct {
  phm_carrier_desc car[MAXC];
  phm_element_desc el[MAXC];
  phm_pair_desc pair[2];
  phm_load_desc load[1];
  phm_spring_desc spr[1];
  phm_actuator_desc act[2];
  phm_component_desc comp[7];
  phm_model_desc d;
} builder;

/* nc carriers with random inertia, placed along a bent and twisted chain; ne = nc - 1 elements
 * between consecutive ones (random K, D, curved unstressed shape) when elements != 0. */
static void chain(builder *b, int nc, int elements) {
  memset(b, 0, sizeof *b);
  double H[16], E[16], x[6];
  rand_pose(H, 1.0);
  for (int c = 0; c < nc; c++) {
    carrier_unit(&b->car[c]);
    rand_spd6(b->car[c].M, 1.0 + c);
    b->car[c].mass = b->car[c].M[21];
    memcpy(b->car[c].H0, H, sizeof H);
    for (int i = 0; i < 6; i++) x[i] = 0.3 * rand11();
    x[3] += 0.4;
    pose_expm(x, E);
    double Hn[16];
    phm_se3_compose(H, E, Hn);
    memcpy(H, Hn, sizeof H);
  }
  b->d.ncarriers = nc;
  b->d.carriers = b->car;
  if (elements) {
    for (int e = 0; e + 1 < nc; e++) {
      phm_element_desc *el = &b->el[e];
      el->a = e;
      el->b = e + 1;
      el->h = 0.4;
      rand_spd6(el->K, 50.0);
      rand_spd6(el->D, 0.5);
      el->eps_hat[0] = 0.5 * rand11();
      el->eps_hat[2] = rand11();
      el->eps_hat[3] = 1.0;
    }
    b->d.nelements = nc - 1;
    b->d.elements = b->el;
  }
}

/* The state at the model's poses with random twists, rates and quaternion norms near 1. */
static void rand_state(const dae_t *d, double *y, double *yp) {
  for (int i = 0; i < d->n; i++) {
    y[i] = rand11();
    yp[i] = rand11();
  }
  for (int c = 0; c < d->m->nc; c++) {
    double *yc = y + PHM_NSTATE * c;
    double R[9], q[4], s = 1.0 + 0.05 * rand11();
    for (int i = 0; i < 3; i++) {
      for (int j = 0; j < 3; j++) R[3 * i + j] = d->m->car[c].H0[4 * i + j];
      yc[4 + i] = d->m->car[c].H0[4 * i + 3];
    }
    phm_quat_from_rot(R, q);
    for (int i = 0; i < 4; i++) yc[i] = s * q[i];
    for (int i = 7; i < 13; i++) yc[i] = 2.0 * rand11();
  }
}

/* Worst relative errors of dae_jacobian against central differences: rows of the carriers and
 * pairs (the ledger rows keep only their diagonal in the pattern, csrc/dae/jacobian.c), entries
 * outside the pattern included (their reference must vanish). */
static void compare_dae(const char *name, builder *b, double tol, int planar) {
  phm_model *m = create_model(&b->d);
  if (!m) return;
  dae_t d;
  phm_error err;
  SUNContext ctx;
  if (phm_sun_context_create(&ctx) ||
      (planar ? dae_planar_init(&d, m, planar - 1, &err) : dae_init(&d, m, &err)) ||
      dae_jacobian_pattern(&d, &err)) {
    check_fail("%s: set-up", name);
    phm_model_free(m);
    return;
  }
  int n = d.n;
  SUNMatrix J = SUNSparseMatrix(n, n, d.nnz, CSC_MAT, ctx), A = SUNDenseMatrix(n, n, ctx);
  double *y = malloc(sizeof(double) * (size_t)n * 6), *yp = y + n, *r0 = yp + n, *yy = r0 + n,
         *ypp = yy + n, *rp = ypp + n, *rm = malloc(sizeof(double) * (size_t)n);
  double *dense = calloc((size_t)n * n, sizeof(double));
  for (int trial = 0; trial < 6; trial++) {
    /* trials 3-5: the kinematic rows of the pairs' carriers in their body frames (IDA's) */
    int body = trial >= 3;
    dae_body_kinematics(&d, body);
    if (planar) { /* the reduced state: any values, a quaternion (q_w, q_k) off the unit circle */
      for (int i = 0; i < n; i++) {
        y[i] = rand11();
        yp[i] = rand11();
      }
      for (int c = 0; c < m->nc; c++) {
        double a = 3.0 * rand11(), s = 1.0 + 0.05 * rand11();
        y[PHM_NSTATE_PLANAR * c] = s * cos(a);
        y[PHM_NSTATE_PLANAR * c + 1] = s * sin(a);
      }
    } else
      rand_state(&d, y, yp);
    double t = 0.1, cj = 37.0 * (1 + trial % 3);
    d.tref = 0.5;
    /* the constraint rows alone (the generalized-alpha's at the step's end), with the data of the
     * previous trial's state still in d: the very bits of the full residual's rows */
    dae_constraint_rows(&d, t, y, rp);
    dae_residual(&d, t, y, yp, r0);
    CHECK(!memcmp(rp + d.il, r0 + d.il, sizeof(double) * (size_t)(n - d.il)),
          "%s: dae_constraint_rows = the residual's constraint rows, bit for bit", name);
    if (dae_jacobian(&d, t, cj, y, yp, r0, J)) {
      check_fail("%s: dae_jacobian failed", name);
      break;
    }
    sunindextype *cp = SUNSparseMatrix_IndexPointers(J), *ri = SUNSparseMatrix_IndexValues(J);
    double *val = SUNSparseMatrix_Data(J);
    memset(dense, 0, sizeof(double) * (size_t)n * n);
    for (int j = 0; j < n; j++)
      for (sunindextype k = cp[j]; k < cp[j + 1]; k++) dense[(size_t)ri[k] * n + j] = val[k];
    /* the dense LUs' matrix (IDA's and the generalized-alpha's): every entry the sparse one's,
     * bit for bit, and 0 off its pattern, over whatever the matrix held before */
    double *a = SUNDenseMatrix_Data(A);
    for (long i = 0; i < (long)n * n; i++) a[i] = NAN;
    dae_jacobian_to_dense(J, A);
    long differ = 0;
    for (int i = 0; i < n; i++)
      for (int j = 0; j < n; j++)
        differ += memcmp(&SM_ELEMENT_D(A, i, j), &dense[(size_t)i * n + j], sizeof(double)) != 0;
    CHECK(differ == 0, "%s: dae_jacobian_to_dense = the sparse Jacobian entry by entry, 0 off its "
          "pattern (%ld of %d x %d differ)", name, differ, n, n);
    double err = 0, big = 0;
    for (int j = 0; j < n; j++) {
      double h = 1e-6 * fmax(1.0, fabs(y[j]));
      memcpy(yy, y, sizeof(double) * (size_t)n);
      memcpy(ypp, yp, sizeof(double) * (size_t)n);
      yy[j] += h;
      ypp[j] += cj * h;
      dae_residual(&d, t, yy, ypp, rp);
      yy[j] -= 2 * h;
      ypp[j] -= 2 * cj * h;
      dae_residual(&d, t, yy, ypp, rm);
      for (int i = 0; i < n; i++) {
        if (i >= d.ie && i < d.il && i != j) continue; /* ledger rows: diagonal only */
        double ref = (rp[i] - rm[i]) / (2 * h);
        err = fmax(err, fabs(ref - dense[(size_t)i * n + j]));
        big = fmax(big, fabs(ref));
      }
    }
    if (body)
      CHECK(err / big <= tol, "%s, kinematic rows in the body frame: error %.3e (tol %.1e)", name,
            err / big, tol);
    else
      check_worst(name, err / big, tol);
  }
  free(y);
  free(rm);
  free(dense);
  SUNMatDestroy(J);
  SUNMatDestroy(A);
  dae_free(&d);
  SUNContext_Free(&ctx);
  phm_model_free(m);
}

static void compare(const char *name, builder *b, double tol) { compare_dae(name, b, tol, 0); }

static void carriers_and_gravity_are_closed_form(void) {
  static builder b;
  chain(&b, 3, 0);
  compare("J = central FD: 3 free carriers (kinematics, gyroscopic terms)", &b, 1e-7);
  for (int c = 0; c < 3; c++)
    for (int i = 0; i < 3; i++) b.car[c].com[i] = 0.2 * rand11();
  b.d.gravity[0] = 1.0;
  b.d.gravity[2] = -9.81;
  compare("J = central FD: 3 free carriers under gravity, centres of mass off the origin", &b, 1e-7);
}

static void elements_are_closed_form(void) {
  static builder b;
  for (int k = 0; k < 3; k++) {
    chain(&b, 5, 1);
    compare("J = central FD: 4 elements, bent, twisted, moving", &b, 1e-7);
  }
  for (int k = 0; k < 2; k++) { /* consistent masses: cj Mc and the couplings' gyroscopic terms */
    chain(&b, 5, 1);
    for (int e = 0; e < 4; e++) {
      b.el[e].mass = PHM_MASS_CONSISTENT;
      rand_spd6(b.el[e].Ms, 2.0);
    }
    compare("J = central FD: 4 elements with consistent mass, bent, twisted, moving", &b, 1e-7);
  }
}

/* Every pair type in closed form (phm_pair_tangent): between two carriers of a chain of elements
 * and from the ground, random frames (the constraints need not hold), driven by a motion (fixed),
 * with driven joint coordinates (every coordinate the table lets follow a law) and with a
 * dropped row. */
static void pairs_are_closed_form(void) {
  static builder b;
  static const char *const names[] = {
      "J = central FD: fixed pairs (one driven by a motion)", "J = central FD: revolute pairs",
      "J = central FD: prismatic pairs", "J = central FD: helical pairs",
      "J = central FD: cylindrical pairs", "J = central FD: universal pairs",
      "J = central FD: spherical pairs", "J = central FD: planar pairs", "J = central FD: free pairs"};
  for (int type = 0; type < phm_pair_type_count() && type < 9; type++)
    for (int variant = 0; variant < 2; variant++) {
      chain(&b, 5, 1);
      int mt = phm_pair_type(type)->m, mask = phm_pair_type(type)->xdrivable;
      for (int p = 0; p < 2; p++) {
        phm_pair_desc *pr = &b.pair[p];
        pr->type = type;
        pr->a = p ? -1 : 1;
        pr->b = p ? 0 : 3;
        pr->pitch = 0.3 * rand11();
        rand_pose(pr->Ta, 1.0);
        rand_pose(pr->Tb, 1.0);
        if (type == pair_code("fixed") && p == variant) {
          pr->driven = 1;
          for (int i = 0; i < 6; i++) pr->axis[i] = rand11();
          pr->law = (phm_law){.kind = PHM_LAW_SINE, .amplitude = 0.7, .frequency = 0.3, .phase = 0.2};
        }
        if (p == variant)
          for (int c = 0; c < 6 - mt; c++)
            if (mask >> c & 1) {
              pr->xdriven |= 1 << c;
              pr->xlaw[c] = (phm_law){.kind = PHM_LAW_SINE, .amplitude = 0.5 + rand01(),
                                      .frequency = 0.2 + rand01(), .phase = rand11()};
            }
        if (p != variant && mt >= 2) pr->drop = 0x1;
      }
      b.d.npairs = 2;
      b.d.pairs = b.pair;
      compare(names[type], &b, 1e-7);
    }
}

/* The planar DAE's Jacobian (csrc/dae/planar.c, gathered from the full one) against central
 * differences of its own residual: a submatrix, whatever the model (planar or not), for each
 * normal axis. */
static void planar_is_the_submatrix(void) {
  static builder b;
  static const char *const names[] = {"J = central FD: planar DAE about x",
                                      "J = central FD: planar DAE about y",
                                      "J = central FD: planar DAE about z"};
  for (int axis = 0; axis < 3; axis++) {
    chain(&b, 5, 1);
    for (int p = 0; p < 2; p++) {
      phm_pair_desc *pr = &b.pair[p];
      pr->type = pair_code("revolute");
      pr->a = p ? -1 : 1;
      pr->b = p ? 0 : 3;
      rand_pose(pr->Ta, 1.0);
      rand_pose(pr->Tb, 1.0);
    }
    b.d.npairs = 2;
    b.d.pairs = b.pair;
    compare_dae(names[axis], &b, 1e-7, axis + 1);
  }
}

/* Five carriers on elements, a fixed pair to the ground, a revolute with a PD actuator between
 * the last two, a spring-damper to the ground, an interaction (load with a reaction), gravity. */
static void applied_model(builder *b) {
  chain(b, 5, 1);
  b->pair[0].type = pair_code("fixed");
  b->pair[0].a = -1;
  b->pair[0].b = 0;
  b->pair[1].type = pair_code("revolute");
  b->pair[1].a = 3;
  b->pair[1].b = 4;
  for (int p = 0; p < 2; p++)
    for (int i = 0; i < 4; i++) b->pair[p].Ta[5 * i] = b->pair[p].Tb[5 * i] = 1.0;
  /* identity frames: the constraints need not hold, only their derivatives are compared */
  b->d.npairs = 2;
  b->d.pairs = b->pair;
  b->spr[0] = (phm_spring_desc){.a = 1, .b = -1, .pa = {0.1, 0, 0}, .pb = {1, 1, 1}, .k = 30, .c = 0.5, .d0 = 0.5};
  b->d.nsprings = 1;
  b->d.springs = b->spr;
  b->load[0] = (phm_load_desc){.carrier = 2, .reaction = 4, .w = {0.1, 0.2, 0.3, 1, -2, 3}, .world = 1,
                               .point = {0.05, 0, 0}, .law = {.kind = PHM_LAW_CONSTANT, .amplitude = 1.0}};
  b->d.nloads = 1;
  b->d.loads = b->load;
  b->d.gravity[2] = -9.81;
  b->act[0] = (phm_actuator_desc){.pair = 1, .kind = PHM_ACT_PD, .kp = {50}, .kd = {2}, .x_set = {0.1},
                                  .vec = {1}, .law = {.kind = PHM_LAW_CONSTANT, .amplitude = 0.2}};
  b->d.nactuators = 1;
  b->d.actuators = b->act;
}

static void pairs_springs_loads_actuators_are_closed_form(void) {
  static builder b;
  applied_model(&b);
  compare("J = central FD: elements, fixed, revolute with PD, spring, load, gravity", &b, 1e-7);
  for (int e = 0; e < 4; e++) {
    b.el[e].mass = PHM_MASS_CONSISTENT;
    rand_spd6(b.el[e].Ms, 2.0);
  }
  compare("J = central FD: the same with consistent masses", &b, 1e-7);
}

/* Components with internal states (csrc/model/component.c, docs/method.md section 4.11): every
 * kind on the revolute between carriers 3 and 4 (a motor with a rotor inertia between two
 * carriers: a mass coupling), then a motor and LuGre friction on a revolute to the ground (its
 * inertia on the carrier): their wrenches, their rows z' - f and their states' columns. Moderate
 * parameters (the LuGre bristles' 1e5 N/m would only scale the entries); the random joint rates
 * are not 0, where |v| has no derivative. */
static void components_are_closed_form(void) {
  static builder b;
  applied_model(&b);
  phm_law volt = {.kind = PHM_LAW_SINE, .amplitude = 2.0, .frequency = 1.5, .offset = 3.0};
  b.comp[0] = (phm_component_desc){.kind = PHM_COMP_LUGRE, .pair = 1, .par = {50, 3, 0.4, 1, 1.5, 0.3}};
  b.comp[1] = (phm_component_desc){.kind = PHM_COMP_MOTOR, .pair = 1, .par = {0.5, 2, 0.3, 4, 0.8, 0.01}, .law = volt};
  b.comp[2] = (phm_component_desc){.kind = PHM_COMP_STRIBECK, .pair = 1, .par = {1, 1.5, 0.4, 0.2, 0.3}};
  b.comp[3] = (phm_component_desc){.kind = PHM_COMP_COULOMB, .pair = 1, .par = {0.7, 0.5}};
  b.comp[4] = (phm_component_desc){.kind = PHM_COMP_VISCOUS, .pair = 1, .par = {0.3}};
  b.comp[5] = (phm_component_desc){.kind = PHM_COMP_MOTOR, .pair = 1, .input = 1, .par = {0.5, 2, 0.3, 4, 0.9, 0}, .law = volt};
  /* a linear controller with two states: A (2 x 2), B (2 x 2), C (2), D (2), a sine reference */
  b.comp[6] = (phm_component_desc){.kind = PHM_COMP_LINEAR, .pair = 1, .nx = 2, .law = volt,
                                   .par = {-1, 0.5, -0.3, -2, 1, 0.2, 3, -0.4, -5, 0.7, -20, -3}};
  for (int i = 0; i < 7; i++) b.comp[i].spair = -1; /* each measures its own pair */
  b.d.ncomponents = 7;
  b.d.components = b.comp;
  compare("J = central FD: LuGre, motors (voltage with J, current), Stribeck, Coulomb, viscous, "
          "a linear controller", &b, 1e-7);
  b.pair[0].type = pair_code("revolute");
  b.comp[0].pair = b.comp[1].pair = 0;
  b.comp[6].spair = 0; /* the controller on the revolute 3-4 measures the one to the ground */
  compare("J = central FD: LuGre and a motor with J on a revolute to the ground, the rest between "
          "two, a controller measuring the other pair", &b, 1e-7);
  b.d.ncomponents = 0;
}

/* A callback controller (PHM_COMP_CALLBACK): u = fn(t, x, v) with the derivatives its function
 * gives when asked (nder 1), here u = -3 sin(x) - 0.5 v^3 + 0.2 t; on the revolute between two
 * carriers, then on one to the ground. */
static int callback_law(void *ctx, double t, double x, double v, int nder, double out[3]) {
  (void)ctx;
  out[0] = -3 * sin(x) - 0.5 * v * v * v + 0.2 * t;
  out[1] = nder ? -3 * cos(x) : 0;
  out[2] = nder ? -1.5 * v * v : 0;
  return 0;
}

static void callback_controller_is_closed_form(void) {
  static builder b;
  applied_model(&b);
  b.comp[0] = (phm_component_desc){.kind = PHM_COMP_CALLBACK, .pair = 1, .spair = -1,
                                   .fn = callback_law};
  b.d.ncomponents = 1;
  b.d.components = b.comp;
  compare("J = central FD: a callback controller", &b, 1e-7);
  b.pair[0].type = pair_code("revolute");
  b.comp[0].pair = 0;
  compare("J = central FD: a callback controller on a revolute to the ground", &b, 1e-7);
  b.d.ncomponents = 0;
}

/* dae_jacobian_prune keeps every entry ever nonzero: the first call reports a new pattern, the
 * same values again do not, an entry gone back to zero stays (its value 0), and a newly nonzero
 * entry grows the pattern. */
static void pruning_keeps_a_growing_pattern(void) {
  static builder b;
  chain(&b, 3, 1);
  phm_model *m = create_model(&b.d);
  if (!m) return;
  dae_t d;
  phm_error err;
  SUNContext ctx;
  if (phm_sun_context_create(&ctx) || dae_init(&d, m, &err) || dae_jacobian_pattern(&d, &err)) {
    check_fail("%s", "prune: set-up");
    phm_model_free(m);
    return;
  }
  SUNMatrix J = SUNSparseMatrix(d.n, d.n, d.nnz, CSC_MAT, ctx);
  sunindextype *cp = SUNSparseMatrix_IndexPointers(J), *ri = SUNSparseMatrix_IndexValues(J);
  double *val = SUNSparseMatrix_Data(J);
  /* the full pattern with every other entry zero */
  #define FILL(zero_at, nonzero_at)                                              \
    do {                                                                       \
      for (int j = 0; j <= d.n; j++) cp[j] = d.colptr[j];                      \
      for (int k = 0; k < d.nnz; k++) {                                        \
        ri[k] = d.rowind[k];                                                   \
        val[k] = (k % 2 == 0 && k != (zero_at)) || k == (nonzero_at) ? 1.0 + k : 0.0; \
      }                                                                        \
    } while (0)
  FILL(-1, -1);
  CHECK(dae_jacobian_prune(&d, J) == 1, "%s", "prune: the first call is a new pattern");
  long kept = (long)cp[d.n];
  CHECK(kept == (d.nnz + 1) / 2, "prune: kept %ld of %d (the nonzero half)", kept, d.nnz);
  FILL(-1, -1);
  CHECK(dae_jacobian_prune(&d, J) == 0, "%s", "prune: the same values, the same pattern");
  FILL(0, -1); /* entry 0 back to zero: kept, with its zero */
  CHECK(dae_jacobian_prune(&d, J) == 0 && (long)cp[d.n] == kept && val[0] == 0.0, "%s",
        "prune: an entry back to zero stays in the pattern");
  FILL(-1, 1); /* entry 1 nonzero for the first time */
  CHECK(dae_jacobian_prune(&d, J) == 1 && (long)cp[d.n] == kept + 1, "%s",
        "prune: a newly nonzero entry grows the pattern");
  #undef FILL
  SUNMatDestroy(J);
  dae_free(&d);
  SUNContext_Free(&ctx);
  phm_model_free(m);
}

/* dae_ledger_dpower against the change of the ledger rows F = E' - P of the residual for a
 * random change of the twists and of lambda, of order one (applied_model with an effort
 * actuator too): the supplied power and the actuators' and loads' ports, exact in those
 * (P is at most quadratic in them: u . xdot with a PD's damping, lambda . G t); held to 1e-12
 * of the largest change. In 3-D and planar about z. */
static void ledger_dpower_is_the_power_change(void) {
  static builder b;
  applied_model(&b);
  b.act[1] = (phm_actuator_desc){.pair = 1, .kind = PHM_ACT_EFFORT, .vec = {1},
                                 .law = {.kind = PHM_LAW_CONSTANT, .amplitude = 0.7}};
  b.d.nactuators = 2;
  phm_model *m = create_model(&b.d);
  if (!m) return;
  for (int planar = 0; planar <= 3; planar += 3) {
    const char *name = planar ? "ledger dpower = the residual's change (planar)" : "ledger dpower = the residual's change";
    dae_t d;
    phm_error err;
    if (planar ? dae_planar_init(&d, m, planar - 1, &err) : dae_init(&d, m, &err)) {
      check_fail("%s: set-up", name);
      continue;
    }
    int n = d.n, nl = d.il - d.ie;
    double *y = malloc(sizeof(double) * (size_t)n * 6), *yp = y + n, *dy = yp + n, *yy = dy + n,
           *rp = yy + n, *rm = rp + n, dP[16];
    for (int trial = 0; trial < 3; trial++) {
      for (int i = 0; i < n; i++) {
        y[i] = rand11();
        yp[i] = rand11();
        dy[i] = i >= d.il && i < d.im ? rand11() : 0.0; /* lambda */
      }
      for (int c = 0; c < m->nc; c++) {
        double a = 3.0 * rand11(), s = 1.0 + 0.05 * rand11();
        double *yc = y + d.ns * c;
        if (planar) {
          yc[0] = s * cos(a);
          yc[1] = s * sin(a);
        } else {
          for (int i = 0; i < 4; i++) yc[i] = rand11();
        }
        for (int j = d.nt0; j < d.ns; j++) dy[d.ns * c + j] = rand11(); /* the twists */
      }
      double t = 0.1;
      d.tref = 0.5;
      for (int i = 0; i < n; i++) yy[i] = y[i] + dy[i];
      dae_residual(&d, t, yy, yp, rp);
      dae_residual(&d, t, y, yp, rm);
      dae_constraint_rows(&d, t, y, yy);
      dae_ledger_dpower(&d, t, y, dy, 1.0, dP);
      double worst = 0, big = 0;
      for (int i = 1; i < 2 + m->na + m->nl && i < nl; i++) { /* not Pd, nor the springs' ports */
        double ref = -(rp[d.ie + i] - rm[d.ie + i]);
        worst = fmax(worst, fabs(ref - dP[i]));
        big = fmax(big, fabs(ref));
      }
      check_worst(name, worst / big, 1e-12);
    }
    free(y);
    dae_free(&d);
  }
  phm_model_free(m);
}

CHECK_MAIN(CHECK_CASE(carriers_and_gravity_are_closed_form), CHECK_CASE(elements_are_closed_form),
           CHECK_CASE(pruning_keeps_a_growing_pattern),
           CHECK_CASE(pairs_are_closed_form), CHECK_CASE(planar_is_the_submatrix),
           CHECK_CASE(pairs_springs_loads_actuators_are_closed_form),
           CHECK_CASE(components_are_closed_form), CHECK_CASE(callback_controller_is_closed_form),
           CHECK_CASE(ledger_dpower_is_the_power_change))
