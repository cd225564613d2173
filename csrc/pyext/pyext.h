/* pyext.h -- shared by the files of the phmech._core extension (the only code that sees Python.h).
 * Each binding file exports a NULL-terminated PyMethodDef table; module.c concatenates them. */
#ifndef PHM_PYEXT_H
#define PHM_PYEXT_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#define PY_ARRAY_UNIQUE_SYMBOL phm_ARRAY_API
#ifndef PHM_PYEXT_MAIN
#define NO_IMPORT_ARRAY
#endif
#include <numpy/arrayobject.h>

#include <math.h>

#include "phmech.h"

/* Exception types, created at import: ModelError(ValueError), SolverError(RuntimeError). */
extern PyObject *phm_py_ModelError;
extern PyObject *phm_py_SolverError;

/* Raise the Python exception matching err->code with err->msg; returns NULL for `return`. */
PyObject *phm_py_raise(const phm_error *err);

/* Convert obj to a C-contiguous float64 array whose trailing dimensions equal `tail`
 * (ntail of them; any number of leading "stack" dimensions allowed when stack != 0).
 * Rejects non-numeric input and non-finite values with phmech.ModelError (a ValueError) naming
 * `what`.
 * Returns a new reference or NULL with an exception set. */
PyArrayObject *phm_py_double_array(PyObject *obj, const char *what, const npy_intp *tail, int ntail,
                                   int stack);

/* A tuple of the n strings s (NULL entries as ""), a list of the n ints v, or the list
 * [item(0, ctx), ..., item(n - 1, ctx)] (item: a new reference, or NULL with an exception set):
 * a new reference, or NULL with an exception set (csrc/pyext/module.c). */
PyObject *phm_py_str_tuple(const char *const *s, int n);
PyObject *phm_py_int_list(const int *v, int n);
PyObject *phm_py_list(int n, PyObject *(*item)(int i, const void *ctx), const void *ctx);

/* Method tables of the binding files. */
extern PyMethodDef phm_py_se3_methods[];
extern PyMethodDef phm_py_mixed_methods[];
extern PyMethodDef phm_py_model_methods[];    /* py_model.c: model_new and its queries */
extern PyMethodDef phm_py_law_methods[];      /* py_laws.c */
extern PyMethodDef phm_py_simulate_methods[]; /* py_simulate.c */
extern PyMethodDef phm_py_analysis_methods[]; /* py_analyses.c: modes, linear model, statics */
extern PyMethodDef phm_py_planar_methods[];   /* py_planar.c */
extern PyMethodDef phm_py_pair_methods[];
extern PyMethodDef phm_py_codes_methods[];

#endif
