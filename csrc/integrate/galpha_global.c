/* galpha_global.c -- the adaptive generalized-alpha's global error estimate
 * (csrc/integrate/galpha_internal.h): each accepted step's local error estimates (galpha_error)
 * carried along the motion by the linearized step, so that errors the motion amplifies are seen.
 *
 * The step controller keeps the local estimates summed over the run within the tolerance
 * (stats["error_sum"] <= 1), which bounds the error at the outputs only as long as errors do not
 * grow along the motion. They do where the motion is sensitive to its state: a pendulum released
 * at 170 deg, whose period depends steeply on its energy, ended 9.7-11.6x rtol off after 5 s at
 * rtol 1e-4 with its estimates summed below 1 (tests/accuracy/test_integrator_contract.py).
 *
 * The propagation: the error e of the states (and e' of their rates, the scheme's second state)
 * is a perturbation of the step's start (y0 + e, y0' + e'); the step from there is one Newton
 * iteration, on the step's own factorized iteration matrix, from the predictor
 * Y + e + h e' (its stage at ya + e + alpha_f h e', ya' + e'; its multipliers at Y's plus their
 * previous e): dY = -A^-1 R(perturbed), e1 = e + h e' + dY, e1' = e' + dY / (gamma h)
 * (backward Euler: dY / h). The residual is the full one at the perturbed stage, minus the
 * converged step's, which is 0 to Newton's tolerance: so e also takes in the Newton error each
 * step leaves (the systematic noise stats["error_sum"] counts). The predictor is the tangent's
 * own extrapolation, so the correction is O(h^2) of e and the iteration matrix's age (a step
 * 20 % away from the one it was made for) spoils only that. The step's local estimates (the
 * configuration's, h^3 y'''/12) are then added to e. One residual, one set of constraint rows
 * and one solve per accepted step.
 *
 * The figure: the largest over the configuration states the local estimate sees (i < ie,
 * without the filtered twists) of |e_i| / (rtol max|y_i| + atol_i), max|y_i| over the run so
 * far (an oscillating coordinate's tolerance is that of its amplitude, not of its value as it
 * crosses zero), atol_i the local estimate's; the largest over the run is
 * stats["global_error_estimate"] (python/phmech/_run.py warns above 1). */
#include "galpha_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"

/* The estimate starts at 0 with every state's scale |y(t0)|. Rigid mechanisms only (see the
 * header). */
void galpha_global_open(galpha_run *gr) {
  galpha_t *g = &gr->g;
  gr->global = gr->rigid && !getenv("PHM_NO_GLOBAL"); /* TEMP measurement */
  if (!gr->global) {
    if (gr->adaptive) { /* not estimated */
      gr->out->glob_err = -1.0;
      gr->out->glob_state = -1;
    }
    return;
  }
  N_VConst(0.0, g->ge);
  N_VConst(0.0, g->gep);
  N_VConst(0.0, g->le);
  N_VAbs(g->y0, g->gy);
}

/* After the step h from gr->t was accepted (g's y0, y0': its start; Y, Y', ya, ya': its end and
 * stage, converged; the iteration matrix factorized in gr->LS): e and e' moved to its end, the
 * step's local estimates added, the figure updated in gr->out. */
phm_status galpha_global_step(galpha_run *gr, double h, phm_error *err) {
  dae_t *d = gr->d;
  galpha_t *g = &gr->g;
  phm_sim_output *out = gr->out;
  const phm_sim_options *opt = gr->opt;
  int n = gr->n, ie = d->ie, il = d->il;
  double *e = N_VGetArrayPointer(g->ge), *ep = N_VGetArrayPointer(g->gep);
  double *ya2 = N_VGetArrayPointer(g->gya), *ypa2 = N_VGetArrayPointer(g->gypa);
  double *R = N_VGetArrayPointer(g->gR), *ymax = N_VGetArrayPointer(g->gy);
  double *dy = N_VGetArrayPointer(g->gdy);
  const double *ya = N_VGetArrayPointer(g->ya), *ypa = N_VGetArrayPointer(g->ypa);
  const double *Y = gr->Y, *le = N_VGetArrayPointer(g->le), *wa = gr->wa;
  double af = g->euler ? 1.0 : g->af, t = gr->t, worst = 0.0;
  int iw = 0;
  double atol_twist = g->wc > 0 ? GALPHA_TWIST_ATOL * g->wc * opt->atol : opt->atol;
  /* the predictor dy = e + h e' (the multipliers': their last e), its stage (the scheme's rates
   * at the predictor are y0' + e': the stage's too) and end */
  for (int i = 0; i < il; i++) {
    dy[i] = i < ie ? e[i] + h * ep[i] : 0.0;
    ya2[i] = ya[i] + e[i] + af * h * ep[i];
    ypa2[i] = ypa[i] + ep[i];
  }
  for (int i = il; i < n; i++) {
    dy[i] = e[i];
    ya2[i] = Y[i] + e[i];
    ypa2[i] = 0.0;
  }
  if (dae_residual_rows(d, t + af * h, ya2, ypa2, R, 0))
    return PHM_FAIL(err, PHM_ESOLVER, "generalized-alpha: the global error estimate's residual "
                                      "failed at t = %.9g s", t);
  for (int i = 0; i < il; i++) ya2[i] = Y[i] + dy[i];
  dae_constraint_rows(d, t + h, ya2, R);
  for (int i = ie; i < il; i++) R[i] = 0.0; /* the ledger's integrals: no error carried */
  N_VScale(-1.0, g->gR, g->gR);
  if (SUNLinSolSolve(gr->LS, gr->A, g->gR, g->gR, 0.0) != PHM_SUN_SUCCESS)
    return PHM_FAIL(err, PHM_ESOLVER, "generalized-alpha: the global error estimate's solve "
                                      "failed at t = %.9g s", t);
  /* the matrix was made for the step hjac (within 20 % of h): on the rows where cj = alpha_m /
   * (alpha_f gamma h) dominates (every state's, at a rigid mechanism's steps) its correction is
   * hjac / h times this step's (unscaled, the compound pendulum's estimate at 2 deg, rtol 1e-4,
   * read 1.68e246 with e' carried by the scheme, below) */
  double sc = gr->hjac > 0 ? h / gr->hjac : 1.0;
  for (int i = 0; i < il; i++) {
    if (i >= ie) { /* the ledger's integrals */
      e[i] = ep[i] = 0.0;
      continue;
    }
    dy[i] += sc * R[i];
    /* the rate error: the backward difference, not the scheme's e' + dY / (gamma h), whose
     * parasitic root (1 - 1/gamma = -0.9 at rho_inf 0.9) the one iteration's error on an aged
     * matrix pushed beyond -1: the four-bar of benchmarks/scenes.py grew 1.25x per step from
     * t = 0.21 s (converged, three iterations: 0.045 tolerances, as this gives) */
    ep[i] = (dy[i] - e[i]) / h;
    e[i] = dy[i] + le[i];
    ymax[i] = fmax(ymax[i], fabs(Y[i]));
    double r = fabs(e[i]) / (opt->rtol * ymax[i] + (wa[i] < 0 ? atol_twist : opt->atol));
    if (r > worst) {
      worst = r;
      iw = i;
    }
  }
  for (int i = il; i < n; i++) e[i] = dy[i] + R[i];
  if (worst > out->glob_err) {
    out->glob_err = worst;
    out->t_glob_err = t + h;
    out->glob_state = iw;
  }
  return PHM_OK;
}
