/* galpha_internal.h -- the generalized-alpha integrator's pieces, shared by its three files:
 * galpha_scheme.c (the scheme's stage, residual and iteration matrix, the fixed step's
 * co-rotated matrix, the error estimate), galpha_step.c (one step: Newton, the error test, the
 * retries) and galpha.c (its row of the integrators' table, a run's set-up, the accepted step's
 * bookkeeping and step-size control, run_galpha). Not a public header: csrc/include/ is. */
#ifndef PHM_GALPHA_INTERNAL_H
#define PHM_GALPHA_INTERNAL_H

#include "integrate.h"

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
  /* the global error estimate (galpha_global.c): the local estimates of this attempt per state
   * (le: galpha_error's, 0 where none), the propagated error of the states and of their rates
   * (ge, gep), the largest |y| of each state so far (gy: its scale), and the scratch of one
   * tangent step (gya, gypa: the perturbed stage; gR: its residual, then the correction) */
  N_Vector le, ge, gep, gy, gya, gypa, gR, gdy, gRc, gl, gyam, gypam;
} galpha_t;

/* the twists' absolute tolerance in the error estimate, in atol times the band's angular
 * frequency (galpha_error; the global estimate's too, galpha_global.c) */
#define GALPHA_TWIST_ATOL 0.1

/* The absolute tolerance of a twist in the error estimates, for the configuration's atol:
 * GALPHA_TWIST_ATOL wc atol, or atol without a band (galpha_error explains the choice). */
static inline double galpha_twist_atol(const galpha_t *g, double atol) {
  return g->wc > 0 ? GALPHA_TWIST_ATOL * g->wc * atol : atol;
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

/* One run of the generalized-alpha: the scheme and its vectors (g), the co-rotation (cr), the
 * iteration matrix and its solver, the arrays (g's vectors' data), the step-size limits and the
 * state its steps share (run_galpha's functions below). */
typedef struct {
  dae_t *d;
  const phm_sim_options *opt;
  phm_sim_output *out;
  int n, adaptive, filtered;
  int nout;               /* the output times (tout[nout - 1]: the run's end) */
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
  double etry, htry, errn, emax, ewmax, elocal; /* this step's attempts (galpha_error_test) */
  double grow_q, grow_qq; /* the last two accepted steps' estimates per unit step over h^2 (0: none) */
  int noise;              /* this step's estimate is at the level of Newton's noise */
  int rigid;              /* adaptive, no flexible link: one-iteration steps (GALPHA_ONE_SAFETY) */
  double rho1;            /* the last first contraction measured on this matrix (0: none yet) */
  int since;              /* steps accepted on one iteration since rho1 was measured */
  int global;             /* the global error estimate is propagated (galpha_global.c) */
  double gH, gtm, ghm;    /* its block so far [s], the time of the block's stage (gyam, gypam)
                           * and the step it was the stage of [s] */
  double gta, gHx;        /* the block's start [s] and expected length [s] */
  int gcount;             /* and its steps */
  int gstep;              /* steps still to propagate one by one after a stiff block */
} galpha_run;

/* galpha_scheme.c */
void galpha_stage(const dae_t *d, galpha_t *g, double h);
void galpha_residual(dae_t *d, galpha_t *g, double t0, double h);
int galpha_factor(SUNLinearSolver LS, SUNMatrix A, int klu, long nnz);
int galpha_jacobian(dae_t *d, galpha_t *g, double t0, double h, SUNMatrix Js, SUNMatrix A,
                    SUNLinearSolver LS);
void galpha_corot_init(const dae_t *d, galpha_corot *cr, double *work);
void galpha_corot_reference(const dae_t *d, galpha_corot *cr, const double *ya);
int galpha_corot_set(const dae_t *d, galpha_corot *cr, const double *ya);
void galpha_corot_apply(const dae_t *d, const galpha_corot *cr, int tr, double *v);
double galpha_error(const dae_t *d, galpha_t *g, double h, double hq, double hqq, double rtol,
                    double atol, double *emax, double *ewmax);

/* galpha_step.c */
phm_status galpha_attempt(galpha_run *gr, double *hp, phm_error *err);

/* galpha_global.c */
void galpha_global_open(galpha_run *gr);
phm_status galpha_global_step(galpha_run *gr, double h, int last, phm_error *err);

#endif
