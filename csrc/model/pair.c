/* pair.c -- the evaluation of a model's pairs from their types' kinematics (pair_types.c):
 * frames, constraints g and their Jacobian blocks G (the kept rows; rows of joint coordinates
 * driven by a motion), joint coordinates and rates, constraint wrenches, the closed-form tangents
 * of all of these along both carriers, and the loops over every pair (constraints, joints, the
 * forces G^T lambda). */
#include "model.h"

#include <math.h>
#include <string.h>

#include "linalg.h"
#include "pose.h"

/* Column c of a 6x6 row-major basis dotted with v: a joint rate Phi_c^T t_rel. */
static double col_dot(const double B[36], int c, const double v[6]) {
  double s = 0;
  for (int i = 0; i < 6; i++) s += B[6 * i + c] * v[i];
  return s;
}

/* ---------------------------------------------------------------- pairs */
/* Frame X = H T (H NULL: T), its first three rows: phm_se3_compose's arithmetic, inline. */
static inline void frame_of(const double *H, const double T[16], double X[16]) {
  for (int i = 0; i < 3; i++) {
    if (!H) {
      for (int j = 0; j < 4; j++) X[4 * i + j] = T[4 * i + j];
      continue;
    }
    for (int j = 0; j < 3; j++)
      X[4 * i + j] = H[4 * i] * T[j] + H[4 * i + 1] * T[4 + j] + H[4 * i + 2] * T[8 + j];
    X[4 * i + 3] = (H[4 * i] * T[3] + H[4 * i + 1] * T[7] + H[4 * i + 2] * T[11]) + H[4 * i + 3];
  }
}

/* Frames of pair ip: B = H_b Tb, h = (H_a Ta)^-1 B, AdTbi = Ad_{Tb^-1}, AdBa = Ad_{B^-1 H_a}, so
 * that the relative twist is t_rel = AdTbi t_b - AdBa t_a (in F_b). Fused (no 4x4 inverse or
 * compose, no copies), with the arithmetic of phm_se3_inverse, phm_se3_compose and phm_se3_Ad
 * (the same numbers; an exact zero's sign aside). */
void phm_pair_frames(const phm_model *m, int ip, const double *Ha, const double *Hb, double h[16],
                     double AdTbi[36], double AdBa[36]) {
  const phm_pair_desc *pr = &m->pair[ip];
  double A[16], B[16];
  frame_of(Ha, pr->Ta, A);
  frame_of(Hb, pr->Tb, B);
  phm_inv_compose(A, B, h);
  if (AdTbi) memcpy(AdTbi, m->pair_AdTbi + 36 * ip, 36 * sizeof(double));
  if (!AdBa) return;
  double R[9], p[3]; /* B^-1 H_a (H_a NULL: B^-1) */
  for (int i = 0; i < 3; i++) {
    double qb = -(B[i] * B[3] + B[4 + i] * B[7] + B[8 + i] * B[11]);
    if (!Ha) {
      for (int j = 0; j < 3; j++) R[3 * i + j] = B[4 * j + i];
      p[i] = qb;
      continue;
    }
    for (int j = 0; j < 3; j++)
      R[3 * i + j] = B[i] * Ha[j] + B[4 + i] * Ha[4 + j] + B[8 + i] * Ha[8 + j];
    p[i] = (B[i] * Ha[3] + B[4 + i] * Ha[7] + B[8 + i] * Ha[11]) + qb;
  }
  for (int i = 0; i < 3; i++) /* Ad = [R 0; hat(p) R, R] */
    for (int j = 0; j < 3; j++) {
      int i1 = (i + 1) % 3, i2 = (i + 2) % 3; /* (hat(p) R)_ij = p_i1 R_i2,j - p_i2 R_i1,j */
      AdBa[6 * i + j] = AdBa[6 * (3 + i) + 3 + j] = R[3 * i + j];
      AdBa[6 * i + 3 + j] = 0.0;
      AdBa[6 * (3 + i) + j] = -p[i2] * R[3 * i1 + j] + p[i1] * R[3 * i2 + j];
    }
}

void phm_pair_rel_twist(const double AdTbi[36], const double AdBa[36], const double *ta,
                        const double *tb, double tr[6]) {
  double u[6] = {0}, v[6] = {0};
  if (tb) phm_mv6(AdTbi, tb, u);
  if (ta) phm_mv6(AdBa, ta, v);
  for (int i = 0; i < 6; i++) tr[i] = u[i] - v[i];
}

int phm_pair_rows_full(const phm_pair_desc *pr) {
  int n = phm_pair_type(pr->type)->m;
  for (int c = 0; c < 6; c++) n += pr->xdriven >> c & 1;
  return n;
}

/* The constraint rows of pair ip from its frames (h; AdTbi and AdBa when Ga or Gb are asked for):
 * g, Ga, Gb, vt (any may be NULL) of the kept rows (all rows with `all`), W their wrench basis
 * (room for 36); Phi, x (may be NULL): the joint's effort basis and coordinates, from the same
 * evaluation of the type's kinematics unless the pair is driven by a motion. A driven joint
 * coordinate c adds the row g = x_c - s_c(t) after the type's rows, with dg = Phi_c^T t_rel - s_c'
 * (xdot_c = Phi_c^T t_rel is dx_c/dt for the coordinates the table lets follow a law), so its
 * wrench column is Phi_c and its prescribed rate s_c'. */
typedef struct {
  double Dg[6 * PHM_MAXCON]; /* d g_r/d eta_j at 6 r + j (the rows pair_rows keeps)             */
  double DW[216], DPhi[216]; /* d B_e/d eta_j at 6 e + j for entry e of the 6x6 bases W, Phi   */
  int W0, Phi0;              /* DW (its kept columns), DPhi vanish: then they are not filled    */
} pair_tan;

static int all_zero(const double *a, int n) {
  for (int i = 0; i < n; i++)
    if (a[i] != 0.0) return 0;
  return 1;
}

/* The row k when column c of the 6x6 basis B is the unit vector e_k, else -1. */
static int unit_col(const double B[36], int c) {
  int k = 0, ones = 0, nonzeros = 0; /* without branches: the pattern changes from column to column */
  for (int i = 0; i < 6; i++) {
    double b = B[6 * i + c];
    ones += b == 1.0;
    nonzeros += b != 0.0;
    k = b == 1.0 ? i : k;
  }
  return ones == 1 && nonzeros == 1 ? k : -1;
}

/* out (n x ncol, leading dimension ldo) = sign B^T A on the first n columns of the 6x6 basis B
 * (A: 6 x ncol, leading dimension lda), unit[r] = unit_col(B, r) (unit_cols). A unit column e_k
 * of B gives A's row k: the sum over its zeros is that row (an exact zero's sign aside), so the
 * constant bases of most types cost a copy. The sign is exact, so each entry is the sum it
 * always was. */
static void bt_mul_cols(const double B[36], const int *unit, int n, const double *A, int lda,
                        int ncol, double sign, double *out, int ldo) {
  for (int r = 0; r < n; r++) {
    int k = unit[r];
    if (k >= 0) {
      for (int j = 0; j < ncol; j++) out[ldo * r + j] = sign * A[lda * k + j];
      continue;
    }
    for (int j = 0; j < ncol; j++) {
      double s = 0;
      for (int i = 0; i < 6; i++) s += B[6 * i + r] * A[lda * i + j];
      out[ldo * r + j] = sign * s;
    }
  }
}

/* unit[r] = unit_col(B, r) for the first n columns of B, for bt_mul_cols. */
static void unit_cols(const double B[36], int n, int *unit) {
  for (int r = 0; r < n; r++) unit[r] = unit_col(B, r);
}

static void bt_mul(const double B[36], int n, const double *A, int lda, int ncol, double sign,
                   double *out, int ldo) {
  int unit[6];
  unit_cols(B, n, unit);
  bt_mul_cols(B, unit, n, A, lda, ncol, sign, out, ldo);
}

static void pair_rows(const phm_model *m, int ip, const double h[16], const double AdTbi[36],
                      const double AdBa[36], const double *xref, double time, double tref, int all,
                      double *g, double *Ga, double *Gb, double *vt, double W[36], double *Phi,
                      double *x, pair_tan *T) {
  const phm_pair_desc *pr = &m->pair[ip];
  int mt = phm_pair_type(pr->type)->m, mc = all ? phm_pair_rows_full(pr) : m->pair_m[ip];
  double s = 0, ds = 0;
  if (pr->driven) s = phm_law_eval(&pr->law, time, tref, &ds, NULL);
  double gf[6], vf[6] = {0, 0, 0, 0, 0, 0};
  double *gk = g ? gf : NULL; /* g not asked for: the kinematics below skips it where it can */
  if (pr->driven && g) {
    double xv[6], r[16], ri[16], E[16];
    for (int i = 0; i < 6; i++) xv[i] = s * pr->axis[i];
    phm_se3_exp(xv, r);
    phm_se3_inverse(r, ri);
    phm_se3_compose(ri, h, E);
    /* E = r^-1 h moves as h does: E exp(eta) = r^-1 h exp(eta) */
    phm_pair_kin_tangent(pr->type, pr->pitch, E, xref, gf, W, NULL, NULL, T ? T->Dg : NULL,
                         T ? T->DW : NULL, NULL, NULL);
    if (Phi || x || T)
      phm_pair_kin_tangent(pr->type, pr->pitch, h, xref, NULL, NULL, Phi, x, NULL, NULL,
                           T ? T->DPhi : NULL, NULL);
  } else if (pr->xdriven) {
    double Pl[36], xl[6], Dx[36];
    phm_pair_kin_tangent(pr->type, pr->pitch, h, xref, gf, W, Pl, xl, T ? T->Dg : NULL,
                         T ? T->DW : NULL, T ? T->DPhi : NULL, T ? Dx : NULL);
    int r = mt;
    for (int c = 0; c < 6 - mt; c++) {
      if (!(pr->xdriven >> c & 1)) continue;
      double sc, dsc;
      sc = phm_law_eval(&pr->xlaw[c], time, tref, &dsc, NULL);
      gf[r] = xl[c] - sc;
      vf[r] = dsc;
      for (int i = 0; i < 6; i++) W[6 * i + r] = Pl[6 * i + c];
      if (T) {
        memcpy(T->Dg + 6 * r, Dx + 6 * c, 6 * sizeof(double));
        for (int i = 0; i < 6; i++)
          memcpy(T->DW + 6 * (6 * i + r), T->DPhi + 6 * (6 * i + c), 6 * sizeof(double));
      }
      r++;
    }
    if (Phi) memcpy(Phi, Pl, sizeof Pl);
    if (x) memcpy(x, xl, sizeof(double) * (size_t)(6 - mt));
  } else {
    int constant = 0; /* a closed form with constant bases (revolute): DW = DPhi = 0, not filled */
    phm_pair_kin_eval(m->pair_general, pr->type, pr->pitch, h, xref, gk, W, Phi, x,
                      T ? T->Dg : NULL, T ? T->DW : NULL, T ? T->DPhi : NULL, NULL, &constant);
    if (T && constant) T->W0 = T->Phi0 = 1;
  }
  if (T && !T->W0 && !m->pair_general) T->W0 = all_zero(T->DW, 216);
  if (T && !T->Phi0 && !m->pair_general) T->Phi0 = all_zero(T->DPhi, 216);
  if (!all && pr->drop) { /* the kept rows: sel increasing, so the forward copy is safe */
    const int *sel = m->pair_sel + 6 * ip;
    for (int r = 0; r < mc; r++) {
      if (g) gf[r] = gf[sel[r]];
      vf[r] = vf[sel[r]];
      for (int i = 0; i < 6; i++) W[6 * i + r] = W[6 * i + sel[r]];
      if (T) memmove(T->Dg + 6 * r, T->Dg + 6 * sel[r], 6 * sizeof(double));
      if (T && !T->W0) {
        for (int i = 0; i < 6; i++)
          memmove(T->DW + 6 * (6 * i + r), T->DW + 6 * (6 * i + sel[r]), 6 * sizeof(double));
      }
    }
  }
  if (g) memcpy(g, gf, sizeof(double) * (size_t)mc);
  /* G_b = W^T Ad_{Tb^-1},  G_a = -W^T Ad_{(H_b Tb)^-1 H_a} */
  int unit[6]; /* W's unit columns, once for both */
  if (Ga || Gb) unit_cols(W, mc, unit);
  if (Gb) bt_mul_cols(W, unit, mc, AdTbi, 6, 6, 1.0, Gb, 6);
  if (Ga) bt_mul_cols(W, unit, mc, AdBa, 6, 6, -1.0, Ga, 6);
  if (vt) {
    for (int r = 0; r < mc; r++) {
      double acc = vf[r];
      if (pr->driven)
        for (int k = 0; k < 6; k++) acc += W[6 * k + r] * ds * pr->axis[k];
      vt[r] = acc;
    }
  }
}

static void pair_eval_rows(const phm_model *m, int ip, const double *Ha, const double *Hb,
                           const double *xref, double time, double tref, double *g, double *Ga,
                           double *Gb, double *vt, int all, double *Wout) {
  double h[16], W[36], AdTbi[36], AdBa[36];
  if (!xref) xref = m->xref0 + m->pair_j[ip];
  phm_pair_frames(m, ip, Ha, Hb, h, (Ga || Gb) ? AdTbi : NULL, Ga ? AdBa : NULL);
  pair_rows(m, ip, h, AdTbi, AdBa, xref, time, tref, all, g, Ga, Gb, vt, W, NULL, NULL, NULL);
  if (Wout) memcpy(Wout, W, sizeof W);
}

void phm_pair_eval(const phm_model *m, int ip, const double *Ha, const double *Hb,
                   const double *xref, double time, double tref, double *g, double *Ga,
                   double *Gb, double *vt) {
  pair_eval_rows(m, ip, Ha, Hb, xref, time, tref, g, Ga, Gb, vt, 0, NULL);
}

void phm_pair_eval_full(const phm_model *m, int ip, const double *Ha, const double *Hb,
                        const double *xref, double time, double tref, double *g, double *Ga,
                        double *Gb, double W[36]) {
  pair_eval_rows(m, ip, Ha, Hb, xref, time, tref, g, Ga, Gb, NULL, 1, W);
}

void phm_pair_evaluate(const phm_model *m, int ip, const double *Ha, const double *Hb,
                       const double *ta, const double *tb, const double *xref, double time,
                       double tref, int what, phm_pair_data *pd) {
  const phm_pair_desc *pr = &m->pair[ip];
  const double *AdTbi = m->pair_AdTbi + 36 * ip;
  int joint = what & PHM_PAIR_JOINT;
  double tr[6];
  if (!xref) xref = m->xref0 + m->pair_j[ip]; /* the rows need it too: helical, driven coordinates */
  phm_pair_frames(m, ip, Ha, Hb, pd->h, NULL, pd->AdBa);
  if (what & PHM_PAIR_ROWS) /* without Phi and x, a driven pair skips its second kinematics */
    pair_rows(m, ip, pd->h, AdTbi, pd->AdBa, xref, time, tref, 0,
              (what & PHM_PAIR_NO_G) && !pr->driven ? NULL : pd->g, pd->Ga, pd->Gb, pd->vt,
              pd->W, joint ? pd->Phi : NULL, joint ? pd->x : NULL, NULL);
  else if (joint)
    phm_pair_kin(pr->type, pr->pitch, pd->h, xref, NULL, NULL, pd->Phi, pd->x);
  if (!joint) return;
  /* xdot = Phi^T t_rel (for a unit column e_k of Phi: t_rel's entry k alone) */
  int k = m->pair_k[ip], unit = !m->pair_general, row[6];
  for (int c = 0; unit && c < k; c++) unit = (row[c] = unit_col(pd->Phi, c)) >= 0;
  if (unit) {
    for (int c = 0; c < k; c++) {
      int i = row[c];
      double u = 0, v = 0;
      for (int j = 0; tb && j < 6; j++) u += AdTbi[6 * i + j] * tb[j];
      for (int j = 0; ta && j < 6; j++) v += pd->AdBa[6 * i + j] * ta[j];
      pd->xdot[c] = u - v;
    }
    return;
  }
  phm_pair_rel_twist(AdTbi, pd->AdBa, ta, tb, tr);
  for (int c = 0; c < k; c++) pd->xdot[c] = col_dot(pd->Phi, c, tr);
}

void phm_pair_wrench(const phm_model *m, int ip, const phm_pair_data *pd, const double *lam,
                     double w[6]) {
  for (int i = 0; i < 6; i++) {
    double acc = 0;
    for (int r = 0; r < m->pair_m[ip]; r++) acc += pd->W[6 * i + r] * lam[r];
    w[i] = acc;
  }
}

/* ---------------------------------------------------------------- tangents of a pair's rows */
/* out (rows x 12) = D (rows x 6, derivatives in eta) [-AdBa, AdTbi]: eta, the body perturbation
 * of h, is AdTbi db - AdBa da for H_a exp(da), H_b exp(db) (docs/method.md 4.3). */
static void eta_to_carriers(const double *D, int rows, const double AdTbi[36],
                            const double AdBa[36], double *out) {
  phm_mul_ends(D, rows, AdBa, AdTbi, out);
}

/* The same skipping D's exact zeros (the sums of phm_mul_ends over the other terms, in the same
 * order: the same numbers, an exact zero's sign aside): the position rows of most types are
 * sparse in eta. */
static void eta_to_carriers_sparse(const double *D, int rows, const double AdTbi[36],
                                   const double AdBa[36], double *out) {
  for (int r = 0; r < rows; r++) {
    double sa[6] = {0, 0, 0, 0, 0, 0}, sb[6] = {0, 0, 0, 0, 0, 0};
    for (int l = 0; l < 6; l++) {
      double d = D[6 * r + l];
      if (d == 0.0) continue;
      for (int j = 0; j < 6; j++) {
        sa[j] += d * AdBa[6 * l + j];
        sb[j] += d * AdTbi[6 * l + j];
      }
    }
    for (int j = 0; j < 6; j++) {
      out[12 * r + j] = -sa[j];
      out[12 * r + 6 + j] = sb[j];
    }
  }
}

/* out (rows x 6) = sum_i B[i][r] v_i along eta: the derivative of B^T v (B: a 6x6 basis, its
 * derivatives DB at 6 e + j, columns r < rows) at fixed v. */
static void basis_dot(const double *DB, int rows, const double v[6], double *out) {
  for (int r = 0; r < rows; r++)
    for (int j = 0; j < 6; j++) {
      double s = 0;
      for (int i = 0; i < 6; i++) s += DB[6 * (6 * i + r) + j] * v[i];
      out[6 * r + j] = s;
    }
}

/* out (n x 12) = d(B^T v)/d[da; db] on B's first n columns at fixed v, with the twist's
 * derivative Dt (6 x 12): (dB^T v) through eta, plus B^T Dt. DB NULL: a constant basis, B^T Dt
 * alone (what the sums give when dB vanishes, an exact zero's sign aside). */
static void basis_rate_tangent(const double B[36], const double *DB, int n, const double v[6],
                               const double Dt[72], const double AdTbi[36],
                               const double AdBa[36], double *out) {
  if (!DB) {
    bt_mul(B, n, Dt, 12, 12, 1.0, out, 12);
    return;
  }
  double D6[36];
  basis_dot(DB, n, v, D6);
  eta_to_carriers(D6, n, AdTbi, AdBa, out);
  for (int r = 0; r < n; r++)
    for (int j = 0; j < 12; j++)
      for (int i = 0; i < 6; i++) out[12 * r + j] += B[6 * i + r] * Dt[12 * i + j];
}

/* bar(z) (6 x 6): bar(z) t = ad_t^T z, the derivative of ad*_(.) z (docs/method.md 3.4). */
static void ad_dual_bar(const double z[6], double B[36]) {
  for (int j = 0; j < 6; j++) {
    double e[6] = {0}, c[6];
    e[j] = 1.0;
    phm_ad_dual_apply(e, z, c);
    for (int i = 0; i < 6; i++) B[6 * i + j] = c[i];
  }
}

/* K (12 x 12) = d [-AdBa^T w; AdTbi^T w]/d[da; db] at fixed l, w = W l (W: a basis with its
 * derivatives DW in eta, columns r < mc): the constraint wrenches [Ga^T l; Gb^T l] (W = W^C) or
 * an effort's (W = Phi, l = u). Beside dw: AdBa = Ad_{F_b^-1 H_a} moves with both carriers,
 * d(AdBa^T w) = bar(AdBa^T w) da - AdBa^T bar(w) AdTbi db (H_a exp(da) on the right; H_b exp(db)
 * through F_b^-1 on the left). */
static void wrench_tangent(const double W[36], const double *DW, int mc, const double *l,
                           const double AdTbi[36], const double AdBa[36], double K[144]) {
  double w[6], z[6], Dl[36], Dw[72], Bz[36], Bw[36], BA[36];
  for (int i = 0; i < 6; i++) {
    w[i] = 0;
    for (int r = 0; r < mc; r++) w[i] += W[6 * i + r] * l[r];
    for (int j = 0; DW && j < 6; j++) {
      double s = 0;
      for (int r = 0; r < mc; r++) s += DW[6 * (6 * i + r) + j] * l[r];
      Dl[6 * i + j] = s;
    }
  }
  if (DW) eta_to_carriers(Dl, 6, AdTbi, AdBa, Dw);
  phm_mtv6(AdBa, w, z);
  ad_dual_bar(z, Bz);
  ad_dual_bar(w, Bw);
  for (int i = 0; i < 6; i++) /* BA = bar(w) AdTbi */
    for (int j = 0; j < 6; j++) {
      double s = 0;
      for (int l2 = 0; l2 < 6; l2++) s += Bw[6 * i + l2] * AdTbi[6 * l2 + j];
      BA[6 * i + j] = s;
    }
  if (!DW) { /* constant basis: Dw = 0, K = [-bar(z), AdBa^T bar(w) AdTbi; 0, 0] */
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 6; j++) {
        double s = 0;
        for (int l2 = 0; l2 < 6; l2++) s += AdBa[6 * l2 + i] * BA[6 * l2 + j];
        K[12 * i + j] = -Bz[6 * i + j];
        K[12 * i + 6 + j] = s;
        K[12 * (6 + i) + j] = K[12 * (6 + i) + 6 + j] = 0.0;
      }
    return;
  }
  for (int i = 0; i < 6; i++)
    for (int j = 0; j < 12; j++) {
      double sa = 0, sb = 0;
      for (int l2 = 0; l2 < 6; l2++) {
        sa += AdBa[6 * l2 + i] * (Dw[12 * l2 + j] - (j >= 6 ? BA[6 * l2 + j - 6] : 0.0));
        sb += AdTbi[6 * l2 + i] * Dw[12 * l2 + j];
      }
      K[12 * i + j] = -sa - (j < 6 ? Bz[6 * i + j] : 0.0);
      K[12 * (6 + i) + j] = sb;
    }
}

void phm_pair_tangent(const phm_model *m, int ip, const double *Ha, const double *Hb,
                      const double *ta, const double *tb, const double *xref, double time,
                      double tref, const double *lam, const double *mu, const double *u,
                      phm_pair_data *pd, double *dg, double *dc, double *dx, double *dxd,
                      double *Kl, double *Km, double *Ku) {
  const phm_pair_desc *pr = &m->pair[ip];
  const double *AdTbi = m->pair_AdTbi + 36 * ip;
  int mc = m->pair_m[ip], k = m->pair_k[ip];
  phm_pair_data own;
  pair_tan T;
  T.W0 = T.Phi0 = 0;
  if (!pd) pd = &own;
  if (!xref) xref = m->xref0 + m->pair_j[ip];
  phm_pair_frames(m, ip, Ha, Hb, pd->h, NULL, pd->AdBa);
  pair_rows(m, ip, pd->h, AdTbi, pd->AdBa, xref, time, tref, 0, pd->g, pd->Ga, pd->Gb, pd->vt,
            pd->W, pd->Phi, pd->x, &T);
  if (dx) { /* the coordinates' derivatives: one more evaluation of the kinematics at h */
    double Dx[36];
    phm_pair_kin_tangent(pr->type, pr->pitch, pd->h, xref, NULL, NULL, NULL, NULL, NULL, NULL,
                         NULL, Dx);
    eta_to_carriers(Dx, k, AdTbi, pd->AdBa, dx);
  }
  double tr[6], Dt[72] = {0};
  phm_pair_rel_twist(AdTbi, pd->AdBa, ta, tb, tr);
  for (int c = 0; c < k; c++) pd->xdot[c] = col_dot(pd->Phi, c, tr);
  if (ta) { /* d t_rel at fixed twists: [AdBa ad_ta, -ad_(AdBa ta) AdTbi] [da; db] */
    double s[6], ad[36], as[36];
    phm_mv6(pd->AdBa, ta, s);
    phm_se3_ad(ta, ad);
    phm_se3_ad(s, as);
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 6; j++) {
        double sa = 0, sb = 0;
        for (int l = 0; l < 6; l++) {
          sa += pd->AdBa[6 * i + l] * ad[6 * l + j];
          sb += as[6 * i + l] * AdTbi[6 * l + j];
        }
        Dt[12 * i + j] = sa;
        Dt[12 * i + 6 + j] = -sb;
      }
  }
  if (dg && m->pair_general) eta_to_carriers(T.Dg, mc, AdTbi, pd->AdBa, dg);
  else if (dg) eta_to_carriers_sparse(T.Dg, mc, AdTbi, pd->AdBa, dg);
  const double *DW = T.W0 ? NULL : T.DW, *DPhi = T.Phi0 ? NULL : T.DPhi; /* NULL: constant */
  if (dc) { /* c = W^T (t_rel - ds a) - vf: a driven pair's prescribed twist ds a is fixed */
    double u[6];
    memcpy(u, tr, sizeof u);
    if (pr->driven) {
      double ds = 0;
      phm_law_eval(&pr->law, time, tref, &ds, NULL);
      for (int i = 0; i < 6; i++) u[i] -= ds * pr->axis[i];
    }
    basis_rate_tangent(pd->W, DW, mc, u, Dt, AdTbi, pd->AdBa, dc);
  }
  if (dxd) basis_rate_tangent(pd->Phi, DPhi, k, tr, Dt, AdTbi, pd->AdBa, dxd); /* Phi^T t_rel */
  if (Kl && lam) wrench_tangent(pd->W, DW, mc, lam, AdTbi, pd->AdBa, Kl);
  if (Km && mu) wrench_tangent(pd->W, DW, mc, mu, AdTbi, pd->AdBa, Km);
  if (Ku && u) wrench_tangent(pd->Phi, DPhi, k, u, AdTbi, pd->AdBa, Ku);
}

void phm_pair_joint(const phm_model *m, int ip, const double *Ha, const double *Hb,
                    const double *ta, const double *tb, const double *xref, double *x,
                    double *xdot) {
  phm_pair_data pd;
  phm_pair_evaluate(m, ip, Ha, Hb, ta, tb, xref, 0.0, 0.0, PHM_PAIR_JOINT, &pd);
  memcpy(x, pd.x, sizeof(double) * (size_t)m->pair_k[ip]);
  if (xdot) memcpy(xdot, pd.xdot, sizeof(double) * (size_t)m->pair_k[ip]);
}

void phm_constraints_columns(const phm_model *m, const double *H, const double *xs, double time,
                             double tref, const int *cmap, int n, double *g, double *G,
                             double *vt) {
  if (G) memset(G, 0, sizeof(double) * (size_t)m->ncons * (size_t)n);
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int r0 = m->pair_row[ip], mc = m->pair_m[ip];
    double Ga[36], Gb[36];
    phm_pair_eval(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                  xs ? xs + m->pair_j[ip] : NULL, time, tref, g ? g + r0 : NULL, Ga, Gb,
                  vt ? vt + r0 : NULL);
    if (G)
      for (int r = 0; r < mc; r++)
        for (int j = 0; j < 6; j++) {
          if (pr->a >= 0) G[(size_t)(r0 + r) * n + 6 * (cmap ? cmap[pr->a] : pr->a) + j] += Ga[6 * r + j];
          if (pr->b >= 0) G[(size_t)(r0 + r) * n + 6 * (cmap ? cmap[pr->b] : pr->b) + j] += Gb[6 * r + j];
        }
  }
}

void phm_constraints_dense(const phm_model *m, const double *H, const double *xs, double time,
                           double tref, double *g, double *G, double *vt) {
  phm_constraints_columns(m, H, xs, time, tref, NULL, 6 * m->nc, g, G, vt);
}

int phm_model_nconstraints_full(const phm_model *m) { return m->ncons_full; }

void phm_constraints_full(const phm_model *m, const double *H, const double *xs, double time,
                          double *g, double *G, double *W) {
  int n = 6 * m->nc;
  double tref = phm_model_tref(m, time, NULL);
  if (G) memset(G, 0, sizeof(double) * (size_t)m->ncons_full * (size_t)n);
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int r0 = m->pair_rowf[ip], mc = phm_pair_rows_full(pr);
    const double *Ha = pr->a >= 0 ? H + 16 * pr->a : NULL, *Hb = pr->b >= 0 ? H + 16 * pr->b : NULL;
    const double *xr = xs ? xs + m->pair_j[ip] : NULL;
    double Ga[36], Gb[36], gl[6];
    phm_pair_eval_full(m, ip, Ha, Hb, xr, time, tref, gl, Ga, Gb, W ? W + 36 * ip : NULL);
    if (g) memcpy(g + r0, gl, sizeof(double) * (size_t)mc);
    if (G)
      for (int r = 0; r < mc; r++)
        for (int j = 0; j < 6; j++) {
          if (pr->a >= 0) G[(size_t)(r0 + r) * n + 6 * pr->a + j] += Ga[6 * r + j];
          if (pr->b >= 0) G[(size_t)(r0 + r) * n + 6 * pr->b + j] += Gb[6 * r + j];
        }
  }
}

void phm_model_joints(const phm_model *m, const double *H, const double *xs, double *x) {
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    if (m->pair_k[ip] == 0) continue;
    phm_pair_joint(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                   NULL, NULL, xs ? xs + m->pair_j[ip] : NULL, x + m->pair_j[ip], NULL);
  }
}

/* f += G^T lam on every carrier: the "evaluate the pair, scatter G^T lambda" loop, once. */
void phm_constraint_forces(const phm_model *m, const double *H, double time, double tref,
                           const double *lam, double *f) {
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int r0 = m->pair_row[ip], mc = m->pair_m[ip];
    double Ga[6 * PHM_MAXCON], Gb[6 * PHM_MAXCON];
    phm_pair_eval(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                  NULL, time, tref, NULL, Ga, Gb, NULL);
    for (int r = 0; r < mc; r++)
      for (int j = 0; j < 6; j++) {
        if (pr->a >= 0) f[6 * pr->a + j] += Ga[6 * r + j] * lam[r0 + r];
        if (pr->b >= 0) f[6 * pr->b + j] += Gb[6 * r + j] * lam[r0 + r];
      }
  }
}
