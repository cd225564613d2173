/* statics.c -- static equilibrium: Newton on [df/ddelta G^T; G 0] with sparse LU (KLU), damped
 * steps and load stepping (halved on failure). */
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
  double *R, *f1, *f2, *Gp, *Hsave, *lsave;
} static_work_t;

/* Newton from (H, lam) at the load scale L->scale; 0 on convergence (H, lam updated), 1 on
 * failure (H, lam restored). Each iteration: the tangent [K G^T; G 0] (force blocks by coloured
 * differences, O(N) force evaluations, csrc/solve/linearize.c) solved by KLU; a step larger than
 * 1 rad or one element length lref is scaled down to that size. Converged when the step is below
 * tol (rad, and lengths in units of lref), or when it stalls at round-off below 1e3 tol.
 * Measured (benchmarks/statics_newton.py): because lref is the element length, the iteration
 * count grows with N (a cantilever under P L^2/EI = 3 in 10 load steps: 54 iterations at N = 20,
 * 858 at N = 1000); capping the rotations only makes it N-independent there (51 and 52) but made
 * the Fig. 3 manipulator's static Newton, which wanders for tens of iterations at any cap
 * (finite-difference tangent), take 1461 iterations instead of 113 in 20 load steps; a line
 * search on the residual norm was worse still. Kept until the analytic tangent lands. */
static int newton(lin_t *L, lin_kkt_t *S, double *H, double *lam, double tol, int maxit,
                  static_work_t *w, int *iters) {
  const phm_model *m = L->m;
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk;
  double *R = w->R;
  memcpy(w->Hsave, H, sizeof(double) * 16 * (size_t)nc);
  if (nk) memcpy(w->lsave, lam, sizeof(double) * (size_t)nk);
  L->lam = lam;
  double sprev = INFINITY;
  for (int it = 0; it < maxit; it++) {
    (*iters)++;
    static_residual(L, H, R);
    lin_force_jacobian_blocks(L, H, w->f1, w->f2);
    if (nk) lin_constraint_blocks(L, H, w->Gp);
    for (int i = 0; i < N; i++) R[i] = -R[i];
    if (lin_kkt_factor(S, L->Kb, w->Gp) || lin_kkt_solve(S, R)) break;
    double sn = 0;
    for (int c = 0; c < nc; c++)
      for (int j = 0; j < 6; j++) sn = fmax(sn, fabs(R[6 * c + j]) / (j < 3 ? 1.0 : m->lref));
    if (!isfinite(sn)) break; /* diverging: let the caller cut the load step */
    if (sn > 1.0) /* damped step: at most 1 rad (or 1 length scale) per iteration */
      for (int i = 0; i < N; i++) R[i] /= sn;
    for (int c = 0; c < nc; c++) phm_retract(H + 16 * c, R + 6 * c);
    for (int i = 0; i < nk; i++) lam[i] += R[n6 + i];
    if (sn < tol) return 0;
    /* round-off floor (stiff sections): the step stopped shrinking at a tiny size */
    if (sn < 1e3 * tol && sn > 0.25 * sprev) return 0;
    sprev = sn;
  }
  memcpy(H, w->Hsave, sizeof(double) * 16 * (size_t)nc);
  if (nk) memcpy(lam, w->lsave, sizeof(double) * (size_t)nk);
  return 1;
}

phm_status phm_static(const phm_model *m, const double *poses, double time, int steps, double tol,
                      double *poses_out, double *lambda_out, int *iters, phm_error *err) {
  return phm_static_monitored(m, poses, time, steps, tol, NULL, NULL, poses_out, lambda_out, iters,
                              err);
}

phm_status phm_static_monitored(const phm_model *m, const double *poses, double time, int steps,
                                double tol, phm_monitor monitor, void *ctx, double *poses_out,
                                double *lambda_out, int *iters, phm_error *err) {
  phm_error_clear(err);
  if (!m || !poses_out) return PHM_FAIL(err, PHM_EINVAL, "phm_static: NULL argument");
  if (steps < 1) return PHM_FAIL(err, PHM_EINVAL, "load steps must be >= 1 (got %d)", steps);
  if (!(tol > 0)) return PHM_FAIL(err, PHM_EINVAL, "tolerance must be > 0 (got %g)", tol);
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk, it = 0;
  phm_status st = PHM_OK;
  lin_t L = {0};
  lin_kkt_t S;
  memset(&S, 0, sizeof S);
  static_work_t w = {
      .R = malloc(sizeof(double) * (size_t)N),
      .f1 = malloc(sizeof(double) * (size_t)n6), .f2 = malloc(sizeof(double) * (size_t)n6),
      .Gp = malloc(sizeof(double) * 12 * (size_t)(nk + 1)),
      .Hsave = malloc(sizeof(double) * 16 * (size_t)nc), .lsave = malloc(sizeof(double) * (size_t)(nk + 1))};
  double *lam = calloc((size_t)(nk + 1), sizeof(double));
  if (!w.R || !w.f1 || !w.f2 || !w.Gp || !w.Hsave || !w.lsave || !lam) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  if ((st = lin_alloc(&L, m, err)) || (st = lin_colour(&L, err))) goto done;
  if ((st = lin_kkt_build(&S, &L, err))) goto done;
  L.time = time;
  L.tref = phm_model_tref(m, time, NULL);
  for (int c = 0; c < nc; c++) memcpy(poses_out + 16 * c, poses ? poses + 16 * c : m->car[c].H0, 16 * sizeof(double));
  /* meet the constraints without load first */
  L.scale = 0.0;
  /* (a mechanism with a free degree of freedom is singular without load: then go on directly) */
  int pre_failed = newton(&L, &S, poses_out, lam, tol, 50, &w, &it);
  double s = 0, ds = 1.0 / steps;
  while (s < 1.0) {
    double snew = fmin(1.0, s + ds);
    L.scale = snew;
    if (newton(&L, &S, poses_out, lam, tol, 30, &w, &it)) {
      ds *= 0.5;
      if (ds < 1e-4 / steps) {
        st = PHM_FAIL(err, PHM_ESOLVER, "static equilibrium: Newton failed at load factor %.6g after step halving (%d iterations)%s", snew, it,
                           pre_failed ? "; it also failed without load (unconstrained rigid-body motion or incompatible constraints?)" : "");
        goto done;
      }
      continue;
    }
    s = snew;
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
  if (lambda_out && nk) memcpy(lambda_out, lam, sizeof(double) * (size_t)nk);
done:
  if (iters) *iters = it;
  lin_free(&L);
  lin_kkt_free(&S);
  free(w.R); free(w.f1); free(w.f2); free(w.Gp);
  free(w.Hsave); free(w.lsave); free(lam);
  return st;
}
