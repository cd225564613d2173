/* statics.c -- static equilibrium: Newton on [df/ddelta G^T; G 0] with sparse LU (KLU), damped
 * to one radian (or one length scale) per iteration, with load stepping (halved on failure). */
#include "solve.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <klu.h>

#include "check.h"
#include "pose.h"

/* The static Newton matrix [df/ddelta  G^T; G  0] in compressed columns, with the source of every
 * entry (a force Jacobian block entry or a constraint Jacobian entry), factored by KLU: the force
 * blocks only couple neighbouring carriers and G only the carriers of each pair, so the cost per
 * iteration stays O(N) where a dense LU was O(N^3). */
typedef struct {
  int n, *Ap, *Ai, *src; /* src >= 0: Kb[src]; src < 0: G[-src - 1] (G nk x n6, row-major) */
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
            S->src[k++] = -(r * n6 + 6 * c + j) - 1;
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
          S->src[k++] = -(r * n6 + 6 * c + i) - 1;
        }
      }
    }
  S->Ap[N] = k;
  free(rows);
  S->sym = klu_analyze(N, S->Ap, S->Ai, &S->common);
  if (!S->sym) return PHM_FAIL(err, PHM_ESOLVER, "static equilibrium: KLU analysis failed (status %d)", S->common.status);
  return PHM_OK;
}

/* Fill the values from Kb and G, factor (with fresh pivoting: the Newton matrix of a buckling
 * problem changes a lot) and solve in place; 0 on success, 1 if singular. */
static int static_matrix_solve(static_matrix_t *S, const double *Kb, const double *G, double *x) {
  for (int k = 0; k < S->Ap[S->n]; k++) S->Ax[k] = S->src[k] >= 0 ? Kb[S->src[k]] : G[-S->src[k] - 1];
  if (S->num) klu_free_numeric(&S->num, &S->common);
  S->num = klu_factor(S->Ap, S->Ai, S->Ax, S->sym, &S->common);
  if (!S->num || S->common.status != KLU_OK) return 1;
  return !klu_solve(S->sym, S->num, S->n, 1, x, &S->common);
}

/* One Newton solve at load scale L->scale from (H, lam); returns 0 on convergence (H and lam
 * updated), 1 on failure (H and lam restored). */
static int newton(lin_t *L, static_matrix_t *S, double *H, double *lam, double tol, int maxit,
                  double *R, double *f1, double *f2, double *Hsave, double *lsave, int *iters) {
  const phm_model *m = L->m;
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk;
  memcpy(Hsave, H, sizeof(double) * 16 * (size_t)nc);
  if (nk) memcpy(lsave, lam, sizeof(double) * (size_t)nk);
  L->lam = lam;
  double sprev = INFINITY;
  for (int it = 0; it < maxit; it++) {
    (*iters)++;
    /* residual */
    lin_total_force(L, H, R);
    if (nk) phm_constraints_dense(m, H, NULL, L->time, L->tref, R + n6, NULL, NULL);
    /* Jacobian: force blocks by coloured differences (O(N) force evaluations per iteration
     * instead of O(N^2) column by column), constraint rows dg/ddelta = G, multiplier columns G^T;
     * sparse LU (KLU) */
    lin_force_jacobian_blocks(L, H, f1, f2);
    if (nk) phm_constraints_dense(m, H, NULL, L->time, L->tref, NULL, L->G, NULL);
    for (int i = 0; i < N; i++) R[i] = -R[i];
    if (static_matrix_solve(S, L->Kb, L->G, R)) break;
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
  memcpy(H, Hsave, sizeof(double) * 16 * (size_t)nc);
  if (nk) memcpy(lam, lsave, sizeof(double) * (size_t)nk);
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
  double *R = malloc(sizeof(double) * (size_t)N);
  double *f1 = malloc(sizeof(double) * (size_t)n6), *f2 = malloc(sizeof(double) * (size_t)n6);
  double *Hs = malloc(sizeof(double) * 16 * (size_t)nc), *ls = malloc(sizeof(double) * (size_t)(nk + 1));
  double *lam = calloc((size_t)(nk + 1), sizeof(double));
  if (!R || !f1 || !f2 || !Hs || !ls || !lam) {
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
  int pre_failed = newton(&L, &S, poses_out, lam, tol, 50, R, f1, f2, Hs, ls, &it);
  double s = 0, ds = 1.0 / steps;
  while (s < 1.0) {
    double snew = fmin(1.0, s + ds);
    L.scale = snew;
    if (newton(&L, &S, poses_out, lam, tol, 30, R, f1, f2, Hs, ls, &it)) {
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
  free(R); free(f1); free(f2);
  free(Hs); free(ls); free(lam);
  return st;
}
