/* py_model.c -- bindings of the model, simulation, modes and statics (csrc/model/, csrc/dae/,
 * csrc/solve/). A model lives in a capsule; python/phmech/mechanism.py builds the flat arrays. */
#include "pyext.h"

#include <limits.h>
#include <math.h>
#include <string.h>

#define CAPSULE_NAME "phmech.model"

static void capsule_free(PyObject *cap) {
  phm_model *m = (phm_model *)PyCapsule_GetPointer(cap, CAPSULE_NAME);
  phm_model_free(m);
}

static phm_model *get_model(PyObject *cap) {
  return (phm_model *)PyCapsule_GetPointer(cap, CAPSULE_NAME);
}

/* law tuple: (kind, amplitude, t0, duration, frequency, phase, offset, table (n, 2) or None);
 * the table array is kept alive in `keep` until the model has copied it. */
static int parse_law(PyObject *obj, phm_law *law, PyObject *keep, const char *what) {
  memset(law, 0, sizeof *law);
  PyObject *tab = Py_None;
  if (!PyArg_ParseTuple(obj, "iddddddO", &law->kind, &law->amplitude, &law->t0, &law->duration,
                        &law->frequency, &law->phase, &law->offset, &tab)) {
    PyErr_Format(phm_py_ModelError, "%s: a time law must be a tuple (kind, amplitude, t0, duration, frequency, phase, offset, table)", what);
    return -1;
  }
  if (tab != Py_None) {
    npy_intp tail[1] = {2};
    PyArrayObject *a = phm_py_double_array(tab, what, tail, 1, 1);
    if (!a) return -1;
    if (PyArray_NDIM(a) != 2) {
      Py_DECREF(a);
      PyErr_Format(phm_py_ModelError, "%s: table must have shape (n, 2)", what);
      return -1;
    }
    law->ntable = (int)PyArray_DIM(a, 0);
    law->table = (const double *)PyArray_DATA(a);
    int r = PyList_Append(keep, (PyObject *)a);
    Py_DECREF(a);
    if (r < 0) return -1;
  }
  return 0;
}

/* Hand a new reference `a` to `keep`, which keeps it alive until the model has copied it;
 * returns a (borrowed) or NULL with the exception set (a is then released). */
static PyArrayObject *kept(PyArrayObject *a, PyObject *keep) {
  if (!a) return NULL;
  int r = PyList_Append(keep, (PyObject *)a);
  Py_DECREF(a);
  return r < 0 ? NULL : a;
}

/* An index or enumeration code given as float64 (the flat arrays of mechanism.py): it must be a
 * whole number representable as int (the core then checks its range); converting anything else
 * to int would truncate (1.5 -> carrier 1) or be undefined behaviour (1e20, C11 6.3.1.4). */
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

/* array with leading length n (checked) and the given tail */
static PyArrayObject *arr(PyObject *o, const char *what, npy_intp n, const npy_intp *tail, int ntail,
                          PyObject *keep) {
  npy_intp t2[4];
  for (int i = 0; i < ntail; i++) t2[i + 1] = tail[i];
  t2[0] = n;
  return kept(phm_py_double_array(o, what, t2, ntail + 1, 0), keep);
}
#define D(a) ((const double *)PyArray_DATA(a))

static PyObject *py_model_new(PyObject *self, PyObject *args, PyObject *kw) {
  (void)self;
  static char *kwl[] = {"M", "mass", "com", "H0", "t0", "el_ab", "el_h", "el_K", "el_D", "el_eps",
                        "pr_type", "pr_ab", "pr_Ta", "pr_Tb", "pr_driven", "pr_axis", "pr_law",
                        "ld_carrier", "ld_world", "ld_point", "ld_w", "ld_law", "gravity",
                        "pr_pitch", "pr_x0", "pr_has_x0", "ld_reaction", "ac_pair", "ac_kind",
                        "ac_vec", "ac_kp", "ac_kd", "ac_xset", "ac_law", "sp_ab", "sp_pa", "sp_pb",
                        "sp_kcd", "pr_drop", NULL};
  PyObject *o[39];
  for (int i = 23; i < 39; i++) o[i] = Py_None;
  if (!PyArg_ParseTupleAndKeywords(args, kw, "OOOOOOOOOOOOOOOOOOOOOOO|OOOOOOOOOOOOOOOO", kwl, &o[0], &o[1], &o[2],
                                   &o[3], &o[4], &o[5], &o[6], &o[7], &o[8], &o[9], &o[10], &o[11],
                                   &o[12], &o[13], &o[14], &o[15], &o[16], &o[17], &o[18], &o[19],
                                   &o[20], &o[21], &o[22], &o[23], &o[24], &o[25], &o[26], &o[27],
                                   &o[28], &o[29], &o[30], &o[31], &o[32], &o[33], &o[34], &o[35],
                                   &o[36], &o[37], &o[38]))
    return NULL;
  PyObject *keep = PyList_New(0);
  if (!keep) return NULL;
  PyObject *result = NULL;
  phm_carrier_desc *car = NULL;
  phm_element_desc *el = NULL;
  phm_pair_desc *pr = NULL;
  phm_load_desc *ld = NULL;
  phm_actuator_desc *ac = NULL;
  phm_spring_desc *sp = NULL;
  PyArrayObject *prdrop = NULL, *prpi = NULL, *prx0 = NULL, *prh0 = NULL, *ldr = NULL, *acp = NULL, *ack = NULL, *acv = NULL,
                *ackp = NULL, *ackd = NULL, *acx = NULL, *spab = NULL, *sppa = NULL, *sppb = NULL, *spk = NULL;
  npy_intp na = 0, ns = 0;
  npy_intp t1[1] = {1}, t3[1] = {3}, t6[1] = {6}, t2[1] = {2}, t66[2] = {6, 6}, t44[2] = {4, 4};
  (void)t1;
  PyArrayObject *mass = kept(phm_py_double_array(o[1], "carrier masses", NULL, 0, 1), keep);
  if (!mass) goto fail;
  if (PyArray_NDIM(mass) != 1) {
    PyErr_SetString(phm_py_ModelError, "carrier masses: expected a 1-D array");
    goto fail;
  }
  npy_intp nc = PyArray_DIM(mass, 0);
  PyArrayObject *M = arr(o[0], "carrier inertias", nc, t66, 2, keep), *com = arr(o[2], "centres of mass", nc, t3, 1, keep),
                *H0 = arr(o[3], "carrier poses", nc, t44, 2, keep), *tw0 = arr(o[4], "carrier twists", nc, t6, 1, keep);
  if (!M || !com || !H0 || !tw0) goto fail;
  PyArrayObject *elh = kept(phm_py_double_array(o[6], "element lengths", NULL, 0, 1), keep);
  if (!elh) goto fail;
  npy_intp ne = PyArray_NDIM(elh) == 1 ? PyArray_DIM(elh, 0) : -1;
  if (ne < 0) {
    PyErr_SetString(phm_py_ModelError, "element lengths: expected a 1-D array");
    goto fail;
  }
  PyArrayObject *elab = arr(o[5], "element nodes", ne, t2, 1, keep), *elK = arr(o[7], "element stiffness", ne, t66, 2, keep),
                *elD = arr(o[8], "element damping", ne, t66, 2, keep), *ele = arr(o[9], "element unstressed strain", ne, t6, 1, keep);
  if (!elab || !elK || !elD || !ele) goto fail;
  PyArrayObject *prt = kept(phm_py_double_array(o[10], "pair types", NULL, 0, 1), keep);
  if (!prt) goto fail;
  npy_intp np_ = PyArray_NDIM(prt) == 1 ? PyArray_DIM(prt, 0) : -1;
  if (np_ < 0) {
    PyErr_SetString(phm_py_ModelError, "pair types: expected a 1-D array");
    goto fail;
  }
  PyArrayObject *prab = arr(o[11], "pair carriers", np_, t2, 1, keep), *prTa = arr(o[12], "pair frames Ta", np_, t44, 2, keep),
                *prTb = arr(o[13], "pair frames Tb", np_, t44, 2, keep), *prdr = arr(o[14], "pair driven flags", np_, NULL, 0, keep),
                *prax = arr(o[15], "pair motion axes", np_, t6, 1, keep);
  if (!prab || !prTa || !prTb || !prdr || !prax) goto fail;
  if (!PyList_Check(o[16]) || PyList_GET_SIZE(o[16]) != np_) {
    PyErr_SetString(phm_py_ModelError, "pair laws: expected a list with one law per pair");
    goto fail;
  }
  PyArrayObject *ldc = kept(phm_py_double_array(o[17], "load carriers", NULL, 0, 1), keep);
  if (!ldc) goto fail;
  npy_intp nl = PyArray_NDIM(ldc) == 1 ? PyArray_DIM(ldc, 0) : -1;
  if (nl < 0) {
    PyErr_SetString(phm_py_ModelError, "load carriers: expected a 1-D array");
    goto fail;
  }
  PyArrayObject *ldw = arr(o[18], "load frames", nl, NULL, 0, keep), *ldp = arr(o[19], "load points", nl, t3, 1, keep),
                *ldv = arr(o[20], "load wrenches", nl, t6, 1, keep), *grav;
  if (!ldw || !ldp || !ldv) goto fail;
  if (!PyList_Check(o[21]) || PyList_GET_SIZE(o[21]) != nl) {
    PyErr_SetString(phm_py_ModelError, "load laws: expected a list with one law per load");
    goto fail;
  }
  {
    npy_intp g3[1] = {3};
    grav = kept(phm_py_double_array(o[22], "gravity", g3, 1, 0), keep);
    if (!grav) goto fail;
  }
  if ((o[23] != Py_None && !(prpi = arr(o[23], "pair pitches", np_, NULL, 0, keep))) ||
      (o[24] != Py_None && !(prx0 = arr(o[24], "pair initial coordinates", np_, t6, 1, keep))) ||
      (o[25] != Py_None && !(prh0 = arr(o[25], "pair x0 flags", np_, NULL, 0, keep))) ||
      (o[26] != Py_None && !(ldr = arr(o[26], "load reactions", nl, NULL, 0, keep))) ||
      (o[38] != Py_None && !(prdrop = arr(o[38], "pair drop masks", np_, NULL, 0, keep))))
    goto fail;
  if (o[27] != Py_None) {
    acp = kept(phm_py_double_array(o[27], "actuator pairs", NULL, 0, 1), keep);
    if (!acp) goto fail;
    na = PyArray_NDIM(acp) == 1 ? PyArray_DIM(acp, 0) : -1;
    if (na < 0) {
      PyErr_SetString(phm_py_ModelError, "actuator pairs: expected a 1-D array");
      goto fail;
    }
    if (!(ack = arr(o[28], "actuator kinds", na, NULL, 0, keep)) || !(acv = arr(o[29], "actuator vectors", na, t6, 1, keep)) ||
        !(ackp = arr(o[30], "actuator kp", na, t6, 1, keep)) || !(ackd = arr(o[31], "actuator kd", na, t6, 1, keep)) ||
        !(acx = arr(o[32], "actuator set points", na, t6, 1, keep)))
      goto fail;
    if (!PyList_Check(o[33]) || PyList_GET_SIZE(o[33]) != na) {
      PyErr_SetString(phm_py_ModelError, "actuator laws: expected a list with one law per actuator");
      goto fail;
    }
  }
  if (o[34] != Py_None) {
    spk = kept(phm_py_double_array(o[37], "spring parameters", t3, 1, 1), keep);
    if (!spk) goto fail;
    ns = PyArray_NDIM(spk) == 2 ? PyArray_DIM(spk, 0) : -1;
    if (ns < 0) {
      PyErr_SetString(phm_py_ModelError, "spring parameters: expected an (n, 3) array");
      goto fail;
    }
    if (!(spab = arr(o[34], "spring carriers", ns, t2, 1, keep)) || !(sppa = arr(o[35], "spring points a", ns, t3, 1, keep)) ||
        !(sppb = arr(o[36], "spring points b", ns, t3, 1, keep)))
      goto fail;
  }
  ac = calloc((size_t)na + 1, sizeof *ac);
  sp = calloc((size_t)ns + 1, sizeof *sp);
  car = calloc((size_t)nc + 1, sizeof *car);
  el = calloc((size_t)ne + 1, sizeof *el);
  pr = calloc((size_t)np_ + 1, sizeof *pr);
  ld = calloc((size_t)nl + 1, sizeof *ld);
  if (!car || !el || !pr || !ld || !ac || !sp) {
    PyErr_NoMemory();
    goto fail;
  }
  for (npy_intp i = 0; i < nc; i++) {
    memcpy(car[i].M, D(M) + 36 * i, 36 * sizeof(double));
    car[i].mass = D(mass)[i];
    memcpy(car[i].com, D(com) + 3 * i, 3 * sizeof(double));
    memcpy(car[i].H0, D(H0) + 16 * i, 16 * sizeof(double));
    memcpy(car[i].t0, D(tw0) + 6 * i, 6 * sizeof(double));
  }
  for (npy_intp i = 0; i < ne; i++) {
    if (to_int(D(elab)[2 * i], "element", i, &el[i].a) < 0 ||
        to_int(D(elab)[2 * i + 1], "element", i, &el[i].b) < 0)
      goto fail;
    el[i].h = D(elh)[i];
    memcpy(el[i].K, D(elK) + 36 * i, 36 * sizeof(double));
    memcpy(el[i].D, D(elD) + 36 * i, 36 * sizeof(double));
    memcpy(el[i].eps_hat, D(ele) + 6 * i, 6 * sizeof(double));
  }
  for (npy_intp i = 0; i < np_; i++) {
    if (to_int(D(prt)[i], "pair type of pair", i, &pr[i].type) < 0 ||
        to_int(D(prab)[2 * i], "pair", i, &pr[i].a) < 0 ||
        to_int(D(prab)[2 * i + 1], "pair", i, &pr[i].b) < 0)
      goto fail;
    memcpy(pr[i].Ta, D(prTa) + 16 * i, 16 * sizeof(double));
    memcpy(pr[i].Tb, D(prTb) + 16 * i, 16 * sizeof(double));
    pr[i].driven = D(prdr)[i] != 0;
    memcpy(pr[i].axis, D(prax) + 6 * i, 6 * sizeof(double));
    if (prpi) pr[i].pitch = D(prpi)[i];
    if (prh0) pr[i].has_x0 = D(prh0)[i] != 0;
    if (prx0) memcpy(pr[i].x0, D(prx0) + 6 * i, 6 * sizeof(double));
    if (prdrop) {
      double v = D(prdrop)[i];
      if (!(v >= 0 && v < 64 && v == (int)v)) {
        PyErr_Format(phm_py_ModelError, "pair %d: drop mask must be an integer in [0, 64)", (int)i);
        goto fail;
      }
      pr[i].drop = (int)v;
    }
    PyObject *lw = PyList_GET_ITEM(o[16], i);
    if (pr[i].driven && parse_law(lw, &pr[i].law, keep, "pair motion law") < 0) goto fail;
  }
  for (npy_intp i = 0; i < nl; i++) {
    if (to_int(D(ldc)[i], "load", i, &ld[i].carrier) < 0) goto fail;
    ld[i].world = D(ldw)[i] != 0;
    memcpy(ld[i].point, D(ldp) + 3 * i, 3 * sizeof(double));
    memcpy(ld[i].w, D(ldv) + 6 * i, 6 * sizeof(double));
    ld[i].reaction = -1;
    if (ldr && to_int(D(ldr)[i], "reaction of load", i, &ld[i].reaction) < 0) goto fail;
    if (parse_law(PyList_GET_ITEM(o[21], i), &ld[i].law, keep, "load law") < 0) goto fail;
  }
  for (npy_intp i = 0; i < na; i++) {
    if (to_int(D(acp)[i], "pair of actuator", i, &ac[i].pair) < 0 ||
        to_int(D(ack)[i], "kind of actuator", i, &ac[i].kind) < 0)
      goto fail;
    memcpy(ac[i].vec, D(acv) + 6 * i, 6 * sizeof(double));
    memcpy(ac[i].kp, D(ackp) + 6 * i, 6 * sizeof(double));
    memcpy(ac[i].kd, D(ackd) + 6 * i, 6 * sizeof(double));
    memcpy(ac[i].x_set, D(acx) + 6 * i, 6 * sizeof(double));
    PyObject *lw = PyList_GET_ITEM(o[33], i);
    if (lw != Py_None && parse_law(lw, &ac[i].law, keep, "actuator law") < 0) goto fail;
  }
  for (npy_intp i = 0; i < ns; i++) {
    if (to_int(D(spab)[2 * i], "spring", i, &sp[i].a) < 0 ||
        to_int(D(spab)[2 * i + 1], "spring", i, &sp[i].b) < 0)
      goto fail;
    memcpy(sp[i].pa, D(sppa) + 3 * i, 3 * sizeof(double));
    memcpy(sp[i].pb, D(sppb) + 3 * i, 3 * sizeof(double));
    sp[i].k = D(spk)[3 * i];
    sp[i].c = D(spk)[3 * i + 1];
    sp[i].d0 = D(spk)[3 * i + 2];
  }
  {
    phm_model_desc d;
    memset(&d, 0, sizeof d);
    d.ncarriers = (int)nc;
    d.carriers = car;
    d.nelements = (int)ne;
    d.elements = el;
    d.npairs = (int)np_;
    d.pairs = pr;
    d.nloads = (int)nl;
    d.loads = ld;
    d.nactuators = (int)na;
    d.actuators = ac;
    d.nsprings = (int)ns;
    d.springs = sp;
    memcpy(d.gravity, D(grav), 3 * sizeof(double));
    phm_model *m = NULL;
    phm_error err;
    if (phm_model_create(&d, &m, &err)) {
      phm_py_raise(&err);
      goto fail;
    }
    result = PyCapsule_New(m, CAPSULE_NAME, capsule_free);
    if (!result) phm_model_free(m);
  }
fail:
  free(car);
  free(el);
  free(pr);
  free(ld);
  free(ac);
  free(sp);
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
  int stop = PyObject_IsTrue(r) == 1;
  Py_DECREF(r);
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

static int interrupt_cb(void *vctx, double t, int iout) {
  (void)t;
  (void)iout;
  PyGILState_STATE g = PyGILState_Ensure();
  int stop = signal_pending((cb_ctx *)vctx);
  PyGILState_Release(g);
  return stop;
}

static int progress_cb(void *vctx, double t, int iout) {
  cb_ctx *c = (cb_ctx *)vctx;
  if (!c->cb) return 0;
  PyGILState_STATE g = PyGILState_Ensure();
  int stop = callable_says_stop(c, PyObject_CallFunction(c->cb, "di", t, iout));
  PyGILState_Release(g);
  return stop;
}

static PyObject *py_model_simulate(PyObject *self, PyObject *args, PyObject *kw) {
  (void)self;
  static char *kwl[] = {"model", "tout", "rtol", "atol", "linear_solver", "poses", "twists",
                        "callback", "max_step", "max_order", "record", "error_test",
                        "integrator", "step", "rho_inf", "adaptive", "band", "monitor", NULL};
  PyObject *cap, *to, *po = Py_None, *twi = Py_None, *cb = Py_None, *rec = Py_None, *mon = Py_None;
  PyObject *res = NULL; /* before the first `goto fail0`: that path returns it */
  PyArrayObject *R = NULL; /* carriers to record (int array) or NULL: all */
  double rtol, atol, max_step = 0;
  int solver = 0, max_order = 0, error_test = 0, integrator = 0;
  double step = 0, rho_inf = 1, band = 0;
  int adaptive = 0;
  if (!PyArg_ParseTupleAndKeywords(args, kw, "OOddi|OOOdiOiiddidO", kwl, &cap, &to, &rtol, &atol, &solver,
                                   &po, &twi, &cb, &max_step, &max_order, &rec, &error_test,
                                   &integrator, &step, &rho_inf, &adaptive, &band, &mon))
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
  if ((cb != Py_None && !PyCallable_Check(cb)) || (mon != Py_None && !PyCallable_Check(mon))) {
    PyErr_SetString(PyExc_TypeError, "callback and monitor must be callable");
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
  npy_intp dp[4] = {nout, nrec, 4, 4}, dt[3] = {nout, nrec, 6}, dl[2] = {nout, nk}, de[2] = {nout, PHM_NENERGY};
  npy_intp dj[2] = {nout, nj}, dw[3] = {nout, npr, 6}, dq[2] = {nout, npt};
  PyArrayObject *jx = (PyArrayObject *)PyArray_ZEROS(2, dj, NPY_DOUBLE, 0);
  PyArrayObject *jv = (PyArrayObject *)PyArray_ZEROS(2, dj, NPY_DOUBLE, 0);
  PyArrayObject *ju = (PyArrayObject *)PyArray_ZEROS(2, dj, NPY_DOUBLE, 0);
  PyArrayObject *pw = (PyArrayObject *)PyArray_ZEROS(3, dw, NPY_DOUBLE, 0);
  PyArrayObject *po_ = (PyArrayObject *)PyArray_ZEROS(2, dq, NPY_DOUBLE, 0);
  PyArrayObject *poses = (PyArrayObject *)PyArray_ZEROS(4, dp, NPY_DOUBLE, 0);
  PyArrayObject *tw = (PyArrayObject *)PyArray_ZEROS(3, dt, NPY_DOUBLE, 0);
  PyArrayObject *lam = (PyArrayObject *)PyArray_ZEROS(2, dl, NPY_DOUBLE, 0);
  PyArrayObject *en = (PyArrayObject *)PyArray_ZEROS(2, de, NPY_DOUBLE, 0);
  if (!poses || !tw || !lam || !en || !jx || !jv || !ju || !pw || !po_) goto fail;
  cb_ctx c = {cb == Py_None ? NULL : cb, 0, 0, NULL, NULL, NULL, mon == Py_None ? NULL : mon};
  phm_sim_options opt = {rtol, atol, solver, 0, max_step, max_order, error_test, interrupt_cb, progress_cb, &c,
                         integrator, step, rho_inf, adaptive, band, monitor_cb};
  phm_sim_output out;
  memset(&out, 0, sizeof out);
  out.record = R ? (const int *)PyArray_DATA(R) : NULL;
  out.nrecord = (int)nrec;
  out.poses = PyArray_DATA(poses);
  out.twists = PyArray_DATA(tw);
  out.lambda = PyArray_DATA(lam);
  out.energy = PyArray_DATA(en);
  out.joints = PyArray_DATA(jx);
  out.jrates = PyArray_DATA(jv);
  out.efforts = PyArray_DATA(ju);
  out.pwrench = PyArray_DATA(pw);
  out.ports = PyArray_DATA(po_);
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
  /* a solver failure still returns what was computed (nout filled outputs), with the error's
   * kind and message: Python raises it with the partial result attached */
  int failed = st != PHM_OK && st != PHM_EINTERRUPT;
  if (failed && (err.code == PHM_EINVAL || err.code == PHM_ENOMEM)) {
    phm_py_raise(&err);
    goto fail;
  }
  res = Py_BuildValue("{s:O,s:O,s:O,s:O,s:O,s:O,s:O,s:O,s:O,s:O,s:i,s:i,s:s,"
                      "s:{s:l,s:l,s:l,s:l,s:l,s:l,s:d,s:d,s:i,s:l,s:d}}", "t", tout,
                      "poses", poses, "twists", tw, "lambda", lam, "energy", en, "joints", jx,
                      "jrates", jv, "efforts", ju, "pair_wrenches", pw, "ports", po_, "nout", out.nout_done,
                      "interrupted", st == PHM_EINTERRUPT, "error", failed ? err.msg : "",
                      "stats", "steps", out.nsteps,
                      "residual_evals", out.nres, "jacobian_evals", out.njac, "nonlinear_iters",
                      out.nniters, "error_test_fails", out.netf, "nonlinear_conv_fails", out.nncf,
                      "wall_time", out.wall_time, "last_step", out.last_step, "last_order", out.last_order,
                      "floor_steps", out.nfloor, "error_estimate", out.err_est);
fail:
  Py_XDECREF(jx);
  Py_XDECREF(jv);
  Py_XDECREF(ju);
  Py_XDECREF(pw);
  Py_XDECREF(po_);
  Py_XDECREF(poses);
  Py_XDECREF(tw);
  Py_XDECREF(lam);
  Py_XDECREF(en);
fail0:
  Py_DECREF(tout);
  Py_XDECREF(P);
  Py_XDECREF(T);
  Py_XDECREF(R);
  return res;
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
  int nc = phm_model_ncarriers(m), nk = phm_model_nconstraints(m);
  PyArrayObject *P = NULL, *L = NULL;
  if (po != Py_None) {
    npy_intp tail[3] = {nc, 4, 4};
    if (!(P = phm_py_double_array(po, "poses", tail, 3, 0))) return NULL;
  }
  if (lo != Py_None) {
    npy_intp tail[1] = {nk};
    if (!(L = phm_py_double_array(lo, "constraint wrenches", tail, 1, 0))) {
      Py_XDECREF(P);
      return NULL;
    }
  }
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
    if (st) phm_py_raise(&err);
    else res = Py_BuildValue("OOOi", om, ze, sh, nf);
  }
  Py_XDECREF(om);
  Py_XDECREF(ze);
  Py_XDECREF(sh);
  Py_XDECREF(P);
  Py_XDECREF(L);
  return res;
}

static PyObject *py_model_static(PyObject *self, PyObject *args) {
  (void)self;
  PyObject *cap, *po = Py_None;
  double time = 0, tol = 1e-10;
  int steps = 1;
  if (!PyArg_ParseTuple(args, "O|Odid", &cap, &po, &time, &steps, &tol)) return NULL;
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
  if (poses && lam) {
    int it = 0;
    phm_error err;
    phm_status st;
    Py_BEGIN_ALLOW_THREADS
    st = phm_static(m, P ? PyArray_DATA(P) : NULL, time, steps, tol, PyArray_DATA(poses),
                    PyArray_DATA(lam), &it, &err);
    Py_END_ALLOW_THREADS
    if (st) phm_py_raise(&err);
    else res = Py_BuildValue("OOi", poses, lam, it);
  }
  Py_XDECREF(poses);
  Py_XDECREF(lam);
  Py_XDECREF(P);
  return res;
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
    res = Py_BuildValue("OOO", g, G, W);
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

PyMethodDef phm_py_model_methods[] = {
    {"model_constraints_full", py_model_constraints_full, METH_VARARGS,
     "model_constraints_full(model, poses, xs=None, time=0) -> (g (nfull,), G (nfull, 6 nc), W "
     "(npairs, 6, 6)): all constraint rows, redundant (dropped) ones included."},
    {"model_joints", py_model_joints, METH_VARARGS,
     "model_joints(model, poses, xs=None) -> x (njoints,): joint coordinates at the poses."},
    {"model_new", (PyCFunction)(void (*)(void))py_model_new, METH_VARARGS | METH_KEYWORDS,
     "model_new(M, mass, com, H0, t0, el_ab, el_h, el_K, el_D, el_eps, pr_type, pr_ab, pr_Ta, "
     "pr_Tb, pr_driven, pr_axis, pr_law, ld_carrier, ld_world, ld_point, ld_w, ld_law, gravity, "
     "pr_pitch=None, pr_x0=None, pr_has_x0=None, ld_reaction=None, ac_pair=None, ac_kind, ac_vec, "
     "ac_kp, ac_kd, ac_xset, ac_law, sp_ab=None, sp_pa, sp_pb, sp_kcd (k, c, d0)) "
     "-> model capsule (validated; raises ModelError)."},
    {"model_simulate", (PyCFunction)(void (*)(void))py_model_simulate, METH_VARARGS | METH_KEYWORDS,
     "model_simulate(model, tout, rtol, atol, linear_solver, poses=None, twists=None, "
     "callback=None, max_step=0, max_order=0, record=None, error_test=0, integrator=0, step=0, "
     "rho_inf=1) -> dict of arrays and solver statistics."},
    {"model_modes", py_model_modes, METH_VARARGS,
     "model_modes(model, n, poses=None, lambda=None, time=0, method=0) -> (omega, zeta, shapes, "
     "nfound); method 0 auto, 1 dense, 2 sparse (phm_modes)."},
    {"model_static", py_model_static, METH_VARARGS,
     "model_static(model, poses=None, time=0, steps=1, tol=1e-10) -> (poses, lambda, iterations)."},
    {"model_sizes", py_model_sizes, METH_O, "model_sizes(model) -> (ncarriers, nconstraints, njoints, nports, [(row, m, joint, k) per pair])."},
    {NULL, NULL, 0, NULL}};
