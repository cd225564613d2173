/* test_linalg.c -- csrc/util/linalg.c and the inline helpers of csrc/util/linalg.h: phm_chol6
 * against the reconstruction L L^T, phm_chol6_solve against the residual, the refusal of
 * indefinite and singular matrices, and phm_lstsq's minimum-norm solutions of full-rank and
 * rank-deficient systems against solutions worked out by hand. */
#include "check.h"
#include "linalg.h"

static void cholesky_reconstructs_the_matrix_and_solves(void) {
  for (int trial = 0; trial < 50; trial++) {
    double A[36], L[36], LLt[36], shift = trial % 2 ? rand01() : 0.0;
    rand_spd6(A, trial % 5 == 0 ? 1e-3 : 1.0);
    int fail = phm_chol6(A, shift, 1e-12, L);
    CHECK(fail == 0, "phm_chol6 factors a positive definite matrix (returned %d)", fail);
    double upper = 0, minpiv = INFINITY;
    for (int i = 0; i < 6; i++) {
      minpiv = fmin(minpiv, L[7 * i]);
      for (int j = i + 1; j < 6; j++) upper = fmax(upper, fabs(L[6 * i + j]));
    }
    check("chol6: L is lower triangular with a positive diagonal", upper + (minpiv > 0 ? 0 : 1), 0.0);
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 6; j++) {
        LLt[6 * i + j] = -(i == j ? shift : 0.0);
        for (int k = 0; k < 6; k++) LLt[6 * i + j] += L[6 * i + k] * L[6 * j + k];
      }
    check("chol6: L L^T = A + shift I", maxdiff(36, LLt, A) / maxabs(36, A), 1e-14);
    double x[6], b[6], r[6];
    for (int i = 0; i < 6; i++) x[i] = b[i] = rand11();
    phm_chol6_solve(L, x);
    for (int i = 0; i < 6; i++) {
      r[i] = -b[i] + shift * x[i];
      for (int j = 0; j < 6; j++) r[i] += A[6 * i + j] * x[j];
    }
    check("chol6_solve: (A + shift I) x = b (residual / |A| |x|)", maxabs(6, r) / (maxabs(36, A) * maxabs(6, x)), 1e-13);
  }
}

static void cholesky_refuses_indefinite_and_singular_matrices(void) {
  double A[36], L[36], v[6];
  rand_spd6(A, 1.0);
  A[7 * 3] = -A[7 * 3]; /* a negative diagonal entry */
  CHECK(phm_chol6(A, 0.0, 0.0, L) == 1, "chol6 refuses a negative pivot");
  memset(A, 0, sizeof A);
  for (int i = 0; i < 6; i++) v[i] = rand11();
  for (int i = 0; i < 6; i++)
    for (int j = 0; j < 6; j++) A[6 * i + j] = v[i] * v[j]; /* rank 1 */
  CHECK(phm_chol6(A, 0.0, 1e-12, L) == 1, "chol6 refuses a rank-1 matrix (pivot below rtol)");
  CHECK(phm_chol6(A, 1e-3, 1e-12, L) == 0, "chol6 factors the same matrix shifted by 1e-3 I");
  eye(6, A);
  A[7 * 5] = 1e-14;
  CHECK(phm_chol6(A, 0.0, 1e-12, L) == 0, "chol6: rtol is relative to each diagonal entry");
  A[6 * 5 + 4] = A[6 * 4 + 5] = 1.0; /* [[1, 1], [1, 1e-14]]: indefinite */
  CHECK(phm_chol6(A, 0.0, 0.0, L) == 1, "chol6 refuses an indefinite matrix with positive diagonal");
}

/* A x = b in the least-squares sense, the minimum-norm x among the minimizers. */
static void lstsq_returns_the_minimum_norm_least_squares_solution(void) {
  phm_error err;
  int rank = -1;
  { /* overdetermined, full rank: normal equations [[2, 1], [1, 2]] x = (5, 6) */
    double A[] = {1, 0, 0, 1, 1, 1}, b[] = {1, 2, 4}, x[] = {4.0 / 3, 7.0 / 3};
    phm_status st = phm_lstsq(3, 2, A, b, &rank, &err);
    check("lstsq 3x2 full rank: x = (4/3, 7/3)", st == PHM_OK && rank == 2 ? maxdiff(2, b, x) : 1.0, 1e-15 * 8);
  }
  { /* underdetermined, full rank: x = A^T (A A^T)^-1 b = (1, 2) */
    double A[] = {1, 2}, b[] = {5, 0}, x[] = {1, 2};
    phm_status st = phm_lstsq(1, 2, A, b, &rank, &err);
    check("lstsq 1x2: minimum-norm x = (1, 2)", st == PHM_OK && rank == 1 ? maxdiff(2, b, x) : 1.0, 1e-15 * 8);
  }
  { /* rank 1, consistent: x1 + x2 = 2 with x3 free -> (1, 1, 0) */
    double A[] = {1, 1, 0, 2, 2, 0}, b[] = {2, 4, 0}, x[] = {1, 1, 0};
    phm_status st = phm_lstsq(2, 3, A, b, &rank, &err);
    check("lstsq 2x3 rank 1: minimum-norm x = (1, 1, 0)", st == PHM_OK && rank == 1 ? maxdiff(3, b, x) : 1.0, 1e-15 * 8);
  }
  { /* rank 1, inconsistent: rows x1 + x2 = 1, x1 + x2 = 3, 0 = 5 -> x1 + x2 = 2, min norm (1, 1) */
    double A[] = {1, 1, 1, 1, 0, 0}, b[] = {1, 3, 5}, x[] = {1, 1};
    phm_status st = phm_lstsq(3, 2, A, b, &rank, &err);
    check("lstsq 3x2 rank 1: minimum-norm least squares x = (1, 1)", st == PHM_OK && rank == 1 ? maxdiff(2, b, x) : 1.0, 1e-15 * 8);
  }
  { /* 3x3 rank 2: A = [[1, 2, 3], [2, 4, 6], [1, 0, 1]], b = (1, 2, 1): rows 1 and 2 agree
     * (x1 + 2 x2 + 3 x3 = 1), row 3: x1 + x3 = 1; x = (1 - t, -t, t), |x|^2 minimal at t = 1/3 */
    double A[] = {1, 2, 3, 2, 4, 6, 1, 0, 1}, b[] = {1, 2, 1}, x[] = {2.0 / 3, -1.0 / 3, 1.0 / 3};
    phm_status st = phm_lstsq(3, 3, A, b, &rank, &err);
    check("lstsq 3x3 rank 2: minimum-norm x = (2/3, -1/3, 1/3)", st == PHM_OK && rank == 2 ? maxdiff(3, b, x) : 1.0, 1e-14);
  }
  { /* no rows: x = 0, rank 0 */
    double A[1] = {0}, b[] = {7, 7};
    phm_status st = phm_lstsq(0, 2, A, b, &rank, &err);
    check("lstsq with no rows: x = 0, rank 0", st == PHM_OK && rank == 0 ? maxabs(2, b) : 1.0, 0.0);
  }
}

static void inline_helpers_multiply_and_find_non_finite_entries(void) {
  double A[36], x[6], y[6], z[6], ref[6], reft[6];
  for (int i = 0; i < 36; i++) A[i] = rand11();
  for (int i = 0; i < 6; i++) x[i] = rand11();
  for (int i = 0; i < 6; i++) {
    ref[i] = reft[i] = 0;
    for (int j = 0; j < 6; j++) {
      ref[i] += A[6 * i + j] * x[j];
      reft[i] += A[6 * j + i] * x[j];
    }
  }
  phm_mv6(A, x, y);
  phm_mtv6(A, x, z);
  check("mv6: y = A x", maxdiff(6, y, ref), 1e-15 * 8);
  check("mtv6: y = A^T x", maxdiff(6, z, reft), 1e-15 * 8);
  check("dot", fabs(phm_dot(x, y, 6) - (x[0] * y[0] + x[1] * y[1] + x[2] * y[2] + x[3] * y[3] + x[4] * y[4] + x[5] * y[5])), 1e-15 * 8);
  double v[5] = {1, 2, 3, 4, 5};
  CHECK(phm_first_nonfinite(v, 5) == -1 && phm_all_finite(v, 5), "finite vector: no non-finite entry");
  v[3] = NAN;
  v[4] = INFINITY;
  CHECK(phm_first_nonfinite(v, 5) == 3 && !phm_all_finite(v, 5), "first non-finite entry: index 3");
  CHECK(phm_first_nonfinite(v, 3) == -1, "only the first n entries are read");
}

CHECK_MAIN(CHECK_CASE(cholesky_reconstructs_the_matrix_and_solves),
           CHECK_CASE(cholesky_refuses_indefinite_and_singular_matrices),
           CHECK_CASE(lstsq_returns_the_minimum_norm_least_squares_solution),
           CHECK_CASE(inline_helpers_multiply_and_find_non_finite_entries))
