/* py_mixed.c -- bindings of Golo's mixed finite element (csrc/model/mixed.c). */
#include "pyext.h"

#include <limits.h>

/* A real number (int, float, NumPy scalar) or ModelError naming `what`. */
static int get_double(PyObject *o, const char *what, double *out) {
  if (PyBool_Check(o) || !(PyFloat_Check(o) || PyLong_Check(o) || PyNumber_Check(o)) ||
      PyComplex_Check(o)) {
    PyErr_Format(phm_py_ModelError, "%s: expected a real number", what);
    return -1;
  }
  double v = PyFloat_AsDouble(o);
  if (v == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    PyErr_Format(phm_py_ModelError, "%s: expected a real number", what);
    return -1;
  }
  *out = v;
  return 0;
}

/* An integer (int or NumPy integer, not bool) or ModelError naming `what`. */
static int get_int(PyObject *o, const char *what, int *out) {
  if (PyBool_Check(o) || !PyIndex_Check(o)) {
    PyErr_Format(phm_py_ModelError, "%s: expected an integer", what);
    return -1;
  }
  PyObject *i = PyNumber_Index(o);
  if (!i) return -1;
  int overflow = 0;
  long v = PyLong_AsLongAndOverflow(i, &overflow);
  Py_DECREF(i);
  if (v == -1 && PyErr_Occurred()) return -1;
  if (overflow || v > INT_MAX || v < INT_MIN) {
    PyErr_Format(phm_py_ModelError, "%s: integer out of range", what);
    return -1;
  }
  *out = (int)v;
  return 0;
}

/* (N, L, EI, kGA, rhoA, rhoI, alpha) -> phm_mixed_beam, validated. */
static int get_beam(PyObject *const *a, phm_mixed_beam *b) {
  if (get_int(a[0], "N", &b->N) || get_double(a[1], "L", &b->L) ||
      get_double(a[2], "EI", &b->EI) || get_double(a[3], "kGA", &b->kGA) ||
      get_double(a[4], "rhoA", &b->rhoA) || get_double(a[5], "rhoI", &b->rhoI) ||
      get_double(a[6], "alpha", &b->alpha))
    return -1;
  phm_error err;
  phm_error_clear(&err);
  if (phm_mixed_check(b, &err) != PHM_OK) {
    phm_py_raise(&err);
    return -1;
  }
  return 0;
}

static PyObject *new_matrix(npy_intp r, npy_intp c) {
  npy_intp dims[2] = {r, c};
  return PyArray_ZEROS(2, dims, NPY_DOUBLE, 0);
}

static PyObject *py_mixed_matrices(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *a[7];
  if (!PyArg_ParseTuple(args, "OOOOOOO:mixed_matrices", &a[0], &a[1], &a[2], &a[3], &a[4], &a[5],
                        &a[6]))
    return NULL;
  phm_mixed_beam b;
  if (get_beam(a, &b)) return NULL;
  const npy_intp n = 4 * (npy_intp)b.N;
  PyObject *J = new_matrix(n, n), *Q = new_matrix(n, n), *B = new_matrix(n, 4),
           *D = new_matrix(4, 4);
  if (!J || !Q || !B || !D) goto fail;
  phm_error err;
  phm_error_clear(&err);
  phm_status st;
  Py_BEGIN_ALLOW_THREADS;
  st = phm_mixed_assemble(&b, PyArray_DATA((PyArrayObject *)J), PyArray_DATA((PyArrayObject *)Q),
                          PyArray_DATA((PyArrayObject *)B), PyArray_DATA((PyArrayObject *)D), &err);
  Py_END_ALLOW_THREADS;
  if (st != PHM_OK) {
    phm_py_raise(&err);
    goto fail;
  }
  return Py_BuildValue("(NNNN)", J, Q, B, D);
fail:
  Py_XDECREF(J);
  Py_XDECREF(Q);
  Py_XDECREF(B);
  Py_XDECREF(D);
  return NULL;
}

static int get_bc(PyObject *o, phm_mixed_bc *bc) {
  if (!PyUnicode_Check(o)) {
    PyErr_SetString(phm_py_ModelError, "bc: expected a string such as 'clamped-free'");
    return -1;
  }
  const char *s = PyUnicode_AsUTF8(o);
  if (!s) return -1;
  phm_error err;
  phm_error_clear(&err);
  if (phm_mixed_bc_from_name(s, bc, &err) != PHM_OK) {
    phm_py_raise(&err);
    return -1;
  }
  return 0;
}

static PyObject *py_mixed_frequencies(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *on, *obc, *a[7];
  if (!PyArg_ParseTuple(args, "OOOOOOOOO:mixed_frequencies", &on, &a[0], &a[1], &a[2], &a[3],
                        &a[4], &a[5], &obc, &a[6]))
    return NULL;
  int n;
  phm_mixed_beam b;
  phm_mixed_bc bc;
  if (get_int(on, "n", &n) || get_beam(a, &b) || get_bc(obc, &bc)) return NULL;
  if (n < 1 || n > 2 * b.N) { /* same bound as the C function */
    PyErr_Format(phm_py_ModelError, "n = %d frequencies requested, need 1 <= n <= 2N = %d", n,
                 2 * b.N);
    return NULL;
  }
  npy_intp dims[1] = {n};
  PyObject *w = PyArray_ZEROS(1, dims, NPY_DOUBLE, 0);
  if (!w) return NULL;
  phm_error err;
  phm_error_clear(&err);
  phm_status st;
  Py_BEGIN_ALLOW_THREADS;
  st = phm_mixed_frequencies(&b, bc, n, PyArray_DATA((PyArrayObject *)w), &err);
  Py_END_ALLOW_THREADS;
  if (st != PHM_OK) {
    Py_DECREF(w);
    return phm_py_raise(&err);
  }
  return w;
}

static PyObject *py_mixed_bc_ports(PyObject *self, PyObject *arg) {
  (void)self;
  phm_mixed_bc bc;
  if (get_bc(arg, &bc)) return NULL;
  int c[4];
  phm_mixed_bc_ports(bc, c);
  return Py_BuildValue("(OOOO)", c[0] ? Py_True : Py_False, c[1] ? Py_True : Py_False,
                       c[2] ? Py_True : Py_False, c[3] ? Py_True : Py_False);
}

PyMethodDef phm_py_mixed_methods[] = {
    {"mixed_matrices", py_mixed_matrices, METH_VARARGS,
     "mixed_matrices(N, L, EI, kGA, rhoA, rhoI, alpha) -> (J, Q, B, D): Golo's mixed finite "
     "element chain of the linear Timoshenko beam, ports u = (v(0), omega(0), Q(L), M(L))."},
    {"mixed_frequencies", py_mixed_frequencies, METH_VARARGS,
     "mixed_frequencies(n, N, L, EI, kGA, rhoA, rhoI, bc, alpha) -> first n natural "
     "frequencies [rad/s]."},
    {"mixed_bc_ports", py_mixed_bc_ports, METH_O,
     "mixed_bc_ports(bc) -> 4 bools: True where the port's output is constrained to zero "
     "(its input becomes a Lagrange multiplier), False where its input is set to zero."},
    {NULL, NULL, 0, NULL}};
