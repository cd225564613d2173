/* linalg.h -- the small dense linear algebra of the core (6-vectors, 6x6 row-major blocks), the
 * LAPACK routines it calls (declared once here) and finiteness tests. */
#ifndef PHM_LINALG_H
#define PHM_LINALG_H

#include <math.h>
#include <stddef.h>

#include "phmech.h"

#define PHM_PI 3.14159265358979323846

static inline void phm_mv6(const double A[36], const double x[6], double y[6]) { /* y = A x */
  for (int i = 0; i < 6; i++) {
    double s = 0;
    for (int j = 0; j < 6; j++) s += A[6 * i + j] * x[j];
    y[i] = s;
  }
}

static inline void phm_mtv6(const double A[36], const double x[6], double y[6]) { /* y = A^T x */
  for (int i = 0; i < 6; i++) {
    double s = 0;
    for (int j = 0; j < 6; j++) s += A[6 * j + i] * x[j];
    y[i] = s;
  }
}

/* out (rows x 12) = D [-A, B] (D: rows x 6, A and B 6x6, all row-major): a derivative in a
 * relative perturbation, D (x) with x = B db - A da, carried to the two ends' (da, db). */
static inline void phm_mul_ends(const double *D, int rows, const double A[36], const double B[36],
                                double *out) {
  for (int r = 0; r < rows; r++)
    for (int j = 0; j < 6; j++) {
      double sa = 0, sb = 0;
      for (int l = 0; l < 6; l++) {
        sa += D[6 * r + l] * A[6 * l + j];
        sb += D[6 * r + l] * B[6 * l + j];
      }
      out[12 * r + j] = -sa;
      out[12 * r + 6 + j] = sb;
    }
}

static inline double phm_dot(const double *a, const double *b, int n) {
  double s = 0;
  for (int i = 0; i < n; i++) s += a[i] * b[i];
  return s;
}

/* The first non-finite entry of x[0..n), or -1. */
static inline long phm_first_nonfinite(const double *x, size_t n) {
  for (size_t i = 0; i < n; i++)
    if (!isfinite(x[i])) return (long)i;
  return -1;
}
static inline int phm_all_finite(const double *x, size_t n) { return phm_first_nonfinite(x, n) < 0; }

/* C = A B (3x3 row-major; C may be A or B). */
static inline void phm_mat3_mul(const double A[9], const double B[9], double C[9]) {
  double T[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      T[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
  for (int e = 0; e < 9; e++) C[e] = T[e];
}

static inline double phm_norm3(const double w[3]) { return sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]); }

/* M = I + alpha W + beta W^2 with W = hat(w) (se3.c). */
void phm_so3_poly(const double w[3], double alpha, double beta, double M[9]);

/* The fast paths at rotations about a coordinate axis e_k (se3.c, quat.c): PHM_AXIS_INLINE
 * functions take k first, and PHM_AXIS_CALL calls one with k a constant, so that each of the
 * three is its own specialization. */
#if defined(__GNUC__)
#define PHM_AXIS_INLINE static inline __attribute__((always_inline))
#else
#define PHM_AXIS_INLINE static inline
#endif

/* fn(k, ...) with k a constant 0, 1 or 2: each call its own specialization of the inlined fn. */
#define PHM_AXIS_CALL(k, fn, ...)   \
  do {                              \
    switch (k) {                    \
    case 0: fn(0, __VA_ARGS__); break; \
    case 1: fn(1, __VA_ARGS__); break; \
    default: fn(2, __VA_ARGS__); break; \
    }                               \
  } while (0)


/* The general paths of se3.c's logarithms and quat.c's quaternion conversion, which take fast paths at
 * rotations about a coordinate axis (a planar scene's: the same numbers; tests/c/test_se3.c
 * compares the two). */
void phm_so3_log_general(const double R[9], double w[3]);
void phm_se3_log_general(const double H[16], double x[6]);
void phm_se3_log_dexp_inv_general(const double H[16], double x[6], double Ai[9], double L[9]);
int phm_so3_axis(const double R[9]); /* the axis k those take (R's row and column k are e_k), or -1 */
void phm_quat_to_rot_general(const double q[4], double R[9]); /* and phm_quat_to_rot's */

/* Cholesky factor L (lower, row-major) of the symmetric 6x6 A + shift I; 0 if every pivot is
 * above rtol times its diagonal entry of A (positive definite), 1 otherwise. */
int phm_chol6(const double A[36], double shift, double rtol, double L[36]);
/* x = A^-1 x with A = L L^T (phm_chol6). */
void phm_chol6_solve(const double L[36], double x[6]);
/* Min-norm least squares A x = b (A: rows x cols, row-major, overwritten); b has max(rows, cols)
 * entries and holds x on return; rank in *rank (may be NULL). Allocates: set-up code only. */
phm_status phm_lstsq(int rows, int cols, double *A, double *b, int *rank, phm_error *err);

/* The memory of LAPACK's dgelss for a set of problem shapes, allocated once so that the solves
 * allocate nothing (the consistent initial values at every breakpoint, csrc/dae/initial.c). */
typedef struct {
  double *a, *s, *work; /* A transposed (column-major), singular values, dgelss's workspace */
  size_t na, ns;        /* their sizes                                                      */
  int lwork;            /* the largest optimal workspace of LAPACK's queries for the shapes  */
} phm_lstsq_work;
/* Size w for the nshape problems (rows, cols) = (shape[2 i], shape[2 i + 1]): a workspace
 * query per shape. */
phm_status phm_lstsq_work_alloc(phm_lstsq_work *w, int nshape, const int *shape, phm_error *err);
void phm_lstsq_work_free(phm_lstsq_work *w);
/* phm_lstsq in w (sized for this shape by phm_lstsq_work_alloc): no allocation. dgelss takes
 * the same path with any workspace at least its optimal one (its blocked steps shrink the
 * block only below that), so the numbers are phm_lstsq's. */
phm_status phm_lstsq_in(int rows, int cols, double *A, double *b, int *rank, phm_lstsq_work *w,
                        phm_error *err);

/* LAPACK (Fortran calling convention) */
void dgelss_(const int *m, const int *n, const int *nrhs, double *a, const int *lda, double *b,
             const int *ldb, double *s, const double *rcond, int *rank, double *work,
             const int *lwork, int *info);
void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n, double *a,
             const int *lda, double *s, double *u, const int *ldu, double *vt, const int *ldvt,
             double *work, const int *lwork, int *info);
void dsygvx_(const int *itype, const char *jobz, const char *range, const char *uplo, const int *n,
             double *a, const int *lda, double *b, const int *ldb, const double *vl,
             const double *vu, const int *il, const int *iu, const double *abstol, int *m,
             double *w, double *z, const int *ldz, double *work, const int *lwork, int *iwork,
             int *ifail, int *info);
double dlamch_(const char *cmach);
void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda, double *w,
            double *work, const int *lwork, int *info);

#endif
