/* jacobian.c -- the Jacobian dF/dy + cj dF/dy' of the DAE: its sparsity pattern from the block
 * structure (carriers couple through elements, pairs, springs and loads; a pair's multipliers
 * and joint coordinates through its two carriers: the coupling graph of csrc/model/graph.c), a
 * colouring of its columns, and its values: the se3 elements', gravity's and the carriers' own
 * terms in closed form, the remainder (pairs, loads, springs, actuators) by coloured forward
 * differences. */
#include "dae.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "linalg.h"
#include "phm_check.h"
#include "pose.h"

/* The rows of a column of block b, ascending, into rows (NULL: only count them): the states of
 * the blocks coupled to b (nb: b's coupling-graph neighbours sorted ascending, nnb of them). A
 * carrier's states come first (they precede the joint coordinates), then the pairs' joint
 * coordinates, multipliers lambda and mu, each range in pair order. A pair without joint
 * coordinates leaves itself out: its rows are constraints, which its own multipliers do not
 * enter. */
static int block_rows(const dae_t *d, int b, const int *nb, int nnb, sunindextype *rows) {
  const phm_model *m = d->m;
  int nc = m->nc, cnt = 0, q = 0;
  for (; q < nnb && nb[q] < nc; q++) {
    if (rows)
      for (int i = 0; i < PHM_NSTATE; i++) rows[cnt + i] = PHM_NSTATE * nb[q] + i;
    cnt += PHM_NSTATE;
  }
  int q0 = q;
  for (int part = 0; part < 3; part++)
    for (q = q0; q < nnb; q++) {
      int ip = nb[q] - nc, first, len;
      if (nb[q] == b && m->pair_k[ip] == 0) continue;
      if (part == 0) first = d->ix + m->pair_j[ip], len = m->pair_k[ip];
      else first = (part == 1 ? d->il : d->im) + m->pair_row[ip], len = m->pair_m[ip];
      if (rows)
        for (int i = 0; i < len; i++) rows[cnt + i] = first + i;
      cnt += len;
    }
  return cnt;
}

/* The blocks of the state: carrier c's 13 states form block c; pair ip's joint coordinates,
 * lambda and mu form block nc + ip; the ledger belongs to none (no row depends on it). A
 * state's column couples to the rows of the blocks next to its block in the coupling graph of
 * carriers and pairs (csrc/model/graph.c); the ledger rows keep only their diagonal (their
 * dependence on the other states is left out of the Newton matrix: nothing else depends on
 * them, so this only delays their convergence by one iteration). */
phm_status dae_jacobian_pattern(dae_t *d, phm_error *err) {
  const phm_model *m = d->m;
  int n = d->n, nc = m->nc, nb = nc + m->np;
  int *ptr = NULL, *nbr = NULL, *srt = NULL, *fill = NULL, *blk = NULL, *bcol = NULL;
  phm_status st = phm_carrier_graph(m, 1, &ptr, &nbr, err);
  if (st) return st;
  free(d->colptr);
  free(d->rowind);
  free(d->color);
  d->rowind = NULL;
  srt = malloc(sizeof(int) * (size_t)(ptr[nb] + 1));
  fill = malloc(sizeof(int) * (size_t)(nb + 1));
  blk = malloc(sizeof(int) * (size_t)(n + 1));
  bcol = malloc(sizeof(int) * (size_t)(nb + 1));
  d->colptr = malloc(sizeof(sunindextype) * (size_t)(n + 1));
  d->color = malloc(sizeof(int) * (size_t)(n + 1));
  if (!srt || !fill || !blk || !bcol || !d->colptr || !d->color) goto oom;
  /* every neighbour list in ascending order: the graph is symmetric, so listing v in the lists
   * of its neighbours for v = 0, 1, ... sorts them (one pass, no comparison sort) */
  for (int v = 0; v < nb; v++) fill[v] = ptr[v];
  for (int v = 0; v < nb; v++)
    for (int q = ptr[v]; q < ptr[v + 1]; q++) srt[fill[nbr[q]]++] = v;
  for (int i = 0; i < n; i++) blk[i] = -1; /* the ledger */
  for (int i = 0; i < d->ix; i++) blk[i] = i / PHM_NSTATE;
  for (int ip = 0; ip < m->np; ip++) {
    for (int c = 0; c < m->pair_k[ip]; c++) blk[d->ix + m->pair_j[ip] + c] = nc + ip;
    for (int r = 0; r < m->pair_m[ip]; r++)
      blk[d->il + m->pair_row[ip] + r] = blk[d->im + m->pair_row[ip] + r] = nc + ip;
  }
  long nnz = 0;
  for (int j = 0; j < n; j++) {
    int bj = blk[j];
    nnz += bj < 0 ? 1 : block_rows(d, bj, srt + ptr[bj], ptr[bj + 1] - ptr[bj], NULL);
  }
  if (nnz > 2147483647L) {
    st = PHM_FAIL(err, PHM_EINVAL, "the Jacobian has %ld nonzeros, more than KLU's int indices hold", nnz);
    goto fail;
  }
  d->nnz = (int)nnz;
  d->rowind = malloc(sizeof(sunindextype) * (size_t)(nnz + 1));
  if (!d->rowind) goto oom;
  long k = 0;
  for (int j = 0; j < n; j++) {
    d->colptr[j] = k;
    int bj = blk[j];
    if (bj < 0) d->rowind[k++] = j;
    else k += block_rows(d, bj, srt + ptr[bj], ptr[bj + 1] - ptr[bj], d->rowind + k);
  }
  d->colptr[n] = k;
  /* greedy distance-2 colouring of the blocks (two blocks of one colour share no neighbour);
   * every column of a block gets a different colour offset: colour = blockcolour * 13 + (index
   * within block). A block's columns: a carrier's 13 states, or a pair's lambda (m), mu (m) and
   * joint coordinates (k), k + 2m <= 12 since k + m = 6: 13 colours per block colour (was 18:
   * the leaf spring of benchmarks/scenes.py needs 81 residuals per Jacobian instead of 111) */
  int nbcol = phm_graph_colours(nb, ptr, nbr, bcol, fill);
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
  goto done;
oom:
  st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
fail:
  free(d->colptr);
  free(d->rowind);
  free(d->color);
  d->colptr = d->rowind = NULL;
  d->color = NULL;
done:
  free(ptr);
  free(nbr);
  free(srt);
  free(fill);
  free(blk);
  free(bcol);
  return st;
}

/* The position of entry (row, col) in the pattern, -1 if it is not there (binary search: each
 * column's rows ascend). */
static sunindextype entry(const dae_t *d, int row, int col) {
  sunindextype lo = d->colptr[col], hi = d->colptr[col + 1] - 1;
  while (lo <= hi) {
    sunindextype mid = lo + (hi - lo) / 2;
    if (d->rowind[mid] == row) return mid;
    if (d->rowind[mid] < row) lo = mid + 1;
    else hi = mid - 1;
  }
  return -1;
}

/* val[(r0 + i, c0 + j)] += B[ldb i + j] for i < nr, j < ncl: a block inside one carrier's rows,
 * which are consecutive in every column that holds them. */
static void add_block(const dae_t *d, double *val, int r0, int nr, int c0, int ncl,
                      const double *B, int ldb) {
  for (int j = 0; j < ncl; j++) {
    sunindextype k = entry(d, r0, c0 + j);
    if (k < 0) continue; /* not reached: the pattern holds every carrier block it is given */
    for (int i = 0; i < nr; i++) val[k + i] += B[ldb * i + j];
  }
}

/* dxi/dq (3 x 4): the body rotation of a change dq of the (not necessarily unit) quaternion q,
 * dw = 2 vec(conj(q) (x) dq)/|q|^2 (phm_quat_to_rot normalizes q). */
static void quat_chart(const double q[4], double E[12]) {
  double s = 2.0 / (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  double Ev[12] = {-q[1], q[0], q[3], -q[2], -q[2], -q[3], q[0], q[1], -q[3], q[2], -q[1], q[0]};
  for (int i = 0; i < 12; i++) E[i] = s * Ev[i];
}

/* The closed-form part of the Jacobian at (y, y') (the poses and twists in d->data): each
 * carrier's kinematic rows q' = 1/2 q (x) (0, w), p' = R v and momentum rows M t' - ad*_t M t
 * - gravity in its own states, and each se3 element's wrenches (phm_element_tangent) in the states of its
 * two carriers, through the chart (q, p) -> body perturbation [dxi/dq, 0; 0, R^T]. */
static void jacobian_closed_form(dae_t *d, double cj, const double *y, double *val) {
  const phm_model *m = d->m;
  const phm_data *D = &d->data;
  double gn = fabs(m->gravity[0]) + fabs(m->gravity[1]) + fabs(m->gravity[2]);
  for (int c = 0; c < m->nc; c++) {
    const double *q = y + PHM_NSTATE * c, *t = q + 7, *Hc = D->H + 16 * c, *M = m->car[c].M;
    int o = PHM_NSTATE * c;
    double B[PHM_NSTATE * PHM_NSTATE] = {0}; /* rows and columns: the carrier's 13 states */
#define JB(i, j) B[PHM_NSTATE * (i) + (j)]
    const double *w = t, *v = t + 3;
    double Jq[16] = {0, .5 * w[0], .5 * w[1], .5 * w[2],     -.5 * w[0], 0, -.5 * w[2], .5 * w[1],
                     -.5 * w[1], .5 * w[2], 0, -.5 * w[0],   -.5 * w[2], -.5 * w[1], .5 * w[0], 0};
    double Jw[12] = {.5 * q[1], .5 * q[2], .5 * q[3],   -.5 * q[0], .5 * q[3], -.5 * q[2],
                     -.5 * q[3], -.5 * q[0], .5 * q[1], .5 * q[2], -.5 * q[1], -.5 * q[0]};
    for (int i = 0; i < 4; i++) {
      for (int j = 0; j < 4; j++) JB(i, j) = Jq[4 * i + j];
      for (int j = 0; j < 3; j++) JB(i, 7 + j) = Jw[3 * i + j];
    }
    /* p' = R v: d(R v) = -R hat(v) dw, dw = E dq */
    double E[12], RV[9];
    quat_chart(q, E);
    for (int i = 0; i < 3; i++) {
      double r[3] = {Hc[4 * i], Hc[4 * i + 1], Hc[4 * i + 2]};
      RV[3 * i] = r[1] * v[2] - r[2] * v[1]; /* row i of R hat(v): r x v, r = row i of R */
      RV[3 * i + 1] = r[2] * v[0] - r[0] * v[2];
      RV[3 * i + 2] = r[0] * v[1] - r[1] * v[0];
      for (int j = 0; j < 4; j++)
        JB(4 + i, j) = RV[3 * i] * E[j] + RV[3 * i + 1] * E[4 + j] + RV[3 * i + 2] * E[8 + j];
      for (int j = 0; j < 3; j++) JB(4 + i, 10 + j) = -r[j];
    }
    for (int i = 0; i < 7; i++) JB(i, i) += cj;
    /* M t' - ad*_t (M t): cj M - ad*_(e_j) M t - ad*_t M e_j */
    double Mt[6];
    phm_mv6(M, t, Mt);
    for (int j = 0; j < 6; j++) {
      double ej[6] = {0}, Me[6], a1[6], a2[6];
      ej[j] = 1.0;
      for (int i = 0; i < 6; i++) Me[i] = M[6 * i + j];
      phm_ad_dual_apply(ej, Mt, a1);
      phm_ad_dual_apply(t, Me, a2);
      for (int i = 0; i < 6; i++) JB(7 + i, 7 + j) = cj * M[6 * i + j] - a1[i] - a2[i];
    }
    if (gn > 0) { /* gravity: -dw/ddelta [E 0; 0 R^T] on the momentum rows (rotation only) */
      double wg[6], Kg[36];
      phm_gravity_tangent(m, c, Hc, 1.0, wg, Kg);
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 4; j++)
          JB(7 + i, j) -= Kg[6 * i] * E[j] + Kg[6 * i + 1] * E[4 + j] + Kg[6 * i + 2] * E[8 + j];
    }
#undef JB
    add_block(d, val, o, PHM_NSTATE, o, PHM_NSTATE, B, PHM_NSTATE);
  }
  for (int ie = 0; ie < m->ne; ie++) {
    const phm_element_desc *e = &m->el[ie];
    double wa[6], wb[6], Kx[144], Ct[144];
    phm_element_tangent(e, D->H + 16 * e->a, D->H + 16 * e->b, D->tw + 6 * e->a, D->tw + 6 * e->b,
                        wa, wb, Kx, Ct);
    int cr[2] = {e->a, e->b};
    for (int bj = 0; bj < 2; bj++) {
      const double *q = y + PHM_NSTATE * cr[bj], *Hc = D->H + 16 * cr[bj];
      double E[12];
      quat_chart(q, E);
      for (int bi = 0; bi < 2; bi++) {
        double blk[6 * PHM_NSTATE]; /* -Kx_(bi, bj) [E 0; 0 R^T], then -Ct_(bi, bj) */
        for (int i = 0; i < 6; i++) {
          const double *k = Kx + 12 * (6 * bi + i) + 6 * bj;
          double *b = blk + PHM_NSTATE * i;
          for (int j = 0; j < 4; j++) b[j] = -(k[0] * E[j] + k[1] * E[4 + j] + k[2] * E[8 + j]);
          for (int j = 0; j < 3; j++) /* R^T: (R^T)_{l j} = R_{j l} */
            b[4 + j] = -(k[3] * Hc[4 * j] + k[4] * Hc[4 * j + 1] + k[5] * Hc[4 * j + 2]);
          for (int j = 0; j < 6; j++) b[7 + j] = -Ct[12 * (6 * bi + i) + 6 * bj + j];
        }
        add_block(d, val, PHM_NSTATE * cr[bi] + 7, 6, PHM_NSTATE * cr[bj], PHM_NSTATE, blk, PHM_NSTATE);
      }
    }
  }
}

/* J = dF/dy + cj dF/dyp (no allocation): the closed-form part (jacobian_closed_form) plus the
 * remainder's coloured forward differences (dae_residual with d->remainder set). r0, the full
 * residual at (y, y'), is not needed: the remainder's is evaluated here. */
int dae_jacobian(dae_t *d, double t, double cj, const double *y, const double *ypv,
                 const double *r0, SUNMatrix J) {
  int n = d->n;
  sunindextype *cp = SUNSparseMatrix_IndexPointers(J), *ri = SUNSparseMatrix_IndexValues(J);
  double *val = SUNSparseMatrix_Data(J);
  for (int j = 0; j <= n; j++) cp[j] = d->colptr[j];
  for (int k = 0; k < d->nnz; k++) ri[k] = d->rowind[k];
  double sq = sqrt(2.2e-16);
  phm_data *D = &d->data;
  (void)r0;
  d->remainder = 1;
  if (dae_residual(d, t, y, ypv, D->rfd)) {
    d->remainder = 0;
    return 1;
  }
  for (int col = 0; col < d->ncolor; col++) {
    int any = 0;
    memcpy(D->ytmp, y, sizeof(double) * n);
    memcpy(D->yptmp, ypv, sizeof(double) * n);
    for (int j = 0; j < n; j++)
      if (d->color[j] == col) {
        double inc = sq * fmax(fabs(y[j]), fmax(fabs(ypv[j]) / (cj > 0 ? cj : 1), 1e-3));
        D->ytmp[j] += inc;
        D->yptmp[j] += cj * inc;
        D->inc[j] = inc; /* the increment of column j */
        any = 1;
      }
    if (!any) continue;
    if (dae_residual(d, t, D->ytmp, D->yptmp, D->rtmp)) {
      d->remainder = 0;
      return 1;
    }
    for (int j = 0; j < n; j++)
      if (d->color[j] == col)
        for (sunindextype k = cp[j]; k < cp[j + 1]; k++)
          val[k] = (D->rtmp[ri[k]] - D->rfd[ri[k]]) / D->inc[j];
  }
  d->remainder = 0;
  dae_unpack(d->m, y, D->H, D->tw); /* the unperturbed poses and twists */
  jacobian_closed_form(d, cj, y, val);
  return 0;
}
