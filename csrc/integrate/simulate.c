/* simulate.c -- phm_simulate: checks the options, sets up the DAE (csrc/dae/) and the
 * integrator's scratch, finds consistent initial values, emits the first output and hands the
 * run to the integrator of the table (integrators.c: ida.c, galpha.c). */
#define _POSIX_C_SOURCE 200809L
#include "integrate.h"

#include <math.h>
#include <string.h>
#include <time.h>

#include "phm_check.h"

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

phm_status phm_simulate(const phm_model *m, const double *poses0, const double *twists0,
                        const double *tout, int nout, const phm_sim_options *opt,
                        phm_sim_output *out, phm_error *err) {
  phm_error_clear(err);
  if (!m || !tout || !opt || !out) return PHM_FAIL(err, PHM_EINVAL, "phm_simulate: NULL argument");
  if (nout < 1) return PHM_FAIL(err, PHM_EINVAL, "need at least one output time");
  for (int i = 0; i < nout; i++) {
    if (!isfinite(tout[i])) return PHM_FAIL(err, PHM_EINVAL, "output time %d is not finite", i);
    if (i > 0 && !(tout[i] > tout[i - 1]))
      return PHM_FAIL(err, PHM_EINVAL, "output times must be strictly increasing (t[%d] = %g <= t[%d] = %g)", i, tout[i], i - 1, tout[i - 1]);
  }
  if (!(opt->rtol > 0) || !(opt->atol > 0) || !isfinite(opt->rtol) || !isfinite(opt->atol))
    return PHM_FAIL(err, PHM_EINVAL, "rtol and atol must be > 0 (got %g, %g)", opt->rtol, opt->atol);
  if (opt->linear_solver != 0 && opt->linear_solver != 1)
    return PHM_FAIL(err, PHM_EINVAL, "unknown linear solver %d (0 dense, 1 KLU)", opt->linear_solver);
  const phm_integrator *ig = phm_integrator_get(opt->integrator);
  if (!ig) return PHM_FAIL(err, PHM_EINVAL, "unknown integrator %d (0 IDA, 1 generalized-alpha, 2 tree)", opt->integrator);
  phm_status st = ig->check(opt, err);
  if (st) return st;
  double t_start = now();
  out->nout_done = 0;
  out->nsteps = out->nres = out->njac = out->nniters = out->netf = out->nncf = out->nfloor = out->nnoise = out->glob_state = out->nglob_stiff = 0;
  out->glob_err = out->t_glob_err = out->glob_err_abs = out->glob_scale = out->err_est = out->err_sum = out->err_sum_max = out->newton_rtol = out->max_mu = out->err_ratio = out->t_err_ratio = out->min_step = 0;
  /* set-up: the DAE's data and Jacobian pattern (every integrator and linear solver evaluates
   * the closed-form Jacobian on it; the dense LUs copy it into their matrix) and the
   * integrator's scratch; nothing of phmech's allocates after it */
  dae_t d;
  if ((st = opt->planar ? dae_planar_init(&d, m, opt->planar - 1, err) : dae_init(&d, m, err))) return st;
  void *work = NULL;
  SUNContext ctx = NULL;
  N_Vector yy = NULL, yp = NULL;
  int nc = m->nc;
  double *H = dae_full(&d)->data.ic.H, *tw = dae_full(&d)->data.ic.tw;
  if ((st = dae_jacobian_pattern(&d, err)) || (st = ig->setup(&d, opt, &work, err))) goto done;
  /* the constraint rows' regularization (csrc/dae/watch.c) */
  dae_regularization_scale(&d, opt->rtol, ig->per_step);
  for (int c = 0; c < nc; c++) {
    memcpy(H + 16 * c, poses0 ? poses0 + 16 * c : m->car[c].H0, 16 * sizeof(double));
    memcpy(tw + 6 * c, twists0 ? twists0 + 6 * c : m->car[c].t0, 6 * sizeof(double));
  }
  if (phm_sun_context_create(&ctx) != 0) {
    st = PHM_FAIL(err, PHM_ESOLVER, "SUNContext_Create failed");
    goto done;
  }
  yy = N_VNew_Serial(d.n, ctx);
  yp = N_VNew_Serial(d.n, ctx);
  if (!yy || !yp) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory (N_Vector)");
    goto done;
  }
  /* compiled vector operations (nvector_ops.c); the integrators' vectors are clones of yy */
  phm_nvector_ops(yy);
  phm_nvector_ops(yp);
  double *y = N_VGetArrayPointer(yy), *ypd = N_VGetArrayPointer(yp);
  double t = tout[0], nbp;
  d.tref = phm_model_tref(m, t, &nbp);
  memset(y, 0, sizeof(double) * (size_t)d.n);
  memset(ypd, 0, sizeof(double) * (size_t)d.n);
  if ((st = dae_consistent_ic(&d, t, H, tw, NULL, m->xref0, 1, y, ypd, err))) goto done;
  double E0 = 0;
  int stop;
  if ((st = dae_emit_output(&d, y, out, 0, &E0, t, opt, &stop, err)) || stop) goto done;
  if (nout == 1) goto done;
  st = ig->run(&d, opt, work, ctx, yy, yp, tout, nout, &E0, nbp, out, err);

done:
  if (yy) N_VDestroy(yy);
  if (yp) N_VDestroy(yp);
  if (ctx) SUNContext_Free(&ctx); /* before the scratch: SUNDIALS 7 keeps IDA's error sink on it */
  if (work) ig->release(work);
  dae_free(&d);
  out->wall_time = now() - t_start;
  return st;
}
