/* galpha.c -- the generalized-alpha integrator (the default), with step-size control from a
 * configuration error estimate, refined below the band's floor when it asks (phm_sim_options in
 * csrc/include/phmech_types.h; measurements in docs/integrators.md). */
#include "galpha_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"

/* the summed estimates below which Newton's tolerance is not tightened, and the steps the run
 * is on course to take above which it is not either (see newton_min) */
#define GALPHA_PACE_START 0.1
#define GALPHA_PACE_MAX_STEPS 3e5

/* ---------------------------------------------------------------- the integrator's row
 * (integrators.c): its options' checks, its scratch */
phm_status galpha_check(const phm_sim_options *opt, phm_error *err) {
  const phm_galpha_options *o = &opt->galpha;
  if (!(o->adaptive ? o->step >= 0 : o->step > 0) || !isfinite(o->step) ||
      !(o->rho_inf >= 0 && o->rho_inf <= 1) || !(o->band >= 0) || !isfinite(o->band))
    return PHM_FAIL(err, PHM_EINVAL, "generalized-alpha needs step > 0 (>= 0 when adaptive), "
                         "0 <= rho_inf <= 1 and a finite band >= 0 (got %g, %g, %g)",
                         o->step, o->rho_inf, o->band);
  return PHM_OK;
}

/* Its scratch, zeroed: nc x 33 doubles for the co-rotation (galpha_corot_init) and the ledger's
 * il - ie rates dP (of the full DAE when planar). */
phm_status galpha_setup(dae_t *d, const phm_sim_options *opt, void **work, phm_error *err) {
  (void)opt;
  const dae_t *f = dae_full(d);
  *work = calloc(33 * (size_t)f->m->nc + (size_t)(f->il - f->ie) + 1, sizeof(double));
  return *work ? PHM_OK : PHM_FAIL(err, PHM_ENOMEM, "out of memory");
}

void galpha_release(void *work) { free(work); }

/* g's vectors, for galpha_open and galpha_close. */
#define GALPHA_VECTORS(g)                                                                        \
  {&(g)->y0, &(g)->yp0, &(g)->Y, &(g)->Yp, &(g)->ya, &(g)->ypa, &(g)->Ra, &(g)->R, &(g)->dY,      \
   &(g)->w, &(g)->yq, &(g)->ypq, &(g)->yqq, &(g)->wa, &(g)->z1, &(g)->z2, &(g)->z2q, &(g)->z2qq,  \
   &(g)->z1n, &(g)->z2n, &(g)->fm, &(g)->le, &(g)->ge, &(g)->gep, &(g)->gy, &(g)->gya,         \
   &(g)->gypa, &(g)->gR, &(g)->gdy, &(g)->gRc, &(g)->gl, \
   &(g)->gyam, &(g)->gypam}

/* The run's step-size limits, first step and Newton's tolerance factor, from the options. */
static void galpha_limits(galpha_run *gr, const phm_sim_options *opt, const double *tout, int nout) {
  int adaptive = opt->galpha.adaptive;
  /* the band's floor: no step below it for accuracy's sake (Newton failures still halve) */
  double hfloor = adaptive && opt->galpha.band > 0 ? 1.0 / (PHM_BAND_STEPS * opt->galpha.band) : 0.0;
  /* and the refinement's limit: a step above the tolerance is redone shorter down to this, and
   * accepted there above it (counted in nfloor, and warned of by simulate) */
  double hlow = hfloor / PHM_REFINE_MAX;
  double hmax = opt->max_step > 0 ? opt->max_step : INFINITY;
  /* and no step above 1/(PHM_BAND_MAX_STEPS band): the band is resolved, whatever the estimate */
  if (adaptive && opt->galpha.band > 0) hmax = fmin(hmax, 1.0 / (PHM_BAND_MAX_STEPS * opt->galpha.band));
  /* proposed step: fixed, or the controller's (first: the given step, else the floor, else 1e-4
   * of the span) */
  /* (the first two steps have no estimate: at most 1e-3 of the span, from which the controller
   * grows the step 1.5x per step; a rigid pendulum run over 1 s with dt_out = 2 s took them at
   * the band's floor, 0.2 s, and ended 9e-3 rad off within its estimate) */
  double h0 = adaptive ? (opt->galpha.step > 0 ? opt->galpha.step : hfloor > 0 ? fmin(hfloor, 1e-3 * (tout[nout - 1] - tout[0]))
                                                                  : 1e-4 * (tout[nout - 1] - tout[0]))
                       : opt->galpha.step;
  /* ... and shorter with a tighter rtol: the first two steps' local error, O(h^3), is not
   * estimated, and the run's share of the tolerance per step is O(rtol h): at 1e-3 of the span
   * the compound pendulum at rtol 1e-6 (30 deg, 5 s) ended 3.3x rtol off, 288x at rtol 1e-8, all
   * of it from its first step; scaled by 10 sqrt(rtol) (0.1 at the default rtol 1e-4), 0.63x and
   * 0.75x, and the README's released cantilever 1.6x -> 0.66x rtol at Newton's tolerance 1e-9.
   * The steps grow 1.5x per step from there: 17 steps from 1e-3 to 1. */
  if (adaptive && opt->galpha.step <= 0) h0 *= fmin(1.0, 10.0 * sqrt(opt->rtol));
  if (adaptive) h0 = fmin(h0, hmax);
  /* Newton's tolerances (fixed step: rtol/atol are Newton's). Adaptive: never looser than
   * rtol 1e-7 (atol 1e-9 for the default atol 1e-6): a loose Newton test breaks the physics,
   * not only the accuracy, since strains are position errors over the element length (at
   * Newton rtol 1e-4 a 0.6 m double pendulum's tip ended 0.88 m from its pivot), and the
   * energy: Newton's residual error is biased (the iteration matrix is kept for many steps) and
   * adds up over the steps -- measured ledger residuals at Newton 1e-6 / 1e-7: free-flying beam
   * 1.4e-3 / 1.2e-5, double pendulum 1.7e-4 / 4.5e-6, flexible arm 6.2e-4 / 3.5e-5, at the same
   * number of iterations within 10 % (docs/integrators.md). Not tighter: at 1e-8 the
   * manipulator's first step fails (round-off of its 3e9 rad/s^2 start). Never tighter than
   * the error tolerance either. The multipliers keep their tolerances (dae_state_atol): their
   * corrections carry the round-off of G t / h. */
  double newton_tol = adaptive ? fmin(1.0, PHM_NEWTON_RTOL / opt->rtol) : 1.0;
  /* and tightened 10x, down to a relative PHM_NEWTON_RTOL_MIN, whenever a step accepted at the
   * level of Newton's noise (below) finds the run's summed estimates ahead of their share of
   * the tolerance, max(0.1, (t - t0) / span): the noise of a converged iterate is systematic
   * (the iteration matrix is kept for many steps) and adds up step after step. Measured on a
   * compound pendulum (30 deg, 5 s, rtol 1e-6): 47x rtol off at the fixed 1e-7, error_sum 17.3,
   * 10 524 of 11 857 steps noise-accepted; paced: 0.63x, error_sum 0.60. Where the sum keeps
   * its pace nothing changes (the rigid scenes of benchmarks/scenes.py); the flexible ones whose
   * sum ran ahead (cantilever + tip mass 1.15, flexible arm 1.02 over their short horizons) took
   * 1.2-1.4x the CPU and ended 0.40x and 0.28x rtol off instead of 0.56x and 0.36x.
   * Not in a run on course to take more than GALPHA_PACE_MAX_STEPS steps: there an error within
   * rtol over the whole span costs span^1.5 (a rod swinging for an hour, rtol 1e-4: 360 s took
   * 3.8e6 steps and 9.2 s instead of 1.0e6 and 0.94 s, and an hour would take ~300 s, its
   * per-unit-step estimates at round-off), and the summed estimates say so instead (the
   * AccuracyWarning of error_sum > 1: python/phmech/_run.py). */
  double newton_min = adaptive ? fmin(1.0, PHM_NEWTON_RTOL_MIN / opt->rtol) : 1.0;
  /* (a Newton failure with a fresh iteration matrix after a tightening loosens it 10x and makes
   * that the floor: at 1e-11 the flexible arm driven through a table of
   * tests/test_default_integrator.py failed Newton in 2047 of 38 414 steps; on any failure, a
   * stale matrix's too, examples/demo.py went back to 1e-7 and its summed estimates to 1.32) */
  const double newton_start = newton_tol;
  double span = tout[nout - 1] - tout[0];
  gr->adaptive = adaptive;
  gr->hfloor = hfloor;
  gr->hlow = hlow;
  gr->hmax = hmax;
  gr->h0 = h0;
  gr->newton_tol = newton_tol;
  gr->newton_min = newton_min;
  gr->newton_start = newton_start;
  gr->span = span;
}

/* The run's scheme, vectors, matrices, solver and step-size limits, from the consistent state
 * yy, yp at tout[0]; work: galpha_setup's. */
static phm_status galpha_open(galpha_run *gr, dae_t *d, const phm_sim_options *opt, void *work,
                              SUNContext ctx, N_Vector yy, N_Vector yp, const double *tout,
                              int nout, phm_error *err) {
  int n = gr->n = d->n;
  gr->nout = nout;
  gr->d = d;
  gr->opt = opt;
  phm_status st = PHM_OK;
  double rho = opt->galpha.rho_inf;
  galpha_limits(gr, opt, tout, nout);
  int adaptive = gr->adaptive;
  galpha_t *g = &gr->g;
  memset(g, 0, sizeof *g);
  g->af = 1.0 / (1.0 + rho);
  g->am = 0.5 * (3.0 - rho) / (1.0 + rho);
  g->gam = 0.5 + g->am - g->af;
  double *gwork = work, *dP = gwork + 33 * (size_t)d->m->nc; /* ledger rates (galpha_setup) */
  galpha_corot_init(d, &gr->cr, gwork);
  N_Vector *vs[] = GALPHA_VECTORS(g);
  int nv = (int)(sizeof vs / sizeof vs[0]);
  for (int k = 0; k < nv; k++) {
    if (!(*vs[k] = N_VClone(yy))) { /* yy's compiled operations (simulate.c) with it */
      st = PHM_FAIL(err, PHM_ENOMEM, "out of memory (N_Vector)");
      goto done;
    }
    N_VConst(0.0, *vs[k]); /* a clone's data is uninitialized */
  }
  SUNMatrix Js = gr->Js = SUNSparseMatrix(n, n, d->nnz, CSC_MAT, ctx); /* never zeroed: no phm_sparse_matrix_ops */
  SUNMatrix A = gr->A = opt->linear_solver == 1 ? Js : SUNDenseMatrix(n, n, ctx);
  if (!Js || !A) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory (matrix)");
    goto done;
  }
  SUNLinearSolver LS = gr->LS = opt->linear_solver == 1 ? SUNLinSol_KLU(yy, A, ctx) : SUNLinSol_Dense(yy, A, ctx);
  if (!LS || SUNLinSolInitialize(LS) != PHM_SUN_SUCCESS) {
    st = PHM_FAIL(err, PHM_ESOLVER, "could not create the linear solver");
    goto done;
  }
  double *y0 = N_VGetArrayPointer(g->y0), *yp0 = N_VGetArrayPointer(g->yp0);
  double *y = N_VGetArrayPointer(yy), *ypd = N_VGetArrayPointer(yp);
  double *wa = N_VGetArrayPointer(g->wa); /* per state, once: two calls per state per step were 2 % of a small scene's run */
  for (int i = 0; i < n; i++) wa[i] = dae_is_twist(d, i) ? -1.0 : dae_state_atol(d, i, opt->atol);
  memcpy(y0, y, sizeof(double) * (size_t)n);
  memcpy(yp0, ypd, sizeof(double) * (size_t)n);
  /* the estimate's filter (galpha_error) starts in the steady state of the motion's initial
   * rate: a ramp y0 + y0' t comes out delayed by 1/wc per stage */
  g->wc = adaptive && opt->galpha.band > 0 ? 6.283185307179586 * PHM_FILTER_BAND * opt->galpha.band : 0.0;
  int filtered = adaptive && g->wc > 0 && d->m->ne > 0;
  if (adaptive) {
    double *z1 = N_VGetArrayPointer(g->z1), *z2 = N_VGetArrayPointer(g->z2);
    double iw = g->wc > 0 ? 1.0 / g->wc : 0.0, *fm = N_VGetArrayPointer(g->fm);
    /* a mechanism with flexible links: every configuration state (the mesh's vibrations reach
     * the joints and the bodies they carry: filtering the nodes' states alone left the arm +
     * strip's elbow angle above the tolerance at steps of 3e-8 s); a rigid one: none, every
     * motion there is the mechanism's own (a chain of 100 rigid links whips its tail far above
     * a band of 10 Hz) */
    if (d->m->ne > 0) N_VConst(1.0, g->fm);
    for (int i = 0; i < n; i++) {
      z1[i] = y[i] - fm[i] * ypd[i] * iw;
      z2[i] = y[i] - 2.0 * fm[i] * ypd[i] * iw;
    }
  }
  gr->y0 = y0;
  gr->yp0 = yp0;
  gr->Y = N_VGetArrayPointer(g->Y);
  gr->Yp = N_VGetArrayPointer(g->Yp);
  gr->dY = N_VGetArrayPointer(g->dY);
  gr->w = N_VGetArrayPointer(g->w);
  gr->yq = N_VGetArrayPointer(g->yq);
  gr->ypq = N_VGetArrayPointer(g->ypq);
  gr->yqq = N_VGetArrayPointer(g->yqq);
  gr->wa = wa;
  gr->dP = dP;
  gr->filtered = filtered;
  gr->rigid = adaptive && d->m->ne == 0;
  gr->t = tout[0];
  gr->hjac = gr->hq = gr->hqq = 0; /* hq = 0: no history */
  gr->fresh = 0;
  /* restart: the first step, and the first after each breakpoint. If it fails, it is redone as
   * backward Euler, which does not use y0': dae_consistent_ic computes y0' exactly, but it can be
   * huge (a joint torque on a light node of the manipulator: 3e9 rad/s^2); carried into the step
   * it drives the unresolved fast modes and the stage powers to 1e14 W, and the finite-difference
   * Jacobian loses every digit. One first-order step adds an O(h^2) error once, so the global
   * error stays second order (with twice the error constant on a pendulum: why it is a fallback
   * and not the rule). */
  gr->restart = 1;
  /* the iteration matrix's extra iterations (beyond two per step, on a matrix not computed in
   * that step) since it was computed, and whether the next step attempt refreshes it (see
   * GALPHA_EXTRA_BUDGET) */
  gr->extra = gr->refresh = 0;
  galpha_global_open(gr);
done:
  return st;
}

static void galpha_close(galpha_run *gr) {
  if (gr->LS) SUNLinSolFree(gr->LS);
  if (gr->A && gr->A != gr->Js) SUNMatDestroy(gr->A);
  if (gr->Js) SUNMatDestroy(gr->Js);
  N_Vector *vs[] = GALPHA_VECTORS(&gr->g);
  for (int k = 0; k < (int)(sizeof vs / sizeof vs[0]); k++)
    if (*vs[k]) N_VDestroy(*vs[k]);
}

/* After the step h from gr->t to target (or t + h): the step's bookkeeping, the controller's
 * next proposal, the monitor, output *iout when reached, and the history moved on. */
static phm_status galpha_accept(galpha_run *gr, double h, double target, const double *tout,
                                int *iout, long *steps_out, double E0[1], int *stop,
                                phm_error *err) {
  dae_t *d = gr->d;
  const phm_sim_options *opt = gr->opt;
  phm_sim_output *out = gr->out;
  galpha_t *g = &gr->g;
  int n = gr->n, adaptive = gr->adaptive;
  double t = gr->t, errn = gr->errn, emax = gr->emax, ewmax = gr->ewmax, elocal = gr->elocal;
  double hmax = gr->hmax, hlow = gr->hlow, h0 = gr->h0, span = gr->span;
  double *Y = gr->Y, *Yp = gr->Yp, *y0 = gr->y0, *yp0 = gr->yp0;
  double *yq = gr->yq, *ypq = gr->ypq, *yqq = gr->yqq;
  phm_status st = PHM_OK;
  galpha_stage(d, g, h); /* y1' of the converged y1 */
  double t1 = fabs(target - (t + h)) < 1e-9 * h ? target : t + h;
  out->nsteps++;
  out->last_step = h;
  if ((st = dae_step_accepted(d, t1, Y, DAE_CONSTRAINT_TOL, opt->atol, t1 == tout[*iout], err))) goto done; /* watch.c */
  if (adaptive) {
    /* next proposal, with a dead band against chattering (every change of h costs Newton
     * iterations with the iteration matrix of another h, and measured on the double pendulum
     * a controller that also shrank h after accepted steps made 4x more convergence failures
     * and a larger error): an accepted step keeps h unless the estimate allows >= 1.25x (then
     * at most 1.5x); a rejected step (above) has already shortened it. A step shortened to
     * land on an output neither shrinks the proposal nor blocks its growth (its estimate is
     * scaled to the proposal by (h0/h)^2). */
    if (errn > 1.0) out->nfloor++;
    if (errn > out->err_ratio) {
      out->err_ratio = errn;
      out->t_err_ratio = t1;
    }
    if (h < out->min_step || out->min_step == 0) out->min_step = h;
    out->err_est += emax;
    out->err_sum += elocal;
    out->err_sum_max += ewmax;
    if (gr->noise && gr->newton_tol > gr->newton_min &&
        out->err_sum > fmax(GALPHA_PACE_START, (t1 - tout[0]) / span) && /* see newton_min */
        span <= GALPHA_PACE_MAX_STEPS * h)
      gr->newton_tol = fmax(gr->newton_min, 0.1 * gr->newton_tol);
    out->newton_rtol = gr->newton_tol * opt->rtol;
    double base = fmax(h, h0), eb = errn * pow(base / h, 2.0); /* the estimate scaled to h0 */
    /* The step grows only if the last three estimates all allow it: one step's estimate
     * scatters ~10x from step to step (the filtered mesh's content, Newton's noise), and a
     * controller that grew on the lowest one had the next step rejected, and then a fresh
     * iteration matrix for each of the two changes of h. Measured (benchmarks/scenes.py,
     * default rtol): the slider-crank rejected 3199 of 17 729 steps and made 9928 matrices,
     * and the arm + strip 8917 of 60 067 with 26 678 matrices, its estimates summed running
     * ahead so that Newton's tolerance was tightened to 1e-11 (newton_min); with the three:
     * 2 and 517 matrices (0.64 -> 0.29 s of CPU), 16 and 1521 matrices (1.55 -> 0.35 s),
     * both within rtol of their references (docs/integrators.md, "What it does"). */
    if (errn >= 0) {
      double b2 = base * base;
      eb = fmax(eb, fmax(gr->grow_q, gr->grow_qq) * b2);
      gr->grow_qq = gr->grow_q;
      gr->grow_q = errn / (h * h);
    } else {
      gr->grow_q = gr->grow_qq = 0;
    }
    double fac = errn < 0 ? 1.0 : eb > 0 ? 0.8 * pow(eb, -0.5) : 1.5;
    double hn = fac >= 1.25 ? base * fmin(1.5, fac) : base;
    h0 = fmin(hmax, fmax(hlow, hn));
  }
  if (opt->monitor && out->nsteps % PHM_MONITOR_STEPS == 0 && opt->monitor(opt->ctx, t1, out->nsteps, h)) {
    st = PHM_FAIL(err, PHM_EINTERRUPT, "interrupted at t = %g s", t1);
    goto done;
  }
  if (t1 == tout[*iout]) {
    if ((st = dae_emit_output(d, Y, out, *iout, E0, t1, opt, stop, err)) || *stop) goto done;
    (*iout)++;
    *steps_out = 0;
  }
  if (gr->global && (st = galpha_global_step(gr, h, t1 == tout[gr->nout - 1], err))) goto done; /* galpha_global.c */
  gr->t = t1;
  gr->hqq = gr->hq;
  gr->hq = g->euler ? 0 : h; /* no history across the Euler step (its y0' is not this scheme's) */
  memcpy(yqq, yq, sizeof(double) * (size_t)n);
  if (g->euler) gr->hjac = 0; /* other coefficients from here on */
  /* adaptive: the two steps after a restart have no error estimate yet and start from the
   * restart's rates; a failing one is redone as backward Euler too */
  if (g->euler) gr->hjac = 0;
  gr->restart = adaptive && gr->restart > 0 && gr->restart < 3 ? gr->restart + 1 : 0;
  g->euler = 0;
  memcpy(yq, y0, sizeof(double) * (size_t)n);
  memcpy(ypq, yp0, sizeof(double) * (size_t)n);
  if (adaptive) { /* the filter moves to t1 (galpha_error filled z1n, z2n) */
    N_Vector tmp = g->z2qq;
    g->z2qq = g->z2q;
    g->z2q = g->z2;
    g->z2 = g->z2n;
    g->z2n = tmp;
    tmp = g->z1;
    g->z1 = g->z1n;
    g->z1n = tmp;
  }
  memcpy(y0, Y, sizeof(double) * (size_t)n);
  memcpy(yp0, Yp, sizeof(double) * (size_t)n);
done:
  gr->h0 = h0;
  return st;
}

phm_status run_galpha(dae_t *d, const phm_sim_options *opt, void *work, SUNContext ctx,
                      N_Vector yy, N_Vector yp, const double *tout, int nout, double E0[1],
                      double nbp, phm_sim_output *out, phm_error *err) {
  galpha_run run, *gr = &run;
  memset(gr, 0, sizeof *gr);
  gr->out = out;
  phm_status st = galpha_open(gr, d, opt, work, ctx, yy, yp, tout, nout, err);
  int iout = 1, stop = 0;
  long max_steps = opt->max_steps > 0 ? opt->max_steps : 1000000L, steps_out = 0;
  while (!st && !stop && iout < nout) {
    double t = gr->t, h0 = gr->h0;
    /* A breakpoint within bptol (1e-9 of a step) of t counts as reached: restart on its new
     * piece. Landing on it exactly would take a step of round-off size: a Step law at
     * 1e-3 + 1e-13 s with outputs every 1e-3 s gave a step of 1e-13 s (h = -inf from ceil(-0)
     * before this rule), and the first step after it fails. */
    double bptol = 1e-9 * h0;
    if (isfinite(nbp) && t >= nbp - bptol) {
      if ((st = dae_restart_at_breakpoint(d, t, fmax(t, nbp), &nbp, gr->y0, gr->yp0, err))) goto done;
      gr->hjac = gr->hq = gr->hqq = 0;
      gr->restart = 1;
    }
    /* steps land on the output times and the breakpoints of the laws: the largest step <= h0
     * that divides what is left of the interval evenly (outputs need no interpolation, and the
     * constraints hold at every output); a breakpoint within bptol before an output is left to
     * the restart above, at the output. So a fixed step longer than the outputs' spacing is
     * shortened to it (a step of 10 ms with outputs every 5 ms takes 5 ms steps). Interpolating
     * outputs inside longer steps was tried (2026-11-27) and dropped: a cubic Hermite in
     * (y0, y0', Y, Y') carried the rates of what the step does not resolve into the outputs
     * (examples/manipulator.py, fixed steps of 1 ms, outputs every 0.1 ms: twist errors up to
     * 2.7 between steps against 0.2-0.5 on them, on twists of at most 7.5; 5.8e4 inside a
     * backward-Euler restart step, whose y0' is the huge consistent initial acceleration), and a
     * linear one, robust, doubled the constraint residuals' order (a four-bar at 1 ms: 7.9e-6
     * against 1e-10 on the steps) and tripled the pendulum's energy error between steps (1.8e-3
     * against 6e-4 of m g d), which the energy ledger would then report as the scheme's. The
     * adaptive steps landed on outputs for the same reason (the modal leaf spring of
     * tests/test_modal_link.py with interpolated outputs: ledger 1.2e-3 instead of 3.3e-5). */
    double target = tout[iout];
    if (isfinite(nbp) && nbp > t && nbp < target - bptol) target = nbp;
    double h = (target - t) / fmax(1.0, ceil((target - t) / h0 - 1e-9));
    if (!(t + h > t)) {
      st = PHM_FAIL(err, PHM_ESOLVER, "generalized-alpha: step %.3g s too small to advance "
                         "t = %.9g s in double precision", h, t);
      goto done;
    }
    if (++steps_out > max_steps) {
      st = PHM_FAIL(err, PHM_ESOLVER, "generalized-alpha: more than %ld steps between two "
                         "output times (t = %.9g s, step %.3g s)", max_steps, t, h);
      goto done;
    }
    if ((st = galpha_attempt(gr, &h, err))) goto done;
    st = galpha_accept(gr, h, target, tout, &iout, &steps_out, E0, &stop, err);
  }
done:
  out->last_order = 2;
  galpha_close(gr);
  return st;
}
