/* py_laws.c -- time laws across the binding (csrc/util/law.c): a law tuple of
 * python/phmech/_marshal.py into a phm_law (model_new's law columns), the trampoline of CALLBACK
 * laws, the re-raising of their exceptions, and law_eval. */
#include "py_model.h"

#include <limits.h>
#include <math.h>
#include <string.h>

/* ---------------------------------------------------------------- laws
 * A law tuple (python/phmech/_marshal.py, _law): (kind, amplitude, t0, duration, frequency,
 * phase, offset, data, order, nodes, fn): data None or a float array (TABLE: its (t, s) points;
 * PPOLY: the breaks then the coefficients, `order` per piece; CALLBACK: its breakpoints), nodes
 * None or the list of an expression's node tuples (postfix), fn None or the callable of a
 * CALLBACK law: fn(t, nder) -> (s, s', s'') or None when it failed (the Python side keeps the
 * exception in the callable's `error`; phm_py_law_error re-raises it). What the law points to is kept
 * alive in `keep` (arrays until the model has copied them, callables as long as the model). */

/* A block of n bytes that lives as long as `keep` (a capsule in it frees the block). */
static void block_free(PyObject *cap) { PyMem_Free(PyCapsule_GetPointer(cap, "phmech.block")); }
static void *keep_block(PyObject *keep, size_t n) {
  void *p = PyMem_Calloc(n ? n : 1, 1);
  if (!p) {
    PyErr_NoMemory();
    return NULL;
  }
  PyObject *cap = PyCapsule_New(p, "phmech.block", block_free);
  if (!cap) {
    PyMem_Free(p);
    return NULL;
  }
  int r = PyList_Append(keep, cap);
  Py_DECREF(cap);
  return r < 0 ? NULL : p;
}

/* A trampoline's end: the callable's result r (a new reference, or NULL) as three floats in
 * out (0), or -1 for anything else; r released, any error cleared, the GIL state g released. */
static int three_floats(PyObject *r, double out[3], PyGILState_STATE g) {
  int rc = -1;
  if (r && PyTuple_Check(r) && PyTuple_GET_SIZE(r) == 3) {
    rc = 0;
    for (int k = 0; k < 3; k++) {
      out[k] = PyFloat_AsDouble(PyTuple_GET_ITEM(r, k));
      if (out[k] == -1.0 && PyErr_Occurred()) rc = -1;
    }
  }
  Py_XDECREF(r);
  if (PyErr_Occurred()) PyErr_Clear();
  PyGILState_Release(g);
  return rc;
}

/* CALLBACK trampoline: the callable's (s, s', s'') with the GIL (the integrators run without
 * it); any failure (an exception the callable did not keep, a malformed result) is -1. */
static int law_callback(void *ctx, double t, int nder, double out[3]) {
  PyGILState_STATE g = PyGILState_Ensure();
  PyObject *r = PyObject_CallFunction((PyObject *)ctx, "di", t, nder);
  return three_floats(r, out, g);
}

/* A callback controller's trampoline (phm_component_desc.fn, PHM_COMP_CALLBACK): its callable
 * (python/phmech/components.py, _ControlCall; the ctx of its component's law) called as
 * ctx.control(t, x, v, nder) -> (u, du/dx, du/dv), with the GIL; None or anything else is a
 * failure (-1: the callable keeps its exception, python/phmech/_simulate.py raises it). */
int phm_py_control_callback(void *ctx, double t, double x, double v, int nder, double out[3]) {
  static PyObject *name = NULL;
  PyGILState_STATE g = PyGILState_Ensure();
  if (!name) name = PyUnicode_InternFromString("control");
  PyObject *a[5] = {(PyObject *)ctx, PyFloat_FromDouble(t), PyFloat_FromDouble(x),
                    PyFloat_FromDouble(v), PyLong_FromLong(nder)}, *r = NULL;
  if (name && a[1] && a[2] && a[3] && a[4]) r = PyObject_VectorcallMethod(name, a, 5, NULL);
  for (int k = 1; k < 5; k++) Py_XDECREF(a[k]);
  return three_floats(r, out, g);
}

int phm_py_parse_law(PyObject *obj, phm_law *law, PyObject *keep, const char *what, int depth) {
  memset(law, 0, sizeof *law);
  PyObject *data = Py_None, *nodes = Py_None, *fn = Py_None;
  if (!PyTuple_Check(obj) ||
      !PyArg_ParseTuple(obj, "iddddddOiOO", &law->kind, &law->amplitude, &law->t0, &law->duration,
                        &law->frequency, &law->phase, &law->offset, &data, &law->order, &nodes, &fn)) {
    PyErr_Clear();
    PyErr_Format(phm_py_ModelError, "%s: a time law must be a tuple (kind, amplitude, t0, duration, frequency, phase, offset, data, order, nodes, fn)", what);
    return -1;
  }
  if (data != Py_None) {
    PyArrayObject *a = phm_py_double_array(data, what, NULL, 0, 1);
    if (!a) return -1;
    npy_intp n = PyArray_SIZE(a);
    law->table = (const double *)PyArray_DATA(a);
    int r = PyList_Append(keep, (PyObject *)a);
    Py_DECREF(a);
    if (r < 0) return -1;
    switch (law->kind) {
    case PHM_LAW_TABLE:
      if (n % 2) {
        PyErr_Format(phm_py_ModelError, "%s: table must have shape (n, 2)", what);
        return -1;
      }
      law->ntable = (int)(n / 2);
      break;
    case PHM_LAW_PPOLY:
      if (law->order < 1 || (n - 1) % (law->order + 1)) {
        PyErr_Format(phm_py_ModelError, "%s: piecewise polynomial data must hold n + 1 breaks and n x order coefficients", what);
        return -1;
      }
      law->ntable = (int)((n - 1) / (law->order + 1));
      break;
    default: law->ntable = (int)n; break;
    }
  }
  if (fn != Py_None) {
    if (!PyCallable_Check(fn)) {
      PyErr_Format(phm_py_ModelError, "%s: a callback law's fn must be callable", what);
      return -1;
    }
    if (PyList_Append(keep, fn) < 0) return -1;
    law->fn = law_callback;
    law->ctx = fn;
  }
  if (nodes != Py_None) {
    if (depth > 0 || !PyList_Check(nodes) || PyList_GET_SIZE(nodes) > INT_MAX / 2) {
      PyErr_Format(phm_py_ModelError, "%s: an expression's nodes must be a flat list of law tuples", what);
      return -1;
    }
    Py_ssize_t n = PyList_GET_SIZE(nodes);
    phm_law *nd = keep_block(keep, sizeof(phm_law) * (size_t)n);
    if (!nd) return -1;
    for (Py_ssize_t i = 0; i < n; i++)
      if (phm_py_parse_law(PyList_GET_ITEM(nodes, i), nd + i, keep, what, depth + 1) < 0) return -1;
    law->nnodes = (int)n;
    law->nodes = nd;
  }
  return 0;
}

/* The laws of column `col`: a list of n entries, into the n structs at `items`. */
int phm_py_fill_laws(const component *cp, const column *col, PyObject *list, npy_intp n, char *items,
                     PyObject *keep) {
  if (!PyList_Check(list) || PyList_GET_SIZE(list) != n) {
    PyErr_Format(phm_py_ModelError, "%s: expected a list with one law per %s", col->what, cp->noun);
    return -1;
  }
  for (npy_intp i = 0; i < n; i++) {
    char *item = items + (size_t)i * cp->size;
    PyObject *lw = PyList_GET_ITEM(list, i);
    if (col->kind == COL_XLAWS) {
      phm_pair_desc *pr = (phm_pair_desc *)item;
      if (lw == Py_None) continue;
      if (!PyList_Check(lw) || PyList_GET_SIZE(lw) > 6) {
        PyErr_Format(phm_py_ModelError, "%s %ld: expected None or a list of at most 6 laws (None: not driven)", col->label, (long)i);
        return -1;
      }
      for (Py_ssize_t c = 0; c < PyList_GET_SIZE(lw); c++) {
        PyObject *lc = PyList_GET_ITEM(lw, c);
        if (lc == Py_None) continue;
        if (phm_py_parse_law(lc, &pr->xlaw[c], keep, col->label, 0) < 0) return -1;
        pr->xdriven |= 1 << c;
      }
      continue;
    }
    int wanted = col->rule == LAW_ALWAYS || (col->rule == LAW_OR_NONE && lw != Py_None) ||
                 (col->rule == LAW_IF_DRIVEN && ((const phm_pair_desc *)item)->driven);
    if (wanted && phm_py_parse_law(lw, (phm_law *)(item + col->offset[0]), keep, col->label, 0) < 0) return -1;
  }
  return 0;
}

/* After a call into the core: the first exception a CALLBACK law's callable kept (its `error`
 * attribute, which is then cleared) is raised; -1 then, else 0. `keep`: the model's list. */
int phm_py_law_error(PyObject *keep) {
  if (!keep || !PyList_Check(keep)) return 0;
  for (Py_ssize_t i = 0; i < PyList_GET_SIZE(keep); i++) {
    PyObject *o = PyList_GET_ITEM(keep, i);
    if (!PyCallable_Check(o) || PyCapsule_CheckExact(o) || !PyObject_HasAttrString(o, "error")) continue;
    PyObject *e = PyObject_GetAttrString(o, "error");
    if (!e) return -1;
    if (e != Py_None && PyExceptionInstance_Check(e)) {
      if (PyObject_SetAttrString(o, "error", Py_None) < 0) {
        Py_DECREF(e);
        return -1;
      }
      PyErr_SetObject((PyObject *)Py_TYPE(e), e);
      Py_DECREF(e);
      return -1;
    }
    Py_DECREF(e);
  }
  return 0;
}

int phm_py_model_law_error(PyObject *cap) { return phm_py_law_error((PyObject *)PyCapsule_GetContext(cap)); }

/* law_eval(law tuple, times) -> (n, 3): s, s', s'' of one law at each time (its piece: that of
 * the time itself, as tref = t), after the core's validation (ModelError). */
static PyObject *py_law_eval(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *lo, *to;
  if (!PyArg_ParseTuple(args, "OO", &lo, &to)) return NULL;
  PyObject *keep = PyList_New(0);
  if (!keep) return NULL;
  PyObject *res = NULL;
  PyArrayObject *T = NULL, *out = NULL;
  phm_law law;
  phm_error err;
  if (phm_py_parse_law(lo, &law, keep, "law", 0) < 0) goto done;
  if (phm_law_check(&law, "law", 0, &err)) {
    phm_py_raise(&err);
    goto done;
  }
  if (!(T = phm_py_double_array(to, "times", NULL, 0, 1))) goto done;
  npy_intp n = PyArray_SIZE(T), dims[2] = {n, 3};
  if (!(out = (PyArrayObject *)PyArray_ZEROS(2, dims, NPY_DOUBLE, 0))) goto done;
  const double *t = PyArray_DATA(T);
  double *o = PyArray_DATA(out);
  for (npy_intp i = 0; i < n; i++) o[3 * i] = phm_law_eval(&law, t[i], t[i], o + 3 * i + 1, o + 3 * i + 2);
  if (phm_py_law_error(keep)) goto done;
  res = (PyObject *)out;
  out = NULL;
done:
  Py_XDECREF(out);
  Py_XDECREF(T);
  Py_DECREF(keep);
  return res;
}

PyMethodDef phm_py_law_methods[] = {
    {"law_eval", py_law_eval, METH_VARARGS,
     "law_eval(law, times) -> (n, 3) array of s, s', s'' (csrc/util/law.c) of a law tuple "
     "(python/phmech/_marshal.py) at each time; ModelError for an invalid law."},
    {NULL, NULL, 0, NULL}};
