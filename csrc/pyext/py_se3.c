/* py_se3.c -- bindings of the SE(3) algebra (csrc/util/se3.c) as phmech._core.so3_* / se3_* /
 * quat_*.
 *
 * Every function takes one element or a stack (..., tail) of them, validates it here (real
 * numbers only, right trailing shape, finite values), loops over the stack calling the C kernel
 * with the GIL released, and returns a new C-ordered float64 array (..., out_tail). */
#include "pyext.h"

#include <math.h>

typedef void (*kernel_fn)(const double *, double *);

static PyArrayObject *get_array(PyObject *obj, const char *what, const npy_intp *tail, int ntail) {
  return phm_py_double_array(obj, what, tail, ntail, 1);
}

/* New array of shape (stack dims of `in` (nd_in - ntail_in of them), out_tail). */
static PyArrayObject *new_out(PyArrayObject *in, int ntail_in, const npy_intp *tail, int ntail) {
  npy_intp dims[NPY_MAXDIMS];
  int ns = PyArray_NDIM(in) - ntail_in;
  if (ns + ntail > NPY_MAXDIMS) {
    PyErr_SetString(phm_py_ModelError, "too many stack dimensions");
    return NULL;
  }
  for (int i = 0; i < ns; i++) dims[i] = PyArray_DIM(in, i);
  for (int i = 0; i < ntail; i++) dims[ns + i] = tail[i];
  return (PyArrayObject *)PyArray_SimpleNew(ns + ntail, dims, NPY_DOUBLE);
}

/* The result o of `what` must be finite: finite input whose magnitude is beyond the function's
 * range in double precision (exp of a 1e300 rad rotation, the inverse of a pose with 1e300
 * entries) gives NaN or inf, which is refused here instead of being returned. Releases o and
 * returns NULL with phmech.ModelError set, or returns o. */
static PyObject *finite_or_raise(PyArrayObject *o, PyArrayObject *in, const char *what) {
  const double *y = (const double *)PyArray_DATA(o);
  npy_intp n = PyArray_SIZE(o);
  for (npy_intp i = 0; i < n; i++) {
    if (!isfinite(y[i])) {
      const double *x = (const double *)PyArray_DATA(in);
      double big = 0;
      for (npy_intp j = 0; j < PyArray_SIZE(in); j++) big = fmax(big, fabs(x[j]));
      char mag[32]; /* PyErr_Format has no floating-point conversions */
      snprintf(mag, sizeof mag, "%.3g", big);
      PyErr_Format(phm_py_ModelError,
                   "%s: the result is not finite although the input is (largest |entry| %s): "
                   "the input is beyond this function's range in double precision", what, mag);
      Py_DECREF(o);
      return NULL;
    }
  }
  return (PyObject *)o;
}

static npy_intp prod(const npy_intp *t, int n) {
  npy_intp p = 1;
  for (int i = 0; i < n; i++) p *= t[i];
  return p;
}

static PyObject *unary(PyObject *arg, const char *what, const npy_intp *tin, int nin,
                       const npy_intp *tout, int nout, kernel_fn k) {
  PyArrayObject *a = get_array(arg, what, tin, nin);
  if (!a) return NULL;
  PyArrayObject *o = new_out(a, nin, tout, nout);
  if (!o) {
    Py_DECREF(a);
    return NULL;
  }
  npy_intp si = prod(tin, nin), so = prod(tout, nout);
  npy_intp n = si ? PyArray_SIZE(a) / si : 0;
  const double *x = (const double *)PyArray_DATA(a);
  double *y = (double *)PyArray_DATA(o);
  Py_BEGIN_ALLOW_THREADS
  for (npy_intp i = 0; i < n; i++) k(x + i * si, y + i * so);
  Py_END_ALLOW_THREADS
  PyObject *r = finite_or_raise(o, a, what);
  Py_DECREF(a);
  return r;
}

static const npy_intp T3[] = {3}, T4[] = {4}, T6[] = {6}, T33[] = {3, 3}, T44[] = {4, 4},
                      T66[] = {6, 6};

#define UNARY(name, what, tin, nin, tout, nout, kern)                                         \
  static PyObject *py_##name(PyObject *self, PyObject *arg) {                                 \
    (void)self;                                                                               \
    return unary(arg, what, tin, nin, tout, nout, kern);                           \
  }

UNARY(so3_hat, "so3_hat: w", T3, 1, T33, 2, phm_so3_hat)
UNARY(so3_vee, "so3_vee: W", T33, 2, T3, 1, phm_so3_vee)
UNARY(so3_exp, "so3_exp: w", T3, 1, T33, 2, phm_so3_exp)
UNARY(so3_log, "so3_log: R", T33, 2, T3, 1, phm_so3_log)
UNARY(so3_jac, "so3_jac: w", T3, 1, T33, 2, phm_so3_jac)
UNARY(so3_jac_inv, "so3_jac_inv: w", T3, 1, T33, 2, phm_so3_jac_inv)
UNARY(se3_hat, "se3_hat: x", T6, 1, T44, 2, phm_se3_hat)
UNARY(se3_vee, "se3_vee: X", T44, 2, T6, 1, phm_se3_vee)
UNARY(se3_exp, "se3_exp: x", T6, 1, T44, 2, phm_se3_exp)
UNARY(se3_log, "se3_log: H", T44, 2, T6, 1, phm_se3_log)
UNARY(se3_inverse, "se3_inverse: H", T44, 2, T44, 2, phm_se3_inverse)
UNARY(se3_Ad, "se3_Ad: H", T44, 2, T66, 2, phm_se3_Ad)
UNARY(se3_Ad_dual, "se3_Ad_dual: H", T44, 2, T66, 2, phm_se3_Ad_dual)
UNARY(se3_ad, "se3_ad: x", T6, 1, T66, 2, phm_se3_ad)
UNARY(se3_ad_dual, "se3_ad_dual: x", T6, 1, T66, 2, phm_se3_ad_dual)
UNARY(se3_dexp, "se3_dexp: x", T6, 1, T66, 2, phm_se3_dexp)
UNARY(se3_dexp_inv, "se3_dexp_inv: x", T6, 1, T66, 2, phm_se3_dexp_inv)
UNARY(quat_from_rot, "quat_from_rot: R", T33, 2, T4, 1, phm_quat_from_rot)

/* quat_to_rot additionally refuses quaternions of (near) zero norm. */
static PyObject *py_quat_to_rot(PyObject *self, PyObject *arg) {
  (void)self;
  PyArrayObject *a = get_array(arg, "quat_to_rot: q", T4, 1);
  if (!a) return NULL;
  const double *q = (const double *)PyArray_DATA(a);
  npy_intp n = PyArray_SIZE(a) / 4;
  for (npy_intp i = 0; i < n; i++) {
    const double *c = q + 4 * i;
    double m = fmax(fmax(fabs(c[0]), fabs(c[1])), fmax(fabs(c[2]), fabs(c[3])));
    if (!(m > 1e-150)) {
      Py_DECREF(a);
      PyErr_Format(phm_py_ModelError, "quat_to_rot: q: quaternion %zd has zero norm", (Py_ssize_t)i);
      return NULL;
    }
  }
  PyObject *o = unary((PyObject *)a, "quat_to_rot: q", T4, 1, T33, 2, phm_quat_to_rot);
  Py_DECREF(a);
  return o;
}

/* se3_compose(A, B): both (..., 4, 4) with identical stack shapes (phmech.se3 broadcasts). */
static PyObject *py_se3_compose(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *oa, *ob;
  if (!PyArg_ParseTuple(args, "OO:se3_compose", &oa, &ob)) return NULL;
  PyArrayObject *a = get_array(oa, "se3_compose: A", T44, 2);
  if (!a) return NULL;
  PyArrayObject *b = get_array(ob, "se3_compose: B", T44, 2);
  if (!b) {
    Py_DECREF(a);
    return NULL;
  }
  if (PyArray_NDIM(a) != PyArray_NDIM(b) ||
      !PyArray_CompareLists(PyArray_DIMS(a), PyArray_DIMS(b), PyArray_NDIM(a))) {
    Py_DECREF(a);
    Py_DECREF(b);
    PyErr_SetString(phm_py_ModelError,
                    "se3_compose: A and B must have the same shape (..., 4, 4); "
                    "phmech.se3.compose broadcasts them");
    return NULL;
  }
  PyArrayObject *o = new_out(a, 2, T44, 2);
  if (o) {
    npy_intp n = PyArray_SIZE(a) / 16;
    const double *x = (const double *)PyArray_DATA(a), *y = (const double *)PyArray_DATA(b);
    double *z = (double *)PyArray_DATA(o);
    Py_BEGIN_ALLOW_THREADS
    for (npy_intp i = 0; i < n; i++) phm_se3_compose(x + 16 * i, y + 16 * i, z + 16 * i);
    Py_END_ALLOW_THREADS
    /* the message reports the larger of the two inputs */
    double ma = 0, mb = 0;
    for (npy_intp i = 0; i < 16 * n; i++) {
      ma = fmax(ma, fabs(x[i]));
      mb = fmax(mb, fabs(y[i]));
    }
    o = (PyArrayObject *)finite_or_raise(o, ma >= mb ? a : b, "se3_compose: A B");
  }
  Py_DECREF(a);
  Py_DECREF(b);
  return (PyObject *)o;
}

#define M1(name, doc) {#name, py_##name, METH_O, doc}

PyMethodDef phm_py_se3_methods[] = {
    M1(so3_hat, "so3_hat(w (...,3)) -> (...,3,3): skew matrix, hat(w) x = w cross x."),
    M1(so3_vee, "so3_vee(W (...,3,3)) -> (...,3): vector of the skew part of W."),
    M1(so3_exp, "so3_exp(w (...,3)) -> (...,3,3): rotation exp(hat w) (Rodrigues)."),
    M1(so3_log, "so3_log(R (...,3,3)) -> (...,3): rotation vector, |w| in [0, pi]."),
    M1(so3_jac, "so3_jac(w (...,3)) -> (...,3,3): left Jacobian sum_k hat(w)^k/(k+1)!."),
    M1(so3_jac_inv, "so3_jac_inv(w (...,3)) -> (...,3,3): inverse left Jacobian, |w| < 2 pi."),
    M1(se3_hat, "se3_hat(x (...,6)) -> (...,4,4): twist x = (omega, v) as a 4x4 matrix."),
    M1(se3_vee, "se3_vee(X (...,4,4)) -> (...,6): twist coordinates (omega, v) of X."),
    M1(se3_exp, "se3_exp(x (...,6)) -> (...,4,4): pose exp(hat x)."),
    M1(se3_log, "se3_log(H (...,4,4)) -> (...,6): twist x with exp(hat x) = H, |omega| <= pi."),
    M1(se3_inverse, "se3_inverse(H (...,4,4)) -> (...,4,4): inverse pose."),
    M1(se3_Ad, "se3_Ad(H (...,4,4)) -> (...,6,6): Ad_H = [[R, 0], [hat(p) R, R]]."),
    M1(se3_Ad_dual, "se3_Ad_dual(H (...,4,4)) -> (...,6,6): Ad_H^T (acts on wrenches)."),
    M1(se3_ad, "se3_ad(x (...,6)) -> (...,6,6): ad_x = [[hat w, 0], [hat v, hat w]]."),
    M1(se3_ad_dual, "se3_ad_dual(x (...,6)) -> (...,6,6): ad_x^T."),
    M1(se3_dexp, "se3_dexp(x (...,6)) -> (...,6,6): sum_k ad_x^k/(k+1)!."),
    M1(se3_dexp_inv, "se3_dexp_inv(x (...,6)) -> (...,6,6): inverse of dexp_x, |omega| < 2 pi."),
    M1(quat_to_rot, "quat_to_rot(q (...,4)) -> (...,3,3): rotation of q = (w, x, y, z), normalized."),
    M1(quat_from_rot, "quat_from_rot(R (...,3,3)) -> (...,4): unit quaternion (w, x, y, z), w >= 0."),
    {"se3_compose", py_se3_compose, METH_VARARGS,
     "se3_compose(A (...,4,4), B (...,4,4)) -> (...,4,4): A B; equal stack shapes."},
    {NULL, NULL, 0, NULL}};
