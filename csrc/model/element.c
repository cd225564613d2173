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

void phm_model_stress_resultants(const phm_model *m, const double *H, const double *t, double *sigma) {
  for (int ie = 0; ie < m->ne; ie++) {
    const phm_element_desc *e = &m->el[ie];
    double wa[6], wb[6];
    phm_element_eval(e, H + 16 * e->a, H + 16 * e->b, t ? t + 6 * e->a : NULL,
                     t ? t + 6 * e->b : NULL, wa, wb, NULL, NULL, sigma + 6 * ie);
  }
}
