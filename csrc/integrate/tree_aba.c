/* tree_aba.c -- the tree integrator's model (tree_internal.h): which models it takes, their tree of
 * bodies and joints, and the O(n) articulated-body algorithm (Featherstone) in body frames.
 *
 * Body c hangs from its parent p (or the ground) by the pair whose b side it is: its pose
 * H_c = H_p L_c with L_c = Ta h(q_c) Tb^-1 (h: phm_pair_type_pose, a rotation about and a
 * translation along z for the types taken, so L_c is linear in cos, sin of the angle and in the
 * slide: precomputed), its twist v_c = X_c v_p + S_c qd_c with
 * X_c = Ad_{H_c^-1 H_p} and S_c = Ad_Tb psi (psi: the type's constant motion subspace in F_b),
 * its acceleration a_c = X_c a_p + S_c qdd_c + c_c with c_c = ad_{v_c} (S_c qd_c). Its momentum
 * balance is the DAE's (csrc/dae/residual.c): M a - ad*_v (M v) = wr + (the joint's wrench) -
 * (its children's, carried back by X^T); wr: every applied wrench of phm_applied (gravity,
 * springs, loads, actuators' efforts on both sides of their pair) and the stateless components'. */
#include "tree_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "pose.h"

void tree_free(tree_work *w) {
  void *p[] = {w->order, w->par, w->pair, w->k, w->j0, w->S, w->K, w->ds, w->ti, w->di, w->H, w->v, w->cb,
               w->X, w->IA, w->pA, w->U, w->Dinv, w->u, w->acc, w->wr, w->pport, w->y, w->y1,
               w->yt, w->err, w->ydae, w->isrt};
  for (size_t i = 0; i < sizeof p / sizeof p[0]; i++) free(p[i]);
  for (int i = 0; i < 7; i++) free(w->ks[i]);
  for (int i = 0; i < 5; i++) free(w->rc[i]);
  memset(w, 0, sizeof *w);
}

/* C = A B for general 4x4 matrices (row-major): the P_e below are not poses, so
 * phm_se3_compose, which takes the last rows as (0, 0, 0, 1), does not apply. */
static void mul4(const double A[16], const double B[16], double C[16]) {
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      double sum = 0;
      for (int l = 0; l < 4; l++) sum += A[4 * i + l] * B[4 * l + j];
      C[4 * i + j] = sum;
    }
}

/* The type's motion subspace in F_b (constant: h = exp(sum psi_c x_c) with commuting psi_c), or
 * -1 if it has none of that kind; its angle's coordinate *ti and slide's *di, *ds (see
 * tree_work.K). */
static int type_psi(const char *name, double pitch, double psi[6 * TREE_MAXK], int *ti, int *di,
                    double *ds) {
  memset(psi, 0, sizeof(double) * 6 * TREE_MAXK);
  *ti = *di = -1;
  *ds = 0.0;
  if (!strcmp(name, "fixed")) return 0;
  if (!strcmp(name, "revolute")) { psi[2] = 1; *ti = 0; return 1; }
  if (!strcmp(name, "prismatic")) { psi[5] = 1; *di = 0; *ds = 1; return 1; }
  if (!strcmp(name, "helical")) { psi[2] = 1; psi[5] = pitch; *ti = 0; *di = 0; *ds = pitch; return 1; }
  if (!strcmp(name, "cylindrical")) { psi[2] = 1; psi[6 + 5] = 1; *ti = 0; *di = 1; *ds = 1; return 2; }
  return -1;
}

phm_status tree_build(const dae_t *d, tree_work *w, phm_error *err) {
  memset(w, 0, sizeof *w);
  const phm_model *m = d->m;
  const char *why = "the tree integrator takes trees of rigid bodies in joint coordinates";
  if (d->pl) return PHM_FAIL(err, PHM_EINVAL, "%s in 3-D: planar=False", why);
  if (m->ne) return PHM_FAIL(err, PHM_EINVAL, "%s: the model has %d beam element(s) (flexible)", why, m->ne);
  if (m->nmc) return PHM_FAIL(err, PHM_EINVAL, "%s: the model has %d kinetic coupling(s) between carriers (consistent element masses, motors' rotor inertias)", why, m->nmc);
  if (m->nz) return PHM_FAIL(err, PHM_EINVAL, "%s: the model's components have %d internal state(s) (LuGre, motor currents, controllers)", why, m->nz);
  if (m->ncons != m->ncons_full) return PHM_FAIL(err, PHM_EINVAL, "%s: %d constraint row(s) are dropped as redundant (a closed loop)", why, m->ncons_full - m->ncons);
  int nc = m->nc;
  w->m = m;
  w->nb = nc;
  w->nj = m->nj;
  w->nled = d->il - d->ie;
  w->N = 2 * m->nj + w->nled;
#define ALLOC(p, cnt, T) if (!((p) = calloc((size_t)(cnt) + 1, sizeof(T)))) goto nomem
  ALLOC(w->order, nc, int); ALLOC(w->par, nc, int); ALLOC(w->pair, nc, int);
  ALLOC(w->k, nc, int); ALLOC(w->j0, nc, int); ALLOC(w->isrt, nc, int);
  ALLOC(w->S, 6 * TREE_MAXK * nc, double); ALLOC(w->K, 64 * nc, double); ALLOC(w->ds, nc, double);
  ALLOC(w->ti, nc, int); ALLOC(w->di, nc, int);
  ALLOC(w->H, 16 * nc, double); ALLOC(w->v, 6 * nc, double); ALLOC(w->cb, 6 * nc, double);
  ALLOC(w->X, 36 * nc, double); ALLOC(w->IA, 36 * nc, double); ALLOC(w->pA, 6 * nc, double);
  ALLOC(w->U, 6 * TREE_MAXK * nc, double); ALLOC(w->Dinv, TREE_MAXK * TREE_MAXK * nc, double);
  ALLOC(w->u, TREE_MAXK * nc, double); ALLOC(w->acc, 6 * nc, double); ALLOC(w->wr, 6 * nc, double);
  ALLOC(w->pport, m->nport, double);
  ALLOC(w->y, w->N, double); ALLOC(w->y1, w->N, double); ALLOC(w->yt, w->N, double);
  ALLOC(w->err, w->N, double); ALLOC(w->ydae, d->n, double);
  for (int i = 0; i < 7; i++) ALLOC(w->ks[i], w->N, double);
  for (int i = 0; i < 5; i++) ALLOC(w->rc[i], w->N, double);
#undef ALLOC
  for (int c = 0; c < nc; c++) w->pair[c] = -1;
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    const phm_pair_type_info *ti = phm_pair_type(pr->type);
    double psi[6 * TREE_MAXK], ds;
    int tj, dj;
    int k = ti ? type_psi(ti->name, pr->pitch, psi, &tj, &dj, &ds) : -1;
    if (pr->driven || pr->xdriven) {
      tree_free(w);
      return PHM_FAIL(err, PHM_EINVAL, "%s: pair %d prescribes a motion (%s)", why, ip,
                      pr->driven ? "driven" : "joint coordinates following laws");
    }
    if (k < 0) {
      tree_free(w);
      return PHM_FAIL(err, PHM_EINVAL, "%s: pair %d is %s, whose motion subspace is not constant "
                      "(supported: fixed, revolute, prismatic, helical, cylindrical)", why, ip,
                      ti ? ti->name : "of an unknown type");
    }
    if (pr->b < 0 || pr->a == pr->b) {
      tree_free(w);
      return PHM_FAIL(err, PHM_EINVAL, "%s: pair %d has %s as its side b (the child body must be "
                      "side b, its parent or the ground side a)", why, ip, pr->b < 0 ? "the ground" : "its side a");
    }
    if (w->pair[pr->b] >= 0) {
      tree_free(w);
      return PHM_FAIL(err, PHM_EINVAL, "%s: carrier %d is side b of pairs %d and %d (a closed "
                      "loop, or a body held twice)", why, pr->b, w->pair[pr->b], ip);
    }
    int c = pr->b;
    w->pair[c] = ip;
    w->par[c] = pr->a;
    w->k[c] = k;
    w->j0[c] = m->pair_j[ip];
    double A[36];
    phm_se3_Ad(pr->Tb, A);
    for (int s = 0; s < k; s++) phm_mv6(A, psi + 6 * s, w->S + 6 * TREE_MAXK * c + 6 * s);
    w->ti[c] = tj;
    w->di[c] = dj;
    w->ds[c] = ds;
    /* h = P0 + cos P1 + sin P2 + d P3: P0 = diag(0, 0, 1, 1), P1 = diag(1, 1, 0, 0), P2 the
     * rotation's sine part (-1 at (0, 1), 1 at (1, 0)), P3 the translation along z (1 at (2, 3)) */
    double P[4][16] = {{0}}, Tbi[16];
    P[0][10] = P[0][15] = 1;
    P[1][0] = P[1][5] = 1;
    P[2][1] = -1;
    P[2][4] = 1;
    P[3][11] = 1;
    phm_se3_inverse(pr->Tb, Tbi);
    for (int e = 0; e < 4; e++) {
      double TP[16];
      mul4(pr->Ta, P[e], TP);
      mul4(TP, Tbi, w->K + 64 * c + 16 * e);
    }
  }
  for (int c = 0; c < nc; c++)
    if (w->pair[c] < 0) {
      tree_free(w);
      return PHM_FAIL(err, PHM_EINVAL, "%s: carrier %d is side b of no pair (a free body, or "
                      "one held only as side a)", why, c);
    }
  /* order: parents first (each carrier's depth below the ground; a cycle never reaches it) */
  int no = 0;
  for (int c = 0; c < nc; c++) w->isrt[c] = 0; /* 0 unplaced, 1 placed */
  while (no < nc) {
    int placed = 0;
    for (int c = 0; c < nc; c++)
      if (!w->isrt[c] && (w->par[c] < 0 || w->isrt[w->par[c]])) {
        w->isrt[c] = 1;
        w->order[no++] = c;
        placed = 1;
      }
    if (!placed) {
      int c = 0;
      while (w->isrt[c]) c++;
      tree_free(w);
      return PHM_FAIL(err, PHM_EINVAL, "%s: carrier %d is on a closed loop of pairs not attached "
                      "to the ground", why, c);
    }
  }
  return PHM_OK;
nomem:
  tree_free(w);
  return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
}

/* The transforms of g = (R, p) = H_c^-1 H_p (4x4, first three rows read) without forming Ad_g:
 * Ad_g x = (R w, p x R w + R v) on a twist x = (w, v); Ad_g^T f = (R^T (tau - p x f), R^T f) on a
 * wrench f = (tau, f). */
static inline void cross3(const double a[3], const double b[3], double c[3]) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}
static inline void Ad_apply(const double g[16], const double x[6], double y[6]) {
  double pc[3];
  for (int i = 0; i < 3; i++) {
    y[i] = g[4 * i] * x[0] + g[4 * i + 1] * x[1] + g[4 * i + 2] * x[2];
    y[3 + i] = g[4 * i] * x[3] + g[4 * i + 1] * x[4] + g[4 * i + 2] * x[5];
  }
  const double p[3] = {g[3], g[7], g[11]};
  cross3(p, y, pc);
  for (int i = 0; i < 3; i++) y[3 + i] += pc[i];
}
static inline void AdT_apply(const double g[16], const double f[6], double y[6]) {
  const double p[3] = {g[3], g[7], g[11]};
  double pc[3], t[3];
  cross3(p, f + 3, pc);
  for (int i = 0; i < 3; i++) t[i] = f[i] - pc[i];
  for (int i = 0; i < 3; i++) {
    y[i] = g[i] * t[0] + g[4 + i] * t[1] + g[8 + i] * t[2];
    y[3 + i] = g[i] * f[3] + g[4 + i] * f[4] + g[8 + i] * f[5];
  }
}

/* B += X^T A X for X = Ad_g = [[I, 0], [P, I]] diag(R, R) (P = hat(p)), A symmetric 6x6
 * (row-major), in 3x3 blocks: the shift S^T A S = [[A11 + Y P - P A12^T, Y], [Y^T, A22]] with
 * Y = A12 - P A22, then R^T (each block) R. */
static void congruence_add(const double g[16], const double A[36], double B[36]) {
  double A11[9], A12[9], A22[9], P[9], Y[9], S11[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      A11[3 * i + j] = A[6 * i + j];
      A12[3 * i + j] = A[6 * i + 3 + j];
      A22[3 * i + j] = A[6 * (3 + i) + 3 + j];
    }
  const double px = g[3], py = g[7], pz = g[11];
  P[0] = 0; P[1] = -pz; P[2] = py;
  P[3] = pz; P[4] = 0; P[5] = -px;
  P[6] = -py; P[7] = px; P[8] = 0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double s = 0;
      for (int l = 0; l < 3; l++) s += P[3 * i + l] * A22[3 * l + j];
      Y[3 * i + j] = A12[3 * i + j] - s;
    }
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double s = A11[3 * i + j];
      for (int l = 0; l < 3; l++) s += Y[3 * i + l] * P[3 * l + j] - P[3 * i + l] * A12[3 * j + l];
      S11[3 * i + j] = s;
    }
  const double *blk[3] = {S11, Y, A22};
  const int off[3][2] = {{0, 0}, {0, 3}, {3, 3}};
  for (int b = 0; b < 3; b++) {
    const double *M = blk[b];
    double MR[9];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++)
        MR[3 * i + j] = M[3 * i] * g[j] + M[3 * i + 1] * g[4 + j] + M[3 * i + 2] * g[8 + j];
    const int r0 = off[b][0], c0 = off[b][1];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        double s = g[i] * MR[j] + g[4 + i] * MR[3 + j] + g[8 + i] * MR[6 + j];
        B[6 * (r0 + i) + c0 + j] += s;
        if (b == 1) B[6 * (c0 + j) + r0 + i] += s;
      }
  }
}

int tree_eval(tree_work *w, double t, double tref, const double *Y, double *dY) {
  const phm_model *m = w->m;
  const int nb = w->nb, nj = w->nj;
  const double *q = Y, *qd = Y + nj;
  /* pass 1, parents first: poses, twists, velocity-product accelerations */
  for (int o = 0; o < nb; o++) {
    const int c = w->order[o], p = w->par[c], k = w->k[c];
    const double *S = w->S + 6 * TREE_MAXK * c;
    double *Hc = w->H + 16 * c, *vc = w->v + 6 * c, *X = w->X + 36 * c;
    /* L = Ta h Tb^-1, H_c = H_p L, and g = H_c^-1 H_p = L^-1 (into X) */
    const double *K = w->K + 64 * c, *qc = q + w->j0[c];
    const double th = w->ti[c] >= 0 ? qc[w->ti[c]] : 0.0, d = w->di[c] >= 0 ? w->ds[c] * qc[w->di[c]] : 0.0;
    const double cs = w->ti[c] >= 0 ? cos(th) : 1.0, sn = w->ti[c] >= 0 ? sin(th) : 0.0;
    double L[12];
    for (int i = 0; i < 12; i++) L[i] = K[i] + cs * K[16 + i] + sn * K[32 + i] + d * K[48 + i];
    if (p >= 0) {
      const double *Hp = w->H + 16 * p;
      for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 4; j++)
          Hc[4 * i + j] = Hp[4 * i] * L[j] + Hp[4 * i + 1] * L[4 + j] + Hp[4 * i + 2] * L[8 + j];
        Hc[4 * i + 3] += Hp[4 * i + 3];
      }
    } else
      memcpy(Hc, L, sizeof(double) * 12);
    Hc[12] = Hc[13] = Hc[14] = 0.0;
    Hc[15] = 1.0;
    for (int i = 0; i < 3; i++) { /* X = (R^T, -R^T p) of L */
      for (int j = 0; j < 3; j++) X[4 * i + j] = L[4 * j + i];
      X[4 * i + 3] = -(L[i] * L[3] + L[4 + i] * L[7] + L[8 + i] * L[11]);
    }
    double Sq[6] = {0};
    for (int s = 0; s < k; s++)
      for (int i = 0; i < 6; i++) Sq[i] += S[6 * s + i] * qd[w->j0[c] + s];
    if (p >= 0) Ad_apply(X, w->v + 6 * p, vc); /* X = Ad_g */
    else memset(vc, 0, sizeof(double) * 6);
    for (int i = 0; i < 6; i++) vc[i] += Sq[i];
    phm_ad_apply(vc, Sq, w->cb + 6 * c);
  }
  /* the applied wrenches at these poses and twists, and the ledger's power rates */
  double Pd = 0, Ps = 0;
  phm_applied(m, w->H, w->v, q, t, tref, 1.0, w->wr, NULL, &Pd, &Ps, w->pport, NULL);
  if (m->ncomp)
    phm_components_apply(m, NULL, w->H, w->v, q, NULL, NULL, t, tref, w->wr, NULL, NULL, NULL, &Pd, &Ps);
  /* articulated inertias and biases: own part, parents first */
  for (int c = 0; c < nb; c++) {
    double Mv[6], adm[6];
    const double *M = m->car[c].M;
    memcpy(w->IA + 36 * c, M, sizeof(double) * 36);
    phm_mv6(M, w->v + 6 * c, Mv);
    phm_ad_dual_apply(w->v + 6 * c, Mv, adm);
    for (int i = 0; i < 6; i++) w->pA[6 * c + i] = -adm[i] - w->wr[6 * c + i];
  }
  /* pass 2, children first */
  for (int o = nb - 1; o >= 0; o--) {
    const int c = w->order[o], p = w->par[c], k = w->k[c];
    const double *S = w->S + 6 * TREE_MAXK * c, *IA = w->IA + 36 * c, *pA = w->pA + 6 * c;
    double *U = w->U + 6 * TREE_MAXK * c, *Di = w->Dinv + TREE_MAXK * TREE_MAXK * c, *u = w->u + TREE_MAXK * c;
    double D[TREE_MAXK * TREE_MAXK];
    for (int s = 0; s < k; s++) {
      phm_mv6(IA, S + 6 * s, U + 6 * s);
      u[s] = -phm_dot(S + 6 * s, pA, 6);
    }
    for (int s = 0; s < k; s++)
      for (int r = 0; r < k; r++) D[k * s + r] = phm_dot(S + 6 * s, U + 6 * r, 6);
    if (k == 1) {
      if (!(D[0] > 0)) return 1;
      Di[0] = 1.0 / D[0];
    } else if (k == 2) {
      double det = D[0] * D[3] - D[1] * D[2];
      if (!(D[0] > 0) || !(det > 0)) return 1;
      Di[0] = D[3] / det; Di[1] = -D[1] / det; Di[2] = -D[2] / det; Di[3] = D[0] / det;
    }
    if (p < 0) continue;
    double Ia[36], pa[6], Du[TREE_MAXK] = {0}, Ic[6];
    if (k == 1) { /* the common case: a rank-one update, unrolled */
      const double f = Di[0];
      Du[0] = f * u[0];
      for (int i = 0; i < 6; i++) {
        const double fu = f * U[i];
        for (int j = 0; j < 6; j++) Ia[6 * i + j] = IA[6 * i + j] - fu * U[j];
      }
    } else {
      memcpy(Ia, IA, sizeof Ia);
      for (int s = 0; s < k; s++)
        for (int r = 0; r < k; r++) Du[s] += Di[k * s + r] * u[r];
      for (int s = 0; s < k; s++)
        for (int r = 0; r < k; r++) {
          double f = Di[k * s + r];
          for (int i = 0; i < 6; i++)
            for (int j = 0; j < 6; j++) Ia[6 * i + j] -= U[6 * s + i] * f * U[6 * r + j];
        }
    }
    phm_mv6(Ia, w->cb + 6 * c, Ic);
    for (int i = 0; i < 6; i++) {
      pa[i] = pA[i] + Ic[i];
      for (int s = 0; s < k; s++) pa[i] += U[6 * s + i] * Du[s];
    }
    const double *X = w->X + 36 * c;
    congruence_add(X, Ia, w->IA + 36 * p);
    double Xp[6];
    AdT_apply(X, pa, Xp);
    for (int i = 0; i < 6; i++) w->pA[6 * p + i] += Xp[i];
  }
  /* pass 3, parents first: accelerations */
  for (int o = 0; o < nb; o++) {
    const int c = w->order[o], p = w->par[c], k = w->k[c];
    const double *S = w->S + 6 * TREE_MAXK * c, *U = w->U + 6 * TREE_MAXK * c;
    const double *Di = w->Dinv + TREE_MAXK * TREE_MAXK * c, *u = w->u + TREE_MAXK * c;
    double *a = w->acc + 6 * c;
    if (p >= 0) Ad_apply(w->X + 36 * c, w->acc + 6 * p, a);
    else memset(a, 0, sizeof(double) * 6);
    for (int i = 0; i < 6; i++) a[i] += w->cb[6 * c + i];
    double r[TREE_MAXK];
    for (int s = 0; s < k; s++) r[s] = u[s] - phm_dot(U + 6 * s, a, 6);
    for (int s = 0; s < k; s++) {
      double qdd = 0;
      for (int l = 0; l < k; l++) qdd += Di[k * s + l] * r[l];
      if (dY) dY[nj + w->j0[c] + s] = qdd;
      for (int i = 0; i < 6; i++) a[i] += S[6 * s + i] * qdd;
    }
  }
  if (dY) {
    memcpy(dY, qd, sizeof(double) * (size_t)nj);
    double *L = dY + 2 * nj;
    L[0] = Pd;
    L[1] = Ps;
    for (int i = 0; i < m->nport; i++) L[2 + i] = w->pport[i];
  }
  return 0;
}

void tree_lambda(tree_work *w, double t, double tref, const double *Y, double *lam) {
  const phm_model *m = w->m;
  for (int c = 0; c < w->nb; c++) {
    const int ip = w->pair[c], p = w->par[c], mr = m->pair_m[ip];
    /* the joint's wrench on c: f = IA a + pA (its articulated balance) */
    double f[6], Ga[6];
    phm_mv6(w->IA + 36 * c, w->acc + 6 * c, f);
    for (int i = 0; i < 6; i++) f[i] += w->pA[6 * c + i];
    (void)Ga;
    phm_pair_data pd;
    phm_pair_evaluate(m, ip, p >= 0 ? w->H + 16 * p : NULL, w->H + 16 * c,
                      p >= 0 ? w->v + 6 * p : NULL, w->v + 6 * c, Y + w->j0[c], t, tref,
                      PHM_PAIR_ROWS, &pd);
    /* least squares of Gb^T lam = f: (Gb Gb^T) lam = Gb f, by Gaussian elimination with
     * partial pivoting (mr <= 6) */
    double A[PHM_MAXCON * PHM_MAXCON], b[PHM_MAXCON];
    for (int r = 0; r < mr; r++) {
      b[r] = phm_dot(pd.Gb + 6 * r, f, 6);
      for (int s = 0; s < mr; s++) A[mr * r + s] = phm_dot(pd.Gb + 6 * r, pd.Gb + 6 * s, 6);
    }
    for (int col = 0; col < mr; col++) {
      int piv = col;
      for (int r = col + 1; r < mr; r++)
        if (fabs(A[mr * r + col]) > fabs(A[mr * piv + col])) piv = r;
      if (piv != col) {
        for (int s = 0; s < mr; s++) {
          double tmp = A[mr * col + s];
          A[mr * col + s] = A[mr * piv + s];
          A[mr * piv + s] = tmp;
        }
        double tmp = b[col];
        b[col] = b[piv];
        b[piv] = tmp;
      }
      for (int r = col + 1; r < mr; r++) {
        double f2 = A[mr * r + col] / A[mr * col + col];
        for (int s = col; s < mr; s++) A[mr * r + s] -= f2 * A[mr * col + s];
        b[r] -= f2 * b[col];
      }
    }
    for (int r = mr - 1; r >= 0; r--) {
      double s = b[r];
      for (int l = r + 1; l < mr; l++) s -= A[mr * r + l] * b[l];
      b[r] = s / A[mr * r + r];
    }
    memcpy(lam + m->pair_row[ip], b, sizeof(double) * (size_t)mr);
  }
}
