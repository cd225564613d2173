/* jacobian.c -- the Jacobian dF/dy + cj dF/dy' of the DAE: its sparsity pattern from the block
 * structure (carriers couple through elements, pairs, springs and loads; a pair's multipliers
 * and joint coordinates through its two carriers: the coupling graph of csrc/model/graph.c), a
 * colouring of its columns, and the coloured forward differences that fill it. */
#include "dae.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"

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

/* J = dF/dy + cj dF/dyp by coloured forward differences (no allocation). */
int dae_jacobian(dae_t *d, double t, double cj, const double *y, const double *ypv,
                 const double *r0, SUNMatrix J) {
  int n = d->n;
  sunindextype *cp = SUNSparseMatrix_IndexPointers(J), *ri = SUNSparseMatrix_IndexValues(J);
  double *val = SUNSparseMatrix_Data(J);
  for (int j = 0; j <= n; j++) cp[j] = d->colptr[j];
  for (int k = 0; k < d->nnz; k++) ri[k] = d->rowind[k];
  double sq = sqrt(2.2e-16);
  phm_data *D = &d->data;
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
    if (dae_residual(d, t, D->ytmp, D->yptmp, D->rtmp)) return 1;
    for (int j = 0; j < n; j++)
      if (d->color[j] == col)
        for (sunindextype k = cp[j]; k < cp[j + 1]; k++)
          val[k] = (D->rtmp[ri[k]] - r0[ri[k]]) / D->inc[j];
  }
  return 0;
}
