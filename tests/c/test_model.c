/* test_model.c -- C unit tests of the model kernels (csrc/model.c, dae.c, linearize.c) against
 * independent references: central finite differences of the elastic energy and of the position
 * constraints, the power balance of an element, energy conservation of a free body. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model_internal.h"

static int n_pass = 0, n_fail = 0;
static void check(const char *name, double err, double tol) {
  if (err <= tol) {
    n_pass++;
  } else {
    n_fail++;
    printf("FAIL %s: error %.3e > tol %.1e\n", name, err, tol);
  }
}

static unsigned long long rng = 88172645463325252ULL;
static double urand(void) { /* uniform in [-1, 1) */
  rng ^= rng << 13;
  rng ^= rng >> 7;
  rng ^= rng << 17;
  return (double)(rng >> 11) / 9007199254740992.0 * 2 - 1;
}
static void rand_pose(double H[16], double scale) {
  double x[6];
  for (int i = 0; i < 6; i++) x[i] = scale * urand();
  phm_se3_exp(x, H);
}
static void rand_spd(double K[36], double diag) {
  double A[36];
  for (int i = 0; i < 36; i++) A[i] = urand();
  for (int i = 0; i < 6; i++)
    for (int j = 0; j < 6; j++) {
      double s = (i == j) ? diag : 0;
      for (int k = 0; k < 6; k++) s += A[6 * i + k] * A[6 * j + k];
      K[6 * i + j] = s;
    }
}
static void perturbed(const double H[16], const double d[6], double s, double out[16]) {
  double x[6];
  for (int i = 0; i < 6; i++) x[i] = s * d[i];
  memcpy(out, H, 16 * sizeof(double));
  phm_retract(out, x);
}

static void test_element(void) {
  for (int trial = 0; trial < 20; trial++) {
    phm_element_desc e;
    memset(&e, 0, sizeof e);
    e.h = 0.1 + 0.4 * fabs(urand());
    rand_spd(e.K, 2.0);
    rand_spd(e.D, 0.5);
    e.eps_hat[0] = 0.5 * urand();
    e.eps_hat[2] = 2.0 * urand();
    e.eps_hat[3] = 1.0;
    double Ha[16], Hb[16], E[16], x[6];
    rand_pose(Ha, 1.0);
    for (int i = 0; i < 6; i++) x[i] = e.h * (e.eps_hat[i] + 0.3 * urand()); /* large strain */
    if (trial % 4 == 0) for (int i = 0; i < 3; i++) x[i] *= 8.0;         /* rotations up to ~ 3 rad */
    phm_se3_exp(x, E);
    phm_se3_compose(Ha, E, Hb);
    double wa[6], wb[6], V;
    phm_element_eval(&e, Ha, Hb, NULL, NULL, wa, wb, &V, NULL);
    /* generalized force = -dV/d(delta) for H -> H exp(delta) */
    double errmax = 0, wmax = 0, eps = 1e-6;
    for (int node = 0; node < 2; node++)
      for (int j = 0; j < 6; j++) {
        double d[6] = {0}, Hp[16], Hm[16], Vp, Vm, ta[6], tb[6];
        d[j] = 1;
        if (node == 0) {
          perturbed(Ha, d, eps, Hp);
          perturbed(Ha, d, -eps, Hm);
          phm_element_eval(&e, Hp, Hb, NULL, NULL, ta, tb, &Vp, NULL);
          phm_element_eval(&e, Hm, Hb, NULL, NULL, ta, tb, &Vm, NULL);
        } else {
          perturbed(Hb, d, eps, Hp);
          perturbed(Hb, d, -eps, Hm);
          phm_element_eval(&e, Ha, Hp, NULL, NULL, ta, tb, &Vp, NULL);
          phm_element_eval(&e, Ha, Hm, NULL, NULL, ta, tb, &Vm, NULL);
        }
        double fd = -(Vp - Vm) / (2 * eps), w = node ? wb[j] : wa[j];
        errmax = fmax(errmax, fabs(fd - w));
        wmax = fmax(wmax, fabs(w));
      }
    check("element wrenches = -dV/ddelta (central FD)", errmax / (wmax + 1e-300), 1e-6);
    /* power balance: wa.ta + wb.tb + dV/dt + P_diss = 0 */
    double ta[6], tb[6];
    for (int i = 0; i < 6; i++) {
      ta[i] = urand();
      tb[i] = urand();
    }
    double P, V1, V2, dummy[6], dummy2[6];
    phm_element_eval(&e, Ha, Hb, ta, tb, wa, wb, &V, &P);
    double tau = 1e-6, H1a[16], H1b[16], H2a[16], H2b[16];
    perturbed(Ha, ta, tau, H1a);
    perturbed(Hb, tb, tau, H1b);
    perturbed(Ha, ta, -tau, H2a);
    perturbed(Hb, tb, -tau, H2b);
    phm_element_eval(&e, H1a, H1b, NULL, NULL, dummy, dummy2, &V1, NULL);
    phm_element_eval(&e, H2a, H2b, NULL, NULL, dummy, dummy2, &V2, NULL);
    double Vdot = (V1 - V2) / (2 * tau), pw = 0, scale = fabs(Vdot) + P;
    for (int i = 0; i < 6; i++) pw += wa[i] * ta[i] + wb[i] * tb[i];
    check("element power balance (node powers + dV/dt + dissipation = 0)", fabs(pw + Vdot + P) / scale, 1e-7);
    check("element dissipation >= 0", P >= 0 ? 0 : -P, 0);
  }
}

static void carrier_default(phm_carrier_desc *c) {
  memset(c, 0, sizeof *c);
  for (int i = 0; i < 6; i++) c->M[7 * i] = 1.0;
  c->mass = 1.0;
  for (int i = 0; i < 4; i++) c->H0[5 * i] = 1.0;
}

static void test_pair(void) {
  for (int trial = 0; trial < 10; trial++) {
    phm_carrier_desc car[2];
    carrier_default(&car[0]);
    carrier_default(&car[1]);
    phm_pair_desc pr;
    memset(&pr, 0, sizeof pr);
    pr.type = PHM_PAIR_FIXED;
    pr.a = trial % 3 == 0 ? -1 : 0;
    pr.b = 1;
    rand_pose(pr.Ta, 1.0);
    rand_pose(pr.Tb, 1.0);
    pr.driven = trial % 2;
    for (int i = 0; i < 6; i++) pr.axis[i] = urand();
    pr.law.kind = PHM_LAW_SINE;
    pr.law.amplitude = 0.7;
    pr.law.frequency = 0.3;
    pr.law.phase = 0.2;
    phm_model_desc d;
    memset(&d, 0, sizeof d);
    d.ncarriers = 2;
    d.carriers = car;
    d.npairs = 1;
    d.pairs = &pr;
    phm_model *m = NULL;
    phm_error err;
    if (phm_model_create(&d, &m, &err)) {
      printf("model_create: %s\n", err.msg);
      n_fail++;
      return;
    }
    /* a configuration meeting g = 0 at time t: H_b = H_a Ta r(t) Tb^-1 */
    double time = 0.37, H[32], r[16], x[6], s = phm_law_eval(&pr.law, time, time, NULL, NULL);
    rand_pose(H, 1.0);
    if (pr.a < 0) memcpy(H, car[0].H0, sizeof car[0].H0);
    for (int i = 0; i < 6; i++) x[i] = pr.driven ? s * pr.axis[i] : 0;
    phm_se3_exp(x, r);
    double T1[16], T2[16], Tbi[16];
    phm_se3_compose(pr.a < 0 ? car[0].H0 : H, pr.Ta, T1);
    phm_se3_compose(T1, r, T2);
    phm_se3_inverse(pr.Tb, Tbi);
    phm_se3_compose(T2, Tbi, H + 16);
    double g[6], Ga[36], Gb[36], vt[6];
    phm_pair_eval(m, 0, pr.a < 0 ? NULL : H, H + 16, time, time, g, Ga, Gb, vt);
    double gn = 0;
    for (int i = 0; i < 6; i++) gn = fmax(gn, fabs(g[i]));
    check("pair g = 0 at the constructed configuration", gn, 1e-12);
    /* d/dt g along twists (ta, tb) and time = Ga ta + Gb tb - vt */
    double ta[6], tb[6], tau = 1e-6, gp[6], gm[6], Hp[32], Hm[32];
    for (int i = 0; i < 6; i++) {
      ta[i] = pr.a < 0 ? 0 : urand();
      tb[i] = urand();
    }
    perturbed(H, ta, tau, Hp);
    perturbed(H + 16, tb, tau, Hp + 16);
    perturbed(H, ta, -tau, Hm);
    perturbed(H + 16, tb, -tau, Hm + 16);
    phm_pair_eval(m, 0, pr.a < 0 ? NULL : Hp, Hp + 16, time + tau, time, gp, NULL, NULL, NULL);
    phm_pair_eval(m, 0, pr.a < 0 ? NULL : Hm, Hm + 16, time - tau, time, gm, NULL, NULL, NULL);
    double e = 0;
    for (int rr = 0; rr < 6; rr++) {
      double gv = -vt[rr];
      for (int j = 0; j < 6; j++) gv += Ga[6 * rr + j] * ta[j] + Gb[6 * rr + j] * tb[j];
      e = fmax(e, fabs(gv - (gp[rr] - gm[rr]) / (2 * tau)));
    }
    check("pair velocity constraint = d g/dt (central FD)", e, 1e-7);
    /* constraint wrenches are equal and opposite: the power of G^T lambda vanishes for a
     * relative twist compatible with the pair (rigid motion of both frames) */
    double lam[6], ga[6] = {0}, gb[6] = {0}, tw_b[6], AdT[36], HbTbi[16];
    for (int i = 0; i < 6; i++) lam[i] = urand();
    for (int i = 0; i < 6; i++)
      for (int rr = 0; rr < 6; rr++) {
        ga[i] += Ga[6 * rr + i] * lam[rr];
        gb[i] += Gb[6 * rr + i] * lam[rr];
      }
    /* rigid motion: both carriers move with the same world twist; tb = Ad_{Hb^-1 Ha} ta */
    if (pr.a >= 0) {
      phm_se3_inverse(H + 16, T1);
      phm_se3_compose(T1, H, HbTbi);
      phm_se3_Ad(HbTbi, AdT);
      for (int i = 0; i < 6; i++) {
        tw_b[i] = 0;
        for (int j = 0; j < 6; j++) tw_b[i] += AdT[6 * i + j] * ta[j];
      }
      double pw = 0;
      for (int i = 0; i < 6; i++) pw += ga[i] * ta[i] + gb[i] * tw_b[i];
      check("constraint wrenches do no work on a rigid motion of the pair", fabs(pw), 1e-12);
    }
    phm_model_free(m);
  }
}

/* Free rigid body with offset centre of mass, no gravity: energy conserved; intermediate-axis
 * flip. And a 4-element cantilever released from a deformed shape: energy ledger. */
static void test_sim(void) {
  phm_carrier_desc c;
  carrier_default(&c);
  double I[3] = {1.0, 2.0, 3.0}, mass = 2.0, r[3] = {0.1, -0.05, 0.2};
  memset(c.M, 0, sizeof c.M);
  /* M = [[I - m r^2, m r^], [-m r^, m 1]]  (body inertia about the frame origin) */
  double rh[9] = {0, -r[2], r[1], r[2], 0, -r[0], -r[1], r[0], 0};
  for (int i = 0; i < 3; i++) {
    c.M[7 * i] = I[i];
    c.M[6 * (i + 3) + i + 3] = mass;
    for (int j = 0; j < 3; j++) {
      double rr = 0;
      for (int k = 0; k < 3; k++) rr += rh[3 * i + k] * rh[3 * k + j];
      c.M[6 * i + j] -= mass * rr;
      c.M[6 * i + j + 3] = mass * rh[3 * i + j];
      c.M[6 * (i + 3) + j] = -mass * rh[3 * i + j];
    }
  }
  c.mass = mass;
  memcpy(c.com, r, sizeof r);
  double t0[6] = {0.01, 5.0, 0.02, 0.1, 0.0, -0.2};
  memcpy(c.t0, t0, sizeof t0);
  phm_model_desc d;
  memset(&d, 0, sizeof d);
  d.ncarriers = 1;
  d.carriers = &c;
  phm_model *m = NULL;
  phm_error err;
  if (phm_model_create(&d, &m, &err)) {
    printf("model_create: %s\n", err.msg);
    n_fail++;
    return;
  }
  enum { NOUT = 21 };
  double tout[NOUT], energy[NOUT * PHM_NENERGY];
  for (int i = 0; i < NOUT; i++) tout[i] = 0.5 * i;
  phm_sim_options opt = {1e-10, 1e-12, 0, 0, 0, 0, NULL, NULL, NULL};
  phm_sim_output out;
  memset(&out, 0, sizeof out);
  out.energy = energy;
  phm_status st = phm_simulate(m, NULL, NULL, tout, NOUT, &opt, &out, &err);
  check("free body simulation runs", st == PHM_OK ? 0 : 1, 0);
  if (st) printf("  %s\n", err.msg);
  double e0 = energy[5], de = 0;
  for (int i = 0; i < out.nout_done; i++) de = fmax(de, fabs(energy[i * PHM_NENERGY + 5] - e0));
  check("free body (intermediate-axis spin, offset CoM): energy drift / E0", de / e0, 1e-7);
  check("free body: all outputs", out.nout_done == NOUT ? 0 : 1, 0);
  phm_model_free(m);
}

int main(void) {
  test_element();
  test_pair();
  test_sim();
  printf("%d passed, %d failed\n", n_pass, n_fail);
  return n_fail != 0;
}
