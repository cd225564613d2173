/* se3_dexp_partials.c -- the partial derivatives of dexp^-1 (the inverse of SE(3)'s tangent map)
 * with respect to the twist, in closed form (phm_se3_dexp_inv_partials): what the closed-form
 * tangents of the logarithms in the pair kinematics and the element need (docs/method.md section
 * 3.6). All matrices row-major, twist x = (omega, v). No allocation. */
#include "linalg.h"

#include <math.h>
/* f(tau) = sum_k a[k] tau^k and df/dtau, tau = t^2 (Horner). */
static void series2(const double *a, int n, double tau, double *f, double *df) {
  double s = a[n - 1], ds = 0.0;
  for (int k = n - 2; k >= 0; k--) {
    ds = ds * tau + s;
    s = s * tau + a[k];
  }
  *f = s;
  *df = ds;
}

/* The coefficients of dexp_x^-1 (so3_jac_inv_coeff's d, se3_dexp_Q's c1, c2, c3) and their
 * derivatives with respect to tau = |omega|^2, at t = |omega|. Below t = 1 by their Taylor series
 * in tau (entire for c1, c2, e; radius 2 pi for d: 10 terms leave < 1e-17 at t = 1), above in
 * closed form (where the cancellation of the derivatives' numerators costs < 1e-13 relative). */
static void dexp_inv_coeffs(double t, double c[4], double dc[4]) {
  double tau = t * t, e, de;
  if (t < 1.0) {
    /* d = sum_{n>=1} |B_2n| t^(2n-2) / (2n)! */
    static const double ad[10] = {1.0 / 12.0, 1.0 / 720.0, 1.0 / 30240.0, 1.0 / 1209600.0,
                                  1.0 / 47900160.0, 691.0 / 1307674368000.0,
                                  7.0 / 523069747200.0, 3617.0 / 510.0 / 20922789888000.0,
                                  43867.0 / 798.0 / 6402373705728000.0,
                                  174611.0 / 330.0 / 2432902008176640000.0};
    double a1[12], a2[12], ae[12], f3 = 1.0 / 6.0; /* f3 = 1/(2k+3)! */
    for (int k = 0; k < 12; k++) {
      double sg = k % 2 ? -1.0 : 1.0, f4 = f3 / (2 * k + 4), f5 = f4 / (2 * k + 5);
      a1[k] = sg * f3;  /* c1 = sum (-1)^k t^2k / (2k+3)! */
      a2[k] = sg * f4;  /* c2 = sum (-1)^k t^2k / (2k+4)! */
      ae[k] = -sg * f5; /* e  = sum (-1)^(k+1) t^2k / (2k+5)! */
      f3 = f5;
    }
    series2(ad, 10, tau, &c[0], &dc[0]);
    series2(a1, 12, tau, &c[1], &dc[1]);
    series2(a2, 12, tau, &c[2], &dc[2]);
    series2(ae, 12, tau, &e, &de);
  } else {
    double s = sin(t), co = cos(t), h = 0.5 * t, sh = sin(h);
    c[0] = (1.0 - h * cos(h) / sh) / tau;
    dc[0] = ((-0.5 * cos(h) / sh + h / (2.0 * sh * sh)) / tau - 2.0 * c[0] / t) / (2.0 * t);
    c[1] = (t - s) / (tau * t);
    dc[1] = ((1.0 - co) / (tau * t) - 3.0 * c[1] / t) / (2.0 * t);
    c[2] = (0.5 * tau + co - 1.0) / (tau * tau);
    dc[2] = ((t - s) / (tau * tau) - 4.0 * c[2] / t) / (2.0 * t);
    e = (t - s - tau * t / 6.0) / (tau * tau * t);
    de = ((1.0 - co - 0.5 * tau) / (tau * tau * t) - 5.0 * e / t) / (2.0 * t);
  }
  c[3] = 0.5 * (c[2] + 3.0 * e);
  dc[3] = 0.5 * (dc[2] + 3.0 * de);
}

/* The partial derivatives of the blocks of dexp_x^-1 = [[Ai, 0], [L, Ai]] with respect to x_k
 * (k = 0..5; Ai depends on omega only, so dAi[k] = 0 for k >= 3), in closed form:
 *   Ai = I - W/2 + d W^2, L = -Ai Q Ai,
 *   Q = V/2 + c1 (v w^T + w v^T - 2s I - s W) + c2 (u w^T - w u^T + s W) - 2 c3 s (w w^T - t^2 I)
 * (se3_dexp_Q; s = w.v, u = w x v), differentiated term by term with dc/dx_k = 2 w_k dc/dtau. */
void phm_se3_dexp_inv_partials(const double x[6], double dAi[6][9], double dL[6][9]) {
  const double *w = x, *v = x + 3;
  double t = phm_norm3(w), tau = t * t, c[4], dc[4];
  dexp_inv_coeffs(t, c, dc);
  double s = w[0] * v[0] + w[1] * v[1] + w[2] * v[2];
  double u[3] = {w[1] * v[2] - w[2] * v[1], w[2] * v[0] - w[0] * v[2], w[0] * v[1] - w[1] * v[0]};
  double W[9], V[9], Ai[9], Q[9], QAi[9], AiQ[9], T[9];
  phm_so3_hat(w, W);
  phm_so3_hat(v, V);
  phm_so3_poly(w, -0.5, c[0], Ai);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      int k = 3 * i + j;
      double I = i == j ? 1.0 : 0.0;
      Q[k] = 0.5 * V[k] + c[1] * (v[i] * w[j] + w[i] * v[j] - 2.0 * s * I - s * W[k]) +
             c[2] * (u[i] * w[j] - w[i] * u[j] + s * W[k]) - 2.0 * c[3] * s * (w[i] * w[j] - tau * I);
    }
  phm_mat3_mul(Q, Ai, QAi);
  phm_mat3_mul(Ai, Q, AiQ);
  for (int k = 0; k < 6; k++) {
    double dw[3] = {0, 0, 0}, dv[3] = {0, 0, 0};
    if (k < 3) dw[k] = 1.0;
    else dv[k - 3] = 1.0;
    double wd = phm_dot(w, dw, 3), g[4];
    for (int i = 0; i < 4; i++) g[i] = 2.0 * wd * dc[i];
    double ds = phm_dot(dw, v, 3) + phm_dot(w, dv, 3);
    double du[3] = {dw[1] * v[2] - dw[2] * v[1] + w[1] * dv[2] - w[2] * dv[1],
                    dw[2] * v[0] - dw[0] * v[2] + w[2] * dv[0] - w[0] * dv[2],
                    dw[0] * v[1] - dw[1] * v[0] + w[0] * dv[1] - w[1] * dv[0]};
    double dW[9], dV[9], dQ[9], *dA = dAi[k];
    phm_so3_hat(dw, dW);
    phm_so3_hat(dv, dV);
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        int q = 3 * i + j;
        double I = i == j ? 1.0 : 0.0, ww = w[i] * w[j] - tau * I;
        double dww = dw[i] * w[j] + w[i] * dw[j] - 2.0 * wd * I;
        dA[q] = -0.5 * dW[q] + g[0] * ww + c[0] * dww;
        dQ[q] = 0.5 * dV[q] +
                g[1] * (v[i] * w[j] + w[i] * v[j] - 2.0 * s * I - s * W[q]) +
                c[1] * (dv[i] * w[j] + v[i] * dw[j] + dw[i] * v[j] + w[i] * dv[j] - 2.0 * ds * I -
                        ds * W[q] - s * dW[q]) +
                g[2] * (u[i] * w[j] - w[i] * u[j] + s * W[q]) +
                c[2] * (du[i] * w[j] + u[i] * dw[j] - dw[i] * u[j] - w[i] * du[j] + ds * W[q] +
                        s * dW[q]) -
                2.0 * (g[3] * s + c[3] * ds) * ww - 2.0 * c[3] * s * dww;
      }
    /* dL = -(dAi Q Ai + Ai dQ Ai + Ai Q dAi) */
    double *l = dL[k];
    phm_mat3_mul(dA, QAi, l);
    phm_mat3_mul(Ai, dQ, T);
    phm_mat3_mul(T, Ai, T);
    for (int i = 0; i < 9; i++) l[i] += T[i];
    phm_mat3_mul(AiQ, dA, T);
    for (int i = 0; i < 9; i++) l[i] = -(l[i] + T[i]);
  }
}
