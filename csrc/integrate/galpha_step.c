/* galpha_step.c -- one step of the generalized-alpha (csrc/integrate/galpha_internal.h): the
 * predictor, Newton's iterations and convergence test, the adaptive error test and the retries
 * (a fresh matrix, backward Euler after a restart, halving). */
#include "galpha_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"

/* Newton's convergence test and the iteration matrix's refresh (measured on
 * benchmarks/scenes.py and the released Table I cantilever, docs/integrators.md "Newton
 * iterations"). An iterate accepted after two iterations on the first rate estimate must have
 * a last correction of at most GALPHA_FIRST_MAX tolerances (WRMS); the matrix is refreshed at the
 * next step once the steps on it have needed GALPHA_EXTRA_BUDGET iterations beyond two: a
 * matrix costs ~10 iterations (N = 100 cantilever: 0.73 ms against 62 us, KLU's refactorization
 * a third of it), and before this rule a matrix was kept until Newton failed, each step taking
 * three iterations meanwhile (2.94 per step there; now 2.14, ledger 6.9e-5 -> 6.5e-5).
 * Why not fewer: the predictor is ~1e4 tolerances off (the mesh's vibrations between the band
 * and the step's Nyquist frequency in the twists; constant, linear and quadratic extrapolations
 * of y' alike), so one iteration needs a contraction <= 3e-5, a matrix of that very step.
 * Dropped: IDA's one-iteration test (185 of 2000 steps accepted); a refresh on a measured rate
 * above 3e-3, or after every three-iteration step, without the cap (the second iteration's rate
 * nrm1/nrm0 is the predictor's, far below the next contraction: the double pendulum then
 * accepted last corrections of 380 tolerances, ledger 3.5e-6 -> 5.9e-4); budgets 1 and 8
 * (Jacobians or ledgers of the slider-crank); the rate of the last two corrections (3.2 per
 * step, worse ledgers). Adaptive runs only: the fixed step's Newton tolerance is the user's rtol
 * (1e-8 by default, 10x tighter), and there the cap made the released cantilever (N = 100,
 * step 0.5 ms) take 2.65 iterations per step, 324 Jacobians and 0.60 s of CPU against 3.22, 16
 * and 0.41 s (the budget alone: 2.17, 84, 0.35 s, ledger 6.0e-5 -> 6.2e-5). */
#define GALPHA_FIRST_MAX 30.0
#define GALPHA_EXTRA_BUDGET 4
/* One iteration in a rigid mechanism (no flexible link): there the predictor is ~1 tolerance
 * off, not ~1e4 (no mesh vibrating between the band and the step's Nyquist frequency), and an
 * aged matrix contracts by ~0.02 per iteration; so a step is accepted after its first
 * correction when that correction times rho / (1 - rho) is within 0.33 tolerances (the test of
 * the later iterations), rho = GALPHA_ONE_SAFETY times the first contraction last measured on
 * this matrix (at least GALPHA_ONE_RATE_MIN, at most 0.9). The first contraction underestimates
 * the later ones (see GALPHA_FIRST_MAX; on the chain of benchmarks/bench_scaling.py, n = 30,
 * median 4.6x on fresh matrices), hence the factor; the matrix ages with the carriers'
 * rotation, hence a step of two iterations, which measures it again, after every
 * GALPHA_ONE_VERIFY steps of one. Never on a matrix not yet measured (a fresh one), nor in a
 * restart. Measured on that chain (rtol 1e-4, 0.5 s; n = 10 / 30 / 100): Newton iterations
 * 13 900 -> 10 636, 11 780 -> 7947, 13 654 -> 8420, CPU 0.76x, 0.73x, 0.67x, link-end errors
 * 2.86e-7 -> 2.83e-7, 2.61e-7 -> 2.54e-7, 2.12e-7 -> 2.14e-7 m, ledgers 8.9e-8 -> 5.1e-8,
 * 6.0e-9 -> 1.9e-9, 1.3e-9 -> 6.6e-10; the four-bar of benchmarks/scenes.py (2 s): 23 841 ->
 * 20 207 iterations, the same CPU (its steps' fixed costs dominate), error 1.7e-6 -> 1.9e-6 of
 * its scale, ledger 1.0e-6 -> 1.7e-6. With a safety of 3: 0.7x the chain's iterations but the
 * four-bar's error 3.0e-6 (its estimates summed 0.15 -> 0.32: the iterates' Newton error, read
 * by the estimate); 10: four-bar 1.8e-6, the chain's iterations 0.83x / 0.73x of 5's gain; no
 * re-measurement: 1.03 iterations per step, the chain's ledger 2x. Flexible mechanisms keep
 * two iterations (docs/integrators.md, "Why two iterations, not one"). */
#define GALPHA_ONE_SAFETY 5.0
#define GALPHA_ONE_VERIFY 8
#define GALPHA_ONE_RATE_MIN 0.01
/* the local error estimate below which it is Newton's noise, in Newton tolerances (run_galpha) */
#define GALPHA_NOISE 0.25

/* Newton on the step h at t from the predictor in Y: ok = 1 when it converged (the caller
 * shortens or redoes the step otherwise), the iteration matrix refreshed when gr->hjac = 0.
 * WRMS norm of the correction, weights 1 / (ntol (rtol |Y| + a)) at the updated iterate:
 * nrm of every state decides convergence; nrm_rate, without the energy ledger's
 * integrals [ie, il), the rate of contraction. Nothing depends on those integrals and
 * their Jacobian rows keep only the diagonal (csrc/dae/jacobian.c), so each iteration
 * corrects them one iteration late: from rest, the first correction holds a whole step's
 * supplied energy, and in the rate it read as divergence (rate > 0.9): a Table I
 * cantilever under a 3.9 kN tip force from t = 0 at dt_out 0.25 s stopped at t = 0
 * "even with step 2.44e-05 s" (tests/test_default_integrator.py). Left out of the
 * convergence test too (as from IDA's, csrc/integrate/ida.c), they lag by the iteration
 * that accepts: the manipulator's ledger went from 1.7e-4 to 1.2e-3. Their rows'
 * diagonal cj is that of the step hjac the matrix was made for: rescaled to this step's
 * (cj ~ 1/h) their correction is exact but for P's lag, and contracts as the others do.
 * The fixed step adds P's change by this correction (dae_ledger_dpower: what the rows
 * leave out), and the test takes only the rest, the error of the last such prediction:
 * on the tip-loaded cantilever of benchmarks/bench_scaling.py at N = 1000 the lag was
 * the tip node's unresolved vibration (hw ~ 1e3, +-7 m/s) times the 3.9 kN tip force,
 * 1.4e5 tolerances, and it alone made 95 % of the steps take a third iteration (2.95
 * per step with the co-rotated matrix, 2.25 without the lag; 2.32 and 2.29 at N = 30).
 * Not in the default integrator: there the manipulator of benchmarks/scenes.py took
 * 1.82 iterations per step instead of 1.58 (its one-iteration acceptance, nrm <= 0.033,
 * sits near the threshold, and the steps then settle in the two-iteration regime; 20 %
 * more CPU) for the same error and ledger, the four-bar's error went from 1.5e-6 to
 * 2.7e-6 and the slider-crank's ledger from 1.5e-6 to 3.1e-6, and the released
 * cantilever of benchmarks/newton_iterations.py did not change (2.22 per step). Nor in
 * a restart's backward Euler step: the manipulator
 * of tests/test_generalized_alpha.py (3e9 rad/s^2 at the start) then took its first
 * step whole instead of halving it, 9.7e-6 m off IDA at h = 0.5 ms against 2.2e-6. */
static phm_status galpha_newton(galpha_run *gr, double t, double h, int *okp, phm_error *err) {
  dae_t *d = gr->d;
  const phm_sim_options *opt = gr->opt;
  phm_sim_output *out = gr->out;
  galpha_t *g = &gr->g;
  galpha_corot *cr = &gr->cr;
  SUNMatrix Js = gr->Js, A = gr->A;
  SUNLinearSolver LS = gr->LS;
  int n = gr->n, adaptive = gr->adaptive, restart = gr->restart;
  double *Y = gr->Y, *dY = gr->dY, *w = gr->w, *wa = gr->wa, *dP = gr->dP;
  double newton_tol = gr->newton_tol, newton_start = gr->newton_start, hjac = gr->hjac;
  int fresh = gr->fresh, extra = gr->extra, refresh = gr->refresh;
  phm_status st = PHM_OK;
  int ok = 0;
  double nrm0 = 0;
  /* the absolute part of Newton's error weights, once per step attempt (the relative part
   * follows the iterate, as before: weights fixed from the step's start, or from the larger
   * of the start and the predictor, raised the energy-ledger residuals of the double
   * pendulum and the flexible arm of benchmarks/scenes.py 16-18x). Twists: a velocity error
   * dv moves the poses by h dv in a step, so the tolerance on the twists that matches atol
   * on the poses is atol / h */
  double ah = opt->atol / h, *fmv = N_VGetArrayPointer(g->fm);
  /* (a twist in the error estimate, unfiltered, keeps atol itself when h < 1: its Newton
   * noise there is read by the estimate against rtol |v| + atol) */
  double ahe = adaptive ? fmin(ah, opt->atol) : ah;
  for (int i = 0; i < d->il; i++) w[i] = newton_tol * (wa[i] >= 0 ? wa[i] : fmv[i] != 0.0 ? ah : ahe);
  for (int i = d->il; i < n; i++) w[i] = wa[i];
  /* four iterations, one more per 10x that Newton's tolerance was tightened (newton_min):
   * the predictor is as far off in tolerances as they are tight */
  int itmax = 4 + (int)lround(log10(newton_start / newton_tol));
  for (int it = 0; it < itmax; it++) {
    galpha_stage(d, g, h);
    galpha_residual(d, g, t, h);
    out->nres++;
    if (hjac == 0) {
      if (galpha_jacobian(d, g, t, h, Js, A, LS) ||
          galpha_factor(LS, A, opt->linear_solver == 1, d->nnz)) {
        if (restart && !g->euler) break; /* redone as backward Euler below */
        if (adaptive) { /* a shorter step (Newton-failure path): fresh, so it halves */
          fresh = 1;
          break;
        }
        st = PHM_FAIL(err, PHM_ESOLVER, "generalized-alpha: singular iteration matrix at t = %.9g s", t);
        goto done;
      }
      out->njac++;
      gr->rho1 = 0; /* a new matrix: its contraction is measured before a step trusts it */
      galpha_corot_reference(d, cr, N_VGetArrayPointer(g->ya));
      extra = 0;
      hjac = h;
      fresh = 1;
    }
    if (it == 0) cr->on = !adaptive && !fresh && galpha_corot_set(d, cr, N_VGetArrayPointer(g->ya)); /* galpha_corot */
    N_VScale(-1.0, g->R, g->dY);
    if (cr->on) galpha_corot_apply(d, cr, 1, dY);
    if (SUNLinSolSolve(LS, A, g->dY, g->dY, 0.0) != PHM_SUN_SUCCESS) {
      st = PHM_FAIL(err, PHM_ESOLVER, "generalized-alpha: linear solve failed at t = %.9g s", t);
      goto done;
    }
    if (cr->on) galpha_corot_apply(d, cr, 0, dY);
    out->nniters++;
    /* WRMS norm of the correction: see galpha_newton */
    int lag = adaptive || g->euler; /* the ledger's corrections keep their lag (see above) */
    if (!lag) dae_ledger_dpower(d, t + g->af * h, Y, dY, g->af, dP); /* not Euler: af is g->af */
    double icj = g->gam * h / g->am; /* 1 / (af cj), this step's (read only without the lag) */
    double sum = 0, suml = 0, rd = newton_tol * opt->rtol;
    for (int i = 0; i < d->il; i++) {
      int ledger = i >= d->ie;
      if (ledger) {
        dY[i] *= h / hjac;
        if (!lag) Y[i] += dP[i - d->ie] * icj;
      }
      Y[i] += dY[i];
      double e = dY[i] / (rd * fabs(Y[i]) + w[i]);
      if (ledger) suml += e * e;
      else sum += e * e;
    }
    for (int i = d->il; i < n; i++) {
      Y[i] += dY[i];
      double e = dY[i] / (opt->rtol * fabs(Y[i]) + w[i]);
      sum += e * e;
    }
    double nrm = sqrt((sum + suml) / d->nnorm), nrm_rate = sqrt(sum / d->nnorm);
    if (!isfinite(nrm)) break;
    if (it == 0) {
      nrm0 = nrm_rate;
      if (nrm <= 0.033) { ok = 1; break; }
      /* a rigid mechanism: one iteration when the contraction measured on this matrix says
       * its iterate is converged (GALPHA_ONE_SAFETY) */
      if (gr->rigid && gr->rho1 > 0 && !restart && !g->euler && gr->since < GALPHA_ONE_VERIFY) {
        double rho = fmin(0.9, fmax(GALPHA_ONE_RATE_MIN, GALPHA_ONE_SAFETY * gr->rho1));
        if (nrm * rho / (1.0 - rho) <= 0.33) {
          ok = 1;
          gr->since++;
          break;
        }
      }
    } else {
      if (it == 1 && gr->rigid && nrm0 > 0) { /* the matrix's contraction, measured again */
        gr->rho1 = nrm_rate / nrm0;
        gr->since = 0;
      }
      /* pow(x, 1) is x: the first contraction without the call */
      double rate = nrm0 > 0 ? (it == 1 ? nrm_rate / nrm0 : pow(nrm_rate / nrm0, 1.0 / it)) : 0.0;
      if (rate > 0.9 && nrm_rate > 0.033) break; /* diverging (not round-off over round-off) */
      /* rate > 0.9 below that: the states are at round-off, the ledger's lag decides */
      int conv = rate <= 0.9 ? nrm * rate / (1.0 - rate) <= 0.33 : nrm <= 0.033;
      /* at it == 1 the rate is the first contraction, from the predictor: its error lies
       * mostly in what any iteration matrix resolves (the unresolved vibrations of the
       * mesh, linear), so nrm1/nrm0 underestimates the contraction of what is left (the
       * rotation of the carriers since the matrix was computed): on the released
       * cantilever 8e-3 against 5e-2 for the next one. Such an iterate is accepted only if
       * its last correction is within GALPHA_FIRST_MAX tolerances */
      if (conv && (!adaptive || it > 1 || nrm <= GALPHA_FIRST_MAX)) {
        ok = 1;
        if (adaptive && !fresh && it >= 2 && (extra += it - 1) >= GALPHA_EXTRA_BUDGET) refresh = 1;
        break;
      }
    }
  }
done:
  *okp = ok;
  gr->hjac = hjac;
  gr->fresh = fresh;
  gr->extra = extra;
  gr->refresh = refresh;
  return st;
}

/* The adaptive step's error test, after Newton converged on the step h at t: 1 when it failed
 * and the step is to be redone shorter (*hp), 0 when accepted (gr->errn, emax, elocal: its
 * figures). */
static int galpha_error_test(galpha_run *gr, double *hp) {
  dae_t *d = gr->d;
  const phm_sim_options *opt = gr->opt;
  phm_sim_output *out = gr->out;
  galpha_t *g = &gr->g;
  double h = *hp, hq = gr->hq, hqq = gr->hqq, newton_tol = gr->newton_tol, span = gr->span;
  double hlow = gr->hlow, h0 = gr->h0;
  int filtered = gr->filtered, retry = 0;
  /* per unit step: the local estimate times the number of such steps in the run, so that
   * the estimates summed over the run (an oscillation's phase error adds up step after
   * step) stay within the tolerance, not only each one. Measured on the impulsed
   * cantilever (benchmarks/scenes.py): per step, its 149 Hz mode (4 % of the energy, in
   * the 500 Hz band) drifted a full period off in 1 s and the tip 17 um off IDA; per unit
   * step 6.7 um, at the band's floor step. */
  gr->errn = galpha_error(d, g, h, hq, hqq, opt->rtol, opt->atol, &gr->emax, &gr->ewmax);
  /* Newton's noise: a converged iterate is within ~0.33 of Newton's tolerance, newton_tol
   * times the estimate's, and a third difference of such noise reads as <= 0.22 of it; a
   * local estimate below GALPHA_NOISE newton_tol is that noise, not the step's error, and
   * no shorter step lowers it (per unit step it grows as 1/h): such a step is accepted and
   * counted (nnoise). Measured on a rigid pendulum over 1 s (rtol 1e-4, span/h up to
   * 5000): six steps went to the refinement's limit at t = 0.07 s, four with this rule
   * (the rule below took the rest). It is also what keeps the flexible scenes' cost: at
   * rtol 1e-4 over 2 s the arm + strip accepted 18 098 of 25 194 steps by it, and without
   * it the scenes of benchmarks/scenes.py took 1.0-8.3x main's CPU (the cantilever + tip
   * mass 8.3x); the price, at rtol 1e-6 the arm + strip's tip 3.5e-7 m off over 0.5 s
   * against 8.7e-8 without it, before Newton's tolerance followed the summed estimates
   * (docs/integrators.md, "Convergence in rtol"). */
  gr->elocal = fmax(gr->errn, 0.0); /* this step's own share, summed in err_sum */
  gr->noise = gr->errn > 0 && gr->errn <= GALPHA_NOISE * newton_tol;
  if (gr->errn > 0) gr->errn *= span / h;
  if (gr->noise && gr->errn > 1.0) {
    out->nnoise++;
    gr->errn = 1.0;
  }
  /* a shorter step that did not lower the estimate (errn ~ h^2 per unit step: a step 0.6x
   * as long should read 0.36x) is not seeing its own error but what the history holds:
   * the last steps' accepted errors, which the third difference carries into the next
   * ones (per unit step: errn ~ delta span / (hq tol), whatever h), Newton's noise, or
   * what the filter lets through above the band. Accepted and counted (nnoise): refining
   * on down to the limit would not change it. Measured on a rigid pendulum (rtol 1e-4,
   * steps grown from 1 ms to 17 ms): errn 2.2, 3.1, 3.2, 2.7, 2.3, 2.0 at steps halved
   * each time from 6 ms to 0.2 ms, the refinement's limit. Rigid mechanisms only: where
   * the estimate is filtered, what the filter lets through above the band would pass for
   * history too (the arm + strip ran the same with and without the rule). */
  if (gr->errn > 1.0 && !filtered && gr->etry > 0 && h < 0.6 * gr->htry && gr->errn > 0.5 * gr->etry) {
    out->nnoise++;
    gr->errn = 1.0;
  }
  if (gr->errn > 1.0 && h > hlow * (1.0 + 1e-9)) { /* error test failed: shorter step, same t */
    gr->etry = gr->errn;
    gr->htry = h;
    out->netf++;
    h = fmax(hlow, h * fmax(0.2, 0.8 * pow(gr->errn, -0.5))); /* errn ~ h^2 (per unit step) */
    h0 = h;
    retry = 1;
    goto done;
  }
done:
  *hp = h;
  gr->h0 = h0;
  return retry;
}

/* One step from gr->t of size *hp: the predictor, Newton (galpha_newton), the error test
 * (adaptive: galpha_error_test); on Newton's failure redone with a fresh matrix, as backward
 * Euler after a restart, or halved (up to 10 times); *hp: the step taken. */
phm_status galpha_attempt(galpha_run *gr, double *hp, phm_error *err) {
  dae_t *d = gr->d;
  phm_sim_output *out = gr->out;
  galpha_t *g = &gr->g;
  int n = gr->n, adaptive = gr->adaptive;
  double t = gr->t, h = *hp, hq = gr->hq;
  double *Y = gr->Y, *y0 = gr->y0, *yp0 = gr->yp0, *yq = gr->yq, *ypq = gr->ypq;
  phm_status st = PHM_OK;
  int halvings = 0;
  gr->etry = -1; /* the last attempt at this t that failed the error test */
  gr->htry = 0;
  gr->errn = gr->emax = gr->ewmax = gr->elocal = 0;
  gr->noise = 0;
  for (;;) { /* one step of size h (halved on Newton failure, shortened on error-test failure) */
    /* predictor: y' (and the multipliers) extrapolated linearly from the last two steps */
    /* (no history on the first step and after a restart: yq, ypq are not read then) */
    double r = hq > 0 ? h / hq : 0;
    for (int i = 0; i < d->il; i++)
      Y[i] = g->euler ? y0[i] : y0[i] + h * yp0[i] + (hq > 0 ? g->gam * h * r * (yp0[i] - ypq[i]) : 0.0);
    for (int i = d->il; i < n; i++) Y[i] = hq > 0 ? y0[i] + r * (y0[i] - yq[i]) : y0[i];
    /* the iteration matrix scales with 1/h: refreshed when h moved by more than 20 %. (The
     * adaptive run allowed 50 % before GALPHA_FIRST_MAX: the controller moves h a little at
     * every step, and a stale matrix only slowed the convergence, which a failure then
     * refreshed. With iterates converged to the tolerance the error estimate is no longer
     * raised by Newton's noise, the controller leaves the band's floor more often and its
     * shortened retries met a matrix 30-40 % off: the flexible arm driven through a table
     * (tests/test_default_integrator.py) had 494 Newton failures in 14 991 steps at 50 %, 7 at
     * 20 %; docs/integrators.md, "Newton iterations".) */
    if (fabs(h / gr->hjac - 1.0) > 0.2) gr->hjac = 0;
    if (gr->refresh) { /* GALPHA_EXTRA_BUDGET spent */
      gr->hjac = 0;
      gr->refresh = 0;
    }
    gr->fresh = 0;
    int ok = 0;
    if ((st = galpha_newton(gr, t, h, &ok, err))) goto done;
    if (ok && adaptive && galpha_error_test(gr, &h)) continue;
    if (ok) break;
    out->nncf++;
    if (gr->fresh && gr->newton_tol < gr->newton_start) { /* tightened beyond what Newton reaches here: back, for good */
      gr->newton_tol = gr->newton_min = fmin(gr->newton_start, 10.0 * gr->newton_tol);
    }
    if (gr->restart && !g->euler && (gr->fresh || gr->hjac == 0)) { /* see `restart` */
      g->euler = 1;
      gr->hjac = 0;
      continue;
    }
    if (!gr->fresh) { gr->hjac = 0; continue; }            /* retry with a fresh Jacobian */
    if (++halvings > 10) {
      st = PHM_FAIL(err, PHM_ESOLVER, "generalized-alpha: Newton failed at t = %.9g s even with "
                         "step %.3g s (fresh Jacobian, 10 halvings)", t, h);
      goto done;
    }
    h *= 0.5;
    gr->hjac = 0;
  }
done:
  *hp = h;
  return st;
}
