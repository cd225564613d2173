/* py_run.c -- a run's callbacks across the binding (simulate, statics): pending signals
 * (Ctrl-C, SIGTERM), the per-output progress callable and the between-outputs monitor, each
 * called with the GIL (the core runs without it); an exception a callable raises is kept in the
 * phm_py_run record and re-raised after the run. */
#include "py_model.h"

/* With the GIL held: a pending signal (Ctrl-C, or SIGTERM when Python handles it) marks the run
 * interrupted; non-zero: stop. */
static int signal_pending(phm_py_run *c) {
  if (PyErr_CheckSignals() == 0) return 0;
  PyErr_Clear();
  c->interrupted = 1;
  return 1;
}

/* With the GIL held: the result r of a user callable; an exception is kept for re-raising after
 * the run. Non-zero: stop (the callable raised or returned something true). */
static int callable_says_stop(phm_py_run *c, PyObject *r) {
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
int phm_py_monitor_cb(void *vctx, double t, long nsteps, double h) {
  phm_py_run *c = (phm_py_run *)vctx;
  PyGILState_STATE g = PyGILState_Ensure();
  int stop = signal_pending(c);
  if (!stop && c->mon) stop = callable_says_stop(c, PyObject_CallFunction(c->mon, "dld", t, nsteps, h));
  PyGILState_Release(g);
  return stop;
}

/* At each output (dae_emit_output): pending signals (interrupt: non-zero), then, with the GIL
 * still held, the progress callable, whose answer phm_py_progress_cb returns right after -- one GIL
 * round trip per output, not two, and its arguments by vectorcall, not a format string (a
 * small scene's outputs cost 3 % of its run in these two). */
int phm_py_interrupt_cb(void *vctx, double t, int iout) {
  phm_py_run *c = (phm_py_run *)vctx;
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

int phm_py_progress_cb(void *vctx, double t, int iout) {
  (void)t;
  (void)iout;
  return ((phm_py_run *)vctx)->cb_stop;
}
