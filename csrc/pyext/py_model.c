/* py_model.c -- the binding of a model's construction (csrc/model/): model_new reads one dict of
 * columns per component kind (COMPONENTS below; python/phmech/_marshal.py builds them) into the
 * core's description structs; a model lives in a capsule. Also the queries of a built model
 * (sizes, constraints, joints, stress resultants) and model_set_initial. Laws: py_laws.c;
 * simulate: py_simulate.c; modes, linearization, statics: py_analyses.c; planar scenes:
 * py_planar.c. */
#include "py_model.h"

#include <limits.h>
#include <math.h>
#include <string.h>

/* A model's capsule keeps, as its context, the list of what its laws refer to (the callables of
 * CALLBACK laws): alive as long as the model. */
static void capsule_free(PyObject *cap) {
  phm_model *m = (phm_model *)PyCapsule_GetPointer(cap, PHM_PY_MODEL_CAPSULE);
  Py_XDECREF((PyObject *)PyCapsule_GetContext(cap));
  phm_model_free(m);
}

phm_model *phm_py_get_model(PyObject *cap) {
  return (phm_model *)PyCapsule_GetPointer(cap, PHM_PY_MODEL_CAPSULE);
}

int phm_py_model_poses(const phm_model *m, PyObject *po, const char *what, int optional, PyArrayObject **P) {
  npy_intp tail[3] = {phm_model_ncarriers(m), 4, 4};
  *P = NULL;
  if (optional && po == Py_None) return 0;
  return (*P = phm_py_double_array(po, what, tail, 3, 0)) ? 0 : -1;
}

/* An index or enumeration code given as float64 (the columns of python/phmech/_marshal.py): it
 * must be a whole number representable as int (the core then checks its range); converting
 * anything else to int would truncate (1.5 -> carrier 1) or be undefined behaviour (1e20, C11
 * 6.3.1.4). */
int phm_py_to_int(double v, const char *what, npy_intp i, int *out) {
  if (!(v >= INT_MIN && v <= INT_MAX && v == floor(v))) {
    char got[32];
    snprintf(got, sizeof got, "%.17g", v);
    PyErr_Format(phm_py_ModelError, "%s %ld: expected a whole number, got %s", what, (long)i, got);
    return -1;
  }
  *out = (int)v;
  return 0;
}

/* Every column of every kind (csrc/pyext/py_model.h); the couplings and components only
 * model_new reads. */
static const column carrier_columns[] = {PHM_PY_CARRIER_COLUMNS(PHM_PY_KEEP, PHM_PY_KEEP)};
static const column element_columns[] = {PHM_PY_ELEMENT_COLUMNS(PHM_PY_KEEP, PHM_PY_KEEP)};
static const column pair_columns[] = {PHM_PY_PAIR_COLUMNS(PHM_PY_KEEP, PHM_PY_KEEP)};
static const column load_columns[] = {PHM_PY_LOAD_COLUMNS(PHM_PY_KEEP, PHM_PY_KEEP)};
static const column actuator_columns[] = {PHM_PY_ACTUATOR_COLUMNS(PHM_PY_KEEP, PHM_PY_KEEP)};
static const column spring_columns[] = {PHM_PY_SPRING_COLUMNS(PHM_PY_KEEP, PHM_PY_KEEP)};

static const column coupling_columns[] = {
    MATRIX("Mc", "mass couplings", phm_coupling_desc, Mc, 12, 12),
    INDEX2("carriers", "coupled carriers", phm_coupling_desc, a, b, "coupling"),
};

static const column component_columns[] = {
    INDEX("kind", "component kinds", phm_component_desc, kind, "kind of component"),
    INDEX("pair", "component pairs", phm_component_desc, pair, "pair of component"),
    INDEX("coord", "component coordinates", phm_component_desc, coord, "coordinate of component"),
    VECTOR("par", "component parameters", phm_component_desc, par, PHM_COMP_NPAR),
    INDEX("input", "component inputs", phm_component_desc, input, "input of component"),
    INDEX("nx", "component state counts", phm_component_desc, nx, "state count of component"),
    INDEX("spair", "component sensor pairs", phm_component_desc, spair, "sensor pair of component"),
    INDEX("scoord", "component sensor coordinates", phm_component_desc, scoord, "sensor coordinate of component"),
    VECTOR("z0", "component initial states", phm_component_desc, z0, PHM_COMP_MAXZ),
    LAW("law", "component laws", phm_component_desc, law, "component law", LAW_OR_NONE),
};

static const component COMPONENTS[] = {PHM_PY_COMPONENT_KINDS(PHM_PY_KEEP, PHM_PY_KEEP)};
enum { NKINDS = sizeof COMPONENTS / sizeof COMPONENTS[0] };

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
        if (phm_py_to_int(row[j], col->label, i, (int *)(item + col->offset[j])) < 0) return -1;
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
int phm_py_parse_component(const component *cp, PyObject *d, PyObject *keep, int strict, npy_intp *n,
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
      if (phm_py_fill_laws(cp, col, o, *n, (char *)*out, keep) < 0) return -1;
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
                        "couplings", "components", NULL};
  /* o[6] gravity, o[7] the couplings, o[8] the components (optional: none) */
  PyObject *o[NKINDS + 1] = {NULL};
  if (!PyArg_ParseTupleAndKeywords(args, kw, "OOOOOOO|OO", kwl, &o[0], &o[1], &o[2], &o[3], &o[4], &o[5],
                                   &o[6], &o[7], &o[8]))
    return NULL;
  PyObject *grav_arg = o[6];
  o[6] = o[7] == Py_None ? NULL : o[7]; /* None: no coupling, as when left out */
  o[7] = o[8] == Py_None ? NULL : o[8]; /* None: no component */
  PyObject *keep = PyList_New(0);
  if (!keep) return NULL;
  PyObject *result = NULL;
  void *items[NKINDS] = {NULL};
  npy_intp n[NKINDS] = {0};
  npy_intp g3[1] = {3};
  PyArrayObject *grav = NULL;
  for (int k = 0; k < NKINDS; k++)
    if (o[k] && phm_py_parse_component(&COMPONENTS[k], o[k], keep, 1, &n[k], &items[k]) < 0) goto fail;
  if (!(grav = phm_py_double_array(grav_arg, "gravity", g3, 1, 0))) goto fail;
  for (npy_intp i = 0; i < n[7]; i++) { /* a callback controller: its law's callable (kept) */
    phm_component_desc *c = (phm_component_desc *)items[7] + i;
    c->fn = NULL;
    c->ctx = NULL;
    if (c->kind == PHM_COMP_CALLBACK && c->law.kind == PHM_LAW_CALLBACK && c->law.ctx) {
      c->fn = phm_py_control_callback;
      c->ctx = c->law.ctx;
    }
  }
  {
    phm_model_desc d = {.ncarriers = (int)n[0], .carriers = items[0], .nelements = (int)n[1],
                        .elements = items[1], .npairs = (int)n[2], .pairs = items[2],
                        .nloads = (int)n[3], .loads = items[3], .nactuators = (int)n[4],
                        .actuators = items[4], .nsprings = (int)n[5], .springs = items[5],
                        .ncouplings = (int)n[6], .couplings = items[6],
                        .ncomponents = (int)n[7], .components = items[7]};
    memcpy(d.gravity, PyArray_DATA(grav), 3 * sizeof(double));
    phm_model *m = NULL;
    phm_error err;
    if (phm_model_create(&d, &m, &err)) {
      phm_py_raise(&err);
      goto fail;
    }
    result = PyCapsule_New(m, PHM_PY_MODEL_CAPSULE, capsule_free);
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

/* model_set_initial(model, H0 (nc, 4, 4), t0 (nc, 6), x0 (npairs, 6), drop (npairs,)): the
 * initial state the loop closure found, set on the model it was found with (phm_model_set_initial;
 * the model is not rebuilt). */
static PyObject *py_model_set_initial(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *cap, *o[4];
  if (!PyArg_ParseTuple(args, "OOOOO", &cap, &o[0], &o[1], &o[2], &o[3])) return NULL;
  phm_model *m = phm_py_get_model(cap);
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
    ok = phm_py_to_int(((const double *)PyArray_DATA(a[3]))[i], "drop mask of pair", i, &drop[i]) == 0;
  phm_error err;
  if (ok && phm_model_set_initial(m, PyArray_DATA(a[0]), PyArray_DATA(a[1]), PyArray_DATA(a[2]), drop, &err)) {
    phm_py_raise(&err);
    ok = 0;
  }
  free(drop);
  for (int i = 0; i < 4; i++) Py_XDECREF(a[i]);
  return ok ? Py_NewRef(Py_None) : NULL;
}

/* model_set_spin(model, S (6,)): the analyses about a steady rotation with the world twist S
 * (phm_model_set_spin; zeros: none). */
static PyObject *py_model_set_spin(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *cap, *so;
  if (!PyArg_ParseTuple(args, "OO", &cap, &so)) return NULL;
  phm_model *m = phm_py_get_model(cap);
  if (!m) return NULL;
  npy_intp shape[1] = {6};
  PyArrayObject *S = phm_py_double_array(so, "spin twist", shape, 1, 0);
  if (!S) return NULL;
  phm_error err;
  phm_status st = phm_model_set_spin(m, PyArray_DATA(S), &err);
  Py_DECREF(S);
  if (st) {
    phm_py_raise(&err);
    return NULL;
  }
  return Py_NewRef(Py_None);
}

static PyObject *py_model_sizes(PyObject *self, PyObject *cap) {
  (void)self;
  phm_model *m = phm_py_get_model(cap);
  if (!m) return NULL;
  int np_ = phm_model_npairs(m);
  PyObject *lay = PyList_New(np_);
  for (int ip = 0; lay && ip < np_; ip++) {
    int row, mc, j, k;
    phm_model_pair_layout(m, ip, &row, &mc, &j, &k);
    PyObject *t = Py_BuildValue("iiii", row, mc, j, k);
    if (!t) Py_CLEAR(lay);
    else PyList_SET_ITEM(lay, ip, t);
  }
  if (!lay) return NULL;
  return Py_BuildValue("iiiiNi", phm_model_ncarriers(m), phm_model_nconstraints(m),
                       phm_model_njoints(m), phm_model_nports(m), lay, phm_model_ncompstates(m));
}

/* The poses (nc, 4, 4) and the joint references (njoints,; None: NULL) the queries below read,
 * as arrays in *P, *X; 0, or -1 with an exception set and nothing held. */
static int poses_and_references(const phm_model *m, PyObject *po, PyObject *xo, PyArrayObject **P,
                                PyArrayObject **X) {
  npy_intp tj[1] = {phm_model_njoints(m)};
  *X = NULL;
  if (phm_py_model_poses(m, po, "poses", 0, P) < 0) return -1;
  if (xo != Py_None && !(*X = phm_py_double_array(xo, "joint references", tj, 1, 0))) {
    Py_CLEAR(*P);
    return -1;
  }
  return 0;
}

/* model_constraints_full(model, poses, xs=None, time=0) -> (g, G, W): every constraint row of
 * every pair (dropped redundant rows included) at the given poses. */
static PyObject *py_model_constraints_full(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *cap, *po, *xo = Py_None;
  double time = 0;
  if (!PyArg_ParseTuple(args, "OO|Od", &cap, &po, &xo, &time)) return NULL;
  phm_model *m = phm_py_get_model(cap);
  if (!m) return NULL;
  int nc = phm_model_ncarriers(m), nf = phm_model_nconstraints_full(m), np_ = phm_model_npairs(m);
  PyArrayObject *P, *X;
  if (poses_and_references(m, po, xo, &P, &X) < 0) return NULL;
  npy_intp dg[1] = {nf}, dG[2] = {nf, 6 * nc}, dW[3] = {np_, 6, 6};
  PyArrayObject *g = (PyArrayObject *)PyArray_ZEROS(1, dg, NPY_DOUBLE, 0);
  PyArrayObject *G = (PyArrayObject *)PyArray_ZEROS(2, dG, NPY_DOUBLE, 0);
  PyArrayObject *W = (PyArrayObject *)PyArray_ZEROS(3, dW, NPY_DOUBLE, 0);
  PyObject *res = NULL;
  if (g && G && W) {
    phm_constraints_full(m, PyArray_DATA(P), X ? PyArray_DATA(X) : NULL, time, PyArray_DATA(g),
                         PyArray_DATA(G), PyArray_DATA(W));
    if (!phm_py_model_law_error(cap)) res = Py_BuildValue("OOO", g, G, W);
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
  phm_model *m = phm_py_get_model(cap);
  if (!m) return NULL;
  npy_intp tj[1] = {phm_model_njoints(m)};
  PyArrayObject *P, *X;
  if (poses_and_references(m, po, xo, &P, &X) < 0) return NULL;
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
  phm_model *m = phm_py_get_model(cap);
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

PyMethodDef phm_py_model_methods[] = {
    {"element_mass", py_element_mass, METH_VARARGS,
     "element_mass(h, Ms (6, 6), eps_hat (6,)) -> Mc (12, 12): the mass coupling a consistent-mass "
     "element adds in its nodes' body twists (csrc/model/element.c, phm_element_mass)."},
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
    {"model_set_spin", py_model_set_spin, METH_VARARGS,
     "model_set_spin(model, S (6,)) -> None: statics, modes and the linear model about a steady "
     "rotation with the world twist S (omega, v at the origin; zeros: none); simulate ignores it."},
    {"model_sizes", py_model_sizes, METH_O, "model_sizes(model) -> (ncarriers, nconstraints, njoints, nports, [(row, m, joint, k) per pair])."},
    
    {NULL, NULL, 0, NULL}};
