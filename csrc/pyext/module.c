/* module.c -- phmech._core: module init, exceptions, info(), and array conversion helpers. */
#define PHM_PYEXT_MAIN
#include "pyext.h"

#include <dlfcn.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "linalg.h"          /* dsyev_: which LAPACK the core calls (build_info) */
#include "sundials_compat.h" /* SUNDIALS_VERSION: the headers built against, 6.x or 7.x */

PyObject *phm_py_ModelError = NULL;
PyObject *phm_py_SolverError = NULL;

PyObject *phm_py_raise(const phm_error *err) {
  PyObject *type = PyExc_RuntimeError;
  switch (err->code) {
  case PHM_EINVAL: type = phm_py_ModelError; break;
  case PHM_ENOMEM: type = PyExc_MemoryError; break;
  case PHM_EINTERRUPT: type = PyExc_KeyboardInterrupt; break;
  default: type = phm_py_SolverError; break;
  }
  PyObject *exc = PyObject_CallFunction(type, "s", err->msg[0] ? err->msg : "phmech: unspecified error");
  if (!exc) return NULL;
  /* where in the core it was raised (csrc/util/phm_check.h), for bug reports */
  PyObject *where = err->file ? PyUnicode_FromFormat("%s:%d", err->file, err->line) : Py_NewRef(Py_None);
  if (where) {
    PyObject_SetAttrString(exc, "core_location", where);
    Py_DECREF(where);
  }
  PyErr_Clear(); /* a failed attribute set only loses the location */
  PyErr_SetObject(type, exc);
  Py_DECREF(exc);
  return NULL;
}

PyObject *phm_py_str_tuple(const char *const *s, int n) {
  PyObject *t = PyTuple_New(n);
  for (int i = 0; t && i < n; i++) {
    PyObject *v = PyUnicode_FromString(s[i] ? s[i] : "");
    if (!v) Py_CLEAR(t);
    else PyTuple_SET_ITEM(t, i, v);
  }
  return t;
}

PyObject *phm_py_list(int n, PyObject *(*item)(int i, const void *ctx), const void *ctx) {
  PyObject *l = PyList_New(n);
  for (int i = 0; l && i < n; i++) {
    PyObject *o = item(i, ctx);
    if (!o) Py_CLEAR(l);
    else PyList_SET_ITEM(l, i, o);
  }
  return l;
}

static PyObject *int_item(int i, const void *v) { return PyLong_FromLong(((const int *)v)[i]); }

PyObject *phm_py_int_list(const int *v, int n) { return phm_py_list(n, int_item, v); }

PyArrayObject *phm_py_double_array(PyObject *obj, const char *what, const npy_intp *tail, int ntail,
                                   int stack) {
  /* Convert with NumPy's natural dtype first, so strings, bytes, complex numbers and objects
   * (None, mixed types) are refused by kind instead of being parsed or truncated by a cast. */
  if (PyUnicode_Check(obj) || PyBytes_Check(obj)) {
    PyErr_Format(phm_py_ModelError, "%s: expected an array of real numbers, got a string", what);
    return NULL;
  }
  PyArrayObject *raw = (PyArrayObject *)PyArray_FromAny(obj, NULL, 0, 0, 0, NULL);
  if (!raw) {
    PyErr_Clear();
    PyErr_Format(phm_py_ModelError, "%s: expected an array of real numbers", what);
    return NULL;
  }
  int t = PyArray_TYPE(raw);
  if (!(PyTypeNum_ISBOOL(t) || PyTypeNum_ISINTEGER(t) || PyTypeNum_ISFLOAT(t))) {
    const char *kind = PyTypeNum_ISCOMPLEX(t)  ? "complex"
                       : PyTypeNum_ISSTRING(t) ? "string"
                       : PyTypeNum_ISOBJECT(t) ? "object (e.g. None or mixed types)"
                                               : "non-numeric";
    PyErr_Format(phm_py_ModelError, "%s: expected an array of real numbers, got %s values", what,
                 kind);
    Py_DECREF(raw);
    return NULL;
  }
  PyArrayObject *a = (PyArrayObject *)PyArray_FromAny(
      (PyObject *)raw, PyArray_DescrFromType(NPY_DOUBLE), 0, 0, NPY_ARRAY_CARRAY_RO, NULL);
  Py_DECREF(raw);
  if (!a) return NULL;
  int nd = PyArray_NDIM(a);
  int ok = stack ? nd >= ntail : nd == ntail;
  for (int i = 0; ok && i < ntail; i++) ok = PyArray_DIM(a, nd - ntail + i) == tail[i];
  if (!ok) {
    char want[64] = "", got[64] = "";
    size_t n = 0;
    for (int i = 0; i < ntail && n < sizeof want; i++)
      n += (size_t)snprintf(want + n, sizeof want - n, i ? ", %ld" : "%ld", (long)tail[i]);
    n = 0;
    for (int i = 0; i < nd && n < sizeof got; i++)
      n += (size_t)snprintf(got + n, sizeof got - n, i ? ", %ld" : "%ld", (long)PyArray_DIM(a, i));
    PyErr_Format(phm_py_ModelError, "%s: expected shape (%s%s), got (%s)", what,
                 stack ? "..., " : "", want, got);
    Py_DECREF(a);
    return NULL;
  }
  const double *d = (const double *)PyArray_DATA(a);
  npy_intp size = PyArray_SIZE(a);
  for (npy_intp i = 0; i < size; i++) {
    if (!isfinite(d[i])) {
      PyErr_Format(phm_py_ModelError, "%s: contains a non-finite value (NaN or inf)", what);
      Py_DECREF(a);
      return NULL;
    }
  }
  return a;
}

/* The LAPACK the core runs with: the file its dsyev_ was resolved to at load time (Debian's
 * alternatives may point liblapack.so.3 at the reference LAPACK, OpenBLAS or another, and may
 * change after the build), with symbolic links resolved. */
static void lapack_library(char *out, size_t n) {
  void (*fn)(void) = (void (*)(void))dsyev_;
  void *addr;
  memcpy(&addr, &fn, sizeof addr);
  Dl_info dl;
  char real[PATH_MAX];
  const char *name = "unknown";
  if (dladdr(addr, &dl) && dl.dli_fname && dl.dli_fname[0])
    name = realpath(dl.dli_fname, real) ? real : dl.dli_fname;
  snprintf(out, n, "%s", name);
}

static PyObject *py_build_info(PyObject *self, PyObject *args) {
  (void)self;
  (void)args;
  char lapack[PATH_MAX];
  lapack_library(lapack, sizeof lapack);
  return Py_BuildValue("{s:s,s:s,s:s,s:s,s:s}", "phmech_core", PHM_VERSION, "sundials",
                       SUNDIALS_VERSION, "linear_solvers", "dense, KLU (SuiteSparse)", "lapack",
                       lapack, "compiler", PHM_COMPILER_NAME);
}

/* The LAPACK the core links may be OpenBLAS (Debian's alternatives), with a thread pool whose
 * threads spin while they wait: on the core's small and medium dense problems (statics, modes,
 * initial values) they cost more CPU than they save, and they compete with other processes on a
 * shared machine (a 10-element cantilever's static solve: 0.17 s CPU with the default threads,
 * 0.014 s with one, on 2 cores). phmech sets the count at import (PHMECH_BLAS_THREADS, default 1). */
typedef void (*set_threads_fn)(int);
typedef int (*get_threads_fn)(void);

static void *openblas_symbol(const char *name) {
  static const char *libs[] = {"libopenblas.so.0", "libopenblasp-r0.so", "libopenblas.so"};
  for (size_t i = 0; i < sizeof libs / sizeof libs[0]; i++) {
    void *h = dlopen(libs[i], RTLD_LAZY | RTLD_NOLOAD); /* only if the core already loaded it */
    if (h) {
      void *f = dlsym(h, name);
      dlclose(h);
      if (f) return f;
    }
  }
  return NULL;
}

static PyObject *py_blas_threads(PyObject *self, PyObject *args) {
  (void)self;
  int n = 0;
  if (!PyArg_ParseTuple(args, "|i", &n)) return NULL;
  if (n < 0) {
    PyErr_SetString(phm_py_ModelError, "the number of BLAS threads must be >= 1 (0: just query)");
    return NULL;
  }
  set_threads_fn set = (set_threads_fn)openblas_symbol("openblas_set_num_threads");
  get_threads_fn get = (get_threads_fn)openblas_symbol("openblas_get_num_threads");
  if (!get) Py_RETURN_NONE; /* not OpenBLAS: single-threaded reference BLAS */
  if (n > 0 && set) set(n);
  return PyLong_FromLong(get());
}

static PyMethodDef module_methods[] = {
    {"build_info", py_build_info, METH_NOARGS,
     "build_info() -> dict: versions of the C core and of the libraries it was linked against."},
    {"blas_threads", py_blas_threads, METH_VARARGS,
     "blas_threads(n=0) -> int or None: set (n >= 1) and return the thread count of the OpenBLAS "
     "the core uses; None when its BLAS is not OpenBLAS (single-threaded)."},
    {NULL, NULL, 0, NULL}};

static PyMethodDef *all_tables[] = {module_methods, phm_py_se3_methods, phm_py_mixed_methods,
                                    phm_py_model_methods, phm_py_law_methods, phm_py_simulate_methods,
                                    phm_py_analysis_methods, phm_py_planar_methods, phm_py_pair_methods,
                                    phm_py_codes_methods};

static struct PyModuleDef core_module = {PyModuleDef_HEAD_INIT, "phmech._core",
                                         "phmech C core (SE(3) algebra, components, DAE, IDA).", -1,
                                         NULL, NULL, NULL, NULL, NULL};

static int add_table(PyObject *m, PyMethodDef *table) {
  return PyModule_AddFunctions(m, table);
}

PyMODINIT_FUNC PyInit__core(void) {
  import_array();
  PyObject *m = PyModule_Create(&core_module);
  if (!m) return NULL;
  for (size_t i = 0; i < sizeof all_tables / sizeof all_tables[0]; i++)
    if (add_table(m, all_tables[i]) < 0) goto fail;
  phm_py_ModelError = PyErr_NewExceptionWithDoc(
      "phmech.ModelError", "An invalid model, parameter or argument.", PyExc_ValueError, NULL);
  phm_py_SolverError = PyErr_NewExceptionWithDoc(
      "phmech.SolverError", "The integrator or a nonlinear solver failed.", PyExc_RuntimeError,
      NULL);
  if (!phm_py_ModelError || !phm_py_SolverError) goto fail;
  Py_INCREF(phm_py_ModelError);
  Py_INCREF(phm_py_SolverError);
  if (PyModule_AddObject(m, "ModelError", phm_py_ModelError) < 0) goto fail;
  if (PyModule_AddObject(m, "SolverError", phm_py_SolverError) < 0) goto fail;
  /* meson.build's project version (phmech.__version__) */
  if (PyModule_AddStringConstant(m, "__version__", PHM_VERSION) < 0) goto fail;
  return m;
fail:
  Py_DECREF(m);
  return NULL;
}
