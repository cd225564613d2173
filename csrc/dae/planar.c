/* planar.c -- the planar reduction of the DAE (dae.h, dae_planar_init): when every carrier moves
 * in the plane normal to a world axis k (e.g. z: rotation about z, twist (omega_z, v_x, v_y)),
 * only 7 of a carrier's 13 states move: q_w, q_k, the two positions across k, omega_k and the
 * two body velocities across k (for k = z: q_w, q_z, p_x, p_y, omega_z, v_x, v_y). The others
 * keep their initial values (for k = z: q_x = q_y = 0, p_z, zero omega_x, omega_y, v_z) with
 * zero rates. The reduced DAE holds
 * those 7 per carrier and then the joint coordinates, ledger and multipliers of the full DAE
 * (whose model has the out-of-plane constraint rows dropped already: Python's planar check);
 * each of its operations expands the reduced vectors into the full DAE's, evaluates that as in
 * 3-D and gathers the in-plane rows (the row of a carrier state is its own equation, so rows
 * and columns keep the same indices). The Jacobian is gathered from the full pattern through
 * a map of entries made once (dae_planar_pattern); nothing here allocates after set-up. */
#include "dae.h"

#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "pose.h"

struct dae_planar {
  dae_t full;     /* the 3-D DAE of the model */
  int keep[PHM_NSTATE_PLANAR];              /* the carrier states kept (of q[4], p[3], t[6]) */
  int drop[PHM_NSTATE - PHM_NSTATE_PLANAR]; /* and those dropped, both ascending */
  double *y, *yp; /* full n: expanded states and rates (the dropped states at base, rates 0) */
  double *F;      /* full n: a full residual */
  double *base;   /* full n: the dropped states' values (from the initial values) */
  double *fval;   /* full nnz: the full Jacobian's values */
  long *jmap;     /* reduced nnz: each reduced entry's place in the full pattern */
  signed char *oop; /* np: every dropped row of the pair is out of the plane (1) or not (0);
                     * -1: not yet known (dae_planar_drops_out_of_plane) */
};

dae_t *dae_full(dae_t *d) { return d->pl ? &d->pl->full : d; }

/* The reduced vector yr into the full yf's kept entries (its dropped ones are left as they are:
 * the base values in pl->y, zero in pl->yp; restore). */
static void expand(const dae_t *d, const double *yr, double *yf) {
  int nc = d->m->nc;
  const int *keep7 = d->pl->keep;
  for (int c = 0; c < nc; c++) {
    double *f = yf + PHM_NSTATE * c;
    const double *r = yr + PHM_NSTATE_PLANAR * c;
    for (int i = 0; i < PHM_NSTATE_PLANAR; i++) f[keep7[i]] = r[i];
  }
  memcpy(yf + d->pl->full.ix, yr + d->ix, sizeof(double) * (size_t)(d->n - d->ix));
}

/* The dropped carrier states of pl->y back to their base values, their rates in pl->yp to 0
 * (after a full operation that wrote them). */
static void restore(dae_t *d) {
  struct dae_planar *pl = d->pl;
  const int *drop6 = pl->drop;
  for (int c = 0; c < d->m->nc; c++)
    for (int i = 0; i < PHM_NSTATE - PHM_NSTATE_PLANAR; i++) {
      int k = PHM_NSTATE * c + drop6[i];
      pl->y[k] = pl->base[k];
      pl->yp[k] = 0.0;
    }
}

/* The full vector yf's kept entries into yr. */
static void gather(const dae_t *d, const double *yf, double *yr) {
  int nc = d->m->nc;
  const int *keep7 = d->pl->keep;
  for (int c = 0; c < nc; c++)
    for (int i = 0; i < PHM_NSTATE_PLANAR; i++)
      yr[PHM_NSTATE_PLANAR * c + i] = yf[PHM_NSTATE * c + keep7[i]];
  memcpy(yr + d->ix, yf + d->pl->full.ix, sizeof(double) * (size_t)(d->n - d->ix));
}

/* The full index of reduced state i. */
static int full_index(const dae_t *d, int i) {
  if (i >= d->ix) return i - d->ix + d->pl->full.ix;
  return PHM_NSTATE * (i / PHM_NSTATE_PLANAR) + d->pl->keep[i % PHM_NSTATE_PLANAR];
}

/* The reduced index of full state i, -1 if it is dropped. */
static int reduced_index(const dae_t *d, int i) {
  int fix = d->pl->full.ix;
  if (i >= fix) return i - fix + d->ix;
  int c = i / PHM_NSTATE, r = i % PHM_NSTATE;
  for (int k = 0; k < PHM_NSTATE_PLANAR; k++)
    if (d->pl->keep[k] == r) return PHM_NSTATE_PLANAR * c + k;
  return -1;
}

phm_status dae_planar_init(dae_t *d, const phm_model *m, int axis, phm_error *err) {
  memset(d, 0, sizeof *d);
  if (axis < 0 || axis > 2) return PHM_FAIL(err, PHM_EINVAL, "planar: unknown normal axis %d", axis);
  struct dae_planar *pl = calloc(1, sizeof *pl);
  if (!pl) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  /* q_w, q_axis; the two positions and velocities across the axis; omega_axis */
  int nk = 0, nd = 0;
  for (int i = 0; i < PHM_NSTATE; i++) {
    int kept = i == 0 || i == 1 + axis || (i >= 4 && i < 7 && i != 4 + axis) || i == 7 + axis ||
               (i >= 10 && i != 10 + axis);
    if (kept) pl->keep[nk++] = i;
    else pl->drop[nd++] = i;
  }
  phm_status st = dae_init(&pl->full, m, err);
  if (st) {
    free(pl);
    return st;
  }
  d->pl = pl;
  d->m = m;
  d->ns = PHM_NSTATE_PLANAR;
  d->nt0 = 4;
  d->ix = PHM_NSTATE_PLANAR * m->nc;
  int shift = pl->full.ix - d->ix;
  d->ie = pl->full.ie - shift;
  d->il = pl->full.il - shift;
  d->im = pl->full.im - shift;
  d->n = pl->full.n - shift;
  d->nnorm = pl->full.n;
  d->ncfg_drop = 3 * m->nc; /* two quaternion components and one position per carrier */
  d->nzcnt = -1;
  size_t nf = (size_t)pl->full.n;
  pl->y = calloc(nf + 1, sizeof(double));
  pl->yp = calloc(nf + 1, sizeof(double));
  pl->F = calloc(nf + 1, sizeof(double));
  pl->base = calloc(nf + 1, sizeof(double));
  pl->oop = malloc((size_t)m->np + 1);
  if (pl->oop) memset(pl->oop, -1, (size_t)m->np + 1);
  if (!pl->y || !pl->yp || !pl->F || !pl->base || !pl->oop) {
    dae_free(d);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
  return PHM_OK;
}

void dae_planar_free(dae_t *d) {
  struct dae_planar *pl = d->pl;
  if (!pl) return;
  dae_free(&pl->full);
  void *bufs[] = {pl->y, pl->yp, pl->F, pl->base, pl->fval, pl->jmap, pl->oop, pl};
  for (size_t i = 0; i < sizeof bufs / sizeof bufs[0]; i++) free(bufs[i]);
  d->pl = NULL;
}

void dae_planar_carrier_states(const dae_t *d, dae_carrier_layout *L) {
  const int *keep = d->pl->keep; /* ascending: q (0..3), p (4..6), then t (7..12) */
  L->nq = L->npos = 2;
  L->nt = 3;
  for (int i = 0; i < 2; i++) {
    L->qf[i] = keep[i];
    L->pf[i] = keep[2 + i] - 4;
  }
  for (int i = 0; i < 3; i++) L->tf[i] = keep[4 + i] - 7;
}

/* The full DAE at the reduced state y (and rates yp, if not NULL): its time reference and states
 * set from d's, for a wrapper to evaluate it there. */
static dae_t *to_full(dae_t *d, const double *y, const double *yp) {
  struct dae_planar *pl = d->pl;
  pl->full.tref = d->tref;
  expand(d, y, pl->y);
  if (yp) expand(d, yp, pl->yp);
  return &pl->full;
}

int dae_planar_drops_out_of_plane(dae_t *d, int ip, const double *yf, double t) {
  struct dae_planar *pl = d->pl;
  if (pl->oop[ip] >= 0) return pl->oop[ip];
  const dae_t *f = &pl->full;
  const phm_model *m = f->m;
  const phm_pair_desc *pr = &m->pair[ip];
  int mc = phm_pair_rows_full(pr), out = 1;
  double Ha[16], Hb[16], g[PHM_MAXCON], Ga[6 * PHM_MAXCON], Gb[6 * PHM_MAXCON], W[36];
  if (pr->a >= 0) phm_qp_to_H(yf + PHM_NSTATE * pr->a, yf + PHM_NSTATE * pr->a + 4, Ha);
  if (pr->b >= 0) phm_qp_to_H(yf + PHM_NSTATE * pr->b, yf + PHM_NSTATE * pr->b + 4, Hb);
  phm_pair_eval_full(m, ip, pr->a >= 0 ? Ha : NULL, pr->b >= 0 ? Hb : NULL,
                     yf + f->ix + m->pair_j[ip], t, f->tref, g, Ga, Gb, W);
  for (int r = 0; r < mc; r++) {
    if (!(pr->drop >> r & 1)) continue;
    for (int i = 4; i < PHM_NSTATE_PLANAR; i++) { /* the kept twist components */
      int j = pl->keep[i] - 7;
      if ((pr->a >= 0 && Ga[6 * r + j] != 0.0) || (pr->b >= 0 && Gb[6 * r + j] != 0.0)) out = 0;
    }
  }
  pl->oop[ip] = (signed char)out;
  return out;
}

const double *dae_planar_state(dae_t *d, const double *y) {
  to_full(d, y, NULL);
  return d->pl->y;
}

int dae_planar_residual(dae_t *d, double time, const double *y, const double *yp, double *F,
                        int crows) {
  struct dae_planar *pl = d->pl;
  int r = dae_residual_rows(to_full(d, y, yp), time, pl->y, pl->yp, pl->F, crows);
  gather(d, pl->F, F);
  return r;
}

void dae_planar_constraint_rows(dae_t *d, double time, const double *y, double *F) {
  struct dae_planar *pl = d->pl;
  dae_constraint_rows(to_full(d, y, NULL), time, pl->y, pl->F);
  memcpy(F + d->il, pl->F + pl->full.il, sizeof(double) * (size_t)(d->n - d->il));
}

/* The reduced pattern: the full pattern's entries whose row and column are both kept (the map
 * is increasing, so each column's rows stay ascending), and each one's place in the full
 * pattern. */
phm_status dae_planar_pattern(dae_t *d, phm_error *err) {
  struct dae_planar *pl = d->pl;
  dae_t *f = &pl->full;
  phm_status st = dae_jacobian_pattern(f, err);
  if (st) return st;
  free(d->colptr);
  free(d->rowind);
  free(d->nzkeep);
  free(pl->fval);
  free(pl->jmap);
  d->rowind = NULL;
  d->nzkeep = NULL;
  pl->jmap = NULL;
  d->nzcnt = -1;
  long nnz = 0;
  for (int j = 0; j < d->n; j++) {
    int J = full_index(d, j);
    for (sunindextype e = f->colptr[J]; e < f->colptr[J + 1]; e++)
      nnz += reduced_index(d, (int)f->rowind[e]) >= 0;
  }
  d->nnz = (int)nnz;
  d->colptr = malloc(sizeof(sunindextype) * ((size_t)d->n + 1));
  d->rowind = malloc(sizeof(sunindextype) * ((size_t)nnz + 1));
  d->nzkeep = calloc((size_t)nnz + 1, 1);
  pl->jmap = malloc(sizeof(long) * ((size_t)nnz + 1));
  pl->fval = calloc((size_t)f->nnz + 1, sizeof(double));
  if (!d->colptr || !d->rowind || !d->nzkeep || !pl->jmap || !pl->fval)
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  long k = 0;
  for (int j = 0; j < d->n; j++) {
    int J = full_index(d, j);
    d->colptr[j] = k;
    for (sunindextype e = f->colptr[J]; e < f->colptr[J + 1]; e++) {
      int r = reduced_index(d, (int)f->rowind[e]);
      if (r < 0) continue;
      d->rowind[k] = r;
      pl->jmap[k++] = (long)e;
    }
  }
  d->colptr[d->n] = k;
  return PHM_OK;
}

void dae_planar_jacobian_values(dae_t *d, double t, double cj, const double *y, const double *yp,
                                double *val) {
  struct dae_planar *pl = d->pl;
  dae_jacobian_values(to_full(d, y, yp), t, cj, pl->y, pl->yp, pl->fval);
  for (int k = 0; k < d->nnz; k++) val[k] = pl->fval[pl->jmap[k]];
}

/* The start's consistent values: the full DAE's, whose dropped carrier states become the base
 * (the initial values the reduction keeps). */
phm_status dae_planar_consistent_ic(dae_t *d, double time, double *H, double *tw,
                                    const double *xs, int check_x0, double *y, double *yp,
                                    phm_error *err) {
  struct dae_planar *pl = d->pl;
  dae_t *f = to_full(d, y, NULL);
  memset(pl->yp, 0, sizeof(double) * (size_t)f->n);
  phm_status st = dae_consistent_ic(f, time, H, tw, NULL, xs, check_x0, pl->y, pl->yp, err);
  if (st) return st;
  /* the base: the out-of-plane position as found; the out-of-plane quaternion components and
   * twist zero, as they are in exact arithmetic (the checks hold them to 1e-12; the values
   * found carry round-off, 1e-24 .. 1e-17, which would leave round-off entries in the
   * Jacobian's in-plane rows that KLU can take as pivots) */
  memcpy(pl->base, pl->y, sizeof(double) * (size_t)pl->full.ix);
  for (int c = 0; c < d->m->nc; c++)
    for (int i = 0; i < PHM_NSTATE - PHM_NSTATE_PLANAR; i++)
      if (pl->drop[i] != 4 && pl->drop[i] != 5 && pl->drop[i] != 6)
        pl->base[PHM_NSTATE * c + pl->drop[i]] = 0.0;
  gather(d, pl->y, y);
  gather(d, pl->yp, yp);
  restore(d); /* the dropped rates are zero (in-plane forces: the checks) */
  return PHM_OK;
}

phm_status dae_planar_restart(dae_t *d, double t, double tpiece, double *nbp, double *y,
                              double *yp, phm_error *err) {
  struct dae_planar *pl = d->pl;
  phm_status st = dae_restart_at_breakpoint(to_full(d, y, yp), t, tpiece, nbp, pl->y, pl->yp, err);
  d->tref = pl->full.tref;
  if (st) return st;
  gather(d, pl->y, y);
  gather(d, pl->yp, yp);
  restore(d);
  return PHM_OK;
}

phm_status dae_planar_emit_output(dae_t *d, const double *y, phm_sim_output *out, int iout,
                                  double E0[1], double t, const phm_sim_options *opt, int *stop,
                                  phm_error *err) {
  return dae_emit_output(to_full(d, y, NULL), d->pl->y, out, iout, E0, t, opt, stop, err);
}
