/* residual.c -- the DAE residual F(t, y, y') (docs/method.md section 6, GGL form; state layout in
 * csrc/dae/dae.h): carrier kinematics q' and p', the momentum balance M t' - ad*_t M t = applied
 * + G^T lambda, the pairs' joint-coordinate rates, velocity and position constraints, and the
 * energy ledger's integrals. Its workspace is allocated once (dae_init); a residual allocates
 * nothing. */
#include "dae.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"
#include "pose.h"

/* Carrier c's pose H[16 c ..] and twist tw[6 c ..] from the state vector y. */
static void unpack_carrier(const double *y, int c, double *H, double *tw) {
  const double *yc = y + PHM_NSTATE * c;
  phm_qp_to_H(yc, yc + 4, H + 16 * c);
  memcpy(tw + 6 * c, yc + 7, 6 * sizeof(double));
}

/* Carrier poses H (nc x 16) and twists tw (nc x 6) from the state vector y. */
void dae_unpack(const phm_model *m, const double *y, double *H, double *tw) {
  for (int c = 0; c < m->nc; c++) unpack_carrier(y, c, H, tw);
}

/* Pair ip at the poses and twists in d->data and the joint-coordinate branches of y. */
static void eval_pair(dae_t *d, int ip, double time, const double *y, int what) {
  const phm_model *m = d->m;
  const phm_pair_desc *pr = &m->pair[ip];
  const double *H = d->data.H, *tw = d->data.tw;
  phm_pair_evaluate(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                    pr->a >= 0 ? tw + 6 * pr->a : NULL, pr->b >= 0 ? tw + 6 * pr->b : NULL,
                    y + d->ix + m->pair_j[ip], time, d->tref, what, d->data.pair + ip);
}

void dae_eval_pairs(dae_t *d, double time, const double *y, int what) {
  for (int ip = 0; ip < d->m->np; ip++) eval_pair(d, ip, time, y, what);
}

/* acc += G^T l for one side's block G (mc x 6) of a pair: the order over the rows r is the one
 * every carrier's sum has always had (a carrier's sums stay bit-identical). */
static void add_GT(const double *G, int mc, const double *lam, const double *mu, double *gl,
                   double *gm) {
  for (int r = 0; r < mc; r++)
    for (int j = 0; j < 6; j++) {
      gl[j] += G[6 * r + j] * lam[r];
      gm[j] += G[6 * r + j] * mu[r];
    }
}

/* The generalized-alpha's stage (rows_of_pairs without `crows`): the pair's constraint wrench
 * made workless there. The velocity rows hold at the step's end, G(q1) t1 = v_t, and the balance
 * is evaluated at the stage, whose interpolated state leaves G(q_a) t_a - v_t = O(h^2): a defect
 * whose power lambda . (G t - v_t) keeps its sign along a motion, so the constraint wrenches did
 * work that no physics does. Measured on the IFToMM A02 four-bar (N = 2, 20 s, defaults,
 * tests/hard/_scenes.py): 2.7e-4 J gained, 2.8e-5 J per turn, which moved this near-separatrix
 * motion's phase until point B0 was 1.93e-3 m off the exact motion (the benchmark's limit is
 * 1e-3 m; 2.6e-4 m with this). The defect's power is taken out along the momenta of the pair's
 * carriers, a wrench -kappa M t on each with kappa = lambda . (G t - v_t) / (t_a.M_a t_a +
 * t_b.M_b t_b), so the pair's wrench does at the stage the prescribed motion's work
 * lambda . v_t alone. kappa h is at most DAE_WORKLESS_STEP: where the carriers are nearly at
 * rest (a start from rest; a clamp whose twists are Newton's noise, for which G t - v_t is the
 * noise itself) the quotient is large and the energy at stake is not: bounded only by the
 * constraint wrench, its wrenches in the noise's directions made Newton fail at a flexible
 * link's clamp. docs/method.md, "The constraint wrench at the stage". */
static void workless_at_stage(dae_t *d, int ip, const double *lam) {
  const phm_model *m = d->m;
  phm_data *D = &d->data;
  const phm_pair_desc *pr = &m->pair[ip];
  const phm_pair_data *p = D->pair + ip;
  const int mc = m->pair_m[ip], side[2] = {pr->a, pr->b};
  const double *G[2] = {p->Ga, p->Gb};
  double power = 0, Mt[2][6] = {{0}}, K2 = 0;
  for (int r = 0; r < mc; r++) {
    double c = -p->vt[r];
    for (int k = 0; k < 2; k++)
      if (side[k] >= 0)
        for (int j = 0; j < 6; j++) c += G[k][6 * r + j] * D->tw[6 * side[k] + j];
    power += lam[r] * c;
  }
  for (int k = 0; k < 2; k++)
    if (side[k] >= 0) {
      const double *t = D->tw + 6 * side[k];
      phm_mv6(m->car[m->car_u[side[k]]].M, t, Mt[k]);
      for (int j = 0; j < 6; j++) K2 += t[j] * Mt[k][j];
    }
  if (!(K2 > 0) || power == 0 || !(d->stage_h > 0)) return;
  double kappa = power / K2, cap = DAE_WORKLESS_STEP / d->stage_h;
  if (fabs(kappa) > cap) kappa = copysign(cap, kappa);
  for (int k = 0; k < 2; k++)
    if (side[k] >= 0)
      for (int j = 0; j < 6; j++) D->gl[6 * side[k] + j] -= kappa * Mt[k][j];
}

/* The pairs' rows; with `full` also the joint-coordinate rates and G^T lambda, G^T mu (see
 * dae_pair_rows and dae_constraint_rows). One body for both, so that the constraint rows of the
 * step's end are the very numbers of a full evaluation; `full` is tested once per pair. Without
 * `full`, a pair without kept rows (free) is not evaluated: it has no row to give. Without
 * `crows` (with `full`), not the constraint rows F[il..n) either (nor g: dae_residual_rows). */
static void rows_of_pairs(dae_t *d, double time, const double *y, const double *yp, double *F,
                          int full, int crows) {
  /* ground's twist: G_r t sums both sides without a test per entry. Adding G * 0 = +-0 leaves
   * every sum as it was (up to the sign of an exact zero) */
  static const double zero6[6] = {0, 0, 0, 0, 0, 0};
  const phm_model *m = d->m;
  phm_data *D = &d->data;
  if (full) {
    memset(D->gl, 0, sizeof(double) * 6 * (size_t)m->nc);
    memset(D->gm, 0, sizeof(double) * 6 * (size_t)m->nc);
  }
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    const phm_pair_data *p = D->pair + ip;
    int r0 = m->pair_row[ip], mc = m->pair_m[ip];
    if (!full && mc == 0) continue;
    eval_pair(d, ip, time, y,
              full ? PHM_PAIR_ROWS | PHM_PAIR_JOINT | (crows ? 0 : PHM_PAIR_NO_G) : PHM_PAIR_ROWS);
    if (full) {
      int j0 = m->pair_j[ip], k = m->pair_k[ip];
      for (int c = 0; c < k; c++) F[d->ix + j0 + c] = yp[d->ix + j0 + c] - p->xdot[c];
      const double *lam = y + d->il + r0, *mu = y + d->im + r0;
      /* a != b (phm_model_create): the two sides' sums never meet */
      if (pr->a >= 0) add_GT(p->Ga, mc, lam, mu, D->gl + 6 * pr->a, D->gm + 6 * pr->a);
      if (pr->b >= 0) add_GT(p->Gb, mc, lam, mu, D->gl + 6 * pr->b, D->gm + 6 * pr->b);
      if (!crows && d->workless[ip]) workless_at_stage(d, ip, lam);
    }
    if (!crows) continue;
    const double *ta = pr->a >= 0 ? D->tw + 6 * pr->a : zero6;
    const double *tb = pr->b >= 0 ? D->tw + 6 * pr->b : zero6;
    for (int r = 0; r < mc; r++) {
      double c = -p->vt[r];
      for (int j = 0; j < 6; j++) {
        c += p->Ga[6 * r + j] * ta[j];
        c += p->Gb[6 * r + j] * tb[j];
      }
      /* velocity constraint -> lambda, position constraint -> mu; both regularized
       * (dae_regularization: a proximal term in lambda, a compliance in mu) */
      F[d->il + r0 + r] = c + d->reg * D->lreg[r0 + r] * (y[d->il + r0 + r] - D->lref[r0 + r]);
      F[d->im + r0 + r] = p->g[r] + d->reg * D->mreg[r0 + r] * y[d->im + r0 + r];
    }
  }
}

/* The pairs' rows of the residual at the poses/twists already unpacked into d->data: joint
 * coordinate rates (F[ix..ie)), velocity constraints (F[il..im)) and position constraints
 * (F[im..n)); accumulates G^T lambda and G^T mu per carrier into gl, gm. No allocation. */
void dae_pair_rows(dae_t *d, double time, const double *y, const double *yp, double *F) {
  rows_of_pairs(d, time, y, yp, F, 1, 1);
}

/* The constraint rows alone (F[il..n)): the generalized-alpha evaluates them at the step's end
 * after the full residual at the stage. The full evaluation it used before also unpacked every
 * carrier and computed the joint rates and G^T lambda, G^T mu, all discarded; only the carriers
 * of the pairs are unpacked here (ic.clist: every pair's carriers, none without constraint rows).
 * No allocation. */
void dae_constraint_rows(dae_t *d, double time, const double *y, double *F) {
  if (d->pl) {
    dae_planar_constraint_rows(d, time, y, F);
    return;
  }
  const dae_ic_work *w = &d->data.ic;
  for (int k = 0; k < w->ncc; k++) unpack_carrier(y, w->clist[k], d->data.H, d->data.tw);
  rows_of_pairs(d, time, y, NULL, F, 0, 1);
}

int dae_residual(dae_t *d, double time, const double *y, const double *yp, double *F) {
  return dae_residual_rows(d, time, y, yp, F, 1);
}

/* The DAE residual; no allocation. The pairs are evaluated once (rows_of_pairs) and their
 * actuators read that evaluation. */
int dae_residual_rows(dae_t *d, double time, const double *y, const double *yp, double *F,
                      int crows) {
  if (d->pl) return dae_planar_residual(d, time, y, yp, F, crows);
  const phm_model *m = d->m;
  phm_data *D = &d->data;
  int nc = m->nc;
  dae_unpack(m, y, D->H, D->tw);
  double Pd = 0, Ps = 0;
  rows_of_pairs(d, time, y, yp, F, 1, crows);
  phm_applied_pairs(m, D->pair, D->H, D->tw, y + d->ix, time, d->tref, 1.0, D->wr, NULL, &Pd, &Ps,
                    D->pport, NULL);
  if (m->ncomp) /* components with internal states: their wrenches, rows z' - f and ledger terms */
    phm_components_apply(m, D->pair, D->H, D->tw, y + d->ix, y + d->iz, yp + d->iz, time, d->tref,
                         D->wr, NULL, F + d->iz, NULL, &Pd, &Ps);
  for (int c = 0; c < nc; c++) {
    const double *yc = y + PHM_NSTATE * c, *ypc = yp + PHM_NSTATE * c;
    double *Fc = F + PHM_NSTATE * c;
    const double *q = yc, *t = yc + 7, *Hc = D->H + 16 * c, *gm = D->gm + 6 * c;
    const double *ypq = ypc;
    double w[3] = {t[0] + gm[0], t[1] + gm[1], t[2] + gm[2]};
    double v[3] = {t[3] + gm[3], t[4] + gm[4], t[5] + gm[5]};
    if (d->kbody[c]) {
      /* in the body frame (dae_body_kinematics): 2 conj(q) (x) [q' - 1/2 q (x) (0, w)] / |q|^2
       * = 2 conj(q) (x) q' / |q|^2 - (0, w), and R^T [p' - R v] = R^T p' - v */
      double s2 = 2.0 / (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      Fc[0] = s2 * (q[0] * ypq[0] + q[1] * ypq[1] + q[2] * ypq[2] + q[3] * ypq[3]);
      Fc[1] = s2 * (q[0] * ypq[1] - q[1] * ypq[0] - q[2] * ypq[3] + q[3] * ypq[2]) - w[0];
      Fc[2] = s2 * (q[0] * ypq[2] - q[2] * ypq[0] - q[3] * ypq[1] + q[1] * ypq[3]) - w[1];
      Fc[3] = s2 * (q[0] * ypq[3] - q[3] * ypq[0] - q[1] * ypq[2] + q[2] * ypq[1]) - w[2];
      for (int i = 0; i < 3; i++) /* (R^T)_ij = R_ji = Hc[4 j + i] */
        Fc[4 + i] = Hc[i] * ypq[4] + Hc[4 + i] * ypq[5] + Hc[8 + i] * ypq[6] - v[i];
    } else {
      /* q' = 1/2 q (x) (0, w) */
      Fc[0] = ypq[0] + 0.5 * (q[1] * w[0] + q[2] * w[1] + q[3] * w[2]);
      Fc[1] = ypq[1] - 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]);
      Fc[2] = ypq[2] - 0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2]);
      Fc[3] = ypq[3] - 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0]);
      for (int i = 0; i < 3; i++)
        Fc[4 + i] = ypq[4 + i] - (Hc[4 * i] * v[0] + Hc[4 * i + 1] * v[1] + Hc[4 * i + 2] * v[2]);
    }
    double Mt[6], adm[6], Mtd[6];
    const double *M = d->m->car[d->m->car_u[c]].M; /* shared when identical (phm_model.car_u) */
    phm_mv6(M, t, Mt);
    phm_ad_dual_apply(t, Mt, adm);
    phm_mv6(M, ypc + 7, Mtd);
    for (int i = 0; i < 6; i++) Fc[7 + i] = Mtd[i] - adm[i] - D->wr[6 * c + i] - D->gl[6 * c + i];
    for (int i = 0; i < 6; i++) Ps += D->gl[6 * c + i] * t[i]; /* power of constraint wrenches */
  }
  for (int k = 0; k < m->nmc; k++) { /* consistent element masses couple their nodes' balances */
    const int ca = m->mc_a[k], cb = m->mc_b[k];
    double f[12];
    phm_element_inertia(phm_mc(m, k), phm_mc_rows(m, k), D->tw + 6 * ca, D->tw + 6 * cb,
                        yp + PHM_NSTATE * ca + 7, yp + PHM_NSTATE * cb + 7, 0.0, f, NULL);
    for (int i = 0; i < 6; i++) {
      F[PHM_NSTATE * ca + 7 + i] += f[i];
      F[PHM_NSTATE * cb + 7 + i] += f[6 + i];
    }
  }
  F[d->ie] = yp[d->ie] - Pd;
  F[d->ie + 1] = yp[d->ie + 1] - Ps;
  for (int k = 0; k < m->nport; k++) F[d->ie + 2 + k] = yp[d->ie + 2 + k] - D->pport[k];
  return 0;
}

void dae_free(dae_t *d) {
  dae_planar_free(d);
  phm_data *D = &d->data;
  dae_ic_work *w = &D->ic;
  void *bufs[] = {D->H, D->tw, D->pair, D->wr, D->gl, D->gm, D->pport, D->eff, D->rtmp, D->dtw, D->lref, D->lreg, D->mreg, w->cmap, w->clist, w->H, w->tw, w->qprev, w->Lc, w->lcfail, w->b1c, w->cg, w->acc, w->G,
                  w->X, w->A, w->b, w->g, w->vt, w->c1, w->lam, w->Hp, w->res, d->colptr,
                  d->rowind, d->nzkeep, d->kbody, d->workless};
  for (size_t i = 0; i < sizeof bufs / sizeof bufs[0]; i++) free(bufs[i]);
  phm_lstsq_work_free(&w->ls);
  ic_schur_free(w);
  memset(D, 0, sizeof *D);
  d->colptr = d->rowind = NULL;
  d->nzkeep = NULL;
  d->kbody = NULL;
  d->workless = NULL;
}

/* The consistent initial values' scratch (dae_consistent_ic): its systems are least-squares
 * problems in the columns of the constrained carriers only (G vanishes elsewhere). */
static phm_status ic_alloc(dae_t *d, phm_error *err) {
  const phm_model *m = d->m;
  dae_ic_work *w = &d->data.ic;
  size_t nc = (size_t)m->nc, nk = (size_t)m->ncons, n = (size_t)d->n;
  w->cmap = malloc(sizeof(int) * (nc + 1));
  w->clist = malloc(sizeof(int) * (nc + 1));
  if (!w->cmap || !w->clist) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  int ncc = 0;
  for (size_t c = 0; c < nc; c++) w->cmap[c] = -1;
  for (int ip = 0; ip < m->np; ip++) {
    int ab[2] = {m->pair[ip].a, m->pair[ip].b};
    for (int s = 0; s < 2; s++)
      if (ab[s] >= 0 && w->cmap[ab[s]] < 0) {
        w->cmap[ab[s]] = ncc;
        w->clist[ncc++] = ab[s];
      }
  }
  if (nk == 0) ncc = 0;
  w->ncc = ncc;
  /* the inertias are constant: whether the KKT path is ever taken is known now */
  w->kkt = 0;
  for (int k = 0; k < ncc; k++) {
    double L[36];
    if (phm_chol6(m->car[w->clist[k]].M, 0.0, 1e-10, L)) w->kkt = 1;
  }
  size_t n6c = 6 * (size_t)ncc, Nk = n6c + nk, na = nk * n6c;
  if (nk * nk > na) na = nk * nk;
  if (w->kkt && Nk * Nk > na) na = Nk * Nk;
  /* The dense least-squares systems (minimum-norm even with dependent rows) serve when the
   * sparse Schur complement is singular: a singular configuration. They are O(N^2) in memory
   * and O(N^3) in time, so only small models keep them (and those with a singular inertia on
   * a constrained carrier, which need the dense KKT system); a large model at a singular
   * configuration gets an error instead. */
  w->dense = w->kkt || na <= PHM_IC_DENSE_MAX;
  size_t nd = w->dense ? na : 0, ng = w->dense ? nk * n6c : 0;
  w->H = malloc(sizeof(double) * 16 * nc);
  w->tw = malloc(sizeof(double) * 6 * nc);
  w->qprev = malloc(sizeof(double) * n);
  w->Lc = malloc(sizeof(double) * 36 * nc);
  w->lcfail = malloc(sizeof(int) * nc);
  w->b1c = malloc(sizeof(double) * (6 * (size_t)ncc + 1));
  w->cg = m->nmc ? malloc(sizeof(double) * 30 * nc) : NULL;
  w->acc = malloc(sizeof(double) * 6 * nc);
  w->G = malloc(sizeof(double) * (ng + 1));
  w->X = malloc(sizeof(double) * (ng + 1));
  w->A = malloc(sizeof(double) * (nd + 1));
  w->b = malloc(sizeof(double) * (Nk + 6 * nc + 1));
  w->g = malloc(sizeof(double) * (nk + 1));
  w->vt = malloc(sizeof(double) * (nk + 1));
  w->c1 = malloc(sizeof(double) * (2 * nk + 1));
  w->lam = malloc(sizeof(double) * (nk + 1));
  w->Hp = malloc(sizeof(double) * 16 * nc);
  w->res = malloc(sizeof(double) * n);
  if (!w->H || !w->tw || !w->qprev || !w->Lc || !w->lcfail || !w->b1c || (m->nmc && !w->cg) || !w->acc || !w->G || !w->X || !w->A || !w->b ||
      !w->g || !w->vt || !w->c1 || !w->lam || !w->Hp || !w->res)
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  phm_status st = ic_schur_alloc(d, err);
  if (st) return st;
  /* the systems: positions and velocities (nk x n6c), Schur complement (nk x nk), a free
   * carrier's own inertia (6 x 6), the KKT system (Nk x Nk) */
  int shapes[] = {(int)nk, (int)n6c, (int)nk, (int)nk, 6, 6, (int)Nk, (int)Nk};
  return w->dense ? phm_lstsq_work_alloc(&w->ls, w->kkt ? 4 : 3, shapes, err)
                  : phm_lstsq_work_alloc(&w->ls, 1, shapes + 4, err);
}

/* d->workless: the pairs whose wrench workless_at_stage corrects: those on a loop (regularized,
 * dae_regularization: where the defect's work moved A02's phase) between rigid bodies (or a
 * rigid body and the ground). Not where a side is a node of a flexible link or shares a mass
 * coupling, nor on an open chain: there the ledger's figure of numerical dissipation reports
 * the mesh's modes above the band, damped by the generalized-alpha, and corrected wrenches
 * moved it (the stiffened arm + strip of tests/accuracy/test_flexible_link_inertia.py at rtol
 * 1e-7, 3e-5 rad off: 26 rtol of its energy scale removed and warned of; corrected on every
 * pair, 0.6 rtol; on its rigid shoulder alone, 18 rtol, under the warning's 20, with the error
 * unchanged). The open chains' defect did little work where measured (the chain of 100 bodies
 * of tests/accuracy, 0.5 s: 6.4e-7 J of 107 J). Uses kbody as scratch. */
static void workless_pairs(dae_t *d) {
  const phm_model *m = d->m;
  unsigned char *flexible = d->kbody;
  for (int e = 0; e < m->ne; e++) flexible[m->el_ab[2 * e]] = flexible[m->el_ab[2 * e + 1]] = 1;
  for (int k = 0; k < m->nmc; k++) flexible[m->mc_a[k]] = flexible[m->mc_b[k]] = 1;
  for (int ip = 0; ip < m->np; ip++) {
    int a = m->pair[ip].a, b = m->pair[ip].b;
    d->workless[ip] = m->pair_m[ip] > 0 && d->data.mreg[m->pair_row[ip]] > 0 &&
                      (a < 0 || !flexible[a]) && (b < 0 || !flexible[b]);
  }
  memset(flexible, 0, (size_t)m->nc);
}

phm_status dae_init(dae_t *d, const phm_model *m, phm_error *err) {
  memset(d, 0, sizeof *d);
  d->m = m;
  d->reg = 1.0;
  d->lscale = dae_length_scale(m);
  d->ns = PHM_NSTATE;
  d->nt0 = 7;
  d->ix = PHM_NSTATE * m->nc;
  d->iz = d->ix + m->nj;
  d->ie = d->iz + m->nz;
  d->il = d->ie + 2 + m->nport;
  d->im = d->il + m->ncons;
  d->n = d->im + m->ncons;
  d->nnorm = d->n;
  phm_data *D = &d->data;
  size_t nc = (size_t)m->nc, n = (size_t)d->n;
  D->H = malloc(sizeof(double) * 16 * nc);
  D->tw = malloc(sizeof(double) * 6 * nc);
  D->pair = malloc(sizeof(phm_pair_data) * (size_t)(m->np + 1));
  D->wr = malloc(sizeof(double) * 6 * nc);
  D->gl = malloc(sizeof(double) * 6 * nc);
  D->gm = malloc(sizeof(double) * 6 * nc);
  D->pport = malloc(sizeof(double) * (size_t)(m->nport + 1));
  D->eff = malloc(sizeof(double) * (size_t)(m->nj + 1));
  D->rtmp = malloc(sizeof(double) * n);
  D->dtw = calloc(6 * nc + 1, sizeof(double));
  D->lref = calloc((size_t)m->ncons + 1, sizeof(double));
  D->lreg = calloc((size_t)m->ncons + 1, sizeof(double));
  D->mreg = calloc((size_t)m->ncons + 1, sizeof(double));
  d->kbody = calloc(nc + 1, 1);
  d->workless = calloc((size_t)m->np + 1, 1);
  phm_status st = PHM_OK;
  if (!D->H || !D->tw || !D->pair || !D->wr || !D->gl || !D->gm || !D->pport || !D->eff ||
      !D->rtmp || !D->dtw || !D->lref || !D->lreg || !D->mreg || !d->kbody || !d->workless)
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  else
    st = ic_alloc(d, err);
  if (!st) st = dae_regularization(d, err);
  if (!st) workless_pairs(d);
  if (st) dae_free(d);
  return st;
}

void dae_body_kinematics(dae_t *d, int on) {
  d = dae_full(d);
  const phm_model *m = d->m;
  memset(d->kbody, 0, (size_t)m->nc);
  if (!on) return;
  for (int ip = 0; ip < m->np; ip++)
    if (m->pair_m[ip] > 0) {
      if (m->pair[ip].a >= 0) d->kbody[m->pair[ip].a] = 1;
      if (m->pair[ip].b >= 0) d->kbody[m->pair[ip].b] = 1;
    }
}

/* Absolute tolerance of state i (IDA's error weights; the generalized-alpha's Newton test).
 * mu (GGL) is a velocity correction whose exact value is zero. Near a tiny step size h (first
 * step, restart after a breakpoint) Newton's corrections of mu are ~ |g round-off| / h: with
 * positions |p| ~ 0.3 m, g carries ~ 5e-17 of round-off, and at h ~ 1e-10 mu moves by ~ 1e-6,
 * so a weight 1/atol on mu made the corrector "diverge" (IDA_CONV_FAIL, h -> 1e-15). mu is
 * left out of the error test, and its convergence is already measured through the positions
 * it corrects (by h G^T mu); so its absolute tolerance is 1 (rad/s, m/s).
 * lambda (constraint wrench, also left out of the error test) has the same defect one level
 * down: its corrections are ~ M |G t round-off| / h. With IDA's default first step
 * 0.5/|y'|_WRMS ~ 1e-11 s (a body at rest with a nonzero acceleration, atol 1e-10) a weight
 * 1/atol on lambda failed the corrector, h shrank by 4 per failure and IDA crept on at
 * h ~ 1e-18 (an open chain "hung" in IDASolve). Two measured remedies together: a first step
 * of min(1e-8 s, 1e-3 of the span), and an absolute tolerance of at least 1e-6 (N, N m) on
 * lambda -- enough for the four-bar at rtol 1e-10 (atol 1e-12), while lambda stays accurate
 * enough for the energy ledger (lambda . rate of driven pairs); an absolute tolerance of 1
 * cost a 350x larger energy drift in a flexible slider-crank and a 1.45e-6 ledger residual. */
double dae_state_atol(const dae_t *d, int i, double atol) {
  return i >= d->im ? fmax(1.0, atol) /* mu */ : i >= d->il ? fmax(1e-6, atol) /* lambda */ : atol;
}

void dae_carrier_states(const dae_t *d, dae_carrier_layout *L) {
  if (d->pl) {
    dae_planar_carrier_states(d, L);
    return;
  }
  L->nq = 4;
  L->npos = 3;
  L->nt = 6;
  for (int i = 0; i < 6; i++) L->tf[i] = i;
  for (int i = 0; i < 4; i++) L->qf[i] = i;
  for (int i = 0; i < 3; i++) L->pf[i] = i;
}

/* dtw's carrier c (-1: none) = at times its twist's change in dy (full layout; planar: the
 * in-plane components, the others stay 0) */
static void twist_change(const dae_t *d, const dae_carrier_layout *L, const double *dy, double at,
                         int c, double *dtw) {
  if (c < 0) return;
  for (int j = 0; j < L->nt; j++) dtw[6 * c + L->tf[j]] = at * dy[d->ns * c + d->nt0 + j];
}

void dae_ledger_dpower(dae_t *d, double time, const double *y, const double *dy, double at,
                       double *dP) {
  const phm_model *m = d->m;
  dae_t *f = dae_full(d);
  phm_data *D = &f->data;
  dae_carrier_layout L;
  dae_carrier_states(d, &L);
  /* the stage's change of the twists of the carriers of the pairs (and so of the actuators)
   * and of the loads: only those are read (all of them: 2 % of the N = 30 cantilever's run) */
  double *dtw = D->dtw;
  for (int ip = 0; ip < m->np; ip++) {
    twist_change(d, &L, dy, at, m->pair[ip].a, dtw);
    twist_change(d, &L, dy, at, m->pair[ip].b, dtw);
  }
  for (int il = 0; il < m->nl; il++) {
    twist_change(d, &L, dy, at, m->load[il].carrier, dtw);
    twist_change(d, &L, dy, at, m->load[il].reaction, dtw);
  }
  for (int i = 0; i < d->il - d->ie; i++) dP[i] = 0.0;
  phm_applied_dpower(m, D->pair, D->H, dtw, time, f->tref, dP + 1, dP + 2);
  /* the constraint wrenches' power sum_c (G^T lambda)_c . t_c (dae_residual's Ps); a workless
   * pair's (workless_at_stage) is lambda . v_t, ~ lambda . G t at the step's end, whatever the
   * twists: only its dl G t */
  const double *lam = y + d->il, *dlam = dy + d->il;
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    const phm_pair_data *p = D->pair + ip;
    int r0 = m->pair_row[ip], workless = f->workless[ip];
    for (int s = 0; s < 2; s++) {
      int c = s ? pr->b : pr->a;
      if (c < 0) continue;
      const double *G = s ? p->Gb : p->Ga, *t = D->tw + 6 * c, *dt = dtw + 6 * c;
      for (int r = 0; r < m->pair_m[ip]; r++)
        dP[1] += (workless ? 0.0 : (lam[r0 + r] + dlam[r0 + r]) * phm_dot(G + 6 * r, dt, 6)) +
                 dlam[r0 + r] * phm_dot(G + 6 * r, t, 6); /* (l + dl) G (t + dt) - l G t */
    }
  }
}

/* State i is a carrier's twist component (layout: q[4], p[3], t[6] per carrier, or the planar
 * q_w, q_z, p_x, p_y, omega_z, v_x, v_y). */
int dae_is_twist(const dae_t *d, int i) { return i < d->ix && i % d->ns >= d->nt0; }
