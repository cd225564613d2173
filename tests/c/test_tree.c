/* test_tree.c -- csrc/integrate/tree.c and tree_aba.c: the tree integrator against IDA on a
 * spatial chain of three bodies (skewed revolute axes, offset centres of mass, a damped joint
 * spring: the motion is 3-D and dissipates), state and multipliers at rtol 1e-10; and the models
 * it refuses, each with its reason. */
#include "check.h"

/* A body of mass ms, principal inertia I about its centre of mass r (body coordinates). */
static void body(phm_carrier_desc *c, double ms, const double I[3], const double r[3]) {
  carrier_unit(c);
  memset(c->M, 0, sizeof c->M);
  double rh[9] = {0, -r[2], r[1], r[2], 0, -r[0], -r[1], r[0], 0};
  for (int i = 0; i < 3; i++) {
    c->M[7 * i] = I[i];
    c->M[6 * (i + 3) + i + 3] = ms;
    for (int j = 0; j < 3; j++) {
      double rr = 0;
      for (int k = 0; k < 3; k++) rr += rh[3 * i + k] * rh[3 * k + j];
      c->M[6 * i + j] -= ms * rr;
      c->M[6 * i + j + 3] = ms * rh[3 * i + j];
      c->M[6 * (i + 3) + j] = -ms * rh[3 * i + j];
    }
  }
  c->mass = ms;
  memcpy(c->com, r, sizeof(double) * 3);
}

/* Frame: a rotation by angle `ang` about axis (x, y, z) (normalized here), origin o. */
static void frame(double ax, double ay, double az, double ang, const double o[3], double T[16]) {
  double n = sqrt(ax * ax + ay * ay + az * az), x[6] = {ang * ax / n, ang * ay / n, ang * az / n, 0, 0, 0};
  phm_se3_exp(x, T);
  T[3] = o[0];
  T[7] = o[1];
  T[11] = o[2];
}

/* The chain: ground -> 0 -> 1 -> 2, revolute pairs with skewed axes, joint 2 (the last) a damped
 * spring; start angles 0.4, -0.7, 1.1 rad, at rest; gravity -z. */
static phm_model *chain3(void) {
  phm_carrier_desc car[3];
  phm_pair_desc pr[3];
  phm_actuator_desc act;
  const double I[3][3] = {{0.02, 0.03, 0.025}, {0.01, 0.015, 0.012}, {0.004, 0.006, 0.005}};
  const double ms[3] = {1.5, 1.0, 0.6};
  const double r[3][3] = {{0.2, 0.01, 0.0}, {0.15, 0.0, -0.02}, {0.1, 0.02, 0.01}};
  const double x0[3] = {0.4, -0.7, 1.1};
  const double o0[3] = {0, 0, 0}, oa[3] = {0.4, 0.0, 0.0}, ob[3] = {0.3, 0.05, 0.0};
  memset(pr, 0, sizeof pr);
  for (int i = 0; i < 3; i++) {
    body(&car[i], ms[i], I[i], r[i]);
    pr[i].type = pair_code("revolute");
    pr[i].a = i - 1;
    pr[i].b = i;
    pr[i].has_x0 = 1;
    pr[i].x0[0] = x0[i];
  }
  frame(1, 0, 0, 0.5 * CHECK_PI, o0, pr[0].Ta);          /* first axis horizontal (world -y) */
  frame(0, 0, 1, 0.0, o0, pr[0].Tb);
  frame(1, 1, 0, 0.6, oa, pr[1].Ta);
  frame(0, 1, 0, -0.3, o0, pr[1].Tb);
  frame(0, 1, 1, -0.8, ob, pr[2].Ta);
  frame(1, 0, 1, 0.2, o0, pr[2].Tb);
  for (int i = 0; i < 3; i++) { /* the poses at the start angles */
    double x[6] = {0, 0, x0[i], 0, 0, 0}, h[16];
    phm_se3_exp(x, h);
    place_b(i ? car[i - 1].H0 : NULL, pr[i].Ta, pr[i].Tb, h, car[i].H0);
  }
  memset(&act, 0, sizeof act);
  act.pair = 2;
  act.kind = PHM_ACT_SPRING;
  act.kp[0] = 2.0;
  act.kd[0] = 0.05;
  act.x_set[0] = 0.5;
  phm_model_desc d = {.ncarriers = 3, .carriers = car, .npairs = 3, .pairs = pr,
                      .gravity = {0, 0, -9.81}, .nactuators = 1, .actuators = &act};
  phm_model *m = NULL;
  phm_error err;
  if (phm_model_create(&d, &m, &err) != PHM_OK) {
    check_fail("chain3: %s", err.msg);
    return NULL;
  }
  return m;
}

#define NOUT 11
typedef struct {
  double poses[NOUT * 3 * 16], twists[NOUT * 3 * 6], lam[NOUT * 15], joints[NOUT * 3],
      energy[NOUT * PHM_NENERGY];
} run_out;

static phm_status run(const phm_model *m, int integrator, double rtol, run_out *r, phm_error *err) {
  double tout[NOUT];
  for (int i = 0; i < NOUT; i++) tout[i] = 0.1 * i;
  phm_sim_options o = {.rtol = rtol, .atol = rtol, .integrator = integrator};
  phm_sim_output out;
  memset(&out, 0, sizeof out);
  out.poses = r->poses;
  out.twists = r->twists;
  out.constraint_wrenches = r->lam;
  out.joints = r->joints;
  out.energy = r->energy;
  phm_status st = phm_simulate(m, NULL, NULL, tout, NOUT, &o, &out, err);
  if (!st && out.nout_done != NOUT) return PHM_ESOLVER;
  return st;
}

static void tree_matches_ida(void) {
  phm_model *m = chain3();
  if (!m) return;
  CHECK(phm_model_nconstraints(m) == 15, "three revolute pairs: 15 rows");
  static run_out a, b;
  phm_error err;
  phm_status s1 = run(m, PHM_INTEGRATOR_IDA, 1e-10, &a, &err);
  CHECK(s1 == PHM_OK, "IDA runs (%s)", err.msg);
  phm_status s2 = run(m, PHM_INTEGRATOR_TREE, 1e-10, &b, &err);
  CHECK(s2 == PHM_OK, "tree runs (%s)", err.msg);
  if (s1 || s2) {
    phm_model_free(m);
    return;
  }
  double dp = 0, dw = 0, dj = 0, dl = 0, lmax = 0, wmax = 0, moved = 0;
  for (int i = 0; i < NOUT * 3; i++) {
    for (int k = 0; k < 3; k++) dp = fmax(dp, fabs(a.poses[16 * i + 4 * k + 3] - b.poses[16 * i + 4 * k + 3]));
    for (int k = 0; k < 12; k++) dp = fmax(dp, fabs(a.poses[16 * i + k] - b.poses[16 * i + k]));
    for (int k = 0; k < 6; k++) {
      dw = fmax(dw, fabs(a.twists[6 * i + k] - b.twists[6 * i + k]));
      wmax = fmax(wmax, fabs(a.twists[6 * i + k]));
    }
    dj = fmax(dj, fabs(a.joints[i] - b.joints[i]));
  }
  for (int i = 0; i < NOUT * 15; i++) {
    dl = fmax(dl, fabs(a.lam[i] - b.lam[i]));
    lmax = fmax(lmax, fabs(a.lam[i]));
  }
  for (int k = 0; k < 3; k++) moved = fmax(moved, fabs(a.joints[3 * (NOUT - 1) + k] - a.joints[k]));
  CHECK(moved > 0.5 && wmax > 1.0, "the chain moves (joint travel %g rad, |t| up to %g)", moved, wmax);
  check("tree vs IDA: poses", dp, 1e-7);
  check("tree vs IDA: twists / max |t|", dw / wmax, 1e-7);
  check("tree vs IDA: joint coordinates", dj, 1e-7);
  check("tree vs IDA: lambda / max |lambda|", dl / lmax, 1e-6);
  /* the ledger: the damped joint spring's power (an actuator's: a port, its work counted as
   * supplied) accounted for, and the same as IDA's */
  const double *ea = a.energy + PHM_NENERGY * (NOUT - 1), *eb = b.energy + PHM_NENERGY * (NOUT - 1);
  double led = 0;
  for (int i = 0; i < NOUT; i++) led = fmax(led, fabs(b.energy[PHM_NENERGY * i + 6]));
  CHECK(fabs(eb[4]) > 1e-3, "the joint spring works through its port (supplied %g J)", eb[4]);
  check("tree: ledger residual [J]", led, 1e-8);
  check("tree vs IDA: supplied energy [J]", fabs(ea[4] - eb[4]), 1e-7);
  check("tree vs IDA: total energy [J]", fabs(ea[5] - eb[5]), 1e-7);
  phm_model_free(m);
}

/* The models the tree integrator refuses: each message names its reason. */
static void tree_refuses(void) {
  double tout[2] = {0, 0.01};
  phm_sim_options o = {.rtol = 1e-6, .atol = 1e-6, .integrator = PHM_INTEGRATOR_TREE};
  phm_sim_output out;
  phm_error err;
  memset(&out, 0, sizeof out);
  /* a beam (elements) */
  {
    phm_carrier_desc car[3];
    phm_element_desc el[2];
    phm_pair_desc clamp;
    const double k[6] = {1, 1, 1, 10, 10, 10};
    straight_beam(2, 1.0, k, car, el, &clamp);
    phm_model_desc d = {.ncarriers = 3, .carriers = car, .nelements = 2, .elements = el,
                        .npairs = 1, .pairs = &clamp};
    phm_model *m = NULL;
    if (phm_model_create(&d, &m, &err) == PHM_OK) {
      check_refused("tree: beam elements", phm_simulate(m, NULL, NULL, tout, 2, &o, &out, &err),
                    PHM_EINVAL, &err, "beam element");
      phm_model_free(m);
    } else
      check_fail("beam: %s", err.msg);
  }
  /* a free body; a spherical pair; a driven pair */
  for (int cas = 0; cas < 3; cas++) {
    phm_carrier_desc c;
    carrier_unit(&c);
    phm_pair_desc p;
    memset(&p, 0, sizeof p);
    p.type = pair_code(cas == 1 ? "spherical" : "fixed");
    p.a = -1;
    p.b = 0;
    for (int i = 0; i < 4; i++) p.Ta[5 * i] = p.Tb[5 * i] = 1.0;
    if (cas == 2) {
      p.driven = 1;
      p.axis[2] = 1;
      p.law.kind = PHM_LAW_LINEAR;
      p.law.amplitude = 1.0;
    }
    phm_model_desc d = {.ncarriers = 1, .carriers = &c, .npairs = cas ? 1 : 0, .pairs = &p};
    phm_model *m = NULL;
    if (phm_model_create(&d, &m, &err) != PHM_OK) {
      check_fail("refusal case %d: %s", cas, err.msg);
      continue;
    }
    const char *why[3] = {"side b of no pair", "motion subspace is not constant", "prescribes a motion"};
    const char *name[3] = {"tree: a free body", "tree: a spherical pair", "tree: a driven pair"};
    check_refused(name[cas], phm_simulate(m, NULL, NULL, tout, 2, &o, &out, &err), PHM_EINVAL,
                  &err, why[cas]);
    phm_model_free(m);
  }
}

CHECK_MAIN(CHECK_CASE(tree_matches_ida), CHECK_CASE(tree_refuses))
