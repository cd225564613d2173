/* reduce.c -- the linearization at a configuration reduced to the null space of the constraint
 * Jacobian (lin_red_t, analyze.h): the stiffness and damping blocks on the carrier graph
 * (csrc/analyze/linearize.c), the null-space basis Z and the reduced K_r, D_r, M_r, shared by
 * the dense modes (modes.c), the sparse modes' blocks (modes_sparse.c) and the linear
 * port-Hamiltonian model (linear_model.c). */
#include "analyze.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"

void lin_red_free(lin_red_t *R) {
  lin_free(&R->L);
  free(R->H); free(R->Db); free(R->cmap); free(R->red); free(R->U);
  free(R->Kr); free(R->Dr); free(R->Mr); free(R->Gb); free(R->Gr);
}

/* K and D blocks at poses (NULL: H0) with constraint wrenches lambda (NULL: none), loads at time. */
phm_status lin_red_blocks(lin_red_t *R, const phm_model *m, const double *poses,
                                 const double *lambda, double time, phm_error *err) {
  int nc = m->nc;
  lin_t *L = &R->L;
  phm_status st;
  if ((st = lin_alloc(L, m, err)) || (st = lin_graph(L, err))) return st;
  int nb = L->ptr[nc];
  R->H = malloc(sizeof(double) * 16 * (size_t)nc);
  R->Db = calloc((size_t)nb * 36, sizeof(double));
  if (!R->H || !R->Db) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  double *H = R->H, *Kb = L->Kb, *Db = R->Db;
  L->time = time;
  L->tref = phm_model_tref(m, time, NULL);
  L->scale = 1.0;
  L->lam = lambda;
  for (int c = 0; c < nc; c++) memcpy(H + 16 * c, poses ? poses + 16 * c : m->car[c].H0, 16 * sizeof(double));
  /* stiffness K = -d f / d delta, block-sparse */
  lin_force_jacobian_blocks(L, H);
  for (size_t i = 0; i < (size_t)nb * 36; i++) Kb[i] = -Kb[i];
  /* damping D = -dw/dt, in closed form (lin_closed_form_blocks; the pairs' wrenches do not
   * depend on the twists) */
  lin_closed_form_blocks(L, H, NULL, Db);
  for (size_t i = 0; i < (size_t)nb * 36; i++) Db[i] = -Db[i];
  if (m->has_spin) { /* a steady rotation's gyroscopic blocks (linearize.c) */
    if (!(R->Gb = malloc(sizeof(double) * 36 * (size_t)nb + 1))) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
    lin_gyro_blocks(L, H, R->Gb);
  }
  return PHM_OK;
}

/* out (nr x nr) += Z^T X Z block by block for the blocks Bw (36 per graph slot), then
 * symmetrized if sym. */
static void red_assemble(const lin_red_t *R, int nc, const double *Bw, double *out, int sym) {
  const int *ptr = R->L.ptr, *nbr = R->L.nbr, *red = R->red, *cmap = R->cmap;
  int nr = R->nr, n0 = R->n0, n6c = R->n6c;
  const double *U0 = R->U0;
  for (int r = 0; r < nc; r++)
    for (int q = ptr[r]; q < ptr[r + 1]; q++) {
      int c = nbr[q];
      const double *B = Bw + 36 * (size_t)q;
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
  for (int a = 0; sym && a < nr; a++)
    for (int b = 0; b < a; b++) {
      double s = 0.5 * (out[(size_t)a * nr + b] + out[(size_t)b * nr + a]);
      out[(size_t)a * nr + b] = out[(size_t)b * nr + a] = s;
    }
}

/* The null space of G and the reduced Kr, Dr, Mr (symmetrized) from the blocks. */
phm_status lin_red_reduce(lin_red_t *R, const phm_model *m, phm_error *err) {
  int nc = m->nc, nk = m->ncons;
  const double *Kb = R->L.Kb, *Db = R->Db;
  double *Gc = NULL, *sv = NULL, *work = NULL;
  int *clist = NULL;
  phm_status st = PHM_OK;
  R->cmap = malloc(sizeof(int) * (size_t)nc);
  clist = malloc(sizeof(int) * (size_t)(nc + 1));
  if (!R->cmap || !clist) goto oom;
  int *cmap = R->cmap, ncc = 0;
  for (int c = 0; c < nc; c++) cmap[c] = -1;
  if (nk > 0)
    for (int ip = 0; ip < m->np; ip++) {
      int ab[2] = {m->pair[ip].a, m->pair[ip].b};
      for (int s = 0; s < 2; s++)
        if (ab[s] >= 0 && cmap[ab[s]] < 0) { cmap[ab[s]] = ncc; clist[ncc++] = ab[s]; }
    }
  int n6c = 6 * ncc, rank = 0, n0 = n6c;
  if (nk > 0 && n6c > 0) {
    Gc = malloc(sizeof(double) * (size_t)n6c * nk); /* column-major G^T: n6c x nk */
    R->U = malloc(sizeof(double) * (size_t)n6c * n6c);
    sv = malloc(sizeof(double) * (size_t)(nk < n6c ? nk : n6c) + sizeof(double));
    if (!Gc || !R->U || !sv) goto oom;
    /* row-major G over the constrained carriers' columns: column-major G^T for dgesvd */
    phm_constraints_columns(m, R->H, NULL, R->L.time, R->L.tref, cmap, n6c, NULL, Gc, NULL);
    int lw = -1, info = 0, one = 1;
    double wq;
    dgesvd_("A", "N", &n6c, &nk, Gc, &n6c, sv, R->U, &n6c, NULL, &one, &wq, &lw, &info);
    lw = (int)wq + 1;
    work = malloc(sizeof(double) * (size_t)lw);
    if (!work) goto oom;
    dgesvd_("A", "N", &n6c, &nk, Gc, &n6c, sv, R->U, &n6c, NULL, &one, work, &lw, &info);
    if (info != 0) {
      st = PHM_FAIL(err, PHM_ESINGULAR, "SVD of the constraint Jacobian failed (dgesvd info %d)", info);
      goto done;
    }
    int ns = nk < n6c ? nk : n6c;
    for (int i = 0; i < ns; i++)
      if (sv[i] > 1e-10 * sv[0]) rank++;
    n0 = n6c - rank;
  }
  R->red = malloc(sizeof(int) * (size_t)nc);
  if (!R->red) goto oom;
  int *red = R->red, nr = n0;
  for (int c = 0; c < nc; c++) {
    red[c] = cmap[c] < 0 ? nr : -1;
    if (cmap[c] < 0) nr += 6;
  }
  R->n6c = n6c;
  R->n0 = n0;
  R->nr = nr;
  if (nr == 0) {
    st = PHM_FAIL(err, PHM_EINVAL, "the mechanism has no degree of freedom: no modes");
    goto done;
  }
  R->Kr = calloc((size_t)nr * nr, sizeof(double));
  R->Mr = calloc((size_t)nr * nr, sizeof(double));
  R->Dr = calloc((size_t)nr * nr, sizeof(double));
  if (!R->Kr || !R->Mr || !R->Dr) goto oom;
  R->U0 = R->U ? R->U + (size_t)rank * n6c : NULL; /* column a: U0[a * n6c + i] */
  /* X_r = Z^T X Z block by block; (Kr, Dr) from the blocks, Mr from the block-diagonal mass */
  for (int w = 0; w < 3; w++)
    red_assemble(R, nc, w == 0 ? Kb : w == 1 ? Db : R->L.Mb, w == 0 ? R->Kr : w == 1 ? R->Dr : R->Mr, 1);
  if (R->Gb) { /* -Z^T Gb Z: M q'' + (D + G) q' + K q = 0 */
    if (!(R->Gr = calloc((size_t)nr * nr, sizeof(double)))) goto oom;
    red_assemble(R, nc, R->Gb, R->Gr, 0);
    for (size_t i = 0; i < (size_t)nr * nr; i++) R->Gr[i] = -R->Gr[i];
  }
  if (!phm_all_finite(R->Kr, (size_t)nr * nr) || !phm_all_finite(R->Mr, (size_t)nr * nr) ||
      !phm_all_finite(R->Dr, (size_t)nr * nr))
    st = PHM_FAIL(err, PHM_ESOLVER, "linearization: the stiffness, damping or mass is not "
                       "finite: the model's numbers overflow double precision");
  goto done;
oom:
  st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
done:
  free(clist); free(Gc); free(sv); free(work);
  return st;
}
/* x = Z y: a reduced vector y (nr) as carrier tangent coordinates x (6 nc). */
void lin_red_expand(const lin_red_t *R, int nc, const double *y, double *x) {
  for (int c = 0; c < nc; c++)
    for (int i = 0; i < 6; i++) {
      double s = 0;
      if (R->red[c] >= 0) s = y[R->red[c] + i];
      else
        for (int a = 0; a < R->n0; a++) s += R->U0[(size_t)a * R->n6c + 6 * R->cmap[c] + i] * y[a];
      x[6 * c + i] = s;
    }
}

/* y = Z^T f: carrier wrenches f (6 nc) as reduced generalized forces y (nr). */
void lin_red_project(const lin_red_t *R, int nc, const double *f, double *y) {
  for (int a = 0; a < R->n0; a++) y[a] = 0;
  for (int c = 0; c < nc; c++)
    if (R->red[c] >= 0)
      for (int i = 0; i < 6; i++) y[R->red[c] + i] = f[6 * c + i];
    else
      for (int a = 0; a < R->n0; a++)
        for (int i = 0; i < 6; i++) y[a] += R->U0[(size_t)a * R->n6c + 6 * R->cmap[c] + i] * f[6 * c + i];
}
