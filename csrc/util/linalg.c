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

phm_status phm_lstsq(int rows, int cols, double *A, double *b, int *rank, phm_error *err) {
  /* row-major A (rows x cols) is column-major A^T; transpose into column-major A. */
  int ld = rows > cols ? rows : cols, one = 1, info = 0, rk = 0, lwork = -1;
  if (rows == 0 || cols == 0) {
    if (rank) *rank = 0;
    for (int i = 0; i < cols; i++) b[i] = 0;
    return PHM_OK;
  }
  double *Ac = malloc(sizeof(double) * (size_t)rows * (size_t)cols);
  double *s = malloc(sizeof(double) * (size_t)(rows < cols ? rows : cols));
  double wq, rcond = 1e-12;
  if (!Ac || !s) {
    free(Ac);
    free(s);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
  for (int i = 0; i < rows; i++)
    for (int j = 0; j < cols; j++) Ac[(size_t)j * rows + i] = A[(size_t)i * cols + j];
  dgelss_(&rows, &cols, &one, Ac, &rows, b, &ld, s, &rcond, &rk, &wq, &lwork, &info);
  lwork = (int)wq + 1;
  double *work = malloc(sizeof(double) * (size_t)lwork);
  if (!work) {
    free(Ac);
    free(s);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
  dgelss_(&rows, &cols, &one, Ac, &rows, b, &ld, s, &rcond, &rk, work, &lwork, &info);
  free(work);
  free(Ac);
  free(s);
  if (rank) *rank = rk;
  if (info != 0) return PHM_FAIL(err, PHM_ESINGULAR, "least-squares solve failed (LAPACK dgelss info %d)", info);
  return PHM_OK;
}
