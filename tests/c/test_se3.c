/* test_se3.c -- C unit tests of the SE(3) algebra (csrc/util/se3.c) against independent references:
 * truncated power series, scaling-and-squaring matrix exponentials, central finite differences,
 * group identities. Random elements include angles within 1e-8 of 0 and of pi. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "phmech.h"

#define PI 3.14159265358979323846

static int n_pass = 0, n_fail = 0;

static void check(const char *name, double err, double tol) {
  if (err <= tol) {
    n_pass++;
  } else {
    n_fail++;
    printf("FAIL %s: error %.3e > tol %.1e\n", name, err, tol);
  }
}

/* worst error per identity, reported at the end */
#define NREC 40
static const char *rec_name[NREC];
static double rec_err[NREC];
static int nrec = 0;
static void record(const char *name, double err, double tol) {
  int i = 0;
  while (i < nrec && strcmp(rec_name[i], name) != 0) i++;
  if (i == nrec && nrec < NREC) {
    rec_name[nrec] = name;
    rec_err[nrec++] = 0.0;
  }
  if (i < NREC && err > rec_err[i]) rec_err[i] = err;
  check(name, err, tol);
}

/* ---- small RNG (splitmix64) ---- */
static unsigned long long rng_state = 0x1234567887654321ULL;
static double urand(void) { /* uniform in [0, 1) */
  unsigned long long z = (rng_state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}
static double nrand(void) { /* standard normal (Box-Muller) */
  double u = urand(), v = urand();
  return sqrt(-2.0 * log(1.0 - u)) * cos(2.0 * PI * v);
}
static void unit3(double n[3]) {
  double s;
  do {
    for (int i = 0; i < 3; i++) n[i] = nrand();
    s = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  } while (s < 1e-3);
  for (int i = 0; i < 3; i++) n[i] /= s;
}

/* Random rotation angle in [0, pi): class 0 uniform, 1 within 1e-8 of 0, 2 within 1e-8 of pi,
 * 3 tiny (< 1e-12) or exactly 0. */
static double rand_angle(int cls) {
  switch (cls) {
  case 1: return 1e-8 * urand();
  case 2: return PI - 1e-8 * (urand() + 1e-3);
  case 3: return urand() < 0.3 ? 0.0 : 1e-12 * urand();
  default: return PI * urand();
  }
}
static void rand_twist(int cls, double x[6]) {
  double n[3], th = rand_angle(cls);
  unit3(n);
  for (int i = 0; i < 3; i++) {
    x[i] = th * n[i];
    x[3 + i] = 2.0 * nrand();
  }
}

/* ---- dense helpers ---- */
static void matmul(int n, const double *A, const double *B, double *C) {
  double T[64];
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) {
      double s = 0.0;
      for (int k = 0; k < n; k++) s += A[n * i + k] * B[n * k + j];
      T[n * i + j] = s;
    }
  memcpy(C, T, sizeof(double) * (size_t)(n * n));
}
static double maxdiff(int m, const double *A, const double *B) {
  double e = 0.0;
  for (int i = 0; i < m; i++) e = fmax(e, fabs(A[i] - B[i]));
  return e;
}
static void eye(int n, double *I) {
  memset(I, 0, sizeof(double) * (size_t)(n * n));
  for (int i = 0; i < n; i++) I[n * i + i] = 1.0;
}
/* expm by scaling and squaring of a Taylor series (reference, independent of se3.c) */
static void expm(int n, const double *A, double *E) {
  double nrm = 0.0;
  for (int i = 0; i < n * n; i++) nrm = fmax(nrm, fabs(A[i]));
  int s = 0;
  while (nrm * n > 0.25) {
    nrm *= 0.5;
    s++;
  }
  double S[64], T[64], Tk[64];
  double scale = ldexp(1.0, -s);
  for (int i = 0; i < n * n; i++) S[i] = A[i] * scale;
  eye(n, E);
  eye(n, Tk);
  for (int k = 1; k <= 20; k++) {
    matmul(n, Tk, S, T);
    for (int i = 0; i < n * n; i++) {
      Tk[i] = T[i] / k;
      E[i] += Tk[i];
    }
  }
  for (int k = 0; k < s; k++) matmul(n, E, E, E);
}
/* sum_k A^k/(k+1)! (reference for dexp) */
static void phi1(int n, const double *A, double *D) {
  double Tk[64], T[64];
  eye(n, D);
  eye(n, Tk);
  for (int k = 1; k <= 60; k++) {
    matmul(n, Tk, A, T);
    for (int i = 0; i < n * n; i++) {
      Tk[i] = T[i] / (k + 1);
      D[i] += Tk[i];
    }
  }
}
static void rand_pose(int cls, double H[16]) {
  double x[6];
  rand_twist(cls, x);
  double X[16];
  phm_se3_hat(x, X);
  expm(4, X, H); /* reference construction, independent of phm_se3_exp */
  /* polish R to orthogonality at rounding level: two steps of R <- R (3 I - R^T R)/2 */
  for (int it = 0; it < 2; it++) {
    double R[9], RtR[9], Rn[9];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) R[3 * i + j] = H[4 * i + j];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++)
        RtR[3 * i + j] = R[i] * R[j] + R[3 + i] * R[3 + j] + R[6 + i] * R[6 + j];
    for (int i = 0; i < 9; i++) RtR[i] = -0.5 * RtR[i];
    RtR[0] += 1.5;
    RtR[4] += 1.5;
    RtR[8] += 1.5;
    matmul(3, R, RtR, Rn);
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) H[4 * i + j] = Rn[3 * i + j];
  }
  H[12] = H[13] = H[14] = 0.0;
  H[15] = 1.0;
}

int main(void) {
  const int N = 400;
  for (int it = 0; it < N; it++) {
    int cls = it % 4;
    double x[6], X[16], H[16], H2[16], y[6], Href[16], R[9], w[3], W[9], A[9], A2[9];

    /* hat / vee round trips */
    rand_twist(0, x);
    phm_se3_hat(x, X);
    phm_se3_vee(X, y);
    record("se3 vee(hat x) = x", maxdiff(6, x, y), 0.0);
    phm_so3_hat(x, W);
    phm_so3_vee(W, w);
    record("so3 vee(hat w) = w", maxdiff(3, x, w), 0.0);
    {
      double a[3] = {nrand(), nrand(), nrand()}, c[3], cr[3];
      phm_so3_hat(x, W);
      for (int i = 0; i < 3; i++) c[i] = W[3 * i] * a[0] + W[3 * i + 1] * a[1] + W[3 * i + 2] * a[2];
      cr[0] = x[1] * a[2] - x[2] * a[1];
      cr[1] = x[2] * a[0] - x[0] * a[2];
      cr[2] = x[0] * a[1] - x[1] * a[0];
      record("hat(w) a = w x a", maxdiff(3, c, cr), 1e-15 * 20);
    }

    /* exp vs reference expm; log(exp x) = x; exp(log H) = H */
    rand_twist(cls, x);
    phm_se3_exp(x, H);
    phm_se3_hat(x, X);
    expm(4, X, Href);
    record("se3 exp = expm(hat x)", maxdiff(16, H, Href), 1e-13);
    phm_se3_log(H, y);
    record("se3 log(exp x) = x", maxdiff(6, x, y) / (1.0 + fabs(x[3]) + fabs(x[4]) + fabs(x[5])),
           1e-12);
    phm_so3_exp(x, R);
    phm_so3_log(R, w);
    record("so3 log(exp w) = w", maxdiff(3, x, w), 1e-13);

    rand_pose(cls, H);
    phm_se3_log(H, y);
    phm_se3_exp(y, H2);
    record("se3 exp(log H) = H", maxdiff(16, H, H2), 1e-12);
    {
      double n[3], th = cls == 2 && it % 8 == 2 ? PI : rand_angle(cls), Rr[9], Rb[9];
      unit3(n);
      for (int i = 0; i < 3; i++) w[i] = th * n[i];
      phm_so3_hat(w, W);
      expm(3, W, Rr);
      phm_so3_log(Rr, y);
      double th2 = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
      record("so3 |log R| <= pi (+2 ulp)", th2 - PI, 9e-16);
      phm_so3_exp(y, Rb);
      record("so3 exp(log R) = R (incl. theta = pi)", maxdiff(9, Rr, Rb), 1e-12);
    }

    /* Ad(AB) = Ad(A) Ad(B); Ad(exp x) = expm(ad x); Ad_dual = Ad^T; ad_dual = ad^T */
    {
      double Hb[16], AB[16], Aa[36], Ab[36], Aab[36], P[36], ad[36], E[36], Ad[36], Add[36];
      rand_pose(0, H);
      rand_pose(cls, Hb);
      phm_se3_compose(H, Hb, AB);
      matmul(4, H, Hb, H2);
      record("compose = 4x4 product", maxdiff(16, AB, H2), 1e-14);
      phm_se3_Ad(H, Aa);
      phm_se3_Ad(Hb, Ab);
      phm_se3_Ad(AB, Aab);
      matmul(6, Aa, Ab, P);
      double big = 1.0;
      for (int i = 0; i < 36; i++) big = fmax(big, fabs(P[i]));
      record("Ad(AB) = Ad(A)Ad(B) (relative to max|Ad|)", maxdiff(36, Aab, P) / big, 2e-14);
      phm_se3_inverse(H, H2);
      phm_se3_compose(H, H2, AB);
      double I4[16];
      eye(4, I4);
      /* H^-1 uses R^T: the error is bounded by the reference pose's own non-orthogonality
       * |R R^T - I| (expm builds it to ~1e-14) times |p|, plus rounding */
      double RRt[9], Rh[9], I3o[9];
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) Rh[3 * i + j] = H[4 * i + j];
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
          RRt[3 * i + j] = Rh[3 * i] * Rh[3 * j] + Rh[3 * i + 1] * Rh[3 * j + 1] + Rh[3 * i + 2] * Rh[3 * j + 2];
      eye(3, I3o);
      double orth = maxdiff(9, RRt, I3o) + 2.2e-16;
      record("H H^-1 = I (units of orthogonality error x |p|)",
             maxdiff(16, AB, I4) / (orth * (1.0 + fabs(H[3]) + fabs(H[7]) + fabs(H[11]))), 8.0);
      rand_twist(cls, x);
      phm_se3_ad(x, ad);
      expm(6, ad, E);
      phm_se3_exp(x, H);
      phm_se3_Ad(H, Ad);
      record("Ad(exp x) = expm(ad x)", maxdiff(36, Ad, E), 1e-12);
      phm_se3_Ad_dual(H, Add);
      double e = 0.0;
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) e = fmax(e, fabs(Add[6 * i + j] - Ad[6 * j + i]));
      record("Ad_dual = Ad^T", e, 0.0);
      phm_se3_ad_dual(x, E);
      e = 0.0;
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) e = fmax(e, fabs(E[6 * i + j] - ad[6 * j + i]));
      record("ad_dual = ad^T", e, 0.0);
      /* hat(ad_x y) = [hat x, hat y] */
      double z[6], Xh[16], Yh[16], XY[16], YX[16], az[6], Z[16];
      rand_twist(0, z);
      phm_se3_hat(x, Xh);
      phm_se3_hat(z, Yh);
      matmul(4, Xh, Yh, XY);
      matmul(4, Yh, Xh, YX);
      for (int i = 0; i < 16; i++) XY[i] -= YX[i];
      for (int i = 0; i < 6; i++) {
        az[i] = 0.0;
        for (int j = 0; j < 6; j++) az[i] += ad[6 * i + j] * z[j];
      }
      phm_se3_hat(az, Z);
      record("hat(ad_x y) = [hat x, hat y]", maxdiff(16, Z, XY), 1e-13);
    }

    /* dexp vs power series; dexp dexp_inv = I; jac blocks; finite differences of exp */
    {
      double D[36], Di[36], Dr[36], ad[36], P[36], I6[36];
      rand_twist(cls, x);
      phm_se3_dexp(x, D);
      phm_se3_ad(x, ad);
      phi1(6, ad, Dr);
      record("dexp = sum ad^k/(k+1)!", maxdiff(36, D, Dr), 1e-13);
      phm_se3_dexp_inv(x, Di);
      matmul(6, D, Di, P);
      eye(6, I6);
      record("dexp dexp_inv = I", maxdiff(36, P, I6), 1e-13);
      { /* the fused log + dexp_inv of a beam element: x = log H, dexp_x^-1 and the block
         * transpose that is dexp_{-x}^-1 */
        double Hx[16], xl[6], xr[6], Ai[9], L[9], Dm[36], mx[6], e1 = 0.0, e2 = 0.0;
        phm_se3_exp(x, Hx);
        phm_se3_log_dexp_inv(Hx, xl, Ai, L);
        phm_se3_log(Hx, xr);
        record("log_dexp_inv: x = log H", maxdiff(6, xl, xr), 0.0);
        phm_se3_dexp_inv(xl, Di);
        for (int i = 0; i < 6; i++) mx[i] = -xl[i];
        phm_se3_dexp_inv(mx, Dm);
        for (int i = 0; i < 3; i++)
          for (int j = 0; j < 3; j++) {
            e1 = fmax(e1, fmax(fabs(Ai[3 * i + j] - Di[6 * i + j]), fabs(L[3 * i + j] - Di[6 * (3 + i) + j])));
            e2 = fmax(e2, fmax(fabs(Ai[3 * j + i] - Dm[6 * i + j]), fabs(L[3 * j + i] - Dm[6 * (3 + i) + j])));
          }
        record("log_dexp_inv blocks = dexp_inv(x)", e1, 1e-15);
        record("log_dexp_inv transposed = dexp_inv(-x)", e2, 1e-13);
      }
      phm_so3_jac(x, A);
      double e = 0.0;
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) e = fmax(e, fabs(A[3 * i + j] - D[6 * i + j]));
      record("so3 jac = dexp block", e, 0.0);
      phm_so3_jac_inv(x, A2);
      matmul(3, A, A2, W);
      double I3[9];
      eye(3, I3);
      record("so3 jac jac_inv = I", maxdiff(9, W, I3), 1e-14);

      /* H(x)^-1 dH = hat(dexp_{-x} dx): central differences, h = 1e-6 */
      double xm[6], Dm[36], Hp[16], Hm[16], Hi[16], dH[16], G[16], g[6];
      for (int i = 0; i < 6; i++) xm[i] = -x[i];
      phm_se3_dexp(xm, Dm);
      phm_se3_exp(x, H);
      phm_se3_inverse(H, Hi);
      double h = 1e-6;
      e = 0.0;
      for (int k = 0; k < 6; k++) {
        double xp[6], xq[6];
        memcpy(xp, x, sizeof xp);
        memcpy(xq, x, sizeof xq);
        xp[k] += h;
        xq[k] -= h;
        phm_se3_exp(xp, Hp);
        phm_se3_exp(xq, Hm);
        for (int i = 0; i < 16; i++) dH[i] = (Hp[i] - Hm[i]) / (2.0 * h);
        matmul(4, Hi, dH, G);
        phm_se3_vee(G, g);
        for (int i = 0; i < 6; i++) e = fmax(e, fabs(g[i] - Dm[6 * i + k]));
      }
      record("H^-1 dH = dexp_{-x} dx (finite differences)", e, 1e-8);
    }

    /* quaternions: round trip, w >= 0, agreement with axis-angle */
    {
      double n[3], th = cls == 2 && it % 8 == 2 ? PI : rand_angle(cls), q[4], Rq[9], qr[4];
      unit3(n);
      for (int i = 0; i < 3; i++) w[i] = th * n[i];
      phm_so3_exp(w, R);
      phm_quat_from_rot(R, q);
      record("quat w >= 0", -q[0], 0.0);
      phm_quat_to_rot(q, Rq);
      record("quat_to_rot(quat_from_rot R) = R", maxdiff(9, R, Rq), 1e-14);
      qr[0] = cos(0.5 * th);
      for (int i = 0; i < 3; i++) qr[i + 1] = sin(0.5 * th) * n[i];
      double e = maxdiff(4, q, qr);
      if (th == PI) { /* q and -q both have w = 0 */
        double qm[4] = {-qr[0], -qr[1], -qr[2], -qr[3]};
        e = fmin(e, maxdiff(4, q, qm));
      }
      record("quat = (cos th/2, sin th/2 n)", e, 1e-14);
      double qs[4] = {3.0 * q[0], 3.0 * q[1], 3.0 * q[2], 3.0 * q[3]};
      phm_quat_to_rot(qs, Rq);
      record("quat_to_rot normalizes", maxdiff(9, R, Rq), 1e-14);
    }
  }

  for (int i = 0; i < nrec; i++) printf("  worst %-45s %.3e\n", rec_name[i], rec_err[i]);
  printf("%d passed, %d failed\n", n_pass, n_fail);
  return n_fail != 0;
}
