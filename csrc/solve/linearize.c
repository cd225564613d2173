/* linearize.c -- linearization on the tangent space (docs/method.md section 7): the generalized
 * forces f(H) = applied + G^T lambda at poses H and their Jacobian blocks df/ddelta by coloured
 * central differences over the carrier coupling graph (csrc/model/graph.c); read by modes
 * (modes.c) and statics (statics.c). Set-up time code: allocates. */
#include "solve.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "pose.h"

/* Generalized forces at poses H: applied wrenches + G^T lambda (nc x 6, body frame). */
void lin_total_force(lin_t *L, const double *H, double *f) {
  const phm_model *m = L->m;
  phm_applied(m, H, NULL, NULL, L->time, L->tref, L->scale, f, NULL, NULL, NULL, NULL, NULL);
  if (L->lam && m->ncons) phm_constraint_forces(m, H, L->time, L->tref, L->lam, f);
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
  free(mark);
  return PHM_OK;
}

/* Kb[q] = d f_r / d delta_c for block q = (row carrier r, column carrier nbr[q]) of the coupling
 * graph (6 x 6, row-major), f = total_force on the perturbed carriers' charts, f_c(delta) =
 * dexp_{-delta}^T w_c(H_c exp(delta)); central differences, one pass per colour and direction
 * (carriers of one colour share no neighbour, so their columns do not mix). Into L->Kb. */
void lin_force_jacobian_blocks(lin_t *L, const double *H, double *f1, double *f2) {
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
        lin_total_force(L, L->Hp, f);
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

