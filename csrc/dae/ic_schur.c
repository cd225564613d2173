/* ic_schur.c -- the constraint systems of the consistent initial values (csrc/dae/initial.c) in
 * O(N): the Schur complement S = G D^-1 G^T of the constraint rows (D = I for the minimum-norm
 * projections of positions and velocities, D = M for the acceleration level), sparse (rows r and
 * s couple when their pairs share a carrier) and factored by KLU. G is kept as row blocks (each
 * row touches the two carriers of its pair), never as a dense nk x 6 nc matrix: a chain of 200
 * rigid bodies took 6 s in the dense least-squares problems this replaces, and a chain of 1000
 * would have needed 0.7 GB for them.
 * The pattern and KLU's analysis are set-up work (allocating); a factorization reuses the
 * pivots of the previous one (klu_refactor) and factors afresh only when that is inaccurate. */
#include "dae.h"

#include <klu.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"

struct ic_schur {
  int nk;
  int *rptr, *rows;   /* ncc + 1, rows touching constrained carrier k: rows[rptr[k] ..]         */
  int *side;          /* the same: 0 if the carrier is the pair's a, 1 if its b                 */
  int *sptr, *slot;   /* carrier k's |rows|^2 slots of Sx: slot[sptr[k] + i * nr + j] = (i, j) */
  int *Sp, *Si;       /* CSC pattern of S (rows ascending)                                      */
  double *Sx;         /* S's values                                                             */
  double *Gr;         /* nk x 12: row r's blocks at carriers a (0..5) and b (6..11)            */
  double *xk;         /* scratch: D^-1 G_rc^T of the rows of one carrier                       */
  int maxrows;
  klu_symbolic *sym;
  klu_numeric *num;
  klu_common common;
};

void ic_schur_free(dae_ic_work *w) {
  struct ic_schur *s = w->schur;
  if (!s) return;
  if (s->num) klu_free_numeric(&s->num, &s->common);
  if (s->sym) klu_free_symbolic(&s->sym, &s->common);
  free(s->rptr); free(s->rows); free(s->side); free(s->sptr); free(s->slot);
  free(s->Sp); free(s->Si); free(s->Sx); free(s->Gr); free(s->xk);
  free(s);
  w->schur = NULL;
}

static int cmp_int(const void *a, const void *b) {
  return (*(const int *)a > *(const int *)b) - (*(const int *)a < *(const int *)b);
}

/* The rows of S's column c: every row that shares one of row c's carriers (rc[2 c], rc[2 c + 1]:
 * their constrained indices, -1 for the ground), each once (mark: a row's last column), into
 * out (NULL: only count them). */
static int column_rows(const struct ic_schur *s, const int *rc, int c, int *mark, int *out) {
  int n = 0;
  for (int t = 0; t < 2; t++) {
    int k = rc[2 * c + t];
    if (k < 0) continue;
    for (int q = s->rptr[k]; q < s->rptr[k + 1]; q++)
      if (mark[s->rows[q]] != c) {
        mark[s->rows[q]] = c;
        if (out) out[n] = s->rows[q];
        n++;
      }
  }
  return n;
}

phm_status ic_schur_alloc(dae_t *d, phm_error *err) {
  const phm_model *m = d->m;
  dae_ic_work *w = &d->data.ic;
  int nk = m->ncons, ncc = w->ncc;
  if (nk == 0 || ncc == 0) return PHM_OK;
  struct ic_schur *s = calloc(1, sizeof *s);
  if (!s) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  w->schur = s;
  s->nk = nk;
  /* the rows of each constrained carrier */
  s->rptr = calloc((size_t)ncc + 1, sizeof(int));
  if (!s->rptr) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  for (int ip = 0; ip < m->np; ip++) {
    int ab[2] = {m->pair[ip].a, m->pair[ip].b};
    for (int t = 0; t < 2; t++)
      if (ab[t] >= 0) s->rptr[w->cmap[ab[t]] + 1] += m->pair_m[ip];
  }
  for (int k = 0; k < ncc; k++) s->rptr[k + 1] += s->rptr[k];
  int nr = s->rptr[ncc];
  s->rows = malloc(sizeof(int) * ((size_t)nr + 1));
  s->side = malloc(sizeof(int) * ((size_t)nr + 1));
  int *fill = malloc(sizeof(int) * ((size_t)ncc + 1));
  if (!s->rows || !s->side || !fill) {
    free(fill);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
  memcpy(fill, s->rptr, sizeof(int) * (size_t)ncc);
  for (int ip = 0; ip < m->np; ip++) { /* pairs in order: each carrier's rows ascend */
    int ab[2] = {m->pair[ip].a, m->pair[ip].b};
    for (int t = 0; t < 2; t++)
      if (ab[t] >= 0)
        for (int r = 0; r < m->pair_m[ip]; r++) {
          int q = fill[w->cmap[ab[t]]]++;
          s->rows[q] = m->pair_row[ip] + r;
          s->side[q] = t;
        }
  }
  free(fill);
  /* the pattern of S: column c holds the rows sharing a carrier with row c */
  s->sptr = malloc(sizeof(int) * ((size_t)ncc + 1));
  if (!s->sptr) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  s->sptr[0] = 0;
  s->maxrows = 0;
  for (int k = 0; k < ncc; k++) {
    int n = s->rptr[k + 1] - s->rptr[k];
    s->sptr[k + 1] = s->sptr[k] + n * n;
    if (n > s->maxrows) s->maxrows = n;
  }
  int *deg = calloc((size_t)nk + 1, sizeof(int)), *mark = malloc(sizeof(int) * ((size_t)nk + 1));
  /* rows of each row's two carriers: row r lies in the lists of its pair's carriers */
  int *rc = malloc(sizeof(int) * (2 * (size_t)nk + 1));
  if (!deg || !mark || !rc) {
    free(deg); free(mark); free(rc);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
  for (int ip = 0; ip < m->np; ip++)
    for (int r = 0; r < m->pair_m[ip]; r++) {
      int row = m->pair_row[ip] + r;
      rc[2 * row] = m->pair[ip].a >= 0 ? w->cmap[m->pair[ip].a] : -1;
      rc[2 * row + 1] = m->pair[ip].b >= 0 ? w->cmap[m->pair[ip].b] : -1;
    }
  for (int r = 0; r < nk; r++) mark[r] = -1;
  long nnz = 0;
  for (int c = 0; c < nk; c++) nnz += deg[c] = column_rows(s, rc, c, mark, NULL);
  s->Sp = malloc(sizeof(int) * ((size_t)nk + 1));
  s->Si = malloc(sizeof(int) * ((size_t)nnz + 1));
  s->Sx = malloc(sizeof(double) * ((size_t)nnz + 1));
  s->slot = malloc(sizeof(int) * ((size_t)s->sptr[ncc] + 1));
  s->Gr = malloc(sizeof(double) * 12 * ((size_t)nk + 1));
  s->xk = malloc(sizeof(double) * 6 * ((size_t)s->maxrows + 1));
  if (!s->Sp || !s->Si || !s->Sx || !s->slot || !s->Gr || !s->xk) {
    free(deg); free(mark); free(rc);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
  s->Sp[0] = 0;
  for (int c = 0; c < nk; c++) s->Sp[c + 1] = s->Sp[c] + deg[c];
  for (int r = 0; r < nk; r++) mark[r] = -1;
  for (int c = 0; c < nk; c++)
    qsort(s->Si + s->Sp[c], (size_t)column_rows(s, rc, c, mark, s->Si + s->Sp[c]), sizeof(int), cmp_int);
  free(deg); free(mark); free(rc);
  /* slots: entry (rows[i], rows[j]) of carrier k's contribution, found in column rows[j] */
  for (int k = 0; k < ncc; k++) {
    int q0 = s->rptr[k], n = s->rptr[k + 1] - q0;
    for (int j = 0; j < n; j++) {
      int col = s->rows[q0 + j];
      for (int i = 0; i < n; i++) {
        int row = s->rows[q0 + i], lo = s->Sp[col], hi = s->Sp[col + 1] - 1;
        while (lo < hi) { /* binary search: the column's rows ascend */
          int mid = (lo + hi) / 2;
          if (s->Si[mid] < row) lo = mid + 1; else hi = mid;
        }
        s->slot[s->sptr[k] + i * n + j] = lo;
      }
    }
  }
  klu_defaults(&s->common);
  s->sym = klu_analyze(nk, s->Sp, s->Si, &s->common);
  if (!s->sym) return PHM_FAIL(err, PHM_ESOLVER, "consistent initial values: KLU analysis failed (status %d)", s->common.status);
  return PHM_OK;
}

int ic_schur_available(const dae_ic_work *w) { return w->schur != NULL; }

/* The row blocks of G, g and the prescribed rates vt at poses H (either may be NULL). */
void ic_schur_rows(dae_t *d, const double *H, const double *xs, double time, double *g,
                   double *vt) {
  const phm_model *m = d->m;
  struct ic_schur *s = d->data.ic.schur;
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int r0 = m->pair_row[ip];
    double Ga[6 * PHM_MAXCON], Gb[6 * PHM_MAXCON];
    phm_pair_eval(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                  xs ? xs + m->pair_j[ip] : NULL, time, d->tref, g ? g + r0 : NULL, Ga, Gb,
                  vt ? vt + r0 : NULL);
    for (int r = 0; r < m->pair_m[ip]; r++) {
      memcpy(s->Gr + 12 * (size_t)(r0 + r), Ga + 6 * r, 6 * sizeof(double));
      memcpy(s->Gr + 12 * (size_t)(r0 + r) + 6, Gb + 6 * r, 6 * sizeof(double));
    }
  }
}

/* out[r] = G_r t for the twists tw (nc x 6) with the blocks of the last ic_schur_rows. */
void ic_schur_apply(const dae_t *d, const double *tw, double *out) {
  const phm_model *m = d->m;
  const struct ic_schur *s = d->data.ic.schur;
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    for (int r = 0; r < m->pair_m[ip]; r++) {
      int row = m->pair_row[ip] + r;
      const double *G = s->Gr + 12 * (size_t)row;
      double v = 0;
      for (int j = 0; j < 6; j++) {
        if (pr->a >= 0) v += G[j] * tw[6 * pr->a + j];
        if (pr->b >= 0) v += G[6 + j] * tw[6 * pr->b + j];
      }
      out[row] = v;
    }
  }
}

/* x = D_c^-1 v for constrained carrier clist[k]: D = I (mass 0) or its inertia through the
 * Cholesky factor Lc (mass 1). */
static void dinv(const dae_ic_work *w, int k, int mass, double *x) {
  if (mass) phm_chol6_solve(w->Lc + 36 * w->clist[k], x);
}

int ic_schur_factor(dae_t *d, int mass) {
  dae_ic_work *w = &d->data.ic;
  struct ic_schur *s = w->schur;
  memset(s->Sx, 0, sizeof(double) * (size_t)s->Sp[s->nk]);
  for (int k = 0; k < w->ncc; k++) {
    int q0 = s->rptr[k], n = s->rptr[k + 1] - q0;
    for (int i = 0; i < n; i++) {
      double *x = s->xk + 6 * i;
      memcpy(x, s->Gr + 12 * (size_t)s->rows[q0 + i] + 6 * s->side[q0 + i], 6 * sizeof(double));
      dinv(w, k, mass, x);
    }
    for (int j = 0; j < n; j++) {
      const double *Gj = s->Gr + 12 * (size_t)s->rows[q0 + j] + 6 * s->side[q0 + j];
      for (int i = 0; i < n; i++)
        s->Sx[s->slot[s->sptr[k] + i * n + j]] += phm_dot(Gj, s->xk + 6 * i, 6);
    }
  }
  /* the previous pivots first (no allocation), fresh pivoting when they are poor */
  if (s->num && klu_refactor(s->Sp, s->Si, s->Sx, s->sym, s->num, &s->common) &&
      klu_rcond(s->sym, s->num, &s->common) && s->common.rcond > 1e-12)
    return 0;
  if (s->num) klu_free_numeric(&s->num, &s->common);
  s->num = klu_factor(s->Sp, s->Si, s->Sx, s->sym, &s->common);
  if (!s->num || s->common.status != KLU_OK) return 1;
  if (!klu_rcond(s->sym, s->num, &s->common) || !(s->common.rcond > 1e-12)) return 1;
  return 0;
}

int ic_schur_solve(dae_t *d, int mass, double *rhs, double *delta) {
  dae_ic_work *w = &d->data.ic;
  struct ic_schur *s = w->schur;
  if (!klu_solve(s->sym, s->num, s->nk, 1, rhs, &s->common)) return 1;
  for (int k = 0; k < w->ncc; k++) {
    int q0 = s->rptr[k], n = s->rptr[k + 1] - q0;
    double x[6] = {0};
    for (int i = 0; i < n; i++) {
      const double *G = s->Gr + 12 * (size_t)s->rows[q0 + i] + 6 * s->side[q0 + i];
      for (int j = 0; j < 6; j++) x[j] += G[j] * rhs[s->rows[q0 + i]];
    }
    dinv(w, k, mass, x);
    for (int j = 0; j < 6; j++) delta[6 * w->clist[k] + j] += x[j];
  }
  return 0;
}
