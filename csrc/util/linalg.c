/* linalg.c -- the 6x6 Cholesky factorization and the minimum-norm least-squares solve
 * (csrc/util/linalg.h). */
#include "linalg.h"

#include <stdlib.h>
#include <string.h>

#include "phm_check.h"

int phm_chol6(const double A[36], double shift, double rtol, double L[36]) {
  memset(L, 0, 36 * sizeof(double));
  for (int j = 0; j < 6; j++) {
    double s = A[7 * j] + shift;
    for (int k = 0; k < j; k++) s -= L[6 * j + k] * L[6 * j + k];
    if (!(s > rtol * A[7 * j])) return 1;
    L[7 * j] = sqrt(s);
    for (int i = j + 1; i < 6; i++) {
      double t = A[6 * i + j];
      for (int k = 0; k < j; k++) t -= L[6 * i + k] * L[6 * j + k];
      L[6 * i + j] = t / L[7 * j];
    }
  }
  return 0;
}

void phm_chol6_solve(const double L[36], double x[6]) {
  for (int i = 0; i < 6; i++) {
    double s = x[i];
    for (int k = 0; k < i; k++) s -= L[6 * i + k] * x[k];
    x[i] = s / L[6 * i + i];
  }
  for (int i = 5; i >= 0; i--) {
    double s = x[i];
    for (int k = i + 1; k < 6; k++) s -= L[6 * k + i] * x[k];
    x[i] = s / L[6 * i + i];
  }
}

/* dgelss's optimal workspace for a rows x cols problem with one right-hand side */
static int lstsq_lwork(int rows, int cols) {
  int ld = rows > cols ? rows : cols, one = 1, info = 0, rk = 0, lwork = -1;
  double wq = 0, rcond = 1e-12, a = 0, b = 0, s = 0;
  dgelss_(&rows, &cols, &one, &a, &rows, &b, &ld, &s, &rcond, &rk, &wq, &lwork, &info);
  return (int)wq + 1;
}

phm_status phm_lstsq_work_alloc(phm_lstsq_work *w, int nshape, const int *shape, phm_error *err) {
  memset(w, 0, sizeof *w);
  for (int i = 0; i < nshape; i++) {
    int r = shape[2 * i], c = shape[2 * i + 1];
    if (r == 0 || c == 0) continue;
    size_t na = (size_t)r * (size_t)c, ns = (size_t)(r < c ? r : c);
    int lw = lstsq_lwork(r, c);
    if (na > w->na) w->na = na;
    if (ns > w->ns) w->ns = ns;
    if (lw > w->lwork) w->lwork = lw;
  }
  w->a = malloc(sizeof(double) * (w->na + 1));
  w->s = malloc(sizeof(double) * (w->ns + 1));
  w->work = malloc(sizeof(double) * ((size_t)w->lwork + 1));
  if (!w->a || !w->s || !w->work) {
    phm_lstsq_work_free(w);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
  return PHM_OK;
}

void phm_lstsq_work_free(phm_lstsq_work *w) {
  free(w->a);
  free(w->s);
  free(w->work);
  memset(w, 0, sizeof *w);
}

phm_status phm_lstsq_in(int rows, int cols, double *A, double *b, int *rank, phm_lstsq_work *w,
                        phm_error *err) {
  /* row-major A (rows x cols) is column-major A^T; transpose into column-major A. */
  int ld = rows > cols ? rows : cols, one = 1, info = 0, rk = 0;
  double rcond = 1e-12;
  if (rows == 0 || cols == 0) {
    if (rank) *rank = 0;
    for (int i = 0; i < cols; i++) b[i] = 0;
    return PHM_OK;
  }
  PHM_CHECK((size_t)rows * (size_t)cols <= w->na && (size_t)(rows < cols ? rows : cols) <= w->ns &&
                lstsq_lwork(rows, cols) <= w->lwork,
            err, PHM_EINVAL, "least-squares workspace not sized for a %d x %d problem", rows, cols);
  double *Ac = w->a;
  for (int i = 0; i < rows; i++)
    for (int j = 0; j < cols; j++) Ac[(size_t)j * rows + i] = A[(size_t)i * cols + j];
  dgelss_(&rows, &cols, &one, Ac, &rows, b, &ld, w->s, &rcond, &rk, w->work, &w->lwork, &info);
  if (rank) *rank = rk;
  if (info != 0) return PHM_FAIL(err, PHM_ESINGULAR, "least-squares solve failed (LAPACK dgelss info %d)", info);
  return PHM_OK;
}

phm_status phm_lstsq(int rows, int cols, double *A, double *b, int *rank, phm_error *err) {
  phm_lstsq_work w;
  int shape[2] = {rows, cols};
  phm_status st = phm_lstsq_work_alloc(&w, 1, shape, err);
  if (!st) st = phm_lstsq_in(rows, cols, A, b, rank, &w, err);
  phm_lstsq_work_free(&w);
  return st;
}
