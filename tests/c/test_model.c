/* test_model.c -- C unit tests of the model kernels (csrc/model/, csrc/dae/, csrc/solve/) against
 * independent references: central finite differences of the elastic energy and of the position
 * constraints, the power balance of an element, energy conservation of a free body. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model.h"
#include "pose.h"

/* The rows of the pair table (csrc/model/pair.c) in its order; main checks them by name. */
enum {
  PHM_PAIR_FIXED, PHM_PAIR_REVOLUTE, PHM_PAIR_PRISMATIC, PHM_PAIR_HELICAL, PHM_PAIR_CYLINDRICAL,
  PHM_PAIR_UNIVERSAL, PHM_PAIR_SPHERICAL, PHM_PAIR_PLANAR, PHM_PAIR_FREE, PAIR_TYPES
};
static const char *const pair_names[PAIR_TYPES] = {"fixed", "revolute", "prismatic", "helical",
                                                   "cylindrical", "universal", "spherical",
                                                   "planar", "free"};

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
    phm_element_eval(&e, Ha, Hb, NULL, NULL, wa, wb, &V, NULL, NULL);
    /* generalized force = -dV/d(delta) for H -> H exp(delta) */
    double errmax = 0, wmax = 0, eps = 1e-6;
    for (int node = 0; node < 2; node++)
      for (int j = 0; j < 6; j++) {
        double d[6] = {0}, Hp[16], Hm[16], Vp, Vm, ta[6], tb[6];
        d[j] = 1;
        if (node == 0) {
          perturbed(Ha, d, eps, Hp);
          perturbed(Ha, d, -eps, Hm);
          phm_element_eval(&e, Hp, Hb, NULL, NULL, ta, tb, &Vp, NULL, NULL);
          phm_element_eval(&e, Hm, Hb, NULL, NULL, ta, tb, &Vm, NULL, NULL);
        } else {
          perturbed(Hb, d, eps, Hp);
          perturbed(Hb, d, -eps, Hm);
          phm_element_eval(&e, Ha, Hp, NULL, NULL, ta, tb, &Vp, NULL, NULL);
          phm_element_eval(&e, Ha, Hm, NULL, NULL, ta, tb, &Vm, NULL, NULL);
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
    phm_element_eval(&e, Ha, Hb, ta, tb, wa, wb, &V, &P, NULL);
    double tau = 1e-6, H1a[16], H1b[16], H2a[16], H2b[16];
    perturbed(Ha, ta, tau, H1a);
    perturbed(Hb, tb, tau, H1b);
    perturbed(Ha, ta, -tau, H2a);
    perturbed(Hb, tb, -tau, H2b);
    phm_element_eval(&e, H1a, H1b, NULL, NULL, dummy, dummy2, &V1, NULL, NULL);
    phm_element_eval(&e, H2a, H2b, NULL, NULL, dummy, dummy2, &V2, NULL, NULL);
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
    phm_pair_eval(m, 0, pr.a < 0 ? NULL : H, H + 16, NULL, time, time, g, Ga, Gb, vt);
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
    phm_pair_eval(m, 0, pr.a < 0 ? NULL : Hp, Hp + 16, NULL, time + tau, time, gp, NULL, NULL, NULL);
    phm_pair_eval(m, 0, pr.a < 0 ? NULL : Hm, Hm + 16, NULL, time - tau, time, gm, NULL, NULL, NULL);
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

/* Forward kinematics h(x) of each pair type (independent of phm_pair_kin). */
static void pair_fk(int type, double pitch, const double *x, double h[16]) {
  double z[6] = {0}, A[16], B[16];
  switch (type) {
  case PHM_PAIR_REVOLUTE: z[2] = x[0]; phm_se3_exp(z, h); break;
  case PHM_PAIR_PRISMATIC: z[5] = x[0]; phm_se3_exp(z, h); break;
  case PHM_PAIR_HELICAL: z[2] = x[0]; z[5] = pitch * x[0]; phm_se3_exp(z, h); break;
  case PHM_PAIR_CYLINDRICAL: z[2] = x[0]; z[5] = x[1]; phm_se3_exp(z, h); break;
  case PHM_PAIR_UNIVERSAL:
    z[0] = x[0]; phm_se3_exp(z, A);
    z[0] = 0; z[1] = x[1]; phm_se3_exp(z, B);
    phm_se3_compose(A, B, h);
    break;
  case PHM_PAIR_SPHERICAL: z[0] = x[0]; z[1] = x[1]; z[2] = x[2]; phm_se3_exp(z, h); break;
  case PHM_PAIR_PLANAR:
    z[2] = x[0]; phm_se3_exp(z, B);
    memcpy(h, B, sizeof B);
    h[3] = x[1]; h[7] = x[2];
    break;
  case PHM_PAIR_FREE:
    z[0] = x[0]; z[1] = x[1]; z[2] = x[2]; phm_se3_exp(z, h);
    h[3] = x[3]; h[7] = x[4]; h[11] = x[5];
    break;
  default: phm_se3_exp(z, h); break;
  }
}

/* H_b = H_a Ta h(x) Tb^-1 */
static void place_b(const double *Ha, const double Ta[16], const double Tb[16], int type,
                    double pitch, const double *x, double Hb[16]) {
  double h[16], A[16], B[16], Tbi[16], I[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  pair_fk(type, pitch, x, h);
  phm_se3_compose(Ha ? Ha : I, Ta, A);
  phm_se3_compose(A, h, B);
  phm_se3_inverse(Tb, Tbi);
  phm_se3_compose(B, Tbi, Hb);
}

static double det_small(double *A, int n) { /* Gaussian elimination with partial pivoting */
  double det = 1;
  for (int c = 0; c < n; c++) {
    int p = c;
    for (int r = c + 1; r < n; r++)
      if (fabs(A[r * n + c]) > fabs(A[p * n + c])) p = r;
    if (A[p * n + c] == 0) return 0;
    if (p != c) {
      for (int j = 0; j < n; j++) { double t = A[c * n + j]; A[c * n + j] = A[p * n + j]; A[p * n + j] = t; }
      det = -det;
    }
    det *= A[c * n + c];
    for (int r = c + 1; r < n; r++) {
      double f = A[r * n + c] / A[c * n + c];
      for (int j = c; j < n; j++) A[r * n + j] -= f * A[c * n + j];
    }
  }
  return det;
}

/* Every pair type: g = 0 on the joint manifold h(x); exact joint coordinates (multi-turn branch);
 * allowed motions x(s) = x + s xi leave g = 0 and G t = 0 and give xdot = xi (finite differences);
 * the GGL matrix (dg/dq) G^T has the determinant of G G^T (equal for the types whose g is exactly
 * W^T-aligned); an actuator's wrenches deliver exactly u . xdot. */
static void test_pair_types(void) {
  for (int type = 1; type <= PHM_PAIR_FREE; type++)
    for (int trial = 0; trial < 6; trial++) {
      char name[96];
      const char *tn = phm_pair_type(type)->name;
      phm_carrier_desc car[2];
      carrier_default(&car[0]);
      carrier_default(&car[1]);
      phm_pair_desc pr;
      memset(&pr, 0, sizeof pr);
      pr.type = type;
      pr.a = trial % 3 == 0 ? -1 : 0;
      pr.b = 1;
      pr.pitch = type == PHM_PAIR_HELICAL ? 0.3 * urand() : 0.0;
      rand_pose(pr.Ta, 1.0);
      rand_pose(pr.Tb, 1.0);
      int mc = phm_pair_type(type)->m, k = 6 - mc;
      double x[6], xi[6];
      for (int i = 0; i < 6; i++) {
        x[i] = 1.2 * urand();
        xi[i] = urand();
      }
      if (type == PHM_PAIR_REVOLUTE || type == PHM_PAIR_HELICAL || type == PHM_PAIR_CYLINDRICAL ||
          type == PHM_PAIR_PLANAR)
        x[0] += 2 * 3.14159265358979 * (trial - 2); /* multi-turn */
      pr.has_x0 = 1;
      memcpy(pr.x0, x, sizeof x);
      phm_actuator_desc ac;
      memset(&ac, 0, sizeof ac);
      ac.pair = 0;
      ac.kind = PHM_ACT_PD;
      for (int i = 0; i < 6; i++) {
        ac.kp[i] = 1 + fabs(urand());
        ac.kd[i] = fabs(urand());
        ac.x_set[i] = urand();
        ac.vec[i] = urand();
      }
      ac.law.kind = PHM_LAW_SINE;
      ac.law.amplitude = 0.5;
      ac.law.frequency = 0.7;
      phm_model_desc d;
      memset(&d, 0, sizeof d);
      d.ncarriers = 2;
      d.carriers = car;
      d.npairs = 1;
      d.pairs = &pr;
      d.nactuators = 1;
      d.actuators = &ac;
      phm_model *m = NULL;
      phm_error err;
      if (phm_model_create(&d, &m, &err)) {
        printf("model_create (%s): %s\n", tn, err.msg);
        n_fail++;
        continue;
      }
      double H[32], Hp[32], Hm[32];
      rand_pose(H, 1.0);
      const double *Ha = pr.a < 0 ? NULL : H;
      place_b(Ha, pr.Ta, pr.Tb, type, pr.pitch, x, H + 16);
      double g[6], Ga[36], Gb[36], xe[6], xref[6];
      for (int i = 0; i < 6; i++) xref[i] = x[i] + 0.3 * urand();
      phm_pair_eval(m, 0, Ha, H + 16, xref, 0.0, 0.0, g, Ga, Gb, NULL);
      double e = 0;
      for (int i = 0; i < mc; i++) e = fmax(e, fabs(g[i]));
      snprintf(name, sizeof name, "%s: g = 0 on the joint manifold", tn);
      check(name, e, 1e-12);
      phm_pair_joint(m, 0, Ha, H + 16, NULL, NULL, xref, xe, NULL);
      e = 0;
      for (int i = 0; i < k; i++) e = fmax(e, fabs(xe[i] - x[i]));
      snprintf(name, sizeof name, "%s: joint coordinates extracted (branch of the reference)", tn);
      check(name, e, 1e-12);
      /* allowed motion: a moves with ta, the joint with xi */
      double ta[6], tb[6], eps = 1e-5, xp[6], xm[6];
      for (int i = 0; i < 6; i++) ta[i] = pr.a < 0 ? 0 : urand();
      for (int i = 0; i < 6; i++) { xp[i] = x[i] + eps * xi[i]; xm[i] = x[i] - eps * xi[i]; }
      perturbed(H, ta, eps, Hp);
      perturbed(H, ta, -eps, Hm);
      place_b(pr.a < 0 ? NULL : Hp, pr.Ta, pr.Tb, type, pr.pitch, xp, Hp + 16);
      place_b(pr.a < 0 ? NULL : Hm, pr.Ta, pr.Tb, type, pr.pitch, xm, Hm + 16);
      { /* tb = central difference of log(H_b^-1 H_b(s)) */
        double Hi[16], D[16], lp[6], lm[6];
        phm_se3_inverse(H + 16, Hi);
        phm_se3_compose(Hi, Hp + 16, D);
        phm_se3_log(D, lp);
        phm_se3_compose(Hi, Hm + 16, D);
        phm_se3_log(D, lm);
        for (int i = 0; i < 6; i++) tb[i] = (lp[i] - lm[i]) / (2 * eps);
      }
      double gp[6], gm[6], xd[6];
      phm_pair_eval(m, 0, pr.a < 0 ? NULL : Hp, Hp + 16, xref, 0, 0, gp, NULL, NULL, NULL);
      phm_pair_eval(m, 0, pr.a < 0 ? NULL : Hm, Hm + 16, xref, 0, 0, gm, NULL, NULL, NULL);
      double eg = 0, eG = 0, ex = 0;
      for (int r = 0; r < mc; r++) {
        double gv = 0;
        for (int j = 0; j < 6; j++) gv += Ga[6 * r + j] * ta[j] + Gb[6 * r + j] * tb[j];
        eG = fmax(eG, fabs(gv));
        eg = fmax(eg, fmax(fabs(gp[r]), fabs(gm[r])));
      }
      phm_pair_joint(m, 0, Ha, H + 16, pr.a < 0 ? NULL : ta, tb, xref, xe, xd);
      double xie[6];
      memcpy(xie, xi, sizeof xie);
      if (type == PHM_PAIR_SPHERICAL || type == PHM_PAIR_FREE) {
        /* rotation vector r: the rate is the body angular velocity omega = jac(-r) dr/dt */
        double mr[3] = {-x[0], -x[1], -x[2]}, J[9];
        phm_so3_jac(mr, J);
        for (int i = 0; i < 3; i++) xie[i] = J[3 * i] * xi[0] + J[3 * i + 1] * xi[1] + J[3 * i + 2] * xi[2];
      }
      for (int i = 0; i < k; i++) ex = fmax(ex, fabs(xd[i] - xie[i]));
      snprintf(name, sizeof name, "%s: allowed motion keeps g = 0", tn);
      check(name, eg, 1e-11);
      snprintf(name, sizeof name, "%s: allowed motion meets G t = 0 (FD twist)", tn);
      check(name, eG, 1e-8);
      snprintf(name, sizeof name, "%s: xdot = Phi^T t_rel equals the coordinate rate (FD)", tn);
      check(name, ex, 1e-8);
      /* constrained directions: A = (dg/dq) G^T by finite differences vs G G^T */
      if (mc > 0) {
        double A[36], GG[36];
        for (int r = 0; r < mc; r++) {
          double da[6], db[6];
          for (int j = 0; j < 6; j++) { da[j] = pr.a < 0 ? 0 : Ga[6 * r + j]; db[j] = Gb[6 * r + j]; }
          perturbed(H, da, 1e-6, Hp);
          perturbed(H + 16, db, 1e-6, Hp + 16);
          perturbed(H, da, -1e-6, Hm);
          perturbed(H + 16, db, -1e-6, Hm + 16);
          phm_pair_eval(m, 0, pr.a < 0 ? NULL : Hp, Hp + 16, xref, 0, 0, gp, NULL, NULL, NULL);
          phm_pair_eval(m, 0, pr.a < 0 ? NULL : Hm, Hm + 16, xref, 0, 0, gm, NULL, NULL, NULL);
          for (int i = 0; i < mc; i++) A[i * mc + r] = (gp[i] - gm[i]) / 2e-6;
          for (int i = 0; i < mc; i++) {
            double s = 0;
            for (int j = 0; j < 6; j++) s += Ga[6 * i + j] * da[j] + Gb[6 * i + j] * db[j];
            GG[i * mc + r] = s;
          }
        }
        int exact = type != PHM_PAIR_HELICAL && type != PHM_PAIR_CYLINDRICAL;
        double eA = 0, sc = 0;
        for (int i = 0; i < mc * mc; i++) { eA = fmax(eA, fabs(A[i] - GG[i])); sc = fmax(sc, fabs(GG[i])); }
        if (exact) {
          snprintf(name, sizeof name, "%s: dg/dq G^T = G G^T (FD)", tn);
          check(name, eA / sc, 1e-7);
        }
        double dA = det_small(A, mc), dG = det_small(GG, mc);
        snprintf(name, sizeof name, "%s: det(dg/dq G^T) = det(G G^T) (GGL nonsingular)", tn);
        check(name, fabs(dA / dG - 1), 1e-6);
      }
      /* actuator: the power of its wrenches on the two carriers equals u . xdot */
      {
        double tw[12], wr[12], Pp[1], eff[6], Ps = 0;
        for (int i = 0; i < 12; i++) tw[i] = urand();
        if (pr.a < 0) for (int i = 0; i < 6; i++) tw[i] = 0;
        phm_applied(m, H, tw, xref, 0.3, 0.3, 1.0, wr, NULL, NULL, &Ps, Pp, eff);
        double pw = 0;
        for (int i = 0; i < 12; i++) pw += wr[i] * tw[i];
        phm_pair_joint(m, 0, Ha, H + 16, pr.a < 0 ? NULL : tw, tw + 6, xref, xe, xd);
        double ux = 0;
        for (int i = 0; i < k; i++) ux += eff[i] * xd[i];
        snprintf(name, sizeof name, "%s: actuator wrench power = u . xdot = port power", tn);
        check(name, fabs(pw - ux) + fabs(Pp[0] - ux) + fabs(Ps - ux), 1e-11 * (1 + fabs(ux)));
        /* PD law: u = -kp (x - x_set - s vec) - kd (xdot - ds vec) */
        double ds, s = phm_law_eval(&ac.law, 0.3, 0.3, &ds, NULL), eu = 0;
        for (int i = 0; i < k; i++)
          eu = fmax(eu, fabs(eff[i] - (-ac.kp[i] * (xe[i] - ac.x_set[i] - s * ac.vec[i]) - ac.kd[i] * (xd[i] - ds * ac.vec[i]))));
        snprintf(name, sizeof name, "%s: PD effort formula", tn);
        check(name, eu, 1e-12);
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
  phm_sim_options opt = {1e-10, 1e-12, 0, 0, 0, 0, PHM_ERRTEST_ALL, NULL, NULL, NULL, PHM_INTEGRATOR_IDA, 0, 0, 0, 0, NULL};
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
  check("pair table: number of types", fabs((double)(phm_pair_type_count() - PAIR_TYPES)), 0);
  for (int t = 0; t < PAIR_TYPES; t++)
    check(pair_names[t], strcmp(phm_pair_type(t)->name, pair_names[t]) != 0, 0);
  test_element();
  test_pair();
  test_pair_types();
  test_sim();
  printf("%d passed, %d failed\n", n_pass, n_fail);
  return n_fail != 0;
}
