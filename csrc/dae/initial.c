/* initial.c -- consistent initial values of the DAE (at the start and at every breakpoint of the
 * laws): positions projected onto g = 0, twists onto G t = vt (minimum-norm corrections), then
 * the acceleration level solved for t' and lambda. */
#include "dae.h"

#include <math.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"
#include "pose.h"

/* Project poses H (nc x 16) onto g = 0 and twists tw onto G t = vt (minimum-norm corrections);
 * then solve the acceleration-level system for t' and lambda. Writes y (carrier blocks and lambda,
 * mu = 0) and yp (all but the ledger values in y, which the caller sets). qprev: previous
 * quaternions for sign continuity.
 * Structure: G only touches the carriers of the pairs (cmap), so the projections are least-squares
 * problems in those columns only (the minimum-norm correction is zero elsewhere); the acceleration
 * level eliminates the block-diagonal mass: S lambda = b2 - G M^-1 b1 with S = G M^-1 G^T (nk x nk,
 * minimum-norm lambda for redundant rows), t' = M^-1 (b1 + G^T lambda). If a constrained carrier's
 * inertia is singular, the KKT system of the constrained carriers is solved instead. */
phm_status dae_consistent_ic(dae_t *d, double time, double *H, double *tw, const double *qprev,
                             const double *xs, int check_x0, double *y, double *yp,
                             phm_error *err) {
  const phm_model *m = d->m;
  dae_ic_work *w = &d->data.ic;
  int nc = m->nc, nk = m->ncons;
  phm_status st = PHM_OK;
  const int *cmap = w->cmap, *clist = w->clist;
  double *Lc = w->Lc, *acc = w->acc, *lam = w->lam, *G = w->G, *A = w->A, *b = w->b, *g = w->g;
  double *vt = w->vt, *Hp = w->Hp, *c1 = w->c1, *X = w->X;
  int ncc = w->ncc, n6c = 6 * ncc, Nk = n6c + nk;
  if (nk > 0) {
    /* positions */
    double gn = 0;
    int it;
    for (it = 0; it < 50; it++) {
      phm_constraints_columns(m, H, xs, time, d->tref, cmap, n6c, g, G, NULL);
      gn = 0;
      for (int i = 0; i < nk; i++) gn = fmax(gn, fabs(g[i]));
      if (gn < 1e-13) break;
      memcpy(A, G, sizeof(double) * (size_t)nk * n6c);
      for (int i = 0; i < nk; i++) b[i] = -g[i];
      if ((st = phm_lstsq_in(nk, n6c, A, b, NULL, &w->ls, err))) goto done;
      for (int k = 0; k < ncc; k++) phm_retract(H + 16 * clist[k], b + 6 * k);
    }
    if (gn > 1e-9) {
      st = PHM_FAIL(err, PHM_EINVAL, "initial configuration: position constraints cannot be met (|g| = %.3e after projection); check the pairs' frames", gn);
      goto done;
    }
    /* velocities */
    phm_constraints_columns(m, H, xs, time, d->tref, cmap, n6c, NULL, G, vt);
    for (int r = 0; r < nk; r++) {
      double s = -vt[r];
      for (int k = 0; k < ncc; k++)
        for (int j = 0; j < 6; j++) s += G[(size_t)r * n6c + 6 * k + j] * tw[6 * clist[k] + j];
      b[r] = -s;
    }
    memcpy(A, G, sizeof(double) * (size_t)nk * n6c);
    if ((st = phm_lstsq_in(nk, n6c, A, b, NULL, &w->ls, err))) goto done;
    for (int k = 0; k < ncc; k++)
      for (int j = 0; j < 6; j++) tw[6 * clist[k] + j] += b[6 * k + j];
  }
  /* acceleration level: [M -G^T; G 0] [t'; lambda] = [b1; b2], b1 = ad^T M t + w, b2 = -dc/dt */
  phm_applied(m, H, tw, xs, time, d->tref, 1.0, d->data.wr, NULL, NULL, NULL, NULL, NULL);
  int spd = 1;
  for (int c = 0; c < nc; c++) {
    const double *M = m->car[c].M;
    double Mt[6], adm[6];
    phm_mv6(M, tw + 6 * c, Mt);
    phm_ad_dual_apply(tw + 6 * c, Mt, adm);
    for (int i = 0; i < 6; i++) acc[6 * c + i] = adm[i] + d->data.wr[6 * c + i];
    if (phm_chol6(M, 0.0, 1e-10, Lc + 36 * c)) {
      if (cmap[c] >= 0 && nk > 0) spd = 0;
      else { /* free carrier with singular inertia: minimum-norm solution of its own block */
        double Mc[36], bc[6];
        memcpy(Mc, M, sizeof Mc);
        memcpy(bc, acc + 6 * c, sizeof bc);
        if ((st = phm_lstsq_in(6, 6, Mc, bc, NULL, &w->ls, err))) goto done;
        memcpy(acc + 6 * c, bc, sizeof bc);
      }
    } else if (cmap[c] < 0 || nk == 0) phm_chol6_solve(Lc + 36 * c, acc + 6 * c);
  }
  if (nk > 0) {
    phm_constraints_columns(m, H, xs, time, d->tref, cmap, n6c, NULL, G, NULL);
    /* dc/dt at fixed t' by central differences along the motion */
    double tau = 1e-6;
    for (int side = 0; side < 2; side++) {
      double s = side ? -tau : tau;
      memcpy(Hp, H, sizeof(double) * 16 * (size_t)nc);
      for (int k = 0; k < ncc; k++) {
        int c = clist[k];
        double dl[6];
        for (int i = 0; i < 6; i++) dl[i] = s * tw[6 * c + i];
        phm_retract(Hp + 16 * c, dl);
      }
      phm_constraints_columns(m, Hp, xs, time + s, d->tref, cmap, n6c, NULL, X, vt);
      for (int r = 0; r < nk; r++) {
        double a = -vt[r];
        for (int k = 0; k < ncc; k++)
          for (int j = 0; j < 6; j++) a += X[(size_t)r * n6c + 6 * k + j] * tw[6 * clist[k] + j];
        c1[side * nk + r] = a;
      }
    }
    double *b2 = c1 + nk; /* reuse: b2 = -dc/dt */
    for (int r = 0; r < nk; r++) b2[r] = -(c1[r] - c1[nk + r]) / (2 * tau);
    if (spd) {
      /* X = M^-1 G^T (n6c x nk, row-major); S = G X; rhs = b2 - G M^-1 b1 */
      for (int k = 0; k < ncc; k++) {
        const double *L = Lc + 36 * clist[k];
        double *a = acc + 6 * clist[k];
        phm_chol6_solve(L, a); /* a = M^-1 b1 */
        for (int r = 0; r < nk; r++) {
          double x[6];
          for (int j = 0; j < 6; j++) x[j] = G[(size_t)r * n6c + 6 * k + j];
          phm_chol6_solve(L, x);
          for (int j = 0; j < 6; j++) X[(size_t)(6 * k + j) * nk + r] = x[j];
        }
      }
      for (int r = 0; r < nk; r++) {
        const double *Gr = G + (size_t)r * n6c;
        for (int s = 0; s < nk; s++) {
          double v = 0;
          for (int j = 0; j < n6c; j++) v += Gr[j] * X[(size_t)j * nk + s];
          A[(size_t)r * nk + s] = v;
        }
        double v = b2[r];
        for (int k = 0; k < ncc; k++)
          for (int j = 0; j < 6; j++) v -= Gr[6 * k + j] * acc[6 * clist[k] + j];
        b[r] = v;
      }
      for (int r = 0; r < nk; r++) /* symmetrize */
        for (int s = 0; s < r; s++) A[(size_t)r * nk + s] = A[(size_t)s * nk + r] = 0.5 * (A[(size_t)r * nk + s] + A[(size_t)s * nk + r]);
      if ((st = phm_lstsq_in(nk, nk, A, b, NULL, &w->ls, err))) goto done;
      memcpy(lam, b, sizeof(double) * (size_t)nk);
      for (int k = 0; k < ncc; k++)
        for (int j = 0; j < 6; j++) {
          double v = 0;
          for (int r = 0; r < nk; r++) v += X[(size_t)(6 * k + j) * nk + r] * lam[r];
          acc[6 * clist[k] + j] += v;
        }
    } else {
      /* KKT system of the constrained carriers, minimum-norm least squares (ic_alloc in
       * csrc/dae/residual.c sized A for it: w->kkt) */
      if (!w->kkt) {
        st = PHM_FAIL(err, PHM_ESINGULAR, "consistent initial values: a constrained carrier's inertia failed the Cholesky test that set-up passed");
        goto done;
      }
      memset(A, 0, sizeof(double) * (size_t)Nk * Nk);
      for (int k = 0; k < ncc; k++) {
        const double *M = m->car[clist[k]].M;
        for (int i = 0; i < 6; i++) {
          for (int j = 0; j < 6; j++) A[(size_t)(6 * k + i) * Nk + 6 * k + j] = M[6 * i + j];
          b[6 * k + i] = acc[6 * clist[k] + i];
        }
      }
      for (int r = 0; r < nk; r++) {
        for (int j = 0; j < n6c; j++) {
          A[(size_t)(n6c + r) * Nk + j] = G[(size_t)r * n6c + j];
          A[(size_t)j * Nk + n6c + r] = -G[(size_t)r * n6c + j];
        }
        b[n6c + r] = b2[r];
      }
      if ((st = phm_lstsq_in(Nk, Nk, A, b, NULL, &w->ls, err))) goto done;
      for (int k = 0; k < ncc; k++) memcpy(acc + 6 * clist[k], b + 6 * k, 6 * sizeof(double));
      memcpy(lam, b + n6c, sizeof(double) * (size_t)nk);
    }
  }
  /* write y and yp */
  for (int c = 0; c < nc; c++) {
    double *yc = y + PHM_NSTATE * c, *ypc = yp + PHM_NSTATE * c;
    phm_H_to_qp(H + 16 * c, yc, yc + 4);
    if (qprev) {
      const double *qo = qprev + PHM_NSTATE * c;
      if (yc[0] * qo[0] + yc[1] * qo[1] + yc[2] * qo[2] + yc[3] * qo[3] < 0)
        for (int i = 0; i < 4; i++) yc[i] = -yc[i];
    }
    memcpy(yc + 7, tw + 6 * c, 6 * sizeof(double));
    const double *q = yc, *w = tw + 6 * c, *v = tw + 6 * c + 3, *Hc = H + 16 * c;
    ypc[0] = -0.5 * (q[1] * w[0] + q[2] * w[1] + q[3] * w[2]);
    ypc[1] = 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]);
    ypc[2] = 0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2]);
    ypc[3] = 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0]);
    for (int i = 0; i < 3; i++) ypc[4 + i] = Hc[4 * i] * v[0] + Hc[4 * i + 1] * v[1] + Hc[4 * i + 2] * v[2];
    memcpy(ypc + 7, acc + 6 * c, 6 * sizeof(double));
  }
  for (int r = 0; r < nk; r++) {
    y[d->il + r] = lam[r];
    y[d->im + r] = 0;
    yp[d->il + r] = yp[d->im + r] = 0;
  }
  /* joint coordinates: exact values on the branch of xs */
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int j0 = m->pair_j[ip], k = m->pair_k[ip];
    if (k == 0) continue;
    double x[6];
    phm_pair_joint(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                   NULL, NULL, xs + j0, x, NULL);
    if (check_x0 && pr->has_x0)
      for (int c = 0; c < k; c++)
        if (fabs(x[c] - pr->x0[c]) > 1e-6 * (1 + fabs(pr->x0[c]))) {
          st = PHM_FAIL(err, PHM_EINVAL, "pair %d: initial joint coordinate %d is %.9g in the initial configuration, not x0 = %.9g; place the bodies accordingly", ip, c, x[c], pr->x0[c]);
          goto done;
        }
    memcpy(y + d->ix + j0, x, sizeof(double) * (size_t)k);
  }
  /* rates of the joint coordinates and of the ledger from the residual (yp = 0 there) */
  for (int i = d->ix; i < d->il; i++) yp[i] = 0;
  dae_residual(d, time, y, yp, w->res);
  for (int i = d->ix; i < d->il; i++) yp[i] = -w->res[i];
done:
  return st;
}

/* At a breakpoint of the laws (a new piece): the new reference time and next breakpoint *nbp
 * (the piece that follows time tpiece: t, or the breakpoint when t is within round-off before
 * it), then consistent values from the current poses and twists; the ledger integrals carry
 * over. The poses, twists and previous state (for quaternion sign continuity) are kept in the
 * data's scratch: a restart allocates nothing. */
phm_status dae_restart_at_breakpoint(dae_t *d, double t, double tpiece, double *nbp, double *y,
                                     double *yp, phm_error *err) {
  double *H = d->data.ic.H, *tw = d->data.ic.tw, *qprev = d->data.ic.qprev;
  d->tref = phm_model_tref(d->m, tpiece, nbp);
  dae_unpack(d->m, y, H, tw);
  memcpy(qprev, y, sizeof(double) * (size_t)d->n);
  phm_status st = dae_consistent_ic(d, t, H, tw, qprev, qprev + d->ix, 0, y, yp, err);
  if (st) return st;
  for (int i = d->ie; i < d->il; i++) y[i] = qprev[i];
  return PHM_OK;
}
