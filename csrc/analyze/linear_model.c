/* linear_model.c -- the linear port-Hamiltonian model (docs/method.md section 7.4): the reduced
 * K, D, M of reduce.c and the input matrix of the ports' generalized forces. */
#include "analyze.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"

/* ---------------------------------------------------------------- linear port-Hamiltonian model */
int phm_linear_port_columns(const phm_model *m, int nports, const phm_linear_port *ports) {
  int n = 0;
  for (int i = 0; i < nports; i++)
    n += ports[i].kind == PHM_PORT_PAIR ? (ports[i].index >= 0 && ports[i].index < m->np ? m->pair_k[ports[i].index] : 0)
         : ports[i].kind == PHM_PORT_LOAD ? 1 : 6;
  return n;
}

phm_status phm_linear_model(const phm_model *m, const double *poses, const double *lambda,
                            double time, int nports, const phm_linear_port *ports, int *nr,
                            double *K, double *D, double *M, double *Z, double *B,
                            phm_error *err) {
  phm_error_clear(err);
  if (!m || !nr || !K || !D || !M || (nports > 0 && (!ports || !B)))
    return PHM_FAIL(err, PHM_EINVAL, "phm_linear_model: NULL argument");
  PHM_CHECK(nports >= 0, err, PHM_EINVAL, "phm_linear_model: nports must be >= 0 (got %d)", nports);
  for (int i = 0; i < nports; i++) {
    const phm_linear_port *p = &ports[i];
    int n = p->kind == PHM_PORT_PAIR ? m->np : p->kind == PHM_PORT_LOAD ? m->nl : p->kind == PHM_PORT_FRAME ? m->nc : -1;
    PHM_CHECK(n >= 0, err, PHM_EINVAL, "linear model: port %d has unknown kind %d (0 pair, 1 load, "
              "2 frame)", i, p->kind);
    PHM_CHECK(p->index >= 0 && p->index < n, err, PHM_EINVAL, "linear model: port %d (%s) index %d "
              "out of range [0, %d)", i, p->kind == PHM_PORT_PAIR ? "pair" : p->kind == PHM_PORT_LOAD
              ? "load" : "carrier", p->index, n);
    if (p->kind == PHM_PORT_FRAME)
      PHM_CHECK(phm_all_finite(p->T, 16), err, PHM_EINVAL, "linear model: port %d: non-finite "
                "frame offset", i);
  }
  *nr = 0;
  int nc = m->nc, n6 = 6 * nc, ncol = phm_linear_port_columns(m, nports, ports);
  phm_status st;
  lin_red_t R;
  memset(&R, 0, sizeof R);
  double *F = calloc((size_t)n6 * (ncol + 1), sizeof(double)), *y = malloc(sizeof(double) * (size_t)n6);
  if (!F || !y) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  if ((st = lin_red_blocks(&R, m, poses, lambda, time, err)) || (st = lin_red_reduce(&R, m, err)))
    goto done;
  int n = R.nr;
  memcpy(K, R.Kr, sizeof(double) * (size_t)n * n);
  memcpy(D, R.Dr, sizeof(double) * (size_t)n * n);
  memcpy(M, R.Mr, sizeof(double) * (size_t)n * n);
  if (Z)
    for (int a = 0; a < n; a++) {
      for (int b = 0; b < n; b++) y[b] = a == b;
      lin_red_expand(&R, nc, y, F);                 /* column a of Z, F as scratch */
      for (int i = 0; i < n6; i++) Z[(size_t)i * n + a] = F[i];
    }
  /* the ports' generalized forces per unit input: F (ncol columns of 6 nc), then B = Z^T F */
  memset(F, 0, sizeof(double) * (size_t)n6 * (ncol + 1));
  double tref = phm_model_tref(m, time, NULL);
  int j = 0;
  for (int i = 0; i < nports; i++) {
    const phm_linear_port *p = &ports[i];
    if (p->kind == PHM_PORT_PAIR) {
      int ip = p->index, k = m->pair_k[ip];
      const phm_pair_desc *pr = &m->pair[ip];
      phm_pair_data pd;
      phm_pair_evaluate(m, ip, pr->a >= 0 ? R.H + 16 * pr->a : NULL, pr->b >= 0 ? R.H + 16 * pr->b : NULL,
                        NULL, NULL, NULL, time, tref, PHM_PAIR_JOINT, &pd);
      for (int c = 0; c < k; c++, j++) {
        double u[6] = {0};
        u[c] = 1.0;
        phm_pair_effort_wrench(m, ip, &pd, u, F + (size_t)j * n6);
      }
    } else if (p->kind == PHM_PORT_LOAD) {
      double w[6], wre[6];
      phm_load_wrench(m, p->index, R.H, 1.0, F + (size_t)j * n6, w, wre);
      j++;
    } else { /* a wrench (tau, f) in the frame's axes at its origin: Ad_{T^-1}^T w on the carrier */
      double Ti[16], A[36];
      phm_se3_inverse(p->T, Ti);
      phm_se3_Ad(Ti, A);
      for (int c = 0; c < 6; c++, j++)
        for (int r = 0; r < 6; r++) F[(size_t)j * n6 + 6 * p->index + r] = A[6 * c + r];
    }
  }
  for (int c = 0; c < ncol; c++) {
    lin_red_project(&R, nc, F + (size_t)c * n6, y);
    for (int a = 0; a < n; a++) B[(size_t)a * ncol + c] = y[a];
  }
  if (!phm_all_finite(B, (size_t)n * ncol)) {
    st = PHM_FAIL(err, PHM_ESOLVER, "linear model: non-finite input matrix");
    goto done;
  }
  *nr = n;
done:
  lin_red_free(&R);
  free(F); free(y);
  return st;
}
