/* nvector_ops.c -- the serial N_Vector operations and the sparse matrix's zero that IDA spends its
 * own time in, compiled with the core. Debian 12's SUNDIALS 6.4.1 (libsundials-ida6, which
 * carries the serial N_Vector and SUNMatrix code) is built without optimization: every element
 * of N_VLinearSum goes through the stack, ~20 instructions. On the rigid chain of 100 bodies
 * (2402 states) IDA's vector operations and SUNMatZero were ~40 % of a run's CPU time once the
 * Jacobian's zeros were pruned (perf and callgrind, docs/perf_scaling.md).
 *
 * Each operation computes what SUNDIALS's serial one computes, operation for operation (the same
 * cases of N_VLinearSum, a*(x + y) where a == b, the norms summed in index order; c11 keeps
 * a*x + b*y from being contracted into a fused multiply-add), so results are bit-identical: the
 * C test test_nvector_ops compares them with SUNDIALS's own. The fused and vector-array
 * operations stay unset, as N_VNew_Serial leaves them: SUNDIALS then composes them from the
 * operations below, as before. */
#include "integrate.h"

#include <math.h>
#include <string.h>

/* z = a x + b y, with the cases of N_VLinearSum_Serial (each one's arithmetic as there). */
static void lin_sum(sunrealtype a, N_Vector x, sunrealtype b, N_Vector y, N_Vector z) {
  sunindextype n = NV_LENGTH_S(z);
  sunrealtype *xd = NV_DATA_S(x), *yd = NV_DATA_S(y), *zd = NV_DATA_S(z);
  if (b == 1.0 && z == y) { /* y += a x */
    if (a == 1.0) for (sunindextype i = 0; i < n; i++) yd[i] += xd[i];
    else if (a == -1.0) for (sunindextype i = 0; i < n; i++) yd[i] -= xd[i];
    else for (sunindextype i = 0; i < n; i++) yd[i] += a * xd[i];
  } else if (a == 1.0 && z == x) { /* x += b y */
    if (b == 1.0) for (sunindextype i = 0; i < n; i++) xd[i] += yd[i];
    else if (b == -1.0) for (sunindextype i = 0; i < n; i++) xd[i] -= yd[i];
    else for (sunindextype i = 0; i < n; i++) xd[i] += b * yd[i];
  } else if (a == 1.0 && b == 1.0) {
    for (sunindextype i = 0; i < n; i++) zd[i] = xd[i] + yd[i];
  } else if (a == 1.0 && b == -1.0) {
    for (sunindextype i = 0; i < n; i++) zd[i] = xd[i] - yd[i];
  } else if (a == -1.0 && b == 1.0) {
    for (sunindextype i = 0; i < n; i++) zd[i] = yd[i] - xd[i];
  } else if (a == 1.0) {
    for (sunindextype i = 0; i < n; i++) zd[i] = b * yd[i] + xd[i];
  } else if (b == 1.0) {
    for (sunindextype i = 0; i < n; i++) zd[i] = a * xd[i] + yd[i];
  } else if (a == -1.0) {
    for (sunindextype i = 0; i < n; i++) zd[i] = b * yd[i] - xd[i];
  } else if (b == -1.0) {
    for (sunindextype i = 0; i < n; i++) zd[i] = a * xd[i] - yd[i];
  } else if (a == b) {
    for (sunindextype i = 0; i < n; i++) zd[i] = a * (xd[i] + yd[i]);
  } else if (a == -b) {
    for (sunindextype i = 0; i < n; i++) zd[i] = a * (xd[i] - yd[i]);
  } else {
    for (sunindextype i = 0; i < n; i++) zd[i] = a * xd[i] + b * yd[i];
  }
}

static void const_(sunrealtype c, N_Vector z) {
  sunindextype n = NV_LENGTH_S(z);
  sunrealtype *zd = NV_DATA_S(z);
  for (sunindextype i = 0; i < n; i++) zd[i] = c;
}

/* z = c x (c = 1 and -1: a copy and a negation, the same numbers) */
static void scale(sunrealtype c, N_Vector x, N_Vector z) {
  sunindextype n = NV_LENGTH_S(z);
  sunrealtype *xd = NV_DATA_S(x), *zd = NV_DATA_S(z);
  if (c == 1.0) {
    if (z != x) memcpy(zd, xd, sizeof(sunrealtype) * (size_t)n);
  } else if (c == -1.0) {
    for (sunindextype i = 0; i < n; i++) zd[i] = -xd[i];
  } else {
    for (sunindextype i = 0; i < n; i++) zd[i] = c * xd[i];
  }
}

static void abs_(N_Vector x, N_Vector z) {
  sunindextype n = NV_LENGTH_S(z);
  sunrealtype *xd = NV_DATA_S(x), *zd = NV_DATA_S(z);
  for (sunindextype i = 0; i < n; i++) zd[i] = fabs(xd[i]);
}

static void inv(N_Vector x, N_Vector z) {
  sunindextype n = NV_LENGTH_S(z);
  sunrealtype *xd = NV_DATA_S(x), *zd = NV_DATA_S(z);
  for (sunindextype i = 0; i < n; i++) zd[i] = 1.0 / xd[i];
}

static void add_const(N_Vector x, sunrealtype b, N_Vector z) {
  sunindextype n = NV_LENGTH_S(z);
  sunrealtype *xd = NV_DATA_S(x), *zd = NV_DATA_S(z);
  for (sunindextype i = 0; i < n; i++) zd[i] = xd[i] + b;
}

/* sqrt(sum_i (x_i w_i)^2 / n), summed in index order */
static sunrealtype wrms_norm(N_Vector x, N_Vector w) {
  sunindextype n = NV_LENGTH_S(x);
  const sunrealtype *xd = NV_DATA_S(x), *wd = NV_DATA_S(w);
  sunrealtype s = 0.0;
  for (sunindextype i = 0; i < n; i++) {
    sunrealtype p = xd[i] * wd[i];
    s += p * p;
  }
  return sqrt(s / (sunrealtype)n);
}

/* the same over the entries with id_i > 0, divided by the full length */
static sunrealtype wrms_norm_mask(N_Vector x, N_Vector w, N_Vector id) {
  sunindextype n = NV_LENGTH_S(x);
  const sunrealtype *xd = NV_DATA_S(x), *wd = NV_DATA_S(w), *idd = NV_DATA_S(id);
  sunrealtype s = 0.0;
  for (sunindextype i = 0; i < n; i++)
    if (idd[i] > 0.0) {
      sunrealtype p = xd[i] * wd[i];
      s += p * p;
    }
  return sqrt(s / (sunrealtype)n);
}

static sunrealtype min_(N_Vector x) {
  sunindextype n = NV_LENGTH_S(x);
  const sunrealtype *xd = NV_DATA_S(x);
  sunrealtype m = xd[0];
  for (sunindextype i = 1; i < n; i++)
    if (xd[i] < m) m = xd[i];
  return m;
}

void phm_nvector_ops(N_Vector v) {
  v->ops->nvlinearsum = lin_sum;
  v->ops->nvconst = const_;
  v->ops->nvscale = scale;
  v->ops->nvabs = abs_;
  v->ops->nvinv = inv;
  v->ops->nvaddconst = add_const;
  v->ops->nvwrmsnorm = wrms_norm;
  v->ops->nvwrmsnormmask = wrms_norm_mask;
  v->ops->nvmin = min_;
}

/* A sparse matrix's zero: values, row indices and column pointers (SUNMatZero_Sparse). */
static int sparse_zero(SUNMatrix A) {
  memset(SM_DATA_S(A), 0, sizeof(sunrealtype) * (size_t)SM_NNZ_S(A));
  memset(SM_INDEXVALS_S(A), 0, sizeof(sunindextype) * (size_t)SM_NNZ_S(A));
  memset(SM_INDEXPTRS_S(A), 0, sizeof(sunindextype) * (size_t)(SM_NP_S(A) + 1));
  return 0;
}

void phm_sparse_matrix_ops(SUNMatrix A) { A->ops->zero = sparse_zero; }
