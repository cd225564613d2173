/* py_planar.c -- planar scenes (csrc/model/planarity.c) for Python. */
#include "py_model.h"

#include <limits.h>
#include <math.h>
#include <string.h>

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
  phm_model *m = phm_py_get_model(cap);
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
    else if (!phm_py_model_law_error(cap)) {
      PyObject *masks = axis >= 0 ? phm_py_int_list(drop, np_) : Py_NewRef(Py_None);
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

/* The columns planar_check reads of _marshal.components (others are ignored): those of
 * csrc/pyext/py_model.h marked BOTH, of the first six kinds. */
static const column carrier_columns[] = {PHM_PY_CARRIER_COLUMNS(PHM_PY_SKIP, PHM_PY_KEEP)};
static const column element_columns[] = {PHM_PY_ELEMENT_COLUMNS(PHM_PY_SKIP, PHM_PY_KEEP)};
static const column pair_columns[] = {PHM_PY_PAIR_COLUMNS(PHM_PY_SKIP, PHM_PY_KEEP)};
static const column load_columns[] = {PHM_PY_LOAD_COLUMNS(PHM_PY_SKIP, PHM_PY_KEEP)};
static const column actuator_columns[] = {PHM_PY_ACTUATOR_COLUMNS(PHM_PY_SKIP, PHM_PY_KEEP)};
static const column spring_columns[] = {PHM_PY_SPRING_COLUMNS(PHM_PY_SKIP, PHM_PY_KEEP)};
static const component PLANAR_COMPONENTS[] = {PHM_PY_COMPONENT_KINDS(PHM_PY_SKIP, PHM_PY_KEEP)};
enum { NPLANAR = sizeof PLANAR_COMPONENTS / sizeof PLANAR_COMPONENTS[0] };

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
    if (phm_py_parse_component(&PLANAR_COMPONENTS[c], d, keep, 0, &n[c], &items[c]) < 0) goto done;
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
  else res = phm_py_int_list(drop, s.np);
  PyMem_Free(drop);
  PyMem_Free(ints);
  Py_DECREF(G);
  return res;
}

PyMethodDef phm_py_planar_methods[] = {
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
    {NULL, NULL, 0, NULL}};
