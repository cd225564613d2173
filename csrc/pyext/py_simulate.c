/* py_simulate.c -- model_simulate (csrc/integrate/simulate.c, phm_simulate): its options (filled by
 * field name; the callbacks between outputs: py_run.c), the result arrays (named and shaped by the
 * table of result quantities, csrc/include/phmech_results.h) and statistics. */
#include "py_model.h"

#include <limits.h>
#include <math.h>
#include <string.h>

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
  phm_model *m = phm_py_get_model(cap);
  if (!m) return NULL;
  int nc = phm_model_ncarriers(m);
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
  if (phm_py_model_poses(m, po, "initial poses", 1, &P) < 0) goto fail0;
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
  /* the result arrays, in the table's order (csrc/include/phmech_results.h), zeros */
  PyArrayObject *ra[PHM_NRESULT_FIELDS] = {NULL};
  for (int f = 0; f < PHM_NRESULT_FIELDS; f++) {
    long shape[3];
    const char *names[3];
    int nd = phm_result_shape(m, (int)nrec, f, shape, names);
    npy_intp dims[4] = {nout};
    for (int k = 0; k < nd; k++) dims[k + 1] = shape[k];
    if (!(ra[f] = (PyArrayObject *)PyArray_ZEROS(nd + 1, dims, NPY_DOUBLE, 0))) goto fail;
  }
  if (arr != Py_None) { /* the arrays the run fills, output by output (a checkpoint reads the
                         * first i + 1 of them at output i: dae_emit_output stores before it calls) */
    PyObject *d = result_arrays(tout, ra), *r = d ? PyObject_CallFunctionObjArgs(arr, d, NULL) : NULL;
    Py_XDECREF(d);
    if (!r) goto fail;
    Py_DECREF(r);
  }
  phm_py_run c = {.cb = cb == Py_None ? NULL : cb, .mon = mon == Py_None ? NULL : mon};
  phm_sim_options opt = {.rtol = rtol, .atol = atol, .linear_solver = solver, .max_steps = 0,
                         .max_step = max_step, .interrupt = phm_py_interrupt_cb,
                         .progress = phm_py_progress_cb, .ctx = &c, .integrator = integrator,
                         .monitor = phm_py_monitor_cb, .planar = planar,
                         .ida = {.max_order = max_order, .error_test = error_test},
                         .galpha = {.step = step, .rho_inf = rho_inf, .adaptive = adaptive, .band = band}};
  phm_sim_output out;
  memset(&out, 0, sizeof out);
  out.record = R ? (const int *)PyArray_DATA(R) : NULL;
  out.nrecord = (int)nrec;
  for (int f = 0; f < PHM_NRESULT_FIELDS; f++) out.field[f] = PyArray_DATA(ra[f]);
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
  /* a callable law raised: that error, not the solver's failure, returned with the outputs
   * computed before it as "law_error" (python/phmech/_simulate.py raises it with the partial
   * result attached, as a solver failure's) */
  PyObject *law_error = NULL;
  if (phm_py_model_law_error(cap)) {
    PyObject *et, *ev, *etb;
    PyErr_Fetch(&et, &ev, &etb);
    PyErr_NormalizeException(&et, &ev, &etb);
    if (ev && etb) PyException_SetTraceback(ev, etb);
    Py_XDECREF(et);
    Py_XDECREF(etb);
    if (!ev) goto fail;
    law_error = ev;
  }
  /* a solver failure still returns what was computed (nout filled outputs), with the error's
   * kind and message: Python raises it with the partial result attached */
  int failed = st != PHM_OK && st != PHM_EINTERRUPT;
  if (!law_error && failed && (err.code == PHM_EINVAL || err.code == PHM_ENOMEM)) {
    phm_py_raise(&err);
    goto fail;
  }
  res = result_arrays(tout, ra);
  PyObject *rest = res ? Py_BuildValue("{s:i,s:i,s:s,"
                      "s:{s:l,s:l,s:l,s:l,s:l,s:l,s:d,s:d,s:i,s:l,s:d,s:d,s:d,s:d,s:d,s:d,s:d,s:l,s:d,s:d,s:d,s:l,s:d,s:d,s:l}}",
                      "nout", out.nout_done,
                      "interrupted", st == PHM_EINTERRUPT, "error", failed ? err.msg : "",
                      "stats", "steps", out.nsteps,
                      "residual_evals", out.nres, "jacobian_evals", out.njac, "nonlinear_iters",
                      out.nniters, "error_test_fails", out.netf, "nonlinear_conv_fails", out.nncf,
                      "wall_time", out.wall_time, "last_step", out.last_step, "last_order", out.last_order,
                      "floor_steps", out.nfloor, "error_estimate", out.err_est, "error_sum", out.err_sum, "error_sum_max", out.err_sum_max, "max_mu", out.max_mu,
                      "error_ratio", out.err_ratio, "error_ratio_time", out.t_err_ratio,
                      "min_step", out.min_step, "noise_steps", out.nnoise, "newton_rtol", out.newton_rtol,
                      "global_error_estimate", out.glob_err, "global_error_time", out.t_glob_err,
                      "global_error_state", out.glob_state,
                      "global_error_absolute", out.glob_err_abs, "global_error_scale", out.glob_scale,
                      "global_error_stiff_blocks", out.nglob_stiff) : NULL;
  if (!rest || PyDict_Update(res, rest) < 0) Py_CLEAR(res);
  Py_XDECREF(rest);
  if (res && PyDict_SetItemString(res, "law_error", law_error ? law_error : Py_None) < 0) Py_CLEAR(res);
  Py_XDECREF(law_error);
fail:
  for (int i = 0; i < PHM_NRESULT_FIELDS; i++) Py_XDECREF(ra[i]);
fail0:
  Py_DECREF(tout);
  Py_XDECREF(P);
  Py_XDECREF(T);
  Py_XDECREF(R);
  return res;
}

PyMethodDef phm_py_simulate_methods[] = {
    {"model_simulate", (PyCFunction)(void (*)(void))py_model_simulate, METH_VARARGS | METH_KEYWORDS,
     "model_simulate(model, tout, rtol, atol, linear_solver, poses=None, twists=None, "
     "callback=None, max_step=0, max_order=0, record=None, error_test=0, integrator=0, step=0, "
     "rho_inf=1, adaptive=0, band=0, monitor=None, arrays=None, planar=0) -> dict of arrays and solver "
     "statistics; arrays(dict) is called once before the run with the output arrays it fills."},
    {NULL, NULL, 0, NULL}};
