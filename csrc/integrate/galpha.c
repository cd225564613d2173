/* galpha.c -- the generalized-alpha integrator (the default), with step-size control from a
 * configuration error estimate, refined below the band's floor when it asks (phm_sim_options in
 * csrc/include/phmech_types.h; measurements in docs/integrators.md). */
#include "integrate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"

/* Generalized-alpha for first-order systems (Jansen, Whiting & Hulbert 2000) applied to the DAE.
 * With rho = rho_inf: alpha_f = 1/(1+rho), alpha_m = (3-rho)/(2(1+rho)), gamma = 1/2 + alpha_m -
 * alpha_f (second order, A-stable, spectral radius rho as h*omega -> infinity):
 *   y1 = y0 + h y0' + gamma h (y1' - y0'),
 *   differential rows of F at (t0 + alpha_f h, y0 + alpha_f (y1 - y0), y0' + alpha_m (y1' - y0')),
 *   constraint rows (g = 0, G t = vt) at (t1, y1): the constraints hold at every step;
 * lambda and mu are stage values (not interpolated). Unknown: y1. Modified Newton on the
 * closed-form Jacobian (csrc/dae/jacobian.c), refreshed when convergence is slow or the step changed; a step
 * whose Newton fails with a fresh Jacobian is retried with half the step (up to 2^-10).
 * Steps are shortened (evenly) to land on the output times and on the breakpoints of the laws. */
typedef struct {
  double af, am, gam;
  int euler; /* this step is backward Euler (see run_galpha) */
  N_Vector y0, yp0, Y, Yp, ya, ypa, Ra, R, dY, w, yq, ypq, yqq; /* yq, ypq: previous step; yqq: the one before */
  N_Vector wa; /* each state's absolute tolerance (dae_state_atol), -1 on the twists (atol / h) */
  /* the error estimate's low-pass filter (galpha_error): its two stages at t0 (z1, z2), its
   * output at the two previous steps (z2q, z2qq) and this attempt's values at t1 (z1n, z2n) */
  N_Vector z1, z2, z2q, z2qq, z1n, z2n;
  N_Vector fm; /* 1 on the states the estimate sees through the filter, 0 on the others */
  double wc; /* its corner [rad/s]: 2 pi PHM_FILTER_BAND band (0: no filter) */
} galpha_t;

/* alpha_f of this step (1 for a backward Euler step: the stage is t1) */
static double stage_af(const galpha_t *g) { return g->euler ? 1.0 : g->af; }

/* Stage values from the unknown y1 (= g->Y) for a step h; fills Yp (y1'), ya, ypa. */
static void galpha_stage(const dae_t *d, galpha_t *g, double h) {
  const double *y0 = N_VGetArrayPointer(g->y0), *yp0 = N_VGetArrayPointer(g->yp0);
  const double *Y = N_VGetArrayPointer(g->Y);
  double *Yp = N_VGetArrayPointer(g->Yp), *ya = N_VGetArrayPointer(g->ya), *ypa = N_VGetArrayPointer(g->ypa);
  if (g->euler) { /* written without y0', which may be huge after a restart */
    double ih = 1.0 / h;
    for (int i = 0; i < d->il; i++) {
      Yp[i] = ypa[i] = (Y[i] - y0[i]) * ih;
      ya[i] = Y[i];
    }
  } else {
    double igh = 1.0 / (g->gam * h);
    for (int i = 0; i < d->il; i++) {
      Yp[i] = yp0[i] + (Y[i] - y0[i] - h * yp0[i]) * igh;
      ya[i] = y0[i] + g->af * (Y[i] - y0[i]);
      ypa[i] = yp0[i] + g->am * (Yp[i] - yp0[i]);
    }
  }
  for (int i = d->il; i < d->n; i++) {
    Yp[i] = ypa[i] = 0;
    ya[i] = Y[i];
  }
}

/* R = [differential rows at the stage; constraint rows at (t1, y1)]; Ra: the stage residual's
 * differential rows (its constraint rows, which nothing reads, are not evaluated: the pairs'
 * position constraints are logs of relative poses). */
static void galpha_residual(dae_t *d, galpha_t *g, double t0, double h) {
  double *Ra = N_VGetArrayPointer(g->Ra), *R = N_VGetArrayPointer(g->R);
  dae_residual_rows(d, t0 + stage_af(g) * h, N_VGetArrayPointer(g->ya), N_VGetArrayPointer(g->ypa),
                    Ra, 0);
  dae_constraint_rows(d, t0 + h, N_VGetArrayPointer(g->Y), R);
  memcpy(R, Ra, sizeof(double) * (size_t)d->il);
}

/* Factor the iteration matrix A. SUNDIALS's KLU refactors each new matrix with the pivot order
 * of its first factorization and, when that order meets a zero pivot, reports a failure without
 * looking for another order; so a failure is retried once after SUNLinSol_KLUReInit, which makes
 * the next setup analyse and factor afresh. Measured: with consistent element masses the
 * manipulator's first step (tests/test_consistent_mass.py) failed on the pivots of an earlier matrix at every
 * step size down to 1e-7 s, and a fresh factorization of the same matrix succeeds. */
static int factor_iteration_matrix(SUNLinearSolver LS, SUNMatrix A, int klu, long nnz) {
  if (SUNLinSolSetup(LS, A) == PHM_SUN_SUCCESS) return 0;
  if (!klu || SUNLinSol_KLUReInit(LS, A, (sunindextype)nnz, SUNKLU_REINIT_PARTIAL) != PHM_SUN_SUCCESS)
    return 1;
  return SUNLinSolSetup(LS, A) != PHM_SUN_SUCCESS;
}

/* dR/dy1 ~ alpha_f (dF/dy + cj dF/dy') on the differential block (cj = alpha_m / (alpha_f gamma h)),
 * dF/dy on the multiplier columns and on the constraint rows; dense copy when LS is dense.
 * KLU (A == Js): the exact zeros are dropped (dae_jacobian_prune), and LS is reset for a fresh
 * analysis when the pattern left differs from the one its factors were made for (a refactor
 * assumes that pattern). */
static int galpha_jacobian(dae_t *d, galpha_t *g, double t0, double h, SUNMatrix Js, SUNMatrix A,
                           SUNLinearSolver LS) {
  double cj = g->euler ? 1.0 / h : g->am / (g->af * g->gam * h);
  double af = stage_af(g);
  if (dae_jacobian(d, t0 + af * h, cj, N_VGetArrayPointer(g->ya), N_VGetArrayPointer(g->ypa),
                   N_VGetArrayPointer(g->Ra), Js))
    return 1;
  sunindextype *cp = SUNSparseMatrix_IndexPointers(Js), *ri = SUNSparseMatrix_IndexValues(Js);
  double *val = SUNSparseMatrix_Data(Js);
  for (int j = 0; j < d->il; j++)
    for (sunindextype k = cp[j]; k < cp[j + 1]; k++)
      if (ri[k] < d->il) val[k] *= af;
  if (A == Js) return phm_klu_prune(d, Js, LS);
  dae_jacobian_to_dense(Js, A);
  return 0;
}

/* The fixed step's iteration matrix co-rotated with the carriers. Modified Newton keeps a
 * matrix for many steps (the fixed step refreshes it only when Newton fails), and in the world
 * coordinates of the poses (q, p) it ages with the carriers' rotation: an element's stiff axial
 * and shear directions turn with it, a change of stiffness ~ dtheta (EA - kGA) / l_e that on a
 * fine mesh dwarfs the M / h^2 of the soft (bending) motions beside it. Measured on the Table I
 * cantilever under a tip force from rest (benchmarks/bench_scaling.py, h = 1 ms, rho_inf 1): the
 * contraction on a matrix ten steps old was 1e-3 .. 7e-3 at N = 30 and 1.6e-2 .. 6e-2 at
 * N = 1000 (fresh: 1.5e-4), the Newton iterations per step grew from 2.38 to 3.66 with N, and
 * a matrix at every step costs ten iterations (3 ms against 0.32 ms at N = 1000).
 * A rotation of a carrier, q -> dq (x) q and p -> dR p, turns its kinematic rows
 * (q' = 1/2 q (x) w, p' = R v) as it turns q and p and leaves its momentum rows and twist (body
 * frame) alone; elements, pairs and springs act through the relative pose of their carriers.
 * So if every carrier turned alike, the matrix would be D J D^T, D = diag(L(dq), dR, I) per
 * carrier (orthogonal); the solve takes D J^-1 D^T with each carrier's own rotation since the
 * matrix was computed, exact to first order in the relative rotation of the carriers an
 * element couples (a beam's neighbours turn nearly alike). Not across a pair or spring whose
 * carriers turned apart (a joint, a pivot on the ground): its rows would turn wrongly, so D is
 * used only while every pair and spring has turned by at most GALPHA_COROT_SLIP times the
 * largest rotation of a carrier (measured on benchmarks/scenes.py: clamps and welds 0 or 1e-13
 * of it, joints 0.5 .. 1.5). Loads and gravity turn with the world, not the body: their
 * stiffness is force times lever, small against an element's.
 * Fixed step only: under the default integrator's refresh rule (GALPHA_EXTRA_BUDGET) the leaf
 * spring of benchmarks/scenes.py kept its matrices 4.7x longer (67 Jacobians against 313) and
 * its ledger went from 1.0e-6 to 2.8e-5 of its energy scale (docs/integrators.md). */
#define GALPHA_COROT_SLIP 1e-2
typedef struct {
  dae_carrier_layout L;  /* where a carrier's q and p sit among its states */
  double *qref;          /* nc x 4: the quaternions at the matrix's stage state */
  double *dq;            /* nc x 4: the rotation of each carrier since then */
  double *D;             /* nc x (nq^2 + npos^2): this step's L(dq), dR on those components */
  int on;                /* D is in use this step */
} galpha_corot;

/* Carrier c's quaternion (w, x, y, z) from state y (planar: the kept components, others 0). */
static void corot_quat(const dae_t *d, const galpha_corot *cr, const double *y, int c, double q[4]) {
  q[0] = q[1] = q[2] = q[3] = 0.0;
  for (int j = 0; j < cr->L.nq; j++) q[cr->L.qf[j]] = y[d->ns * c + j];
}

/* The buffers, in work (nc x 33 doubles: the DAE's gwork). */
static void corot_init(const dae_t *d, galpha_corot *cr, double *work) {
  size_t nc = (size_t)d->m->nc;
  memset(cr, 0, sizeof *cr);
  dae_carrier_states(d, &cr->L);
  cr->qref = work;
  cr->dq = work + 4 * nc;
  cr->D = work + 8 * nc; /* at most 16 + 9 per carrier */
}

/* The carriers' quaternions at ya, the stage state a new matrix was computed at. */
static void corot_reference(const dae_t *d, galpha_corot *cr, const double *ya) {
  for (int c = 0; c < d->m->nc; c++) corot_quat(d, cr, ya, c, cr->qref + 4 * c);
}

/* The angle of the rotation between carriers a and b's (-1: the ground's, none) since the
 * matrix was computed. */
static double corot_slip(const galpha_corot *cr, int a, int b) {
  static const double one[4] = {1, 0, 0, 0};
  const double *p = a >= 0 ? cr->dq + 4 * a : one, *r = b >= 0 ? cr->dq + 4 * b : one;
  double v[3] = {-p[0] * r[1] + p[1] * r[0] - p[2] * r[3] + p[3] * r[2], /* vec(p (x) conj(r)) */
                 -p[0] * r[2] + p[1] * r[3] + p[2] * r[0] - p[3] * r[1],
                 -p[0] * r[3] - p[1] * r[2] + p[2] * r[1] + p[3] * r[0]};
  return 2.0 * sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* This step's D from the stage state ya: per carrier dq = q (x) conj(q_ref), then, unless a
 * pair or spring turned across by more than GALPHA_COROT_SLIP times the largest rotation of a
 * carrier (returns 0: D not used), L(dq) (dq (x) .) on its quaternion components and
 * dR = R(dq) on its position axes (returns 1). */
static int corot_set(const dae_t *d, galpha_corot *cr, const double *ya) {
  const phm_model *m = d->m;
  int nq = cr->L.nq, np = cr->L.npos, nd = nq * nq + np * np;
  double rot = 0, slip = 0;
  for (int c = 0; c < m->nc; c++) {
    double q[4], *a = cr->dq + 4 * c;
    const double *r = cr->qref + 4 * c;
    corot_quat(d, cr, ya, c, q);
    a[0] = q[0] * r[0] + q[1] * r[1] + q[2] * r[2] + q[3] * r[3];
    a[1] = -q[0] * r[1] + q[1] * r[0] - q[2] * r[3] + q[3] * r[2];
    a[2] = -q[0] * r[2] + q[1] * r[3] + q[2] * r[0] - q[3] * r[1];
    a[3] = -q[0] * r[3] - q[1] * r[2] + q[2] * r[1] + q[3] * r[0];
    rot = fmax(rot, corot_slip(cr, c, -1));
  }
  for (int k = 0; k < m->np; k++) slip = fmax(slip, corot_slip(cr, m->pair[k].a, m->pair[k].b));
  for (int k = 0; k < m->ns; k++) slip = fmax(slip, corot_slip(cr, m->spr[k].a, m->spr[k].b));
  if (!(slip <= GALPHA_COROT_SLIP * rot)) return 0;
  for (int c = 0; c < m->nc; c++) {
    const double *a = cr->dq + 4 * c;
    const double Lq[16] = {a[0], -a[1], -a[2], -a[3], a[1], a[0], -a[3], a[2],
                           a[2], a[3],  a[0],  -a[1], a[3], -a[2], a[1], a[0]};
    double R[9], *Dc = cr->D + (size_t)nd * c;
    phm_quat_to_rot(a, R);
    for (int i = 0; i < nq; i++)
      for (int j = 0; j < nq; j++) Dc[nq * i + j] = Lq[4 * cr->L.qf[i] + cr->L.qf[j]];
    for (int i = 0; i < np; i++)
      for (int j = 0; j < np; j++) Dc[nq * nq + np * i + j] = R[3 * cr->L.pf[i] + cr->L.pf[j]];
  }
  return 1;
}

/* x <- B x (tr = 0) or B^T x (tr = 1) for the nb x nb matrix B; inlined with constant nb by
 * corot_apply (a loop of variable length, and a memcpy of the result, per carrier made the
 * N = 30 cantilever's run 5 % slower) */
static inline void corot_block(const double *B, int nb, int tr, double *x) {
  double t[4];
  for (int i = 0; i < nb; i++) {
    t[i] = 0.0;
    for (int j = 0; j < nb; j++) t[i] += (tr ? B[nb * j + i] : B[nb * i + j]) * x[j];
  }
  for (int i = 0; i < nb; i++) x[i] = t[i];
}

/* v <- D v (tr = 0) or D^T v (tr = 1) */
static void corot_apply(const dae_t *d, const galpha_corot *cr, int tr, double *v) {
  int nc = d->m->nc, ns = d->ns;
  if (cr->L.nq == 2) /* planar: two 2 x 2 blocks */
    for (int c = 0; c < nc; c++) {
      corot_block(cr->D + 8 * (size_t)c, 2, tr, v + ns * c);
      corot_block(cr->D + 8 * (size_t)c + 4, 2, tr, v + ns * c + 2);
    }
  else
    for (int c = 0; c < nc; c++) {
      corot_block(cr->D + 25 * (size_t)c, 4, tr, v + ns * c);
      corot_block(cr->D + 25 * (size_t)c + 16, 3, tr, v + ns * c + 4);
    }
}

/* the twists' absolute tolerance in the error estimate, in atol times the band's angular
 * frequency (galpha_error) */
#define GALPHA_TWIST_ATOL 0.1
/* Local error estimate of a converged step h (previous steps hq, hqq; 0: not there), WRMS-normed
 * with the error weights of the configuration states (poses, joint coordinates; twists, ledger
 * integrals and multipliers are left out): the trapezoidal local error h^3 y'''/12, with y''' = 6
 * times the third divided difference over the last four points -- of the configuration seen
 * through a low-pass filter at the band: two first-order stages with corner wc = 2 pi
 * PHM_FILTER_BAND band, each exact for an input linear over the step. A motion slow against wc
 * passes delayed by 2/wc with its y''' kept to (w/wc)^2; a vibration at w >> wc is divided by
 * (w/wc)^2. What the filter removes is the content above the band, which the method damps
 * (rho_inf) instead of resolving. Measured on the README's arm + strip (band 500 Hz): the raw
 * estimate stayed above rtol 1e-4 with the steps refined 64x below the band's floor, while the
 * default run was within 4e-6 of 0.6 m of a tight reference (docs/integrators.md, "The error
 * estimate"). Positions, not rates: a fast vibration the step does not resolve has a tiny
 * amplitude in the poses and a large one in the rates (by omega).
 * Fills g->z1n, g->z2n (the filter at t1, kept by the caller when the step is accepted).
 * Returns -1 without enough history (the first two steps after a start or a breakpoint).
 * *emax: the max-norm estimate. */
static double galpha_error(const dae_t *d, galpha_t *g, double h, double hq, double hqq,
                           double rtol, double atol, double *emax) {
  *emax = 0;
  const double *Y = N_VGetArrayPointer(g->Y), *y0 = N_VGetArrayPointer(g->y0);
  const double *z1 = N_VGetArrayPointer(g->z1), *z2 = N_VGetArrayPointer(g->z2);
  const double *zq = N_VGetArrayPointer(g->z2q), *zqq = N_VGetArrayPointer(g->z2qq);
  double *z1n = N_VGetArrayPointer(g->z1n), *z2n = N_VGetArrayPointer(g->z2n);
  const double *wa = N_VGetArrayPointer(g->wa), *fm = N_VGetArrayPointer(g->fm);
  /* no band (wc = 0): no filter, z = y */
  double x = g->wc * h, ex = x > 0 ? exp(-x) : 0.0, ix = x > 0 ? 1.0 / x : 0.0;
  int est = hq > 0 && hqq > 0;
  double sum = 0, mx = 0;
  int cnt = 0;
  /* reciprocals once: six divisions per state per step were ~5 % of a flexible scene's CPU */
  double ih = 1.0 / h, ihq = est ? 1.0 / hq : 0, ihqq = est ? 1.0 / hqq : 0;
  double ia = 1.0 / (h + hq), ib = est ? 1.0 / (hq + hqq) : 0;
  double c3 = 0.5 * h * h * h / (h + hq + hqq);
  /* The twists count where the estimate is not filtered (a rigid mechanism): an oscillation's
   * phase error accrues in the twists near its turning points, where the positions' third
   * difference vanishes; without them a compound pendulum (30 deg, 5 s, rtol 1e-4) ended 2.8x
   * rtol off with its estimates summed to 0.64 (now 0.65x rtol, 1.36x the steps; 2 deg: 3.7x
   * -> 0.94x). Filtered (flexible links): not, the twists of the mesh's vibrations above the
   * band pass the filter's two stages enough to take 20-200x the steps (benchmarks/scenes.py).
   * Their absolute tolerance is atol times GALPHA_TWIST_ATOL wc: the twist error that moves the
   * positions by atol over 1/(0.1 wc), 1.6 periods of the band's highest frequency. With atol
   * itself (1/s) the chain of 100 links of tests/accuracy/ (rtol 1e-4, 0.5 s) took 2.5x the
   * steps to end 9e-8 m off instead of 4e-7 (its tolerance is 1e-3 m); with 1 wc the pendulum
   * at 2 deg ended 2.6x rtol off (0.1 wc: 1.2x, 0.93x of rtol amp + atol). */
  double atol_twist = g->wc > 0 ? GALPHA_TWIST_ATOL * g->wc * atol : atol;
  for (int i = 0; i < d->ie; i++) {
    if (wa[i] < 0 && fm[i] != 0.0) continue; /* a twist, filtered */
    double a = Y[i], b = Y[i];
    if (fm[i] != 0.0) {
      double s1 = (Y[i] - y0[i]) * ix, s2;
      a = Y[i] - s1 + ex * (z1[i] - y0[i] + s1);
      s2 = (a - z1[i]) * ix;
      b = a - s2 + ex * (z2[i] - z1[i] + s2);
    }
    z1n[i] = a;
    z2n[i] = b;
    if (!est) continue;
    double d10 = (b - z2[i]) * ih, d0q = (z2[i] - zq[i]) * ihq, dqq = (zq[i] - zqq[i]) * ihqq;
    double dd2a = (d10 - d0q) * ia, dd2b = (d0q - dqq) * ib;
    double e = c3 * (dd2a - dd2b);
    double wgt = rtol * fabs(Y[i]) + (wa[i] < 0 ? atol_twist : atol);
    sum += (e / wgt) * (e / wgt);
    mx = fmax(mx, fabs(e));
    cnt++;
  }
  *emax = mx;
  if (!est) return -1.0;
  return cnt ? sqrt(sum / (cnt + d->ncfg_drop)) : 0.0;
}

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

/* Its scratch, zeroed: nc x 33 doubles for the co-rotation (corot_init) and the ledger's
 * il - ie rates dP (of the full DAE when planar). */
phm_status galpha_setup(dae_t *d, const phm_sim_options *opt, void **work, phm_error *err) {
  (void)opt;
  const dae_t *f = dae_full(d);
  *work = calloc(33 * (size_t)f->m->nc + (size_t)(f->il - f->ie) + 1, sizeof(double));
  return *work ? PHM_OK : PHM_FAIL(err, PHM_ENOMEM, "out of memory");
}

void galpha_release(void *work) { free(work); }

/* One run of the generalized-alpha: the scheme and its vectors (g), the co-rotation (cr), the
 * iteration matrix and its solver, the arrays (g's vectors' data), the step-size limits and the
 * state its steps share (run_galpha's functions below). */
typedef struct {
  dae_t *d;
  const phm_sim_options *opt;
  phm_sim_output *out;
  int n, adaptive, filtered;
  galpha_t g;
  galpha_corot cr;
  SUNMatrix Js, A;
  SUNLinearSolver LS;
  double *y0, *yp0, *Y, *Yp, *dY, *w, *yq, *ypq, *yqq, *wa, *dP;
  double hfloor, hlow, hmax, span;
  double newton_tol, newton_min, newton_start; /* Newton's tolerance factor, its floor, its start */
  double t, h0;           /* the time reached, the proposed step */
  double hjac, hq, hqq;   /* the step the matrix was made for (0: none), the last two steps */
  int fresh, restart, extra, refresh; /* see galpha_open */
  double etry, htry, errn, emax, elocal; /* this step's attempts (galpha_error_test) */
  double grow_q, grow_qq; /* the last two accepted steps' estimates per unit step over h^2 (0: none) */
  int noise;              /* this step's estimate is at the level of Newton's noise */
  int rigid;              /* adaptive, no flexible link: one-iteration steps (GALPHA_ONE_SAFETY) */
  double rho1;            /* the last first contraction measured on this matrix (0: none yet) */
  int since;              /* steps accepted on one iteration since rho1 was measured */
} galpha_run;

/* g's vectors, for galpha_open and galpha_close. */
#define GALPHA_VECTORS(g)                                                                        \
  {&(g)->y0, &(g)->yp0, &(g)->Y, &(g)->Yp, &(g)->ya, &(g)->ypa, &(g)->Ra, &(g)->R, &(g)->dY,      \
   &(g)->w, &(g)->yq, &(g)->ypq, &(g)->yqq, &(g)->wa, &(g)->z1, &(g)->z2, &(g)->z2q, &(g)->z2qq,  \
   &(g)->z1n, &(g)->z2n, &(g)->fm}

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
  corot_init(d, &gr->cr, gwork);
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
          factor_iteration_matrix(LS, A, opt->linear_solver == 1, d->nnz)) {
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
      corot_reference(d, cr, N_VGetArrayPointer(g->ya));
      extra = 0;
      hjac = h;
      fresh = 1;
    }
    if (it == 0) cr->on = !adaptive && !fresh && corot_set(d, cr, N_VGetArrayPointer(g->ya)); /* galpha_corot */
    N_VScale(-1.0, g->R, g->dY);
    if (cr->on) corot_apply(d, cr, 1, dY);
    if (SUNLinSolSolve(LS, A, g->dY, g->dY, 0.0) != PHM_SUN_SUCCESS) {
      st = PHM_FAIL(err, PHM_ESOLVER, "generalized-alpha: linear solve failed at t = %.9g s", t);
      goto done;
    }
    if (cr->on) corot_apply(d, cr, 0, dY);
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
  gr->errn = galpha_error(d, g, h, hq, hqq, opt->rtol, opt->atol, &gr->emax);
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
static phm_status galpha_attempt(galpha_run *gr, double *hp, phm_error *err) {
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
  gr->errn = gr->emax = gr->elocal = 0;
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
  double t = gr->t, errn = gr->errn, emax = gr->emax, elocal = gr->elocal;
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
