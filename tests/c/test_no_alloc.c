/* test_no_alloc.c -- after set-up, a simulation allocates nothing of phmech's own: the residual,
 * the Jacobian, the outputs and the restarts at the laws' breakpoints work in the DAE's data
 * (phm_data, csrc/dae/dae.h), allocated once by dae_init and dae_jacobian_pattern.
 *
 * How it counts: this executable is linked with -Wl,--wrap=malloc,--wrap=calloc,--wrap=realloc
 * (meson.build), so every call to those functions from an object linked into it -- the test and
 * the core's static library -- goes through the counters below. SUNDIALS, KLU and LAPACK are
 * shared libraries whose calls the wrap does not see: IDA's and the linear solvers' set-up (after
 * the first output: run_ida and run_galpha create them) and their internals are not phmech's and
 * are not counted. The count is read at the first output (the progress callback, output 0: the
 * consistent initial values are done) and after phm_simulate returns; the difference must be 0,
 * for the generalized-alpha integrator (adaptive, and fixed step) and IDA (KLU and dense), on a
 * model with a driven pair, a PD-actuated pair, a spring, a load with a reaction and Table laws
 * with several breakpoints inside the run (each one a restart from consistent values). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "linalg.h"
#include "model.h"

/* ---------------------------------------------------------------- the counting wrappers */
void *__real_malloc(size_t size);
void *__real_calloc(size_t n, size_t size);
void *__real_realloc(void *p, size_t size);
void *__wrap_malloc(size_t size);
void *__wrap_calloc(size_t n, size_t size);
void *__wrap_realloc(void *p, size_t size);

static long n_alloc = 0;
void *__wrap_malloc(size_t size) {
  n_alloc++;
  return __real_malloc(size);
}
void *__wrap_calloc(size_t n, size_t size) {
  n_alloc++;
  return __real_calloc(n, size);
}
void *__wrap_realloc(void *p, size_t size) {
  n_alloc++;
  return __real_realloc(p, size);
}


/* ---------------------------------------------------------------- the model */
/* A flexible strip of NE elements along x whose root is turned about z by a driven fixed pair
 * (a Table law), a rigid body on its tip on a revolute pair about z held by a PD actuator with a
 * Table set point, LuGre friction and a DC motor, a spring from the body to the ground, a load on
 * a node with its reaction on the body (an expression law), gravity. */
enum { NE = 4, NC = NE + 2 };
static const double drive_table[] = {0.0, 0.0, 0.01, 0.02, 0.02, 0.03, 0.03, 0.03, 0.04, 0.0};
static const double setpoint_table[] = {0.0, 0.0, 0.015, 0.1, 0.035, 0.1};

static int type_code(const char *name) {
  for (int t = 0; t < phm_pair_type_count(); t++)
    if (!strcmp(phm_pair_type(t)->name, name)) return t;
  return -1;
}

static void translation(double H[16], double x) {
  memset(H, 0, 16 * sizeof(double));
  for (int i = 0; i < 4; i++) H[5 * i] = 1;
  H[3] = x;
}

/* A PD actuator on pair 1's first coordinate following setpoint_table (its breakpoints). */
static void pd_on_pair1(phm_actuator_desc *a, double kp, double kd) {
  a->pair = 1;
  a->kind = PHM_ACT_PD;
  a->vec[0] = 1.0;
  a->kp[0] = kp;
  a->kd[0] = kd;
  a->law.kind = PHM_LAW_TABLE;
  a->law.ntable = 3;
  a->law.table = setpoint_table;
}

static phm_model *build(int mass, int planar) {
  static phm_carrier_desc car[NC];
  static phm_element_desc el[NE];
  static phm_pair_desc pr[2];
  static phm_actuator_desc act[1];
  static phm_spring_desc spr[1];
  static phm_load_desc ld[1];
  double h = 0.1;
  memset(car, 0, sizeof car);
  for (int c = 0; c < NC; c++) {
    double mass = c < NC - 1 ? 0.05 : 0.2, J = c < NC - 1 ? 1e-5 : 1e-4;
    for (int i = 0; i < 3; i++) {
      car[c].M[7 * i] = J;
      car[c].M[7 * (i + 3)] = mass;
    }
    car[c].mass = mass;
    translation(car[c].H0, h * (c < NC - 1 ? c : NE));
  }
  memset(el, 0, sizeof el);
  double K[6] = {5.0, 8.0, 8.0, 2e5, 1e5, 1e5};
  for (int e = 0; e < NE; e++) {
    el[e].a = e;
    el[e].b = e + 1;
    el[e].h = h;
    for (int i = 0; i < 6; i++) {
      el[e].K[7 * i] = K[i] / h;
      el[e].D[7 * i] = 1e-3 * K[i] / h;
    }
    el[e].eps_hat[3] = 1.0;
    el[e].mass = mass;
    for (int i = 0; i < 6; i++) el[e].Ms[7 * i] = i < 3 ? 1e-4 : 0.5; /* per metre */
  }
  memset(pr, 0, sizeof pr);
  for (int p = 0; p < 2; p++) {
    translation(pr[p].Ta, 0);
    translation(pr[p].Tb, 0);
  }
  pr[0].type = type_code("fixed"); /* driven: the root turned about z */
  pr[0].a = -1;
  pr[0].b = 0;
  pr[0].driven = 1;
  pr[0].axis[2] = 1.0;
  pr[0].law.kind = PHM_LAW_TABLE;
  pr[0].law.ntable = 5;
  pr[0].law.table = drive_table;
  pr[1].type = type_code("revolute"); /* about z */
  pr[1].a = NE;
  pr[1].b = NC - 1;
  memset(act, 0, sizeof act);
  pd_on_pair1(&act[0], 2.0, 0.05);
  memset(spr, 0, sizeof spr);
  spr[0].a = NC - 1;
  spr[0].b = -1;
  spr[0].pb[0] = h * NE;
  spr[0].pb[1] = 0.05;
  spr[0].k = 20.0;
  spr[0].c = 0.1;
  spr[0].d0 = 0.05;
  memset(ld, 0, sizeof ld);
  ld[0].carrier = 2;
  ld[0].reaction = NC - 1;
  ld[0].w[4] = 0.5;
  /* its law an expression (1 + p(t) sin(2 pi 30 t), p a two-piece cubic): evaluated on the
   * stack, without allocating */
  static const double poly[] = {0.0, 0.02, 0.05, 0, 0, 1.0, 0.0, 0, 3.0, 0.0, 0.02};
  static phm_law nodes[5];
  memset(nodes, 0, sizeof nodes);
  nodes[0].kind = PHM_LAW_PPOLY;
  nodes[0].ntable = 2;
  nodes[0].order = 4;
  nodes[0].table = poly;
  nodes[1].kind = PHM_LAW_SINE;
  nodes[1].amplitude = 1.0;
  nodes[1].frequency = 30.0;
  nodes[2].kind = PHM_LAW_PRODUCT;
  nodes[3].kind = PHM_LAW_CONSTANT;
  nodes[3].amplitude = 1.0;
  nodes[4].kind = PHM_LAW_SUM;
  ld[0].law.kind = PHM_LAW_EXPR;
  ld[0].law.nnodes = 5;
  ld[0].law.nodes = nodes;
  phm_model_desc d;
  memset(&d, 0, sizeof d);
  d.ncarriers = NC;
  d.carriers = car;
  d.nelements = NE;
  d.elements = el;
  d.npairs = 2;
  d.pairs = pr;
  d.nactuators = 1;
  d.actuators = act;
  d.nsprings = 1;
  d.springs = spr;
  d.nloads = 1;
  d.loads = ld;
  /* components with internal states on the revolute: LuGre friction and a DC motor with a
   * rotor inertia (a mass coupling of the pair's two carriers) */
  static phm_component_desc comp[2];
  comp[0] = (phm_component_desc){.kind = PHM_COMP_LUGRE, .pair = 1, .par = {1e3, 5, 0.01, 0.05, 0.08, 0.01}};
  comp[1] = (phm_component_desc){.kind = PHM_COMP_MOTOR, .pair = 1, .par = {1e-3, 2.0, 0.02, 10, 0.9, 1e-6},
                                 .law = {.kind = PHM_LAW_CONSTANT, .amplitude = 0.5}};
  d.ncomponents = 2;
  d.components = comp;
  d.gravity[2] = -9.81;
  if (planar) { /* everything in the x-y plane: gravity along -y, the out-of-plane rows dropped
                 * (the fixed pair's rx, ry, tz; the revolute's rx, ry, tz) */
    d.gravity[2] = 0.0;
    d.gravity[1] = -9.81;
    pr[0].drop = 0x23;
    pr[1].drop = 0x13;
  }
  phm_model *m = NULL;
  phm_error err;
  if (phm_model_create(&d, &m, &err)) {
    printf("model: %s\n", err.msg);
    return NULL;
  }
  return m;
}

/* ---------------------------------------------------------------- one run */
static long at_first_output = -1;
static int first_output(void *ctx, double t, int iout) {
  (void)ctx;
  (void)t;
  if (iout == 0) at_first_output = n_alloc;
  return 0;
}

enum { NOUT = 11 };

static void run(const phm_model *m, const char *name, phm_sim_options opt) {
  int nc = phm_model_ncarriers(m), nk = phm_model_nconstraints(m), np = phm_model_npairs(m);
  int nj = phm_model_njoints(m), nport = phm_model_nports(m);
  double tout[NOUT];
  for (int i = 0; i < NOUT; i++) tout[i] = 0.005 * i; /* to 0.05 s: past every breakpoint */
  phm_sim_output out;
  memset(&out, 0, sizeof out);
  out.poses = malloc(sizeof(double) * NOUT * 16 * (size_t)nc);
  out.twists = malloc(sizeof(double) * NOUT * 6 * (size_t)nc);
  out.constraint_wrenches = malloc(sizeof(double) * NOUT * (size_t)(nk + 1));
  out.energy = malloc(sizeof(double) * NOUT * PHM_NENERGY);
  out.joints = malloc(sizeof(double) * NOUT * (size_t)(nj + 1));
  out.joint_rates = malloc(sizeof(double) * NOUT * (size_t)(nj + 1));
  out.efforts = malloc(sizeof(double) * NOUT * (size_t)(nj + 1));
  out.pair_wrenches = malloc(sizeof(double) * NOUT * 6 * (size_t)np);
  out.port_energy = malloc(sizeof(double) * NOUT * (size_t)(nport + 1));
  opt.progress = first_output;
  at_first_output = -1;
  phm_error err;
  long before = n_alloc;
  phm_status st = phm_simulate(m, NULL, NULL, tout, NOUT, &opt, &out, &err);
  long after = n_alloc;
  char msg[200];
  snprintf(msg, sizeof msg, "%s: runs to the end (%d outputs, %ld steps)", name, out.nout_done, out.nsteps);
  CHECK(st == PHM_OK && out.nout_done == NOUT, "%s", msg);
  if (st) printf("  %s\n", err.msg);
  snprintf(msg, sizeof msg, "%s: set-up allocates through the counted functions (%ld calls)", name,
           at_first_output - before);
  CHECK(at_first_output > before, "%s", msg);
  snprintf(msg, sizeof msg, "%s: no allocation after the first output (%ld)", name, after - at_first_output);
  CHECK(at_first_output >= 0 && after == at_first_output, "%s", msg);
  printf("%-36s %5ld steps, %4ld allocations in set-up, %ld after the first output\n", name,
         out.nsteps, at_first_output - before, after - at_first_output);
  free(out.poses);
  free(out.twists);
  free(out.constraint_wrenches);
  free(out.energy);
  free(out.joints);
  free(out.joint_rates);
  free(out.efforts);
  free(out.pair_wrenches);
  free(out.port_energy);
}

/* A rigid tree for the tree integrator: two links on revolute pairs about z (ground -> 0 -> 1),
 * a PD actuator on the second with the Table set point (breakpoints inside the run), a spring
 * from link 1 to the ground, gravity. */
static phm_model *build_tree(void) {
  static phm_carrier_desc car[2];
  static phm_pair_desc pr[2];
  static phm_actuator_desc act[1];
  static phm_spring_desc spr[1];
  memset(car, 0, sizeof car);
  memset(pr, 0, sizeof pr);
  memset(act, 0, sizeof act);
  memset(spr, 0, sizeof spr);
  for (int c = 0; c < 2; c++) {
    for (int i = 0; i < 3; i++) car[c].M[7 * i] = 1e-3;
    for (int i = 3; i < 6; i++) car[c].M[7 * i] = 0.1;
    car[c].mass = 0.1;
    for (int i = 0; i < 4; i++) car[c].H0[5 * i] = 1.0;
    car[c].H0[3] = 0.2 * c;
    pr[c].type = type_code("revolute");
    pr[c].a = c - 1;
    pr[c].b = c;
    for (int i = 0; i < 4; i++) pr[c].Ta[5 * i] = pr[c].Tb[5 * i] = 1.0;
    pr[c].Ta[3] = c ? 0.2 : 0.0;
  }
  pd_on_pair1(&act[0], 5.0, 0.1);
  spr[0].a = 1;
  spr[0].b = -1;
  spr[0].pa[0] = 0.1;
  spr[0].pb[0] = 0.3;
  spr[0].pb[1] = 0.1;
  spr[0].k = 20.0;
  spr[0].c = 0.05;
  spr[0].d0 = 0.05;
  phm_model_desc d = {.ncarriers = 2, .carriers = car, .npairs = 2, .pairs = pr,
                      .gravity = {0, -9.81, 0}, .nactuators = 1, .actuators = act,
                      .nsprings = 1, .springs = spr};
  phm_model *m = NULL;
  phm_error err;
  if (phm_model_create(&d, &m, &err) != PHM_OK) printf("  tree model: %s\n", err.msg);
  return m;
}

int main(void) {
  phm_model *m = build(PHM_MASS_LUMPED, 0);
  CHECK(m != NULL, "%s", "model created");
  if (!m) return 1;
  CHECK(m->nbp >= 5 && m->bp[m->nbp - 1] < 0.05, "%s", "breakpoints inside the run (0.01 ... 0.04 s)");
  phm_sim_options base;
  memset(&base, 0, sizeof base);
  base.rtol = 1e-6;
  base.atol = 1e-8;
  base.ida.error_test = PHM_ERRTEST_ALL;
  base.galpha.rho_inf = 0.9;

  phm_sim_options defaults = base; /* simulate()'s defaults (python/phmech/mechanism.py) */
  defaults.integrator = PHM_INTEGRATOR_GALPHA;
  defaults.galpha.adaptive = 1;
  defaults.rtol = 1e-4;
  defaults.atol = 1e-6;
  defaults.galpha.band = 100.0; /* 1 / (2 dt_out) */
  defaults.linear_solver = 1;
  phm_sim_options o = defaults;
  run(m, "generalized-alpha, adaptive, KLU", o);
  o.linear_solver = 0;
  run(m, "generalized-alpha, adaptive, dense", o);
  o = base;
  o.integrator = PHM_INTEGRATOR_GALPHA;
  o.galpha.step = 2.5e-4;
  o.rtol = 1e-8;
  o.atol = 1e-10;
  o.linear_solver = 1;
  run(m, "generalized-alpha, fixed step, KLU", o);
  o = base;
  o.integrator = PHM_INTEGRATOR_IDA;
  o.linear_solver = 1;
  run(m, "IDA, KLU", o);
  o.linear_solver = 0;
  run(m, "IDA, dense", o);
  phm_model_free(m);

  /* the same with consistent element masses: their couplings in the residual and Jacobian, the
   * initial accelerations by conjugate gradients at every breakpoint */
  m = build(PHM_MASS_CONSISTENT, 0);
  CHECK(m != NULL, "%s", "model with consistent masses created");
  if (!m) return 1;
  run(m, "consistent masses: generalized-alpha, adaptive, KLU", defaults);
  o = base;
  o.integrator = PHM_INTEGRATOR_IDA;
  o.linear_solver = 1;
  run(m, "consistent masses: IDA, KLU", o);

  phm_model_free(m);

  /* the planar DAE (csrc/dae/planar.c): its expansions and gathers allocate nothing either */
  m = build(PHM_MASS_LUMPED, 1);
  CHECK(m != NULL, "%s", "planar model created");
  if (!m) return 1;
  o = defaults;
  o.planar = 3;
  run(m, "planar: generalized-alpha, adaptive, KLU", o);
  o = base;
  o.planar = 3;
  o.integrator = PHM_INTEGRATOR_IDA;
  o.linear_solver = 1;
  run(m, "planar: IDA, KLU", o);
  o.linear_solver = 0;
  run(m, "planar: IDA, dense", o);

  phm_model_free(m);

  /* the tree integrator (csrc/integrate/tree.c): its steps, dense outputs and restarts at the
   * breakpoints work in its set-up's scratch */
  m = build_tree();
  CHECK(m != NULL, "%s", "rigid tree model created");
  if (!m) return 1;
  o = base;
  o.integrator = PHM_INTEGRATOR_TREE;
  run(m, "tree", o);

  /* the counters see the core's own calls: a least-squares solve without a workspace allocates */
  double A[4] = {2, 0, 0, 1}, b[2] = {1, 1};
  phm_error err;
  long before = n_alloc;
  phm_lstsq(2, 2, A, b, NULL, &err);
  CHECK(n_alloc > before, "%s", "the core's allocations are counted (phm_lstsq)");
  phm_model_free(m);
  printf("%d passed, %d failed\n", check_npass, check_nfail);
  return check_nfail != 0 || check_npass == 0;
}
