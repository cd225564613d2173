/* linearize.c -- linearization on the tangent space, modes (DESIGN section 7) and static
 * equilibrium by Newton's method with load stepping (sparse LU by KLU); modes use dense LAPACK on
 * the reduced problem. Set-up time code. */
#include "model_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <klu.h>

extern void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n, double *a,
                    const int *lda, double *s, double *u, const int *ldu, double *vt,
                    const int *ldvt, double *work, const int *lwork, int *info);

typedef struct {
  const phm_model *m;
  double time, tref, scale;
  const double *lam; /* constraint wrenches added to the forces (may be NULL) */
  double *wr, *gl, *G, *Hp;
  /* carrier coupling graph (CSR), its distance-2 colouring and the force Jacobian blocks
   * (lin_colour; modes and statics) */
  int *ptr, *nbr, *col, ncol;
  double *Kb;
} lin_t;

/* 1 if x[0..n) are all finite. */
static int all_finite(const double *x, size_t n) {
  for (size_t i = 0; i < n; i++)
    if (!isfinite(x[i])) return 0;
  return 1;
}

/* Generalized forces at poses H: applied wrenches + G^T lambda (nc x 6, body frame). */
static void total_force(lin_t *L, const double *H, double *f) {
  const phm_model *m = L->m;
  phm_applied(m, H, NULL, NULL, L->time, L->tref, L->scale, f, NULL, NULL, NULL, NULL, NULL);
  if (L->lam && m->ncons)
    for (int ip = 0; ip < m->np; ip++) {
      const phm_pair_desc *pr = &m->pair[ip];
      int r0 = m->pair_row[ip], mc = m->pair_m[ip];
      double Ga[36], Gb[36];
      phm_pair_eval(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                    NULL, L->time, L->tref, NULL, Ga, Gb, NULL);
      for (int r = 0; r < mc; r++)
        for (int j = 0; j < 6; j++) {
          if (pr->a >= 0) f[6 * pr->a + j] += Ga[6 * r + j] * L->lam[r0 + r];
          if (pr->b >= 0) f[6 * pr->b + j] += Gb[6 * r + j] * L->lam[r0 + r];
        }
    }
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
  free(L->ptr);
  free(L->nbr);
  free(L->col);
  free(L->Kb);
}

/* ---------------------------------------------------------------- modes */
/* Carrier coupling graph (CSR, self included): carriers that share an element, pair, spring or
 * load. A perturbation of carrier c changes only the forces of its neighbours. */
static phm_status carrier_graph(const phm_model *m, int **ptr_out, int **nbr_out, phm_error *err) {
  int nc = m->nc, ned = m->ne + m->np + m->nl + m->ns;
  int *ea = malloc(sizeof(int) * (size_t)(ned + 1)), *eb = malloc(sizeof(int) * (size_t)(ned + 1));
  int *ptr = calloc((size_t)nc + 1, sizeof(int)), *nbr = NULL, *fill = NULL;
  if (!ea || !eb || !ptr) goto oom;
  int k = 0;
  for (int i = 0; i < m->ne; i++) { ea[k] = m->el[i].a; eb[k++] = m->el[i].b; }
  for (int i = 0; i < m->np; i++) { ea[k] = m->pair[i].a; eb[k++] = m->pair[i].b; }
  for (int i = 0; i < m->nl; i++) { ea[k] = m->load[i].carrier; eb[k++] = m->load[i].reaction; }
  for (int i = 0; i < m->ns; i++) { ea[k] = m->spr[i].a; eb[k++] = m->spr[i].b; }
  for (int c = 0; c < nc; c++) ptr[c + 1] = 1;
  for (int e = 0; e < k; e++)
    if (ea[e] >= 0 && eb[e] >= 0 && ea[e] != eb[e]) { ptr[ea[e] + 1]++; ptr[eb[e] + 1]++; }
  for (int c = 0; c < nc; c++) ptr[c + 1] += ptr[c];
  nbr = malloc(sizeof(int) * (size_t)(ptr[nc] + 1));
  fill = malloc(sizeof(int) * (size_t)(nc + 1));
  if (!nbr || !fill) goto oom;
  for (int c = 0; c < nc; c++) { nbr[ptr[c]] = c; fill[c] = ptr[c] + 1; }
  for (int e = 0; e < k; e++)
    if (ea[e] >= 0 && eb[e] >= 0 && ea[e] != eb[e]) {
      int a = ea[e], b = eb[e], dup = 0;
      for (int q = ptr[a]; q < fill[a]; q++) dup |= nbr[q] == b;
      if (dup) continue;
      nbr[fill[a]++] = b;
      nbr[fill[b]++] = a;
    }
  /* compact away duplicate slots */
  int w = 0;
  for (int c = 0; c < nc; c++) {
    int s0 = ptr[c], s1 = fill[c];
    ptr[c] = w;
    for (int q = s0; q < s1; q++) nbr[w++] = nbr[q];
  }
  ptr[nc] = w;
  free(ea); free(eb); free(fill);
  *ptr_out = ptr;
  *nbr_out = nbr;
  return PHM_OK;
oom:
  free(ea); free(eb); free(ptr); free(nbr); free(fill);
  return phm_error_set(err, PHM_ENOMEM, "out of memory");
}

/* Greedy distance-2 colouring: carriers of one colour share no neighbour. Returns the count. */
static int carrier_colours(int nc, const int *ptr, const int *nbr, int *col, int *mark) {
  int ncol = 0;
  for (int c = 0; c < nc; c++) col[c] = -1;
  for (int c = 0; c < nc; c++) mark[c] = -1;
  for (int c = 0; c < nc; c++) {
    for (int q = ptr[c]; q < ptr[c + 1]; q++)
      for (int q2 = ptr[nbr[q]]; q2 < ptr[nbr[q] + 1]; q2++)
        if (col[nbr[q2]] >= 0) mark[col[nbr[q2]]] = c;
    int k = 0;
    while (k < nc && mark[k] == c) k++;
    col[c] = k;
    if (k + 1 > ncol) ncol = k + 1;
  }
  return ncol;
}

extern void dsygvx_(const int *itype, const char *jobz, const char *range, const char *uplo,
                    const int *n, double *a, const int *lda, double *b, const int *ldb,
                    const double *vl, const double *vu, const int *il, const int *iu,
                    const double *abstol, int *m, double *w, double *z, const int *ldz,
                    double *work, const int *lwork, int *iwork, int *ifail, int *info);
extern double dlamch_(const char *cmach);

/* The coupling graph of L's model, its colouring and room for the force Jacobian blocks. */
static phm_status lin_colour(lin_t *L, phm_error *err) {
  const phm_model *m = L->m;
  int nc = m->nc;
  phm_status st = carrier_graph(m, &L->ptr, &L->nbr, err);
  if (st) return st;
  int *mark = malloc(sizeof(int) * (size_t)(nc + 1));
  L->col = malloc(sizeof(int) * (size_t)nc);
  L->Kb = calloc(36 * (size_t)L->ptr[nc] + 1, sizeof(double));
  if (!mark || !L->col || !L->Kb) {
    free(mark);
    return phm_error_set(err, PHM_ENOMEM, "out of memory");
  }
  L->ncol = carrier_colours(nc, L->ptr, L->nbr, L->col, mark);
  free(mark);
  return PHM_OK;
}

/* Kb[q] = d f_r / d delta_c for block q = (row carrier r, column carrier nbr[q]) of the coupling
 * graph (6 x 6, row-major), f = total_force on the perturbed carriers' charts, f_c(delta) =
 * dexp_{-delta}^T w_c(H_c exp(delta)); central differences, one pass per colour and direction
 * (carriers of one colour share no neighbour, so their columns do not mix). Into L->Kb. */
static void force_jacobian_blocks(lin_t *L, const double *H, double *f1, double *f2) {
  const phm_model *m = L->m;
  int nc = m->nc, ncol = L->ncol;
  const int *col = L->col, *ptr = L->ptr, *nbr = L->nbr;
  double *Kb = L->Kb;
  for (int k = 0; k < ncol; k++)
    for (int j = 0; j < 6; j++) {
      double eps = 1e-6 * (j < 3 ? 1.0 : m->lref);
      for (int side = 0; side < 2; side++) {
        double dl[6] = {0}, md[6] = {0}, D[36], *f = side ? f2 : f1;
        dl[j] = side ? -eps : eps;
        md[j] = -dl[j];
        phm_se3_dexp(md, D);
        memcpy(L->Hp, H, sizeof(double) * 16 * (size_t)nc);
        for (int c = 0; c < nc; c++)
          if (col[c] == k) phm_retract(L->Hp + 16 * c, dl);
        total_force(L, L->Hp, f);
        for (int c = 0; c < nc; c++)
          if (col[c] == k) {
            double w[6];
            for (int i = 0; i < 6; i++) {
              double s = 0;
              for (int q = 0; q < 6; q++) s += D[6 * q + i] * f[6 * c + q];
              w[i] = s;
            }
            memcpy(f + 6 * c, w, sizeof w);
          }
      }
      for (int r = 0; r < nc; r++)
        for (int q = ptr[r]; q < ptr[r + 1]; q++)
          if (col[nbr[q]] == k)
            for (int i = 0; i < 6; i++)
              Kb[36 * (size_t)q + 6 * i + j] = (f1[6 * r + i] - f2[6 * r + i]) / (2 * eps);
    }
}

/* Structure: the stiffness K = -df/ddelta and damping D = -df/dt are block-sparse (only
 * neighbouring carriers couple) and computed by coloured differences; the constraint Jacobian G
 * touches only the carriers of the pairs, so the null-space basis is Z = diag(U0, I): U0 from the
 * SVD of G restricted to the constrained carriers, identity on the free ones. The reduced problem
 * Kr y = omega^2 Mr y is solved for the lowest modes only (dsygvx). */
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
  int *cmap = NULL, *clist = NULL, *red = NULL;
  int *iwork = NULL, *ifail = NULL;
  double *H = malloc(sizeof(double) * 16 * (size_t)nc);
  double *f0 = malloc(sizeof(double) * (size_t)n6), *f1 = malloc(sizeof(double) * (size_t)n6);
  double *f2 = malloc(sizeof(double) * (size_t)n6), *tw = calloc((size_t)n6, sizeof(double));
  double *Db = NULL, *Gc = NULL, *U = NULL, *sv = NULL, *work = NULL;
  double *Kr = NULL, *Mr = NULL, *Dr = NULL, *ev = NULL, *Y = NULL;
  if (!H || !f0 || !f1 || !f2 || !tw) goto oom;
  if ((st = lin_alloc(&L, m, err)) || (st = lin_colour(&L, err))) goto done;
  const int *ptr = L.ptr, *nbr = L.nbr, *col = L.col, ncol = L.ncol;
  double *Kb = L.Kb;
  int nb = ptr[nc];
  Db = calloc((size_t)nb * 36, sizeof(double));
  if (!Db) goto oom;
  L.time = time;
  L.tref = phm_model_tref(m, time, NULL);
  L.scale = 1.0;
  L.lam = lambda;
  for (int c = 0; c < nc; c++) memcpy(H + 16 * c, poses ? poses + 16 * c : m->car[c].H0, 16 * sizeof(double));
  /* stiffness K = -d f / d delta, block-sparse */
  force_jacobian_blocks(&L, H, f1, f2);
  for (size_t i = 0; i < (size_t)nb * 36; i++) Kb[i] = -Kb[i];
  /* damping D = -dw/dt (linear in t: one-sided differences are exact up to round-off) */
  phm_applied(m, H, tw, NULL, time, L.tref, 1.0, f0, NULL, NULL, NULL, NULL, NULL);
  for (int k = 0; k < ncol; k++)
    for (int j = 0; j < 6; j++) {
      for (int c = 0; c < nc; c++) tw[6 * c + j] = col[c] == k ? 1.0 : 0.0;
      phm_applied(m, H, tw, NULL, time, L.tref, 1.0, f2, NULL, NULL, NULL, NULL, NULL);
      for (int c = 0; c < nc; c++) tw[6 * c + j] = 0.0;
      for (int r = 0; r < nc; r++)
        for (int q = ptr[r]; q < ptr[r + 1]; q++)
          if (col[nbr[q]] == k)
            for (int i = 0; i < 6; i++) Db[36 * (size_t)q + 6 * i + j] = -(f2[6 * r + i] - f0[6 * r + i]);
    }
  /* constrained carriers and the null space of G restricted to them */
  cmap = malloc(sizeof(int) * (size_t)nc);
  clist = malloc(sizeof(int) * (size_t)(nc + 1));
  if (!cmap || !clist) goto oom;
  int ncc = 0;
  for (int c = 0; c < nc; c++) cmap[c] = -1;
  if (nk > 0)
    for (int ip = 0; ip < m->np; ip++) {
      int ab[2] = {m->pair[ip].a, m->pair[ip].b};
      for (int s = 0; s < 2; s++)
        if (ab[s] >= 0 && cmap[ab[s]] < 0) { cmap[ab[s]] = ncc; clist[ncc++] = ab[s]; }
    }
  int n6c = 6 * ncc, rank = 0, n0 = n6c;
  if (nk > 0 && n6c > 0) {
    Gc = calloc((size_t)n6c * nk, sizeof(double)); /* column-major G^T: n6c x nk */
    U = malloc(sizeof(double) * (size_t)n6c * n6c);
    sv = malloc(sizeof(double) * (size_t)(nk < n6c ? nk : n6c) + sizeof(double));
    if (!Gc || !U || !sv) goto oom;
    for (int ip = 0; ip < m->np; ip++) {
      const phm_pair_desc *pr = &m->pair[ip];
      int r0 = m->pair_row[ip], mc = m->pair_m[ip];
      double Ga[36], Gb[36];
      phm_pair_eval(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                    NULL, time, L.tref, NULL, Ga, Gb, NULL);
      for (int r = 0; r < mc; r++)
        for (int j = 0; j < 6; j++) {
          if (pr->a >= 0) Gc[(size_t)(r0 + r) * n6c + 6 * cmap[pr->a] + j] += Ga[6 * r + j];
          if (pr->b >= 0) Gc[(size_t)(r0 + r) * n6c + 6 * cmap[pr->b] + j] += Gb[6 * r + j];
        }
    }
    int lw = -1, info = 0, one = 1;
    double wq;
    dgesvd_("A", "N", &n6c, &nk, Gc, &n6c, sv, U, &n6c, NULL, &one, &wq, &lw, &info);
    lw = (int)wq + 1;
    work = malloc(sizeof(double) * (size_t)lw);
    if (!work) goto oom;
    dgesvd_("A", "N", &n6c, &nk, Gc, &n6c, sv, U, &n6c, NULL, &one, work, &lw, &info);
    free(work);
    work = NULL;
    if (info != 0) {
      st = phm_error_set(err, PHM_ESINGULAR, "SVD of the constraint Jacobian failed (dgesvd info %d)", info);
      goto done;
    }
    int ns = nk < n6c ? nk : n6c;
    for (int i = 0; i < ns; i++)
      if (sv[i] > 1e-10 * sv[0]) rank++;
    n0 = n6c - rank;
  }
  /* reduced coordinates: first the n0 null-space directions of the constrained carriers (U0 =
   * columns rank.. of U), then 6 per free carrier in carrier order (red[c]: first index) */
  red = malloc(sizeof(int) * (size_t)nc);
  if (!red) goto oom;
  int nr = n0;
  for (int c = 0; c < nc; c++) {
    red[c] = cmap[c] < 0 ? nr : -1;
    if (cmap[c] < 0) nr += 6;
  }
  if (nr == 0) {
    st = phm_error_set(err, PHM_EINVAL, "the mechanism has no degree of freedom: no modes");
    goto done;
  }
  Kr = calloc((size_t)nr * nr, sizeof(double));
  Mr = calloc((size_t)nr * nr, sizeof(double));
  Dr = calloc((size_t)nr * nr, sizeof(double));
  ev = malloc(sizeof(double) * (size_t)nr);
  if (!Kr || !Mr || !Dr || !ev) goto oom;
  const double *U0 = U ? U + (size_t)rank * n6c : NULL; /* column a of U0: U0[a * n6c + i] */
  /* X_r = Z^T X Z block by block; (Kr, Dr) from the blocks, Mr from the block-diagonal mass */
  for (int w = 0; w < 3; w++) {
    double *out = w == 0 ? Kr : w == 1 ? Dr : Mr;
    for (int r = 0; r < nc; r++)
      for (int q = ptr[r]; q < ptr[r + 1]; q++) {
        int c = nbr[q];
        const double *B;
        if (w < 2) B = (w == 0 ? Kb : Db) + 36 * (size_t)q;
        else if (c == r) B = m->car[c].M;
        else continue;
        if (red[r] >= 0 && red[c] >= 0) {
          for (int i = 0; i < 6; i++)
            for (int j = 0; j < 6; j++) out[(size_t)(red[r] + i) * nr + red[c] + j] += B[6 * i + j];
        } else if (red[r] >= 0) { /* row free, column constrained: B U0 */
          int c6 = 6 * cmap[c];
          for (int i = 0; i < 6; i++)
            for (int a = 0; a < n0; a++) {
              double s = 0;
              for (int j = 0; j < 6; j++) s += B[6 * i + j] * U0[(size_t)a * n6c + c6 + j];
              out[(size_t)(red[r] + i) * nr + a] += s;
            }
        } else if (red[c] >= 0) { /* row constrained: U0^T B */
          int r6 = 6 * cmap[r];
          for (int a = 0; a < n0; a++)
            for (int j = 0; j < 6; j++) {
              double s = 0;
              for (int i = 0; i < 6; i++) s += U0[(size_t)a * n6c + r6 + i] * B[6 * i + j];
              out[(size_t)a * nr + red[c] + j] += s;
            }
        } else { /* both constrained: U0^T B U0 */
          int r6 = 6 * cmap[r], c6 = 6 * cmap[c];
          for (int b = 0; b < n0; b++) {
            double BU[6];
            for (int i = 0; i < 6; i++) {
              double s = 0;
              for (int j = 0; j < 6; j++) s += B[6 * i + j] * U0[(size_t)b * n6c + c6 + j];
              BU[i] = s;
            }
            for (int a = 0; a < n0; a++) {
              double s = 0;
              for (int i = 0; i < 6; i++) s += U0[(size_t)a * n6c + r6 + i] * BU[i];
              out[(size_t)a * nr + b] += s;
            }
          }
        }
      }
    for (int a = 0; a < nr; a++)
      for (int b = 0; b < a; b++) {
        double s = 0.5 * (out[(size_t)a * nr + b] + out[(size_t)b * nr + a]);
        out[(size_t)a * nr + b] = out[(size_t)b * nr + a] = s;
      }
  }
  if (!all_finite(Kr, (size_t)nr * nr) || !all_finite(Mr, (size_t)nr * nr) ||
      !all_finite(Dr, (size_t)nr * nr)) {
    st = phm_error_set(err, PHM_ESOLVER, "modes: the linearized stiffness, damping or mass is not "
                       "finite: the model's numbers overflow double precision");
    goto done;
  }
  int nf = nmodes < nr ? nmodes : nr, mfound = 0;
  Y = malloc(sizeof(double) * (size_t)nr * nf);
  iwork = malloc(sizeof(int) * 5 * (size_t)nr);
  ifail = malloc(sizeof(int) * (size_t)nr);
  if (!Y || !iwork || !ifail) goto oom;
  {
    int one = 1, lw = -1, info = 0;
    double wq, vl = 0, vu = 0, abstol = 2 * dlamch_("S");
    dsygvx_(&one, "V", "I", "U", &nr, Kr, &nr, Mr, &nr, &vl, &vu, &one, &nf, &abstol, &mfound, ev,
            Y, &nr, &wq, &lw, iwork, ifail, &info);
    lw = (int)wq + 1;
    if (lw < 8 * nr) lw = 8 * nr;
    work = malloc(sizeof(double) * (size_t)lw);
    if (!work) goto oom;
    dsygvx_(&one, "V", "I", "U", &nr, Kr, &nr, Mr, &nr, &vl, &vu, &one, &nf, &abstol, &mfound, ev,
            Y, &nr, work, &lw, iwork, ifail, &info);
    if (info != 0 || mfound < nf) {
      st = phm_error_set(err, PHM_ESINGULAR, "generalized eigenproblem failed (dsygvx info %d, %d of "
                         "%d eigenvalues found%s)", info, mfound, nf,
                         info > nr ? ": mass matrix not positive definite" : "");
      goto done;
    }
  }
  for (int k = 0; k < nf; k++) {
    double lamk = ev[k];
    omega[k] = lamk >= 0 ? sqrt(lamk) : -sqrt(-lamk);
    const double *yk = Y + (size_t)k * nr; /* column-major: eigenvector k is contiguous */
    if (zeta) {
      double s = 0;
      for (int a = 0; a < nr; a++) {
        double t = 0;
        for (int b = 0; b < nr; b++) t += Dr[(size_t)a * nr + b] * yk[b];
        s += yk[a] * t;
      }
      zeta[k] = omega[k] > 0 ? s / (2 * omega[k]) : 0.0;
    }
    if (shapes)
      for (int c = 0; c < nc; c++)
        for (int i = 0; i < 6; i++) {
          double s = 0;
          if (red[c] >= 0) s = yk[red[c] + i];
          else
            for (int a = 0; a < n0; a++) s += U0[(size_t)a * n6c + 6 * cmap[c] + i] * yk[a];
          shapes[(size_t)k * n6 + 6 * c + i] = s;
        }
  }
  if (!all_finite(omega, (size_t)nf) || (zeta && !all_finite(zeta, (size_t)nf)) ||
      (shapes && !all_finite(shapes, (size_t)nf * n6))) {
    st = phm_error_set(err, PHM_ESOLVER, "modes: non-finite frequencies, damping ratios or mode "
                       "shapes: the model's numbers overflow double precision");
    goto done;
  }
  *nfound = nf;
  goto done;
oom:
  st = phm_error_set(err, PHM_ENOMEM, "out of memory");
done:
  lin_free(&L);
  free(cmap); free(clist); free(red);
  free(iwork); free(ifail);
  free(H); free(f0); free(f1); free(f2); free(tw);
  free(Db); free(Gc); free(U); free(sv); free(work);
  free(Kr); free(Mr); free(Dr); free(ev); free(Y);
  return st;
}

/* ---------------------------------------------------------------- statics */
/* One Newton solve at load scale s from (H, lam); returns 0 on convergence. */
/* ---------------------------------------------------------------- statics */
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
    return phm_error_set(err, PHM_ENOMEM, "out of memory");
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
  if (!S->sym) return phm_error_set(err, PHM_ESOLVER, "static equilibrium: KLU analysis failed (status %d)", S->common.status);
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
    total_force(L, H, R);
    if (nk) phm_constraints_dense(m, H, NULL, L->time, L->tref, R + n6, NULL, NULL);
    /* Jacobian: force blocks by coloured differences (O(N) force evaluations per iteration
     * instead of O(N^2) column by column), constraint rows dg/ddelta = G, multiplier columns G^T;
     * sparse LU (KLU) */
    force_jacobian_blocks(L, H, f1, f2);
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
  if (!m || !poses_out) return phm_error_set(err, PHM_EINVAL, "phm_static: NULL argument");
  if (steps < 1) return phm_error_set(err, PHM_EINVAL, "load steps must be >= 1 (got %d)", steps);
  if (!(tol > 0)) return phm_error_set(err, PHM_EINVAL, "tolerance must be > 0 (got %g)", tol);
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
    st = phm_error_set(err, PHM_ENOMEM, "out of memory");
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
        st = phm_error_set(err, PHM_ESOLVER, "static equilibrium: Newton failed at load factor %.6g after step halving (%d iterations)%s", snew, it,
                           pre_failed ? "; it also failed without load (unconstrained rigid-body motion or incompatible constraints?)" : "");
        goto done;
      }
      continue;
    }
    s = snew;
  }
  if (!all_finite(poses_out, 16 * (size_t)nc) || !all_finite(lam, (size_t)nk)) {
    st = phm_error_set(err, PHM_ESOLVER, "static equilibrium: non-finite poses or constraint "
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
