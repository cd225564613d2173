/* linearize.c -- linearization on the tangent space (docs/method.md section 7): the generalized
 * forces f(H) = applied + G^T lambda at poses H and their Jacobian blocks df/ddelta over the
 * carrier coupling graph (csrc/model/graph.c): the se3 elements', gravity's and the pairs' G^T
 * lambda blocks in closed form (phm_element_tangent, phm_gravity_tangent, phm_pair_tangent), the
 * rest (loads, springs, actuators) by coloured central differences on the colours of the carriers
 * they act on; read by modes (modes.c) and statics (statics.c).
 * Set-up time code: allocates. */
#include "solve.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"
#include "pose.h"

/* Generalized forces at poses H: applied wrenches + G^T lambda (nc x 6, body frame); with
 * remainder, only what has no closed-form tangent (loads, springs, actuators). */
static void lin_forces(lin_t *L, const double *H, int remainder, double *f) {
  const phm_model *m = L->m;
  phm_applied_pairs(m, NULL, H, NULL, NULL, L->time, L->tref, L->scale, remainder, f, NULL, NULL,
                    NULL, NULL, NULL);
  if (!remainder && L->lam && m->ncons) phm_constraint_forces(m, H, L->time, L->tref, L->lam, f);
}
void lin_total_force(lin_t *L, const double *H, double *f) { lin_forces(L, H, 0, f); }

/* The slot of block (row carrier r, column carrier c) in the coupling graph's lists. */
static int lin_slot(const lin_t *L, int r, int c) {
  for (int q = L->ptr[r]; q < L->ptr[r + 1]; q++)
    if (L->nbr[q] == c) return q;
  return -1; /* not reached: an element's carriers are neighbours */
}

/* K += dw/ddelta (6 x 6) - 1/2 ad*_(.) w: a carrier's own block of f_c(delta) =
 * dexp_{-delta}^T w_c(H_c exp(delta)) for a wrench w (with its derivative Kw, NULL: none). */
static void add_own_block(double *K, const double *Kw, int ldk, const double w[6]) {
  for (int j = 0; j < 6; j++) {
    double ej[6] = {0}, z[6];
    ej[j] = 1.0;
    phm_ad_dual_apply(ej, w, z);
    for (int i = 0; i < 6; i++) K[6 * i + j] += (Kw ? Kw[ldk * i + j] : 0.0) - 0.5 * z[i];
  }
}

/* Add the closed-form blocks at poses H (at rest) -- the se3 elements' (phm_element_tangent),
 * gravity's (phm_gravity_tangent, x L->scale) and the pairs' constraint wrenches G^T L->lam
 * (phm_pair_tangent: their geometric stiffness) -- to Kb (if not NULL; d f/d delta, with f_c's
 * chart factor dexp_{-delta}^T: its derivative -1/2 ad*_(.) w_c on the diagonal blocks) and, if
 * Db is not NULL, the elements' to Db (d f/d t: the damping, the same at any twist since the
 * wrenches are affine in them). */
void lin_closed_form_blocks(const lin_t *L, const double *H, double *Kb, double *Db) {
  const phm_model *m = L->m;
  static const double zero[6] = {0};
  for (int ie = 0; ie < m->ne; ie++) {
    const phm_element_desc *e = &m->el[ie];
    double w[12], Kx[144], Ct[144];
    phm_element_tangent(e, H + 16 * e->a, H + 16 * e->b, zero, zero, w, w + 6, Kx, Db ? Ct : NULL);
    int cr[2] = {e->a, e->b};
    for (int bi = 0; bi < 2; bi++)
      for (int bj = 0; bj < 2; bj++) {
        int q = lin_slot(L, cr[bi], cr[bj]);
        if (q < 0) continue;
        double *K = Kb ? Kb + 36 * (size_t)q : NULL, *Dq = Db ? Db + 36 * (size_t)q : NULL;
        const double *kx = Kx + 12 * 6 * bi + 6 * bj, *ct = Ct + 12 * 6 * bi + 6 * bj;
        if (Dq)
          for (int i = 0; i < 6; i++)
            for (int j = 0; j < 6; j++) Dq[6 * i + j] += ct[12 * i + j];
        if (!K) continue;
        if (bi == bj) add_own_block(K, kx, 12, w + 6 * bi);
        else
          for (int i = 0; i < 6; i++)
            for (int j = 0; j < 6; j++) K[6 * i + j] += kx[12 * i + j];
      }
  }
  if (!Kb) return;
  double gn = fabs(m->gravity[0]) + fabs(m->gravity[1]) + fabs(m->gravity[2]);
  for (int c = 0; gn > 0 && c < m->nc; c++) {
    double w[6], Kg[36];
    phm_gravity_tangent(m, c, H + 16 * c, L->scale, w, Kg);
    add_own_block(Kb + 36 * (size_t)lin_slot(L, c, c), Kg, 6, w);
  }
  for (int ip = 0; L->lam && ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int cr[2] = {pr->a, pr->b}, mc = m->pair_m[ip];
    const double *lam = L->lam + m->pair_row[ip];
    phm_pair_data pd;
    double Kl[144], w[12] = {0};
    phm_pair_tangent(m, ip, cr[0] >= 0 ? H + 16 * cr[0] : NULL, cr[1] >= 0 ? H + 16 * cr[1] : NULL,
                     NULL, NULL, NULL, L->time, L->tref, lam, NULL, &pd, NULL, NULL, NULL, Kl, NULL);
    for (int r = 0; r < mc; r++) /* the wrenches G_a^T lam, G_b^T lam */
      for (int j = 0; j < 6; j++) {
        w[j] += pd.Ga[6 * r + j] * lam[r];
        w[6 + j] += pd.Gb[6 * r + j] * lam[r];
      }
    for (int bi = 0; bi < 2; bi++)
      for (int bj = 0; bj < 2; bj++) {
        if (cr[bi] < 0 || cr[bj] < 0) continue;
        double *K = Kb + 36 * (size_t)lin_slot(L, cr[bi], cr[bj]);
        const double *kl = Kl + 12 * 6 * bi + 6 * bj;
        if (bi == bj) add_own_block(K, kl, 12, w + 6 * bi);
        else
          for (int i = 0; i < 6; i++)
            for (int j = 0; j < 6; j++) K[6 * i + j] += kl[12 * i + j];
      }
  }
}

phm_status lin_alloc(lin_t *L, const phm_model *m, phm_error *err) {
  int n6 = 6 * m->nc;
  L->m = m;
  L->wr = malloc(sizeof(double) * (size_t)n6);
  L->gl = malloc(sizeof(double) * (size_t)n6);
  L->G = malloc(sizeof(double) * ((size_t)m->ncons * n6 + 1));
  L->Hp = malloc(sizeof(double) * 16 * (size_t)m->nc);
  if (!L->wr || !L->gl || !L->G || !L->Hp) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  return PHM_OK;
}
void lin_free(lin_t *L) {
  free(L->wr);
  free(L->gl);
  free(L->G);
  free(L->Hp);
  free(L->ptr);
  free(L->nbr);
  free(L->col);
  free(L->fdcol);
  free(L->Kb);
}

/* The coupling graph of L's model, its colouring and room for the force Jacobian blocks. */
phm_status lin_colour(lin_t *L, phm_error *err) {
  const phm_model *m = L->m;
  int nc = m->nc;
  phm_status st = phm_carrier_graph(m, 0, &L->ptr, &L->nbr, err);
  if (st) return st;
  int *mark = malloc(sizeof(int) * (size_t)(nc + 1));
  L->col = malloc(sizeof(int) * (size_t)nc);
  L->Kb = calloc(36 * (size_t)L->ptr[nc] + 1, sizeof(double));
  if (!mark || !L->col || !L->Kb) {
    free(mark);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
  L->ncol = phm_graph_colours(nc, L->ptr, L->nbr, L->col, mark);
  /* the colours the differences need: those of the carriers a spring, load or actuator acts on */
  L->fdcol = calloc((size_t)L->ncol + 1, 1);
  if (!L->fdcol) {
    free(mark);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
  phm_remainder_carriers(m, mark);
  for (int c = 0; c < nc; c++)
    if (mark[c]) L->fdcol[L->col[c]] = 1;
  free(mark);
  return PHM_OK;
}

/* Kb[q] = d f_r / d delta_c for block q = (row carrier r, column carrier nbr[q]) of the coupling
 * graph (6 x 6, row-major), f = lin_total_force on the perturbed carriers' charts, f_c(delta) =
 * dexp_{-delta}^T w_c(H_c exp(delta)): the elements', gravity's and pairs' part in closed form
 * (lin_closed_form_blocks), the rest by central differences, one pass per colour that holds a
 * carrier a load, spring or actuator acts on (L->fdcol) and direction (carriers of one colour
 * share no neighbour, so their columns do not mix). Into L->Kb. */
void lin_force_jacobian_blocks(lin_t *L, const double *H, double *f1, double *f2) {
  const phm_model *m = L->m;
  int nc = m->nc, ncol = L->ncol;
  const int *col = L->col, *ptr = L->ptr, *nbr = L->nbr;
  double *Kb = L->Kb;
  memset(Kb, 0, sizeof(double) * 36 * (size_t)ptr[nc]);
  for (int k = 0; k < ncol; k++)
    for (int j = 0; j < 6 && L->fdcol[k]; j++) {
      double eps = 1e-6 * (j < 3 ? 1.0 : m->lref);
      for (int side = 0; side < 2; side++) {
        double dl[6] = {0}, md[6] = {0}, D[36], *f = side ? f2 : f1;
        dl[j] = side ? -eps : eps;
        md[j] = -dl[j];
        phm_se3_dexp(md, D);
        memcpy(L->Hp, H, sizeof(double) * 16 * (size_t)nc);
        for (int c = 0; c < nc; c++)
          if (col[c] == k) phm_retract(L->Hp + 16 * c, dl);
        lin_forces(L, L->Hp, 1, f);
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
  lin_closed_form_blocks(L, H, Kb, NULL);
}


void lin_kkt_free(lin_kkt_t *S) {
  if (S->num) klu_free_numeric(&S->num, &S->common);
  if (S->sym) klu_free_symbolic(&S->sym, &S->common);
  free(S->Ap); free(S->Ai); free(S->src); free(S->Ax);
}

static int cmp_int(const void *a, const void *b) { return (*(const int *)a > *(const int *)b) - (*(const int *)a < *(const int *)b); }

phm_status lin_kkt_build(lin_kkt_t *S, const lin_t *L, phm_error *err) {
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
void lin_constraint_blocks(const lin_t *L, const double *H, double *Gp) {
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

int lin_kkt_factor(lin_kkt_t *S, const double *Kb, const double *Gp) {
  for (int k = 0; k < S->Ap[S->n]; k++) S->Ax[k] = S->src[k] >= 0 ? Kb[S->src[k]] : Gp[-S->src[k] - 1];
  if (S->num) klu_free_numeric(&S->num, &S->common);
  S->num = klu_factor(S->Ap, S->Ai, S->Ax, S->sym, &S->common);
  return !S->num || S->common.status != KLU_OK;
}

int lin_kkt_solve(lin_kkt_t *S, double *x) { return !klu_solve(S->sym, S->num, S->n, 1, x, &S->common); }
