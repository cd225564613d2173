/* statics.c -- static equilibrium: Newton on [df/ddelta G^T; G 0] with sparse LU (KLU), damped
 * steps and load stepping (halved on failure). */
#include "solve.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <klu.h>

#include "check.h"
#include "linalg.h"
#include "pose.h"

/* The static Newton matrix [df/ddelta  G^T; G  0] in compressed columns, with the source of every
 * entry (a force Jacobian block entry or a constraint Jacobian entry), factored by KLU: the force
 * blocks only couple neighbouring carriers and G only the carriers of each pair, so the cost per
 * iteration stays O(N) where a dense LU was O(N^3). */
typedef struct {
  int n, *Ap, *Ai, *src; /* src >= 0: Kb[src]; src < 0: Gp[-src - 1] (Gp: the pairs' blocks) */
  double *Ax;
  klu_symbolic *sym;
  klu_numeric *num;
  klu_common common;
} static_matrix_t;

static void static_matrix_free(static_matrix_t *S) {
  if (S->num) klu_free_numeric(&S->num, &S->common);
  if (S->sym) klu_free_symbolic(&S->sym, &S->common);
  free(S->Ap); free(S->Ai); free(S->src); free(S->Ax);
}

static int cmp_int(const void *a, const void *b) { return (*(const int *)a > *(const int *)b) - (*(const int *)a < *(const int *)b); }

static phm_status static_matrix_build(static_matrix_t *S, const lin_t *L, phm_error *err) {
  const phm_model *m = L->m;
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk;
  const int *ptr = L->ptr, *nbr = L->nbr;
  memset(S, 0, sizeof *S);
  klu_defaults(&S->common);
  S->n = N;
  /* entries: force blocks 36 per graph slot, G and G^T: 2 x 6 per row and carrier of its pair */
  size_t cap = 36 * (size_t)ptr[nc] + 12 * 2 * (size_t)nk + 1;
  S->Ap = malloc(sizeof(int) * (size_t)(N + 1));
  S->Ai = malloc(sizeof(int) * cap);
  S->src = malloc(sizeof(int) * cap);
  S->Ax = malloc(sizeof(double) * cap);
  int *rows = malloc(sizeof(int) * (size_t)(ptr[nc] + 1));
  if (!S->Ap || !S->Ai || !S->src || !S->Ax || !rows) {
    free(rows);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
  int k = 0;
  for (int c = 0; c < nc; c++) {
    int deg = ptr[c + 1] - ptr[c];
    memcpy(rows, nbr + ptr[c], sizeof(int) * (size_t)deg); /* the graph is symmetric */
    qsort(rows, (size_t)deg, sizeof(int), cmp_int);
    for (int j = 0; j < 6; j++) {
      S->Ap[6 * c + j] = k;
      for (int t = 0; t < deg; t++) {
        int r = rows[t], q = ptr[r];
        while (nbr[q] != c) q++; /* block (row r, column c) in r's list */
        for (int i = 0; i < 6; i++) {
          S->Ai[k] = 6 * r + i;
          S->src[k++] = 36 * q + 6 * i + j;
        }
      }
      for (int ip = 0; ip < m->np; ip++) /* pairs in order: their rows ascend */
        if (m->pair[ip].a == c || m->pair[ip].b == c)
          for (int rr = 0; rr < m->pair_m[ip]; rr++) {
            int r = m->pair_row[ip] + rr;
            S->Ai[k] = n6 + r;
            S->src[k++] = -(12 * r + 6 * (m->pair[ip].b == c) + j) - 1;
          }
    }
  }
  for (int ip = 0; ip < m->np; ip++)
    for (int rr = 0; rr < m->pair_m[ip]; rr++) {
      int r = m->pair_row[ip] + rr, a = m->pair[ip].a, b = m->pair[ip].b;
      int lo = a < b ? a : b, hi = a < b ? b : a;
      S->Ap[n6 + r] = k;
      for (int side = 0; side < 2; side++) {
        int c = side ? hi : lo;
        if (c < 0) continue;
        for (int i = 0; i < 6; i++) {
          S->Ai[k] = 6 * c + i;
          S->src[k++] = -(12 * r + 6 * (b == c) + i) - 1;
        }
      }
    }
  S->Ap[N] = k;
  free(rows);
  S->sym = klu_analyze(N, S->Ap, S->Ai, &S->common);
  if (!S->sym) return PHM_FAIL(err, PHM_ESOLVER, "static equilibrium: KLU analysis failed (status %d)", S->common.status);
  return PHM_OK;
}

/* The pairs' constraint Jacobian blocks at poses H: row r of pair ip holds G_a in Gp[12 r ..] and
 * G_b in Gp[12 r + 6 ..] (O(N) storage and work; a dense G would be O(N^2)). */
static void constraint_blocks(const lin_t *L, const double *H, double *Gp) {
  const phm_model *m = L->m;
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    double Ga[6 * PHM_MAXCON], Gb[6 * PHM_MAXCON];
    phm_pair_eval(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                  NULL, L->time, L->tref, NULL, Ga, Gb, NULL);
    for (int rr = 0; rr < m->pair_m[ip]; rr++) {
      double *row = Gp + 12 * (m->pair_row[ip] + rr);
      memcpy(row, Ga + 6 * rr, 6 * sizeof(double));
      memcpy(row + 6, Gb + 6 * rr, 6 * sizeof(double));
    }
  }
}

/* Fill the values from Kb and Gp, factor (with fresh pivoting: the Newton matrix of a buckling
 * problem changes a lot) and solve in place; 0 on success, 1 if singular. */
static int static_matrix_solve(static_matrix_t *S, const double *Kb, const double *G, double *x) {
  for (int k = 0; k < S->Ap[S->n]; k++) S->Ax[k] = S->src[k] >= 0 ? Kb[S->src[k]] : G[-S->src[k] - 1];
  if (S->num) klu_free_numeric(&S->num, &S->common);
  S->num = klu_factor(S->Ap, S->Ai, S->Ax, S->sym, &S->common);
  if (!S->num || S->common.status != KLU_OK) return 1;
  return !klu_solve(S->sym, S->num, S->n, 1, x, &S->common);
}

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
static int newton(lin_t *L, static_matrix_t *S, double *H, double *lam, double tol, int maxit,
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
    if (nk) constraint_blocks(L, H, w->Gp);
    for (int i = 0; i < N; i++) R[i] = -R[i];
    if (static_matrix_solve(S, L->Kb, w->Gp, R)) break;
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
  phm_error_clear(err);
  if (!m || !poses_out) return PHM_FAIL(err, PHM_EINVAL, "phm_static: NULL argument");
  if (steps < 1) return PHM_FAIL(err, PHM_EINVAL, "load steps must be >= 1 (got %d)", steps);
  if (!(tol > 0)) return PHM_FAIL(err, PHM_EINVAL, "tolerance must be > 0 (got %g)", tol);
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk, it = 0;
  phm_status st = PHM_OK;
  lin_t L = {0};
  static_matrix_t S;
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
  if ((st = static_matrix_build(&S, &L, err))) goto done;
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
  static_matrix_free(&S);
  free(w.R); free(w.f1); free(w.f2); free(w.Gp);
  free(w.Hsave); free(w.lsave); free(lam);
  return st;
}
