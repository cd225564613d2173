/* graph.c -- the carrier coupling graph (which carriers share an element, pair, spring or load)
 * and its distance-2 colouring: the structure behind every coloured finite-difference Jacobian
 * (modes, statics). */
#include "model.h"

#include <stdlib.h>

#include "phm_check.h"

phm_status phm_carrier_graph(const phm_model *m, int **ptr_out, int **nbr_out, phm_error *err) {
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
  return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
}

int phm_graph_colours(int nc, const int *ptr, const int *nbr, int *col, int *mark) {
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
