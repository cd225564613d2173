/* se3.c -- so(3)/SO(3) and se(3)/SE(3) algebra: hat, exp, log, compose, inverse, Ad, ad, dexp and
 * dexp^-1 (conventions: csrc/include/phmech_types.h, docs/method.md section 3); with fast paths at
 * rotations about a coordinate axis. Quaternions: quat.c; the derivatives of dexp^-1:
 * se3_dexp_partials.c.
 *
 * All matrices row-major. Twist x = (omega, v). No allocation, no printing.
 * Near theta = 0 the trigonometric coefficients are evaluated by truncated Taylor series
 * (or in forms without cancellation); near theta = pi the SO(3) log takes its axis from the
 * symmetric part of R. */
#include "linalg.h"

#include <math.h>
#include <string.h>

/* ---------------------------------------------------------------- small helpers */

/* sin(t)/t, accurate for all t. */
static double sinc(double t) {
  double t2 = t * t;
  if (fabs(t) < 1e-3) return 1.0 - t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0));
  return sin(t) / t;
}

/* Coefficients of the SO(3) exponential and left Jacobian for angle t = |w|:
 *   a = sin t / t,  b = (1 - cos t)/t^2,  c = (t - sin t)/t^3. */
static void so3_coeffs(double t, double *a, double *b, double *c) {
  double t2 = t * t;
  double s = sinc(0.5 * t);
  *a = sinc(t);
  *b = 0.5 * s * s; /* (1 - cos t)/t^2 = 2 sin^2(t/2)/t^2, no cancellation */
  if (t < 0.1)
    *c = 1.0 / 6.0 - t2 * (1.0 / 120.0 - t2 * (1.0 / 5040.0 - t2 * (1.0 / 362880.0 - t2 / 39916800.0)));
  else
    *c = (t - sin(t)) / (t2 * t);
}

/* d = (1 - (t/2) cot(t/2)) / t^2, the W^2 coefficient of the inverse left Jacobian. */
static double so3_jac_inv_coeff(double t) {
  double t2 = t * t;
  if (t < 0.1)
    return 1.0 / 12.0 + t2 * (1.0 / 720.0 + t2 * (1.0 / 30240.0 + t2 * (1.0 / 1209600.0 + t2 / 47900160.0)));
  double h = 0.5 * t;
  return (1.0 - h * cos(h) / sin(h)) / t2;
}

/* M = I + alpha W + beta W^2 with W = hat(w) (csrc/util/linalg.h). */
void phm_so3_poly(const double w[3], double alpha, double beta, double M[9]) {
  double W[9], t2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
  phm_so3_hat(w, W);
  /* W^2 = w w^T - |w|^2 I */
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) M[3 * i + j] = alpha * W[3 * i + j] + beta * (w[i] * w[j] - (i == j ? t2 : 0.0));
  M[0] += 1.0;
  M[4] += 1.0;
  M[8] += 1.0;
}

static void mat3_vec(const double A[9], const double x[3], double y[3]) {
  double t[3];
  for (int i = 0; i < 3; i++) t[i] = A[3 * i] * x[0] + A[3 * i + 1] * x[1] + A[3 * i + 2] * x[2];
  y[0] = t[0];
  y[1] = t[1];
  y[2] = t[2];
}

/* Write the 3x3 block B into the 6x6 matrix M at block row bi, block column bj. */
static void put_block(double M[36], int bi, int bj, const double B[9]) {
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) M[6 * (3 * bi + i) + 3 * bj + j] = B[3 * i + j];
}

static void block_lower(const double D[9], const double L[9], double M[36]) {
  static const double Z[9] = {0};
  put_block(M, 0, 0, D);
  put_block(M, 0, 1, Z);
  put_block(M, 1, 0, L);
  put_block(M, 1, 1, D);
}

/* The coefficients c1, c2, c3 of se3_dexp_Q_at (which states them) at t = |omega|. */
static void se3_dexp_Q_coeffs(double t, double *c1, double *c2, double *c3) {
  double t2 = t * t, e;
  if (t < 0.1) {
    *c1 = 1.0 / 6.0 - t2 * (1.0 / 120.0 - t2 * (1.0 / 5040.0 - t2 * (1.0 / 362880.0 - t2 / 39916800.0)));
    *c2 = 1.0 / 24.0 - t2 * (1.0 / 720.0 - t2 * (1.0 / 40320.0 - t2 * (1.0 / 3628800.0 - t2 / 479001600.0)));
    e = -1.0 / 120.0 + t2 * (1.0 / 5040.0 - t2 * (1.0 / 362880.0 - t2 * (1.0 / 39916800.0 - t2 / 6227020800.0)));
  } else {
    double s = sin(t), co = cos(t);
    *c1 = (t - s) / (t2 * t);
    *c2 = (0.5 * t2 + co - 1.0) / (t2 * t2);
    e = (t - s - t2 * t / 6.0) / (t2 * t2 * t);
  }
  *c3 = 0.5 * (*c2 + 3.0 * e);
}

/* ---------------------------------------------------------------- rotations about a coordinate axis
 * In a planar scene every relative rotation turns about the plane's normal, a coordinate axis
 * e_k of the bodies' frames: R's row and column k are exactly e_k (their other entries exact
 * zeros, as quaternions (q_w, 0, q_y, 0) and their products make them), and log R = theta e_k.
 * The functions below are the general path's arithmetic on the entries that are not exactly
 * zero -- the same products, summed in the same order, each sum dropping only exact-zero terms
 * (which leave a sum as it is, up to the sign of a zero result) -- so they return the general
 * path's numbers at a fraction of its cost (tests/c/test_se3.c compares the two). (i, j, k) is
 * a cyclic order of the axes: hat(theta e_k) has -theta at (i, j) and theta at (j, i). */

/* The axis k of a rotation matrix R (3x3) whose row and column k are e_k off the diagonal (exact
 * zeros), -1 if none (two tests for a general R). */
static inline int rot_axis(const double R[9]) {
  if (R[1] == 0.0 && R[3] == 0.0) { /* z: R[5], R[7]; y: R[2]..; x: R[2], R[6] */
    if (R[5] == 0.0 && R[7] == 0.0) return 1;
    if (R[2] == 0.0 && R[6] == 0.0) return 0;
    return -1;
  }
  if (R[2] == 0.0 && R[5] == 0.0 && R[6] == 0.0 && R[7] == 0.0) return 2;
  return -1;
}

/* phm_so3_log_general at R = rotation about e_k (rot_axis(R) == k): w = theta e_k. Returns 0
 * (w untouched) where the general path would take another axis from R's symmetric part (theta
 * = pi about another axis, or R not a rotation): the caller then takes the general path. */
PHM_AXIS_INLINE int so3_log_axis(const double R[9], int k, double w[3]) {
  int i = (k + 1) % 3, j = (k + 2) % 3;
  double sk = 0.5 * (R[3 * j + i] - R[3 * i + j]); /* vee's component k, the others 0.5 (0 - 0) */
  double sn = fabs(sk); /* norm3 of (0, sk, 0): sqrt(sk * sk) is |sk| in binary floating point */
  double c = 0.5 * (R[0] + R[4] + R[8] - 1.0);
  double theta = atan2(sn, c);
  if (c >= 0.0) {
    double f = sn > 0.0 ? theta / sn : 1.0;
    w[k] = f * sk;
    w[i] = w[j] = 0.0;
    return 1;
  }
  /* B = (R + R^T)/2 - c I: its diagonal R_aa - c; column k is (0, B_kk, 0) */
  double B0 = R[0] - c, B4 = R[4] - c, B8 = R[8] - c;
  int kk = 0;
  double bk = B0;
  if (B4 > bk) kk = 1, bk = B4;
  if (B8 > bk) kk = 2, bk = B8;
  if (kk != k || !(fabs(bk) > 0.0)) return 0;
  double sgn = bk * sk < 0.0 ? -1.0 : 1.0;
  w[k] = sgn * theta * bk / fabs(bk);
  w[i] = w[j] = 0.0;
  return 1;
}

/* Ai = phm_so3_poly(theta e_k, alpha, beta): I + alpha W + beta (w w^T - theta^2 I). */
PHM_AXIS_INLINE void so3_poly_axis(int k, double th, double alpha, double beta, double M[9]) {
  int i = (k + 1) % 3, j = (k + 2) % 3;
  double t2 = th * th;
  M[3 * k + k] = 1.0;
  M[3 * i + i] = M[3 * j + j] = 1.0 + -(beta * t2);
  M[3 * i + j] = -(alpha * th); /* alpha W_ij = alpha (-theta) */
  M[3 * j + i] = alpha * th;
  M[3 * i + k] = M[3 * k + i] = M[3 * j + k] = M[3 * k + j] = 0.0;
}

/* y = M p for M = so3_poly_axis's (row k: p_k). */
PHM_AXIS_INLINE void mat3_vec_axis(int k, const double M[9], const double p[3], double y[3]) {
  int i = (k + 1) % 3, j = (k + 2) % 3;
  double yi = i < j ? M[3 * i + i] * p[i] + M[3 * i + j] * p[j] : M[3 * i + j] * p[j] + M[3 * i + i] * p[i];
  double yj = i < j ? M[3 * j + i] * p[i] + M[3 * j + j] * p[j] : M[3 * j + j] * p[j] + M[3 * j + i] * p[i];
  y[i] = yi;
  y[j] = yj;
  y[k] = p[k];
}

/* se3_dexp_Q_at (which states Q) at x = (theta e_k, v), t = |theta|, entry by entry with s =
 * theta v_k, u = w x v = (u_i, u_j, 0) = (-theta v_j, theta v_i, 0). */
PHM_AXIS_INLINE void se3_dexp_Q_axis(int k, double th, double t, const double v[3], double Q[9]) {
  int i = (k + 1) % 3, j = (k + 2) % 3;
  double c1, c2, c3;
  se3_dexp_Q_coeffs(t, &c1, &c2, &c3);
  double t2 = t * t, s = th * v[k], ui = -(th * v[j]), uj = th * v[i], st = s * th;
  double tii = 2.0 * c3 * s * t2;
  Q[3 * k + k] = 0.0;
  Q[3 * i + i] = Q[3 * j + j] = -(c1 * (2.0 * s)) + tii;
  Q[3 * i + j] = (-(0.5 * v[k]) + c1 * st) + -(c2 * st);
  Q[3 * j + i] = (0.5 * v[k] + -(c1 * st)) + c2 * st;
  Q[3 * i + k] = (0.5 * v[j] + c1 * (v[i] * th)) + c2 * (ui * th);
  Q[3 * k + i] = (-(0.5 * v[j]) + c1 * (th * v[i])) + c2 * -(th * ui);
  Q[3 * j + k] = (-(0.5 * v[i]) + c1 * (v[j] * th)) + c2 * (uj * th);
  Q[3 * k + j] = (0.5 * v[i] + c1 * (th * v[j])) + c2 * -(th * uj);
}

/* The sum a + b of a row-column product's two nonzero terms, in the general path's order. */
#define SUM2(first_is_a, a, b) ((first_is_a) ? (a) + (b) : (b) + (a))

/* L = -(Ai Q) Ai (se3_dexp_inv_blocks) for Ai = so3_poly_axis's. */
PHM_AXIS_INLINE void dexp_inv_L_axis(int k, const double Ai[9], const double Q[9], double L[9]) {
  int i = (k + 1) % 3, j = (k + 2) % 3, o = i < j;
  double a = Ai[3 * i + i], bij = Ai[3 * i + j], bji = Ai[3 * j + i], T[9];
  for (int c = 0; c < 3; c++) {
    T[3 * i + c] = SUM2(o, a * Q[3 * i + c], bij * Q[3 * j + c]);
    T[3 * j + c] = SUM2(o, bji * Q[3 * i + c], a * Q[3 * j + c]);
    T[3 * k + c] = Q[3 * k + c];
  }
  for (int r = 0; r < 3; r++) {
    L[3 * r + i] = -SUM2(o, T[3 * r + i] * a, T[3 * r + j] * bji);
    L[3 * r + j] = -SUM2(o, T[3 * r + i] * bij, T[3 * r + j] * a);
    L[3 * r + k] = -T[3 * r + k];
  }
}

/* phm_se3_log at R = rotation about e_k (*ok = 0: the general path's turn, so3_log_axis). */
PHM_AXIS_INLINE void se3_log_axis(int k, const double R[9], const double p[3], double x[6], int *ok) {
  if (!(*ok = so3_log_axis(R, k, x))) return;
  double th = x[k], Ai[9];
  so3_poly_axis(k, th, -0.5, so3_jac_inv_coeff(fabs(th)), Ai);
  mat3_vec_axis(k, Ai, p, x + 3);
}

/* phm_se3_log_dexp_inv at R = rotation about e_k (*ok = 0: the general path's turn). */
PHM_AXIS_INLINE void se3_log_dexp_inv_axis(int k, const double R[9], const double p[3], double x[6],
                                       double Ai[9], double L[9], int *ok) {
  if (!(*ok = so3_log_axis(R, k, x))) return;
  double th = x[k], t = fabs(th), Q[9];
  so3_poly_axis(k, th, -0.5, so3_jac_inv_coeff(t), Ai);
  mat3_vec_axis(k, Ai, p, x + 3);
  se3_dexp_Q_axis(k, th, t, x + 3, Q);
  dexp_inv_L_axis(k, Ai, Q, L);
}

/* ---------------------------------------------------------------- so(3) / SO(3) */

void phm_so3_hat(const double w[3], double W[9]) {
  W[0] = 0.0;   W[1] = -w[2]; W[2] = w[1];
  W[3] = w[2];  W[4] = 0.0;   W[5] = -w[0];
  W[6] = -w[1]; W[7] = w[0];  W[8] = 0.0;
}

void phm_so3_vee(const double W[9], double w[3]) {
  w[0] = 0.5 * (W[7] - W[5]);
  w[1] = 0.5 * (W[2] - W[6]);
  w[2] = 0.5 * (W[3] - W[1]);
}

void phm_so3_exp(const double w[3], double R[9]) {
  double a, b, c;
  so3_coeffs(phm_norm3(w), &a, &b, &c);
  phm_so3_poly(w, a, b, R);
}

/* The general SO(3) log (phm_so3_log_general; inlined into each caller). */
static inline void so3_log_gen(const double R[9], double w[3]) {
  double s[3]; /* vee of the skew part = sin(theta) n */
  phm_so3_vee(R, s);
  double sn = phm_norm3(s);
  double c = 0.5 * (R[0] + R[4] + R[8] - 1.0); /* cos(theta) */
  double theta = atan2(sn, c);
  if (c >= 0.0) {
    /* theta <= pi/2: w = s theta/sin(theta); theta/sn computed directly, no cancellation. */
    double f = sn > 0.0 ? theta / sn : 1.0;
    for (int i = 0; i < 3; i++) w[i] = f * s[i];
    return;
  }
  /* theta > pi/2: (R + R^T)/2 - c I = (1 - c) n n^T, with 1 - c in (1, 2]. */
  double B[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) B[3 * i + j] = 0.5 * (R[3 * i + j] + R[3 * j + i]) - (i == j ? c : 0.0);
  int k = 0;
  if (B[4] > B[3 * k + k]) k = 1;
  if (B[8] > B[3 * k + k]) k = 2;
  double n[3];
  for (int i = 0; i < 3; i++) n[i] = B[3 * i + k];
  double nn = phm_norm3(n);
  if (!(nn > 0.0)) { /* not a rotation matrix; fall back on the skew part */
    double f = sn > 0.0 ? theta / sn : 0.0;
    for (int i = 0; i < 3; i++) w[i] = f * s[i];
    return;
  }
  double sgn = (n[0] * s[0] + n[1] * s[1] + n[2] * s[2]) < 0.0 ? -1.0 : 1.0;
  for (int i = 0; i < 3; i++) w[i] = sgn * theta * n[i] / nn;
}

void phm_so3_log_general(const double R[9], double w[3]) { so3_log_gen(R, w); }

int phm_so3_axis(const double R[9]) { return rot_axis(R); }

void phm_so3_log(const double R[9], double w[3]) {
  int k = rot_axis(R);
  if (k >= 0 && so3_log_axis(R, k, w)) return;
  so3_log_gen(R, w);
}

void phm_so3_jac(const double w[3], double A[9]) {
  double a, b, c;
  so3_coeffs(phm_norm3(w), &a, &b, &c);
  phm_so3_poly(w, b, c, A);
}

void phm_so3_jac_inv(const double w[3], double Ai[9]) {
  phm_so3_poly(w, -0.5, so3_jac_inv_coeff(phm_norm3(w)), Ai);
}

/* ---------------------------------------------------------------- se(3) / SE(3) */

void phm_se3_hat(const double x[6], double X[16]) {
  double W[9];
  phm_so3_hat(x, W);
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++) X[4 * i + j] = W[3 * i + j];
    X[4 * i + 3] = x[3 + i];
  }
  X[12] = X[13] = X[14] = X[15] = 0.0;
}

void phm_se3_vee(const double X[16], double x[6]) {
  x[0] = 0.5 * (X[9] - X[6]);
  x[1] = 0.5 * (X[2] - X[8]);
  x[2] = 0.5 * (X[4] - X[1]);
  x[3] = X[3];
  x[4] = X[7];
  x[5] = X[11];
}

static void pose_split(const double H[16], double R[9], double p[3]) {
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++) R[3 * i + j] = H[4 * i + j];
    p[i] = H[4 * i + 3];
  }
}

static void pose_join(const double R[9], const double p[3], double H[16]) {
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++) H[4 * i + j] = R[3 * i + j];
    H[4 * i + 3] = p[i];
  }
  H[12] = H[13] = H[14] = 0.0;
  H[15] = 1.0;
}

void phm_se3_exp(const double x[6], double H[16]) {
  double a, b, c, R[9], A[9], p[3];
  so3_coeffs(phm_norm3(x), &a, &b, &c);
  phm_so3_poly(x, a, b, R);
  phm_so3_poly(x, b, c, A);
  mat3_vec(A, x + 3, p);
  pose_join(R, p, H);
}

/* phm_se3_log's general path, from H's rotation R and position p. */
static void se3_log_rp(const double R[9], const double p[3], double x[6]) {
  double Ai[9];
  so3_log_gen(R, x);
  phm_so3_jac_inv(x, Ai);
  mat3_vec(Ai, p, x + 3);
}

void phm_se3_log_general(const double H[16], double x[6]) {
  double R[9], p[3];
  pose_split(H, R, p);
  se3_log_rp(R, p, x);
}

void phm_se3_log(const double H[16], double x[6]) {
  double R[9], p[3];
  pose_split(H, R, p);
  int k = rot_axis(R);
  int ok = 0;
  if (k >= 0) PHM_AXIS_CALL(k, se3_log_axis, R, p, x, &ok);
  if (!ok) se3_log_rp(R, p, x);
}

void phm_se3_compose(const double A[16], const double B[16], double AB[16]) {
  double Ra[9], pa[3], Rb[9], pb[3], R[9], p[3];
  pose_split(A, Ra, pa);
  pose_split(B, Rb, pb);
  phm_mat3_mul(Ra, Rb, R);
  mat3_vec(Ra, pb, p);
  for (int i = 0; i < 3; i++) p[i] += pa[i];
  pose_join(R, p, AB);
}

void phm_se3_inverse(const double H[16], double Hi[16]) {
  double R[9], p[3], Rt[9], q[3];
  pose_split(H, R, p);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) Rt[3 * i + j] = R[3 * j + i];
  mat3_vec(Rt, p, q);
  for (int i = 0; i < 3; i++) q[i] = -q[i];
  pose_join(Rt, q, Hi);
}

void phm_se3_Ad(const double H[16], double A[36]) {
  double R[9], p[3], P[9], PR[9];
  pose_split(H, R, p);
  phm_so3_hat(p, P);
  phm_mat3_mul(P, R, PR);
  block_lower(R, PR, A);
}

static void transpose6(double A[36]) {
  for (int i = 0; i < 6; i++)
    for (int j = i + 1; j < 6; j++) {
      double t = A[6 * i + j];
      A[6 * i + j] = A[6 * j + i];
      A[6 * j + i] = t;
    }
}

void phm_se3_Ad_dual(const double H[16], double A[36]) {
  phm_se3_Ad(H, A);
  transpose6(A);
}

void phm_se3_ad(const double x[6], double a[36]) {
  double W[9], V[9];
  phm_so3_hat(x, W);
  phm_so3_hat(x + 3, V);
  block_lower(W, V, a);
}

void phm_se3_ad_dual(const double x[6], double a[36]) {
  phm_se3_ad(x, a);
  transpose6(a);
}

/* Lower-left block Q of dexp_x = [[A, 0], [Q, A]]:
 *   Q = V/2 + c1 (WV + VW + WVW) + c2 (W^2 V + V W^2 - 3 WVW) + c3 (WVW^2 + W^2 VW),
 * c1 = (t - sin t)/t^3, c2 = (t^2/2 + cos t - 1)/t^4,
 * c3 = (c2 + 3 (t - sin t - t^3/6)/t^5)/2, each by its Taylor series for t < 0.1. */
static void se3_dexp_Q_at(const double x[6], double t, double Q[9]) {
  double t2 = t * t, c1, c2, c3;
  se3_dexp_Q_coeffs(t, &c1, &c2, &c3);
  /* the products of hats written out (hat(a) hat(b) = b a^T - (a.b) I, W w = 0): with s = w.v,
   * u = w x v: WV + VW + WVW = v w^T + w v^T - 2s I - s W; W^2 V + V W^2 - 3 WVW = u w^T - w u^T
   * + s W; WVW^2 + W^2 VW = -2s W^2 = -2s (w w^T - t^2 I). Seven 3x3 products were 10 % of a
   * flexible scene's CPU. */
  const double *w = x, *v = x + 3;
  double s = w[0] * v[0] + w[1] * v[1] + w[2] * v[2];
  double u[3] = {w[1] * v[2] - w[2] * v[1], w[2] * v[0] - w[0] * v[2], w[0] * v[1] - w[1] * v[0]};
  double W[9], V[9];
  phm_so3_hat(w, W);
  phm_so3_hat(v, V);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      int k = 3 * i + j;
      double I = i == j ? 1.0 : 0.0;
      Q[k] = 0.5 * V[k] + c1 * (v[i] * w[j] + w[i] * v[j] - 2.0 * s * I - s * W[k]) +
             c2 * (u[i] * w[j] - w[i] * u[j] + s * W[k]) - 2.0 * c3 * s * (w[i] * w[j] - t2 * I);
    }
}

/* (t = |omega|) */
static void se3_dexp_Q(const double x[6], double Q[9]) { se3_dexp_Q_at(x, phm_norm3(x), Q); }

void phm_se3_dexp(const double x[6], double D[36]) {
  double A[9], Q[9];
  phm_so3_jac(x, A);
  se3_dexp_Q(x, Q);
  block_lower(A, Q, D);
}

/* The blocks of dexp_x^-1 = [[Ai, 0], [L, Ai]]: Ai = so3 jac_inv(omega), L = -Ai Q Ai
 * (t = |omega|). */
static void se3_dexp_inv_blocks(const double x[6], double t, const double Ai[9], double L[9]) {
  double Q[9], T[9];
  se3_dexp_Q_at(x, t, Q);
  phm_mat3_mul(Ai, Q, T);
  phm_mat3_mul(T, Ai, L);
  for (int i = 0; i < 9; i++) L[i] = -L[i];
}

void phm_se3_dexp_inv(const double x[6], double Di[36]) {
  double Ai[9], L[9], t = phm_norm3(x);
  phm_so3_poly(x, -0.5, so3_jac_inv_coeff(t), Ai); /* phm_so3_jac_inv, sharing |omega| */
  se3_dexp_inv_blocks(x, t, Ai, L);
  block_lower(Ai, L, Di);
}

/* x = log(H) and the blocks of dexp_x^-1 = [[Ai, 0], [L, Ai]], sharing Ai between the two. Since
 * jac_inv(-w) = jac_inv(w)^T and Q(-x) = Q(x)^T (every term of Q is even in x and symmetric, or
 * odd and skew), dexp_{-x}^-1 = [[Ai^T, 0], [L^T, Ai^T]]: one evaluation serves both ends of a
 * beam element. */
/* phm_se3_log_dexp_inv's general path, from H's rotation R and position p. */
static void se3_log_dexp_inv_rp(const double R[9], const double p[3], double x[6], double Ai[9],
                                double L[9]) {
  so3_log_gen(R, x);
  double t = phm_norm3(x);
  phm_so3_poly(x, -0.5, so3_jac_inv_coeff(t), Ai); /* phm_so3_jac_inv, sharing |omega| */
  mat3_vec(Ai, p, x + 3);
  se3_dexp_inv_blocks(x, t, Ai, L);
}

void phm_se3_log_dexp_inv_general(const double H[16], double x[6], double Ai[9], double L[9]) {
  double R[9], p[3];
  pose_split(H, R, p);
  se3_log_dexp_inv_rp(R, p, x, Ai, L);
}

void phm_se3_log_dexp_inv(const double H[16], double x[6], double Ai[9], double L[9]) {
  double R[9], p[3];
  pose_split(H, R, p);
  int k = rot_axis(R);
  int ok = 0;
  if (k >= 0) PHM_AXIS_CALL(k, se3_log_dexp_inv_axis, R, p, x, Ai, L, &ok);
  if (!ok) se3_log_dexp_inv_rp(R, p, x, Ai, L);
}
