/* element.c -- the se3 beam element (docs/method.md section 4): strain from the relative pose of
 * its two nodes, eps = log(Ha^-1 Hb)/h, stress resultant sigma = K (eps - eps_hat) + D eps', and
 * the node wrenches dexp^-T sigma; also every element's stress resultants for the results. */
#include "model.h"

#include <string.h>

#include "linalg.h"

void phm_element_eval(const phm_element_desc *e, const double Ha[16], const double Hb[16],
                      const double ta[6], const double tb[6], double wa[6], double wb[6],
                      double *V, double *P, double *sigma) {
  double Hai[16], Hab[16], X[6], A[9], L[9], sig[6], de[6];
  /* Hab = Ha^-1 Hb. Written as Ra^T (pb - pa) its position is 4x more accurate (measured on
   * strains of 1e-6), yet that made IDA's every-state reference of the leaf spring crawl (30 ->
   * 170 000 steps over 0.05 s, tests/test_scenes.py): IDA's Newton there is sensitive to the
   * residual's round-off (docs/integrators.md, Limits), so this form is kept. */
  phm_se3_inverse(Ha, Hai);
  phm_se3_compose(Hai, Hb, Hab);
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
  double Hai[16], Hab[16], X[6], Ab[9], Lb[9], A[36], B[36], sig[6], de[6];
  double dAi[6][9], dL[6][9], JX[72], ed[6] = {0};
  int damp = ta && tb;
  phm_se3_inverse(Ha, Hai);
  phm_se3_compose(Hai, Hb, Hab);
  phm_se3_log_dexp_inv(Hab, X, Ab, Lb);
  blocks6(Ab, Lb, 0, A);
  blocks6(Ab, Lb, 1, B);
  for (int i = 0; i < 6; i++) de[i] = X[i] / e->h - e->eps_hat[i];
  phm_mv6(e->K, de, sig);
  if (damp) {
    double xb[6], xa[6], s2[6];
    phm_mv6(B, tb, xb);
    phm_mv6(A, ta, xa);
    for (int i = 0; i < 6; i++) ed[i] = (xb[i] - xa[i]) / e->h;
    phm_mv6(e->D, ed, s2);
    for (int i = 0; i < 6; i++) sig[i] += s2[i];
  }
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
      double xb[6], xa[6], s2[6], dd[6];
      phm_mv6(dB, tb, xb);
      phm_mv6(dA, ta, xa);
      for (int i = 0; i < 6; i++) dd[i] = (xb[i] - xa[i]) / e->h;
      phm_mv6(e->D, dd, s2);
      for (int i = 0; i < 6; i++) ds[i] += s2[i];
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
