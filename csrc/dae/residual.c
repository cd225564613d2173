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

/* Carrier poses H (nc x 16) and twists tw (nc x 6) from the state vector y. */
void dae_unpack(const phm_model *m, const double *y, double *H, double *tw) {
  for (int c = 0; c < m->nc; c++) {
    const double *yc = y + PHM_NSTATE * c;
    phm_qp_to_H(yc, yc + 4, H + 16 * c);
    memcpy(tw + 6 * c, yc + 7, 6 * sizeof(double));
  }
}

/* The pairs' rows of the residual at the poses/twists already unpacked into d->H, d->tw: joint
 * coordinate rates (F[ix..ie)), velocity constraints (F[il..im)) and position constraints
 * (F[im..n)); accumulates G^T lambda and G^T mu per carrier into d->gl, d->gm. No allocation. */
void dae_pair_rows(dae_t *d, double time, const double *y, const double *yp, double *F) {
  const phm_model *m = d->m;
  int nc = m->nc;
  const double *xs = y + d->ix;
  memset(d->gl, 0, sizeof(double) * 6 * (size_t)nc);
  memset(d->gm, 0, sizeof(double) * 6 * (size_t)nc);
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int r0 = m->pair_row[ip], mc = m->pair_m[ip];
    double g[PHM_MAXCON], Ga[6 * PHM_MAXCON], Gb[6 * PHM_MAXCON], vt[PHM_MAXCON], x[6], xd[6];
    const double *Ha = pr->a >= 0 ? d->H + 16 * pr->a : NULL, *Hb = pr->b >= 0 ? d->H + 16 * pr->b : NULL;
    int j0 = m->pair_j[ip], k = m->pair_k[ip];
    phm_pair_eval(m, ip, Ha, Hb, xs + j0, time, d->tref, g, Ga, Gb, vt);
    if (k > 0) {
      phm_pair_joint(m, ip, Ha, Hb, pr->a >= 0 ? d->tw + 6 * pr->a : NULL,
                     pr->b >= 0 ? d->tw + 6 * pr->b : NULL, xs + j0, x, xd);
      for (int c = 0; c < k; c++) F[d->ix + j0 + c] = yp[d->ix + j0 + c] - xd[c];
    }
    const double *lam = y + d->il + r0, *mu = y + d->im + r0;
    for (int r = 0; r < mc; r++) {
      double c = -vt[r];
      for (int j = 0; j < 6; j++) {
        if (pr->a >= 0) {
          c += Ga[6 * r + j] * d->tw[6 * pr->a + j];
          d->gl[6 * pr->a + j] += Ga[6 * r + j] * lam[r];
          d->gm[6 * pr->a + j] += Ga[6 * r + j] * mu[r];
        }
        if (pr->b >= 0) {
          c += Gb[6 * r + j] * d->tw[6 * pr->b + j];
          d->gl[6 * pr->b + j] += Gb[6 * r + j] * lam[r];
          d->gm[6 * pr->b + j] += Gb[6 * r + j] * mu[r];
        }
      }
      F[d->il + r0 + r] = c;    /* velocity constraint -> lambda */
      F[d->im + r0 + r] = g[r]; /* position constraint -> mu     */
    }
  }
}

/* The DAE residual; no allocation. */
int dae_residual(dae_t *d, double time, const double *y, const double *yp, double *F) {
  const phm_model *m = d->m;
  int nc = m->nc;
  dae_unpack(m, y, d->H, d->tw);
  double Pd = 0, Ps = 0;
  phm_applied(m, d->H, d->tw, y + d->ix, time, d->tref, 1.0, d->wr, NULL, &Pd, &Ps, d->pport, NULL);
  dae_pair_rows(d, time, y, yp, F);
  for (int c = 0; c < nc; c++) {
    const double *yc = y + PHM_NSTATE * c, *ypc = yp + PHM_NSTATE * c;
    double *Fc = F + PHM_NSTATE * c;
    const double *q = yc, *t = yc + 7, *Hc = d->H + 16 * c, *gm = d->gm + 6 * c;
    double w[3] = {t[0] + gm[0], t[1] + gm[1], t[2] + gm[2]};
    double v[3] = {t[3] + gm[3], t[4] + gm[4], t[5] + gm[5]};
    /* q' = 1/2 q (x) (0, w) */
    Fc[0] = ypc[0] + 0.5 * (q[1] * w[0] + q[2] * w[1] + q[3] * w[2]);
    Fc[1] = ypc[1] - 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]);
    Fc[2] = ypc[2] - 0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2]);
    Fc[3] = ypc[3] - 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0]);
    for (int i = 0; i < 3; i++)
      Fc[4 + i] = ypc[4 + i] - (Hc[4 * i] * v[0] + Hc[4 * i + 1] * v[1] + Hc[4 * i + 2] * v[2]);
    double Mt[6], adm[6], Mtd[6];
    phm_mv6(d->m->car[c].M, t, Mt);
    phm_ad_dual_apply(t, Mt, adm);
    phm_mv6(d->m->car[c].M, ypc + 7, Mtd);
    for (int i = 0; i < 6; i++) Fc[7 + i] = Mtd[i] - adm[i] - d->wr[6 * c + i] - d->gl[6 * c + i];
    for (int i = 0; i < 6; i++) Ps += d->gl[6 * c + i] * t[i]; /* power of constraint wrenches */
  }
  F[d->ie] = yp[d->ie] - Pd;
  F[d->ie + 1] = yp[d->ie + 1] - Ps;
  for (int k = 0; k < m->nport; k++) F[d->ie + 2 + k] = yp[d->ie + 2 + k] - d->pport[k];
  return 0;
}

void dae_free(dae_t *d) {
  free(d->H);
  free(d->tw);
  free(d->wr);
  free(d->gl);
  free(d->gm);
  free(d->pport);
  free(d->eff);
  free(d->colptr);
  free(d->rowind);
  free(d->color);
  free(d->ytmp);
  free(d->yptmp);
  free(d->rtmp);
  free(d->r0);
}

phm_status dae_init(dae_t *d, const phm_model *m, phm_error *err) {
  memset(d, 0, sizeof *d);
  d->m = m;
  d->ix = PHM_NSTATE * m->nc;
  d->ie = d->ix + m->nj;
  d->il = d->ie + 2 + m->nport;
  d->im = d->il + m->ncons;
  d->n = d->im + m->ncons;
  size_t nc = (size_t)m->nc;
  d->H = malloc(sizeof(double) * 16 * nc);
  d->tw = malloc(sizeof(double) * 6 * nc);
  d->wr = malloc(sizeof(double) * 6 * nc);
  d->gl = malloc(sizeof(double) * 6 * nc);
  d->gm = malloc(sizeof(double) * 6 * nc);
  d->pport = malloc(sizeof(double) * (size_t)(m->nport + 1));
  d->eff = malloc(sizeof(double) * (size_t)(m->nj + 1));
  if (!d->H || !d->tw || !d->wr || !d->gl || !d->gm || !d->pport || !d->eff) {
    dae_free(d);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
  return PHM_OK;
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

/* State i is a carrier's twist component (layout: q[4], p[3], t[6] per carrier). */
int dae_is_twist(const dae_t *d, int i) { return i < d->ix && i % PHM_NSTATE >= 7; }
