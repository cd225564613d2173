/* test_se3.c -- csrc/util/se3.c (SO(3), SE(3), quaternions) against independent references:
 * truncated power series, scaling-and-squaring matrix exponentials (tests/c/check.h), central
 * finite differences, group identities. Each case draws N random elements, a quarter each with
 * rotation angles uniform, within 1e-8 of 0, within 1e-8 of pi, and tiny or exactly 0. */
#include "check.h"
#include "linalg.h"

enum { N = 400 };

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

/* max |A - B^T| of two n x n matrices */
static double maxdiff_transposed(int n, const double *A, const double *B) {
  double e = 0.0;
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) e = fmax(e, fabs(A[n * i + j] - B[n * j + i]));
  return e;
}

/* A rotation angle of class it % 4, exactly pi on every eighth element. */
static double angle_incl_pi(int it) { return it % 8 == 2 ? CHECK_PI : rand_angle(it % 4); }

static void hat_and_vee_are_inverse_and_hat_is_the_cross_product(void) {
  for (int it = 0; it < N; it++) {
    double x[6], X[16], y[6], w[3], W[9];
    rand_twist(0, x);
    phm_se3_hat(x, X);
    phm_se3_vee(X, y);
    check_worst("se3 vee(hat x) = x", maxdiff(6, x, y), 0.0);
    phm_so3_hat(x, W);
    phm_so3_vee(W, w);
    check_worst("so3 vee(hat w) = w", maxdiff(3, x, w), 0.0);
    double a[3] = {randn(), randn(), randn()}, c[3], cr[3];
    for (int i = 0; i < 3; i++) c[i] = W[3 * i] * a[0] + W[3 * i + 1] * a[1] + W[3 * i + 2] * a[2];
    cr[0] = x[1] * a[2] - x[2] * a[1];
    cr[1] = x[2] * a[0] - x[0] * a[2];
    cr[2] = x[0] * a[1] - x[1] * a[0];
    check_worst("hat(w) a = w x a", maxdiff(3, c, cr), 1e-15 * 20);
  }
}

static void exp_matches_expm_and_log_inverts_it(void) {
  for (int it = 0; it < N; it++) {
    int cls = it % 4;
    double x[6], X[16], H[16], H2[16], y[6], Href[16], R[9], w[3], W[9];
    rand_twist(cls, x);
    phm_se3_exp(x, H);
    phm_se3_hat(x, X);
    expm(4, X, Href);
    check_worst("se3 exp = expm(hat x)", maxdiff(16, H, Href), 1e-13);
    phm_se3_log(H, y);
    check_worst("se3 log(exp x) = x",
                maxdiff(6, x, y) / (1.0 + fabs(x[3]) + fabs(x[4]) + fabs(x[5])), 1e-12);
    phm_so3_exp(x, R);
    phm_so3_log(R, w);
    check_worst("so3 log(exp w) = w", maxdiff(3, x, w), 1e-13);

    rand_pose_class(cls, H);
    phm_se3_log(H, y);
    phm_se3_exp(y, H2);
    check_worst("se3 exp(log H) = H", maxdiff(16, H, H2), 1e-12);

    double n[3], th = angle_incl_pi(it), Rr[9], Rb[9];
    rand_unit3(n);
    for (int i = 0; i < 3; i++) w[i] = th * n[i];
    phm_so3_hat(w, W);
    expm(3, W, Rr);
    phm_so3_log(Rr, y);
    double th2 = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
    check_worst("so3 |log R| <= pi (+2 ulp)", th2 - CHECK_PI, 9e-16);
    phm_so3_exp(y, Rb);
    check_worst("so3 exp(log R) = R (incl. theta = pi)", maxdiff(9, Rr, Rb), 1e-12);
  }
}

/* compose, inverse, Ad(AB) = Ad(A) Ad(B), Ad(exp x) = expm(ad x), Ad_dual = Ad^T, ad_dual = ad^T,
 * hat(ad_x y) = [hat x, hat y] */
static void adjoints_are_group_and_algebra_representations(void) {
  for (int it = 0; it < N; it++) {
    int cls = it % 4;
    double x[6], H[16], H2[16], Hb[16], AB[16], Aa[36], Ab[36], Aab[36], P[36], ad[36], E[36],
        Ad[36], Add[36];
    rand_pose_class(0, H);
    rand_pose_class(cls, Hb);
    phm_se3_compose(H, Hb, AB);
    matmul(4, H, Hb, H2);
    check_worst("compose = 4x4 product", maxdiff(16, AB, H2), 1e-14);
    phm_se3_Ad(H, Aa);
    phm_se3_Ad(Hb, Ab);
    phm_se3_Ad(AB, Aab);
    matmul(6, Aa, Ab, P);
    check_worst("Ad(AB) = Ad(A)Ad(B) (relative to max|Ad|)",
                maxdiff(36, Aab, P) / fmax(1.0, maxabs(36, P)), 2e-14);
    phm_se3_inverse(H, H2);
    phm_se3_compose(H, H2, AB);
    double I4[16];
    eye(4, I4);
    /* H^-1 uses R^T: the error is bounded by the reference pose's own non-orthogonality
     * |R R^T - I| (expm builds it to ~1e-14) times |p|, plus rounding */
    double RRt[9], I3[9];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++)
        RRt[3 * i + j] = H[4 * i] * H[4 * j] + H[4 * i + 1] * H[4 * j + 1] + H[4 * i + 2] * H[4 * j + 2];
    eye(3, I3);
    double orth = maxdiff(9, RRt, I3) + 2.2e-16;
    check_worst("H H^-1 = I (units of orthogonality error x |p|)",
                maxdiff(16, AB, I4) / (orth * (1.0 + fabs(H[3]) + fabs(H[7]) + fabs(H[11]))), 8.0);
    rand_twist(cls, x);
    phm_se3_ad(x, ad);
    expm(6, ad, E);
    phm_se3_exp(x, H);
    phm_se3_Ad(H, Ad);
    check_worst("Ad(exp x) = expm(ad x)", maxdiff(36, Ad, E), 1e-12);
    phm_se3_Ad_dual(H, Add);
    check_worst("Ad_dual = Ad^T", maxdiff_transposed(6, Add, Ad), 0.0);
    phm_se3_ad_dual(x, E);
    check_worst("ad_dual = ad^T", maxdiff_transposed(6, E, ad), 0.0);
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
    check_worst("hat(ad_x y) = [hat x, hat y]", maxdiff(16, Z, XY), 1e-13);
  }
}

/* dexp vs its power series, dexp dexp_inv = I, the fused log + dexp_inv of a beam element, the
 * SO(3) Jacobians as blocks of dexp, and H^-1 dH = hat(dexp_{-x} dx) by central differences. */
static void dexp_is_the_derivative_of_exp(void) {
  for (int it = 0; it < N; it++) {
    double x[6], H[16], W[9], A[9], A2[9], D[36], Di[36], Dr[36], ad[36], P[36], I6[36];
    rand_twist(it % 4, x);
    phm_se3_dexp(x, D);
    phm_se3_ad(x, ad);
    phi1(6, ad, Dr);
    check_worst("dexp = sum ad^k/(k+1)!", maxdiff(36, D, Dr), 1e-13);
    phm_se3_dexp_inv(x, Di);
    matmul(6, D, Di, P);
    eye(6, I6);
    check_worst("dexp dexp_inv = I", maxdiff(36, P, I6), 1e-13);
    { /* x = log H, dexp_x^-1 and the block transpose that is dexp_{-x}^-1 */
      double Hx[16], xl[6], xr[6], Ai[9], L[9], Dm[36], mx[6], e1 = 0.0, e2 = 0.0;
      phm_se3_exp(x, Hx);
      phm_se3_log_dexp_inv(Hx, xl, Ai, L);
      phm_se3_log(Hx, xr);
      check_worst("log_dexp_inv: x = log H", maxdiff(6, xl, xr), 0.0);
      phm_se3_dexp_inv(xl, Di);
      for (int i = 0; i < 6; i++) mx[i] = -xl[i];
      phm_se3_dexp_inv(mx, Dm);
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
          e1 = fmax(e1, fmax(fabs(Ai[3 * i + j] - Di[6 * i + j]), fabs(L[3 * i + j] - Di[6 * (3 + i) + j])));
          e2 = fmax(e2, fmax(fabs(Ai[3 * j + i] - Dm[6 * i + j]), fabs(L[3 * j + i] - Dm[6 * (3 + i) + j])));
        }
      check_worst("log_dexp_inv blocks = dexp_inv(x)", e1, 1e-15);
      check_worst("log_dexp_inv transposed = dexp_inv(-x)", e2, 1e-13);
    }
    phm_so3_jac(x, A);
    double e = 0.0;
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) e = fmax(e, fabs(A[3 * i + j] - D[6 * i + j]));
    check_worst("so3 jac = dexp block", e, 0.0);
    phm_so3_jac_inv(x, A2);
    matmul(3, A, A2, W);
    double I3[9];
    eye(3, I3);
    check_worst("so3 jac jac_inv = I", maxdiff(9, W, I3), 1e-14);

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
    check_worst("H^-1 dH = dexp_{-x} dx (finite differences)", e, 1e-8);
  }
}

/* quaternions: round trip, w >= 0, agreement with axis-angle, normalization */
static void quaternions_round_trip_and_match_axis_angle(void) {
  for (int it = 0; it < N; it++) {
    double n[3], w[3], R[9], th = angle_incl_pi(it), q[4], Rq[9], qr[4];
    rand_unit3(n);
    for (int i = 0; i < 3; i++) w[i] = th * n[i];
    phm_so3_exp(w, R);
    phm_quat_from_rot(R, q);
    check_worst("quat w >= 0", -q[0], 0.0);
    phm_quat_to_rot(q, Rq);
    check_worst("quat_to_rot(quat_from_rot R) = R", maxdiff(9, R, Rq), 1e-14);
    qr[0] = cos(0.5 * th);
    for (int i = 0; i < 3; i++) qr[i + 1] = sin(0.5 * th) * n[i];
    double e = maxdiff(4, q, qr);
    if (th == CHECK_PI) { /* q and -q both have w = 0 */
      double qm[4] = {-qr[0], -qr[1], -qr[2], -qr[3]};
      e = fmin(e, maxdiff(4, q, qm));
    }
    check_worst("quat = (cos th/2, sin th/2 n)", e, 1e-14);
    double qs[4] = {3.0 * q[0], 3.0 * q[1], 3.0 * q[2], 3.0 * q[3]};
    phm_quat_to_rot(qs, Rq);
    check_worst("quat_to_rot normalizes", maxdiff(9, R, Rq), 1e-14);
  }
}

/* phm_se3_dexp_inv_partials against central differences (step 1e-5: truncation ~ 1e-10,
 * round-off ~ 1e-11 of entries of order 1) of phm_se3_dexp_inv, at rotation angles on both
 * sides of the series/closed-form switch (t = 1) and near pi. */
static void dexp_inv_partials_are_its_derivative(void) {
  static const double angles[] = {0.0, 1e-4, 0.05, 0.3, 0.999, 1.001, 2.0, 3.0};
  for (size_t ia = 0; ia < sizeof angles / sizeof angles[0]; ia++)
    for (int trial = 0; trial < 4; trial++) {
      double x[6], n[3], dAi[6][9], dL[6][9], err = 0, big = 0, hs = 1e-5;
      rand_unit3(n);
      for (int i = 0; i < 3; i++) x[i] = angles[ia] * n[i];
      for (int i = 3; i < 6; i++) x[i] = rand11();
      phm_se3_dexp_inv_partials(x, dAi, dL);
      for (int k = 0; k < 6; k++) {
        double xp[6], xm[6], Dp[36], Dm[36];
        memcpy(xp, x, sizeof xp);
        memcpy(xm, x, sizeof xm);
        xp[k] += hs;
        xm[k] -= hs;
        phm_se3_dexp_inv(xp, Dp);
        phm_se3_dexp_inv(xm, Dm);
        for (int i = 0; i < 3; i++)
          for (int j = 0; j < 3; j++) {
            double fa = (Dp[6 * i + j] - Dm[6 * i + j]) / (2 * hs);
            double fl = (Dp[6 * (3 + i) + j] - Dm[6 * (3 + i) + j]) / (2 * hs);
            double fa2 = (Dp[6 * (3 + i) + 3 + j] - Dm[6 * (3 + i) + 3 + j]) / (2 * hs);
            err = fmax(err, fmax(fabs(fa - dAi[k][3 * i + j]), fabs(fa2 - dAi[k][3 * i + j])));
            err = fmax(err, fabs(fl - dL[k][3 * i + j]));
            big = fmax(big, fmax(fabs(dAi[k][3 * i + j]), fabs(dL[k][3 * i + j])));
          }
      }
      check_worst("d(dexp^-1)/dx = central FD", err / fmax(big, 1.0), 1e-8);
    }
}

/* The logarithms' fast paths at rotations about a coordinate axis (a planar scene's relative
 * poses, csrc/util/se3.c) against their general paths: poses rotating about e_k by angles of
 * every class of rand_angle (either sign; exactly pi on some), translations with and without a
 * component along e_k, made directly (cos, sin and exact zeros) or as A^-1 B of two poses from
 * quaternions (q_w, q_k) (as a planar simulation makes them). The fast path must be taken
 * (phm_so3_axis) and agree to 1e-14 of the values' size; its arithmetic is the general path's
 * minus exact-zero terms, so it agrees to the last bit (checked too). A pose about no axis, or a
 * rotation by pi about another axis (R diagonal), takes the general path. Likewise
 * phm_quat_to_rot at quaternions about a coordinate axis. */
static void axis_fast_paths_match_the_general_paths(void) {
  int nbits = 0, ntot = 0;
  for (int it = 0; it < 3 * N; it++) {
    int k = it % 3, i = (k + 1) % 3, j = (k + 2) % 3, quat = (it / 3) % 2;
    double th = angle_incl_pi(it / 6) * (rand01() < 0.5 ? -1.0 : 1.0);
    double H[16] = {0}, R[9];
    if (!quat) {
      double c = cos(th), s = sin(th);
      H[5 * k] = 1.0;
      H[5 * i] = H[5 * j] = c;
      H[4 * j + i] = s;
      H[4 * i + j] = -s;
      for (int r = 0; r < 3; r++) H[4 * r + 3] = 2.0 * randn();
      if (it % 4 == 1) H[4 * k + 3] = 0.0;
      H[15] = 1.0;
    } else {
      double Ha[16] = {0}, Hb[16] = {0}, Hi[16], qa[4] = {0}, qb[4] = {0}, Ra[9], Rb[9];
      double ta = CHECK_PI * rand11();
      qa[0] = cos(0.5 * ta), qa[1 + k] = sin(0.5 * ta);
      qb[0] = cos(0.5 * (ta + th)), qb[1 + k] = sin(0.5 * (ta + th));
      phm_quat_to_rot(qa, Ra);
      phm_quat_to_rot(qb, Rb);
      double pk = it % 4 == 1 ? 0.0 : randn();
      for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++) Ha[4 * r + c] = Ra[3 * r + c], Hb[4 * r + c] = Rb[3 * r + c];
        Ha[4 * r + 3] = r == k ? 0.3 : randn();
        Hb[4 * r + 3] = r == k ? 0.3 + pk : randn();
      }
      Ha[15] = Hb[15] = 1.0;
      phm_se3_inverse(Ha, Hi);
      phm_se3_compose(Hi, Hb, H);
    }
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) R[3 * r + c] = H[4 * r + c];
    int diag = R[1] == 0.0 && R[2] == 0.0 && R[3] == 0.0 && R[5] == 0.0 && R[6] == 0.0 && R[7] == 0.0;
    CHECK(phm_so3_axis(R) == k || (diag && phm_so3_axis(R) >= 0), "axis %d, angle %g: axis %d", k,
          th, phm_so3_axis(R));
    double w[3], wg[3], x[6], xg[6], y[6], yg[6], A[9], Ag[9], L[9], Lg[9];
    phm_so3_log(R, w);
    phm_so3_log_general(R, wg);
    phm_se3_log(H, x);
    phm_se3_log_general(H, xg);
    phm_se3_log_dexp_inv(H, y, A, L);
    phm_se3_log_dexp_inv_general(H, yg, Ag, Lg);
    double sx = fmax(1.0, maxabs(6, xg)), sl = fmax(1.0, maxabs(9, Lg));
    check_worst("axis so3_log = general", maxdiff(3, w, wg), 1e-14);
    check_worst("axis se3_log = general", maxdiff(6, x, xg) / sx, 1e-14);
    check_worst("axis log_dexp_inv x = general", maxdiff(6, y, yg) / sx, 1e-14);
    check_worst("axis log_dexp_inv Ai = general", maxdiff(9, A, Ag), 1e-14);
    check_worst("axis log_dexp_inv L = general", maxdiff(9, L, Lg) / sl, 1e-14);
    double e = maxdiff(3, w, wg) + maxdiff(6, x, xg) + maxdiff(6, y, yg) + maxdiff(9, A, Ag) +
               maxdiff(9, L, Lg);
    nbits += e == 0.0;
    ntot++;
  }
  CHECK(nbits == ntot, "fast paths bit-identical to the general paths in %d of %d", nbits, ntot);
  for (int it = 0; it < 3 * N; it++) { /* quaternions (q_w, q_k e_k), not normalized */
    int k = it % 3;
    double q[4] = {rand11(), 0, 0, 0}, R[9], Rg[9];
    q[1 + k] = it % 5 == 0 ? 0.0 : it % 7 == 0 ? 1e-9 * rand11() : rand11();
    phm_quat_to_rot(q, R);
    phm_quat_to_rot_general(q, Rg);
    check_worst("axis quat_to_rot = general (bit for bit)", maxdiff(9, R, Rg), 0.0);
    CHECK(phm_so3_axis(R) >= 0, "quaternion about axis %d: R about an axis", k);
  }
  for (int it = 0; it < N; it++) { /* no axis: the general path (and the same numbers) */
    double H[16], R[9], x[6], xg[6];
    rand_pose_class(it % 4, H);
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) R[3 * r + c] = H[4 * r + c];
    if (it % 4 != 3) CHECK(phm_so3_axis(R) < 0, "a general rotation has no axis (%d)", it);
    phm_se3_log(H, x);
    phm_se3_log_general(H, xg);
    check_worst("3-D se3_log = general", maxdiff(6, x, xg), 0.0);
  }
  for (int k = 0; k < 3; k++) { /* pi about axis k: diagonal, so it is "about" every axis */
    double R[9] = {-1, 0, 0, 0, -1, 0, 0, 0, -1}, w[3], wg[3];
    R[4 * k] = 1.0;
    phm_so3_log(R, w);
    phm_so3_log_general(R, wg);
    check_worst("pi about another axis = general", maxdiff(3, w, wg), 0.0);
    check_worst("pi about another axis: |w| = pi", fabs(fabs(w[k]) - CHECK_PI), 0.0);
  }
}

CHECK_MAIN(CHECK_CASE(hat_and_vee_are_inverse_and_hat_is_the_cross_product),
           CHECK_CASE(exp_matches_expm_and_log_inverts_it),
           CHECK_CASE(adjoints_are_group_and_algebra_representations),
           CHECK_CASE(dexp_is_the_derivative_of_exp),
           CHECK_CASE(quaternions_round_trip_and_match_axis_angle),
           CHECK_CASE(dexp_inv_partials_are_its_derivative),
           CHECK_CASE(axis_fast_paths_match_the_general_paths))
