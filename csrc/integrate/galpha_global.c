/* galpha_global.c -- the adaptive generalized-alpha's global error estimate
 * (csrc/integrate/galpha_internal.h; docs/integrators.md, "The global error estimate"): the
 * accepted steps' local error estimates (galpha_error) carried along the motion by the
 * linearized steps, so that errors the motion amplifies are seen. Rigid mechanisms only.
 *
 * The step controller keeps the local estimates summed over the run within the tolerance
 * (stats["error_sum"] <= 1), which bounds the error at the outputs only as long as errors do not
 * grow along the motion. They do where the motion is sensitive to its state: a compound
 * pendulum released at 170 deg, whose period depends steeply on its energy, ended 7.8x rtol amp
 * off after 5 s at rtol 1e-4 with its estimates summed to 0.63, silently
 * (tests/accuracy/test_integrator_contract.py).
 *
 * The propagation, per block of GALPHA_GLOBAL_EVERY accepted steps (H long): the error e of the
 * states, with its rate e', is a perturbation of the block's start, and the block is one
 * Newton iteration of the perturbed motion on the last step's factorized iteration matrix, from
 * the predictor e + H e': the residual's differential rows at the stage of the block's step
 * nearest alpha_f of it (ya + e + alpha_f H e', ya' + e'; the multipliers at theirs plus their
 * last e), its constraint rows at the block's end (Y + e + H e'). That stage's own residual is
 * 0 to Newton's tolerance, so e also takes in the Newton error the steps leave. Then e1 = the
 * predictor + the correction, e1' = (e1 - e) / H, and the block's local estimates (summed) are
 * added. One residual, one set of constraint rows and two solves per block; each step adds its
 * local estimates to the block's and keeps the stage of the block's middle. A stiff block
 * (GALPHA_GLOBAL_STIFF: a force element that damps within it) is carried unchanged instead,
 * and the steps after it propagated one by one.
 *
 * The figure: the largest over the states the local estimate sees (i < ie) of
 * |e_i| / (rtol max|y_i| + atol_i), max|y_i| over the run so far (an oscillating coordinate is
 * held to its amplitude, not to its value crossing zero), atol_i the local estimate's; the
 * largest over the run is stats["global_error_estimate"] (python/phmech/_run.py warns above 1),
 * its state stats["global_error_state"].
 *
 * Not with flexible links: there the mesh's modes above the band made the one-iteration
 * propagation unstable on six of benchmarks/scenes.py's seven scenes (to 1e112 .. 1e285), and
 * it cost 35-47 % of their CPU per step. */
#include "galpha_internal.h"

#include <math.h>
#include <string.h>

#include "phm_check.h"

/* the steps of a block, propagated as one. Measured on the compound pendulum (5 s; estimate,
 * truth over rtol amp + atol): step by step 13.4 (170 deg, rtol 1e-4), 1.08 (2 deg, 1e-6), 0.96
 * (2 deg, 1e-4), truth 7.8, 1.11, 0.86; blocks of 4: 13.2, 1.09, 0.97; of 8: 24.6, 1.09, 0.98;
 * of 16: 28-250 at 170 deg and 1.00 at 2 deg (rtol 1e-4: a false alarm). CPU on rigid runs
 * (medians of 5, back to back): step by step +10 % (four-bar of benchmarks/scenes.py) to +62 %
 * (the chain of 100 links of tests/accuracy/, one Newton iteration per step); blocks of 8:
 * +5..14 % */
#define GALPHA_GLOBAL_EVERY 8
/* A block is stiff when its correction (the differential rows', sc R below) exceeds this share
 * of the error it moves (|e| + |H e'|, weighed as the figure weighs them): the matrix, made for
 * the step hjac, then does not stand for the block's (see sc), and its one iteration
 * over-corrects what damps fast (the predictor's e + H e' grows where the motion damps within
 * H). Repeated over the blocks it diverged: a block on a spring with regularized Coulomb
 * friction (its slope Fc / v_reg = 1e3 N s/m at rest: 500 1/s on 2 kg) read 30 (rtol 1e-4) and
 * 2849 (1e-6) for a true 0.11x and 0.08x, 3.8e5 with v_reg 1e-5 in blocks of 4; a stiff PD
 * (kp 1e6, kd 2e3 on 2 kg) 5.9 for 0.00x. Step by step (H = h, the matrix's own step but for
 * its age) they read 0.11, 0.12 and 0.02, and with the stiff blocks so detected 0.10, 0.12 and
 * 0.03. Measured per block: those runs' corrections 1 to 87 times that error in 250-1060
 * blocks; the non-stiff runs' (benchmarks/scenes.py's four-bar, the chain of 100 links of
 * tests/accuracy/, the UR5 swing of examples/urdf_robot.py, PD and effort-driven blocks) at
 * most 0.43, in one or two blocks, and under 0.1 in the rest: their figures are unchanged. */
#define GALPHA_GLOBAL_STIFF 0.5
/* the steps propagated one by one after a stiff block, before blocks are tried again: one by
 * one costs a residual and two solves per step (see GALPHA_GLOBAL_EVERY), and stiffness comes
 * and goes (friction sticks and slips; the IFToMM A02 four-bar's 14 stiff blocks in 10 s are
 * its singular positions: 0.50 s of CPU against 0.48, where step by step throughout took 0.61) */
#define GALPHA_GLOBAL_STEPWISE 64

/* The estimate starts at 0 with every state's scale |y(t0)|. Rigid mechanisms only (see the
 * header). */
void galpha_global_open(galpha_run *gr) {
  galpha_t *g = &gr->g;
  gr->global = gr->rigid;
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
  N_VConst(0.0, g->gl);
  gr->gH = 0;
  gr->gcount = 0;
  gr->gstep = 0;
}

/* Whether the block's correction sc R (R: the differential rows' solution, sc = H / hjac) is
 * stiff: its norm over the error it moves, |e| + |H e'|, above GALPHA_GLOBAL_STIFF, each state
 * weighed by its tolerance as in the figure (rtol max|y| + atol). */
static int galpha_global_stiff(const galpha_run *gr, double H, double sc, const double *e,
                               const double *ep, const double *R, const double *ymax,
                               double atol_twist) {
  const phm_sim_options *opt = gr->opt;
  const double *Y = gr->Y, *wa = gr->wa;
  double corr = 0, moved = 0;
  for (int i = 0; i < gr->d->ie; i++) {
    double w = 1.0 / (opt->rtol * fmax(ymax[i], fabs(Y[i])) + (wa[i] < 0 ? atol_twist : opt->atol));
    double c = sc * R[i] * w, m = (fabs(e[i]) + fabs(H * ep[i])) * w;
    corr += c * c;
    moved += m * m;
  }
  return moved > 0 && corr > GALPHA_GLOBAL_STIFF * GALPHA_GLOBAL_STIFF * moved;
}

/* After the step h from gr->t was accepted (g's Y, ya, ya': its end and stage, converged; the
 * iteration matrix factorized in gr->LS): its local estimates added to the block's, and at the
 * block's end (GALPHA_GLOBAL_EVERY steps, or `last`: the run's last step) e and e' moved over the
 * block, its local estimates added, the figure updated in gr->out. */
phm_status galpha_global_step(galpha_run *gr, double h, int last, phm_error *err) {
  dae_t *d = gr->d;
  galpha_t *g = &gr->g;
  phm_sim_output *out = gr->out;
  const phm_sim_options *opt = gr->opt;
  int n = gr->n, ie = d->ie, il = d->il;
  double *e = N_VGetArrayPointer(g->ge), *ep = N_VGetArrayPointer(g->gep);
  double *ya2 = N_VGetArrayPointer(g->gya), *ypa2 = N_VGetArrayPointer(g->gypa);
  double *R = N_VGetArrayPointer(g->gR), *ymax = N_VGetArrayPointer(g->gy);
  double *dy = N_VGetArrayPointer(g->gdy), *L = N_VGetArrayPointer(g->gl);
  double *Rc = N_VGetArrayPointer(g->gRc);
  const double *ya = N_VGetArrayPointer(g->ya), *ypa = N_VGetArrayPointer(g->ypa);
  const double *Y = gr->Y, *le = N_VGetArrayPointer(g->le), *wa = gr->wa;
  double *yam = N_VGetArrayPointer(g->gyam), *ypam = N_VGetArrayPointer(g->gypam);
  for (int i = 0; i < ie; i++) L[i] += le[i];
  /* the block's stage: that of its last step whose stage is within alpha_f of the block it
   * is expected to be, GALPHA_GLOBAL_EVERY steps of this one's */
  const int every = gr->gstep > 0 ? 1 : GALPHA_GLOBAL_EVERY;
  double ts = gr->t + (g->euler ? 1.0 : g->af) * h;
  if (gr->gcount == 0) {
    gr->gta = gr->t;
    gr->gHx = every * h;
  }
  if (gr->gcount == 0 || ts <= gr->gta + g->af * gr->gHx) {
    memcpy(yam, ya, sizeof(double) * (size_t)n);
    memcpy(ypam, ypa, sizeof(double) * (size_t)n);
    gr->gtm = ts;
    gr->ghm = h;
  }
  gr->gH += h;
  if (++gr->gcount < every && !last) return PHM_OK;
  double H = gr->gH, af = g->euler ? 1.0 : g->af, worst = 0.0;
  int iw = 0;
  gr->gH = 0;
  gr->gcount = 0;
  double atol_twist = galpha_twist_atol(g, opt->atol);
  /* the predictor dy = e + H e' (the multipliers': their last e), its stage (the tangent's rates
   * at the predictor are e': the stage's too) at the block's stage, and its end at the block's */
  for (int i = 0; i < il; i++) {
    dy[i] = i < ie ? e[i] + H * ep[i] : 0.0;
    ya2[i] = yam[i] + e[i] + af * H * ep[i];
    ypa2[i] = ypam[i] + ep[i];
  }
  for (int i = il; i < n; i++) {
    dy[i] = e[i];
    ya2[i] = yam[i] + e[i];
    ypa2[i] = 0.0;
  }
  dae_full(d)->stage_h = gr->ghm; /* the stage's own step (residual.c, workless_at_stage) */
  if (dae_residual_rows(d, gr->gtm, ya2, ypa2, R, 0))
    return PHM_FAIL(err, PHM_ESOLVER, "generalized-alpha: the global error estimate's residual "
                                      "failed at t = %.9g s", gr->t);
  for (int i = 0; i < il; i++) ya2[i] = Y[i] + dy[i];
  dae_constraint_rows(d, gr->t + h, ya2, R);
  /* the constraint rows apart (Rc), the differential ones in R (the ledger's integrals: no
   * error carried) */
  for (int i = 0; i < il; i++) Rc[i] = 0.0;
  for (int i = il; i < n; i++) {
    Rc[i] = -R[i];
    R[i] = 0.0;
  }
  for (int i = 0; i < il; i++) R[i] = i < ie ? -R[i] : 0.0;
  if (SUNLinSolSolve(gr->LS, gr->A, g->gR, g->gR, 0.0) != PHM_SUN_SUCCESS ||
      SUNLinSolSolve(gr->LS, gr->A, g->gRc, g->gRc, 0.0) != PHM_SUN_SUCCESS)
    return PHM_FAIL(err, PHM_ESOLVER, "generalized-alpha: the global error estimate's solve "
                                      "failed at t = %.9g s", gr->t);
  /* the matrix is the last step's, made for the step hjac; the block's is H. Where cj = alpha_m
   * / (alpha_f gamma h) dominates its differential block K (every state's, at a rigid
   * mechanism's steps: cj ~ 2/h against its rates' ~ omega), the block's matrix is K hjac / H
   * with the constraint blocks G, G^T as they are, and its solution is the differential rows'
   * (R) states times H / hjac with their multipliers as they are, plus the constraint rows'
   * (Rc) states as they are with their multipliers times hjac / H. (Per step, unscaled, the
   * compound pendulum's estimate at 2 deg, rtol 1e-4, read 1.7e246.) */
  double sc = gr->hjac > 0 ? H / gr->hjac : 1.0;
  /* a stiff block (GALPHA_GLOBAL_STIFF): its propagation is not trusted, the error is carried
   * over it unchanged (e' 0), and the next GALPHA_GLOBAL_STEPWISE steps are propagated one by
   * one (a step's matrix is its own but for its age: trusted) */
  int stiff = 0;
  if (gr->gstep > 0) gr->gstep--;
  else if (galpha_global_stiff(gr, H, sc, e, ep, R, ymax, atol_twist)) {
    stiff = 1;
    gr->gstep = GALPHA_GLOBAL_STEPWISE;
    out->nglob_stiff++;
  }
  for (int i = 0; i < il; i++) {
    if (i >= ie) { /* the ledger's integrals */
      e[i] = ep[i] = 0.0;
      continue;
    }
    if (stiff) dy[i] = e[i];
    else dy[i] += sc * R[i] + Rc[i];
    /* the rate error: the backward difference, not the scheme's e' + dY / (gamma h), whose
     * parasitic root (1 - 1/gamma = -0.9 at rho_inf 0.9) the one iteration's error on an aged
     * matrix pushed beyond -1: the four-bar of benchmarks/scenes.py grew 1.25x per step from
     * t = 0.21 s (converged, three iterations: 0.045 tolerances, as this gives) */
    ep[i] = (dy[i] - e[i]) / H;
    e[i] = dy[i] + L[i];
    L[i] = 0.0;
    ymax[i] = fmax(ymax[i], fabs(Y[i]));
    double r = fabs(e[i]) / (opt->rtol * ymax[i] + (wa[i] < 0 ? atol_twist : opt->atol));
    if (r > worst) {
      worst = r;
      iw = i;
    }
  }
  for (int i = il; i < n; i++) e[i] = stiff ? dy[i] : dy[i] + R[i] + Rc[i] / sc;
  if (worst > out->glob_err) {
    out->glob_err = worst;
    out->t_glob_err = gr->t + h;
    out->glob_state = iw;
    out->glob_err_abs = fabs(e[iw]);
    out->glob_scale = ymax[iw];
  }
  return PHM_OK;
}
