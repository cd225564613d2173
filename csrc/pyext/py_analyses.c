/* py_analyses.c -- the analyses of a model at a point (csrc/analyze/): modes and their count,
 * the linear model, statics and the free motions that prove there is no static equilibrium. */
#include "py_model.h"

#include <limits.h>
#include <math.h>
#include <string.h>

/* ---------------------------------------------------------------- analyses */
/* The poses (None: the model's initial ones) and constraint wrenches (None: zero) a
 * linearization is taken at, as arrays in *P, *L (NULL for None); 0, or -1 with an exception set
 * and nothing held. */
static int linearization_point(const phm_model *m, PyObject *po, PyObject *lo, PyArrayObject **P,
                               PyArrayObject **L) {
  *L = NULL;
  if (phm_py_model_poses(m, po, "poses", 1, P) < 0) return -1;
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
  phm_model *m = phm_py_get_model(cap);
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
    phm_modes_stats ms;
    phm_error err;
    phm_status st;
    Py_BEGIN_ALLOW_THREADS
    st = phm_modes(m, P ? PyArray_DATA(P) : NULL, L ? PyArray_DATA(L) : NULL, time, n, method,
                   PyArray_DATA(om), PyArray_DATA(ze), PyArray_DATA(sh), &nf, &ms, &err);
    Py_END_ALLOW_THREADS
    if (phm_py_model_law_error(cap)) res = NULL;
    else if (st) phm_py_raise(&err);
    else
      res = Py_BuildValue("OOOi{s:i,s:i,s:i,s:d,s:d}", om, ze, sh, nf, "method", ms.method,
                          "iterations", ms.iterations, "reshifts", ms.reshifts, "shift0",
                          ms.shift0, "shift", ms.shift);
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
  phm_model *m = phm_py_get_model(cap);
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
  if (phm_py_model_law_error(cap)) res = NULL;
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
  PyObject *cap, *plist, *po = Py_None, *lo = Py_None, *zo = Py_None;
  double time = 0;
  int withc = 0;
  if (!PyArg_ParseTuple(args, "OO|OOdpO", &cap, &plist, &po, &lo, &time, &withc, &zo)) return NULL;
  phm_model *m = phm_py_get_model(cap);
  if (!m) return NULL;
  if (!PyList_Check(plist)) {
    PyErr_SetString(phm_py_ModelError, "model_linear: ports must be a list of (kind, index, T)");
    return NULL;
  }
  int nc = phm_model_ncarriers(m), n6 = 6 * nc;
  Py_ssize_t np_ = PyList_GET_SIZE(plist);
  phm_linear_port *ports = PyMem_Calloc((size_t)np_ + 1, sizeof(phm_linear_port));
  PyArrayObject *P = NULL, *L = NULL, *K = NULL, *D = NULL, *M = NULL, *Z = NULL, *B = NULL;
  PyArrayObject *C[10] = {NULL}, *Zs = NULL; /* the components' blocks (phm_linear_components) */
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
  phm_linear_components comp = {0};
  int nz = phm_model_ncompstates(m);
  if (withc) {
    npy_intp sz[10] = {(npy_intp)n6 * n6, (npy_intp)n6 * n6, (npy_intp)n6 * nz, (npy_intp)n6 * nz,
                       (npy_intp)n6 * nz, (npy_intp)nz * nz, n6, n6, nz, (npy_intp)n6 * n6};
    for (int i = 0; i < 10; i++)
      if (!(C[i] = (PyArrayObject *)PyArray_ZEROS(1, sz + i, NPY_DOUBLE, 0))) goto fail;
    double **out[10] = {&comp.Kc, &comp.Dc, &comp.Kz, &comp.Fq, &comp.Fv, &comp.Fz, &comp.f, &comp.fc,
                        &comp.zdot, &comp.G};
    for (int i = 0; i < 10; i++) *out[i] = PyArray_DATA(C[i]);
    if (zo != Py_None) {
      npy_intp tail[1] = {nz};
      if (!(Zs = phm_py_double_array(zo, "component states", tail, 1, 0))) goto fail;
      comp.z = PyArray_DATA(Zs);
    }
  }
  {
    int nr = 0;
    phm_error err;
    phm_status st;
    Py_BEGIN_ALLOW_THREADS
    st = phm_linear_closed_loop(m, P ? PyArray_DATA(P) : NULL, L ? PyArray_DATA(L) : NULL, time,
                                (int)np_, ports, &nr, PyArray_DATA(K), PyArray_DATA(D),
                                PyArray_DATA(M), PyArray_DATA(Z), PyArray_DATA(B),
                                withc ? &comp : NULL, &err);
    Py_END_ALLOW_THREADS
    if (st) {
      phm_py_raise(&err);
      goto fail;
    }
    /* flat buffers: the leading nr x nr (Z: 6 nc x nr, B: nr x ncol) values are the matrices */
    PyObject *sizes = Py_BuildValue("(ii)", nr, ncol);
    if (sizes && withc)
      res = Py_BuildValue("(OOOOON(OOOOOOOOOiOd))", K, D, M, Z, B, sizes, C[0], C[1], C[2], C[3],
                          C[4], C[5], C[6], C[7], C[8], nz, C[9], comp.fmax);
    else if (sizes)
      res = Py_BuildValue("(OOOOON)", K, D, M, Z, B, sizes);
  }
fail:
  PyMem_Free(ports);
  Py_XDECREF(P); Py_XDECREF(L);
  Py_XDECREF(K); Py_XDECREF(D); Py_XDECREF(M); Py_XDECREF(Z); Py_XDECREF(B);
  for (int i = 0; i < 10; i++) Py_XDECREF(C[i]);
  Py_XDECREF(Zs);
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
  phm_model *m = phm_py_get_model(cap);
  if (!m) return NULL;
  int nc = phm_model_ncarriers(m), nk = phm_model_nconstraints(m);
  PyArrayObject *P;
  if (phm_py_model_poses(m, po, "poses", 1, &P) < 0) return NULL;
  npy_intp dp[3] = {nc, 4, 4}, dl[1] = {nk};
  PyArrayObject *poses = (PyArrayObject *)PyArray_ZEROS(3, dp, NPY_DOUBLE, 0);
  PyArrayObject *lam = (PyArrayObject *)PyArray_ZEROS(1, dl, NPY_DOUBLE, 0);
  PyObject *res = NULL;
  /* with a monitor: called after each load step (progress), and Ctrl-C stops the solve */
  phm_py_run c = {0};
  c.mon = mon == Py_None ? NULL : mon;
  if (poses && lam) {
    int it = 0;
    double reached = 0;
    phm_error err;
    phm_status st;
    Py_BEGIN_ALLOW_THREADS
    st = phm_static_monitored(m, P ? PyArray_DATA(P) : NULL, time, steps, tol,
                              c.mon ? phm_py_monitor_cb : NULL, &c, PyArray_DATA(poses),
                              PyArray_DATA(lam), &it, &reached, &err);
    Py_END_ALLOW_THREADS
    if (c.failed) PyErr_Restore(c.et, c.ev, c.etb);
    else if (phm_py_model_law_error(cap)) res = NULL; /* a callable law raised: that exception */
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

/* What phm_static_free found: its motions, each one's moving carriers (nc flags) and loads' work
 * (nl values). */
typedef struct {
  const phm_free_motion *fm;
  const unsigned char *mv;
  const double *lw;
  int nc, nl;
} free_motions;

/* Motion k of the free_motions `ctx` as a dict (model_static_free). */
static PyObject *free_motion_dict(int k, const void *ctx) {
  const free_motions *f = ctx;
  const phm_free_motion *fm = f->fm + k;
  npy_intp d6[1] = {6}, dn[1] = {f->nc}, dl[1] = {f->nl};
  PyArrayObject *tw = (PyArrayObject *)PyArray_SimpleNew(1, d6, NPY_DOUBLE);
  PyArrayObject *mo = (PyArrayObject *)PyArray_SimpleNew(1, dn, NPY_BOOL);
  PyArrayObject *lo = (PyArrayObject *)PyArray_SimpleNew(1, dl, NPY_DOUBLE);
  PyObject *d = NULL;
  if (tw && mo && lo) {
    memcpy(PyArray_DATA(tw), fm->twist, sizeof fm->twist);
    for (int c = 0; c < f->nc; c++) ((npy_bool *)PyArray_DATA(mo))[c] = f->mv[(size_t)k * f->nc + c] != 0;
    if (f->nl) memcpy(PyArray_DATA(lo), f->lw + (size_t)k * f->nl, sizeof(double) * (size_t)f->nl);
    d = Py_BuildValue("{s:i,s:i,s:i,s:O,s:d,s:d,s:d,s:d,s:O,s:O}", "pair", fm->pair, "coord",
                      fm->coord, "carrier", fm->carrier, "twist", tw, "force", fm->force, "gravity",
                      fm->gravity, "effort", fm->effort, "mass", fm->mass, "moving", mo,
                      "load_work", lo);
  }
  Py_XDECREF(tw);
  Py_XDECREF(mo);
  Py_XDECREF(lo);
  return d;
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
  phm_model *m = phm_py_get_model(cap);
  if (!m) return NULL;
  if (nmax < 1 || nmax > 1000) {
    PyErr_SetString(phm_py_ModelError, "model_static_free: nmax must be in [1, 1000]");
    return NULL;
  }
  int nc = phm_model_ncarriers(m), nl = phm_model_nloads(m);
  PyArrayObject *P;
  if (phm_py_model_poses(m, po, "poses", 1, &P) < 0) return NULL;
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
  if (phm_py_model_law_error(cap)) goto done;
  if (st) {
    phm_py_raise(&err);
    goto done;
  }
  free_motions f = {fm, mv, lw, nc, nl};
  res = phm_py_list(n, free_motion_dict, &f);
done:
  PyMem_Free(fm);
  PyMem_Free(mv);
  PyMem_Free(lw);
  Py_XDECREF(P);
  return res;
}

PyMethodDef phm_py_analysis_methods[] = {
    {"model_modes", py_model_modes, METH_VARARGS,
     "model_modes(model, n, poses=None, lambda=None, time=0, method=0) -> (omega, zeta, shapes, "
     "nfound, stats); method 0 auto, 1 dense, 2 sparse (phm_modes); stats: dict of "
     "phm_modes_stats (method, iterations, reshifts, shift0, shift)."},
    {"model_modes_count", py_model_modes_count, METH_VARARGS,
     "model_modes_count(model, shift, poses=None, lambda=None, time=0) -> (below, check): how many "
     "eigenvalues omega^2 lie below shift [(rad/s)^2] (phm_modes_count)"},
    {"model_linear", py_model_linear, METH_VARARGS,
     "model_linear(model, ports, poses=None, lambda=None, time=0, components=False, z=None) -> (K, "
     "D, M, Z, B, (nr, ncol)): flat buffers whose leading nr*nr (Z: 6nc*nr, B: nr*ncol) values are "
     "the row-major matrices of phm_linear_model; ports: a list of (kind 0 pair | 1 load | 2 frame, "
     "index, T (4, 4)). components: a 7th entry (Kc, Dc, Kz, Fq, Fv, Fz, f, fc, zdot, nz, G, fmax) of "
     "phm_linear_closed_loop at the components' states z (nz; None: their initial states)."},
    {"model_static", py_model_static, METH_VARARGS,
     "model_static(model, poses=None, time=0, steps=1, tol=1e-10, monitor=None) -> (poses, lambda, "
     "iterations); monitor(load factor, iterations, load step) after each load step, truthy to stop; "
     "steps=0: the full load at once from poses (no unloaded start); steps=-1: the same, Newton only (no continuation)."},
    {"model_static_free", py_model_static_free, METH_VARARGS,
     "model_static_free(model, poses=None, time=0, nmax=8) -> list of dicts (pair, coord, carrier, "
     "twist, force, gravity, effort, mass, moving, load_work): motions nothing resists on which the "
     "loads do work (phm_static_free): each proves there is no static equilibrium."},
    {NULL, NULL, 0, NULL}};
