/* linearize.c -- linearization on the tangent space, modes (DESIGN section 7) and static
 * equilibrium by Newton's method with load stepping. Dense LAPACK throughout (set-up time code). */
#include "model_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

extern void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n, double *a,
                    const int *lda, double *s, double *u, const int *ldu, double *vt,
                    const int *ldvt, double *work, const int *lwork, int *info);
extern void dsygv_(const int *itype, const char *jobz, const char *uplo, const int *n, double *a,
                   const int *lda, double *b, const int *ldb, double *w, double *work,
                   const int *lwork, int *info);
extern void dgesv_(const int *n, const int *nrhs, double *a, const int *lda, int *ipiv, double *b,
                   const int *ldb, int *info);

typedef struct {
  const phm_model *m;
  double time, tref, scale;
  const double *lam; /* constraint wrenches added to the forces (may be NULL) */
  double *wr, *gl, *G, *Hp;
} lin_t;

/* Generalized forces at poses H: applied wrenches + G^T lambda (nc x 6, body frame). */
static void total_force(lin_t *L, const double *H, double *f) {
  const phm_model *m = L->m;
  phm_applied(m, H, NULL, NULL, L->time, L->tref, L->scale, f, NULL, NULL, NULL, NULL, NULL);
  if (L->lam && m->ncons) {
    int n6 = 6 * m->nc;
    phm_constraints_dense(m, H, NULL, L->time, L->tref, NULL, L->G, NULL);
    for (int r = 0; r < m->ncons; r++)
      for (int j = 0; j < n6; j++) f[j] += L->G[(size_t)r * n6 + j] * L->lam[r];
  }
}

/* Column (c, j) of d f / d delta by central differences on carrier c's chart, with the map
 * f_c(delta) = dexp_{-delta}^T w_c(H_c exp(delta)); also d g / d delta if dg != NULL. */
static void force_column(lin_t *L, const double *H, int c, int j, double *col, double *dg,
                         double *f1, double *f2, double *g1, double *g2) {
  const phm_model *m = L->m;
  int nc = m->nc, n6 = 6 * nc;
  double eps = 1e-6 * (j < 3 ? 1.0 : m->lref);
  for (int side = 0; side < 2; side++) {
    double dl[6] = {0}, D[36], *f = side ? f2 : f1;
    dl[j] = side ? -eps : eps;
    memcpy(L->Hp, H, sizeof(double) * 16 * (size_t)nc);
    phm_retract(L->Hp + 16 * c, dl);
    total_force(L, L->Hp, f);
    double md[6];
    for (int i = 0; i < 6; i++) md[i] = -dl[i];
    phm_se3_dexp(md, D);
    double w[6];
    for (int i = 0; i < 6; i++) {
      double s = 0;
      for (int k = 0; k < 6; k++) s += D[6 * k + i] * f[6 * c + k];
      w[i] = s;
    }
    memcpy(f + 6 * c, w, sizeof w);
    if (dg) phm_constraints_dense(m, L->Hp, NULL, L->time, L->tref, side ? g2 : g1, NULL, NULL);
  }
  for (int i = 0; i < n6; i++) col[i] = (f1[i] - f2[i]) / (2 * eps);
  if (dg)
    for (int i = 0; i < m->ncons; i++) dg[i] = (g1[i] - g2[i]) / (2 * eps);
}

static phm_status lin_alloc(lin_t *L, const phm_model *m, phm_error *err) {
  int n6 = 6 * m->nc;
  L->m = m;
  L->wr = malloc(sizeof(double) * (size_t)n6);
  L->gl = malloc(sizeof(double) * (size_t)n6);
  L->G = malloc(sizeof(double) * ((size_t)m->ncons * n6 + 1));
  L->Hp = malloc(sizeof(double) * 16 * (size_t)m->nc);
  if (!L->wr || !L->gl || !L->G || !L->Hp) return phm_error_set(err, PHM_ENOMEM, "out of memory");
  return PHM_OK;
}
static void lin_free(lin_t *L) {
  free(L->wr);
  free(L->gl);
  free(L->G);
  free(L->Hp);
}

/* ---------------------------------------------------------------- modes */
phm_status phm_modes(const phm_model *m, const double *poses, const double *lambda, double time,
                     int nmodes, double *omega, double *zeta, double *shapes, int *nfound,
                     phm_error *err) {
  phm_error_clear(err);
  if (!m || !omega || !nfound) return phm_error_set(err, PHM_EINVAL, "phm_modes: NULL argument");
  if (nmodes < 1) return phm_error_set(err, PHM_EINVAL, "number of modes must be >= 1 (got %d)", nmodes);
  *nfound = 0;
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons;
  phm_status st = PHM_OK;
  lin_t L = {0};
  double *H = malloc(sizeof(double) * 16 * (size_t)nc);
  double *K = malloc(sizeof(double) * (size_t)n6 * n6), *Dm = malloc(sizeof(double) * (size_t)n6 * n6);
  double *f1 = malloc(sizeof(double) * (size_t)n6), *f2 = malloc(sizeof(double) * (size_t)n6);
  double *col = malloc(sizeof(double) * (size_t)n6), *tw = calloc((size_t)n6, sizeof(double));
  double *Z = NULL, *Kr = NULL, *Mr = NULL, *Dr = NULL, *T = NULL, *ev = NULL, *work = NULL, *U = NULL, *sv = NULL;
  if (!H || !K || !Dm || !f1 || !f2 || !col || !tw) {
    st = phm_error_set(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  if ((st = lin_alloc(&L, m, err))) goto done;
  L.time = time;
  L.tref = phm_model_tref(m, time, NULL);
  L.scale = 1.0;
  L.lam = lambda;
  for (int c = 0; c < nc; c++) memcpy(H + 16 * c, poses ? poses + 16 * c : m->car[c].H0, 16 * sizeof(double));
  /* stiffness K = -df/ddelta (symmetrized) */
  for (int c = 0; c < nc; c++)
    for (int j = 0; j < 6; j++) {
      force_column(&L, H, c, j, col, NULL, f1, f2, NULL, NULL);
      for (int i = 0; i < n6; i++) K[(size_t)i * n6 + 6 * c + j] = -col[i];
    }
  for (int i = 0; i < n6; i++)
    for (int j = 0; j < i; j++) {
      double s = 0.5 * (K[(size_t)i * n6 + j] + K[(size_t)j * n6 + i]);
      K[(size_t)i * n6 + j] = K[(size_t)j * n6 + i] = s;
    }
  /* damping D = -dw/dt (linear in t: one-sided differences are exact up to round-off) */
  phm_applied(m, H, tw, NULL, time, L.tref, 1.0, f1, NULL, NULL, NULL, NULL, NULL);
  for (int k = 0; k < n6; k++) {
    tw[k] = 1.0;
    phm_applied(m, H, tw, NULL, time, L.tref, 1.0, f2, NULL, NULL, NULL, NULL, NULL);
    tw[k] = 0.0;
    for (int i = 0; i < n6; i++) Dm[(size_t)i * n6 + k] = -(f2[i] - f1[i]);
  }
  /* null space of G */
  int nr = n6, rank = 0;
  if (nk > 0) {
    phm_constraints_dense(m, H, NULL, time, L.tref, NULL, L.G, NULL);
    U = malloc(sizeof(double) * (size_t)n6 * n6);
    sv = malloc(sizeof(double) * (size_t)(nk < n6 ? nk : n6) + sizeof(double));
    T = malloc(sizeof(double) * (size_t)nk * n6);
    if (!U || !sv || !T) {
      st = phm_error_set(err, PHM_ENOMEM, "out of memory");
      goto done;
    }
    memcpy(T, L.G, sizeof(double) * (size_t)nk * n6); /* column-major G^T, n6 x nk */
    int lw = -1, info = 0, one = 1;
    double wq;
    dgesvd_("A", "N", &n6, &nk, T, &n6, sv, U, &n6, NULL, &one, &wq, &lw, &info);
    lw = (int)wq + 1;
    work = malloc(sizeof(double) * (size_t)lw);
    if (!work) {
      st = phm_error_set(err, PHM_ENOMEM, "out of memory");
      goto done;
    }
    dgesvd_("A", "N", &n6, &nk, T, &n6, sv, U, &n6, NULL, &one, work, &lw, &info);
    free(work);
    work = NULL;
    if (info != 0) {
      st = phm_error_set(err, PHM_ESINGULAR, "SVD of the constraint Jacobian failed (dgesvd info %d)", info);
      goto done;
    }
    int ns = nk < n6 ? nk : n6;
    for (int i = 0; i < ns; i++)
      if (sv[i] > 1e-10 * sv[0]) rank++;
    nr = n6 - rank;
  }
  if (nr == 0) {
    st = phm_error_set(err, PHM_EINVAL, "the mechanism has no degree of freedom: no modes");
    goto done;
  }
  Z = malloc(sizeof(double) * (size_t)n6 * nr);
  Kr = malloc(sizeof(double) * (size_t)nr * nr);
  Mr = malloc(sizeof(double) * (size_t)nr * nr);
  Dr = malloc(sizeof(double) * (size_t)nr * nr);
  free(T);
  T = malloc(sizeof(double) * (size_t)n6 * nr);
  ev = malloc(sizeof(double) * (size_t)nr);
  if (!Z || !Kr || !Mr || !Dr || !T || !ev) {
    st = phm_error_set(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  for (int i = 0; i < n6; i++)
    for (int k = 0; k < nr; k++) Z[(size_t)i * nr + k] = nk > 0 ? U[(size_t)(rank + k) * n6 + i] : (i == k);
  /* reduced matrices: X_r = Z^T X Z */
  double *mats[3] = {K, NULL, Dm}, *outs[3] = {Kr, Mr, Dr};
  for (int w = 0; w < 3; w++) {
    for (int i = 0; i < n6; i++)
      for (int k = 0; k < nr; k++) {
        double s = 0;
        if (w == 1) {
          int c = i / 6, a = i % 6;
          for (int b = 0; b < 6; b++) s += m->car[c].M[6 * a + b] * Z[(size_t)(6 * c + b) * nr + k];
        } else {
          const double *Xi = mats[w] + (size_t)i * n6;
          for (int j = 0; j < n6; j++) s += Xi[j] * Z[(size_t)j * nr + k];
        }
        T[(size_t)i * nr + k] = s;
      }
    for (int a = 0; a < nr; a++)
      for (int b = 0; b < nr; b++) {
        double s = 0;
        for (int i = 0; i < n6; i++) s += Z[(size_t)i * nr + a] * T[(size_t)i * nr + b];
        outs[w][(size_t)a * nr + b] = s;
      }
    for (int a = 0; a < nr; a++)
      for (int b = 0; b < a; b++) {
        double s = 0.5 * (outs[w][(size_t)a * nr + b] + outs[w][(size_t)b * nr + a]);
        outs[w][(size_t)a * nr + b] = outs[w][(size_t)b * nr + a] = s;
      }
  }
  {
    int one = 1, lw = -1, info = 0;
    double wq;
    dsygv_(&one, "V", "U", &nr, Kr, &nr, Mr, &nr, ev, &wq, &lw, &info);
    lw = (int)wq + 1;
    work = malloc(sizeof(double) * (size_t)lw);
    if (!work) {
      st = phm_error_set(err, PHM_ENOMEM, "out of memory");
      goto done;
    }
    dsygv_(&one, "V", "U", &nr, Kr, &nr, Mr, &nr, ev, work, &lw, &info);
    if (info != 0) {
      st = phm_error_set(err, PHM_ESINGULAR, "generalized eigenproblem failed (dsygv info %d%s)", info,
                         info > nr ? ": mass matrix not positive definite" : "");
      goto done;
    }
  }
  int nf = nmodes < nr ? nmodes : nr;
  for (int k = 0; k < nf; k++) {
    double lamk = ev[k];
    omega[k] = lamk >= 0 ? sqrt(lamk) : -sqrt(-lamk);
    const double *yk = Kr + (size_t)k * nr; /* column-major: eigenvector k is contiguous */
    if (zeta) {
      double s = 0;
      for (int a = 0; a < nr; a++)
        for (int b = 0; b < nr; b++) s += yk[a] * Dr[(size_t)a * nr + b] * yk[b];
      zeta[k] = omega[k] > 0 ? s / (2 * omega[k]) : 0.0;
    }
    if (shapes)
      for (int i = 0; i < n6; i++) {
        double s = 0;
        for (int a = 0; a < nr; a++) s += Z[(size_t)i * nr + a] * yk[a];
        shapes[(size_t)k * n6 + i] = s;
      }
  }
  *nfound = nf;
done:
  lin_free(&L);
  free(H); free(K); free(Dm); free(f1); free(f2); free(col); free(tw);
  free(Z); free(Kr); free(Mr); free(Dr); free(T); free(ev); free(work); free(U); free(sv);
  return st;
}

/* ---------------------------------------------------------------- statics */
/* One Newton solve at load scale s from (H, lam); returns 0 on convergence. */
static int newton(lin_t *L, double *H, double *lam, double tol, int maxit, double *J, double *R,
                  int *ipiv, double *f1, double *f2, double *g1, double *g2, double *col, double *dg,
                  double *Hsave, double *lsave, int *iters) {
  const phm_model *m = L->m;
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk;
  memcpy(Hsave, H, sizeof(double) * 16 * (size_t)nc);
  if (nk) memcpy(lsave, lam, sizeof(double) * (size_t)nk);
  L->lam = lam;
  double sprev = INFINITY;
  for (int it = 0; it < maxit; it++) {
    (*iters)++;
    /* residual */
    total_force(L, H, R);
    if (nk) phm_constraints_dense(m, H, NULL, L->time, L->tref, R + n6, NULL, NULL);
    /* Jacobian */
    for (int c = 0; c < nc; c++)
      for (int j = 0; j < 6; j++) {
        force_column(L, H, c, j, col, nk ? dg : NULL, f1, f2, g1, g2);
        int cj = 6 * c + j;
        for (int i = 0; i < n6; i++) J[(size_t)cj * N + i] = col[i]; /* column-major */
        for (int i = 0; i < nk; i++) J[(size_t)cj * N + n6 + i] = dg[i];
      }
    if (nk) {
      phm_constraints_dense(m, H, NULL, L->time, L->tref, NULL, L->G, NULL);
      for (int r = 0; r < nk; r++) {
        for (int i = 0; i < n6; i++) J[(size_t)(n6 + r) * N + i] = L->G[(size_t)r * n6 + i];
        for (int i = 0; i < nk; i++) J[(size_t)(n6 + r) * N + n6 + i] = 0;
      }
    }
    for (int i = 0; i < N; i++) R[i] = -R[i];
    int one = 1, info = 0;
    dgesv_(&N, &one, J, &N, ipiv, R, &N, &info);
    if (info != 0) break;
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
  if (!m || !poses_out) return phm_error_set(err, PHM_EINVAL, "phm_static: NULL argument");
  if (steps < 1) return phm_error_set(err, PHM_EINVAL, "load steps must be >= 1 (got %d)", steps);
  if (!(tol > 0)) return phm_error_set(err, PHM_EINVAL, "tolerance must be > 0 (got %g)", tol);
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk, it = 0;
  phm_status st = PHM_OK;
  lin_t L = {0};
  double *J = malloc(sizeof(double) * (size_t)N * N), *R = malloc(sizeof(double) * (size_t)N);
  int *ipiv = malloc(sizeof(int) * (size_t)N);
  double *f1 = malloc(sizeof(double) * (size_t)n6), *f2 = malloc(sizeof(double) * (size_t)n6);
  double *g1 = malloc(sizeof(double) * (size_t)(nk + 1)), *g2 = malloc(sizeof(double) * (size_t)(nk + 1));
  double *col = malloc(sizeof(double) * (size_t)n6), *dg = malloc(sizeof(double) * (size_t)(nk + 1));
  double *Hs = malloc(sizeof(double) * 16 * (size_t)nc), *ls = malloc(sizeof(double) * (size_t)(nk + 1));
  double *lam = calloc((size_t)(nk + 1), sizeof(double));
  if (!J || !R || !ipiv || !f1 || !f2 || !g1 || !g2 || !col || !dg || !Hs || !ls || !lam) {
    st = phm_error_set(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  if ((st = lin_alloc(&L, m, err))) goto done;
  L.time = time;
  L.tref = phm_model_tref(m, time, NULL);
  for (int c = 0; c < nc; c++) memcpy(poses_out + 16 * c, poses ? poses + 16 * c : m->car[c].H0, 16 * sizeof(double));
  /* meet the constraints without load first */
  L.scale = 0.0;
  /* (a mechanism with a free degree of freedom is singular without load: then go on directly) */
  int pre_failed = newton(&L, poses_out, lam, tol, 50, J, R, ipiv, f1, f2, g1, g2, col, dg, Hs, ls, &it);
  double s = 0, ds = 1.0 / steps;
  while (s < 1.0) {
    double snew = fmin(1.0, s + ds);
    L.scale = snew;
    if (newton(&L, poses_out, lam, tol, 30, J, R, ipiv, f1, f2, g1, g2, col, dg, Hs, ls, &it)) {
      ds *= 0.5;
      if (ds < 1e-4 / steps) {
        st = phm_error_set(err, PHM_ESOLVER, "static equilibrium: Newton failed at load factor %.6g after step halving (%d iterations)%s", snew, it,
                           pre_failed ? "; it also failed without load (unconstrained rigid-body motion or incompatible constraints?)" : "");
        goto done;
      }
      continue;
    }
    s = snew;
  }
  if (lambda_out && nk) memcpy(lambda_out, lam, sizeof(double) * (size_t)nk);
done:
  if (iters) *iters = it;
  lin_free(&L);
  free(J); free(R); free(ipiv); free(f1); free(f2); free(g1); free(g2); free(col); free(dg);
  free(Hs); free(ls); free(lam);
  return st;
}
