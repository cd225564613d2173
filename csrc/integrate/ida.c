/* ida.c -- the IDA driver (SUNDIALS' variable-order BDF): tolerances per state, the linear
 * solver (KLU or the dense LU, both with the closed-form Jacobian of csrc/dae/jacobian.c), output
 * times, breakpoints of the laws (restart from consistent values) and the monitor. */
#include "integrate.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "phm_check.h"

/* IDA's user data: the DAE, and the KLU solver whose factors the Jacobian resets (KLU) or the
 * sparse matrix the dense LU's Jacobian is evaluated into (dense). */
typedef struct {
  dae_t *d;
  SUNLinearSolver klu;
  SUNMatrix js;
  /* for ledger_solve: the solver it wraps, the last residual's time and state (IDA's iterate,
   * unchanged while the linear system of that iterate is solved), the cj of the matrix's ledger
   * diagonal, and scratch for the powers' change (n >= il - ie entries) */
  SUNLinearSolver inner;
  double tres, cjac;
  const double *yres;
  N_Vector dP;
} ida_ud;

static int ida_res(sunrealtype t, N_Vector yy, N_Vector yp, N_Vector rr, void *ud) {
  ida_ud *u = ud;
  u->tres = t;
  u->yres = N_VGetArrayPointer(yy);
  return dae_residual(u->d, t, N_VGetArrayPointer(yy), N_VGetArrayPointer(yp),
                      N_VGetArrayPointer(rr));
}

/* The energy ledger's Newton rows, made exact. Their Jacobian rows hold only the diagonal cj
 * (csrc/dae/jacobian.c): the full row is [-dP/dy, cj] (F_E = E' - P(y)), and nothing depends
 * on E, so the full system's solution is the one solved, with x_E = (b_E + dP/dy x) / cj --
 * the solved x_E plus the change of the powers along x over cj (dae_ledger_dpower, as the
 * fixed-step generalized-alpha adds it, csrc/integrate/galpha.c). Without it the integrals lag
 * Newton by an iteration: IDA often takes one iteration per step, and the ledger then holds the
 * predictor's powers (a driven revolute's spin-up, tests/test_driven_pairs.py, at rtol 1e-8:
 * 1.5e-5 of its energy scale with KLU, 8.7e-8 with the correction). This wrapper solver adds
 * that correction to the solver it wraps (KLU or the dense LU), whose set-up and factors it
 * shares. Its content is run_ida's ida_ud and its scratch a SUNDIALS vector: nothing of
 * phmech's own is allocated after the first output (tests/c/test_no_alloc.c). */
static SUNLinearSolver_Type ledger_gettype(SUNLinearSolver S) {
  (void)S;
  return SUNLINEARSOLVER_DIRECT;
}
static int ledger_initialize(SUNLinearSolver S) {
  return SUNLinSolInitialize(((ida_ud *)S->content)->inner);
}
static int ledger_setup(SUNLinearSolver S, SUNMatrix A) {
  return SUNLinSolSetup(((ida_ud *)S->content)->inner, A);
}
static int ledger_solve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b, sunrealtype tol) {
  ida_ud *u = S->content;
  int r = SUNLinSolSolve(u->inner, A, x, b, tol);
  dae_t *d = u->d;
  if (r || !u->yres || !(u->cjac > 0)) return r; /* (no residual or Jacobian yet: none) */
  double *X = N_VGetArrayPointer(x), *dP = N_VGetArrayPointer(u->dP);
  dae_ledger_dpower(d, u->tres, u->yres, X, 1.0, dP);
  for (int i = d->ie; i < d->il; i++) X[i] += dP[i - d->ie] / u->cjac;
  return 0;
}
static sunindextype ledger_lastflag(SUNLinearSolver S) {
  return SUNLinSolLastFlag(((ida_ud *)S->content)->inner);
}
static int ledger_free(SUNLinearSolver S) {
  if (S) {
    S->content = NULL; /* run_ida's */
    SUNLinSolFreeEmpty(S);
  }
  return 0;
}

/* A direct solver that is u->inner plus the ledger's correction (NULL: out of memory); the
 * operations it does not name stay unset, as SUNLinSolNewEmpty leaves them. */
static const struct _generic_SUNLinearSolver_Ops ledger_ops = {
    .gettype = ledger_gettype, .initialize = ledger_initialize, .setup = ledger_setup,
    .solve = ledger_solve,     .lastflag = ledger_lastflag,     .free = ledger_free};
static SUNLinearSolver ledger_wrap(ida_ud *u, SUNContext ctx) {
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  if (!S) return NULL;
  S->content = u;
  *S->ops = ledger_ops;
  return S;
}

/* The closed-form Jacobian for KLU without its exact zeros (dae_jacobian_prune): the block
 * pattern of a chain of rigid bodies is ~80 % zeros (n = 100: ~22160 of 119378 entries kept; KLU's
 * factors, lnz + unz, 40900 entries against 145540 on the full pattern), so each Newton
 * iteration's triangular solves and each refactorization shrink with it. When the kept pattern grows, the factors were made for
 * another pattern: SUNLinSol_KLUReInit makes IDA's next linear-solver set-up (which follows this
 * call) analyse and factor afresh, as the generalized-alpha does. */
static int ida_jac(sunrealtype t, sunrealtype cj, N_Vector yy, N_Vector yp, N_Vector rr, SUNMatrix J,
                   void *ud, N_Vector t1, N_Vector t2, N_Vector t3) {
  (void)t1; (void)t2; (void)t3;
  ida_ud *u = ud;
  u->cjac = cj;
  int r = dae_jacobian(u->d, t, cj, N_VGetArrayPointer(yy), N_VGetArrayPointer(yp),
                       N_VGetArrayPointer(rr), J);
  if (r) return r;
  return phm_klu_prune(u->d, J, u->klu) ? -1 : 0;
}

/* The dense LU's Jacobian: the same closed form on the sparse pattern (into js, allocated with
 * the solver), copied into the dense matrix J (dae_jacobian_to_dense; entries off the pattern 0).
 * IDA's own difference quotients, which the dense LU used before, cost one residual per state
 * for each Jacobian and perturbed a state by 1/weight (the ledger's overflow,
 * PHM_IDA_LEDGER_ATOL). The Fig. 3 manipulator of examples/manipulator.py (474 states, 0.05 s at
 * rtol 1e-6): 23511 residuals and 0.52 s of CPU before, 760 and 0.35 s now, KLU 760 and 0.04 s --
 * the rest is the dense LU's own factorizations and O(n^2) solves (docs/integrators.md, "IDA's
 * linear solvers: one Jacobian"). What still differs on purpose is KLU's: the pruned pattern and
 * its pivoting (run_ida); the dense LU factors every entry, exact zeros included, with partial
 * pivoting. The quotients held the ledger rows' full derivative, the closed form only their
 * diagonal: ledger_solve completes them for both solvers. */
static int ida_jac_dense(sunrealtype t, sunrealtype cj, N_Vector yy, N_Vector yp, N_Vector rr,
                         SUNMatrix J, void *ud, N_Vector t1, N_Vector t2, N_Vector t3) {
  (void)t1; (void)t2; (void)t3;
  ida_ud *u = ud;
  u->cjac = cj;
  int r = dae_jacobian(u->d, t, cj, N_VGetArrayPointer(yy), N_VGetArrayPointer(yp),
                       N_VGetArrayPointer(rr), u->js);
  if (r) return r;
  dae_jacobian_to_dense(u->js, J);
  return 0;
}

/* ---------------------------------------------------------------- the integrator's row
 * (integrators.c): its options' checks, its scratch */
phm_status ida_check(const phm_sim_options *opt, phm_error *err) {
  const phm_ida_options *o = &opt->ida;
  if (o->error_test != PHM_ERRTEST_ALL && o->error_test != PHM_ERRTEST_CONFIGURATION)
    return PHM_FAIL(err, PHM_EINVAL, "unknown error test %d (0 all states, 1 configuration)", o->error_test);
  if (o->error_test == PHM_ERRTEST_CONFIGURATION && !(o->max_order > 0 && o->max_order <= 2))
    return PHM_FAIL(err, PHM_EINVAL, "the configuration error test needs a maximum BDF order of 1 or 2 "
                         "(got %d): without the twists in the error test, BDF 3-5 let unresolved vibrations grow", o->max_order);
  return PHM_OK;
}

/* IDA's scratch: its last error message, quoted in the failure's phm_error (SUNDIALS prints
 * nothing: csrc/util/sundials_compat.h), and the sink that writes it. Allocated at set-up, freed
 * after the SUNDIALS context (simulate.c), which keeps the sink with SUNDIALS 7. */
typedef struct {
  char msg[256];
  phm_sun_errsink sink;
} ida_work;

static void ida_err_message(void *ud, const char *function, const char *msg) {
  ida_work *w = ud;
  snprintf(w->msg, sizeof w->msg, "%s: %s", function, msg);
}

phm_status ida_setup(dae_t *d, const phm_sim_options *opt, void **work, phm_error *err) {
  (void)d;
  (void)opt;
  ida_work *w = calloc(1, sizeof *w);
  if (!w) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  w->sink = (phm_sun_errsink){ida_err_message, w};
  *work = w;
  return PHM_OK;
}

void ida_release(void *work) { free(work); }

/* ---------------------------------------------------------------- driver */
#define IDACHK(call)                                                                           \
  do {                                                                                         \
    int flag_ = (call);                                                                        \
    if (flag_ < 0) {                                                                           \
      char *nm_ = IDAGetReturnFlagName(flag_);                                                 \
      st = PHM_FAIL(err, PHM_ESOLVER, "IDA set-up failed: %s returned %s", #call,         \
                         nm_ ? nm_ : "?");                                                     \
      free(nm_);                                                                               \
      goto done;                                                                               \
    }                                                                                          \
  } while (0)

/* IDA's absolute tolerance of state i: dae_state_atol, but none for the energy ledger's
 * integrals (1e100 J: weight 0). Nothing depends on them, and their Jacobian rows keep only the
 * diagonal (csrc/dae/jacobian.c), so a Newton iteration corrected them one iteration late (until
 * ledger_solve): in the error and Newton tests they only measured that lag. With the closed-form Jacobian IDA's Newton
 * often stops after one iteration, and the lag then failed the error test at almost every step
 * (the PD arm of tests/test_arm.py at rtol 1e-8: 51733 error-test failures in 53583 steps; left
 * out, 21 in 2050, ledger residual 3.1e-9 of the energy scale; with the finite-difference
 * Jacobian they were in, 54 in 2232 and 3.5e-9). Their accuracy follows that of the states they
 * integrate.
 * The same arm at rtol 1e-9 used to fail the error test at almost every step from t = 0.46 s
 * (150101 failures in 153084 steps), the largest estimates on the pairs' joint coordinates. It
 * now takes 3559 steps with 119 failures, ledger 9.2e-10 (rtol 1e-8: 1935 steps, 20 failures,
 * 7.3e-9; measured 2026-11-27, not bisected: likely the rows of the carriers mu acts on, now in
 * their body frames, docs/integrators.md "IDA and mu"). */
/* The ledger's "none": 1e100 J. Its weight 1/(rtol |E| + 1e100) squares to an exact 0 in every
 * WRMS norm (energies far below 1e100 J), as 1e300's did. Not 1e300: the dense solver's
 * difference-quotient Jacobian (IDA's own, which the dense LU used until it took the closed form,
 * ida_jac_dense) perturbed state j by 1/w_j and its rate by cj times
 * that, and 1e300 cj overflowed for cj > 1.8e8 (steps below ~5e-9 s at order 1): the ledger's
 * columns were inf, its Newton corrections 0 (the integrals stood still) or the iterate NaN (a
 * convergence failure). The Fig. 3 manipulator (examples/manipulator.py), whose first steps are
 * ~1e-15 s (run_ida), closed its ledger over 2 ms with the dense LU to 9.2e-5 of its energy
 * scale at rtol 1e-8 and 1.1e-3 at 1e-10 (KLU: 7.9e-10, 6.9e-11); now 6.7e-10 and 7.9e-11. And
 * its dense run at rtol 1e-8 had got past t = 0 before run_ida's first-step retry only through
 * such a NaN, which IDA counts as a convergence failure, not as one of its 10 error-test
 * failures. 1e100 cj stays finite for any cj below 1e200 (steps above ~1e-200 s). */
#define PHM_IDA_LEDGER_ATOL 1e100
static double ida_atol(const dae_t *d, int i, double atol) {
  return i >= d->ie && i < d->il ? PHM_IDA_LEDGER_ATOL : dae_state_atol(d, i, atol);
}

/* One of IDA's counters (0 where IDA does not give it). */
static long ida_count(int (*get)(void *, long *), void *mem) {
  long a = 0;
  return get(mem, &a) == 0 ? a : 0;
}

static void add_stats(void *mem, phm_sim_output *out) {
  out->nsteps += ida_count(IDAGetNumSteps, mem);
  out->nres += ida_count(IDAGetNumResEvals, mem);
  /* the residuals IDA's linear solver spends on difference quotients: none with ida_jac and
   * ida_jac_dense (tests/test_solver_robustness.py holds the dense run's count to that) */
  out->nres += ida_count(IDAGetNumLinResEvals, mem);
  out->njac += ida_count(IDAGetNumJacEvals, mem);
  out->nniters += ida_count(IDAGetNumNonlinSolvIters, mem);
  out->netf += ida_count(IDAGetNumErrTestFails, mem);
  out->nncf += ida_count(IDAGetNumNonlinSolvConvFails, mem);
  double h = 0;
  if (IDAGetLastStep(mem, &h) == 0) out->last_step = h;
  int q = 0;
  if (IDAGetLastOrder(mem, &q) == 0) out->last_order = q;
}

/* One run of IDA: what run_ida creates (ida_free_run frees it) and the state its output
 * intervals share. */
typedef struct {
  ida_ud ud;
  ida_work *w;
  void *mem;
  N_Vector id, ys, yps; /* ys, yps: the last (re)start's values */
  SUNMatrix A;
  SUNLinearSolver LS, W; /* W: LS with the ledger's rows exact (ledger_wrap) */
  long max_steps;        /* per output interval */
  double hmin, h0;       /* the step's floor and the first step (ida_create) */
  int retried, relaxed;  /* the first step retried since the (re)start; floor lifted */
} ida_run;

/* The differential states (id) and the tolerances per state. */
static phm_status ida_tolerances(ida_run *r, dae_t *d, const phm_sim_options *opt, SUNContext ctx,
                                 phm_error *err) {
  phm_status st = PHM_OK;
  void *mem = r->mem;
  r->id = N_VNew_Serial(d->n, ctx);
  if (!r->id) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory (N_Vector)");
    goto done;
  }
  double *idd = N_VGetArrayPointer(r->id);
  /* id: 1 differential, 0 algebraic. IDA uses it only to leave the 0 components out of the local
   * error test (IDASetSuppressAlg; no IDACalcIC here), so the configuration error test marks the
   * twists 0 as well: they keep their weights in the Newton convergence test. The energy ledger's
   * integrals are marked 0 too and get no weight in the Newton test either (ida_atol; the
   * generalized-alpha's error estimate leaves them out as well). */
  for (int i = 0; i < d->n; i++)
    idd[i] = i < d->ie && !(dae_is_twist(d, i) && opt->ida.error_test == PHM_ERRTEST_CONFIGURATION) ? 1.0 : 0.0;
  {
    N_Vector av = N_VNew_Serial(d->n, ctx);
    if (!av) {
      st = PHM_FAIL(err, PHM_ENOMEM, "out of memory (N_Vector)");
      goto done;
    }
    double *a = N_VGetArrayPointer(av);
    /* IDA's WRMS norms divide by n: tolerances scaled by sqrt(nnorm / n) give a planar DAE the
     * norms of its 3-D solve (dae.h, nnorm); 1 in 3-D */
    double f = sqrt((double)d->nnorm / d->n);
    for (int i = 0; i < d->n; i++) a[i] = f * ida_atol(d, i, opt->atol);
    int fl = IDASVtolerances(mem, f * opt->rtol, av);
    N_VDestroy(av);
    IDACHK(fl);
  }
  IDACHK(IDASetId(mem, r->id));
  IDACHK(IDASetSuppressAlg(mem, SUNTRUE));
done:
  return st;
}

/* IDA at the consistent state yy, yp at tout[0], with its error sink, tolerances, step limits
 * and the state of its first-step retry. */
static phm_status ida_create(ida_run *r, dae_t *d, const phm_sim_options *opt, SUNContext ctx,
                             N_Vector yy, N_Vector yp, const double *tout, int nout,
                             phm_error *err) {
  phm_status st = PHM_OK;
  void *mem = r->mem = IDACreate(ctx);
  if (!mem) {
    st = PHM_FAIL(err, PHM_ENOMEM, "IDACreate failed");
    goto done;
  }
  IDACHK(phm_ida_set_errsink(mem, ctx, &r->w->sink));
  IDACHK(IDAInit(mem, ida_res, tout[0], yy, yp));
  if ((st = ida_tolerances(r, d, opt, ctx, err))) goto done;
  IDACHK(IDASetUserData(mem, &r->ud));
  /* bounded failure: at most 10^6 steps per output interval, and no step below 1e-14 of the
   * simulated span (a corrector that keeps failing ends in IDA_CONV_FAIL/IDA_ERR_FAIL there
   * instead of creeping on at h ~ 1e-18) */
  /* with a monitor, IDASolve returns every PHM_MONITOR_STEPS steps (IDA_TOO_MUCH_WORK, state
   * intact) so the monitor sees long output intervals; the per-interval limit is counted here */
  r->max_steps = opt->max_steps > 0 ? opt->max_steps : 1000000L;
  IDACHK(IDASetMaxNumSteps(mem, opt->monitor ? PHM_MONITOR_STEPS : r->max_steps));
  r->hmin = 1e-14 * fmax(1.0, tout[nout - 1] - tout[0]);
  r->h0 = fmin(1e-8, 1e-3 * (tout[nout - 1] - tout[0]));
  IDACHK(IDASetMinStep(mem, r->hmin));
  IDACHK(IDASetInitStep(mem, r->h0));
  /* The first step from consistent values (the start, each breakpoint's restart) may need to be
   * far shorter than h0 and hmin: IDA's 10 error-test failures (each cutting h by 4 at most)
   * reach 4^-9 h0 = 3.8e-14 s, and hmin stops them at 1e-14 s. The Fig. 3 manipulator
   * (examples/manipulator.py, consistent masses, material damping D = 5e-3 s K) needs ~6e-15 s at
   * rtol 1e-8 and ~6e-16 s at 1e-10: its set-point step gives the links' nodes consistent
   * accelerations of 1e8 .. 5e8 rad/s^2 (F3's first node: 24 N m on 6.8e-9 kg m^2 about z,
   * shared through the consistent mass), which decay within ~15 ps (the elements' stiffest
   * modes, shear with the nodes' rotation at ~2e6 rad/s, decay at beta omega^2 ~ 3e10 /s), so
   * omega'' ~ 3e19 rad/s^3 there, and the every-state error test on omega (atol 1e-10 rad/s)
   * admits h^2 omega'' / 2 only for h ~ 1e-15 s. (The dense solver got past t = 0 at rtol 1e-8
   * only through a NaN Newton iterate, which IDA counts as a convergence failure, not as one of
   * the 10 error-test failures: it had an 11th attempt, at hmin, which passed; ida_atol.)
   * So when the error test fails 10 times before the first step, IDA is re-initialized from the
   * same consistent values with a first step of a quarter of the last one tried and no floor
   * but the round-off of t, once per (re)start: its 10 failures reach 1e-6 of that, and its
   * first failure sizes the step from the error estimate. The floor and h0 come back once IDA's
   * step has grown past hmin. Measured on that manipulator over 0.05 s (KLU): rtol 1e-8 1319
   * steps, 0.04 s of CPU; 1e-10 6780 steps, 0.15 s (before: IDA_ERR_FAIL at t = 0, KLU and
   * dense alike). */
  r->ys = N_VClone(yy);
  r->yps = N_VClone(yy);
  if (!r->ys || !r->yps) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory (N_Vector)");
    goto done;
  }
  N_VScale(1.0, yy, r->ys);
  N_VScale(1.0, yp, r->yps);
  r->retried = r->relaxed = 0;
  if (opt->max_step > 0) IDACHK(IDASetMaxStep(mem, opt->max_step));
  if (opt->ida.max_order > 0) IDACHK(IDASetMaxOrd(mem, opt->ida.max_order < 5 ? opt->ida.max_order : 5));
done:
  return st;
}

/* The linear solver, KLU or the dense LU, each with the closed-form Jacobian and wrapped by
 * ledger_wrap. */
static phm_status ida_linear_solver(ida_run *r, dae_t *d, const phm_sim_options *opt,
                                    SUNContext ctx, N_Vector yy, phm_error *err) {
  phm_status st = PHM_OK;
  void *mem = r->mem;
  SUNLinearSolver LS = NULL;
  if (opt->linear_solver == 1) {
    r->A = SUNSparseMatrix(d->n, d->n, d->nnz, CSC_MAT, ctx);
    if (!r->A) {
      st = PHM_FAIL(err, PHM_ENOMEM, "out of memory (sparse matrix)");
      goto done;
    }
    phm_sparse_matrix_ops(r->A);
    LS = r->LS = r->ud.klu = SUNLinSol_KLU(yy, r->A, ctx);
    /* The pruned pattern (ida_jac) needs safer pivoting than KLU's defaults gave the full block
     * pattern. No block triangular form: its maximum transversal may make a round-off entry
     * (1e-35 .. 1e-19, zero in exact arithmetic) the pivot of a 1 x 1 block, where partial
     * pivoting has no choice -- on the flexible slider-crank of tests/test_flexible_loop.py
     * KLU's rcond (min/max |U_kk|) fell to 1e-66 and IDA's corrector failed at h = 2e-11 s
     * (without BTF: 2e-15; the full pattern with BTF: 9e-13). And a diagonal pivot only within
     * 0.1 of its column's largest entry (KLU's default 0.001): with 0.001, or with AMD instead
     * of COLAMD, that slider-crank or the PD arm of tests/test_arm.py (rtol 1e-8: the
     * error-test failure at every step described at ida_atol, 58354 in 59949 steps) failed;
     * with 0.1 both pass as before, and the chain of 100 bodies costs 0.55 CPU s per simulated
     * s with 0.1, 0.51 with 0.001. The planar DAE (csrc/dae/planar.c) takes the largest entry
     * of the column (1.0) and AMD: with COLAMD and 0.1 that slider-crank, planar, failed again
     * at h = 2e-11 s (rtol 1e-8; with 1.0 at t = 0.164 s, with BTF too at 0.031 s), and its
     * ledger was 5.8e-7 at rtol 1e-6 (dense LU 9.3e-9); with AMD and 1.0 it runs, ledgers
     * 7.5e-9 (rtol 1e-8; 3-D 6.8e-10) and 5.2e-8 (1e-6; 3-D 2.7e-8). Measured 2026-11-27 on
     * that one scene. Why its pivots failed (found later): not KLU's doing, the iterate had
     * diverged before. mu grew without bound in the world-frame kinematic rows (the comment at the
     * dae_body_kinematics call above), and the matrix holds G^T mu's geometric stiffness, ~mu:
     * cond(J) 1e114-1e117 at |mu| ~ 1e77 before IDA_CONV_FAIL, against 1.2e13-1.9e13 along
     * runs without that growth (medians 7e4-9e4 with rows and columns equilibrated), while
     * sigma_min/sigma_max of G stayed 0.365 (no nearly redundant row). With the body-frame
     * rows that slider-crank reaches 0.3 s with every setting tried (lumped and consistent
     * masses, rtol 1e-6 and 1e-8, 3-D and planar DAE; KLU's defaults, 0.001 without BTF, COLAMD
     * or AMD with 0.1 or 1.0: 40 runs); the settings above stay for accuracy: with KLU's
     * defaults the lumped run's energy drift at rtol 1e-8 was 8.6e-9 (3-D) and 2.3e-8 (planar)
     * of its kinetic energy, against 2.5e-9 and 1.2e-9. */
    if (LS) {
      SUNLinSol_KLUGetCommon(LS)->btf = 0;
      if (d->pl) SUNLinSol_KLUGetCommon(LS)->ordering = 0; /* AMD */
      SUNLinSol_KLUGetCommon(LS)->tol = d->pl ? 1.0 : 0.1;
    }
  } else {
    r->A = SUNDenseMatrix(d->n, d->n, ctx);
    r->ud.js = SUNSparseMatrix(d->n, d->n, d->nnz, CSC_MAT, ctx); /* never zeroed: dae_jacobian fills it */
    if (!r->A || !r->ud.js) {
      st = PHM_FAIL(err, PHM_ENOMEM, "out of memory (dense matrix)");
      goto done;
    }
    LS = r->LS = SUNLinSol_Dense(yy, r->A, ctx);
  }
  if (!LS) {
    st = PHM_FAIL(err, PHM_ESOLVER, "could not create the linear solver");
    goto done;
  }
  r->ud.inner = LS;
  r->ud.dP = N_VClone(yy);
  if (!r->ud.dP || !(r->W = ledger_wrap(&r->ud, ctx))) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory (linear solver)");
    goto done;
  }
  IDACHK(IDASetLinearSolver(mem, r->W, r->A));
  IDACHK(IDASetJacFn(mem, opt->linear_solver == 1 ? ida_jac : ida_jac_dense));
done:
  return st;
}

/* Integrate from *t to the output time target, restarting at the laws' breakpoints (*nbp: the
 * next) and calling the monitor every PHM_MONITOR_STEPS steps. */
static phm_status ida_interval(ida_run *r, dae_t *d, const phm_sim_options *opt, N_Vector yy,
                               N_Vector yp, double *tp, double target, double *nbp,
                               phm_sim_output *out, phm_error *err) {
  phm_status st = PHM_OK;
  void *mem = r->mem;
  const double hmin = r->hmin, h0 = r->h0;
  double t = *tp, *y = N_VGetArrayPointer(yy), *ypd = N_VGetArrayPointer(yp);
  long chunks = 0;
  while (t < target) {
    if (isfinite(*nbp)) IDACHK(IDASetStopTime(mem, *nbp));
    double tret = t;
    int flag = IDASolve(mem, target, &tret, yy, yp, IDA_NORMAL);
    long ns0 = -1;
    if (flag == IDA_ERR_FAIL && IDAGetNumSteps(mem, &ns0) == 0 && ns0 == 0 && !r->retried) {
      double hf = 0;
      IDAGetCurrentStep(mem, &hf);
      add_stats(mem, out); /* IDAReInit zeroes IDA's counters */
      N_VScale(1.0, r->ys, yy);
      N_VScale(1.0, r->yps, yp);
      IDACHK(IDASetInitStep(mem, 0.25 * hf));
      IDACHK(IDASetMinStep(mem, 16 * DBL_EPSILON * fabs(t)));
      IDACHK(IDAReInit(mem, t, yy, yp));
      r->retried = r->relaxed = 1;
      continue;
    }
    if (r->relaxed) {
      double hc = 0;
      if (IDAGetCurrentStep(mem, &hc) == 0 && fabs(hc) >= hmin) {
        IDACHK(IDASetMinStep(mem, hmin));
        IDACHK(IDASetInitStep(mem, h0));
        r->relaxed = 0;
      }
    }
    if (flag == IDA_TOO_MUCH_WORK && opt->monitor && ++chunks * PHM_MONITOR_STEPS < r->max_steps) {
      long ns = 0;
      double hl = 0;
      IDAGetNumSteps(mem, &ns);
      IDAGetLastStep(mem, &hl);
      t = tret;
      if (opt->monitor(opt->ctx, t, out->nsteps + ns, hl)) {
        st = PHM_FAIL(err, PHM_EINTERRUPT, "interrupted at t = %g s", t);
        goto done;
      }
      continue;
    }
    if (flag < 0) {
      char *nm = IDAGetReturnFlagName(flag);
      st = PHM_FAIL(err, PHM_ESOLVER, "IDA failed with %s at t = %.9g s (%s)", nm ? nm : "?", tret, r->w->msg);
      free(nm);
      goto done;
    }
    t = tret;
    if (flag == IDA_TSTOP_RETURN) {
      /* breakpoint: new piece of the laws, re-initialize from consistent values */
      add_stats(mem, out);
      if ((st = dae_restart_at_breakpoint(d, t, t, nbp, y, ypd, err))) goto done;
      N_VScale(1.0, yy, r->ys);
      N_VScale(1.0, yp, r->yps);
      if (r->relaxed) {
        IDACHK(IDASetMinStep(mem, hmin));
        IDACHK(IDASetInitStep(mem, h0));
      }
      r->retried = r->relaxed = 0;
      IDACHK(IDAReInit(mem, t, yy, yp));
      /* an output within round-off after the breakpoint is the breakpoint's (outputs i dt put
       * simulate(0.3, 0.05)'s last at 0.30000000000000004: IDA refuses a tout that close) */
      if (t >= target - 16 * DBL_EPSILON * fabs(target)) t = target;
    }
  }
done:
  *tp = t;
  return st;
}

static void ida_free_run(ida_run *r, phm_sim_output *out) {
  if (r->mem) add_stats(r->mem, out);
  if (r->mem) IDAFree(&r->mem);
  if (r->W) SUNLinSolFree(r->W);
  if (r->ud.dP) N_VDestroy(r->ud.dP);
  if (r->LS) SUNLinSolFree(r->LS);
  if (r->A) SUNMatDestroy(r->A);
  if (r->ud.js) SUNMatDestroy(r->ud.js);
  if (r->id) N_VDestroy(r->id);
  if (r->ys) N_VDestroy(r->ys);
  if (r->yps) N_VDestroy(r->yps);
}

phm_status run_ida(dae_t *d, const phm_sim_options *opt, void *work, SUNContext ctx, N_Vector yy,
                   N_Vector yp, const double *tout, int nout, double E0[1], double nbp,
                   phm_sim_output *out, phm_error *err) {
  phm_status st = PHM_OK;
  ida_run r = {.ud = {d, NULL, NULL, NULL, 0.0, 0.0, NULL, NULL}, .w = work};
  int stop;
  double t = tout[0], *y = N_VGetArrayPointer(yy);
  /* The kinematic rows of the carriers that mu acts on in their body frames (dae_body_kinematics).
   * In the world frame mu enters p' = R (v + dv) and q' = 1/2 q (x) (0, w + dw) through R and q:
   * its columns of the Newton matrix turn with the carrier, and IDA keeps that matrix until
   * Newton fails or cj leaves 0.6 .. 1.67 times its value then, for hundreds of steps. mu's
   * exact value is 0 and its discrete values are Newton's leftovers, which BDF's predictor
   * extrapolates, amplifying an alternating sequence, and a matrix that has turned by dtheta
   * leaves ~dtheta of that prediction in mu. IDA accepts one-iteration corrections on a rate
   * estimate from the matrix's first steps, and mu's weight is loose (dae_state_atol), so
   * nothing stopped it. Measured on the flexible slider-crank of tests/test_flexible_loop.py
   * with consistent masses (N = 4, rtol 1e-6, order 5): the predictor put mu at 13-30x (median
   * 20) its last value; the fraction of that left after the step grew from 0.001 right after a
   * refresh to 0.15 6 ms later (1.3 times the angle the crank turned at 20 rad/s); past ~0.03
   * mu grew 1.2-2x per step with alternating sign (the crank pivot's f_x, f_y rows: 0.03 at
   * t = 24 ms, 2e9 at 25, 7e89 at 28.8), each step accepted after one iteration with
   * corrections of 1e6-4e7 tolerances, until IDA_CONV_FAIL at t = 28.9 ms, h = 4e-11 s (and so
   * for N = 3 .. 8 at rtol 1e-6 and 1e-8). With lumped masses, or with the dense solver, mu
   * swung the same way (median |mu| ~1 m/s, peaks 1e16 and 5e8) and recovered at the refreshes
   * that followed Newton failures. In the body frame mu's columns are -G^T, constant: its
   * correction is exact whatever the matrix's age, median |mu| 2e-6 .. 5e-6, max 2e-3, and the
   * consistent-mass runs pass (docs/integrators.md, "IDA and mu"). The cost is on the rotating
   * columns that remain, q' and p' (times cj): only the carriers that mu acts on take these
   * rows, the others keep the world frame's (all carriers: a free modal link's momentum,
   * tests/test_modal_link.py at rtol 1e-9, drifted 8.6e-12 instead of 2.9e-12), and the
   * constrained carriers' positions now keep Newton's leftovers (the slider-crank's max |g|
   * 5.4e-12 against 3.9e-14 at rtol 1e-8). The generalized-alpha keeps the world frame: its
   * predictor of the multipliers is linear and its first corrections are capped
   * (csrc/integrate/galpha.c), and in the body frame a quaternion's norm correction, large after
   * its second-order predictor, leaked into the rotation through the turned matrix (a
   * pendulum over 100 s: 9x the Jacobians, 7x the ledger). */
  dae_body_kinematics(d, 1);
  if ((st = ida_create(&r, d, opt, ctx, yy, yp, tout, nout, err)) ||
      (st = ida_linear_solver(&r, d, opt, ctx, yy, err)))
    goto done;
  for (int iout = 1; iout < nout; iout++) {
    if ((st = ida_interval(&r, d, opt, yy, yp, &t, tout[iout], &nbp, out, err))) goto done;
    if ((st = dae_step_accepted(d, t, y, fmax(DAE_CONSTRAINT_TOL, opt->rtol), opt->atol, 1, err))) goto done; /* IDA: at the outputs */
    if ((st = dae_emit_output(d, y, out, iout, E0, t, opt, &stop, err)) || stop) goto done;
  }
done:
  ida_free_run(&r, out);
  return st;
}
