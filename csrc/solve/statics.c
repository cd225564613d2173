/* statics.c -- static equilibrium: Newton on [df/ddelta G^T; G 0] with sparse LU (KLU) and
 * load stepping (halved on failure, grown back after fast convergence). */
#include "solve.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"
#include "pose.h"

/* The static residual at poses H and multipliers L->lam: forces f (6 nc, applied x scale +
 * G^T lambda), then the constraints g (nk). */
static void static_residual(lin_t *L, const double *H, double *R) {
  const phm_model *m = L->m;
  lin_total_force(L, H, R);
  if (m->ncons) phm_constraints_dense(m, H, NULL, L->time, L->tref, R + 6 * m->nc, NULL, NULL);
}

/* Work arrays of one Newton solve (allocated once by phm_static). */
typedef struct {
  double *R, *Gp, *Hsave, *lsave, *bar;
} static_work_t;

/* The size of a step x (6 nc carrier components, then nk multipliers): its largest rotation
 * (rad) and translation in units of the element length lref; *rot: the largest rotation. */
static double step_size(const phm_model *m, const double *x, double *rot) {
  double sn = 0, sr = 0;
  for (int c = 0; c < m->nc; c++)
    for (int j = 0; j < 6; j++) {
      double a = fabs(x[6 * c + j]);
      sn = fmax(sn, j < 3 ? a : a / m->lref);
      if (j < 3) sr = fmax(sr, a);
    }
  if (rot) *rot = sr;
  return sn;
}

/* (H, lam) <- (H exp(a x), lam + a x) for the carriers' and multipliers' parts of x. */
static void take_step(const phm_model *m, double *H, double *lam, const double *x, double a) {
  for (int c = 0; c < m->nc; c++) {
    double d[6];
    for (int j = 0; j < 6; j++) d[j] = a * x[6 * c + j];
    phm_retract(H + 16 * c, d);
  }
  for (int i = 0; i < m->ncons; i++) lam[i] += a * x[6 * m->nc + i];
}

/* Newton from (H, lam) at the load scale L->scale; 0 on convergence (H, lam updated), 1 on
 * failure (H, lam restored). Each iteration: the tangent [K G^T; G 0] (in closed form,
 * csrc/solve/linearize.c) solved by KLU, the step
 * scaled down to at most 1 rad of rotation, then the simplified Newton correction at the new
 * iterate (the same factorization, one more residual and solve): converged when it is below tol
 * (rad, and lengths in units of the element length lref; it is then applied), or when it stalls
 * at round-off below 1e3 tol. Failure (non-finite steps, maxit iterations) lets the caller cut
 * the load step.
 * Measured (benchmarks/statics_newton.py, iterations = tangents): with the finite-difference
 * tangent the steps were also capped at one element length lref, and the count grew with N (a
 * cantilever under P L^2/EI = 3 in 10 load steps: 54 iterations at N = 20, 858 at N = 1000; the
 * stiff roll-up 2344). With the exact tangent and without the length cap: 41 and 42, stiff
 * roll-up 1158 (doubling the load step beyond 1/steps after fast convergence gave 22 and 24, but
 * jumped past the bifurcation of the imperfect elastica of tests/hard/test_hard_statics.py). A line search by the natural monotonicity test (Deuflhard 2004, section 3.3) on
 * top halved the soft cases' counts no further and quadrupled the stiff ones' (the simplified
 * correction of a stiff beam's stretched trial state is huge); a secant predictor on every
 * carrier's pose cost the roll-up 40 % more. */
static int newton(lin_t *L, lin_kkt_t *S, double *H, double *lam, double tol, int maxit,
                  static_work_t *w, int *iters) {
  const phm_model *m = L->m;
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk;
  double *R = w->R;
  memcpy(w->Hsave, H, sizeof(double) * 16 * (size_t)nc);
  if (nk) memcpy(w->lsave, lam, sizeof(double) * (size_t)nk);
  L->lam = lam;
  static_residual(L, H, R);
  double sprev = INFINITY;
  for (int it = 0; it < maxit; it++) {
    (*iters)++;
    lin_force_jacobian_blocks(L, H);
    if (nk) lin_constraint_blocks(L, H, w->Gp);
    for (int i = 0; i < N; i++) R[i] = -R[i];
    if (lin_kkt_factor(S, L->Kb, w->Gp) || lin_kkt_solve(S, R)) break;
    double rot, sn = step_size(m, R, &rot);
    if (!isfinite(sn)) break; /* diverging: let the caller cut the load step */
    double a = rot > 1.0 ? 1.0 / rot : 1.0;
    take_step(m, H, lam, R, a);
    if (sn < tol) return 0;
    static_residual(L, H, R);
    for (int i = 0; i < N; i++) w->bar[i] = -R[i];
    if (lin_kkt_solve(S, w->bar)) break;
    double sbar = step_size(m, w->bar, NULL);
    if (!isfinite(sbar)) break;
    if (sbar < tol || (sbar < 1e3 * tol && sbar > 0.25 * sprev)) {
      take_step(m, H, lam, w->bar, 1.0);
      return 0;
    }
    sprev = a * sn;
  }
  memcpy(H, w->Hsave, sizeof(double) * 16 * (size_t)nc);
  if (nk) memcpy(lam, w->lsave, sizeof(double) * (size_t)nk);
  return 1;
}

/* Pseudo-transient continuation at the load scale L->scale from (H, lam), for where Newton's
 * tangent is singular or misleading (a pendulum started horizontal: gravity has no stiffness
 * there, and Newton's step is infinite): Newton on an implicit Euler step of the overdamped
 * motion M d(delta)/dtau = f, i.e. [df/ddelta - M/dtau, G^T; G, 0] x = -R, with the pseudo time
 * step dtau grown as the residual falls (switched evolution relaxation: dtau *= |R_prev| / |R|,
 * at most x10 per step). Far from equilibrium it moves downhill, near it it is Newton, so it
 * ends at a stable equilibrium as a rule: after each step that moved less than 1e-2 (rad, element
 * lengths) newton() is tried from there. 0 on convergence, 1 on failure (H, lam restored). */
static int ptc(lin_t *L, lin_kkt_t *S, double *H, double *lam, double tol, int maxit,
               static_work_t *w, int *iters) {
  const phm_model *m = L->m;
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk;
  const int *ptr = L->ptr, *nbr = L->nbr;
  double *R = w->R;
  memcpy(w->Hsave, H, sizeof(double) * 16 * (size_t)nc);
  if (nk) memcpy(w->lsave, lam, sizeof(double) * (size_t)nk);
  L->lam = lam;
  double trM = 0;
  for (int c = 0; c < nc; c++)
    for (int i = 0; i < 6; i++) trM += m->car[c].M[7 * i];
  double dtau = 0, rn = 0;
  static_residual(L, H, R);
  for (int i = 0; i < N; i++) rn += R[i] * R[i];
  rn = sqrt(rn);
  for (int it = 0; it < maxit && isfinite(rn); it++) {
    (*iters)++;
    lin_force_jacobian_blocks(L, H);
    if (nk) lin_constraint_blocks(L, H, w->Gp);
    if (it == 0) { /* the first step: the inertia term 100 times the stiffness */
      double trK = 0;
      for (int r = 0; r < nc; r++)
        for (int q = ptr[r]; q < ptr[r + 1]; q++)
          if (nbr[q] == r)
            for (int i = 0; i < 6; i++) trK += fabs(L->Kb[36 * (size_t)q + 7 * i]);
      dtau = trK > 0 && trM > 0 ? 1e-2 * trM / trK : 1e-2;
    }
    for (int r = 0; r < nc; r++)
      for (int q = ptr[r]; q < ptr[r + 1]; q++)
        if (nbr[q] == r)
          for (int i = 0; i < 36; i++) L->Kb[36 * (size_t)q + i] -= m->car[r].M[i] / dtau;
    for (int i = 0; i < N; i++) R[i] = -R[i];
    if (lin_kkt_factor(S, L->Kb, w->Gp) || lin_kkt_solve(S, R)) {
      dtau *= 0.1;
      static_residual(L, H, R);
      continue;
    }
    double rot, sn = step_size(m, R, &rot);
    if (!isfinite(sn)) break;
    take_step(m, H, lam, R, rot > 1.0 ? 1.0 / rot : 1.0);
    static_residual(L, H, R);
    double rnew = 0;
    for (int i = 0; i < N; i++) rnew += R[i] * R[i];
    rnew = sqrt(rnew);
    if (!isfinite(rnew)) break;
    /* switched evolution relaxation, growing at least x2 (x10 while the steps are tiny) while
     * the residual does not grow: a pendulum's torque hardly changes over its first small
     * steps, and SER alone stalls there */
    dtau *= rnew > rn ? 0.5 : fmin(10.0, fmax(sn < 1e-4 ? 10.0 : 2.0, rnew > 0 ? rn / rnew : 10.0));
    rn = rnew;
    /* near an equilibrium: Newton (which restores the state when it fails) */
    if (sn < 1e-2 && !newton(L, S, H, lam, tol, 8, w, iters)) return 0;
  }
  memcpy(H, w->Hsave, sizeof(double) * 16 * (size_t)nc);
  if (nk) memcpy(lam, w->lsave, sizeof(double) * (size_t)nk);
  return 1;
}

phm_status phm_static(const phm_model *m, const double *poses, double time, int steps, double tol,
                      double *poses_out, double *lambda_out, int *iters, phm_error *err) {
  return phm_static_monitored(m, poses, time, steps, tol, NULL, NULL, poses_out, lambda_out, iters,
                              NULL, err);
}

phm_status phm_static_monitored(const phm_model *m, const double *poses, double time, int steps,
                                double tol, phm_monitor monitor, void *ctx, double *poses_out,
                                double *lambda_out, int *iters, double *reached, phm_error *err) {
  phm_error_clear(err);
  if (!m || !poses_out) return PHM_FAIL(err, PHM_EINVAL, "phm_static: NULL argument");
  if (steps < 1) return PHM_FAIL(err, PHM_EINVAL, "load steps must be >= 1 (got %d)", steps);
  if (!(tol > 0)) return PHM_FAIL(err, PHM_EINVAL, "tolerance must be > 0 (got %g)", tol);
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk, it = 0;
  double s = 0; /* the load factor reached */
  phm_status st = PHM_OK;
  lin_t L = {0};
  lin_kkt_t S;
  memset(&S, 0, sizeof S);
  static_work_t w = {
      .R = malloc(sizeof(double) * (size_t)N),
      .Gp = malloc(sizeof(double) * 12 * (size_t)(nk + 1)),
      .Hsave = malloc(sizeof(double) * 16 * (size_t)nc), .lsave = malloc(sizeof(double) * (size_t)(nk + 1)),
      .bar = malloc(sizeof(double) * (size_t)N)};
  double *lam = calloc((size_t)(nk + 1), sizeof(double));
  if (!w.R || !w.Gp || !w.Hsave || !w.lsave || !w.bar || !lam) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  if ((st = lin_alloc(&L, m, err)) || (st = lin_graph(&L, err))) goto done;
  if ((st = lin_kkt_build(&S, &L, err))) goto done;
  L.time = time;
  L.tref = phm_model_tref(m, time, NULL);
  for (int c = 0; c < nc; c++) memcpy(poses_out + 16 * c, poses ? poses + 16 * c : m->car[c].H0, 16 * sizeof(double));
  /* meet the constraints without load first */
  L.scale = 0.0;
  /* (a mechanism with a free degree of freedom is singular without load: then go on directly) */
  int pre_failed = newton(&L, &S, poses_out, lam, tol, 50, &w, &it);
  /* load stepping from the unloaded equilibrium: a step is halved when Newton fails to converge
   * in 12 iterations (with the exact tangent, one that has not converged by then rarely does; 30
   * cost the stiff roll-up of benchmarks/statics_newton.py 1501 iterations instead of 1158) and
   * doubled after one that took at most 4, up to 1/steps: `steps` bounds the increment (a larger
   * one can pass a bifurcation unseen) */
  double ds = 1.0 / steps;
  while (s < 1.0) {
    double snew = fmin(1.0, s + ds);
    L.scale = snew;
    int it0 = it;
    if (newton(&L, &S, poses_out, lam, tol, 12, &w, &it)) {
      ds *= 0.5;
      if (ds < 1e-4 / steps) {
        /* Newton cannot take even a tiny load step: its tangent is singular or misleading here
         * (a mechanism away from any equilibrium); pseudo-transient continuation instead */
        if (!ptc(&L, &S, poses_out, lam, tol, 500, &w, &it)) {
          s = snew;
          ds = 1.0 / steps;
          continue;
        }
        st = PHM_FAIL(err, PHM_ESOLVER, "static equilibrium: Newton failed at load factor %.6g after step halving, and pseudo-transient continuation too (%d iterations)%s", snew, it,
                           pre_failed ? "; it also failed without load (unconstrained rigid-body motion or incompatible constraints?)" : "");
        goto done;
      }
      continue;
    }
    s = snew;
    if (it - it0 <= 4) ds = fmin(2.0 * ds, 1.0 / steps);
    if (monitor && monitor(ctx, s, it, ds)) {
      st = PHM_FAIL(err, PHM_EINTERRUPT, "static equilibrium: stopped by the caller at load factor %.6g", s);
      goto done;
    }
  }
  if (!phm_all_finite(poses_out, 16 * (size_t)nc) || !phm_all_finite(lam, (size_t)nk)) {
    st = PHM_FAIL(err, PHM_ESOLVER, "static equilibrium: non-finite poses or constraint "
                       "wrenches: the model's numbers overflow double precision");
    goto done;
  }
done:
  /* also after a failure: the last converged state, at load factor *reached */
  if (lam && lambda_out && nk) memcpy(lambda_out, lam, sizeof(double) * (size_t)nk);
  if (reached) *reached = s;
  if (iters) *iters = it;
  lin_free(&L);
  lin_kkt_free(&S);
  free(w.R); free(w.Gp);
  free(w.Hsave); free(w.lsave); free(w.bar); free(lam);
  return st;
}
