/* test_nvector_ops.c -- csrc/integrate/nvector_ops.c: the serial N_Vector operations and the sparse
 * zero phmech installs for IDA give bit for bit what SUNDIALS's own give, in every case of
 * N_VLinearSum (coefficients 1, -1, equal, opposite, other; z aliasing x or y or neither), on
 * values with signed zeros, subnormals and large magnitudes. */
#include "check.h"
#include "integrate.h"

enum { N = 37 };

static SUNContext ctx; /* one for the whole run (freed at exit) */

static void setup(void) {
  if (!ctx && phm_sun_context_create(&ctx)) {
    printf("FAIL: no SUNDIALS context\n");
    exit(1);
  }
}

/* the same values for the same salt (both vectors of a comparison): signs and magnitudes 1e-4 ..
 * 1e4 from a sine, then the special values */
static void fill(N_Vector v, int salt) {
  double *d = N_VGetArrayPointer(v);
  for (int i = 0; i < N; i++) d[i] = sin(1.7 * i + 0.3 * salt) * pow(10.0, (double)((i * 7 + salt) % 9) - 4.0);
  d[0] = -0.0;
  d[1] = 0.0;
  d[2] = 4.9e-320 * (salt % 2 ? 1 : -1); /* subnormal */
  d[3] = 1e300;
}

static N_Vector fresh(int own, int salt) {
  N_Vector v = N_VNew_Serial(N, ctx);
  if (own) phm_nvector_ops(v);
  fill(v, salt);
  return v;
}

static int same(N_Vector a, N_Vector b) {
  return !memcmp(N_VGetArrayPointer(a), N_VGetArrayPointer(b), sizeof(double) * N);
}
static int same_real(double a, double b) { return !memcmp(&a, &b, sizeof a); }

/* z = a x + b y by both, for z a third vector, x (z == x) and y (z == y) */
static void linear_sum_matches_every_case(void) {
  setup();
  const double cs[] = {1.0, -1.0, 0.0, 0.37, -0.37, 2.5, -4.0};
  int nc = (int)(sizeof cs / sizeof cs[0]);
  for (int ia = 0; ia < nc; ia++)
    for (int ib = 0; ib < nc; ib++)
      for (int alias = 0; alias < 3; alias++) {
        double a = cs[ia], b = cs[ib];
        N_Vector x0 = fresh(0, 1), y0 = fresh(0, 2), z0 = fresh(0, 3);
        N_Vector x1 = fresh(1, 1), y1 = fresh(1, 2), z1 = fresh(1, 3);
        N_Vector zz0 = alias == 1 ? x0 : alias == 2 ? y0 : z0;
        N_Vector zz1 = alias == 1 ? x1 : alias == 2 ? y1 : z1;
        N_VLinearSum_Serial(a, x0, b, y0, zz0);
        N_VLinearSum(a, x1, b, y1, zz1); /* through the installed ops */
        CHECK(same(x0, x1) && same(y0, y1) && same(z0, z1),
              "linear sum a = %g, b = %g, z %s: the same bits", a, b,
              alias == 1 ? "= x" : alias == 2 ? "= y" : "apart");
        N_VDestroy(x0); N_VDestroy(y0); N_VDestroy(z0);
        N_VDestroy(x1); N_VDestroy(y1); N_VDestroy(z1);
      }
}

static void scale_const_abs_inv_addconst_min_match(void) {
  setup();
  const double cs[] = {1.0, -1.0, 0.0, 0.37, -2.5};
  for (int ic = 0; ic < 5; ic++)
    for (int alias = 0; alias < 2; alias++) {
      double c = cs[ic];
      N_Vector x0 = fresh(0, 4), z0 = fresh(0, 5), x1 = fresh(1, 4), z1 = fresh(1, 5);
      N_VScale_Serial(c, x0, alias ? x0 : z0);
      N_VScale(c, x1, alias ? x1 : z1);
      CHECK(same(x0, x1) && same(z0, z1), "scale c = %g, z %s", c, alias ? "= x" : "apart");
      N_VConst_Serial(c, z0);
      N_VConst(c, z1);
      CHECK(same(z0, z1), "const %g", c);
      N_VAddConst_Serial(x0, c, z0);
      N_VAddConst(x1, c, z1);
      CHECK(same(z0, z1), "add const %g", c);
      N_VDestroy(x0); N_VDestroy(z0); N_VDestroy(x1); N_VDestroy(z1);
    }
  N_Vector x0 = fresh(0, 6), z0 = fresh(0, 7), x1 = fresh(1, 6), z1 = fresh(1, 7);
  N_VAbs_Serial(x0, z0);
  N_VAbs(x1, z1);
  CHECK(same(z0, z1), "abs");
  N_VInv_Serial(z0, x0);
  N_VInv(z1, x1);
  CHECK(same(x0, x1), "inverse (1/0 included)");
  CHECK(same_real(N_VMin_Serial(x0), N_VMin(x1)), "min");
  N_VDestroy(x0); N_VDestroy(z0); N_VDestroy(x1); N_VDestroy(z1);
}

static void weighted_norms_match(void) {
  setup();
  N_Vector x0 = fresh(0, 8), w0 = fresh(0, 9), id0 = fresh(0, 10);
  N_Vector x1 = fresh(1, 8), w1 = fresh(1, 9), id1 = fresh(1, 10);
  double *a = N_VGetArrayPointer(x0), *b = N_VGetArrayPointer(x1);
  a[3] = b[3] = 1.5; /* no overflow in the squares */
  N_VAbs_Serial(w0, w0);
  N_VAbs_Serial(w1, w1);
  CHECK(same_real(N_VWrmsNorm_Serial(x0, w0), N_VWrmsNorm(x1, w1)), "WRMS norm");
  CHECK(same_real(N_VWrmsNormMask_Serial(x0, w0, id0), N_VWrmsNormMask(x1, w1, id1)),
        "masked WRMS norm (id > 0 on about half the entries)");
  N_VConst_Serial(0.0, x0);
  N_VConst(0.0, x1);
  CHECK(same_real(N_VWrmsNorm_Serial(x0, w0), N_VWrmsNorm(x1, w1)), "WRMS norm of zero");
  N_VDestroy(x0); N_VDestroy(w0); N_VDestroy(id0);
  N_VDestroy(x1); N_VDestroy(w1); N_VDestroy(id1);
}

/* the fused operations, composed by SUNDIALS from the installed ones, as from its own */
static void composed_operations_match(void) {
  setup();
  N_Vector X0[4], X1[4];
  for (int i = 0; i < 4; i++) {
    X0[i] = fresh(0, 11 + i);
    X1[i] = fresh(1, 11 + i);
  }
  N_Vector z0 = fresh(0, 20), z1 = fresh(1, 20);
  double c[4] = {1.0, -0.5, 0.25, 3.0};
  N_VLinearCombination(4, c, X0, z0);
  N_VLinearCombination(4, c, X1, z1);
  CHECK(same(z0, z1), "linear combination of 4");
  for (int i = 0; i < 4; i++) {
    N_VDestroy(X0[i]);
    N_VDestroy(X1[i]);
  }
  N_VDestroy(z0);
  N_VDestroy(z1);
}

static void sparse_zero_clears_values_indices_and_pointers(void) {
  setup();
  SUNMatrix A = SUNSparseMatrix(5, 5, 12, CSC_MAT, ctx);
  phm_sparse_matrix_ops(A);
  double *v = SUNSparseMatrix_Data(A);
  sunindextype *ri = SUNSparseMatrix_IndexValues(A), *cp = SUNSparseMatrix_IndexPointers(A);
  for (int k = 0; k < 12; k++) {
    v[k] = rand11();
    ri[k] = k % 5;
  }
  for (int j = 0; j <= 5; j++) cp[j] = 2 * j;
  CHECK(SUNMatZero(A) == 0, "zero returns success");
  int bad = 0;
  for (int k = 0; k < 12; k++) bad += v[k] != 0.0 || ri[k] != 0;
  for (int j = 0; j <= 5; j++) bad += cp[j] != 0;
  CHECK(bad == 0, "every value, row index and column pointer zero (%d left)", bad);
  SUNMatDestroy(A);
}


CHECK_MAIN(CHECK_CASE(linear_sum_matches_every_case),
           CHECK_CASE(scale_const_abs_inv_addconst_min_match), CHECK_CASE(weighted_norms_match),
           CHECK_CASE(composed_operations_match),
           CHECK_CASE(sparse_zero_clears_values_indices_and_pointers))
