/* galpha_scheme.c -- the generalized-alpha scheme's formulas (csrc/integrate/galpha_internal.h):
 * the stage state and residual, the iteration matrix, the fixed step's co-rotated matrix and the
 * configuration error estimate with its low-pass filter. */
#include "galpha_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"

/* alpha_f of this step (1 for a backward Euler step: the stage is t1) */
static double stage_af(const galpha_t *g) { return g->euler ? 1.0 : g->af; }

/* Stage values from the unknown y1 (= g->Y) for a step h; fills Yp (y1'), ya, ypa. */
void galpha_stage(const dae_t *d, galpha_t *g, double h) {
  const double *y0 = N_VGetArrayPointer(g->y0), *yp0 = N_VGetArrayPointer(g->yp0);
  const double *Y = N_VGetArrayPointer(g->Y);
  double *Yp = N_VGetArrayPointer(g->Yp), *ya = N_VGetArrayPointer(g->ya), *ypa = N_VGetArrayPointer(g->ypa);
  if (g->euler) { /* written without y0', which may be huge after a restart */
    double ih = 1.0 / h;
    for (int i = 0; i < d->il; i++) {
      Yp[i] = ypa[i] = (Y[i] - y0[i]) * ih;
      ya[i] = Y[i];
    }
  } else {
    double igh = 1.0 / (g->gam * h);
    for (int i = 0; i < d->il; i++) {
      Yp[i] = yp0[i] + (Y[i] - y0[i] - h * yp0[i]) * igh;
      ya[i] = y0[i] + g->af * (Y[i] - y0[i]);
      ypa[i] = yp0[i] + g->am * (Yp[i] - yp0[i]);
    }
  }
  for (int i = d->il; i < d->n; i++) {
    Yp[i] = ypa[i] = 0;
    ya[i] = Y[i];
  }
}

/* R = [differential rows at the stage; constraint rows at (t1, y1)]; Ra: the stage residual's
 * differential rows (its constraint rows, which nothing reads, are not evaluated: the pairs'
 * position constraints are logs of relative poses). */
void galpha_residual(dae_t *d, galpha_t *g, double t0, double h) {
  double *Ra = N_VGetArrayPointer(g->Ra), *R = N_VGetArrayPointer(g->R);
  dae_full(d)->stage_h = h;
  dae_residual_rows(d, t0 + stage_af(g) * h, N_VGetArrayPointer(g->ya), N_VGetArrayPointer(g->ypa),
                    Ra, 0);
  dae_constraint_rows(d, t0 + h, N_VGetArrayPointer(g->Y), R);
  memcpy(R, Ra, sizeof(double) * (size_t)d->il);
}

/* Factor the iteration matrix A. SUNDIALS's KLU refactors each new matrix with the pivot order
 * of its first factorization and, when that order meets a zero pivot, reports a failure without
 * looking for another order; so a failure is retried once after SUNLinSol_KLUReInit, which makes
 * the next setup analyse and factor afresh. Measured: with consistent element masses the
 * manipulator's first step (tests/test_consistent_mass.py) failed on the pivots of an earlier matrix at every
 * step size down to 1e-7 s, and a fresh factorization of the same matrix succeeds. */
int galpha_factor(SUNLinearSolver LS, SUNMatrix A, int klu, long nnz) {
  if (SUNLinSolSetup(LS, A) == PHM_SUN_SUCCESS) return 0;
  if (!klu || SUNLinSol_KLUReInit(LS, A, (sunindextype)nnz, SUNKLU_REINIT_PARTIAL) != PHM_SUN_SUCCESS)
    return 1;
  return SUNLinSolSetup(LS, A) != PHM_SUN_SUCCESS;
}

/* dR/dy1 ~ alpha_f (dF/dy + cj dF/dy') on the differential block (cj = alpha_m / (alpha_f gamma h)),
 * dF/dy on the multiplier columns and on the constraint rows; dense copy when LS is dense.
 * KLU (A == Js): the exact zeros are dropped (dae_jacobian_prune), and LS is reset for a fresh
 * analysis when the pattern left differs from the one its factors were made for (a refactor
 * assumes that pattern). */
int galpha_jacobian(dae_t *d, galpha_t *g, double t0, double h, SUNMatrix Js, SUNMatrix A,
                           SUNLinearSolver LS) {
  double cj = g->euler ? 1.0 / h : g->am / (g->af * g->gam * h);
  double af = stage_af(g);
  if (dae_jacobian(d, t0 + af * h, cj, N_VGetArrayPointer(g->ya), N_VGetArrayPointer(g->ypa),
                   N_VGetArrayPointer(g->Ra), Js))
    return 1;
  sunindextype *cp = SUNSparseMatrix_IndexPointers(Js), *ri = SUNSparseMatrix_IndexValues(Js);
  double *val = SUNSparseMatrix_Data(Js);
  for (int j = 0; j < d->il; j++)
    for (sunindextype k = cp[j]; k < cp[j + 1]; k++)
      if (ri[k] < d->il) val[k] *= af;
  if (A == Js) return phm_klu_prune(d, Js, LS);
  dae_jacobian_to_dense(Js, A);
  return 0;
}

/* Carrier c's quaternion (w, x, y, z) from state y (planar: the kept components, others 0). */
static void corot_quat(const dae_t *d, const galpha_corot *cr, const double *y, int c, double q[4]) {
  q[0] = q[1] = q[2] = q[3] = 0.0;
  for (int j = 0; j < cr->L.nq; j++) q[cr->L.qf[j]] = y[d->ns * c + j];
}

/* The buffers, in work (nc x 33 doubles: the DAE's gwork). */
void galpha_corot_init(const dae_t *d, galpha_corot *cr, double *work) {
  size_t nc = (size_t)d->m->nc;
  memset(cr, 0, sizeof *cr);
  dae_carrier_states(d, &cr->L);
  cr->qref = work;
  cr->dq = work + 4 * nc;
  cr->D = work + 8 * nc; /* at most 16 + 9 per carrier */
}

/* The carriers' quaternions at ya, the stage state a new matrix was computed at. */
void galpha_corot_reference(const dae_t *d, galpha_corot *cr, const double *ya) {
  for (int c = 0; c < d->m->nc; c++) corot_quat(d, cr, ya, c, cr->qref + 4 * c);
}

/* The angle of the rotation between carriers a and b's (-1: the ground's, none) since the
 * matrix was computed. */
static double corot_slip(const galpha_corot *cr, int a, int b) {
  static const double one[4] = {1, 0, 0, 0};
  const double *p = a >= 0 ? cr->dq + 4 * a : one, *r = b >= 0 ? cr->dq + 4 * b : one;
  double v[3] = {-p[0] * r[1] + p[1] * r[0] - p[2] * r[3] + p[3] * r[2], /* vec(p (x) conj(r)) */
                 -p[0] * r[2] + p[1] * r[3] + p[2] * r[0] - p[3] * r[1],
                 -p[0] * r[3] - p[1] * r[2] + p[2] * r[1] + p[3] * r[0]};
  return 2.0 * sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* This step's D from the stage state ya: per carrier dq = q (x) conj(q_ref), then, unless a
 * pair or spring turned across by more than GALPHA_COROT_SLIP times the largest rotation of a
 * carrier (returns 0: D not used), L(dq) (dq (x) .) on its quaternion components and
 * dR = R(dq) on its position axes (returns 1). */
int galpha_corot_set(const dae_t *d, galpha_corot *cr, const double *ya) {
  const phm_model *m = d->m;
  int nq = cr->L.nq, np = cr->L.npos, nd = nq * nq + np * np;
  double rot = 0, slip = 0;
  for (int c = 0; c < m->nc; c++) {
    double q[4], *a = cr->dq + 4 * c;
    const double *r = cr->qref + 4 * c;
    corot_quat(d, cr, ya, c, q);
    a[0] = q[0] * r[0] + q[1] * r[1] + q[2] * r[2] + q[3] * r[3];
    a[1] = -q[0] * r[1] + q[1] * r[0] - q[2] * r[3] + q[3] * r[2];
    a[2] = -q[0] * r[2] + q[1] * r[3] + q[2] * r[0] - q[3] * r[1];
    a[3] = -q[0] * r[3] - q[1] * r[2] + q[2] * r[1] + q[3] * r[0];
    rot = fmax(rot, corot_slip(cr, c, -1));
  }
  for (int k = 0; k < m->np; k++) slip = fmax(slip, corot_slip(cr, m->pair[k].a, m->pair[k].b));
  for (int k = 0; k < m->ns; k++) slip = fmax(slip, corot_slip(cr, m->spr[k].a, m->spr[k].b));
  if (!(slip <= GALPHA_COROT_SLIP * rot)) return 0;
  for (int c = 0; c < m->nc; c++) {
    const double *a = cr->dq + 4 * c;
    const double Lq[16] = {a[0], -a[1], -a[2], -a[3], a[1], a[0], -a[3], a[2],
                           a[2], a[3],  a[0],  -a[1], a[3], -a[2], a[1], a[0]};
    double R[9], *Dc = cr->D + (size_t)nd * c;
    phm_quat_to_rot(a, R);
    for (int i = 0; i < nq; i++)
      for (int j = 0; j < nq; j++) Dc[nq * i + j] = Lq[4 * cr->L.qf[i] + cr->L.qf[j]];
    for (int i = 0; i < np; i++)
      for (int j = 0; j < np; j++) Dc[nq * nq + np * i + j] = R[3 * cr->L.pf[i] + cr->L.pf[j]];
  }
  return 1;
}

/* x <- B x (tr = 0) or B^T x (tr = 1) for the nb x nb matrix B; inlined with constant nb by
 * galpha_corot_apply (a loop of variable length, and a memcpy of the result, per carrier made the
 * N = 30 cantilever's run 5 % slower) */
static inline void corot_block(const double *B, int nb, int tr, double *x) {
  double t[4];
  for (int i = 0; i < nb; i++) {
    t[i] = 0.0;
    for (int j = 0; j < nb; j++) t[i] += (tr ? B[nb * j + i] : B[nb * i + j]) * x[j];
  }
  for (int i = 0; i < nb; i++) x[i] = t[i];
}

/* v <- D v (tr = 0) or D^T v (tr = 1) */
void galpha_corot_apply(const dae_t *d, const galpha_corot *cr, int tr, double *v) {
  int nc = d->m->nc, ns = d->ns;
  if (cr->L.nq == 2) /* planar: two 2 x 2 blocks */
    for (int c = 0; c < nc; c++) {
      corot_block(cr->D + 8 * (size_t)c, 2, tr, v + ns * c);
      corot_block(cr->D + 8 * (size_t)c + 4, 2, tr, v + ns * c + 2);
    }
  else
    for (int c = 0; c < nc; c++) {
      corot_block(cr->D + 25 * (size_t)c, 4, tr, v + ns * c);
      corot_block(cr->D + 25 * (size_t)c + 16, 3, tr, v + ns * c + 4);
    }
}

/* Local error estimate of a converged step h (previous steps hq, hqq; 0: not there), WRMS-normed
 * with the error weights of the configuration states (poses, joint coordinates; twists, ledger
 * integrals and multipliers are left out): the trapezoidal local error h^3 y'''/12, with y''' = 6
 * times the third divided difference over the last four points -- of the configuration seen
 * through a low-pass filter at the band: two first-order stages with corner wc = 2 pi
 * PHM_FILTER_BAND band, each exact for an input linear over the step. A motion slow against wc
 * passes delayed by 2/wc with its y''' kept to (w/wc)^2; a vibration at w >> wc is divided by
 * (w/wc)^2. What the filter removes is the content above the band, which the method damps
 * (rho_inf) instead of resolving. Measured on the README's arm + strip (band 500 Hz): the raw
 * estimate stayed above rtol 1e-4 with the steps refined 64x below the band's floor, while the
 * default run was within 4e-6 of 0.6 m of a tight reference (docs/integrators.md, "The error
 * estimate"). Positions, not rates: a fast vibration the step does not resolve has a tiny
 * amplitude in the poses and a large one in the rates (by omega).
 * Fills g->z1n, g->z2n (the filter at t1, kept by the caller when the step is accepted).
 * Returns -1 without enough history (the first two steps after a start or a breakpoint).
 * *emax: the max-norm estimate; *ewmax: the largest state's estimate in its own tolerance (the
 * WRMS norm averages it with every other state's, idle ones included). */
double galpha_error(const dae_t *d, galpha_t *g, double h, double hq, double hqq,
                           double rtol, double atol, double *emax, double *ewmax) {
  *emax = *ewmax = 0;
  const double *Y = N_VGetArrayPointer(g->Y), *y0 = N_VGetArrayPointer(g->y0);
  const double *z1 = N_VGetArrayPointer(g->z1), *z2 = N_VGetArrayPointer(g->z2);
  const double *zq = N_VGetArrayPointer(g->z2q), *zqq = N_VGetArrayPointer(g->z2qq);
  double *z1n = N_VGetArrayPointer(g->z1n), *z2n = N_VGetArrayPointer(g->z2n);
  const double *wa = N_VGetArrayPointer(g->wa), *fm = N_VGetArrayPointer(g->fm);
  double *le = N_VGetArrayPointer(g->le); /* each state's estimate, for galpha_global.c */
  /* no band (wc = 0): no filter, z = y */
  double x = g->wc * h, ex = x > 0 ? exp(-x) : 0.0, ix = x > 0 ? 1.0 / x : 0.0;
  int est = hq > 0 && hqq > 0;
  double sum = 0, mx = 0, mxw = 0;
  int cnt = 0;
  /* reciprocals once: six divisions per state per step were ~5 % of a flexible scene's CPU */
  double ih = 1.0 / h, ihq = est ? 1.0 / hq : 0, ihqq = est ? 1.0 / hqq : 0;
  double ia = 1.0 / (h + hq), ib = est ? 1.0 / (hq + hqq) : 0;
  double c3 = 0.5 * h * h * h / (h + hq + hqq);
  /* The twists count where the estimate is not filtered (a rigid mechanism): an oscillation's
   * phase error accrues in the twists near its turning points, where the positions' third
   * difference vanishes; without them a compound pendulum (30 deg, 5 s, rtol 1e-4) ended 2.8x
   * rtol off with its estimates summed to 0.64 (now 0.65x rtol, 1.36x the steps; 2 deg: 3.7x
   * -> 0.94x). Filtered (flexible links): not, the twists of the mesh's vibrations above the
   * band pass the filter's two stages enough to take 20-200x the steps (benchmarks/scenes.py).
   * Their absolute tolerance is atol times GALPHA_TWIST_ATOL wc: the twist error that moves the
   * positions by atol over 1/(0.1 wc), 1.6 periods of the band's highest frequency. With atol
   * itself (1/s) the chain of 100 links of tests/accuracy/ (rtol 1e-4, 0.5 s) took 2.5x the
   * steps to end 9e-8 m off instead of 4e-7 (its tolerance is 1e-3 m); with 1 wc the pendulum
   * at 2 deg ended 2.6x rtol off (0.1 wc: 1.2x, 0.93x of rtol amp + atol). */
  double atol_twist = galpha_twist_atol(g, atol);
  for (int i = 0; i < d->ie; i++) {
    if (wa[i] < 0 && fm[i] != 0.0) continue; /* a twist, filtered */
    double a = Y[i], b = Y[i];
    if (fm[i] != 0.0) {
      double s1 = (Y[i] - y0[i]) * ix, s2;
      a = Y[i] - s1 + ex * (z1[i] - y0[i] + s1);
      s2 = (a - z1[i]) * ix;
      b = a - s2 + ex * (z2[i] - z1[i] + s2);
    }
    z1n[i] = a;
    z2n[i] = b;
    if (!est) {
      le[i] = 0.0;
      continue;
    }
    double d10 = (b - z2[i]) * ih, d0q = (z2[i] - zq[i]) * ihq, dqq = (zq[i] - zqq[i]) * ihqq;
    double dd2a = (d10 - d0q) * ia, dd2b = (d0q - dqq) * ib;
    double e = c3 * (dd2a - dd2b);
    le[i] = e;
    double wgt = rtol * fabs(Y[i]) + (wa[i] < 0 ? atol_twist : atol);
    double r = e / wgt;
    sum += r * r;
    mx = fmax(mx, fabs(e));
    mxw = fmax(mxw, fabs(r));
    cnt++;
  }
  *emax = mx;
  *ewmax = mxw;
  if (!est) return -1.0;
  return cnt ? sqrt(sum / (cnt + d->ncfg_drop)) : 0.0;
}
