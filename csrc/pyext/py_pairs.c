/* py_pairs.c -- the pair table (csrc/model/pair_types.c) for Python: phmech._core.pair_types() lists
 * every type with its parameters, units and constraint directions, from which python/phmech
 * builds its pair classes; pair_pose / pair_coordinates give a type's kinematics alone. */
#include "pyext.h"

#include <string.h>

/* Pair type i as a dict (pair_types). */
static PyObject *pair_type_dict(int i, const void *ctx) {
  (void)ctx;
  const phm_pair_type_info *t = phm_pair_type(i);
  int k = 6 - t->m;
  PyObject *units = phm_py_str_tuple(t->units, k), *dirs = phm_py_str_tuple(t->directions, t->m);
  PyObject *d = units && dirs ? Py_BuildValue("{s:i,s:s,s:i,s:i,s:s,s:O,s:O,s:O,s:i,s:s}", "code", i,
                                              "name", t->name, "k", k, "m", t->m, "params",
                                              t->params, "units", units, "directions", dirs,
                                              "drivable", t->drivable ? Py_True : Py_False,
                                              "xdrivable", t->xdrivable, "doc", t->doc)
                              : NULL;
  Py_XDECREF(units);
  Py_XDECREF(dirs);
  return d;
}

static PyObject *py_pair_types(PyObject *self, PyObject *noargs) {
  (void)self;
  (void)noargs;
  return phm_py_list(phm_pair_type_count(), pair_type_dict, NULL);
}

/* The type code and pitch arguments, checked. */
static int type_pitch(int type, double pitch) {
  if (type < 0 || type >= phm_pair_type_count()) {
    PyErr_Format(phm_py_ModelError, "unknown pair type %d", type);
    return -1;
  }
  if (!isfinite(pitch)) {
    PyErr_SetString(phm_py_ModelError, "pair pitch must be finite");
    return -1;
  }
  return 0;
}

static PyObject *py_pair_pose(PyObject *self, PyObject *args) {
  (void)self;
  int type;
  double pitch;
  PyObject *xo;
  if (!PyArg_ParseTuple(args, "idO", &type, &pitch, &xo) || type_pitch(type, pitch)) return NULL;
  npy_intp k = 6 - phm_pair_type(type)->m, dims[2] = {4, 4};
  PyArrayObject *x = phm_py_double_array(xo, "joint coordinates", &k, 1, 0);
  if (!x) return NULL;
  PyArrayObject *h = (PyArrayObject *)PyArray_SimpleNew(2, dims, NPY_DOUBLE);
  if (h) phm_pair_type_pose(type, pitch, (const double *)PyArray_DATA(x), (double *)PyArray_DATA(h));
  Py_DECREF(x);
  return (PyObject *)h;
}

static PyObject *py_pair_coordinates(PyObject *self, PyObject *args) {
  (void)self;
  int type;
  double pitch;
  PyObject *ho, *xro = Py_None;
  if (!PyArg_ParseTuple(args, "idO|O", &type, &pitch, &ho, &xro) || type_pitch(type, pitch)) return NULL;
  npy_intp k = 6 - phm_pair_type(type)->m, t44[2] = {4, 4};
  PyArrayObject *h = phm_py_double_array(ho, "relative pose", t44, 2, 0), *xr = NULL, *x = NULL;
  if (h && xro != Py_None) xr = phm_py_double_array(xro, "reference joint coordinates", &k, 1, 0);
  if (h && (xro == Py_None || xr)) {
    double out[6];
    phm_pair_type_coordinates(type, pitch, (const double *)PyArray_DATA(h),
                              xr ? (const double *)PyArray_DATA(xr) : NULL, out);
    x = (PyArrayObject *)PyArray_SimpleNew(1, &k, NPY_DOUBLE);
    if (x) memcpy(PyArray_DATA(x), out, sizeof(double) * (size_t)k);
  }
  Py_XDECREF(h);
  Py_XDECREF(xr);
  return (PyObject *)x;
}

PyMethodDef phm_py_pair_methods[] = {
    {"pair_types", py_pair_types, METH_NOARGS,
     "pair_types() -> list of dict: the core's pair table (code, name, k, m, params, units, "
     "directions, drivable, xdrivable (bit c: joint coordinate c can follow a law), doc), in "
     "type-code order."},
    {"pair_pose", py_pair_pose, METH_VARARGS,
     "pair_pose(type, pitch, x (k,)) -> (4,4): relative pose h(x) of a pair type's frames."},
    {"pair_coordinates", py_pair_coordinates, METH_VARARGS,
     "pair_coordinates(type, pitch, h (4,4), xref (k,) = None) -> (k,): joint coordinates of a "
     "relative pose, angles nearest xref (None: principal values; helical: the turn nearest the "
     "translation)."},
    {NULL, NULL, 0, NULL}};
