/* element.c -- the se3 beam element (docs/method.md section 4): strain from the relative pose of
 * its two nodes, eps = log(Ha^-1 Hb)/h, stress resultant sigma = K (eps - eps_hat) + D eps', and
 * the node wrenches dexp^-T sigma; also every element's stress resultants for the results. */
#include "model.h"

#include <stdint.h>
#include <string.h>

#include "linalg.h"
#include "pose.h"

/* Hab = Ha^-1 Hb (phm_inv_compose). Written as Ra^T (pb - pa) its position is 4x more accurate
 * (measured on strains of 1e-6), yet that made IDA's every-state reference of the leaf spring
 * crawl (30 -> 170 000 steps over 0.05 s, tests/test_scenes.py): IDA's Newton there is sensitive
 * to the residual's round-off (docs/integrators.md, Limits), so this form is kept. */
static void relative_pose(const double Ha[16], const double Hb[16], double Hab[16]) {
  phm_inv_compose(Ha, Hb, Hab);
}

double phm_element_energy(const phm_element_desc *e, const double Ha[16], const double Hb[16]) {
  double Hab[16], X[6], sig[6], de[6];
  relative_pose(Ha, Hb, Hab);
  phm_se3_log(Hab, X); /* phm_se3_log_dexp_inv's X, without the blocks */
  for (int i = 0; i < 6; i++) de[i] = X[i] / e->h - e->eps_hat[i];
  phm_mv6(e->K, de, sig);
  return 0.5 * e->h * phm_dot(de, sig, 6);
}

void phm_element_eval(const phm_element_desc *e, const double Ha[16], const double Hb[16],
                      const double ta[6], const double tb[6], double wa[6], double wb[6],
                      double *V, double *P, double *sigma) {
  double Hab[16], X[6], A[9], L[9], sig[6], de[6];
  relative_pose(Ha, Hb, Hab);
  /* X = log(Hab); dexp_X^-1 = [[A, 0], [L, A]], dexp_{-X}^-1 = [[A^T, 0], [L^T, A^T]] */
  phm_se3_log_dexp_inv(Hab, X, A, L);
  for (int i = 0; i < 6; i++) de[i] = X[i] / e->h - e->eps_hat[i];
  phm_mv6(e->K, de, sig);
  if (V) *V = 0.5 * e->h * phm_dot(de, sig, 6);
  double pd = 0;
  if (ta && tb) {
    double ed[6], s2[6];
    /* strain rate h eps' = dexp_{-X}^-1 t_b - dexp_X^-1 t_a */
    for (int i = 0; i < 3; i++) {
      double xaw = A[3 * i] * ta[0] + A[3 * i + 1] * ta[1] + A[3 * i + 2] * ta[2];
      double xav = L[3 * i] * ta[0] + L[3 * i + 1] * ta[1] + L[3 * i + 2] * ta[2] +
                   A[3 * i] * ta[3] + A[3 * i + 1] * ta[4] + A[3 * i + 2] * ta[5];
      double xbw = A[i] * tb[0] + A[3 + i] * tb[1] + A[6 + i] * tb[2];
      double xbv = L[i] * tb[0] + L[3 + i] * tb[1] + L[6 + i] * tb[2] +
                   A[i] * tb[3] + A[3 + i] * tb[4] + A[6 + i] * tb[5];
      ed[i] = (xbw - xaw) / e->h;
      ed[3 + i] = (xbv - xav) / e->h;
    }
    phm_mv6(e->D, ed, s2);
    pd = e->h * phm_dot(ed, s2, 6);
    for (int i = 0; i < 6; i++) sig[i] += s2[i];
  }
  if (P) *P = pd;
  if (sigma) memcpy(sigma, sig, sizeof sig);
  /* w_a = dexp_X^-T sigma, w_b = -dexp_{-X}^-T sigma */
  for (int i = 0; i < 3; i++) {
    wa[i] = A[i] * sig[0] + A[3 + i] * sig[1] + A[6 + i] * sig[2] +
            L[i] * sig[3] + L[3 + i] * sig[4] + L[6 + i] * sig[5];
    wa[3 + i] = A[i] * sig[3] + A[3 + i] * sig[4] + A[6 + i] * sig[5];
    wb[i] = -(A[3 * i] * sig[0] + A[3 * i + 1] * sig[1] + A[3 * i + 2] * sig[2] +
              L[3 * i] * sig[3] + L[3 * i + 1] * sig[4] + L[3 * i + 2] * sig[5]);
    wb[3 + i] = -(A[3 * i] * sig[3] + A[3 * i + 1] * sig[4] + A[3 * i + 2] * sig[5]);
  }
}

/* dexp_X^-1 = [[A, 0], [L, A]] (6x6, row-major) from its blocks; tr: the transpose of each block,
 * dexp_{-X}^-1 (csrc/util/se3.c, phm_se3_log_dexp_inv). */
static void blocks6(const double A[9], const double L[9], int tr, double M[36]) {
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      int ij = tr ? 3 * j + i : 3 * i + j;
      M[6 * i + j] = M[6 * (3 + i) + 3 + j] = A[ij];
      M[6 * (3 + i) + j] = L[ij];
      M[6 * i + 3 + j] = 0.0;
    }
}

/* The damping stress of a strain rate: rate = (B tb - A ta)/h (6x6 row-major A, B), sig += D rate
 * (the tangent's stress, and each of its derivatives with dA_k, dB_k). */
static void damping_add(const phm_element_desc *e, const double B[36], const double A[36],
                        const double tb[6], const double ta[6], double rate[6], double sig[6]) {
  double xb[6], xa[6], s2[6];
  phm_mv6(B, tb, xb);
  phm_mv6(A, ta, xa);
  for (int i = 0; i < 6; i++) rate[i] = (xb[i] - xa[i]) / e->h;
  phm_mv6(e->D, rate, s2);
  for (int i = 0; i < 6; i++) sig[i] += s2[i];
}

/* The fused evaluation (docs/method.md section 4.2, "Tangent"): with A = dexp_X^-1, B = dexp_{-X}^-1,
 * a perturbation Ha -> Ha exp(da), Hb -> Hb exp(db) moves X by dX = B db - A da; the wrenches
 * wa = A^T sigma, wb = -B^T sigma, with sigma = K (X/h - eps_hat) + D (B tb - A ta)/h, vary by
 *   d[wa; wb]/dX_k = [dA_k^T sigma + A^T dsigma_k; -(dB_k^T sigma + B^T dsigma_k)],
 *   dsigma_k = K e_k/h + D (dB_k tb - dA_k ta)/h   (geometric + material + damping parts),
 * dA_k, dB_k from phm_se3_dexp_inv_partials (dB_k: the transposed blocks). Then
 * Kx = [dw/dX (-A), dw/dX B] and Ct = [P (-D A/h), P (D B/h)] with P = [A^T; -B^T]. */
void phm_element_tangent(const phm_element_desc *e, const double Ha[16], const double Hb[16],
                         const double ta[6], const double tb[6], double wa[6], double wb[6],
                         double Kx[144], double Ct[144]) {
  double Hab[16], X[6], Ab[9], Lb[9], A[36], B[36], sig[6], de[6];
  double dAi[6][9], dL[6][9], JX[72], ed[6] = {0};
  int damp = ta && tb;
  relative_pose(Ha, Hb, Hab);
  phm_se3_log_dexp_inv(Hab, X, Ab, Lb);
  blocks6(Ab, Lb, 0, A);
  blocks6(Ab, Lb, 1, B);
  for (int i = 0; i < 6; i++) de[i] = X[i] / e->h - e->eps_hat[i];
  phm_mv6(e->K, de, sig);
  if (damp) damping_add(e, B, A, tb, ta, ed, sig);
  phm_mtv6(A, sig, wa);
  phm_mtv6(B, sig, wb);
  for (int i = 0; i < 6; i++) wb[i] = -wb[i];
  phm_se3_dexp_inv_partials(X, dAi, dL);
  for (int k = 0; k < 6; k++) {
    double dA[36], dB[36], ds[6], t1[6], t2[6];
    blocks6(dAi[k], dL[k], 0, dA);
    blocks6(dAi[k], dL[k], 1, dB);
    for (int i = 0; i < 6; i++) ds[i] = e->K[6 * i + k] / e->h;
    if (damp) {
      double dd[6];
      damping_add(e, dB, dA, tb, ta, dd, ds);
    }
    phm_mtv6(dA, sig, t1);
    phm_mtv6(A, ds, t2);
    for (int i = 0; i < 6; i++) JX[6 * i + k] = t1[i] + t2[i];
    phm_mtv6(dB, sig, t1);
    phm_mtv6(B, ds, t2);
    for (int i = 0; i < 6; i++) JX[6 * (6 + i) + k] = -(t1[i] + t2[i]);
  }
  phm_mul_ends(JX, 12, A, B, Kx);
  if (!Ct) return;
  if (!damp) {
    memset(Ct, 0, 144 * sizeof(double));
    return;
  }
  double DA[36], DB[36]; /* D A / h, D B / h */
  for (int i = 0; i < 6; i++)
    for (int j = 0; j < 6; j++) {
      double sa = 0, sb = 0;
      for (int k = 0; k < 6; k++) {
        sa += e->D[6 * i + k] * A[6 * k + j];
        sb += e->D[6 * i + k] * B[6 * k + j];
      }
      DA[6 * i + j] = sa / e->h;
      DB[6 * i + j] = sb / e->h;
    }
  for (int i = 0; i < 6; i++)
    for (int j = 0; j < 6; j++) {
      double aa = 0, ab = 0, ba = 0, bb = 0; /* rows of P: A^T (node a), -B^T (node b) */
      for (int k = 0; k < 6; k++) {
        aa += A[6 * k + i] * DA[6 * k + j];
        ab += A[6 * k + i] * DB[6 * k + j];
        ba += B[6 * k + i] * DA[6 * k + j];
        bb += B[6 * k + i] * DB[6 * k + j];
      }
      Ct[12 * i + j] = -aa;
      Ct[12 * i + 6 + j] = ab;
      Ct[12 * (6 + i) + j] = ba;
      Ct[12 * (6 + i) + 6 + j] = -bb;
    }
}

void phm_model_stress_resultants(const phm_model *m, const double *H, const double *t, double *sigma) {
  for (int ie = 0; ie < m->ne; ie++) {
    const phm_element_desc *e = &m->el[ie];
    double wa[6], wb[6];
    phm_element_eval(e, H + 16 * e->a, H + 16 * e->b, t ? t + 6 * e->a : NULL,
                     t ? t + 6 * e->b : NULL, wa, wb, NULL, NULL, sigma + 6 * ie);
  }
}

/* ---------------------------------------------------------------- mass (docs/method.md section 4.2, "Mass") */
/* 6-point Gauss-Legendre on [0, 1]: exact for the straight element's integrand (degree 4 in xi)
 * and, for a curved one, converged to round-off while an element turns by less than ~1 rad. */
static const double GAUSS_X[6] = {0.033765242898423987, 0.16939530676686776, 0.38069040695840156,
                                  0.61930959304159845, 0.83060469323313224, 0.96623475710157601};
static const double GAUSS_W[6] = {0.085662246189585178, 0.18038078652406930, 0.23395696728634552,
                                  0.23395696728634552, 0.18038078652406930, 0.085662246189585178};

/* Mc += w T^T Ms T for T (6 x 12, row-major). */
static void add_gram(double Mc[144], const double T[72], const double Ms[36], double w) {
  double MT[72];
  for (int i = 0; i < 6; i++)
    for (int j = 0; j < 12; j++) {
      double s = 0;
      for (int k = 0; k < 6; k++) s += Ms[6 * i + k] * T[12 * k + j];
      MT[12 * i + j] = s;
    }
  for (int i = 0; i < 12; i++)
    for (int j = 0; j < 12; j++) {
      double s = 0;
      for (int k = 0; k < 6; k++) s += T[12 * k + i] * MT[12 * k + j];
      Mc[12 * i + j] += w * s;
    }
}

/* The section at xi in [0, 1] of the element's helix H(xi) = H_a exp(xi X) moves with the body
 * twist t(xi) = A_a(xi) t_a + A_b(xi) t_b: from X' = dexp_{-X}^-1 (t_b - Ad_{exp(-X)} t_a) =
 * dexp_{-X}^-1 t_b - dexp_X^-1 t_a, t(xi) = Ad_{exp(-xi X)} t_a + xi dexp_{-xi X} X'. At the
 * unstressed shape X = h eps_hat this is constant; for a straight element it interpolates the
 * rotations linearly and the displacements with the cubic term (h/2) xi (1 - xi) of the rotations'
 * difference (docs/mass_matrix_study.md, "d4 helix"). */
void phm_element_mass(double h, const double Ms[36], const double eps_hat[6], double Mc[144]) {
  double X[6], mX[6], Dp[36], Dm[36];
  for (int i = 0; i < 6; i++) X[i] = h * eps_hat[i], mX[i] = -X[i];
  phm_se3_dexp_inv(X, Dp);
  phm_se3_dexp_inv(mX, Dm);
  memset(Mc, 0, sizeof(double) * 144);
  for (int g = 0; g < 6; g++) {
    double xi = GAUSS_X[g], Y[6], E[16], AdE[36], dY[36], T[72];
    for (int i = 0; i < 6; i++) Y[i] = -xi * X[i];
    phm_se3_exp(Y, E);
    phm_se3_Ad(E, AdE);
    phm_se3_dexp(Y, dY);
    phm_mul_ends(dY, 6, Dp, Dm, T); /* [-dexp_{-xi X} dexp_X^-1, dexp_{-xi X} dexp_{-X}^-1] */
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 6; j++) {
        T[12 * i + j] = AdE[6 * i + j] + xi * T[12 * i + j];
        T[12 * i + 6 + j] *= xi;
      }
    add_gram(Mc, T, Ms, h * GAUSS_W[g]);
  }
  /* + (h/12) d^T Ms d, d = t_b - Ad_{R0^T} t_a (t_a's components in b's axes, R0 the rotation
   * of exp(X)): half the difference of lumped and consistent on the transported velocity
   * difference, which cancels the helix's leading dispersion error; - the nodes' h/2 Ms */
  double E0[16], T[72] = {0};
  phm_se3_exp(X, E0);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double r = E0[4 * j + i]; /* R0^T */
      T[12 * i + j] = T[12 * (3 + i) + 3 + j] = -r;
    }
  for (int i = 0; i < 6; i++) T[12 * i + 6 + i] = 1.0;
  add_gram(Mc, T, Ms, h / 12.0);
  for (int i = 0; i < 6; i++)
    for (int j = 0; j < 6; j++) {
      Mc[12 * i + j] -= 0.5 * h * Ms[6 * i + j];
      Mc[12 * (6 + i) + 6 + j] -= 0.5 * h * Ms[6 * i + j];
    }
  for (int i = 0; i < 12; i++) /* symmetric to the last bit */
    for (int j = 0; j < i; j++) Mc[12 * i + j] = Mc[12 * j + i] = 0.5 * (Mc[12 * i + j] + Mc[12 * j + i]);
}

/* f = [ (Mc t')_a - ad*_{t_a} (Mc t)_a ; (Mc t')_b - ad*_{t_b} (Mc t)_b ], t = [t_a; t_b]: the mass
 * coupling's terms in its nodes' momentum balances (the Euler-Poincare equations of the kinetic
 * energy 1/2 t^T Mc t, left-invariant on SE(3) x SE(3), whose power t . f is d/dt of that energy).
 * Kt (may be NULL) = df/dt + cj df/dt'. */
void phm_mass_rows(const double Mc[144], unsigned short rows[12]) {
  for (int i = 0; i < 12; i++) {
    rows[i] = 0;
    for (int j = 0; j < 12; j++)
      if (Mc[12 * i + j] != 0.0) rows[i] |= (unsigned short)(1u << j);
  }
}

/* The lowest set bit of b != 0 (its index), and b without it. */
static inline int pop_low(unsigned *b) {
#if defined(__GNUC__)
  int j = __builtin_ctz(*b);
#else
  int j = 0;
  while (!(*b >> j & 1u)) j++;
#endif
  *b &= *b - 1u;
  return j;
}

/* The bits j of the j with t[j] or s[j] nonzero (12; a NaN is nonzero): a double is zero iff its
 * bits without the sign bit are, so one integer test serves both (24 floating-point comparisons
 * were 15 % of a planar element's phm_element_inertia). */
static inline unsigned nonzero_either(const double t[12], const double s[12]) {
  unsigned b = 0;
  for (int j = 0; j < 12; j++) {
    uint64_t x, y;
    memcpy(&x, t + j, sizeof x);
    memcpy(&y, s + j, sizeof y);
    b |= (unsigned)(((x | y) << 1) != 0) << j;
  }
  return b;
}

void phm_element_inertia(const double Mc[144], const unsigned short rows[12], const double ta[6],
                         const double tb[6], const double dta[6], const double dtb[6], double cj,
                         double f[12], double Kt[144]) {
  double t[12], td[12], u[12], fd[12];
  memcpy(t, ta, 6 * sizeof(double));
  memcpy(t + 6, tb, 6 * sizeof(double));
  memcpy(td, dta, 6 * sizeof(double));
  memcpy(td + 6, dtb, 6 * sizeof(double));
  /* Mc t and Mc t' over the products whose two factors are nonzero only: Mc's nonzeros (a
   * straight element's: 40 of 144) in the columns of the twists' nonzero entries (a planar
   * scene's out-of-plane components are zero) -- 20 of 144 for a planar straight element. The
   * same sums: a sum from +0 is never -0 in round-to-nearest, so adding a zero product (of
   * finite factors) leaves it as it is. */
  unsigned tz = nonzero_either(t, td);
  for (int i = 0; i < 12; i++) {
    double s = 0, sd = 0;
    for (unsigned b = rows[i] & tz; b;) {
      int j = pop_low(&b);
      s += Mc[12 * i + j] * t[j], sd += Mc[12 * i + j] * td[j];
    }
    u[i] = s;
    fd[i] = sd;
  }
  for (int s = 0; s < 2; s++) {
    double a[6];
    phm_ad_dual_apply(t + 6 * s, u + 6 * s, a);
    for (int i = 0; i < 6; i++) f[6 * s + i] = fd[6 * s + i] - a[i];
  }
  if (!Kt) return;
  for (int s = 0; s < 2; s++) {
    const double *ts = t + 6 * s, *us = u + 6 * s;
    for (int j = 0; j < 12; j++) {
      double col[6], a[6];
      for (int i = 0; i < 6; i++) col[i] = Mc[12 * (6 * s + i) + j];
      phm_ad_dual_apply(ts, col, a); /* ad*_{t_s} Mc e_j */
      for (int i = 0; i < 6; i++) Kt[12 * (6 * s + i) + j] = cj * col[i] - a[i];
    }
    for (int j = 0; j < 6; j++) { /* ad*_{e_j} u_s: the twist's own slot */
      double ej[6] = {0}, a[6];
      ej[j] = 1.0;
      phm_ad_dual_apply(ej, us, a);
      for (int i = 0; i < 6; i++) Kt[12 * (6 * s + i) + 6 * s + j] -= a[i];
    }
  }
}

/* 1/2 t^T Mc t, t = [t_a; t_b]. */
double phm_element_kinetic(const double Mc[144], const unsigned short rows[12], const double ta[6],
                           const double tb[6]) {
  double t[12], K = 0;
  memcpy(t, ta, 6 * sizeof(double));
  memcpy(t + 6, tb, 6 * sizeof(double));
  unsigned tz = nonzero_either(t, t); /* the nonzero products only: the same sum (phm_element_inertia) */
  for (unsigned a = tz; a;) {
    int i = pop_low(&a);
    for (unsigned b = rows[i] & tz; b;) {
      int j = pop_low(&b);
      K += t[i] * Mc[12 * i + j] * t[j];
    }
  }
  return 0.5 * K;
}
