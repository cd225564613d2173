/* dae.c -- the stabilized index-2 DAE (DESIGN section 6), consistent initial values and the IDA
 * driver. State layout: per carrier (q[4], p[3], t[6]); then the joint coordinates (nj, integrated
 * from their rates; they select the branch of multi-turn angles); then the energy ledger integrals
 * (dissipated, supplied, one per port); then lambda (ncons); then mu (ncons). */
#define _POSIX_C_SOURCE 200809L
#include "model_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

typedef struct {
  const phm_model *m;
  int n, ix, ie, il, im; /* sizes and offsets of the state blocks */
  double tref;
  double *H, *tw, *wr, *gl, *gm, *pport, *eff; /* scratch, allocated at set-up */
  char idamsg[256];
  /* KLU: sparsity pattern (CSC) and column colouring for the finite-difference Jacobian */
  int nnz, ncolor;
  sunindextype *colptr, *rowind;
  int *color;
  double *ytmp, *yptmp, *rtmp, *r0;
} dae_t;

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void mv6(const double A[36], const double x[6], double y[6]) {
  for (int i = 0; i < 6; i++) {
    double s = 0;
    for (int j = 0; j < 6; j++) s += A[6 * i + j] * x[j];
    y[i] = s;
  }
}

/* ad_t^T m = (-w x L - v x P, -w x P) */
static void ad_dual_apply(const double t[6], const double mm[6], double out[6]) {
  const double *w = t, *v = t + 3, *L = mm, *P = mm + 3;
  out[0] = -(w[1] * L[2] - w[2] * L[1]) - (v[1] * P[2] - v[2] * P[1]);
  out[1] = -(w[2] * L[0] - w[0] * L[2]) - (v[2] * P[0] - v[0] * P[2]);
  out[2] = -(w[0] * L[1] - w[1] * L[0]) - (v[0] * P[1] - v[1] * P[0]);
  out[3] = -(w[1] * P[2] - w[2] * P[1]);
  out[4] = -(w[2] * P[0] - w[0] * P[2]);
  out[5] = -(w[0] * P[1] - w[1] * P[0]);
}

/* Carrier poses H (nc x 16) and twists tw (nc x 6) from the state vector y. */
static void unpack_states(const phm_model *m, const double *y, double *H, double *tw) {
  for (int c = 0; c < m->nc; c++) {
    const double *yc = y + PHM_NSTATE * c;
    phm_qp_to_H(yc, yc + 4, H + 16 * c);
    memcpy(tw + 6 * c, yc + 7, 6 * sizeof(double));
  }
}

/* The pairs' rows of the residual at the poses/twists already unpacked into d->H, d->tw: joint
 * coordinate rates (F[ix..ie)), velocity constraints (F[il..im)) and position constraints
 * (F[im..n)); accumulates G^T lambda and G^T mu per carrier into d->gl, d->gm. No allocation. */
static void pair_rows(dae_t *d, double time, const double *y, const double *yp, double *F) {
  const phm_model *m = d->m;
  int nc = m->nc;
  const double *xs = y + d->ix;
  memset(d->gl, 0, sizeof(double) * 6 * (size_t)nc);
  memset(d->gm, 0, sizeof(double) * 6 * (size_t)nc);
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int r0 = m->pair_row[ip], mc = m->pair_m[ip];
    double g[PHM_MAXCON], Ga[6 * PHM_MAXCON], Gb[6 * PHM_MAXCON], vt[PHM_MAXCON], x[6], xd[6];
    const double *Ha = pr->a >= 0 ? d->H + 16 * pr->a : NULL, *Hb = pr->b >= 0 ? d->H + 16 * pr->b : NULL;
    int j0 = m->pair_j[ip], k = m->pair_k[ip];
    phm_pair_eval(m, ip, Ha, Hb, xs + j0, time, d->tref, g, Ga, Gb, vt);
    if (k > 0) {
      phm_pair_joint(m, ip, Ha, Hb, pr->a >= 0 ? d->tw + 6 * pr->a : NULL,
                     pr->b >= 0 ? d->tw + 6 * pr->b : NULL, xs + j0, x, xd);
      for (int c = 0; c < k; c++) F[d->ix + j0 + c] = yp[d->ix + j0 + c] - xd[c];
    }
    const double *lam = y + d->il + r0, *mu = y + d->im + r0;
    for (int r = 0; r < mc; r++) {
      double c = -vt[r];
      for (int j = 0; j < 6; j++) {
        if (pr->a >= 0) {
          c += Ga[6 * r + j] * d->tw[6 * pr->a + j];
          d->gl[6 * pr->a + j] += Ga[6 * r + j] * lam[r];
          d->gm[6 * pr->a + j] += Ga[6 * r + j] * mu[r];
        }
        if (pr->b >= 0) {
          c += Gb[6 * r + j] * d->tw[6 * pr->b + j];
          d->gl[6 * pr->b + j] += Gb[6 * r + j] * lam[r];
          d->gm[6 * pr->b + j] += Gb[6 * r + j] * mu[r];
        }
      }
      F[d->il + r0 + r] = c;    /* velocity constraint -> lambda */
      F[d->im + r0 + r] = g[r]; /* position constraint -> mu     */
    }
  }
}

/* The DAE residual; no allocation. */
static int dae_residual(dae_t *d, double time, const double *y, const double *yp, double *F) {
  const phm_model *m = d->m;
  int nc = m->nc;
  unpack_states(m, y, d->H, d->tw);
  double Pd = 0, Ps = 0;
  phm_applied(m, d->H, d->tw, y + d->ix, time, d->tref, 1.0, d->wr, NULL, &Pd, &Ps, d->pport, NULL);
  pair_rows(d, time, y, yp, F);
  for (int c = 0; c < nc; c++) {
    const double *yc = y + PHM_NSTATE * c, *ypc = yp + PHM_NSTATE * c;
    double *Fc = F + PHM_NSTATE * c;
    const double *q = yc, *t = yc + 7, *Hc = d->H + 16 * c, *gm = d->gm + 6 * c;
    double w[3] = {t[0] + gm[0], t[1] + gm[1], t[2] + gm[2]};
    double v[3] = {t[3] + gm[3], t[4] + gm[4], t[5] + gm[5]};
    /* q' = 1/2 q (x) (0, w) */
    Fc[0] = ypc[0] + 0.5 * (q[1] * w[0] + q[2] * w[1] + q[3] * w[2]);
    Fc[1] = ypc[1] - 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]);
    Fc[2] = ypc[2] - 0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2]);
    Fc[3] = ypc[3] - 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0]);
    for (int i = 0; i < 3; i++)
      Fc[4 + i] = ypc[4 + i] - (Hc[4 * i] * v[0] + Hc[4 * i + 1] * v[1] + Hc[4 * i + 2] * v[2]);
    double Mt[6], adm[6], Mtd[6];
    mv6(d->m->car[c].M, t, Mt);
    ad_dual_apply(t, Mt, adm);
    mv6(d->m->car[c].M, ypc + 7, Mtd);
    for (int i = 0; i < 6; i++) Fc[7 + i] = Mtd[i] - adm[i] - d->wr[6 * c + i] - d->gl[6 * c + i];
    for (int i = 0; i < 6; i++) Ps += d->gl[6 * c + i] * t[i]; /* power of constraint wrenches */
  }
  F[d->ie] = yp[d->ie] - Pd;
  F[d->ie + 1] = yp[d->ie + 1] - Ps;
  for (int k = 0; k < m->nport; k++) F[d->ie + 2 + k] = yp[d->ie + 2 + k] - d->pport[k];
  return 0;
}

static int ida_res(realtype t, N_Vector yy, N_Vector yp, N_Vector rr, void *ud) {
  return dae_residual((dae_t *)ud, t, N_VGetArrayPointer(yy), N_VGetArrayPointer(yp),
                      N_VGetArrayPointer(rr));
}

static void ida_err_handler(int code, const char *module, const char *function, char *msg, void *ud) {
  dae_t *d = (dae_t *)ud;
  (void)code;
  snprintf(d->idamsg, sizeof d->idamsg, "%s/%s: %s", module, function, msg);
}

static void dae_free(dae_t *d) {
  free(d->H);
  free(d->tw);
  free(d->wr);
  free(d->gl);
  free(d->gm);
  free(d->pport);
  free(d->eff);
  free(d->colptr);
  free(d->rowind);
  free(d->color);
  free(d->ytmp);
  free(d->yptmp);
  free(d->rtmp);
  free(d->r0);
}

static phm_status dae_init(dae_t *d, const phm_model *m, phm_error *err) {
  memset(d, 0, sizeof *d);
  d->m = m;
  d->ix = PHM_NSTATE * m->nc;
  d->ie = d->ix + m->nj;
  d->il = d->ie + 2 + m->nport;
  d->im = d->il + m->ncons;
  d->n = d->im + m->ncons;
  size_t nc = (size_t)m->nc;
  d->H = malloc(sizeof(double) * 16 * nc);
  d->tw = malloc(sizeof(double) * 6 * nc);
  d->wr = malloc(sizeof(double) * 6 * nc);
  d->gl = malloc(sizeof(double) * 6 * nc);
  d->gm = malloc(sizeof(double) * 6 * nc);
  d->pport = malloc(sizeof(double) * (size_t)(m->nport + 1));
  d->eff = malloc(sizeof(double) * (size_t)(m->nj + 1));
  if (!d->H || !d->tw || !d->wr || !d->gl || !d->gm || !d->pport || !d->eff) {
    dae_free(d);
    return phm_error_set(err, PHM_ENOMEM, "out of memory");
  }
  return PHM_OK;
}

/* ---------------------------------------------------------------- consistent initial values */
/* Cholesky factor of a 6 x 6 symmetric matrix (lower, row-major); 0 if positive definite (every
 * pivot above 1e-10 of its diagonal entry), 1 otherwise (massless or singular inertia). */
static int chol6(const double A[36], double L[36]) {
  memset(L, 0, 36 * sizeof(double));
  for (int j = 0; j < 6; j++) {
    double s = A[6 * j + j];
    if (!(s > 0)) return 1;
    for (int k = 0; k < j; k++) s -= L[6 * j + k] * L[6 * j + k];
    if (!(s > 1e-10 * A[6 * j + j])) return 1;
    L[6 * j + j] = sqrt(s);
    for (int i = j + 1; i < 6; i++) {
      double t = A[6 * i + j];
      for (int k = 0; k < j; k++) t -= L[6 * i + k] * L[6 * j + k];
      L[6 * i + j] = t / L[6 * j + j];
    }
  }
  return 0;
}

/* x = A^-1 x with A = L L^T (chol6) */
static void chol6_solve(const double L[36], double x[6]) {
  for (int i = 0; i < 6; i++) {
    double s = x[i];
    for (int k = 0; k < i; k++) s -= L[6 * i + k] * x[k];
    x[i] = s / L[6 * i + i];
  }
  for (int i = 5; i >= 0; i--) {
    double s = x[i];
    for (int k = i + 1; k < 6; k++) s -= L[6 * k + i] * x[k];
    x[i] = s / L[6 * i + i];
  }
}

/* Project poses H (nc x 16) onto g = 0 and twists tw onto G t = vt (minimum-norm corrections);
 * then solve the acceleration-level system for t' and lambda. Writes y (carrier blocks and lambda,
 * mu = 0) and yp (all but the ledger values in y, which the caller sets). qprev: previous
 * quaternions for sign continuity.
 * Structure: G only touches the carriers of the pairs (cmap), so the projections are least-squares
 * problems in those columns only (the minimum-norm correction is zero elsewhere); the acceleration
 * level eliminates the block-diagonal mass: S lambda = b2 - G M^-1 b1 with S = G M^-1 G^T (nk x nk,
 * minimum-norm lambda for redundant rows), t' = M^-1 (b1 + G^T lambda). If a constrained carrier's
 * inertia is singular, the KKT system of the constrained carriers is solved instead. */
static phm_status consistent_ic(dae_t *d, double time, double *H, double *tw, const double *qprev,
                                const double *xs, int check_x0, double *y, double *yp,
                                phm_error *err) {
  const phm_model *m = d->m;
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons;
  phm_status st = PHM_OK;
  int *cmap = malloc(sizeof(int) * (size_t)(nc + 1)), *clist = malloc(sizeof(int) * (size_t)(nc + 1));
  double *Lc = malloc(sizeof(double) * 36 * (size_t)(nc + 1));
  double *acc = malloc(sizeof(double) * (size_t)(n6 + 1)), *lam = NULL;
  double *G = NULL, *A = NULL, *b = NULL, *g = NULL, *vt = NULL, *Hp = NULL, *c1 = NULL, *X = NULL;
  if (!cmap || !clist || !Lc || !acc) {
    st = phm_error_set(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  int ncc = 0;
  for (int c = 0; c < nc; c++) cmap[c] = -1;
  for (int ip = 0; ip < m->np; ip++) {
    int ab[2] = {m->pair[ip].a, m->pair[ip].b};
    for (int s = 0; s < 2; s++)
      if (ab[s] >= 0 && cmap[ab[s]] < 0) {
        cmap[ab[s]] = ncc;
        clist[ncc++] = ab[s];
      }
  }
  if (nk == 0) ncc = 0;
  int n6c = 6 * ncc, Nk = n6c + nk, mx = Nk > nk ? Nk : nk;
  G = malloc(sizeof(double) * ((size_t)nk * n6c + 1));
  A = malloc(sizeof(double) * ((size_t)Nk * Nk + (size_t)nk * n6c + 1));
  b = malloc(sizeof(double) * (size_t)(mx + 1));
  g = malloc(sizeof(double) * (size_t)(nk + 1));
  vt = malloc(sizeof(double) * (size_t)(nk + 1));
  Hp = malloc(sizeof(double) * 16 * (size_t)nc);
  c1 = malloc(sizeof(double) * (size_t)(nk + 1) * 2);
  X = malloc(sizeof(double) * ((size_t)n6c * nk + 1));
  lam = malloc(sizeof(double) * (size_t)(nk + 1));
  if (!G || !A || !b || !g || !vt || !Hp || !c1 || !X || !lam) {
    st = phm_error_set(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  if (nk > 0) {
    /* positions */
    double gn = 0;
    int it;
    for (it = 0; it < 50; it++) {
      phm_constraints_columns(m, H, xs, time, d->tref, cmap, n6c, g, G, NULL);
      gn = 0;
      for (int i = 0; i < nk; i++) gn = fmax(gn, fabs(g[i]));
      if (gn < 1e-13) break;
      memcpy(A, G, sizeof(double) * (size_t)nk * n6c);
      for (int i = 0; i < nk; i++) b[i] = -g[i];
      if ((st = phm_lstsq(nk, n6c, A, b, NULL, err))) goto done;
      for (int k = 0; k < ncc; k++) phm_retract(H + 16 * clist[k], b + 6 * k);
    }
    if (gn > 1e-9) {
      st = phm_error_set(err, PHM_EINVAL, "initial configuration: position constraints cannot be met (|g| = %.3e after projection); check the pairs' frames", gn);
      goto done;
    }
    /* velocities */
    phm_constraints_columns(m, H, xs, time, d->tref, cmap, n6c, NULL, G, vt);
    for (int r = 0; r < nk; r++) {
      double s = -vt[r];
      for (int k = 0; k < ncc; k++)
        for (int j = 0; j < 6; j++) s += G[(size_t)r * n6c + 6 * k + j] * tw[6 * clist[k] + j];
      b[r] = -s;
    }
    memcpy(A, G, sizeof(double) * (size_t)nk * n6c);
    if ((st = phm_lstsq(nk, n6c, A, b, NULL, err))) goto done;
    for (int k = 0; k < ncc; k++)
      for (int j = 0; j < 6; j++) tw[6 * clist[k] + j] += b[6 * k + j];
  }
  /* acceleration level: [M -G^T; G 0] [t'; lambda] = [b1; b2], b1 = ad^T M t + w, b2 = -dc/dt */
  phm_applied(m, H, tw, xs, time, d->tref, 1.0, d->wr, NULL, NULL, NULL, NULL, NULL);
  int spd = 1;
  for (int c = 0; c < nc; c++) {
    const double *M = m->car[c].M;
    double Mt[6], adm[6];
    mv6(M, tw + 6 * c, Mt);
    ad_dual_apply(tw + 6 * c, Mt, adm);
    for (int i = 0; i < 6; i++) acc[6 * c + i] = adm[i] + d->wr[6 * c + i];
    if (chol6(M, Lc + 36 * c)) {
      if (cmap[c] >= 0 && nk > 0) spd = 0;
      else { /* free carrier with singular inertia: minimum-norm solution of its own block */
        double Mc[36], bc[6];
        memcpy(Mc, M, sizeof Mc);
        memcpy(bc, acc + 6 * c, sizeof bc);
        if ((st = phm_lstsq(6, 6, Mc, bc, NULL, err))) goto done;
        memcpy(acc + 6 * c, bc, sizeof bc);
      }
    } else if (cmap[c] < 0 || nk == 0) chol6_solve(Lc + 36 * c, acc + 6 * c);
  }
  if (nk > 0) {
    phm_constraints_columns(m, H, xs, time, d->tref, cmap, n6c, NULL, G, NULL);
    /* dc/dt at fixed t' by central differences along the motion */
    double tau = 1e-6;
    for (int side = 0; side < 2; side++) {
      double s = side ? -tau : tau;
      memcpy(Hp, H, sizeof(double) * 16 * (size_t)nc);
      for (int k = 0; k < ncc; k++) {
        int c = clist[k];
        double dl[6];
        for (int i = 0; i < 6; i++) dl[i] = s * tw[6 * c + i];
        phm_retract(Hp + 16 * c, dl);
      }
      phm_constraints_columns(m, Hp, xs, time + s, d->tref, cmap, n6c, NULL, X, vt);
      for (int r = 0; r < nk; r++) {
        double a = -vt[r];
        for (int k = 0; k < ncc; k++)
          for (int j = 0; j < 6; j++) a += X[(size_t)r * n6c + 6 * k + j] * tw[6 * clist[k] + j];
        c1[side * nk + r] = a;
      }
    }
    double *b2 = c1 + nk; /* reuse: b2 = -dc/dt */
    for (int r = 0; r < nk; r++) b2[r] = -(c1[r] - c1[nk + r]) / (2 * tau);
    if (spd) {
      /* X = M^-1 G^T (n6c x nk, row-major); S = G X; rhs = b2 - G M^-1 b1 */
      for (int k = 0; k < ncc; k++) {
        const double *L = Lc + 36 * clist[k];
        double *a = acc + 6 * clist[k];
        chol6_solve(L, a); /* a = M^-1 b1 */
        for (int r = 0; r < nk; r++) {
          double x[6];
          for (int j = 0; j < 6; j++) x[j] = G[(size_t)r * n6c + 6 * k + j];
          chol6_solve(L, x);
          for (int j = 0; j < 6; j++) X[(size_t)(6 * k + j) * nk + r] = x[j];
        }
      }
      for (int r = 0; r < nk; r++) {
        const double *Gr = G + (size_t)r * n6c;
        for (int s = 0; s < nk; s++) {
          double v = 0;
          for (int j = 0; j < n6c; j++) v += Gr[j] * X[(size_t)j * nk + s];
          A[(size_t)r * nk + s] = v;
        }
        double v = b2[r];
        for (int k = 0; k < ncc; k++)
          for (int j = 0; j < 6; j++) v -= Gr[6 * k + j] * acc[6 * clist[k] + j];
        b[r] = v;
      }
      for (int r = 0; r < nk; r++) /* symmetrize */
        for (int s = 0; s < r; s++) A[(size_t)r * nk + s] = A[(size_t)s * nk + r] = 0.5 * (A[(size_t)r * nk + s] + A[(size_t)s * nk + r]);
      if ((st = phm_lstsq(nk, nk, A, b, NULL, err))) goto done;
      memcpy(lam, b, sizeof(double) * (size_t)nk);
      for (int k = 0; k < ncc; k++)
        for (int j = 0; j < 6; j++) {
          double v = 0;
          for (int r = 0; r < nk; r++) v += X[(size_t)(6 * k + j) * nk + r] * lam[r];
          acc[6 * clist[k] + j] += v;
        }
    } else {
      /* KKT system of the constrained carriers, minimum-norm least squares */
      memset(A, 0, sizeof(double) * (size_t)Nk * Nk);
      for (int k = 0; k < ncc; k++) {
        const double *M = m->car[clist[k]].M;
        for (int i = 0; i < 6; i++) {
          for (int j = 0; j < 6; j++) A[(size_t)(6 * k + i) * Nk + 6 * k + j] = M[6 * i + j];
          b[6 * k + i] = acc[6 * clist[k] + i];
        }
      }
      for (int r = 0; r < nk; r++) {
        for (int j = 0; j < n6c; j++) {
          A[(size_t)(n6c + r) * Nk + j] = G[(size_t)r * n6c + j];
          A[(size_t)j * Nk + n6c + r] = -G[(size_t)r * n6c + j];
        }
        b[n6c + r] = b2[r];
      }
      if ((st = phm_lstsq(Nk, Nk, A, b, NULL, err))) goto done;
      for (int k = 0; k < ncc; k++) memcpy(acc + 6 * clist[k], b + 6 * k, 6 * sizeof(double));
      memcpy(lam, b + n6c, sizeof(double) * (size_t)nk);
    }
  }
  /* write y and yp */
  for (int c = 0; c < nc; c++) {
    double *yc = y + PHM_NSTATE * c, *ypc = yp + PHM_NSTATE * c;
    phm_H_to_qp(H + 16 * c, yc, yc + 4);
    if (qprev) {
      const double *qo = qprev + PHM_NSTATE * c;
      if (yc[0] * qo[0] + yc[1] * qo[1] + yc[2] * qo[2] + yc[3] * qo[3] < 0)
        for (int i = 0; i < 4; i++) yc[i] = -yc[i];
    }
    memcpy(yc + 7, tw + 6 * c, 6 * sizeof(double));
    const double *q = yc, *w = tw + 6 * c, *v = tw + 6 * c + 3, *Hc = H + 16 * c;
    ypc[0] = -0.5 * (q[1] * w[0] + q[2] * w[1] + q[3] * w[2]);
    ypc[1] = 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]);
    ypc[2] = 0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2]);
    ypc[3] = 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0]);
    for (int i = 0; i < 3; i++) ypc[4 + i] = Hc[4 * i] * v[0] + Hc[4 * i + 1] * v[1] + Hc[4 * i + 2] * v[2];
    memcpy(ypc + 7, acc + 6 * c, 6 * sizeof(double));
  }
  for (int r = 0; r < nk; r++) {
    y[d->il + r] = lam[r];
    y[d->im + r] = 0;
    yp[d->il + r] = yp[d->im + r] = 0;
  }
  /* joint coordinates: exact values on the branch of xs */
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int j0 = m->pair_j[ip], k = m->pair_k[ip];
    if (k == 0) continue;
    double x[6];
    phm_pair_joint(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                   NULL, NULL, xs + j0, x, NULL);
    if (check_x0 && pr->has_x0)
      for (int c = 0; c < k; c++)
        if (fabs(x[c] - pr->x0[c]) > 1e-6 * (1 + fabs(pr->x0[c]))) {
          st = phm_error_set(err, PHM_EINVAL, "pair %d: initial joint coordinate %d is %.9g in the initial configuration, not x0 = %.9g; place the bodies accordingly", ip, c, x[c], pr->x0[c]);
          goto done;
        }
    memcpy(y + d->ix + j0, x, sizeof(double) * (size_t)k);
  }
  /* rates of the joint coordinates and of the ledger from the residual (yp = 0 there) */
  {
    double *tmp = malloc(sizeof(double) * (size_t)d->n);
    if (!tmp) {
      st = phm_error_set(err, PHM_ENOMEM, "out of memory");
      goto done;
    }
    for (int i = d->ix; i < d->il; i++) yp[i] = 0;
    dae_residual(d, time, y, yp, tmp);
    for (int i = d->ix; i < d->il; i++) yp[i] = -tmp[i];
    free(tmp);
  }
done:
  free(cmap);
  free(clist);
  free(Lc);
  free(acc);
  free(lam);
  free(G);
  free(A);
  free(b);
  free(g);
  free(vt);
  free(Hp);
  free(c1);
  free(X);
  return st;
}

/* ---------------------------------------------------------------- output */
/* The first non-finite entry of x[0..n), or -1. */
static long first_nonfinite(const double *x, size_t n) {
  for (size_t i = 0; i < n; i++)
    if (!isfinite(x[i])) return (long)i;
  return -1;
}

/* Output iout must be finite: a NaN or inf in a result is never handed back silently. PHM_OK, or
 * PHM_ESOLVER naming the quantity (output iout is then not counted as done). */
static phm_status check_output(const dae_t *d, const phm_sim_output *out, int iout, double time,
                               phm_error *err) {
  const phm_model *m = d->m;
  size_t nr = out->record ? (size_t)out->nrecord : (size_t)m->nc, i = (size_t)iout;
  struct {
    const char *name;
    const double *base;
    size_t n;
  } q[] = {{"poses", out->poses, 16 * nr},
           {"twists", out->twists, 6 * nr},
           {"constraint wrenches", out->lambda, (size_t)m->ncons},
           {"energies", out->energy, PHM_NENERGY},
           {"joint coordinates", out->joints, (size_t)m->nj},
           {"joint rates", out->jrates, (size_t)m->nj},
           {"actuator efforts", out->efforts, (size_t)m->nj},
           {"pair wrenches", out->pwrench, 6 * (size_t)m->np},
           {"port energies", out->ports, (size_t)m->nport}};
  for (size_t k = 0; k < sizeof q / sizeof q[0]; k++) {
    if (!q[k].base || !q[k].n) continue;
    long j = first_nonfinite(q[k].base + i * q[k].n, q[k].n);
    if (j >= 0)
      return phm_error_set(err, PHM_ESOLVER,
                           "non-finite %s at t = %.9g s (entry %ld is %g): the model's numbers "
                           "overflow double precision (check for huge or tiny masses, stiffnesses, "
                           "loads, lengths or initial values)",
                           q[k].name, time, j, q[k].base[i * q[k].n + (size_t)j]);
  }
  return PHM_OK;
}

static void record(dae_t *d, const double *y, phm_sim_output *out, int iout, double E0[1],
                   double time) {
  const phm_model *m = d->m;
  int nc = m->nc;
  unpack_states(m, y, d->H, d->tw);
  if (out->record) { /* only the carriers the caller asked for: memory stays small on long runs */
    for (int k = 0; k < out->nrecord; k++) {
      size_t o = (size_t)iout * out->nrecord + (size_t)k;
      int c = out->record[k];
      if (out->poses) memcpy(out->poses + 16 * o, d->H + 16 * c, sizeof(double) * 16);
      if (out->twists) memcpy(out->twists + 6 * o, d->tw + 6 * c, sizeof(double) * 6);
    }
  } else {
    if (out->poses) memcpy(out->poses + (size_t)iout * 16 * nc, d->H, sizeof(double) * 16 * nc);
    if (out->twists) memcpy(out->twists + (size_t)iout * 6 * nc, d->tw, sizeof(double) * 6 * nc);
  }
  if (out->lambda && m->ncons)
    memcpy(out->lambda + (size_t)iout * m->ncons, y + d->il, sizeof(double) * m->ncons);
  const double *xs = y + d->ix;
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    const double *Ha = pr->a >= 0 ? d->H + 16 * pr->a : NULL, *Hb = pr->b >= 0 ? d->H + 16 * pr->b : NULL;
    int j0 = m->pair_j[ip];
    double x[6], xd[6];
    phm_pair_joint(m, ip, Ha, Hb, pr->a >= 0 ? d->tw + 6 * pr->a : NULL,
                   pr->b >= 0 ? d->tw + 6 * pr->b : NULL, xs + j0, x, xd);
    for (int c = 0; c < m->pair_k[ip]; c++) {
      if (out->joints) out->joints[(size_t)iout * m->nj + j0 + c] = x[c];
      if (out->jrates) out->jrates[(size_t)iout * m->nj + j0 + c] = xd[c];
    }
    if (out->pwrench)
      phm_pair_wrench(m, ip, Ha, Hb, xs + j0, time, d->tref, y + d->il + m->pair_row[ip],
                      out->pwrench + ((size_t)iout * m->np + ip) * 6);
  }
  if (out->efforts && m->nj) {
    phm_applied(m, d->H, d->tw, xs, time, d->tref, 1.0, d->wr, NULL, NULL, NULL, NULL, d->eff);
    memcpy(out->efforts + (size_t)iout * m->nj, d->eff, sizeof(double) * (size_t)m->nj);
  }
  if (out->ports && m->nport)
    memcpy(out->ports + (size_t)iout * m->nport, y + d->ie + 2, sizeof(double) * (size_t)m->nport);
  double e[3];
  phm_model_energy(m, d->H, d->tw, e);
  double tot = e[0] + e[1] + e[2];
  if (iout == 0) E0[0] = tot;
  if (out->energy) {
    double *o = out->energy + (size_t)iout * PHM_NENERGY;
    o[0] = e[0];
    o[1] = e[1];
    o[2] = e[2];
    o[3] = y[d->ie];
    o[4] = y[d->ie + 1];
    o[5] = tot;
    o[6] = tot - E0[0] - (y[d->ie + 1] - y[d->ie]);
  }
}

/* Absolute tolerance of state i (IDA's error weights; the generalized-alpha's Newton test).
 * mu (GGL) is a velocity correction whose exact value is zero. Near a tiny step size h (first
 * step, restart after a breakpoint) Newton's corrections of mu are ~ |g round-off| / h: with
 * positions |p| ~ 0.3 m, g carries ~ 5e-17 of round-off, and at h ~ 1e-10 mu moves by ~ 1e-6,
 * so a weight 1/atol on mu made the corrector "diverge" (IDA_CONV_FAIL, h -> 1e-15). mu is
 * left out of the error test, and its convergence is already measured through the positions
 * it corrects (by h G^T mu); so its absolute tolerance is 1 (rad/s, m/s).
 * lambda (constraint wrench, also left out of the error test) has the same defect one level
 * down: its corrections are ~ M |G t round-off| / h. With IDA's default first step
 * 0.5/|y'|_WRMS ~ 1e-11 s (a body at rest with a nonzero acceleration, atol 1e-10) a weight
 * 1/atol on lambda failed the corrector, h shrank by 4 per failure and IDA crept on at
 * h ~ 1e-18 (an open chain "hung" in IDASolve). Two measured remedies together: a first step
 * of min(1e-8 s, 1e-3 of the span), and an absolute tolerance of at least 1e-6 (N, N m) on
 * lambda -- enough for the four-bar at rtol 1e-10 (atol 1e-12), while lambda stays accurate
 * enough for the energy ledger (lambda . rate of driven pairs); an absolute tolerance of 1
 * cost a 350x larger energy drift in a flexible slider-crank and a 1.45e-6 ledger residual. */
static double state_atol(const dae_t *d, int i, double atol) {
  return i >= d->im ? fmax(1.0, atol) /* mu */ : i >= d->il ? fmax(1e-6, atol) /* lambda */ : atol;
}

/* State i is a carrier's twist component (layout: q[4], p[3], t[6] per carrier). */
static int is_twist(const dae_t *d, int i) { return i < d->ix && i % PHM_NSTATE >= 7; }

/* Store output iout (state y at time t) and call the user's callbacks. PHM_EINTERRUPT if the
 * interrupt callback asks; *stop = 1 if the progress callback asks to stop quietly. */
static phm_status emit_output(dae_t *d, const double *y, phm_sim_output *out, int iout, double E0[1],
                              double t, const phm_sim_options *opt, int *stop, phm_error *err) {
  *stop = 0;
  record(d, y, out, iout, E0, t);
  phm_status st = check_output(d, out, iout, t, err);
  if (st) return st;
  out->nout_done = iout + 1;
  if (opt->interrupt && opt->interrupt(opt->ctx, t, iout))
    return phm_error_set(err, PHM_EINTERRUPT, "interrupted at t = %g s", t);
  if (opt->progress && opt->progress(opt->ctx, t, iout)) *stop = 1;
  return PHM_OK;
}

/* At a breakpoint of the laws (a new piece): the new reference time and next breakpoint *nbp
 * (the piece that follows time tpiece: t, or the breakpoint when t is within round-off before
 * it), then consistent values from the current poses and twists; the ledger integrals carry
 * over. qprev: scratch of n (previous state, for quaternion sign continuity). */
static phm_status restart_at_breakpoint(dae_t *d, double t, double tpiece, double *nbp, double *y,
                                        double *yp, double *H, double *tw, double *qprev,
                                        phm_error *err) {
  d->tref = phm_model_tref(d->m, tpiece, nbp);
  unpack_states(d->m, y, H, tw);
  memcpy(qprev, y, sizeof(double) * (size_t)d->n);
  phm_status st = consistent_ic(d, t, H, tw, qprev, qprev + d->ix, 0, y, yp, err);
  if (st) return st;
  for (int i = d->ie; i < d->il; i++) y[i] = qprev[i];
  return PHM_OK;
}

/* ---------------------------------------------------------------- KLU Jacobian (coloured FD) */
/* Structural coupling of the state blocks: carrier c's rows depend on the carriers it shares an
 * element or pair with, the ledger and multiplier columns of its pairs. */
static phm_status klu_pattern(dae_t *d, phm_error *err);
static int ida_jac_klu(realtype t, realtype cj, N_Vector yy, N_Vector yp, N_Vector rr, SUNMatrix J,
                       void *ud, N_Vector t1, N_Vector t2, N_Vector t3);

/* ---------------------------------------------------------------- driver */
#define IDACHK(call)                                                                           \
  do {                                                                                         \
    int flag_ = (call);                                                                        \
    if (flag_ < 0) {                                                                           \
      char *nm_ = IDAGetReturnFlagName(flag_);                                                 \
      st = phm_error_set(err, PHM_ESOLVER, "IDA set-up failed: %s returned %s", #call,         \
                         nm_ ? nm_ : "?");                                                     \
      free(nm_);                                                                               \
      goto done;                                                                               \
    }                                                                                          \
  } while (0)

static void add_stats(void *mem, phm_sim_output *out, int use_klu) {
  long a = 0;
  if (IDAGetNumSteps(mem, &a) == 0) out->nsteps += a;
  a = 0;
  if (IDAGetNumResEvals(mem, &a) == 0) out->nres += a;
  a = 0;
  if (!use_klu && IDAGetNumLinResEvals(mem, &a) == 0) out->nres += a;
  a = 0;
  if (IDAGetNumJacEvals(mem, &a) == 0) out->njac += a;
  a = 0;
  if (IDAGetNumNonlinSolvIters(mem, &a) == 0) out->nniters += a;
  a = 0;
  if (IDAGetNumErrTestFails(mem, &a) == 0) out->netf += a;
  a = 0;
  if (IDAGetNumNonlinSolvConvFails(mem, &a) == 0) out->nncf += a;
  double h = 0;
  if (IDAGetLastStep(mem, &h) == 0) out->last_step = h;
  int q = 0;
  if (IDAGetLastOrder(mem, &q) == 0) out->last_order = q;
}

/* ---------------------------------------------------------------- generalized-alpha */
/* Generalized-alpha for first-order systems (Jansen, Whiting & Hulbert 2000) applied to the DAE.
 * With rho = rho_inf: alpha_f = 1/(1+rho), alpha_m = (3-rho)/(2(1+rho)), gamma = 1/2 + alpha_m -
 * alpha_f (second order, A-stable, spectral radius rho as h*omega -> infinity):
 *   y1 = y0 + h y0' + gamma h (y1' - y0'),
 *   differential rows of F at (t0 + alpha_f h, y0 + alpha_f (y1 - y0), y0' + alpha_m (y1' - y0')),
 *   constraint rows (g = 0, G t = vt) at (t1, y1): the constraints hold at every step;
 * lambda and mu are stage values (not interpolated). Unknown: y1. Modified Newton on the coloured
 * finite-difference Jacobian, refreshed when convergence is slow or the step changed; a step
 * whose Newton fails with a fresh Jacobian is retried with half the step (up to 2^-10).
 * Steps are shortened (evenly) to land on the output times and on the breakpoints of the laws. */
typedef struct {
  double af, am, gam;
  int euler; /* this step is backward Euler (see run_galpha) */
  N_Vector y0, yp0, Y, Yp, ya, ypa, Ra, R, dY, w, yq, ypq, yqq; /* yq, ypq: previous step; yqq: the one before */
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

/* R = [differential rows at the stage; constraint rows at (t1, y1)]; Ra keeps the full stage
 * residual (the base of the finite-difference Jacobian). */
static void galpha_residual(dae_t *d, galpha_t *g, double t0, double h) {
  double *Ra = N_VGetArrayPointer(g->Ra), *R = N_VGetArrayPointer(g->R);
  dae_residual(d, t0 + stage_af(g) * h, N_VGetArrayPointer(g->ya), N_VGetArrayPointer(g->ypa), Ra);
  unpack_states(d->m, N_VGetArrayPointer(g->Y), d->H, d->tw);
  pair_rows(d, t0 + h, N_VGetArrayPointer(g->Y), N_VGetArrayPointer(g->Yp), R);
  memcpy(R, Ra, sizeof(double) * (size_t)d->il); /* incl. the joint-rate rows pair_rows wrote */
}

/* dR/dy1 ~ alpha_f (dF/dy + cj dF/dy') on the differential block (cj = alpha_m / (alpha_f gamma h)),
 * dF/dy on the multiplier columns and on the constraint rows; dense copy when LS is dense. */
static int galpha_jacobian(dae_t *d, galpha_t *g, double t0, double h, SUNMatrix Js, SUNMatrix A) {
  double cj = g->euler ? 1.0 / h : g->am / (g->af * g->gam * h);
  double af = stage_af(g);
  if (ida_jac_klu(t0 + af * h, cj, g->ya, g->ypa, g->Ra, Js, d, NULL, NULL, NULL)) return 1;
  sunindextype *cp = SUNSparseMatrix_IndexPointers(Js), *ri = SUNSparseMatrix_IndexValues(Js);
  double *val = SUNSparseMatrix_Data(Js);
  for (int j = 0; j < d->il; j++)
    for (sunindextype k = cp[j]; k < cp[j + 1]; k++)
      if (ri[k] < d->il) val[k] *= af;
  if (A != Js) {
    SUNMatZero(A);
    for (int j = 0; j < d->n; j++)
      for (sunindextype k = cp[j]; k < cp[j + 1]; k++) SM_ELEMENT_D(A, ri[k], j) = val[k];
  }
  return 0;
}

/* Local error estimate of a converged step h (previous steps hq, hqq; 0: not there), WRMS-normed
 * with the error weights of the configuration states (poses, joint coordinates; twists, ledger
 * integrals and multipliers are left out): the trapezoidal local error h^3 y'''/12, with y''' = 6
 * times the third divided difference of y over the last four points. Positions, not rates: a fast
 * vibration the step does not resolve has a tiny amplitude in the poses and a large one in the
 * rates (by omega), so an estimate from the rates would resolve it. Returns -1 without enough
 * history (the first two steps after a start or a breakpoint). *emax: the max-norm estimate. */
static double galpha_error(const dae_t *d, const galpha_t *g, double h, double hq, double hqq,
                           double rtol, double atol, double *emax) {
  *emax = 0;
  if (!(hq > 0 && hqq > 0)) return -1.0;
  const double *Y = N_VGetArrayPointer(g->Y), *y0 = N_VGetArrayPointer(g->y0);
  const double *yq = N_VGetArrayPointer(g->yq), *yqq = N_VGetArrayPointer(g->yqq);
  double sum = 0, mx = 0;
  int cnt = 0;
  /* reciprocals once: six divisions per state per step were ~5 % of a flexible scene's CPU */
  double ih = 1.0 / h, ihq = 1.0 / hq, ihqq = 1.0 / hqq, ia = 1.0 / (h + hq), ib = 1.0 / (hq + hqq);
  double c3 = 0.5 * h * h * h / (h + hq + hqq);
  for (int i = 0; i < d->ie; i++) {
    if (is_twist(d, i)) continue;
    double d10 = (Y[i] - y0[i]) * ih, d0q = (y0[i] - yq[i]) * ihq, dqq = (yq[i] - yqq[i]) * ihqq;
    double dd2a = (d10 - d0q) * ia, dd2b = (d0q - dqq) * ib;
    double e = c3 * (dd2a - dd2b);
    double wgt = rtol * fabs(Y[i]) + atol;
    sum += (e / wgt) * (e / wgt);
    mx = fmax(mx, fabs(e));
    cnt++;
  }
  *emax = mx;
  return cnt ? sqrt(sum / cnt) : 0.0;
}

static phm_status run_galpha(dae_t *d, const phm_sim_options *opt, SUNContext ctx, N_Vector yy,
                             N_Vector yp, const double *tout, int nout, double *H, double *tw,
                             double *qprev, double E0[1], double nbp, phm_sim_output *out,
                             phm_error *err) {
  int n = d->n;
  phm_status st = PHM_OK;
  double rho = opt->rho_inf;
  int adaptive = opt->adaptive;
  /* the band's floor: no step below it for accuracy's sake (Newton failures still halve) */
  double hfloor = adaptive && opt->band > 0 ? 1.0 / (PHM_BAND_STEPS * opt->band) : 0.0;
  double hmax = opt->max_step > 0 ? opt->max_step : INFINITY;
  /* and no step above 1/(PHM_BAND_MAX_STEPS band): the band is resolved, whatever the estimate */
  if (adaptive && opt->band > 0) hmax = fmin(hmax, 1.0 / (PHM_BAND_MAX_STEPS * opt->band));
  /* proposed step: fixed, or the controller's (first: the given step, else the floor, else 1e-4
   * of the span) */
  double h0 = adaptive ? (opt->step > 0 ? opt->step : hfloor > 0 ? hfloor : 1e-4 * (tout[nout - 1] - tout[0]))
                       : opt->step;
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
   * the error tolerance either. The multipliers keep their tolerances (state_atol): their
   * corrections carry the round-off of G t / h. */
  double newton_tol = adaptive ? fmin(1.0, PHM_NEWTON_RTOL / opt->rtol) : 1.0;
  double span = tout[nout - 1] - tout[0];
  galpha_t g;
  memset(&g, 0, sizeof g);
  g.af = 1.0 / (1.0 + rho);
  g.am = 0.5 * (3.0 - rho) / (1.0 + rho);
  g.gam = 0.5 + g.am - g.af;
  SUNMatrix Js = NULL, A = NULL;
  SUNLinearSolver LS = NULL;
  N_Vector *vs[] = {&g.y0, &g.yp0, &g.Y, &g.Yp, &g.ya, &g.ypa, &g.Ra, &g.R, &g.dY, &g.w, &g.yq, &g.ypq, &g.yqq};
  int nv = (int)(sizeof vs / sizeof vs[0]);
  for (int k = 0; k < nv; k++) {
    if (!(*vs[k] = N_VNew_Serial(n, ctx))) {
      st = phm_error_set(err, PHM_ENOMEM, "out of memory (N_Vector)");
      goto done;
    }
    N_VConst(0.0, *vs[k]); /* N_VNew leaves the data uninitialized */
  }
  if ((st = klu_pattern(d, err))) goto done;
  Js = SUNSparseMatrix(n, n, d->nnz, CSC_MAT, ctx);
  A = opt->linear_solver == 1 ? Js : SUNDenseMatrix(n, n, ctx);
  if (!Js || !A) {
    st = phm_error_set(err, PHM_ENOMEM, "out of memory (matrix)");
    goto done;
  }
  LS = opt->linear_solver == 1 ? SUNLinSol_KLU(yy, A, ctx) : SUNLinSol_Dense(yy, A, ctx);
  if (!LS || SUNLinSolInitialize(LS) != SUNLS_SUCCESS) {
    st = phm_error_set(err, PHM_ESOLVER, "could not create the linear solver");
    goto done;
  }
  double *y0 = N_VGetArrayPointer(g.y0), *yp0 = N_VGetArrayPointer(g.yp0), *Y = N_VGetArrayPointer(g.Y);
  double *Yp = N_VGetArrayPointer(g.Yp), *dY = N_VGetArrayPointer(g.dY), *w = N_VGetArrayPointer(g.w);
  double *y = N_VGetArrayPointer(yy), *ypd = N_VGetArrayPointer(yp);
  double *yq = N_VGetArrayPointer(g.yq), *ypq = N_VGetArrayPointer(g.ypq), hq = 0; /* hq = 0: no history */
  double *yqq = N_VGetArrayPointer(g.yqq), hqq = 0;
  memcpy(y0, y, sizeof(double) * (size_t)n);
  memcpy(yp0, ypd, sizeof(double) * (size_t)n);
  double t = tout[0], hjac = 0;
  int iout = 1, fresh = 0;
  /* restart: the first step, and the first after each breakpoint. If it fails, it is redone as
   * backward Euler, which does not use y0': consistent_ic computes y0' exactly, but it can be
   * huge (a joint torque on a light node of the manipulator: 3e9 rad/s^2); carried into the step
   * it drives the unresolved fast modes and the stage powers to 1e14 W, and the finite-difference
   * Jacobian loses every digit. One first-order step adds an O(h^2) error once, so the global
   * error stays second order (with twice the error constant on a pendulum: why it is a fallback
   * and not the rule). */
  int restart = 1;
  long max_steps = opt->max_steps > 0 ? opt->max_steps : 1000000L, steps_out = 0;
  while (iout < nout) {
    /* A breakpoint within bptol (1e-9 of a step) of t counts as reached: restart on its new
     * piece. Landing on it exactly would take a step of round-off size: a Step law at
     * 1e-3 + 1e-13 s with outputs every 1e-3 s gave a step of 1e-13 s (h = -inf from ceil(-0)
     * before this rule), and the first step after it fails. */
    double bptol = 1e-9 * h0;
    if (isfinite(nbp) && t >= nbp - bptol) {
      if ((st = restart_at_breakpoint(d, t, fmax(t, nbp), &nbp, y0, yp0, H, tw, qprev, err))) goto done;
      hjac = hq = hqq = 0;
      restart = 1;
    }
    /* steps land on the output times and the breakpoints of the laws: the largest step <= h0
     * that divides what is left of the interval evenly (outputs need no interpolation, and the
     * constraints hold at every output); a breakpoint within bptol before an output is left to
     * the restart above, at the output */
    double target = tout[iout];
    if (isfinite(nbp) && nbp > t && nbp < target - bptol) target = nbp;
    double h = (target - t) / fmax(1.0, ceil((target - t) / h0 - 1e-9));
    if (!(t + h > t)) {
      st = phm_error_set(err, PHM_ESOLVER, "generalized-alpha: step %.3g s too small to advance "
                         "t = %.9g s in double precision", h, t);
      goto done;
    }
    if (++steps_out > max_steps) {
      st = phm_error_set(err, PHM_ESOLVER, "generalized-alpha: more than %ld steps between two "
                         "output times (t = %.9g s, step %.3g s)", max_steps, t, h);
      goto done;
    }
    int halvings = 0;
    double errn = 0, emax = 0;
    for (;;) { /* one step of size h (halved on Newton failure, shortened on error-test failure) */
      /* predictor: y' (and the multipliers) extrapolated linearly from the last two steps */
      /* (no history on the first step and after a restart: yq, ypq are not read then) */
      double r = hq > 0 ? h / hq : 0;
      for (int i = 0; i < d->il; i++)
        Y[i] = g.euler ? y0[i] : y0[i] + h * yp0[i] + (hq > 0 ? g.gam * h * r * (yp0[i] - ypq[i]) : 0.0);
      for (int i = d->il; i < n; i++) Y[i] = hq > 0 ? y0[i] + r * (y0[i] - yq[i]) : y0[i];
      /* the iteration matrix scales with 1/h: refreshed when h moved by more than 20 % (fixed
       * step) or 50 % (adaptive: the controller moves h a little at every step, and a stale
       * matrix only slows the convergence, which a failure then refreshes) */
      if (fabs(h / hjac - 1.0) > (adaptive ? 0.5 : 0.2)) hjac = 0;
      fresh = 0;
      int ok = 0;
      double nrm0 = 0;
      /* the absolute part of Newton's error weights, once per step attempt (the relative part
       * follows the iterate, as before: weights fixed from the step's start, or from the larger
       * of the start and the predictor, raised the energy-ledger residuals of the double
       * pendulum and the flexible arm of benchmarks/scenes.py 16-18x). Twists: a velocity error
       * dv moves the poses by h dv in a step, so the tolerance on the twists that matches atol
       * on the poses is atol / h */
      for (int i = 0; i < n; i++)
        w[i] = (i < d->il ? newton_tol : 1.0) * (is_twist(d, i) ? opt->atol / h : state_atol(d, i, opt->atol));
      for (int it = 0; it < 4; it++) {
        galpha_stage(d, &g, h);
        galpha_residual(d, &g, t, h);
        out->nres++;
        if (hjac == 0) {
          if (galpha_jacobian(d, &g, t, h, Js, A) || SUNLinSolSetup(LS, A) != SUNLS_SUCCESS) {
            if (restart && !g.euler) break; /* redone as backward Euler below */
            if (adaptive) { /* a shorter step (Newton-failure path): fresh, so it halves */
              fresh = 1;
              break;
            }
            st = phm_error_set(err, PHM_ESOLVER, "generalized-alpha: singular iteration matrix at t = %.9g s", t);
            goto done;
          }
          out->njac++;
          hjac = h;
          fresh = 1;
        }
        N_VScale(-1.0, g.R, g.dY);
        if (SUNLinSolSolve(LS, A, g.dY, g.dY, 0.0) != SUNLS_SUCCESS) {
          st = phm_error_set(err, PHM_ESOLVER, "generalized-alpha: linear solve failed at t = %.9g s", t);
          goto done;
        }
        out->nniters++;
        /* WRMS norm of the correction, weights 1 / (ntol (rtol |Y| + a)) at the updated iterate */
        double sum = 0, rd = newton_tol * opt->rtol;
        for (int i = 0; i < d->il; i++) {
          Y[i] += dY[i];
          double e = dY[i] / (rd * fabs(Y[i]) + w[i]);
          sum += e * e;
        }
        for (int i = d->il; i < n; i++) {
          Y[i] += dY[i];
          double e = dY[i] / (opt->rtol * fabs(Y[i]) + w[i]);
          sum += e * e;
        }
        double nrm = sqrt(sum / n);
        if (!isfinite(nrm)) break;
        if (it == 0) {
          nrm0 = nrm;
          if (nrm <= 0.033) { ok = 1; break; }
        } else {
          double rate = pow(nrm / nrm0, 1.0 / it);
          if (rate > 0.9) break;
          if (nrm * rate / (1.0 - rate) <= 0.33) { ok = 1; break; }
        }
      }
      if (ok && adaptive) {
        /* per unit step: the local estimate times the number of such steps in the run, so that
         * the estimates summed over the run (an oscillation's phase error adds up step after
         * step) stay within the tolerance, not only each one. Measured on the impulsed
         * cantilever (benchmarks/scenes.py): per step, its 149 Hz mode (4 % of the energy, in
         * the 500 Hz band) drifted a full period off in 1 s and the tip 17 um off IDA; per unit
         * step 6.7 um, at the band's floor step. */
        errn = galpha_error(d, &g, h, hq, hqq, opt->rtol, opt->atol, &emax);
        if (errn > 0) errn *= span / h;
        if (errn > 1.0 && h > hfloor * (1.0 + 1e-9)) { /* error test failed: shorter step, same t */
          out->netf++;
          h = fmax(hfloor, h * fmax(0.2, 0.8 * pow(errn, -0.5))); /* errn ~ h^2 (per unit step) */
          h0 = h;
          continue;
        }
      }
      if (ok) break;
      out->nncf++;
      if (restart && !g.euler && (fresh || hjac == 0)) { /* see `restart` */
        g.euler = 1;
        hjac = 0;
        continue;
      }
      if (!fresh) { hjac = 0; continue; }            /* retry with a fresh Jacobian */
      if (++halvings > 10) {
        st = phm_error_set(err, PHM_ESOLVER, "generalized-alpha: Newton failed at t = %.9g s even with "
                           "step %.3g s (fresh Jacobian, 10 halvings)", t, h);
        goto done;
      }
      h *= 0.5;
      hjac = 0;
    }
    galpha_stage(d, &g, h); /* y1' of the converged y1 */
    double t1 = fabs(target - (t + h)) < 1e-9 * h ? target : t + h;
    out->nsteps++;
    out->last_step = h;
    if (adaptive) {
      /* next proposal, with a dead band against chattering (every change of h costs Newton
       * iterations with the iteration matrix of another h, and measured on the double pendulum
       * a controller that also shrank h after accepted steps made 4x more convergence failures
       * and a larger error): an accepted step keeps h unless the estimate allows >= 1.25x (then
       * at most 1.5x); a rejected step (above) has already shortened it. A step shortened to
       * land on an output neither shrinks the proposal nor blocks its growth (its estimate is
       * scaled to the proposal by (h0/h)^2). */
      if (errn > 1.0) out->nfloor++;
      out->err_est += emax;
      double base = fmax(h, h0), eb = errn * pow(base / h, 2.0); /* the estimate scaled to h0 */
      double fac = errn < 0 ? 1.0 : eb > 0 ? 0.8 * pow(eb, -0.5) : 1.5;
      double hn = fac >= 1.25 ? base * fmin(1.5, fac) : base;
      h0 = fmin(hmax, fmax(hfloor, hn));
    }
    if (opt->monitor && out->nsteps % PHM_MONITOR_STEPS == 0 && opt->monitor(opt->ctx, t1, out->nsteps, h)) {
      st = phm_error_set(err, PHM_EINTERRUPT, "interrupted at t = %g s", t1);
      goto done;
    }
    if (t1 == tout[iout]) {
      int stop;
      if ((st = emit_output(d, Y, out, iout, E0, t1, opt, &stop, err)) || stop) goto done;
      iout++;
      steps_out = 0;
    }
    t = t1;
    hqq = hq;
    hq = g.euler ? 0 : h; /* no history across the Euler step (its y0' is not this scheme's) */
    memcpy(yqq, yq, sizeof(double) * (size_t)n);
    if (g.euler) hjac = 0; /* other coefficients from here on */
    /* adaptive: the two steps after a restart have no error estimate yet and start from the
     * restart's rates; a failing one is redone as backward Euler too */
    if (g.euler) hjac = 0;
    restart = adaptive && restart > 0 && restart < 3 ? restart + 1 : 0;
    g.euler = 0;
    memcpy(yq, y0, sizeof(double) * (size_t)n);
    memcpy(ypq, yp0, sizeof(double) * (size_t)n);
    memcpy(y0, Y, sizeof(double) * (size_t)n);
    memcpy(yp0, Yp, sizeof(double) * (size_t)n);
  }
done:
  out->last_order = 2;
  if (LS) SUNLinSolFree(LS);
  if (A && A != Js) SUNMatDestroy(A);
  if (Js) SUNMatDestroy(Js);
  for (int k = 0; k < nv; k++)
    if (*vs[k]) N_VDestroy(*vs[k]);
  return st;
}

phm_status phm_simulate(const phm_model *m, const double *poses0, const double *twists0,
                        const double *tout, int nout, const phm_sim_options *opt,
                        phm_sim_output *out, phm_error *err) {
  phm_error_clear(err);
  if (!m || !tout || !opt || !out) return phm_error_set(err, PHM_EINVAL, "phm_simulate: NULL argument");
  if (nout < 1) return phm_error_set(err, PHM_EINVAL, "need at least one output time");
  for (int i = 0; i < nout; i++) {
    if (!isfinite(tout[i])) return phm_error_set(err, PHM_EINVAL, "output time %d is not finite", i);
    if (i > 0 && !(tout[i] > tout[i - 1]))
      return phm_error_set(err, PHM_EINVAL, "output times must be strictly increasing (t[%d] = %g <= t[%d] = %g)", i, tout[i], i - 1, tout[i - 1]);
  }
  if (!(opt->rtol > 0) || !(opt->atol > 0) || !isfinite(opt->rtol) || !isfinite(opt->atol))
    return phm_error_set(err, PHM_EINVAL, "rtol and atol must be > 0 (got %g, %g)", opt->rtol, opt->atol);
  if (opt->error_test != PHM_ERRTEST_ALL && opt->error_test != PHM_ERRTEST_CONFIGURATION)
    return phm_error_set(err, PHM_EINVAL, "unknown error test %d (0 all states, 1 configuration)", opt->error_test);
  if (opt->error_test == PHM_ERRTEST_CONFIGURATION && !(opt->max_order > 0 && opt->max_order <= 2))
    return phm_error_set(err, PHM_EINVAL, "the configuration error test needs a maximum BDF order of 1 or 2 "
                         "(got %d): without the twists in the error test, BDF 3-5 let unresolved vibrations grow", opt->max_order);
  if (opt->linear_solver != 0 && opt->linear_solver != 1)
    return phm_error_set(err, PHM_EINVAL, "unknown linear solver %d (0 dense, 1 KLU)", opt->linear_solver);
  if (opt->integrator != PHM_INTEGRATOR_IDA && opt->integrator != PHM_INTEGRATOR_GALPHA)
    return phm_error_set(err, PHM_EINVAL, "unknown integrator %d (0 IDA, 1 generalized-alpha)", opt->integrator);
  if (opt->integrator == PHM_INTEGRATOR_GALPHA &&
      (!(opt->adaptive ? opt->step >= 0 : opt->step > 0) || !isfinite(opt->step) ||
       !(opt->rho_inf >= 0 && opt->rho_inf <= 1) || !(opt->band >= 0) || !isfinite(opt->band)))
    return phm_error_set(err, PHM_EINVAL, "generalized-alpha needs step > 0 (>= 0 when adaptive), "
                         "0 <= rho_inf <= 1 and a finite band >= 0 (got %g, %g, %g)",
                         opt->step, opt->rho_inf, opt->band);
  double t_start = now();
  out->nout_done = 0;
  out->nsteps = out->nres = out->njac = out->nniters = out->netf = out->nncf = out->nfloor = 0;
  out->err_est = 0;
  phm_status st = PHM_OK;
  dae_t d;
  if ((st = dae_init(&d, m, err))) return st;
  SUNContext ctx = NULL;
  N_Vector yy = NULL, yp = NULL, id = NULL;
  SUNMatrix A = NULL;
  SUNLinearSolver LS = NULL;
  void *mem = NULL;
  int nc = m->nc;
  double *H = malloc(sizeof(double) * 16 * (size_t)nc), *tw = malloc(sizeof(double) * 6 * (size_t)nc);
  double *qprev = malloc(sizeof(double) * (size_t)d.n);
  if (!H || !tw || !qprev) {
    st = phm_error_set(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  for (int c = 0; c < nc; c++) {
    memcpy(H + 16 * c, poses0 ? poses0 + 16 * c : m->car[c].H0, 16 * sizeof(double));
    memcpy(tw + 6 * c, twists0 ? twists0 + 6 * c : m->car[c].t0, 6 * sizeof(double));
  }
  if (SUNContext_Create(NULL, &ctx) != 0) {
    st = phm_error_set(err, PHM_ESOLVER, "SUNContext_Create failed");
    goto done;
  }
  yy = N_VNew_Serial(d.n, ctx);
  yp = N_VNew_Serial(d.n, ctx);
  id = N_VNew_Serial(d.n, ctx);
  if (!yy || !yp || !id) {
    st = phm_error_set(err, PHM_ENOMEM, "out of memory (N_Vector)");
    goto done;
  }
  double *y = N_VGetArrayPointer(yy), *ypd = N_VGetArrayPointer(yp), *idd = N_VGetArrayPointer(id);
  /* id: 1 differential, 0 algebraic. IDA uses it only to leave the 0 components out of the local
   * error test (IDASetSuppressAlg; no IDACalcIC here), so the configuration error test marks the
   * twists 0 as well: they keep their weights in the Newton convergence test. */
  for (int i = 0; i < d.n; i++)
    idd[i] = i < d.il && !(is_twist(&d, i) && opt->error_test == PHM_ERRTEST_CONFIGURATION) ? 1.0 : 0.0;
  double t = tout[0], nbp;
  d.tref = phm_model_tref(m, t, &nbp);
  memset(y, 0, sizeof(double) * (size_t)d.n);
  memset(ypd, 0, sizeof(double) * (size_t)d.n);
  if ((st = consistent_ic(&d, t, H, tw, NULL, m->xref0, 1, y, ypd, err))) goto done;
  double E0 = 0;
  int stop;
  if ((st = emit_output(&d, y, out, 0, &E0, t, opt, &stop, err)) || stop) goto done;
  if (nout == 1) goto done;
  if (opt->integrator == PHM_INTEGRATOR_GALPHA) {
    st = run_galpha(&d, opt, ctx, yy, yp, tout, nout, H, tw, qprev, &E0, nbp, out, err);
    goto done;
  }

  mem = IDACreate(ctx);
  if (!mem) {
    st = phm_error_set(err, PHM_ENOMEM, "IDACreate failed");
    goto done;
  }
  IDACHK(IDASetErrHandlerFn(mem, ida_err_handler, &d));
  IDACHK(IDAInit(mem, ida_res, t, yy, yp));
  {
    N_Vector av = N_VNew_Serial(d.n, ctx);
    if (!av) {
      st = phm_error_set(err, PHM_ENOMEM, "out of memory (N_Vector)");
      goto done;
    }
    double *a = N_VGetArrayPointer(av);
    for (int i = 0; i < d.n; i++) a[i] = state_atol(&d, i, opt->atol);
    int fl = IDASVtolerances(mem, opt->rtol, av);
    N_VDestroy(av);
    IDACHK(fl);
  }
  IDACHK(IDASetUserData(mem, &d));
  IDACHK(IDASetId(mem, id));
  IDACHK(IDASetSuppressAlg(mem, SUNTRUE));
  /* bounded failure: at most 10^6 steps per output interval, and no step below 1e-14 of the
   * simulated span (a corrector that keeps failing ends in IDA_CONV_FAIL/IDA_ERR_FAIL there
   * instead of creeping on at h ~ 1e-18) */
  /* with a monitor, IDASolve returns every PHM_MONITOR_STEPS steps (IDA_TOO_MUCH_WORK, state
   * intact) so the monitor sees long output intervals; the per-interval limit is counted here */
  long max_steps = opt->max_steps > 0 ? opt->max_steps : 1000000L;
  IDACHK(IDASetMaxNumSteps(mem, opt->monitor ? PHM_MONITOR_STEPS : max_steps));
  IDACHK(IDASetMinStep(mem, 1e-14 * fmax(1.0, tout[nout - 1] - tout[0])));
  IDACHK(IDASetInitStep(mem, fmin(1e-8, 1e-3 * (tout[nout - 1] - tout[0]))));
  if (opt->max_step > 0) IDACHK(IDASetMaxStep(mem, opt->max_step));
  if (opt->max_order > 0) IDACHK(IDASetMaxOrd(mem, opt->max_order < 5 ? opt->max_order : 5));
  if (opt->linear_solver == 1) {
    if ((st = klu_pattern(&d, err))) goto done;
    A = SUNSparseMatrix(d.n, d.n, d.nnz, CSC_MAT, ctx);
    if (!A) {
      st = phm_error_set(err, PHM_ENOMEM, "out of memory (sparse matrix)");
      goto done;
    }
    LS = SUNLinSol_KLU(yy, A, ctx);
  } else {
    A = SUNDenseMatrix(d.n, d.n, ctx);
    if (!A) {
      st = phm_error_set(err, PHM_ENOMEM, "out of memory (dense matrix)");
      goto done;
    }
    LS = SUNLinSol_Dense(yy, A, ctx);
  }
  if (!LS) {
    st = phm_error_set(err, PHM_ESOLVER, "could not create the linear solver");
    goto done;
  }
  IDACHK(IDASetLinearSolver(mem, LS, A));
  if (opt->linear_solver == 1) IDACHK(IDASetJacFn(mem, ida_jac_klu));

  for (int iout = 1; iout < nout; iout++) {
    double target = tout[iout];
    long chunks = 0;
    while (t < target) {
      if (isfinite(nbp)) IDACHK(IDASetStopTime(mem, nbp));
      double tret = t;
      int flag = IDASolve(mem, target, &tret, yy, yp, IDA_NORMAL);
      if (flag == IDA_TOO_MUCH_WORK && opt->monitor && ++chunks * PHM_MONITOR_STEPS < max_steps) {
        long ns = 0;
        double hl = 0;
        IDAGetNumSteps(mem, &ns);
        IDAGetLastStep(mem, &hl);
        t = tret;
        if (opt->monitor(opt->ctx, t, out->nsteps + ns, hl)) {
          st = phm_error_set(err, PHM_EINTERRUPT, "interrupted at t = %g s", t);
          goto done;
        }
        continue;
      }
      if (flag < 0) {
        char *nm = IDAGetReturnFlagName(flag);
        st = phm_error_set(err, PHM_ESOLVER, "IDA failed with %s at t = %.9g s (%s)", nm ? nm : "?", tret, d.idamsg);
        free(nm);
        goto done;
      }
      t = tret;
      if (flag == IDA_TSTOP_RETURN) {
        /* breakpoint: new piece of the laws, re-initialize from consistent values */
        add_stats(mem, out, opt->linear_solver);
        if ((st = restart_at_breakpoint(&d, t, t, &nbp, y, ypd, H, tw, qprev, err))) goto done;
        IDACHK(IDAReInit(mem, t, yy, yp));
        if (t >= target) t = target;
      }
    }
    if ((st = emit_output(&d, y, out, iout, &E0, t, opt, &stop, err)) || stop) goto done;
  }
done:
  if (mem) add_stats(mem, out, opt->linear_solver);
  if (mem) IDAFree(&mem);
  if (LS) SUNLinSolFree(LS);
  if (A) SUNMatDestroy(A);
  if (yy) N_VDestroy(yy);
  if (yp) N_VDestroy(yp);
  if (id) N_VDestroy(id);
  if (ctx) SUNContext_Free(&ctx);
  free(H);
  free(tw);
  free(qprev);
  dae_free(&d);
  out->wall_time = now() - t_start;
  return st;
}

/* ---------------------------------------------------------------- KLU pattern and Jacobian */
static phm_status klu_pattern(dae_t *d, phm_error *err) {
  const phm_model *m = d->m;
  int n = d->n, nc = m->nc;
  /* column block of each state index: carrier c -> c; ledger -> none (no row depends on it);
   * lambda/mu row r of pair ip -> "pair block". Build a dense boolean block adjacency. */
  int nb = nc + m->np; /* blocks: carriers, then pairs (their lambda and mu) */
  char *adj = calloc((size_t)nb * nb, 1);
  if (!adj) return phm_error_set(err, PHM_ENOMEM, "out of memory");
  for (int c = 0; c < nc; c++) adj[(size_t)c * nb + c] = 1;
  for (int ie = 0; ie < m->ne; ie++) {
    int a = m->el[ie].a, b = m->el[ie].b;
    adj[(size_t)a * nb + b] = adj[(size_t)b * nb + a] = 1;
  }
  for (int is = 0; is < m->ns; is++) {
    int a = m->spr[is].a, b = m->spr[is].b;
    if (a >= 0 && b >= 0) adj[(size_t)a * nb + b] = adj[(size_t)b * nb + a] = 1;
  }
  for (int il = 0; il < m->nl; il++) {
    int a = m->load[il].carrier, b = m->load[il].reaction;
    if (a >= 0 && b >= 0) adj[(size_t)a * nb + b] = adj[(size_t)b * nb + a] = 1;
  }
  for (int ip = 0; ip < m->np; ip++) {
    int a = m->pair[ip].a, b = m->pair[ip].b, p = nc + ip;
    if (m->pair_k[ip] > 0) adj[(size_t)p * nb + p] = 1; /* joint coordinates: own rate */
    if (a >= 0 && b >= 0) adj[(size_t)a * nb + b] = adj[(size_t)b * nb + a] = 1;
    if (a >= 0) adj[(size_t)a * nb + p] = adj[(size_t)p * nb + a] = 1;
    if (b >= 0) adj[(size_t)b * nb + p] = adj[(size_t)p * nb + b] = 1;
  }
  int *blk = malloc(sizeof(int) * (size_t)n);
  d->colptr = malloc(sizeof(sunindextype) * (size_t)(n + 1));
  d->color = malloc(sizeof(int) * (size_t)n);
  d->ytmp = malloc(sizeof(double) * (size_t)n);
  d->yptmp = malloc(sizeof(double) * (size_t)n);
  d->rtmp = malloc(sizeof(double) * (size_t)n);
  d->r0 = malloc(sizeof(double) * (size_t)n);
  if (!blk || !d->colptr || !d->color || !d->ytmp || !d->yptmp || !d->rtmp || !d->r0) {
    free(adj);
    free(blk);
    return phm_error_set(err, PHM_ENOMEM, "out of memory");
  }
  for (int i = 0; i < n; i++) {
    if (i < d->ix) blk[i] = i / PHM_NSTATE;
    else if (i < d->ie) {
      int ip = 0;
      while (ip + 1 < m->np && m->pair_j[ip + 1] <= i - d->ix) ip++;
      blk[i] = nc + ip;
    } else if (i < d->il) blk[i] = -1; /* ledger */
    else {
      int r = (i < d->im ? i - d->il : i - d->im), ip = 0;
      while (ip + 1 < m->np && m->pair_row[ip + 1] <= r) ip++;
      blk[i] = nc + ip;
    }
  }
  /* column j (block bj) has entries in the rows of the blocks adjacent to bj; the ledger rows keep
   * only their diagonal (their dependence on the other states is left out of the Newton matrix:
   * nothing else depends on them, so this only delays their convergence by one iteration) */
  long nnz = 0;
  for (int j = 0; j < n; j++) {
    int bj = blk[j];
    if (bj < 0) { nnz += 1; continue; }
    for (int i = 0; i < n; i++) {
      int bi = blk[i];
      if (bi >= 0 && adj[(size_t)bi * nb + bj]) nnz++;
    }
  }
  d->nnz = (int)nnz;
  d->rowind = malloc(sizeof(sunindextype) * (size_t)nnz);
  if (!d->rowind) {
    free(adj);
    free(blk);
    return phm_error_set(err, PHM_ENOMEM, "out of memory");
  }
  long k = 0;
  for (int j = 0; j < n; j++) {
    d->colptr[j] = k;
    int bj = blk[j];
    if (bj < 0) { d->rowind[k++] = j; continue; }
    for (int i = 0; i < n; i++) {
      int bi = blk[i];
      if (bi >= 0 && adj[(size_t)bi * nb + bj]) d->rowind[k++] = i;
    }
  }
  d->colptr[n] = k;
  /* greedy colouring of the blocks (distance-2 in the block graph); every column of a block
   * gets a different colour offset: colour = blockcolour * 13 + (index within block) */
  int *bcol = malloc(sizeof(int) * (size_t)nb);
  char *used = malloc((size_t)nb + 1);
  if (!bcol || !used) {
    free(adj); free(blk); free(bcol); free(used);
    return phm_error_set(err, PHM_ENOMEM, "out of memory");
  }
  int nbcol = 0;
  for (int b = 0; b < nb; b++) {
    memset(used, 0, (size_t)nb + 1);
    for (int x = 0; x < nb; x++) {
      if (!adj[(size_t)b * nb + x]) continue;
      for (int z = 0; z < b; z++)
        if (adj[(size_t)x * nb + z]) used[bcol[z]] = 1;
    }
    int cidx = 0;
    while (used[cidx]) cidx++;
    bcol[b] = cidx;
    if (cidx + 1 > nbcol) nbcol = cidx + 1;
  }
  /* a block's columns: a carrier's 13 states, or a pair's lambda (m), mu (m) and joint
   * coordinates (k), k + 2m <= 12 since k + m = 6: 13 colours per block colour (was 18: the
   * leaf spring of benchmarks/scenes.py needs 81 residuals per Jacobian instead of 111) */
  int width = PHM_NSTATE;
  for (int i = 0; i < n; i++) {
    int b = blk[i];
    if (b < 0) { d->color[i] = nbcol * width + (i - d->ie); continue; }
    int off;
    if (b < nc) off = i - PHM_NSTATE * b;
    else {
      int ip = b - nc, mc = m->pair_m[ip];
      if (i < d->ie) off = i - d->ix - m->pair_j[ip] + 2 * mc;
      else if (i < d->im) off = i - d->il - m->pair_row[ip];
      else off = i - d->im - m->pair_row[ip] + mc;
    }
    d->color[i] = bcol[b] * width + off;
  }
  d->ncolor = nbcol * width + (d->il - d->ie);
  free(adj);
  free(blk);
  free(bcol);
  free(used);
  return PHM_OK;
}

/* J = dF/dy + cj dF/dyp by coloured forward differences (no allocation). */
static int ida_jac_klu(realtype t, realtype cj, N_Vector yy, N_Vector yp, N_Vector rr, SUNMatrix J,
                       void *ud, N_Vector t1, N_Vector t2, N_Vector t3) {
  (void)t1; (void)t2; (void)t3;
  dae_t *d = (dae_t *)ud;
  int n = d->n;
  const double *y = N_VGetArrayPointer(yy), *ypv = N_VGetArrayPointer(yp), *r0 = N_VGetArrayPointer(rr);
  sunindextype *cp = SUNSparseMatrix_IndexPointers(J), *ri = SUNSparseMatrix_IndexValues(J);
  double *val = SUNSparseMatrix_Data(J);
  for (int j = 0; j <= n; j++) cp[j] = d->colptr[j];
  for (int k = 0; k < d->nnz; k++) ri[k] = d->rowind[k];
  double sq = sqrt(2.2e-16);
  for (int col = 0; col < d->ncolor; col++) {
    int any = 0;
    memcpy(d->ytmp, y, sizeof(double) * n);
    memcpy(d->yptmp, ypv, sizeof(double) * n);
    for (int j = 0; j < n; j++)
      if (d->color[j] == col) {
        double inc = sq * fmax(fabs(y[j]), fmax(fabs(ypv[j]) / (cj > 0 ? cj : 1), 1e-3));
        d->ytmp[j] += inc;
        d->yptmp[j] += cj * inc;
        d->r0[j] = inc; /* store the increment of column j */
        any = 1;
      }
    if (!any) continue;
    if (dae_residual(d, t, d->ytmp, d->yptmp, d->rtmp)) return 1;
    for (int j = 0; j < n; j++)
      if (d->color[j] == col)
        for (sunindextype k = cp[j]; k < cp[j + 1]; k++)
          val[k] = (d->rtmp[ri[k]] - r0[ri[k]]) / d->r0[j];
  }
  return 0;
}
