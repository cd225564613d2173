/* graph.c -- the coupling graph of the carriers (which share an element, pair, spring, load or mass coupling)
 * and of the pairs (each coupled to its carriers): the block structure of every Jacobian (the
 * DAE's pattern, csrc/dae/jacobian.c, on carriers and pairs; the stiffness blocks of modes and
 * statics, csrc/analyze/linearize.c, on the carriers). */
#include "model.h"

#include <stdlib.h>

#include "phm_check.h"

phm_status phm_carrier_graph(const phm_model *m, int pairs, int **ptr_out, int **nbr_out,
                             phm_error *err) {
  int nc = m->nc, nv = nc + (pairs ? m->np : 0), ned = m->ne + m->np + m->nl + m->ns + m->nmc;
  if (pairs) ned += 2 * m->np;
  ned += phm_components_sensor_edges(m, NULL, NULL, pairs);
  /* the edges in the order of the components; a pair's vertex meets its carriers after all
   * carrier-carrier edges */
  int *ea = malloc(sizeof(int) * (size_t)(ned + 1)), *eb = malloc(sizeof(int) * (size_t)(ned + 1));
  int *ptr = calloc((size_t)nv + 1, sizeof(int)), *nbr = NULL, *seen = NULL;
  if (!ea || !eb || !ptr) goto oom;
  int k = 0;
  for (int i = 0; i < m->ne; i++) { ea[k] = m->el[i].a; eb[k++] = m->el[i].b; }
  for (int i = 0; i < m->np; i++) { ea[k] = m->pair[i].a; eb[k++] = m->pair[i].b; }
  for (int i = 0; i < m->nl; i++) { ea[k] = m->load[i].carrier; eb[k++] = m->load[i].reaction; }
  for (int i = 0; i < m->ns; i++) { ea[k] = m->spr[i].a; eb[k++] = m->spr[i].b; }
  for (int i = 0; i < m->nmc; i++) { ea[k] = m->mc_a[i]; eb[k++] = m->mc_b[i]; } /* couplings */
  if (pairs)
    for (int i = 0; i < m->np; i++) {
      ea[k] = nc + i; eb[k++] = m->pair[i].a;
      ea[k] = nc + i; eb[k++] = m->pair[i].b;
    }
  k += phm_components_sensor_edges(m, ea + k, eb + k, pairs); /* non-collocated controllers */
  /* every vertex itself first, then both directions of each edge in order (with repeats) */
  for (int v = 0; v < nv; v++) ptr[v + 1] = 1;
  for (int e = 0; e < k; e++)
    if (ea[e] >= 0 && eb[e] >= 0 && ea[e] != eb[e]) { ptr[ea[e] + 1]++; ptr[eb[e] + 1]++; }
  for (int v = 0; v < nv; v++) ptr[v + 1] += ptr[v];
  nbr = malloc(sizeof(int) * (size_t)(ptr[nv] + 1));
  seen = malloc(sizeof(int) * (size_t)(nv + 1));
  if (!nbr || !seen) goto oom;
  for (int v = 0; v < nv; v++) { nbr[ptr[v]] = v; seen[v] = ptr[v] + 1; } /* seen: fill point */
  for (int e = 0; e < k; e++)
    if (ea[e] >= 0 && eb[e] >= 0 && ea[e] != eb[e]) {
      nbr[seen[ea[e]]++] = eb[e];
      nbr[seen[eb[e]]++] = ea[e];
    }
  /* drop the repeats, keeping each neighbour's first place (seen[u] = v: u already listed by v) */
  for (int v = 0; v < nv; v++) seen[v] = -1;
  int wpos = 0;
  for (int v = 0; v < nv; v++) {
    int s0 = ptr[v], s1 = ptr[v + 1];
    ptr[v] = wpos;
    for (int q = s0; q < s1; q++)
      if (seen[nbr[q]] != v) {
        seen[nbr[q]] = v;
        nbr[wpos++] = nbr[q];
      }
  }
  ptr[nv] = wpos;
  free(ea); free(eb); free(seen);
  *ptr_out = ptr;
  *nbr_out = nbr;
  return PHM_OK;
oom:
  free(ea); free(eb); free(ptr); free(nbr); free(seen);
  return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
}
