/* jacobian.c -- the Jacobian dF/dy + cj dF/dy' of the DAE: its sparsity pattern from the block
 * structure (carriers couple through elements, pairs, springs and loads; a pair's multipliers
 * and joint coordinates through its two carriers), a colouring of its columns, and the coloured
 * forward differences that fill it. */
#include "dae.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"

phm_status dae_jacobian_pattern(dae_t *d, phm_error *err) {
  const phm_model *m = d->m;
  int n = d->n, nc = m->nc;
  /* column block of each state index: carrier c -> c; ledger -> none (no row depends on it);
   * lambda/mu row r of pair ip -> "pair block". Build a dense boolean block adjacency. */
  int nb = nc + m->np; /* blocks: carriers, then pairs (their lambda and mu) */
  char *adj = calloc((size_t)nb * nb, 1);
  if (!adj) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
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
  if (!blk || !d->colptr || !d->color) {
    free(adj);
    free(blk);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
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
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
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
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
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
