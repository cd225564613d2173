/* test_pair.c -- csrc/model/pair_types.c and pair.c, the pair table and the evaluation of a pair: the table's rows
 * and their order, a driven fixed pair against its prescribed motion, every pair type's
 * constraints, Jacobian blocks and joint coordinates against finite differences and an
 * independent forward kinematics (pair_fk below), phm_pair_type_pose and
 * phm_pair_type_coordinates, the rows a drop mask keeps, joint coordinates driven by laws, and the
 * closed forms and shortcuts of the evaluation against the table's general path. */
#include "check.h"
#include "model.h"

/* The rows of the pair table (csrc/model/pair_types.c) in its order; the first case checks them by name. */
enum {
  PHM_PAIR_FIXED, PHM_PAIR_REVOLUTE, PHM_PAIR_PRISMATIC, PHM_PAIR_HELICAL, PHM_PAIR_CYLINDRICAL,
  PHM_PAIR_UNIVERSAL, PHM_PAIR_SPHERICAL, PHM_PAIR_PLANAR, PHM_PAIR_FREE, PHM_PAIR_SLOT, PAIR_TYPES
};
static const char *const pair_names[PAIR_TYPES] = {"fixed", "revolute", "prismatic", "helical",
                                                   "cylindrical", "universal", "spherical",
                                                   "planar", "free", "slot"};
static const double I4[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

/* Forward kinematics h(x) of each pair type, written from the table's docs (independent of
 * phm_pair_kin and phm_pair_type_pose). */
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
  case PHM_PAIR_SLOT: /* Rz(x0), then x1 along F_a's x */
    z[2] = x[0]; phm_se3_exp(z, h);
    h[3] = x[1];
    break;
  case PHM_PAIR_FREE:
    z[0] = x[0]; z[1] = x[1]; z[2] = x[2]; phm_se3_exp(z, h);
    h[3] = x[3]; h[7] = x[4]; h[11] = x[5];
    break;
  default: phm_se3_exp(z, h); break;
  }
}

/* H_b = H_a Ta h(x) Tb^-1 with h from pair_fk (Ha NULL: ground) */
static void place_b_fk(const double *Ha, const double Ta[16], const double Tb[16], int type,
                       double pitch, const double *x, double Hb[16]) {
  double h[16];
  pair_fk(type, pitch, x, h);
  place_b(Ha, Ta, Tb, h, Hb);
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

/* g of pair 0 at the two-carrier poses H (a's NULL-able: a_ground) moved along twists (ta, tb)
 * by +tau and -tau, at times time + dt and time - dt (reference time `time`): into gp, gm. */
static void g_moved(const phm_model *m, int a_ground, const double H[32], const double ta[6],
                    const double tb[6], double tau, const double *x, double time, double dt,
                    double *gp, double *gm) {
  double Hp[32], Hm[32];
  perturbed(H, ta, tau, Hp);
  perturbed(H + 16, tb, tau, Hp + 16);
  perturbed(H, ta, -tau, Hm);
  perturbed(H + 16, tb, -tau, Hm + 16);
  phm_pair_eval(m, 0, a_ground ? NULL : Hp, Hp + 16, x, time + dt, time, gp, NULL, NULL, NULL);
  phm_pair_eval(m, 0, a_ground ? NULL : Hm, Hm + 16, x, time - dt, time, gm, NULL, NULL, NULL);
}

static void pair_table_lists_the_types_in_order(void) {
  check("pair table: number of types", fabs((double)(phm_pair_type_count() - PAIR_TYPES)), 0);
  for (int t = 0; t < PAIR_TYPES; t++) {
    char name[96];
    snprintf(name, sizeof name, "pair table row %d is %s", t, pair_names[t]);
    check(name, strcmp(phm_pair_type(t)->name, pair_names[t]) != 0, 0);
    /* k = 6 - m joint coordinates with a unit each, m constraint-wrench directions */
    const phm_pair_type_info *ti = phm_pair_type(t);
    int k = 6 - ti->m, ok = ti->m >= 0 && ti->m <= 6;
    for (int i = 0; i < 6 && ok; i++) {
      ok &= (i < k) == (ti->units[i] != NULL) && (i < ti->m) == (ti->directions[i] != NULL);
      if (ok && i < k) ok = strcmp(ti->units[i], "rad") == 0 || strcmp(ti->units[i], "m") == 0;
    }
    CHECK(ok, "pair table row %s: k = %d units (rad or m) and m = %d directions", ti->name, k, ti->m);
  }
  CHECK(phm_pair_type(-1) == NULL && phm_pair_type(PAIR_TYPES) == NULL, "no row outside the table");
}

/* A fixed pair, driven (r(t) = exp(law(t) axis)) or not, to ground or between two carriers: g = 0
 * at H_b = H_a Ta r(t) Tb^-1, the velocity constraint is dg/dt, and the constraint wrenches do
 * no work on a rigid motion of the two carriers. */
static void driven_fixed_pair_follows_its_prescribed_motion(void) {
  for (int trial = 0; trial < 10; trial++) {
    phm_pair_desc pr;
    memset(&pr, 0, sizeof pr);
    pr.type = PHM_PAIR_FIXED;
    pr.a = trial % 3 == 0 ? -1 : 0;
    pr.b = 1;
    rand_pose(pr.Ta, 1.0);
    rand_pose(pr.Tb, 1.0);
    pr.driven = trial % 2;
    for (int i = 0; i < 6; i++) pr.axis[i] = rand11();
    pr.law.kind = PHM_LAW_SINE;
    pr.law.amplitude = 0.7;
    pr.law.frequency = 0.3;
    pr.law.phase = 0.2;
    phm_model *m = two_carrier_model(&pr, NULL, 0);
    if (!m) return;
    /* a configuration meeting g = 0 at time t: H_b = H_a Ta r(t) Tb^-1 */
    double time = 0.37, H[32], r[16], x[6], s = phm_law_eval(&pr.law, time, time, NULL, NULL);
    rand_pose(H, 1.0);
    if (pr.a < 0) memcpy(H, I4, sizeof I4);
    for (int i = 0; i < 6; i++) x[i] = pr.driven ? s * pr.axis[i] : 0;
    phm_se3_exp(x, r);
    place_b(H, pr.Ta, pr.Tb, r, H + 16);
    double g[6], Ga[36], Gb[36], vt[6];
    phm_pair_eval(m, 0, pr.a < 0 ? NULL : H, H + 16, NULL, time, time, g, Ga, Gb, vt);
    check("pair g = 0 at the constructed configuration", maxabs(6, g), 1e-12);
    /* d/dt g along twists (ta, tb) and time = Ga ta + Gb tb - vt */
    double ta[6], tb[6], tau = 1e-6, gp[6], gm[6];
    for (int i = 0; i < 6; i++) {
      ta[i] = pr.a < 0 ? 0 : rand11();
      tb[i] = rand11();
    }
    g_moved(m, pr.a < 0, H, ta, tb, tau, NULL, time, tau, gp, gm);
    double e = 0;
    for (int rr = 0; rr < 6; rr++) {
      double gv = -vt[rr];
      for (int j = 0; j < 6; j++) gv += Ga[6 * rr + j] * ta[j] + Gb[6 * rr + j] * tb[j];
      e = fmax(e, fabs(gv - (gp[rr] - gm[rr]) / (2 * tau)));
    }
    check("pair velocity constraint = d g/dt (central FD)", e, 1e-7);
    /* constraint wrenches are equal and opposite: the power of G^T lambda vanishes for a
     * relative twist compatible with the pair (rigid motion of both frames) */
    double lam[6], ga[6] = {0}, gb[6] = {0}, tw_b[6], AdT[36], Hbi[16], HbiHa[16];
    for (int i = 0; i < 6; i++) lam[i] = rand11();
    for (int i = 0; i < 6; i++)
      for (int rr = 0; rr < 6; rr++) {
        ga[i] += Ga[6 * rr + i] * lam[rr];
        gb[i] += Gb[6 * rr + i] * lam[rr];
      }
    /* rigid motion: both carriers move with the same world twist; tb = Ad_{Hb^-1 Ha} ta */
    if (pr.a >= 0) {
      phm_se3_inverse(H + 16, Hbi);
      phm_se3_compose(Hbi, H, HbiHa);
      phm_se3_Ad(HbiHa, AdT);
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

/* Every pair type: g = 0 on the joint manifold h(x); exact joint coordinates (multi-turn branch);
 * allowed motions x(s) = x + s xi leave g = 0 and G t = 0 and give xdot = xi (finite differences);
 * the GGL matrix (dg/dq) G^T has the determinant of G G^T (equal for the types whose g is exactly
 * W^T-aligned). */
static void every_type_vanishes_on_its_manifold_with_consistent_jacobians(void) {
  for (int type = 1; type <= PHM_PAIR_FREE; type++)
    for (int trial = 0; trial < 6; trial++) {
      char name[96];
      const char *tn = phm_pair_type(type)->name;
      phm_pair_desc pr;
      rand_pair(type, trial, &pr);
      int mc = phm_pair_type(type)->m, k = 6 - mc;
      double x[6], xi[6];
      rand_joint_coordinates(type, trial - 2, x);
      for (int i = 0; i < 6; i++) xi[i] = rand11();
      pr.has_x0 = 1;
      memcpy(pr.x0, x, sizeof x);
      phm_model *m = two_carrier_model(&pr, NULL, 0);
      if (!m) continue;
      double H[32], Hp[32], Hm[32];
      rand_pose(H, 1.0);
      const double *Ha = pr.a < 0 ? NULL : H;
      place_b_fk(Ha, pr.Ta, pr.Tb, type, pr.pitch, x, H + 16);
      double g[6], Ga[36], Gb[36], xe[6], xref[6];
      for (int i = 0; i < 6; i++) xref[i] = x[i] + 0.3 * rand11();
      phm_pair_eval(m, 0, Ha, H + 16, xref, 0.0, 0.0, g, Ga, Gb, NULL);
      snprintf(name, sizeof name, "%s: g = 0 on the joint manifold", tn);
      check(name, maxabs(mc, g), 1e-12);
      phm_pair_joint(m, 0, Ha, H + 16, NULL, NULL, xref, xe, NULL);
      snprintf(name, sizeof name, "%s: joint coordinates extracted (branch of the reference)", tn);
      check(name, maxdiff(k, xe, x), 1e-12);
      /* allowed motion: a moves with ta, the joint with xi */
      double ta[6], tb[6], eps = 1e-5, xp[6], xm[6];
      for (int i = 0; i < 6; i++) ta[i] = pr.a < 0 ? 0 : rand11();
      for (int i = 0; i < 6; i++) { xp[i] = x[i] + eps * xi[i]; xm[i] = x[i] - eps * xi[i]; }
      perturbed(H, ta, eps, Hp);
      perturbed(H, ta, -eps, Hm);
      place_b_fk(pr.a < 0 ? NULL : Hp, pr.Ta, pr.Tb, type, pr.pitch, xp, Hp + 16);
      place_b_fk(pr.a < 0 ? NULL : Hm, pr.Ta, pr.Tb, type, pr.pitch, xm, Hm + 16);
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
      double eg = 0, eG = 0;
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
      snprintf(name, sizeof name, "%s: allowed motion keeps g = 0", tn);
      check(name, eg, 1e-11);
      snprintf(name, sizeof name, "%s: allowed motion meets G t = 0 (FD twist)", tn);
      check(name, eG, 1e-8);
      snprintf(name, sizeof name, "%s: xdot = Phi^T t_rel equals the coordinate rate (FD)", tn);
      check(name, maxdiff(k, xd, xie), 1e-8);
      /* constrained directions: A = (dg/dq) G^T by finite differences vs G G^T */
      if (mc > 0) {
        double A[36], GG[36];
        for (int r = 0; r < mc; r++) {
          double da[6], db[6];
          for (int j = 0; j < 6; j++) { da[j] = pr.a < 0 ? 0 : Ga[6 * r + j]; db[j] = Gb[6 * r + j]; }
          g_moved(m, pr.a < 0, H, da, db, 1e-6, xref, 0, 0, gp, gm);
          for (int i = 0; i < mc; i++) A[i * mc + r] = (gp[i] - gm[i]) / 2e-6;
          for (int i = 0; i < mc; i++) {
            double s = 0;
            for (int j = 0; j < 6; j++) s += Ga[6 * i + j] * da[j] + Gb[6 * i + j] * db[j];
            GG[i * mc + r] = s;
          }
        }
        int exact = type != PHM_PAIR_HELICAL && type != PHM_PAIR_CYLINDRICAL;
        if (exact) {
          snprintf(name, sizeof name, "%s: dg/dq G^T = G G^T (FD)", tn);
          check(name, maxdiff(mc * mc, A, GG) / maxabs(mc * mc, GG), 1e-7);
        }
        double dA = det_small(A, mc), dG = det_small(GG, mc);
        snprintf(name, sizeof name, "%s: det(dg/dq G^T) = det(G G^T) (GGL nonsingular)", tn);
        check(name, fabs(dA / dG - 1), 1e-6);
      }
      phm_model_free(m);
    }
}

/* phm_pair_type_pose is the forward kinematics pair_fk; phm_pair_type_coordinates inverts it:
 * coordinates(pose(x)) = x with a branch reference near x, and without one for principal
 * angles (and a helical pair's turn, read from its translation); pose(coordinates(h)) = h for
 * every h on the type's manifold, multi-turn angles included. */
static void type_pose_and_coordinates_are_inverse(void) {
  for (int type = 0; type < PAIR_TYPES; type++)
    for (int trial = 0; trial < 12; trial++) {
      char name[112];
      const char *tn = phm_pair_type(type)->name;
      int k = 6 - phm_pair_type(type)->m;
      double pitch = type == PHM_PAIR_HELICAL ? (trial == 0 ? 0.0 : 0.3 * rand11()) : 0.0;
      double x[6], xp[6], xref[6], xe[6], h[16], hfk[16], he[16];
      /* principal values: angles in (-pi, pi) (Universal's too), rotation vectors of norm < pi */
      for (int i = 0; i < 6; i++) xp[i] = 3.0 * rand11();
      if (type == PHM_PAIR_SPHERICAL || type == PHM_PAIR_FREE) {
        double n[3], th = rand_angle(trial % 4);
        rand_unit3(n);
        for (int i = 0; i < 3; i++) xp[i] = th * n[i];
      }
      memcpy(x, xp, sizeof x);
      if (pair_winds(type)) x[0] += 2 * CHECK_PI * (trial % 5 - 2);
      phm_pair_type_pose(type, pitch, x, h);
      pair_fk(type, pitch, x, hfk);
      snprintf(name, sizeof name, "%s: phm_pair_type_pose = forward kinematics", tn);
      check(name, maxdiff(16, h, hfk), 1e-14);
      if (k == 0) continue; /* fixed: no coordinates */
      for (int i = 0; i < 6; i++) xref[i] = x[i] + 0.3 * rand11();
      phm_pair_type_coordinates(type, pitch, h, xref, xe);
      snprintf(name, sizeof name, "%s: coordinates(pose(x), xref near x) = x", tn);
      check(name, maxdiff(k, xe, x), 1e-12);
      phm_pair_type_pose(type, pitch, xp, h);
      phm_pair_type_coordinates(type, pitch, h, NULL, xe);
      snprintf(name, sizeof name, "%s: coordinates(pose(x), no reference) = x (principal values)", tn);
      check(name, maxdiff(k, xe, xp), 1e-12);
      /* h on the manifold (pair_fk, multi-turn): pose(coordinates(h)) = h without a reference */
      phm_pair_type_coordinates(type, pitch, hfk, NULL, xe);
      phm_pair_type_pose(type, pitch, xe, he);
      snprintf(name, sizeof name, "%s: pose(coordinates(h)) = h on the manifold", tn);
      check(name, maxdiff(16, he, hfk) / (1.0 + maxabs(16, hfk)), 1e-12);
      if (type == PHM_PAIR_HELICAL && pitch != 0) {
        snprintf(name, sizeof name, "helical: the turn is read from the translation (x = %.3f)", x[0]);
        check(name, fabs(xe[0] - x[0]), 1e-12 * (1.0 + fabs(x[0])));
      }
    }
}

/* A drop mask leaves out the named rows: the kept rows of g and G (phm_constraints_dense) are
 * those rows of the full set (phm_constraints_full), and phm_pair_wrench uses their W^C columns. */
static void drop_mask_keeps_the_other_rows_of_the_full_set(void) {
  const struct { int type, drop; } cases[] = {
      {PHM_PAIR_REVOLUTE, 0x12}, {PHM_PAIR_SPHERICAL, 0x1}, {PHM_PAIR_FIXED, 0x2c}, {PHM_PAIR_UNIVERSAL, 0x0}};
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    const char *tn = phm_pair_type(cases[c].type)->name;
    phm_pair_desc pr;
    memset(&pr, 0, sizeof pr);
    pr.type = cases[c].type;
    pr.a = c % 2 ? -1 : 0;
    pr.b = 1;
    pr.drop = cases[c].drop;
    rand_pose(pr.Ta, 1.0);
    rand_pose(pr.Tb, 1.0);
    phm_model *m = two_carrier_model(&pr, NULL, 0);
    if (!m) continue;
    int mt = phm_pair_type(pr.type)->m, kept = 0, sel[6];
    for (int r = 0; r < mt; r++)
      if (!(pr.drop & (1 << r))) sel[kept++] = r;
    CHECK(phm_model_nconstraints(m) == kept && phm_model_nconstraints_full(m) == mt,
          "%s, drop %#x: %d of %d rows kept (model says %d of %d)", tn, pr.drop, kept, mt,
          phm_model_nconstraints(m), phm_model_nconstraints_full(m));
    double H[32], g[6], G[6 * 12], vt[6], gf[6], Gf[6 * 12], W[36], lam[6], w[6], wref[6] = {0};
    rand_pose(H, 1.0); /* off the manifold: g != 0 */
    rand_pose(H + 16, 1.0);
    phm_constraints_dense(m, H, NULL, 0.0, 0.5, g, G, vt);
    phm_constraints_full(m, H, NULL, 0.0, gf, Gf, W);
    double eg = 0, eG = 0;
    for (int r = 0; r < kept; r++) {
      eg = fmax(eg, fabs(g[r] - gf[sel[r]]));
      eG = fmax(eG, maxdiff(12, G + 12 * r, Gf + 12 * sel[r]));
    }
    char name[96];
    snprintf(name, sizeof name, "%s, drop %#x: kept g rows = full rows", tn, pr.drop);
    check(name, eg, 0.0);
    snprintf(name, sizeof name, "%s, drop %#x: kept G rows = full rows", tn, pr.drop);
    check(name, eG, 0.0);
    for (int r = 0; r < kept; r++) lam[r] = rand11();
    for (int i = 0; i < 6; i++)
      for (int r = 0; r < kept; r++) wref[i] += W[6 * i + sel[r]] * lam[r];
    phm_pair_data pd;
    phm_pair_evaluate(m, 0, pr.a < 0 ? NULL : H, H + 16, NULL, NULL, NULL, 0.0, 1.0, PHM_PAIR_ROWS,
                      &pd);
    phm_pair_wrench(m, 0, &pd, lam, w);
    snprintf(name, sizeof name, "%s, drop %#x: wrench = kept W^C columns lambda", tn, pr.drop);
    check(name, maxdiff(6, w, wref), 1e-15 * (1.0 + maxabs(6, wref)));
    phm_model_free(m);
  }
}

/* Joint coordinates that follow laws (xdriven, every coordinate the table lets follow one): one
 * more row per coordinate after the type's, g = x_c - s_c(t) = 0 on the joint manifold at
 * x_c = s_c(t); along any motion of the two carriers and time, Ga ta + Gb tb - vt = dg/dt
 * (central differences); the driven rows' wrench columns are the effort basis Phi_c; a spherical
 * pair's coordinates (rates are angular velocities) and a motion with joint laws are refused. */
static void driven_joint_coordinates_follow_their_laws(void) {
  for (int type = 1; type <= PHM_PAIR_FREE; type++) {
    int mask = phm_pair_type(type)->xdrivable;
    if (!mask) continue;
    for (int trial = 0; trial < 4; trial++) {
      char name[128];
      const char *tn = phm_pair_type(type)->name;
      phm_pair_desc pr;
      rand_pair(type, trial, &pr);
      int mt = phm_pair_type(type)->m, k = 6 - mt, mc = mt;
      pr.xdriven = mask;
      double x[6], time = 0.37;
      rand_joint_coordinates(type, 0, x);
      for (int c = 0; c < k; c++)
        if (mask >> c & 1) {
          pr.xlaw[c].kind = PHM_LAW_SINE;
          pr.xlaw[c].amplitude = 0.5 + rand01();
          pr.xlaw[c].frequency = 0.2 + rand01();
          pr.xlaw[c].phase = rand11();
          x[c] = phm_law_eval(&pr.xlaw[c], time, time, NULL, NULL);
          mc++;
        }
      pr.has_x0 = 1;
      memcpy(pr.x0, x, sizeof x);
      phm_model *m = two_carrier_model(&pr, NULL, 0);
      CHECK(m != NULL, "%s with driven coordinates %#x: model built", tn, mask);
      if (!m) continue;
      CHECK(phm_model_nconstraints(m) == mc, "%s: %d type rows + driven rows = %d", tn, mt, mc);
      double H[32];
      rand_pose(H, 1.0);
      const double *Ha = pr.a < 0 ? NULL : H;
      place_b_fk(Ha, pr.Ta, pr.Tb, type, pr.pitch, x, H + 16);
      double g[6], Ga[36], Gb[36], vt[6];
      phm_pair_eval(m, 0, Ha, H + 16, x, time, time, g, Ga, Gb, vt);
      snprintf(name, sizeof name, "%s: every row (driven ones too) = 0 at x_c = s_c(t)", tn);
      check(name, maxabs(mc, g), 1e-12);
      double ta[6], tb[6], tau = 1e-6, gp[6], gm[6], Hp[32], Hm[32], e = 0;
      for (int i = 0; i < 6; i++) {
        ta[i] = pr.a < 0 ? 0 : rand11();
        tb[i] = rand11();
      }
      g_moved(m, pr.a < 0, H, ta, tb, tau, x, time, tau, gp, gm);
      /* any motion: the driven rows (the type's own: every_type_...; helical ones, whose
       * driven row equals dg/dt up to a multiple of its screw row's, below) */
      for (int r = mt; r < mc && type != PHM_PAIR_HELICAL; r++) {
        double gv = -vt[r];
        for (int j = 0; j < 6; j++) gv += Ga[6 * r + j] * ta[j] + Gb[6 * r + j] * tb[j];
        e = fmax(e, fabs(gv - (gp[r] - gm[r]) / (2 * tau)));
      }
      snprintf(name, sizeof name, "%s: driven velocity rows = dg/dt with the laws' rates (central FD)", tn);
      check(name, e, 1e-7);
      /* an allowed motion of the type, x(s) = x + s xi, a moving with ta: every row's velocity
       * residual is dg/dt (the type's vanish; a driven one is xi_c - s_c') */
      double xi[6], xp[6], xm[6];
      for (int i = 0; i < 6; i++) {
        xi[i] = rand11();
        xp[i] = x[i] + tau * xi[i];
        xm[i] = x[i] - tau * xi[i];
      }
      perturbed(H, ta, tau, Hp);
      perturbed(H, ta, -tau, Hm);
      place_b_fk(pr.a < 0 ? NULL : Hp, pr.Ta, pr.Tb, type, pr.pitch, xp, Hp + 16);
      place_b_fk(pr.a < 0 ? NULL : Hm, pr.Ta, pr.Tb, type, pr.pitch, xm, Hm + 16);
      {
        double Hi[16], D[16], lp[6], lm[6];
        phm_se3_inverse(H + 16, Hi);
        phm_se3_compose(Hi, Hp + 16, D);
        phm_se3_log(D, lp);
        phm_se3_compose(Hi, Hm + 16, D);
        phm_se3_log(D, lm);
        for (int i = 0; i < 6; i++) tb[i] = (lp[i] - lm[i]) / (2 * tau);
      }
      phm_pair_eval(m, 0, pr.a < 0 ? NULL : Hp, Hp + 16, x, time + tau, time, gp, NULL, NULL, NULL);
      phm_pair_eval(m, 0, pr.a < 0 ? NULL : Hm, Hm + 16, x, time - tau, time, gm, NULL, NULL, NULL);
      e = 0;
      for (int r = 0; r < mc; r++) {
        double gv = -vt[r];
        for (int j = 0; j < 6; j++) gv += Ga[6 * r + j] * ta[j] + Gb[6 * r + j] * tb[j];
        e = fmax(e, fabs(gv - (gp[r] - gm[r]) / (2 * tau)));
      }
      snprintf(name, sizeof name, "%s: every velocity row = dg/dt along an allowed motion", tn);
      check(name, e, 1e-7);
      double W[6 * 36], Phi[36], h[16], Gf[6 * 12];
      phm_constraints_full(m, H, x, time, NULL, Gf, W);
      phm_pair_frames(m, 0, Ha, H + 16, h, NULL, NULL);
      phm_pair_kin(type, pr.pitch, h, x, NULL, NULL, Phi, NULL);
      double ew = 0;
      for (int c = 0, r = mt; c < k; c++)
        if (mask >> c & 1) {
          for (int i = 0; i < 6; i++) ew = fmax(ew, fabs(W[6 * i + r] - Phi[6 * i + c]));
          r++;
        }
      snprintf(name, sizeof name, "%s: a driven row's wrench column is Phi_c", tn);
      check(name, ew, 1e-15);
      phm_model_free(m);
    }
  }
  /* refusals */
  phm_pair_desc pr;
  rand_pair(PHM_PAIR_SPHERICAL, 1, &pr);
  pr.xdriven = 1;
  pr.xlaw[0].kind = PHM_LAW_CONSTANT;
  phm_model_desc d;
  phm_carrier_desc car[2];
  carrier_unit(&car[0]);
  carrier_unit(&car[1]);
  memset(&d, 0, sizeof d);
  d.ncarriers = 2;
  d.carriers = car;
  d.npairs = 1;
  d.pairs = &pr;
  phm_model *m = NULL;
  phm_error err;
  check_refused("spherical coordinate driven", phm_model_create(&d, &m, &err), PHM_EINVAL, &err,
                "a spherical pair's joint coordinates 0x1 cannot follow a law");
  rand_pair(PHM_PAIR_REVOLUTE, 1, &pr);
  pr.xdriven = 2;
  check_refused("coordinate beyond k", phm_model_create(&d, &m, &err), PHM_EINVAL, &err,
                "driven coordinates 0x2 beyond the 1 joint coordinates of a revolute pair");
}

/* The values of pair 0 that phm_pair_tangent differentiates, at poses H (a's ignored with
 * a_ground) and fixed twists ta, tb: g, c = Ga ta + Gb tb - vt, x, xdot (k), [Ga^T lam; Gb^T lam],
 * the same for mu and the effort wrenches of u (phm_pair_effort_wrench), in one vector (mc, mc,
 * k, k, 12, 12, 12). */
static int pair_values(const phm_model *m, int a_ground, const double H[32], const double ta[6],
                       const double tb[6], const double *xref, double time, const double *lam,
                       const double *mu, const double *u, double *v) {
  phm_pair_data pd;
  int mc = m->pair_m[0], k = m->pair_k[0], n = 0;
  phm_pair_evaluate(m, 0, a_ground ? NULL : H, H + 16, a_ground ? NULL : ta, tb, xref, time, time,
                    PHM_PAIR_ROWS | PHM_PAIR_JOINT, &pd);
  for (int r = 0; r < mc; r++) v[n++] = pd.g[r];
  double wu[12] = {0};
  phm_pair_effort_wrench(m, 0, &pd, u, wu);
  for (int r = 0; r < mc; r++) {
    double c = -pd.vt[r];
    for (int j = 0; j < 6; j++) c += (a_ground ? 0.0 : pd.Ga[6 * r + j] * ta[j]) + pd.Gb[6 * r + j] * tb[j];
    v[n++] = c;
  }
  for (int c = 0; c < k; c++) v[n++] = pd.x[c];
  for (int c = 0; c < k; c++) v[n++] = pd.xdot[c];
  for (int s = 0; s < 2; s++) {
    const double *l = s ? mu : lam;
    for (int side = 0; side < 2; side++)
      for (int j = 0; j < 6; j++) {
        double acc = 0;
        for (int r = 0; r < mc; r++) acc += (side ? pd.Gb : pd.Ga)[6 * r + j] * l[r];
        v[n++] = acc;
      }
  }
  for (int i = 0; i < 12; i++) v[n++] = wu[i];
  return n;
}

/* A random pair of the type (rand_pair), driven by a motion when it is a fixed one on an odd
 * trial, and with its drivable joint coordinates following laws when xdrive. */
static void rand_pair_driven(int type, int trial, int xdrive, phm_pair_desc *pr) {
  rand_pair(type, trial, pr);
  int k = 6 - phm_pair_type(type)->m, mask = phm_pair_type(type)->xdrivable;
  if (type == PHM_PAIR_FIXED && trial % 2) {
    pr->driven = 1;
    for (int i = 0; i < 6; i++) pr->axis[i] = rand11();
    pr->law = (phm_law){.kind = PHM_LAW_SINE, .amplitude = 0.7, .frequency = 0.3, .phase = 0.2};
  }
  if (mask && xdrive)
    for (int c = 0; c < k; c++)
      if (mask >> c & 1) {
        pr->xdriven |= 1 << c;
        pr->xlaw[c] = (phm_law){.kind = PHM_LAW_SINE, .amplitude = 0.5 + rand01(),
                                .frequency = 0.2 + rand01(), .phase = rand11()};
      }
}

/* phm_pair_tangent against central differences (step 1e-6 along H exp(eps e_j) of each carrier)
 * for every pair type at random poses off its manifold and random twists and multipliers: a to
 * the ground or to a carrier, a driven fixed pair, driven joint coordinates, a dropped row. The
 * position rows dg, the velocity rows dc, the joint coordinates dx and rates dxd, the constraint
 * wrenches' Kl, Km and the effort wrenches' Ku each to 1e-7 relative to their largest entry. */
static void pair_tangent_is_central_differences(void) {
  static const char *const part[7] = {
      "pair tangent = central FD: dg/dpose", "pair tangent = central FD: d(G t - vt)/dpose",
      "pair tangent = central FD: dx/dpose", "pair tangent = central FD: d(Phi^T t_rel)/dpose",
      "pair tangent = central FD: d(G^T lambda)/dpose", "pair tangent = central FD: d(G^T mu)/dpose",
      "pair tangent = central FD: d(effort wrenches)/dpose"};
  for (int type = 0; type < PAIR_TYPES; type++)
    for (int trial = 0; trial < 8; trial++) {
      const char *tn = phm_pair_type(type)->name;
      phm_pair_desc pr;
      rand_pair_driven(type, trial, trial % 2, &pr);
      int mt = phm_pair_type(type)->m, k = 6 - mt;
      double time = 0.37;
      if (trial == 4 && mt >= 2) pr.drop = 0x2;
      phm_model *m = two_carrier_model(&pr, NULL, 0);
      if (!m) continue;
      int ag = pr.a < 0, mc = m->pair_m[0];
      double H[32], ta[6], tb[6], lam[6], mu[6], u[6], xref[6];
      rand_pose(H, 1.0);
      rand_pose(H + 16, 1.0);
      for (int i = 0; i < 6; i++) {
        ta[i] = ag ? 0.0 : rand11();
        tb[i] = rand11();
        lam[i] = rand11();
        mu[i] = rand11();
        u[i] = rand11();
      }
      /* the branch of the angles: the principal values at H (no reference within pi of a jump) */
      phm_pair_joint(m, 0, ag ? NULL : H, H + 16, NULL, NULL, NULL, xref, NULL);
      double dg[72], dc[72], dx[72], dxd[72], Kl[144], Km[144], Ku[144];
      phm_pair_tangent(m, 0, ag ? NULL : H, H + 16, ag ? NULL : ta, tb, xref, time, time, lam, mu,
                       u, NULL, dg, dc, dx, dxd, Kl, Km, Ku);
      /* reference: central differences, column j of [da; db] */
      double ref[96 * 12], vp[96], vm[96], eps = 1e-6;
      int nv = 0;
      for (int j = 0; j < 12; j++) {
        double Hp[32], Hm[32], e[6] = {0};
        e[j % 6] = 1.0;
        memcpy(Hp, H, sizeof Hp);
        memcpy(Hm, H, sizeof Hm);
        perturbed(H + 16 * (j / 6), e, eps, Hp + 16 * (j / 6));
        perturbed(H + 16 * (j / 6), e, -eps, Hm + 16 * (j / 6));
        nv = pair_values(m, ag, Hp, ta, tb, xref, time, lam, mu, u, vp);
        pair_values(m, ag, Hm, ta, tb, xref, time, lam, mu, u, vm);
        for (int i = 0; i < nv; i++) ref[12 * i + j] = (vp[i] - vm[i]) / (2 * eps);
      }
      /* the closed forms in the same order; a's columns only when a is a carrier */
      const double *got[7] = {dg, dc, dx, dxd, Kl, Km, Ku};
      int rows[7] = {mc, mc, k, k, 12, 12, 12}, off = 0;
      for (int c = 0; c < 7; c++) {
        double err = 0, big = 0;
        for (int i = 0; i < rows[c]; i++)
          for (int j = ag ? 6 : 0; j < 12; j++) {
            if (ag && c >= 4 && i < 6) continue; /* the ground's wrench */
            err = fmax(err, fabs(got[c][12 * i + j] - ref[12 * (off + i) + j]));
            big = fmax(big, fabs(ref[12 * (off + i) + j]));
          }
        off += rows[c];
        if (rows[c] == 0) continue;
        check_worst(part[c], err / fmax(big, 1e-300), 1e-7);
        if (!(err <= 1e-7 * big))
          printf("  (%s, trial %d, driven %d, xdriven %#x, drop %#x)\n", tn, trial, pr.driven,
                 pr.xdriven, pr.drop);
      }
      phm_model_free(m);
    }
}

/* Largest |a - b| over n entries relative to the largest |b| (1 when b vanishes). */
static double reldiff(int n, const double *a, const double *b) {
  return maxdiff(n, a, b) / fmax(maxabs(n, b), 1.0);
}

/* phm_pair_kin_tangent (closed forms where a type has one: the revolute) against the table's
 * general switch (phm_pair_kin_general), values and derivatives, for every type at random poses
 * near and far from the manifold, with and without a branch reference. */
static void closed_forms_are_the_general_kinematics(void) {
  for (int type = 0; type < PAIR_TYPES; type++)
    for (int trial = 0; trial < 40; trial++) {
      double h[16], xref[6], pitch = 0.3 * rand11();
      rand_pose(h, trial % 2 ? 1.0 : 1e-3);
      for (int i = 0; i < 6; i++) xref[i] = 4 * rand11();
      double v[2][6 + 36 + 36 + 6 + 36 + 216 + 216 + 36];
      for (int general = 0; general < 2; general++) {
        double *o = v[general];
        memset(o, 0, sizeof v[0]);
        (general ? phm_pair_kin_general : phm_pair_kin_tangent)(
            type, pitch, h, trial % 3 ? xref : NULL, o, o + 6, o + 42, o + 78, o + 84, o + 120,
            o + 336, o + 552);
      }
      static char names[PAIR_TYPES][96]; /* check_worst keeps the name */
      char *name = names[type];
      snprintf(name, sizeof names[0], "%s: closed-form kinematics = general (values, tangents)",
               phm_pair_type(type)->name);
      check_worst(name, reldiff((int)(sizeof v[0] / sizeof(double)), v[0], v[1]), 1e-13);
    }
}

/* Frames h = F_a^-1 F_b and AdBa = Ad_{F_b^-1 H_a} (phm_pair_frames, fused) against the SE(3)
 * algebra's inverse, compose and Ad. */
static void frames_are_the_se3_compositions(void) {
  for (int trial = 0; trial < 20; trial++) {
    phm_pair_desc pr;
    rand_pair(PHM_PAIR_REVOLUTE, trial, &pr);
    phm_model *m = two_carrier_model(&pr, NULL, 0);
    if (!m) continue;
    double H[32], h[16], AdTbi[36], AdBa[36], A[16], B[16], Ai[16], Bi[16], T[16], hr[16], Ar[36];
    rand_pose(H, 2.0);
    rand_pose(H + 16, 2.0);
    const double *Ha = pr.a < 0 ? NULL : H;
    phm_pair_frames(m, 0, Ha, H + 16, h, AdTbi, AdBa);
    if (Ha) phm_se3_compose(Ha, pr.Ta, A);
    else memcpy(A, pr.Ta, sizeof A);
    phm_se3_compose(H + 16, pr.Tb, B);
    phm_se3_inverse(A, Ai);
    phm_se3_compose(Ai, B, hr);
    phm_se3_inverse(B, Bi);
    if (Ha) phm_se3_compose(Bi, Ha, T);
    else memcpy(T, Bi, sizeof T);
    phm_se3_Ad(T, Ar);
    check_worst("frames: h = (H_a Ta)^-1 H_b Tb", reldiff(16, h, hr), 1e-15);
    check_worst("frames: AdBa = Ad((H_b Tb)^-1 H_a)", reldiff(36, AdBa, Ar), 1e-15);
    phm_model_free(m);
  }
}

/* phm_pair_evaluate and phm_pair_tangent with their closed forms and structural shortcuts
 * (unit columns of a basis, vanishing derivatives of constant bases, sparse position rows)
 * against the general path (m->pair_general = 1) for every type at random poses, twists,
 * multipliers and efforts: a to the ground or to a carrier, a driven fixed pair, driven joint
 * coordinates, a dropped row. Every output to 1e-13 relative to its largest entry. */
static void pair_shortcuts_are_the_general_path(void) {
  static const char *const part[4] = {"shortcuts = general: evaluation (g, G, vt, W, Phi, x, xdot)",
                                      "shortcuts = general: dg, dc, dx, dxd",
                                      "shortcuts = general: Kl, Km, Ku",
                                      "shortcuts = general: tangent's evaluation"};
  for (int type = 0; type < PAIR_TYPES; type++)
    for (int trial = 0; trial < 12; trial++) {
      phm_pair_desc pr;
      rand_pair_driven(type, trial, trial % 4 == 1, &pr);
      int mt = phm_pair_type(type)->m;
      double time = 0.37;
      if (trial % 4 == 2 && mt >= 2) pr.drop = 0x2 | (mt >= 4 ? 0x8 : 0);
      phm_model *m = two_carrier_model(&pr, NULL, 0);
      if (!m) continue;
      int ag = pr.a < 0;
      double H[32], ta[6], tb[6], lam[6], mu[6], u[6], xref[6];
      rand_pose(H, 1.0);
      rand_pose(H + 16, 1.0);
      for (int i = 0; i < 6; i++) {
        ta[i] = rand11();
        tb[i] = rand11();
        lam[i] = rand11();
        mu[i] = rand11();
        u[i] = rand11();
        xref[i] = 4 * rand11();
      }
      enum { NE = 6 + 36 + 36 + 6 + 36 + 36 + 6 + 6, NT = 4 * 72, NK = 3 * 144 };
      double ev[2][NE], tv[2][NT], kv[2][NK], pv[2][NE];
      for (int general = 0; general < 2; general++) {
        phm_pair_data pd, pt;
        memset(&pd, 0, sizeof pd);
        memset(&pt, 0, sizeof pt);
        m->pair_general = general;
        phm_pair_evaluate(m, 0, ag ? NULL : H, H + 16, ag ? NULL : ta, tb, xref, time, time,
                          PHM_PAIR_ROWS | PHM_PAIR_JOINT, &pd);
        double *t = tv[general], *kk = kv[general];
        memset(t, 0, sizeof tv[0]);
        phm_pair_tangent(m, 0, ag ? NULL : H, H + 16, ag ? NULL : ta, tb, xref, time, time, lam,
                         mu, u, &pt, t, t + 72, t + 144, t + 216, kk, kk + 144, kk + 288);
        const phm_pair_data *src[2] = {&pd, &pt};
        for (int s = 0; s < 2; s++) {
          double *e = s ? pv[general] : ev[general];
          int n = 0;
          memcpy(e + n, src[s]->g, sizeof pd.g); n += 6;
          memcpy(e + n, src[s]->Ga, sizeof pd.Ga); n += 36;
          memcpy(e + n, src[s]->Gb, sizeof pd.Gb); n += 36;
          memcpy(e + n, src[s]->vt, sizeof pd.vt); n += 6;
          memcpy(e + n, src[s]->W, sizeof pd.W); n += 36;
          memcpy(e + n, src[s]->Phi, sizeof pd.Phi); n += 36;
          memcpy(e + n, src[s]->x, sizeof pd.x); n += 6;
          memcpy(e + n, src[s]->xdot, sizeof pd.xdot);
        }
      }
      m->pair_general = 0;
      double err[4] = {reldiff(NE, ev[0], ev[1]), reldiff(NT, tv[0], tv[1]),
                       reldiff(NK, kv[0], kv[1]), reldiff(NE, pv[0], pv[1])};
      for (int c = 0; c < 4; c++)
        if (!check_worst(part[c], err[c], 1e-13))
          printf("  (%s, trial %d, driven %d, xdriven %#x, drop %#x)\n", phm_pair_type(type)->name,
                 trial, pr.driven, pr.xdriven, pr.drop);
      phm_model_free(m);
    }
}

CHECK_MAIN(CHECK_CASE(pair_table_lists_the_types_in_order),
           CHECK_CASE(driven_fixed_pair_follows_its_prescribed_motion),
           CHECK_CASE(every_type_vanishes_on_its_manifold_with_consistent_jacobians),
           CHECK_CASE(type_pose_and_coordinates_are_inverse),
           CHECK_CASE(drop_mask_keeps_the_other_rows_of_the_full_set),
           CHECK_CASE(driven_joint_coordinates_follow_their_laws),
           CHECK_CASE(pair_tangent_is_central_differences),
           CHECK_CASE(closed_forms_are_the_general_kinematics),
           CHECK_CASE(frames_are_the_se3_compositions),
           CHECK_CASE(pair_shortcuts_are_the_general_path))
