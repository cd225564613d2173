/* py_model.c -- bindings of the model, simulation, modes and statics (csrc/model/, csrc/dae/,
 * csrc/solve/). A model lives in a capsule; python/phmech/_marshal.py builds its description,
 * one dict of columns per component kind (COMPONENTS below). */
#include "pyext.h"

#include <limits.h>
#include <math.h>
#include <string.h>

#define CAPSULE_NAME "phmech.model"

/* A model's capsule keeps, as its context, the list of what its laws refer to (the callables of
 * CALLBACK laws): alive as long as the model. */
static void capsule_free(PyObject *cap) {
  phm_model *m = (phm_model *)PyCapsule_GetPointer(cap, CAPSULE_NAME);
  Py_XDECREF((PyObject *)PyCapsule_GetContext(cap));
  phm_model_free(m);
}

static phm_model *get_model(PyObject *cap) {
  return (phm_model *)PyCapsule_GetPointer(cap, CAPSULE_NAME);
}

/* An index or enumeration code given as float64 (the columns of python/phmech/_marshal.py): it
 * must be a whole number representable as int (the core then checks its range); converting
 * anything else to int would truncate (1.5 -> carrier 1) or be undefined behaviour (1e20, C11
 * 6.3.1.4). */
static int to_int(double v, const char *what, npy_intp i, int *out) {
  if (!(v >= INT_MIN && v <= INT_MAX && v == floor(v))) {
    char got[32];
    snprintf(got, sizeof got, "%.17g", v);
    PyErr_Format(phm_py_ModelError, "%s %ld: expected a whole number, got %s", what, (long)i, got);
    return -1;
  }
  *out = (int)v;
  return 0;
}

/* ---------------------------------------------------------------- model_new
 * One description per component kind: a dict of columns, each with one row per component (see
 * python/phmech/_marshal.py). The tables below say, for each column, its key, its name in
 * messages, how its values are read and where they go in the core's description struct
 * (csrc/phmech.h, phm_*_desc). The first column of a kind gives the number of components. */
typedef enum {
  COL_REALS, /* doubles, copied                                                       */
  COL_INDEX, /* whole numbers to int fields (indices, codes); a tail (2) fills two fields */
  COL_FLAG,  /* nonzero -> 1                                                          */
  COL_DROP,  /* redundant-row mask, an integer in [0, 64)                             */
  COL_LAW,   /* a list with one law tuple (or None, see law_rule) per component          */
  COL_XLAWS  /* pairs: a list with, per pair, None or k entries (a law tuple or None per
              * joint coordinate): the coordinates that follow a law (xdriven, xlaw)     */
} column_kind;

typedef enum {
  LAW_ALWAYS,    /* every component has a law                                  */
  LAW_OR_NONE,   /* None: no law (actuators that use none)                     */
  LAW_IF_DRIVEN  /* read for driven pairs only (their `driven` column comes first) */
} law_rule;

typedef struct {
  const char *key;   /* key in the component's dict                                      */
  const char *what;  /* name in messages                                                 */
  column_kind kind;
  int ntail;         /* shape of one row                                                 */
  npy_intp tail[2];
  size_t offset[2];  /* where the row goes in the struct (COL_INDEX with tail (2): two fields) */
  const char *label; /* COL_INDEX: "<label> <i>: expected a whole number"; COL_LAW: the law's name */
  law_rule rule;     /* COL_LAW                                                          */
} column;

typedef struct {
  const char *name;  /* argument of model_new                                            */
  const char *noun;  /* one component, in messages                                       */
  size_t size;       /* sizeof its description struct                                    */
  const column *columns;
  int ncolumns;
} component;

#define SCALAR(key, what, st, field) {key, what, COL_REALS, 0, {0}, {offsetof(st, field), 0}, NULL, 0}
#define VECTOR(key, what, st, field, n) {key, what, COL_REALS, 1, {n}, {offsetof(st, field), 0}, NULL, 0}
#define MATRIX(key, what, st, field, r, c) \
  {key, what, COL_REALS, 2, {r, c}, {offsetof(st, field), 0}, NULL, 0}
#define INDEX(key, what, st, field, label) \
  {key, what, COL_INDEX, 0, {0}, {offsetof(st, field), 0}, label, 0}
#define INDEX2(key, what, st, a, b, label) \
  {key, what, COL_INDEX, 1, {2}, {offsetof(st, a), offsetof(st, b)}, label, 0}
#define FLAG(key, what, st, field) {key, what, COL_FLAG, 0, {0}, {offsetof(st, field), 0}, NULL, 0}
#define LAW(key, what, st, field, label, rule) \
  {key, what, COL_LAW, 0, {0}, {offsetof(st, field), 0}, label, rule}

static const column carrier_columns[] = {
    SCALAR("mass", "carrier masses", phm_carrier_desc, mass),
    MATRIX("M", "carrier inertias", phm_carrier_desc, M, 6, 6),
    VECTOR("com", "centres of mass", phm_carrier_desc, com, 3),
    MATRIX("H0", "carrier poses", phm_carrier_desc, H0, 4, 4),
    VECTOR("t0", "carrier twists", phm_carrier_desc, t0, 6),
};
static const column element_columns[] = {
    SCALAR("h", "element lengths", phm_element_desc, h),
    INDEX2("nodes", "element nodes", phm_element_desc, a, b, "element"),
    MATRIX("K", "element stiffness", phm_element_desc, K, 6, 6),
    MATRIX("D", "element damping", phm_element_desc, D, 6, 6),
    VECTOR("eps_hat", "element unstressed strain", phm_element_desc, eps_hat, 6),
    INDEX("mass", "element mass kinds", phm_element_desc, mass, "mass kind of element"),
    MATRIX("Ms", "element section inertias", phm_element_desc, Ms, 6, 6),
    MATRIX("Mc", "element mass couplings", phm_element_desc, Mc, 12, 12),
};
static const column pair_columns[] = {
    INDEX("type", "pair types", phm_pair_desc, type, "pair type of pair"),
    INDEX2("carriers", "pair carriers", phm_pair_desc, a, b, "pair"),
    MATRIX("Ta", "pair frames Ta", phm_pair_desc, Ta, 4, 4),
    MATRIX("Tb", "pair frames Tb", phm_pair_desc, Tb, 4, 4),
    FLAG("driven", "pair driven flags", phm_pair_desc, driven),
    VECTOR("axis", "pair motion axes", phm_pair_desc, axis, 6),
    LAW("law", "pair laws", phm_pair_desc, law, "pair motion law", LAW_IF_DRIVEN),
    {"xlaws", "pair joint laws", COL_XLAWS, 0, {0}, {offsetof(phm_pair_desc, xlaw), 0}, "pair joint law", 0},
    SCALAR("pitch", "pair pitches", phm_pair_desc, pitch),
    VECTOR("x0", "pair initial coordinates", phm_pair_desc, x0, 6),
    FLAG("has_x0", "pair x0 flags", phm_pair_desc, has_x0),
    {"drop", "pair drop masks", COL_DROP, 0, {0}, {offsetof(phm_pair_desc, drop), 0}, NULL, 0},
};
static const column load_columns[] = {
    INDEX("carrier", "load carriers", phm_load_desc, carrier, "load"),
    FLAG("world", "load frames", phm_load_desc, world),
    VECTOR("point", "load points", phm_load_desc, point, 3),
    VECTOR("w", "load wrenches", phm_load_desc, w, 6),
    LAW("law", "load laws", phm_load_desc, law, "load law", LAW_ALWAYS),
    INDEX("reaction", "load reactions", phm_load_desc, reaction, "reaction of load"),
};
static const column actuator_columns[] = {
    INDEX("pair", "actuator pairs", phm_actuator_desc, pair, "pair of actuator"),
    INDEX("kind", "actuator kinds", phm_actuator_desc, kind, "kind of actuator"),
    VECTOR("vec", "actuator vectors", phm_actuator_desc, vec, 6),
    VECTOR("kp", "actuator kp", phm_actuator_desc, kp, 6),
    VECTOR("kd", "actuator kd", phm_actuator_desc, kd, 6),
    VECTOR("x_set", "actuator set points", phm_actuator_desc, x_set, 6),
    LAW("law", "actuator laws", phm_actuator_desc, law, "actuator law", LAW_OR_NONE),
};
static const column spring_columns[] = {
    SCALAR("k", "spring stiffnesses", phm_spring_desc, k),
    INDEX2("carriers", "spring carriers", phm_spring_desc, a, b, "spring"),
    VECTOR("pa", "spring points a", phm_spring_desc, pa, 3),
    VECTOR("pb", "spring points b", phm_spring_desc, pb, 3),
    SCALAR("c", "spring damping coefficients", phm_spring_desc, c),
    SCALAR("rest_length", "spring rest lengths", phm_spring_desc, d0),
};

static const column coupling_columns[] = {
    MATRIX("Mc", "mass couplings", phm_coupling_desc, Mc, 12, 12),
    INDEX2("carriers", "coupled carriers", phm_coupling_desc, a, b, "coupling"),
};

#define KIND(name, noun, st, cols) {name, noun, sizeof(st), cols, (int)(sizeof cols / sizeof cols[0])}
enum { NKINDS = 7 };
static const component COMPONENTS[NKINDS] = {
    KIND("carriers", "carrier", phm_carrier_desc, carrier_columns),
    KIND("elements", "element", phm_element_desc, element_columns),
    KIND("pairs", "pair", phm_pair_desc, pair_columns),
    KIND("loads", "load", phm_load_desc, load_columns),
    KIND("actuators", "actuator", phm_actuator_desc, actuator_columns),
    KIND("springs", "spring", phm_spring_desc, spring_columns),
    KIND("couplings", "coupling", phm_coupling_desc, coupling_columns),
};

/* ---------------------------------------------------------------- laws
 * A law tuple (python/phmech/_marshal.py, _law): (kind, amplitude, t0, duration, frequency,
 * phase, offset, data, order, nodes, fn): data None or a float array (TABLE: its (t, s) points;
 * PPOLY: the breaks then the coefficients, `order` per piece; CALLBACK: its breakpoints), nodes
 * None or the list of an expression's node tuples (postfix), fn None or the callable of a
 * CALLBACK law: fn(t, nder) -> (s, s', s'') or None when it failed (the Python side keeps the
 * exception in the callable's `error`; law_error re-raises it). What the law points to is kept
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

/* CALLBACK trampoline: the callable's (s, s', s'') with the GIL (the integrators run without
 * it); any failure (an exception the callable did not keep, a malformed result) is -1. */
static int law_callback(void *ctx, double t, int nder, double out[3]) {
  PyGILState_STATE g = PyGILState_Ensure();
  int rc = -1;
  PyObject *r = PyObject_CallFunction((PyObject *)ctx, "di", t, nder);
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

static int parse_law(PyObject *obj, phm_law *law, PyObject *keep, const char *what, int depth) {
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
      if (parse_law(PyList_GET_ITEM(nodes, i), nd + i, keep, what, depth + 1) < 0) return -1;
    law->nnodes = (int)n;
    law->nodes = nd;
  }
  return 0;
}

/* The laws of column `col`: a list of n entries, into the n structs at `items`. */
static int fill_laws(const component *cp, const column *col, PyObject *list, npy_intp n, char *items,
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
        if (parse_law(lc, &pr->xlaw[c], keep, col->label, 0) < 0) return -1;
        pr->xdriven |= 1 << c;
      }
      continue;
    }
    int wanted = col->rule == LAW_ALWAYS || (col->rule == LAW_OR_NONE && lw != Py_None) ||
                 (col->rule == LAW_IF_DRIVEN && ((const phm_pair_desc *)item)->driven);
    if (wanted && parse_law(lw, (phm_law *)(item + col->offset[0]), keep, col->label, 0) < 0) return -1;
  }
  return 0;
}

/* After a call into the core: the first exception a CALLBACK law's callable kept (its `error`
 * attribute, which is then cleared) is raised; -1 then, else 0. `keep`: the model's list. */
static int law_error(PyObject *keep) {
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

static int model_law_error(PyObject *cap) { return law_error((PyObject *)PyCapsule_GetContext(cap)); }

/* The numeric column `col` (an array of shape (n, tail)) into the n structs at `items`. */
static int fill_numbers(const component *cp, const column *col, PyArrayObject *a, npy_intp n, char *items) {
  npy_intp width = 1;
  for (int t = 0; t < col->ntail; t++) width *= col->tail[t];
  const double *v = (const double *)PyArray_DATA(a);
  for (npy_intp i = 0; i < n; i++) {
    char *item = items + (size_t)i * cp->size;
    const double *row = v + i * width;
    switch (col->kind) {
    case COL_REALS: memcpy(item + col->offset[0], row, (size_t)width * sizeof(double)); break;
    case COL_INDEX:
      for (npy_intp j = 0; j < width; j++)
        if (to_int(row[j], col->label, i, (int *)(item + col->offset[j])) < 0) return -1;
      break;
    case COL_FLAG: *(int *)(item + col->offset[0]) = row[0] != 0; break;
    case COL_DROP:
      if (!(row[0] >= 0 && row[0] < 64 && row[0] == (int)row[0])) {
        PyErr_Format(phm_py_ModelError, "%s %d: drop mask must be an integer in [0, 64)", cp->noun, (int)i);
        return -1;
      }
      *(int *)(item + col->offset[0]) = (int)row[0];
      break;
    case COL_LAW: case COL_XLAWS: break;
    }
  }
  return 0;
}

/* ModelError unless every key of the dict `d` is a column of `cp`. */
static int known_columns(const component *cp, PyObject *d) {
  Py_ssize_t pos = 0;
  PyObject *key, *value;
  while (PyDict_Next(d, &pos, &key, &value)) {
    int known = 0;
    for (int c = 0; c < cp->ncolumns && !known; c++)
      known = PyUnicode_Check(key) && PyUnicode_CompareWithASCIIString(key, cp->columns[c].key) == 0;
    if (!known) {
      PyErr_Format(phm_py_ModelError, "%s: unknown column %R", cp->name, key);
      return -1;
    }
  }
  return 0;
}

/* The components of kind `cp` described by the dict `d`: *n of them in a new array *out (free
 * it); law tables are kept alive in `keep`. strict: refuse a column `cp` does not have (else
 * read only those it has). */
static int parse_component(const component *cp, PyObject *d, PyObject *keep, int strict, npy_intp *n,
                           void **out) {
  *out = NULL;
  *n = 0;
  if (!PyDict_Check(d)) {
    PyErr_Format(phm_py_ModelError, "%s: expected a dict of columns, one row per %s", cp->name, cp->noun);
    return -1;
  }
  if (strict && known_columns(cp, d) < 0) return -1;
  for (int c = 0; c < cp->ncolumns; c++) {
    const column *col = &cp->columns[c];
    PyObject *o = PyDict_GetItemString(d, col->key);
    if (!o) {
      PyErr_Format(phm_py_ModelError, "%s: missing the column '%s' (%s)", cp->name, col->key, col->what);
      return -1;
    }
    if (col->kind == COL_LAW || col->kind == COL_XLAWS) {
      if (fill_laws(cp, col, o, *n, (char *)*out, keep) < 0) return -1;
      continue;
    }
    npy_intp shape[3];
    shape[0] = *n;
    for (int t = 0; t < col->ntail; t++) shape[t + 1] = col->tail[t];
    /* the first column sets n: any leading length, checked to be one axis */
    PyArrayObject *a = c == 0 ? phm_py_double_array(o, col->what, col->tail, col->ntail, 1)
                              : phm_py_double_array(o, col->what, shape, col->ntail + 1, 0);
    if (!a) return -1;
    if (c == 0) {
      if (PyArray_NDIM(a) != col->ntail + 1) {
        PyErr_Format(phm_py_ModelError, "%s: expected a 1-D array", col->what);
        Py_DECREF(a);
        return -1;
      }
      *n = PyArray_DIM(a, 0);
      *out = calloc((size_t)*n + 1, cp->size);
      if (!*out) {
        Py_DECREF(a);
        PyErr_NoMemory();
        return -1;
      }
    }
    int r = fill_numbers(cp, col, a, *n, (char *)*out);
    Py_DECREF(a);
    if (r < 0) return -1;
  }
  if (*n > INT_MAX) {
    PyErr_Format(phm_py_ModelError, "%s: %ld of them, at most %d", cp->name, (long)*n, INT_MAX);
    return -1;
  }
  return 0;
}

static PyObject *py_model_new(PyObject *self, PyObject *args, PyObject *kw) {
  (void)self;
  static char *kwl[] = {"carriers", "elements", "pairs", "loads", "actuators", "springs", "gravity",
                        "couplings", NULL};
  /* o[6] gravity, o[7] the couplings (optional: none) */
  PyObject *o[NKINDS + 1] = {NULL};
  if (!PyArg_ParseTupleAndKeywords(args, kw, "OOOOOOO|O", kwl, &o[0], &o[1], &o[2], &o[3], &o[4], &o[5],
                                   &o[6], &o[7]))
    return NULL;
  PyObject *grav_arg = o[6];
  o[6] = o[7] == Py_None ? NULL : o[7]; /* None: no coupling, as when left out */
  PyObject *keep = PyList_New(0);
  if (!keep) return NULL;
  PyObject *result = NULL;
  void *items[NKINDS] = {NULL};
  npy_intp n[NKINDS] = {0};
  npy_intp g3[1] = {3};
  PyArrayObject *grav = NULL;
  for (int k = 0; k < NKINDS; k++)
    if (o[k] && parse_component(&COMPONENTS[k], o[k], keep, 1, &n[k], &items[k]) < 0) goto fail;
  if (!(grav = phm_py_double_array(grav_arg, "gravity", g3, 1, 0))) goto fail;
  {
    phm_model_desc d = {.ncarriers = (int)n[0], .carriers = items[0], .nelements = (int)n[1],
                        .elements = items[1], .npairs = (int)n[2], .pairs = items[2],
                        .nloads = (int)n[3], .loads = items[3], .nactuators = (int)n[4],
                        .actuators = items[4], .nsprings = (int)n[5], .springs = items[5],
                        .ncouplings = (int)n[6], .couplings = items[6]};
    memcpy(d.gravity, PyArray_DATA(grav), 3 * sizeof(double));
    phm_model *m = NULL;
    phm_error err;
    if (phm_model_create(&d, &m, &err)) {
      phm_py_raise(&err);
      goto fail;
    }
    result = PyCapsule_New(m, CAPSULE_NAME, capsule_free);
    if (!result) phm_model_free(m);
    else if (PyCapsule_SetContext(result, keep) == 0) Py_INCREF(keep);
    else Py_CLEAR(result);
  }
fail:
  for (int k = 0; k < NKINDS; k++) free(items[k]);
  Py_XDECREF(grav);
  Py_DECREF(keep);
  return result;
}

/* ---------------------------------------------------------------- simulate */
typedef struct {
  PyObject *cb;    /* progress callable(t, iout) -> truthy to stop, or None */
  int interrupted; /* Ctrl-C seen */
  int failed;      /* the callback raised */
  PyObject *et, *ev, *etb;
  PyObject *mon;   /* monitor callable(t, steps, h) -> truthy to stop, or None */
  int cb_stop;     /* the progress callable's answer at this output (interrupt_cb asks it) */
} cb_ctx;

/* With the GIL held: a pending signal (Ctrl-C, or SIGTERM when Python handles it) marks the run
 * interrupted; non-zero: stop. */
static int signal_pending(cb_ctx *c) {
  if (PyErr_CheckSignals() == 0) return 0;
  PyErr_Clear();
  c->interrupted = 1;
  return 1;
}

/* With the GIL held: the result r of a user callable; an exception is kept for re-raising after
 * the run. Non-zero: stop (the callable raised or returned something true). */
static int callable_says_stop(cb_ctx *c, PyObject *r) {
  if (!r) {
    PyErr_Fetch(&c->et, &c->ev, &c->etb);
    c->failed = 1;
    return 1;
  }
  int stop = PyObject_IsTrue(r);
  Py_DECREF(r);
  if (stop < 0) {   /* an answer that is no truth value: the callable's error, raised after the run */
    PyErr_Fetch(&c->et, &c->ev, &c->etb);
    c->failed = 1;
    return 1;
  }
  return stop;
}

/* Between outputs: pending signals, then the Python monitor, if any (progress line, cost
 * warnings). */
static int monitor_cb(void *vctx, double t, long nsteps, double h) {
  cb_ctx *c = (cb_ctx *)vctx;
  PyGILState_STATE g = PyGILState_Ensure();
  int stop = signal_pending(c);
  if (!stop && c->mon) stop = callable_says_stop(c, PyObject_CallFunction(c->mon, "dld", t, nsteps, h));
  PyGILState_Release(g);
  return stop;
}

/* At each output (dae_emit_output): pending signals (interrupt: non-zero), then, with the GIL
 * still held, the progress callable, whose answer progress_cb returns right after -- one GIL
 * round trip per output, not two, and its arguments by vectorcall, not a format string (a
 * small scene's outputs cost 3 % of its run in these two). */
static int interrupt_cb(void *vctx, double t, int iout) {
  cb_ctx *c = (cb_ctx *)vctx;
  PyGILState_STATE g = PyGILState_Ensure();
  int stop = signal_pending(c);
  c->cb_stop = 0;
  if (!stop && !c->cb && c->mon) {
    /* no per-output callable (no progress bar, checkpoint or user callback): only the monitor's
     * SIGTERM flag (_run.sigterm_as_interrupt), read here without a call into Python */
    static PyObject *terminated = NULL;
    if (!terminated) terminated = PyUnicode_InternFromString("terminated");
    PyObject *f = terminated ? PyObject_GetAttr(c->mon, terminated) : NULL;
    if (f) {
      int set = PyObject_IsTrue(f);
      Py_DECREF(f);
      if (set < 0) PyErr_Clear();   /* a flag that is no truth value: nothing to stop for */
      c->cb_stop = set == 1;
    } else {
      PyErr_Clear();   /* a monitor without the flag: nothing to stop for */
    }
  }
  if (!stop && c->cb) {
    PyObject *a[3] = {NULL, PyFloat_FromDouble(t), PyLong_FromLong(iout)}, *r = NULL;
    if (a[1] && a[2]) r = PyObject_Vectorcall(c->cb, a + 1, 2 | PY_VECTORCALL_ARGUMENTS_OFFSET, NULL);
    Py_XDECREF(a[1]);
    Py_XDECREF(a[2]);
    c->cb_stop = callable_says_stop(c, r);
  }
  PyGILState_Release(g);
  return stop;
}

static int progress_cb(void *vctx, double t, int iout) {
  (void)t;
  (void)iout;
  return ((cb_ctx *)vctx)->cb_stop;
}

/* {"t": tout, then each result array under its name (the result-field table,
 * csrc/util/codes.c)}: a new dict, or NULL with an exception set. */
static PyObject *result_arrays(PyArrayObject *tout, PyArrayObject *const ra[PHM_NRESULT_FIELDS]) {
  const phm_code_table *f = phm_code_table_named("result_fields");
  PyObject *d = PyDict_New();
  if (d && PyDict_SetItemString(d, "t", (PyObject *)tout) < 0) Py_CLEAR(d);
  for (int i = 0; d && i < f->nrows; i++)
    if (PyDict_SetItemString(d, f->rows[i].name, (PyObject *)ra[f->rows[i].value]) < 0) Py_CLEAR(d);
  return d;
}

static PyObject *py_model_simulate(PyObject *self, PyObject *args, PyObject *kw) {
  (void)self;
  static char *kwl[] = {"model", "tout", "rtol", "atol", "linear_solver", "poses", "twists",
                        "callback", "max_step", "max_order", "record", "error_test",
                        "integrator", "step", "rho_inf", "adaptive", "band", "monitor", "arrays", "planar", NULL};
  PyObject *cap, *to, *po = Py_None, *twi = Py_None, *cb = Py_None, *rec = Py_None, *mon = Py_None;
  PyObject *arr = Py_None; /* callable(dict of the output arrays), called once before the run */
  PyObject *res = NULL; /* before the first `goto fail0`: that path returns it */
  PyArrayObject *R = NULL; /* carriers to record (int array) or NULL: all */
  double rtol, atol, max_step = 0;
  int solver = 0, max_order = 0, error_test = 0, integrator = 0;
  double step = 0, rho_inf = 1, band = 0;
  int adaptive = 0, planar = 0;
  if (!PyArg_ParseTupleAndKeywords(args, kw, "OOddi|OOOdiOiiddidOOi", kwl, &cap, &to, &rtol, &atol, &solver,
                                   &po, &twi, &cb, &max_step, &max_order, &rec, &error_test,
                                   &integrator, &step, &rho_inf, &adaptive, &band, &mon, &arr,
                                   &planar))
    return NULL;
  phm_model *m = get_model(cap);
  if (!m) return NULL;
  int nc = phm_model_ncarriers(m), nk = phm_model_nconstraints(m), nj = phm_model_njoints(m),
      npt = phm_model_nports(m), npr = phm_model_npairs(m);
  PyArrayObject *tout = phm_py_double_array(to, "output times", NULL, 0, 1), *P = NULL, *T = NULL;
  if (!tout) return NULL;
  if (PyArray_NDIM(tout) != 1 || PyArray_DIM(tout, 0) < 1) {
    Py_DECREF(tout);
    PyErr_SetString(phm_py_ModelError, "output times: expected a non-empty 1-D array");
    return NULL;
  }
  npy_intp nout = PyArray_DIM(tout, 0);
  if (nout > INT_MAX) {
    Py_DECREF(tout);
    PyErr_Format(phm_py_ModelError, "output times: %ld of them, at most %d", (long)nout, INT_MAX);
    return NULL;
  }
  if (po != Py_None) {
    npy_intp tail[3] = {nc, 4, 4};
    if (!(P = phm_py_double_array(po, "initial poses", tail, 3, 0))) goto fail0;
  }
  if (twi != Py_None) {
    npy_intp tail[2] = {nc, 6};
    if (!(T = phm_py_double_array(twi, "initial twists", tail, 2, 0))) goto fail0;
  }
  if ((cb != Py_None && !PyCallable_Check(cb)) || (mon != Py_None && !PyCallable_Check(mon)) ||
      (arr != Py_None && !PyCallable_Check(arr))) {
    PyErr_SetString(PyExc_TypeError, "callback, monitor and arrays must be callable");
    goto fail0;
  }
  npy_intp nrec = nc;
  if (rec != Py_None) {
    R = (PyArrayObject *)PyArray_FROMANY(rec, NPY_INT, 1, 1, NPY_ARRAY_CARRAY | NPY_ARRAY_FORCECAST);
    if (!R) goto fail0;
    nrec = PyArray_DIM(R, 0);
    const int *ri = (const int *)PyArray_DATA(R);
    for (npy_intp k = 0; k < nrec; k++) {
      if (ri[k] < 0 || ri[k] >= nc) {
        PyErr_Format(phm_py_ModelError, "record: carrier index %d out of range [0, %d)", ri[k], nc);
        goto fail0;
      }
    }
  }
  /* the result arrays, in the result-field table's order (csrc/util/codes.c) */
  npy_intp dims[PHM_NRESULT_FIELDS][4] = {
      [PHM_RESULT_POSES] = {nout, nrec, 4, 4}, [PHM_RESULT_TWISTS] = {nout, nrec, 6},
      [PHM_RESULT_LAMBDA] = {nout, nk},        [PHM_RESULT_ENERGY] = {nout, PHM_NENERGY},
      [PHM_RESULT_JOINTS] = {nout, nj},        [PHM_RESULT_JRATES] = {nout, nj},
      [PHM_RESULT_EFFORTS] = {nout, nj},       [PHM_RESULT_PAIR_WRENCHES] = {nout, npr, 6},
      [PHM_RESULT_PORTS] = {nout, npt}};
  static const int ndims[PHM_NRESULT_FIELDS] = {[PHM_RESULT_POSES] = 4, [PHM_RESULT_TWISTS] = 3,
                                                [PHM_RESULT_LAMBDA] = 2, [PHM_RESULT_ENERGY] = 2,
                                                [PHM_RESULT_JOINTS] = 2, [PHM_RESULT_JRATES] = 2,
                                                [PHM_RESULT_EFFORTS] = 2, [PHM_RESULT_PAIR_WRENCHES] = 3,
                                                [PHM_RESULT_PORTS] = 2};
  PyArrayObject *ra[PHM_NRESULT_FIELDS] = {NULL};
  for (int i = 0; i < PHM_NRESULT_FIELDS; i++)
    if (!(ra[i] = (PyArrayObject *)PyArray_ZEROS(ndims[i], dims[i], NPY_DOUBLE, 0))) goto fail;
  if (arr != Py_None) { /* the arrays the run fills, output by output (a checkpoint reads the
                         * first i + 1 of them at output i: dae_emit_output stores before it calls) */
    PyObject *d = result_arrays(tout, ra), *r = d ? PyObject_CallFunctionObjArgs(arr, d, NULL) : NULL;
    Py_XDECREF(d);
    if (!r) goto fail;
    Py_DECREF(r);
  }
  cb_ctx c = {cb == Py_None ? NULL : cb, 0, 0, NULL, NULL, NULL, mon == Py_None ? NULL : mon, 0};
  phm_sim_options opt = {.rtol = rtol, .atol = atol, .linear_solver = solver, .max_steps = 0,
                         .max_step = max_step, .max_order = max_order, .error_test = error_test,
                         .interrupt = interrupt_cb, .progress = progress_cb, .ctx = &c,
                         .integrator = integrator, .step = step, .rho_inf = rho_inf,
                         .adaptive = adaptive, .band = band, .monitor = monitor_cb, .planar = planar};
  phm_sim_output out;
  memset(&out, 0, sizeof out);
  out.record = R ? (const int *)PyArray_DATA(R) : NULL;
  out.nrecord = (int)nrec;
  out.poses = PyArray_DATA(ra[PHM_RESULT_POSES]);
  out.twists = PyArray_DATA(ra[PHM_RESULT_TWISTS]);
  out.lambda = PyArray_DATA(ra[PHM_RESULT_LAMBDA]);
  out.energy = PyArray_DATA(ra[PHM_RESULT_ENERGY]);
  out.joints = PyArray_DATA(ra[PHM_RESULT_JOINTS]);
  out.jrates = PyArray_DATA(ra[PHM_RESULT_JRATES]);
  out.efforts = PyArray_DATA(ra[PHM_RESULT_EFFORTS]);
  out.pwrench = PyArray_DATA(ra[PHM_RESULT_PAIR_WRENCHES]);
  out.ports = PyArray_DATA(ra[PHM_RESULT_PORTS]);
  phm_error err;
  phm_status st;
  Py_BEGIN_ALLOW_THREADS
  st = phm_simulate(m, P ? PyArray_DATA(P) : NULL, T ? PyArray_DATA(T) : NULL, PyArray_DATA(tout),
                    (int)nout, &opt, &out, &err);
  Py_END_ALLOW_THREADS
  if (c.failed) {
    PyErr_Restore(c.et, c.ev, c.etb);
    goto fail;
  }
  if (model_law_error(cap)) goto fail; /* a callable law raised: that, not the solver's failure */
  /* a solver failure still returns what was computed (nout filled outputs), with the error's
   * kind and message: Python raises it with the partial result attached */
  int failed = st != PHM_OK && st != PHM_EINTERRUPT;
  if (failed && (err.code == PHM_EINVAL || err.code == PHM_ENOMEM)) {
    phm_py_raise(&err);
    goto fail;
  }
  res = result_arrays(tout, ra);
  PyObject *rest = res ? Py_BuildValue("{s:i,s:i,s:s,"
                      "s:{s:l,s:l,s:l,s:l,s:l,s:l,s:d,s:d,s:i,s:l,s:d,s:d,s:d,s:d,s:d,s:l}}",
                      "nout", out.nout_done,
                      "interrupted", st == PHM_EINTERRUPT, "error", failed ? err.msg : "",
                      "stats", "steps", out.nsteps,
                      "residual_evals", out.nres, "jacobian_evals", out.njac, "nonlinear_iters",
                      out.nniters, "error_test_fails", out.netf, "nonlinear_conv_fails", out.nncf,
                      "wall_time", out.wall_time, "last_step", out.last_step, "last_order", out.last_order,
                      "floor_steps", out.nfloor, "error_estimate", out.err_est, "max_mu", out.max_mu,
                      "error_ratio", out.err_ratio, "error_ratio_time", out.t_err_ratio,
                      "min_step", out.min_step, "noise_steps", out.nnoise) : NULL;
  if (!rest || PyDict_Update(res, rest) < 0) Py_CLEAR(res);
  Py_XDECREF(rest);
fail:
  for (int i = 0; i < PHM_NRESULT_FIELDS; i++) Py_XDECREF(ra[i]);
fail0:
  Py_DECREF(tout);
  Py_XDECREF(P);
  Py_XDECREF(T);
  Py_XDECREF(R);
  return res;
}

/* The poses (None: the model's initial ones) and constraint wrenches (None: zero) a
 * linearization is taken at, as arrays in *P, *L (NULL for None); 0, or -1 with an exception set
 * and nothing held. */
static int linearization_point(const phm_model *m, PyObject *po, PyObject *lo, PyArrayObject **P,
                               PyArrayObject **L) {
  *P = *L = NULL;
  if (po != Py_None) {
    npy_intp tail[3] = {phm_model_ncarriers(m), 4, 4};
    if (!(*P = phm_py_double_array(po, "poses", tail, 3, 0))) return -1;
  }
  if (lo != Py_None) {
    npy_intp tail[1] = {phm_model_nconstraints(m)};
    if (!(*L = phm_py_double_array(lo, "constraint wrenches", tail, 1, 0))) {
      Py_CLEAR(*P);
      return -1;
    }
  }
  return 0;
}

static PyObject *py_model_modes(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *cap, *po = Py_None, *lo = Py_None;
  int n, method = PHM_MODES_AUTO;
  double time = 0;
  if (!PyArg_ParseTuple(args, "Oi|OOdi", &cap, &n, &po, &lo, &time, &method)) return NULL;
  phm_model *m = get_model(cap);
  if (!m) return NULL;
  if (n < 1) {
    PyErr_SetString(phm_py_ModelError, "number of modes must be >= 1");
    return NULL;
  }
  int nc = phm_model_ncarriers(m);
  PyArrayObject *P, *L;
  if (linearization_point(m, po, lo, &P, &L)) return NULL;
  npy_intp d1[1] = {n}, d3[3] = {n, nc, 6};
  PyArrayObject *om = (PyArrayObject *)PyArray_ZEROS(1, d1, NPY_DOUBLE, 0);
  PyArrayObject *ze = (PyArrayObject *)PyArray_ZEROS(1, d1, NPY_DOUBLE, 0);
  PyArrayObject *sh = (PyArrayObject *)PyArray_ZEROS(3, d3, NPY_DOUBLE, 0);
  PyObject *res = NULL;
  if (om && ze && sh) {
    int nf = 0;
    phm_error err;
    phm_status st;
    Py_BEGIN_ALLOW_THREADS
    st = phm_modes(m, P ? PyArray_DATA(P) : NULL, L ? PyArray_DATA(L) : NULL, time, n, method,
                   PyArray_DATA(om), PyArray_DATA(ze), PyArray_DATA(sh), &nf, &err);
    Py_END_ALLOW_THREADS
    if (model_law_error(cap)) res = NULL;
    else if (st) phm_py_raise(&err);
    else res = Py_BuildValue("OOOi", om, ze, sh, nf);
  }
  Py_XDECREF(om);
  Py_XDECREF(ze);
  Py_XDECREF(sh);
  Py_XDECREF(P);
  Py_XDECREF(L);
  return res;
}

static PyObject *py_model_modes_count(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *cap, *po = Py_None, *lo = Py_None;
  double shift, time = 0;
  if (!PyArg_ParseTuple(args, "Od|OOd", &cap, &shift, &po, &lo, &time)) return NULL;
  phm_model *m = get_model(cap);
  if (!m) return NULL;
  PyArrayObject *P, *L;
  if (linearization_point(m, po, lo, &P, &L)) return NULL;
  int below = -1;
  double check = 0;
  phm_error err;
  phm_status st;
  Py_BEGIN_ALLOW_THREADS
  st = phm_modes_count(m, P ? PyArray_DATA(P) : NULL, L ? PyArray_DATA(L) : NULL, time, shift,
                       &below, &check, &err);
  Py_END_ALLOW_THREADS
  PyObject *res = NULL;
  if (model_law_error(cap)) res = NULL;
  else if (st) phm_py_raise(&err);
  else res = Py_BuildValue("id", below, check);
  Py_XDECREF(P);
  Py_XDECREF(L);
  return res;
}

/* model_linear(model, ports, poses=None, lambda=None, time=0): ports a list of (kind, index, T
 * (4, 4)) -> (K, D, M, Z, B, (nr, ncol)) of phm_linear_model, flat (Python reshapes). */
static PyObject *py_model_linear(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *cap, *plist, *po = Py_None, *lo = Py_None;
  double time = 0;
  if (!PyArg_ParseTuple(args, "OO|OOd", &cap, &plist, &po, &lo, &time)) return NULL;
  phm_model *m = get_model(cap);
  if (!m) return NULL;
  if (!PyList_Check(plist)) {
    PyErr_SetString(phm_py_ModelError, "model_linear: ports must be a list of (kind, index, T)");
    return NULL;
  }
  int nc = phm_model_ncarriers(m), n6 = 6 * nc;
  Py_ssize_t np_ = PyList_GET_SIZE(plist);
  phm_linear_port *ports = PyMem_Calloc((size_t)np_ + 1, sizeof(phm_linear_port));
  PyArrayObject *P = NULL, *L = NULL, *K = NULL, *D = NULL, *M = NULL, *Z = NULL, *B = NULL;
  PyObject *res = NULL;
  if (!ports) return PyErr_NoMemory();
  for (Py_ssize_t i = 0; i < np_; i++) {
    PyObject *it = PyList_GET_ITEM(plist, i), *To;
    if (!PyArg_ParseTuple(it, "iiO", &ports[i].kind, &ports[i].index, &To)) goto fail;
    npy_intp t2[2] = {4, 4};
    PyArrayObject *T = phm_py_double_array(To, "port frame offset", t2, 2, 0);
    if (!T) goto fail;
    memcpy(ports[i].T, PyArray_DATA(T), 16 * sizeof(double));
    Py_DECREF(T);
  }
  if (linearization_point(m, po, lo, &P, &L)) goto fail;
  int ncol = phm_linear_port_columns(m, (int)np_, ports);
  npy_intp dnn[1] = {(npy_intp)n6 * n6}, db[1] = {(npy_intp)n6 * ncol};
  K = (PyArrayObject *)PyArray_ZEROS(1, dnn, NPY_DOUBLE, 0);
  D = (PyArrayObject *)PyArray_ZEROS(1, dnn, NPY_DOUBLE, 0);
  M = (PyArrayObject *)PyArray_ZEROS(1, dnn, NPY_DOUBLE, 0);
  Z = (PyArrayObject *)PyArray_ZEROS(1, dnn, NPY_DOUBLE, 0);
  B = (PyArrayObject *)PyArray_ZEROS(1, db, NPY_DOUBLE, 0);
  if (!K || !D || !M || !Z || !B) goto fail;
  {
    int nr = 0;
    phm_error err;
    phm_status st;
    Py_BEGIN_ALLOW_THREADS
    st = phm_linear_model(m, P ? PyArray_DATA(P) : NULL, L ? PyArray_DATA(L) : NULL, time, (int)np_,
                          ports, &nr, PyArray_DATA(K), PyArray_DATA(D), PyArray_DATA(M),
                          PyArray_DATA(Z), PyArray_DATA(B), &err);
    Py_END_ALLOW_THREADS
    if (st) {
      phm_py_raise(&err);
      goto fail;
    }
    /* flat buffers: the leading nr x nr (Z: 6 nc x nr, B: nr x ncol) values are the matrices */
    PyObject *sizes = Py_BuildValue("(ii)", nr, ncol);
    if (sizes) res = Py_BuildValue("(OOOOON)", K, D, M, Z, B, sizes);
  }
fail:
  PyMem_Free(ports);
  Py_XDECREF(P); Py_XDECREF(L);
  Py_XDECREF(K); Py_XDECREF(D); Py_XDECREF(M); Py_XDECREF(Z); Py_XDECREF(B);
  return res;
}

static PyObject *py_model_static(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *cap, *po = Py_None, *mon = Py_None;
  double time = 0, tol = 1e-10;
  int steps = 1;
  if (!PyArg_ParseTuple(args, "O|OdidO", &cap, &po, &time, &steps, &tol, &mon)) return NULL;
  if (mon != Py_None && !PyCallable_Check(mon)) {
    PyErr_SetString(PyExc_TypeError, "monitor must be callable or None");
    return NULL;
  }
  phm_model *m = get_model(cap);
  if (!m) return NULL;
  int nc = phm_model_ncarriers(m), nk = phm_model_nconstraints(m);
  PyArrayObject *P = NULL;
  if (po != Py_None) {
    npy_intp tail[3] = {nc, 4, 4};
    if (!(P = phm_py_double_array(po, "poses", tail, 3, 0))) return NULL;
  }
  npy_intp dp[3] = {nc, 4, 4}, dl[1] = {nk};
  PyArrayObject *poses = (PyArrayObject *)PyArray_ZEROS(3, dp, NPY_DOUBLE, 0);
  PyArrayObject *lam = (PyArrayObject *)PyArray_ZEROS(1, dl, NPY_DOUBLE, 0);
  PyObject *res = NULL;
  /* with a monitor: called after each load step (progress), and Ctrl-C stops the solve */
  cb_ctx c = {0};
  c.mon = mon == Py_None ? NULL : mon;
  if (poses && lam) {
    int it = 0;
    double reached = 0;
    phm_error err;
    phm_status st;
    Py_BEGIN_ALLOW_THREADS
    st = phm_static_monitored(m, P ? PyArray_DATA(P) : NULL, time, steps, tol,
                              c.mon ? monitor_cb : NULL, &c, PyArray_DATA(poses),
                              PyArray_DATA(lam), &it, &reached, &err);
    Py_END_ALLOW_THREADS
    if (c.failed) PyErr_Restore(c.et, c.ev, c.etb);
    else if (model_law_error(cap)) res = NULL; /* a callable law raised: that exception */
    else if (c.interrupted) PyErr_SetNone(PyExc_KeyboardInterrupt);
    else if (st) {
      /* the error carries the last converged state: partial = (poses, lambda, iterations,
       * load factor reached), from which Mechanism.static builds err.result */
      phm_py_raise(&err);
      PyObject *et, *ev, *etb;
      PyErr_Fetch(&et, &ev, &etb);
      PyErr_NormalizeException(&et, &ev, &etb);
      PyObject *partial = ev ? Py_BuildValue("OOid", poses, lam, it, reached) : NULL;
      if (partial) {
        if (PyObject_SetAttrString(ev, "partial", partial) < 0) PyErr_Clear(); /* keep the error */
        Py_DECREF(partial);
      }
      PyErr_Restore(et, ev, etb);
    } else res = Py_BuildValue("OOi", poses, lam, it);
  }
  Py_XDECREF(poses);
  Py_XDECREF(lam);
  Py_XDECREF(P);
  return res;
}

/* model_static_free(model, poses=None, time=0, nmax=8) -> [dict(pair, coord, carrier, twist (6,),
 * force, gravity, effort, mass, moving (nc,) bool, load_work (nloads,)), ...]: the motions that
 * nothing resists and on which the loads do work (phm_static_free); [] when none is found. */
static PyObject *py_model_static_free(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *cap, *po = Py_None;
  double time = 0;
  int nmax = 8;
  if (!PyArg_ParseTuple(args, "O|Odi", &cap, &po, &time, &nmax)) return NULL;
  phm_model *m = get_model(cap);
  if (!m) return NULL;
  if (nmax < 1 || nmax > 1000) {
    PyErr_SetString(phm_py_ModelError, "model_static_free: nmax must be in [1, 1000]");
    return NULL;
  }
  int nc = phm_model_ncarriers(m), nl = phm_model_nloads(m);
  PyArrayObject *P = NULL;
  if (po != Py_None) {
    npy_intp tail[3] = {nc, 4, 4};
    if (!(P = phm_py_double_array(po, "poses", tail, 3, 0))) return NULL;
  }
  phm_free_motion *fm = PyMem_Calloc((size_t)nmax, sizeof *fm);
  unsigned char *mv = PyMem_Calloc((size_t)nmax * (size_t)nc + 1, 1);
  double *lw = PyMem_Calloc((size_t)nmax * (size_t)nl + 1, sizeof(double));
  PyObject *res = NULL;
  if (!fm || !mv || !lw) {
    PyErr_NoMemory();
    goto done;
  }
  int n = 0;
  phm_error err;
  phm_status st;
  Py_BEGIN_ALLOW_THREADS
  st = phm_static_free(m, P ? PyArray_DATA(P) : NULL, time, nmax, fm, mv, lw, &n, &err);
  Py_END_ALLOW_THREADS
  if (model_law_error(cap)) goto done;
  if (st) {
    phm_py_raise(&err);
    goto done;
  }
  if (!(res = PyList_New(n))) goto done;
  for (int k = 0; k < n; k++) {
    npy_intp d6[1] = {6}, dn[1] = {nc}, dl[1] = {nl};
    PyArrayObject *tw = (PyArrayObject *)PyArray_SimpleNew(1, d6, NPY_DOUBLE);
    PyArrayObject *mo = (PyArrayObject *)PyArray_SimpleNew(1, dn, NPY_BOOL);
    PyArrayObject *lo = (PyArrayObject *)PyArray_SimpleNew(1, dl, NPY_DOUBLE);
    PyObject *d = NULL;
    if (tw && mo && lo) {
      memcpy(PyArray_DATA(tw), fm[k].twist, sizeof fm[k].twist);
      for (int c = 0; c < nc; c++) ((npy_bool *)PyArray_DATA(mo))[c] = mv[(size_t)k * nc + c] != 0;
      if (nl) memcpy(PyArray_DATA(lo), lw + (size_t)k * nl, sizeof(double) * (size_t)nl);
      d = Py_BuildValue("{s:i,s:i,s:i,s:O,s:d,s:d,s:d,s:d,s:O,s:O}", "pair", fm[k].pair, "coord",
                        fm[k].coord, "carrier", fm[k].carrier, "twist", tw, "force", fm[k].force,
                        "gravity", fm[k].gravity, "effort", fm[k].effort, "mass", fm[k].mass,
                        "moving", mo, "load_work", lo);
    }
    Py_XDECREF(tw);
    Py_XDECREF(mo);
    Py_XDECREF(lo);
    if (!d) {
      Py_CLEAR(res);
      goto done;
    }
    PyList_SET_ITEM(res, k, d);
  }
done:
  PyMem_Free(fm);
  PyMem_Free(mv);
  PyMem_Free(lw);
  Py_XDECREF(P);
  return res;
}

/* model_set_initial(model, H0 (nc, 4, 4), t0 (nc, 6), x0 (npairs, 6), drop (npairs,)): the
 * initial state the loop closure found, set on the model it was found with (phm_model_set_initial;
 * the model is not rebuilt). */
static PyObject *py_model_set_initial(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *cap, *o[4];
  if (!PyArg_ParseTuple(args, "OOOOO", &cap, &o[0], &o[1], &o[2], &o[3])) return NULL;
  phm_model *m = get_model(cap);
  if (!m) return NULL;
  npy_intp nc = phm_model_ncarriers(m), np_ = phm_model_npairs(m);
  const npy_intp shape[4][3] = {{nc, 4, 4}, {nc, 6}, {np_, 6}, {np_}};
  const int ndim[4] = {3, 2, 2, 1};
  const char *what[4] = {"carrier poses", "carrier twists", "pair initial coordinates", "pair drop masks"};
  PyArrayObject *a[4] = {NULL, NULL, NULL, NULL};
  int *drop = calloc((size_t)np_ + 1, sizeof *drop);
  int ok = drop != NULL;
  if (!ok) PyErr_NoMemory();
  for (int i = 0; ok && i < 4; i++) ok = (a[i] = phm_py_double_array(o[i], what[i], shape[i], ndim[i], 0)) != NULL;
  for (npy_intp i = 0; ok && i < np_; i++)
    ok = to_int(((const double *)PyArray_DATA(a[3]))[i], "drop mask of pair", i, &drop[i]) == 0;
  phm_error err;
  if (ok && phm_model_set_initial(m, PyArray_DATA(a[0]), PyArray_DATA(a[1]), PyArray_DATA(a[2]), drop, &err)) {
    phm_py_raise(&err);
    ok = 0;
  }
  free(drop);
  for (int i = 0; i < 4; i++) Py_XDECREF(a[i]);
  return ok ? Py_NewRef(Py_None) : NULL;
}

static PyObject *py_model_sizes(PyObject *self, PyObject *cap) {
  (void)self;
  phm_model *m = get_model(cap);
  if (!m) return NULL;
  int np_ = phm_model_npairs(m);
  PyObject *lay = PyList_New(np_);
  if (!lay) return NULL;
  for (int ip = 0; ip < np_; ip++) {
    int row, mc, j, k;
    phm_model_pair_layout(m, ip, &row, &mc, &j, &k);
    PyList_SET_ITEM(lay, ip, Py_BuildValue("iiii", row, mc, j, k));
  }
  return Py_BuildValue("iiiiN", phm_model_ncarriers(m), phm_model_nconstraints(m),
                       phm_model_njoints(m), phm_model_nports(m), lay);
}

/* model_constraints_full(model, poses, xs=None, time=0) -> (g, G, W): every constraint row of
 * every pair (dropped redundant rows included) at the given poses. */
static PyObject *py_model_constraints_full(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *cap, *po, *xo = Py_None;
  double time = 0;
  if (!PyArg_ParseTuple(args, "OO|Od", &cap, &po, &xo, &time)) return NULL;
  phm_model *m = get_model(cap);
  if (!m) return NULL;
  int nc = phm_model_ncarriers(m), nf = phm_model_nconstraints_full(m), np_ = phm_model_npairs(m),
      nj = phm_model_njoints(m);
  npy_intp tail[3] = {nc, 4, 4}, tj[1] = {nj};
  PyArrayObject *P = phm_py_double_array(po, "poses", tail, 3, 0), *X = NULL;
  if (!P) return NULL;
  if (xo != Py_None && !(X = phm_py_double_array(xo, "joint references", tj, 1, 0))) {
    Py_DECREF(P);
    return NULL;
  }
  npy_intp dg[1] = {nf}, dG[2] = {nf, 6 * nc}, dW[3] = {np_, 6, 6};
  PyArrayObject *g = (PyArrayObject *)PyArray_ZEROS(1, dg, NPY_DOUBLE, 0);
  PyArrayObject *G = (PyArrayObject *)PyArray_ZEROS(2, dG, NPY_DOUBLE, 0);
  PyArrayObject *W = (PyArrayObject *)PyArray_ZEROS(3, dW, NPY_DOUBLE, 0);
  PyObject *res = NULL;
  if (g && G && W) {
    phm_constraints_full(m, PyArray_DATA(P), X ? PyArray_DATA(X) : NULL, time, PyArray_DATA(g),
                         PyArray_DATA(G), PyArray_DATA(W));
    if (!model_law_error(cap)) res = Py_BuildValue("OOO", g, G, W);
  }
  Py_XDECREF(g);
  Py_XDECREF(G);
  Py_XDECREF(W);
  Py_DECREF(P);
  Py_XDECREF(X);
  return res;
}

/* model_joints(model, poses, xs=None) -> x (nj): joint coordinates of every pair at the poses. */
static PyObject *py_model_joints(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *cap, *po, *xo = Py_None;
  if (!PyArg_ParseTuple(args, "OO|O", &cap, &po, &xo)) return NULL;
  phm_model *m = get_model(cap);
  if (!m) return NULL;
  int nc = phm_model_ncarriers(m), nj = phm_model_njoints(m);
  npy_intp tail[3] = {nc, 4, 4}, tj[1] = {nj};
  PyArrayObject *P = phm_py_double_array(po, "poses", tail, 3, 0), *X = NULL;
  if (!P) return NULL;
  if (xo != Py_None && !(X = phm_py_double_array(xo, "joint references", tj, 1, 0))) {
    Py_DECREF(P);
    return NULL;
  }
  PyArrayObject *x = (PyArrayObject *)PyArray_ZEROS(1, tj, NPY_DOUBLE, 0);
  if (x) phm_model_joints(m, PyArray_DATA(P), X ? PyArray_DATA(X) : NULL, PyArray_DATA(x));
  Py_DECREF(P);
  Py_XDECREF(X);
  return (PyObject *)x;
}

static PyObject *py_model_stress_resultants(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *cap, *po, *to;
  if (!PyArg_ParseTuple(args, "OOO", &cap, &po, &to)) return NULL;
  phm_model *m = get_model(cap);
  if (!m) return NULL;
  int nc = phm_model_ncarriers(m), ne = phm_model_nelements(m);
  npy_intp tp[3] = {nc, 4, 4}, tt[2] = {nc, 6};
  PyArrayObject *P = phm_py_double_array(po, "poses", tp, 3, 1), *T = NULL, *S = NULL;
  if (P) T = phm_py_double_array(to, "twists", tt, 2, 1);
  if (P && T) {
    npy_intp nt = PyArray_SIZE(P) / (16 * (npy_intp)nc);
    if (PyArray_SIZE(T) / (6 * (npy_intp)nc) != nt) {
      PyErr_SetString(phm_py_ModelError, "stress resultants: poses and twists have different numbers of states");
    } else {
      npy_intp dims[3] = {nt, ne, 6};
      S = (PyArrayObject *)PyArray_ZEROS(3, dims, NPY_DOUBLE, 0);
      if (S) {
        const double *Pd = PyArray_DATA(P), *Td = PyArray_DATA(T);
        double *Sd = PyArray_DATA(S);
        Py_BEGIN_ALLOW_THREADS
        for (npy_intp i = 0; i < nt; i++)
          phm_model_stress_resultants(m, Pd + 16 * nc * i, Td + 6 * nc * i, Sd + 6 * ne * i);
        Py_END_ALLOW_THREADS
      }
    }
  }
  Py_XDECREF(P);
  Py_XDECREF(T);
  return (PyObject *)S;
}

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
  if (parse_law(lo, &law, keep, "law", 0) < 0) goto done;
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
  if (law_error(keep)) goto done;
  res = (PyObject *)out;
  out = NULL;
done:
  Py_XDECREF(out);
  Py_XDECREF(T);
  Py_DECREF(keep);
  return res;
}

/* element_mass(h, Ms (6, 6), eps_hat (6,)) -> Mc (12, 12) (phm_element_mass). */
static PyObject *py_element_mass(PyObject *self, PyObject *args) {
  (void)self;
  double h;
  PyObject *mo, *eo, *res = NULL;
  PyArrayObject *Ms = NULL, *eps = NULL, *out = NULL;
  if (!PyArg_ParseTuple(args, "dOO", &h, &mo, &eo)) return NULL;
  npy_intp t66[2] = {6, 6}, t6[1] = {6}, dims[2] = {12, 12};
  if (!(Ms = phm_py_double_array(mo, "Ms", t66, 2, 1))) goto done;
  if (!(eps = phm_py_double_array(eo, "eps_hat", t6, 1, 1))) goto done;
  if (PyArray_NDIM(Ms) != 2 || PyArray_NDIM(eps) != 1 || !(h > 0) || !isfinite(h)) {
    PyErr_SetString(phm_py_ModelError, "element_mass: expected h > 0, Ms (6, 6) and eps_hat (6,)");
    goto done;
  }
  if (!(out = (PyArrayObject *)PyArray_SimpleNew(2, dims, NPY_DOUBLE))) goto done;
  phm_element_mass(h, PyArray_DATA(Ms), PyArray_DATA(eps), PyArray_DATA(out));
  res = (PyObject *)out;
  out = NULL;
done:
  Py_XDECREF(out);
  Py_XDECREF(Ms);
  Py_XDECREF(eps);
  return res;
}


/* ---------------------------------------------------------------- planar scenes
 * The check of csrc/model/planarity.c: for a model (model_planar, Mechanism.simulate), or for the
 * columns of python/phmech/_marshal.components with the constraint rows as a dense G
 * (planar_check, planar_rows: python/phmech/planar.py's check and out_of_plane_rows). */

/* names: a list of np str (or None) as UTF-8 strings in *out (PyMem_Free it; NULL for None),
 * valid while the list lives. */
static int utf8_names(PyObject *names, npy_intp np_, const char ***out) {
  *out = NULL;
  if (names == Py_None) return 0;
  if (!PyList_Check(names) || PyList_GET_SIZE(names) != np_) {
    PyErr_Format(phm_py_ModelError, "pair names: expected a list of %ld str", (long)np_);
    return -1;
  }
  const char **nm = PyMem_Malloc(sizeof(char *) * (size_t)(np_ + 1));
  if (!nm) {
    PyErr_NoMemory();
    return -1;
  }
  for (npy_intp i = 0; i < np_; i++) {
    PyObject *o = PyList_GET_ITEM(names, i);
    if (!PyUnicode_Check(o) || !(nm[i] = PyUnicode_AsUTF8(o))) {
      if (!PyErr_Occurred()) PyErr_Format(phm_py_ModelError, "pair names: entry %ld is not a str", (long)i);
      PyMem_Free(nm);
      return -1;
    }
  }
  *out = nm;
  return 0;
}

/* A check's message (the core cuts long names at a byte count, which may split a UTF-8
 * character: replaced, not an error), or None. */
static PyObject *why_or_none(const char *why) {
  return why[0] ? PyUnicode_DecodeUTF8(why, (Py_ssize_t)strlen(why), "replace") : Py_NewRef(Py_None);
}

/* model_planar(model, poses (nc, 4, 4), twists (nc, 6), names) -> (axis, masks, why): the first
 * of the axes z, y, x the scene is planar about (0, 1, 2; None: none) with its pairs'
 * out-of-plane rows (a list of masks; None), and the first failing check about each axis tried
 * (why[k]: str, or None when planar about k or not tried). */
static PyObject *py_model_planar(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *cap, *po, *to, *names;
  if (!PyArg_ParseTuple(args, "OOOO", &cap, &po, &to, &names)) return NULL;
  phm_model *m = get_model(cap);
  if (!m) return NULL;
  int nc = phm_model_ncarriers(m), np_ = phm_model_npairs(m);
  npy_intp tp[3] = {nc, 4, 4}, tt[2] = {nc, 6};
  PyArrayObject *P = phm_py_double_array(po, "poses", tp, 3, 0), *T = NULL;
  const char **nm = NULL;
  PyObject *res = NULL;
  int dstack[64], *drop = np_ <= 64 ? dstack : PyMem_Malloc(sizeof(int) * (size_t)np_);
  char why[3][PHM_PLANAR_WHY];
  if (!drop) PyErr_NoMemory();
  else if (P && (T = phm_py_double_array(to, "twists", tt, 2, 0)) && utf8_names(names, np_, &nm) == 0) {
    phm_error err;
    int axis;
    for (int k = 0; k < 3; k++) why[k][0] = '\0';
    if (phm_planar_check(m, PyArray_DATA(P), PyArray_DATA(T), nm, &axis, drop, why, &err)) phm_py_raise(&err);
    else if (!model_law_error(cap)) {
      PyObject *masks = Py_NewRef(Py_None);
      if (axis >= 0) {
        Py_SETREF(masks, PyList_New(np_));
        for (int ip = 0; masks && ip < np_; ip++) {
          PyObject *v = PyLong_FromLong(drop[ip]);
          if (!v) Py_CLEAR(masks);
          else PyList_SET_ITEM(masks, ip, v);
        }
      }
      if (masks)
        res = Py_BuildValue("NN(NNN)", axis >= 0 ? PyLong_FromLong(axis) : Py_NewRef(Py_None), masks,
                            why_or_none(why[0]), why_or_none(why[1]), why_or_none(why[2]));
    }
  }
  if (drop != dstack) PyMem_Free(drop);
  PyMem_Free(nm);
  Py_XDECREF(P);
  Py_XDECREF(T);
  return res;
}

/* The columns planar_check reads of _marshal.components (others are ignored). */
static const column planar_carrier_columns[] = {
    SCALAR("mass", "carrier masses", phm_carrier_desc, mass),
    MATRIX("M", "carrier inertias", phm_carrier_desc, M, 6, 6),
    VECTOR("com", "centres of mass", phm_carrier_desc, com, 3),
};
static const column planar_element_columns[] = {
    MATRIX("K", "element stiffness", phm_element_desc, K, 6, 6),
    MATRIX("D", "element damping", phm_element_desc, D, 6, 6),
    MATRIX("Ms", "element section inertias", phm_element_desc, Ms, 6, 6),
    MATRIX("Mc", "element mass couplings", phm_element_desc, Mc, 12, 12),
    VECTOR("eps_hat", "element unstressed strain", phm_element_desc, eps_hat, 6),
};
static const column planar_pair_columns[] = {
    INDEX2("carriers", "pair carriers", phm_pair_desc, a, b, "pair"),
    FLAG("driven", "pair driven flags", phm_pair_desc, driven),
    {"xlaws", "pair joint laws", COL_XLAWS, 0, {0}, {offsetof(phm_pair_desc, xlaw), 0}, "pair joint law", 0},
};
static const column planar_load_columns[] = {
    VECTOR("w", "load wrenches", phm_load_desc, w, 6),
    VECTOR("point", "load points", phm_load_desc, point, 3),
};
static const column planar_actuator_columns[] = {
    INDEX("pair", "actuator pairs", phm_actuator_desc, pair, "pair of actuator"),
};
static const column planar_spring_columns[] = {
    INDEX2("carriers", "spring carriers", phm_spring_desc, a, b, "spring"),
    VECTOR("pa", "spring points a", phm_spring_desc, pa, 3),
    VECTOR("pb", "spring points b", phm_spring_desc, pb, 3),
};
enum { NPLANAR = 6 };
static const component PLANAR_COMPONENTS[NPLANAR] = {
    KIND("carriers", "carrier", phm_carrier_desc, planar_carrier_columns),
    KIND("elements", "element", phm_element_desc, planar_element_columns),
    KIND("pairs", "pair", phm_pair_desc, planar_pair_columns),
    KIND("loads", "load", phm_load_desc, planar_load_columns),
    KIND("actuators", "actuator", phm_actuator_desc, planar_actuator_columns),
    KIND("springs", "spring", phm_spring_desc, planar_spring_columns),
};

/* The rows of a scene from a dense G (nrow, 6 nc) and a layout [(row, m, joint, k) per pair]:
 * blocks of every carrier (nblk = nc); np pairs. Allocates s->Gcar and the layout (PyMem_Free
 * *ints). Returns the G array (a new reference) or NULL. */
static PyArrayObject *planar_rows_of(PyObject *go, PyObject *layout, int nc, phm_planar_scene *s,
                                     int **ints) {
  *ints = NULL;
  npy_intp tail[1] = {6 * (npy_intp)nc};
  PyArrayObject *G = phm_py_double_array(go, "constraint rows G", tail, 1, 1);
  if (!G) return NULL;
  if (PyArray_NDIM(G) != 2 || PyArray_DIM(G, 0) > INT_MAX / (nc + 1) / 6) {
    PyErr_Format(phm_py_ModelError, "constraint rows G: expected shape (rows, %d)", 6 * nc);
    Py_DECREF(G);
    return NULL;
  }
  PyObject *lay = PySequence_Fast(layout, "layout: expected a list of (row, m, joint, k)");
  if (!lay) {
    Py_DECREF(G);
    return NULL;
  }
  npy_intp nrow = PyArray_DIM(G, 0), np_ = PySequence_Fast_GET_SIZE(lay);
  int *v = PyMem_Malloc(sizeof(int) * (size_t)(nrow * nc + 3 * np_ + 1));
  if (!v) PyErr_NoMemory();
  for (npy_intp r = 0; v && r < nrow * nc; r++) v[r] = (int)(r % nc);
  int *row = v ? v + nrow * nc : NULL, *mm = row ? row + np_ : NULL, *kk = mm ? mm + np_ : NULL;
  for (npy_intp ip = 0; v && ip < np_; ip++) {
    int j;
    PyObject *item = PySequence_Tuple(PySequence_Fast_GET_ITEM(lay, ip));   /* any 4-sequence */
    if (!item || !PyArg_ParseTuple(item, "iiii", &row[ip], &mm[ip], &j, &kk[ip])) {
      PyMem_Free(v);
      v = NULL;
    }
    Py_XDECREF(item);
  }
  Py_DECREF(lay);
  if (!v) {
    Py_DECREF(G);
    return NULL;
  }
  *ints = v;
  s->np = (int)np_;
  s->pair_row = row;
  s->pair_m = mm;
  s->pair_k = kk;
  s->nrow = (int)nrow;
  s->nblk = nc;
  s->G = PyArray_DATA(G);
  s->Gcar = v;
  return G;
}

/* planar_check(comp, poses, twists, G, layout, names, k) -> None (planar about axis k) or the
 * first failing check (python/phmech/planar.py, check). */
static PyObject *py_planar_check(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *comp, *po, *to, *go, *layout, *names;
  int k;
  if (!PyArg_ParseTuple(args, "OOOOOOi", &comp, &po, &to, &go, &layout, &names, &k)) return NULL;
  if (!PyDict_Check(comp)) return PyErr_Format(phm_py_ModelError, "planar check: expected the dict of _marshal.components");
  PyObject *keep = PyList_New(0), *res = NULL;
  void *items[NPLANAR] = {NULL};
  npy_intp n[NPLANAR] = {0}, t44[2] = {4, 4}, t3[1] = {3}, t12[2] = {12, 12};
  PyArrayObject *P = NULL, *T = NULL, *grav = NULL, *Mc = NULL, *G = NULL;
  int *ints = NULL;
  const char **nm = NULL;
  if (!keep) return NULL;
  for (int c = 0; c < NPLANAR; c++) {
    PyObject *d = PyDict_GetItemString(comp, PLANAR_COMPONENTS[c].name);
    if (!d) {
      PyErr_Format(phm_py_ModelError, "planar check: no '%s' in the components", PLANAR_COMPONENTS[c].name);
      goto done;
    }
    if (parse_component(&PLANAR_COMPONENTS[c], d, keep, 0, &n[c], &items[c]) < 0) goto done;
  }
  PyObject *cp = PyDict_GetItemString(comp, "couplings"), *go_ = PyDict_GetItemString(comp, "gravity");
  PyObject *cmc = cp && PyDict_Check(cp) ? PyDict_GetItemString(cp, "Mc") : NULL;
  if (!cmc || !go_) {
    PyErr_SetString(phm_py_ModelError, "planar check: no couplings' Mc or gravity in the components");
    goto done;
  }
  if (!(P = phm_py_double_array(po, "poses", t44, 2, 1)) || !(grav = phm_py_double_array(go_, "gravity", t3, 1, 0)) ||
      !(Mc = phm_py_double_array(cmc, "mass couplings", t12, 2, 1)))
    goto done;
  int nc = (int)(PyArray_SIZE(P) / 16);
  npy_intp tt[2] = {nc, 6};
  if (nc != n[0]) {
    PyErr_Format(phm_py_ModelError, "planar check: %d poses for %ld carriers", nc, (long)n[0]);
    goto done;
  }
  if (!(T = phm_py_double_array(to, "twists", tt, 2, 0))) goto done;
  phm_planar_scene s = {.nc = nc, .H = PyArray_DATA(P), .t = PyArray_DATA(T), .car = items[0],
                        .ne = (int)n[1], .el = items[1], .ncoup = (int)(PyArray_SIZE(Mc) / 144),
                        .coupling_Mc = PyArray_DATA(Mc), .nl = (int)n[3], .load = items[3],
                        .ns = (int)n[5], .spr = items[5], .na = (int)n[4], .act = items[4],
                        .pair = items[2]};
  memcpy(s.gravity, PyArray_DATA(grav), sizeof s.gravity);
  if (!(G = planar_rows_of(go, layout, nc, &s, &ints))) goto done;
  if (s.np != n[2]) {
    PyErr_Format(phm_py_ModelError, "planar check: a layout of %d pairs for %ld pairs", s.np, (long)n[2]);
    goto done;
  }
  if (utf8_names(names, s.np, &nm) < 0) goto done;
  s.names = nm;
  char why[PHM_PLANAR_WHY];
  phm_error err;
  if (phm_planar_check_scene(&s, k, NULL, why, &err)) phm_py_raise(&err);
  else res = why_or_none(why);
done:
  for (int c = 0; c < NPLANAR; c++) free(items[c]);
  PyMem_Free(ints);
  PyMem_Free(nm);
  Py_XDECREF(P);
  Py_XDECREF(T);
  Py_XDECREF(grav);
  Py_XDECREF(Mc);
  Py_XDECREF(G);
  Py_DECREF(keep);
  return res;
}

/* planar_rows(G, layout, nc, k) -> [mask per pair]: the rows without an in-plane component. */
static PyObject *py_planar_rows(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *go, *layout;
  int nc, k;
  if (!PyArg_ParseTuple(args, "OOii", &go, &layout, &nc, &k)) return NULL;
  if (nc < 0 || nc > INT_MAX / 6) return PyErr_Format(phm_py_ModelError, "planar rows: %d carriers", nc);
  phm_planar_scene s = {.nc = nc};
  int *ints;
  PyArrayObject *G = planar_rows_of(go, layout, nc, &s, &ints);
  if (!G) return NULL;
  PyObject *res = NULL;
  int *drop = PyMem_Malloc(sizeof(int) * (size_t)(s.np + 1));
  phm_error err;
  if (!drop) PyErr_NoMemory();
  else if (phm_planar_rows(&s, k, drop, &err)) phm_py_raise(&err);
  else if ((res = PyList_New(s.np)))
    for (int ip = 0; ip < s.np; ip++) {
      PyObject *v = PyLong_FromLong(drop[ip]);
      if (!v) {
        Py_CLEAR(res);
        break;
      }
      PyList_SET_ITEM(res, ip, v);
    }
  PyMem_Free(drop);
  PyMem_Free(ints);
  Py_DECREF(G);
  return res;
}

PyMethodDef phm_py_model_methods[] = {
    {"model_planar", py_model_planar, METH_VARARGS,
     "model_planar(model, poses (nc, 4, 4), twists (nc, 6), names) -> (axis, masks, why): the "
     "first of the world axes z, y, x (2, 1, 0) the scene is planar about, or None; its pairs' "
     "out-of-plane rows (drop masks), or None; per axis k the first failing check (str) or None "
     "(csrc/model/planarity.c, phm_planar_check)."},
    {"planar_check", py_planar_check, METH_VARARGS,
     "planar_check(comp, poses, twists, G (rows, 6 nc), layout, names, k) -> None (planar about "
     "axis k) or the first failing check (python/phmech/planar.py, check; phm_planar_check_scene)."},
    {"planar_rows", py_planar_rows, METH_VARARGS,
     "planar_rows(G (rows, 6 nc), layout, nc, k) -> [mask per pair]: the rows without an in-plane "
     "component about axis k (phm_planar_rows)."},
    {"element_mass", py_element_mass, METH_VARARGS,
     "element_mass(h, Ms (6, 6), eps_hat (6,)) -> Mc (12, 12): the mass coupling a consistent-mass "
     "element adds in its nodes' body twists (csrc/model/element.c, phm_element_mass)."},
    {"law_eval", py_law_eval, METH_VARARGS,
     "law_eval(law, times) -> (n, 3) array of s, s', s'' (csrc/util/law.c) of a law tuple "
     "(python/phmech/_marshal.py) at each time; ModelError for an invalid law."},
    {"model_stress_resultants", py_model_stress_resultants, METH_VARARGS,
     "model_stress_resultants(model, poses (..., nc, 4, 4), twists (..., nc, 6)) -> (nt, nelements, "
     "6): every element's stress resultants K (eps - eps_hat) + D eps' (csrc/model/element.c)."},
    {"model_constraints_full", py_model_constraints_full, METH_VARARGS,
     "model_constraints_full(model, poses, xs=None, time=0) -> (g (nfull,), G (nfull, 6 nc), W "
     "(npairs, 6, 6)): all constraint rows, redundant (dropped) ones included."},
    {"model_joints", py_model_joints, METH_VARARGS,
     "model_joints(model, poses, xs=None) -> x (njoints,): joint coordinates at the poses."},
    {"model_new", (PyCFunction)(void (*)(void))py_model_new, METH_VARARGS | METH_KEYWORDS,
     "model_new(carriers, elements, pairs, loads, actuators, springs, gravity, couplings=None) -> model capsule "
     "(validated; raises ModelError). Each component kind is a dict of columns with one row per "
     "component (keys: carriers mass, M, com, H0, t0; elements h, nodes, K, D, eps_hat, mass (0 lumped, 1 consistent, 2 given), Ms, Mc; pairs "
     "type, carriers, Ta, Tb, driven, axis, law, pitch, x0, has_x0, drop; loads carrier, world, "
     "point, w, law, reaction; actuators pair, kind, vec, kp, kd, x_set, law; springs k, "
     "carriers, pa, pb, c, rest_length; couplings Mc (12, 12), carriers; pairs also xlaws: per pair None or one law or None "
     "per joint coordinate); laws are tuples (kind, amplitude, t0, duration, frequency, "
     "phase, offset, data, order, nodes, fn) (python/phmech/_marshal.py); gravity (3,)."},
    {"model_set_initial", py_model_set_initial, METH_VARARGS,
     "model_set_initial(model, H0 (nc, 4, 4), t0 (nc, 6), x0 (npairs, 6), drop (npairs,)) -> None: "
     "a new initial state (poses, twists, joint coordinates, redundant-row masks) without "
     "rebuilding the model."},
    {"model_simulate", (PyCFunction)(void (*)(void))py_model_simulate, METH_VARARGS | METH_KEYWORDS,
     "model_simulate(model, tout, rtol, atol, linear_solver, poses=None, twists=None, "
     "callback=None, max_step=0, max_order=0, record=None, error_test=0, integrator=0, step=0, "
     "rho_inf=1, adaptive=0, band=0, monitor=None, arrays=None, planar=0) -> dict of arrays and solver "
     "statistics; arrays(dict) is called once before the run with the output arrays it fills."},
    {"model_modes", py_model_modes, METH_VARARGS,
     "model_modes(model, n, poses=None, lambda=None, time=0, method=0) -> (omega, zeta, shapes, "
     "nfound); method 0 auto, 1 dense, 2 sparse (phm_modes)."},
    {"model_modes_count", py_model_modes_count, METH_VARARGS,
     "model_modes_count(model, shift, poses=None, lambda=None, time=0) -> (below, check): how many "
     "eigenvalues omega^2 lie below shift [(rad/s)^2] (phm_modes_count)"},
    {"model_linear", py_model_linear, METH_VARARGS,
     "model_linear(model, ports, poses=None, lambda=None, time=0) -> (K, D, M, Z, B, (nr, ncol)): "
     "flat buffers whose leading nr*nr (Z: 6nc*nr, B: nr*ncol) values are the row-major matrices "
     "of phm_linear_model; ports: a list of (kind 0 pair | 1 load | 2 frame, index, T (4, 4))."},
    {"model_static", py_model_static, METH_VARARGS,
     "model_static(model, poses=None, time=0, steps=1, tol=1e-10, monitor=None) -> (poses, lambda, "
     "iterations); monitor(load factor, iterations, load step) after each load step, truthy to stop; "
     "steps=0: the full load at once from poses (no unloaded start)."},
    {"model_static_free", py_model_static_free, METH_VARARGS,
     "model_static_free(model, poses=None, time=0, nmax=8) -> list of dicts (pair, coord, carrier, "
     "twist, force, gravity, effort, mass, moving, load_work): motions nothing resists on which the "
     "loads do work (phm_static_free): each proves there is no static equilibrium."},
    {"model_sizes", py_model_sizes, METH_O, "model_sizes(model) -> (ncarriers, nconstraints, njoints, nports, [(row, m, joint, k) per pair])."},
    {NULL, NULL, 0, NULL}};
