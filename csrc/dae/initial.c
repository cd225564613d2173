/* initial.c -- consistent initial values of the DAE (at the start and at every breakpoint of the
 * laws): positions projected onto g = 0, twists onto G t = vt (minimum-norm corrections), then
 * the acceleration level solved for t' and lambda. */
#include "dae.h"

#include <math.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"
#include "pose.h"

/* ---------------------------------------------------------------- the sparse path (O(N)) */
/* Positions onto g = 0 (Newton on the minimum-norm correction, at most 50 steps), then twists
 * onto G t = vt: each a solve with S = G G^T (csrc/dae/ic_schur.c). PHM_ESINGULAR when S is
 * singular (dependent rows at this configuration): the caller takes the dense path. */
static phm_status sparse_positions_velocities(dae_t *d, double time, double *H, double *tw,
                                              const double *xs, phm_error *err) {
  const phm_model *m = d->m;
  dae_ic_work *w = &d->data.ic;
  int nk = m->ncons, nc = m->nc;
  double *rhs = w->b, *dl = w->b + nk, *g = w->g, *vt = w->vt, gn = 0, gprev = INFINITY;
  for (int it = 0; it < 50; it++) {
    ic_schur_rows(d, H, xs, time, g, NULL);
    gn = 0;
    for (int i = 0; i < nk; i++) gn = fmax(gn, fabs(g[i]));
    /* converged; below 1e-13, steps continue while they still gain a digit: S = G G^T squares
     * G's condition, and a closed loop's last step left |g| ~ 6e-15 where the dense
     * least-squares step reached 4e-16 (its energy ledger noticed) */
    if (gn < 1e-13 && (gn < 1e-15 || gn > 0.1 * gprev)) break;
    gprev = gn;
    if (ic_schur_factor(d, 0)) return PHM_ESINGULAR;
    for (int i = 0; i < nk; i++) rhs[i] = -g[i];
    memset(dl, 0, sizeof(double) * 6 * (size_t)nc);
    if (ic_schur_solve(d, 0, rhs, dl)) return PHM_ESINGULAR;
    for (int k = 0; k < w->ncc; k++) phm_retract(H + 16 * w->clist[k], dl + 6 * w->clist[k]);
  }
  if (gn > 1e-9)
    return PHM_FAIL(err, PHM_EINVAL, "initial configuration: position constraints cannot be met (|g| = %.3e after projection); check the pairs' frames", gn);
  ic_schur_rows(d, H, xs, time, NULL, vt);
  if (ic_schur_factor(d, 0)) return PHM_ESINGULAR;
  for (int pass = 0; pass < 2; pass++) { /* the second pass refines the first's round-off */
    ic_schur_apply(d, tw, rhs);
    for (int r = 0; r < nk; r++) rhs[r] = vt[r] - rhs[r];
    if (ic_schur_solve(d, 0, rhs, tw)) return PHM_ESINGULAR;
  }
  return PHM_OK;
}

/* b2 = -dc/dt at fixed t': the constraint rates G t - vt differentiated along the motion by
 * central differences (poses moved by +-tau t). Into w->c1 + nk. Uses ic_schur_rows's blocks. */
static void sparse_rate_of_constraint_rates(dae_t *d, double time, const double *H,
                                            const double *tw, const double *xs) {
  const phm_model *m = d->m;
  dae_ic_work *w = &d->data.ic;
  int nk = m->ncons, nc = m->nc;
  double tau = 1e-6, *c1 = w->c1;
  for (int side = 0; side < 2; side++) {
    double s = side ? -tau : tau;
    memcpy(w->Hp, H, sizeof(double) * 16 * (size_t)nc);
    for (int k = 0; k < w->ncc; k++) {
      int c = w->clist[k];
      double dl[6];
      for (int i = 0; i < 6; i++) dl[i] = s * tw[6 * c + i];
      phm_retract(w->Hp + 16 * c, dl);
    }
    ic_schur_rows(d, w->Hp, xs, time + s, NULL, w->vt);
    ic_schur_apply(d, tw, c1 + side * nk);
    for (int r = 0; r < nk; r++) c1[side * nk + r] -= w->vt[r];
  }
  for (int r = 0; r < nk; r++) c1[nk + r] = -(c1[r] - c1[nk + r]) / (2 * tau);
}

/* The acceleration level with S = G M^-1 G^T: lambda = S^-1 (b2 - G M^-1 b1), t' = M^-1 (b1 +
 * G^T lambda). acc holds b1 on entry (the constrained carriers' still unsolved); homog: b2 = 0. */
static phm_status sparse_acceleration(dae_t *d, double time, const double *H, const double *tw,
                                      const double *xs, int homog) {
  const phm_model *m = d->m;
  dae_ic_work *w = &d->data.ic;
  int nk = m->ncons;
  double *acc = w->acc, *rhs = w->b;
  if (homog) memset(w->c1 + nk, 0, sizeof(double) * (size_t)nk);
  else sparse_rate_of_constraint_rates(d, time, H, tw, xs);
  ic_schur_rows(d, H, xs, time, NULL, NULL);
  if (ic_schur_factor(d, 1)) return PHM_ESINGULAR;
  for (int k = 0; k < w->ncc; k++) phm_chol6_solve(w->Lc + 36 * w->clist[k], acc + 6 * w->clist[k]);
  ic_schur_apply(d, acc, rhs);
  for (int r = 0; r < nk; r++) rhs[r] = w->c1[nk + r] - rhs[r];
  if (ic_schur_solve(d, 1, rhs, acc)) return PHM_ESINGULAR;
  memcpy(w->lam, rhs, sizeof(double) * (size_t)nk);
  return PHM_OK;
}

/* ---------------------------------------------------------------- the dense path (fallback) */
/* The same levels as dense least-squares problems in the constrained carriers' columns:
 * minimum-norm corrections even where rows are dependent (a singular configuration). Only small
 * models have the memory for them (w->dense; csrc/dae/residual.c). */
static phm_status dense_positions_velocities(dae_t *d, double time, double *H, double *tw,
                                             const double *xs, phm_error *err) {
  const phm_model *m = d->m;
  dae_ic_work *w = &d->data.ic;
  int nk = m->ncons, ncc = w->ncc, n6c = 6 * ncc;
  const int *cmap = w->cmap, *clist = w->clist;
  double *G = w->G, *A = w->A, *b = w->b, *g = w->g, *vt = w->vt, gn = 0;
  phm_status st;
  for (int it = 0; it < 50; it++) {
    phm_constraints_columns(m, H, xs, time, d->tref, cmap, n6c, g, G, NULL);
    gn = 0;
    for (int i = 0; i < nk; i++) gn = fmax(gn, fabs(g[i]));
    if (gn < 1e-13) break;
    memcpy(A, G, sizeof(double) * (size_t)nk * n6c);
    for (int i = 0; i < nk; i++) b[i] = -g[i];
    if ((st = phm_lstsq_in(nk, n6c, A, b, NULL, &w->ls, err))) return st;
    for (int k = 0; k < ncc; k++) phm_retract(H + 16 * clist[k], b + 6 * k);
  }
  if (gn > 1e-9)
    return PHM_FAIL(err, PHM_EINVAL, "initial configuration: position constraints cannot be met (|g| = %.3e after projection); check the pairs' frames", gn);
  phm_constraints_columns(m, H, xs, time, d->tref, cmap, n6c, NULL, G, vt);
  for (int r = 0; r < nk; r++) {
    double s = -vt[r];
    for (int k = 0; k < ncc; k++)
      for (int j = 0; j < 6; j++) s += G[(size_t)r * n6c + 6 * k + j] * tw[6 * clist[k] + j];
    b[r] = -s;
  }
  memcpy(A, G, sizeof(double) * (size_t)nk * n6c);
  if ((st = phm_lstsq_in(nk, n6c, A, b, NULL, &w->ls, err))) return st;
  for (int k = 0; k < ncc; k++)
    for (int j = 0; j < 6; j++) tw[6 * clist[k] + j] += b[6 * k + j];
  return PHM_OK;
}

/* spd: the Schur complement densely (minimum-norm lambda for redundant rows); otherwise (a
 * constrained carrier's inertia is singular) the KKT system of the constrained carriers.
 * homog: b2 = 0. */
static phm_status dense_acceleration(dae_t *d, double time, const double *H, const double *tw,
                                     const double *xs, int spd, int homog, phm_error *err) {
  const phm_model *m = d->m;
  dae_ic_work *w = &d->data.ic;
  int nk = m->ncons, ncc = w->ncc, n6c = 6 * ncc, Nk = n6c + nk, nc = m->nc;
  const int *cmap = w->cmap, *clist = w->clist;
  double *Lc = w->Lc, *acc = w->acc, *lam = w->lam, *G = w->G, *A = w->A, *b = w->b;
  double *vt = w->vt, *Hp = w->Hp, *c1 = w->c1, *X = w->X;
  phm_status st;
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
  for (int r = 0; r < nk; r++) b2[r] = homog ? 0.0 : -(c1[r] - c1[nk + r]) / (2 * tau);
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
    if ((st = phm_lstsq_in(nk, nk, A, b, NULL, &w->ls, err))) return st;
    memcpy(lam, b, sizeof(double) * (size_t)nk);
    for (int k = 0; k < ncc; k++)
      for (int j = 0; j < 6; j++) {
        double v = 0;
        for (int r = 0; r < nk; r++) v += X[(size_t)(6 * k + j) * nk + r] * lam[r];
        acc[6 * clist[k] + j] += v;
      }
    return PHM_OK;
  }
  /* KKT system of the constrained carriers, minimum-norm least squares (ic_alloc in
   * csrc/dae/residual.c sized A for it: w->kkt) */
  if (!w->kkt)
    return PHM_FAIL(err, PHM_ESINGULAR, "consistent initial values: a constrained carrier's inertia failed the Cholesky test that set-up passed");
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
  if ((st = phm_lstsq_in(Nk, Nk, A, b, NULL, &w->ls, err))) return st;
  for (int k = 0; k < ncc; k++) memcpy(acc + 6 * clist[k], b + 6 * k, 6 * sizeof(double));
  memcpy(lam, b + n6c, sizeof(double) * (size_t)nk);
  return PHM_OK;
}

/* No dense fallback for a large model whose constraint rows are dependent here. */
static phm_status singular_here(double time, phm_error *err) {
  return PHM_FAIL(err, PHM_ESINGULAR, "consistent initial values at t = %.6g s: the constraint rows are dependent at this configuration (a singular position of the mechanism: a dead point, aligned axes)", time);
}

/* The acceleration level with the carriers' own inertias (w->Lc, their Cholesky factors;
 * w->lcfail: those that failed it): acc holds b1 on entry, t' on exit, with lambda in w->lam,
 * G t' = b2 (homog: 0). A free carrier solves its own 6x6 block (minimum-norm if its inertia is
 * singular); the constrained ones the Schur complement sparsely, or densely where it is singular
 * (or spd = 0: a constrained carrier's inertia is singular, the KKT system). */
static phm_status accel_carriers(dae_t *d, double time, const double *H, const double *tw,
                                 const double *xs, int spd, int homog, phm_error *err) {
  const phm_model *m = d->m;
  dae_ic_work *w = &d->data.ic;
  int nc = m->nc, nk = m->ncons;
  double *acc = w->acc;
  phm_status st;
  for (int c = 0; c < nc; c++) {
    if (w->cmap[c] >= 0 && nk > 0) continue;
    if (!w->lcfail[c]) phm_chol6_solve(w->Lc + 36 * c, acc + 6 * c);
    else { /* free carrier with singular inertia: minimum-norm solution of its own block */
      double Mc[36], bc[6];
      memcpy(Mc, m->car[c].M, sizeof Mc);
      memcpy(bc, acc + 6 * c, sizeof bc);
      if ((st = phm_lstsq_in(6, 6, Mc, bc, NULL, &w->ls, err))) return st;
      memcpy(acc + 6 * c, bc, sizeof bc);
    }
  }
  if (nk == 0) return PHM_OK;
  /* a failed sparse solve may leave M^-1 b1 in acc: b1 is kept for the dense path */
  for (int k = 0; k < w->ncc; k++) memcpy(w->b1c + 6 * k, acc + 6 * w->clist[k], 6 * sizeof(double));
  st = spd ? sparse_acceleration(d, time, H, tw, xs, homog) : PHM_ESINGULAR;
  if (st == PHM_ESINGULAR) {
    for (int k = 0; k < w->ncc; k++) memcpy(acc + 6 * w->clist[k], w->b1c + 6 * k, 6 * sizeof(double));
    st = w->dense ? dense_acceleration(d, time, H, tw, xs, spd, homog, err) : singular_here(time, err);
  }
  return st;
}

/* y = M_l x: the carriers' own inertias (the lumped mass). */
static void carrier_mass_mv(const phm_model *m, const double *x, double *y) {
  for (int c = 0; c < m->nc; c++) phm_mv6(m->car[c].M, x + 6 * c, y + 6 * c);
}

/* y = M x with the consistent and given elements' couplings: each adds Mc [x_a; x_b], its
 * inertial terms at rest (phm_element_inertia with zero twists). */
static void coupled_mass_mv(const phm_model *m, const double *x, double *y) {
  static const double zero[6];
  carrier_mass_mv(m, x, y);
  for (int k = 0; k < m->nmc; k++) {
    const int ca = m->mc_a[k], cb = m->mc_b[k];
    double f[12];
    phm_element_inertia(m->mc + 144 * (size_t)k, m->mc_rows + 12 * (size_t)k, zero, zero, x + 6 * ca,
                        x + 6 * cb, 0.0, f, NULL);
    for (int i = 0; i < 6; i++) y[6 * ca + i] += f[i], y[6 * cb + i] += f[6 + i];
  }
}

/* In the conjugate gradients below, the residual r is replaced by M_l z after each lumped
 * solve z = P r: that drops r's component G^T mu in the constraints' range, which the solve left
 * out (M_l z = r + G^T mu), and keeps r^T z = z^T M_l z non-negative; without it the range
 * component grows with the iterations and r^T z, swamped by mu^T G z at round-off, went negative
 * before convergence (Gould, Hribar & Nocedal's residual update). */

/* The acceleration level with the consistent elements' mass couplings: the mass M = M_l + the
 * couplings is no longer block-diagonal, and M^-1 is dense, so the Schur complement is not
 * sparse. Projected preconditioned conjugate gradients (Gould, Hribar & Nocedal 2001): from the
 * lumped solution (accel_carriers, which meets G t' = b2), CG on the constraint manifold with the
 * lumped solve (b2 = 0) as preconditioner and projector; M is symmetric positive definite, so it
 * converges, in few iterations where M_l^-1 M is well clustered. lambda from the last residual:
 * M t' - b1 = G^T lambda. acc holds b1 on entry (the carriers' parts; the couplings' gyroscopic
 * terms are added here). */
static phm_status accel_coupled(dae_t *d, double time, const double *H, const double *tw,
                                const double *xs, int spd, phm_error *err) {
  const phm_model *m = d->m;
  dae_ic_work *w = &d->data.ic;
  size_t n6 = 6 * (size_t)m->nc;
  double *acc = w->acc, *b1 = w->cg, *x = b1 + n6, *r = x + n6, *p = r + n6, *q = p + n6;
  phm_status st;
  static const double zero[6];
  for (int k = 0; k < m->nmc; k++) { /* b1 -= the couplings' terms at t' = 0: -ad*_t (Mc t) */
    const int ca = m->mc_a[k], cb = m->mc_b[k];
    double f[12];
    phm_element_inertia(m->mc + 144 * (size_t)k, m->mc_rows + 12 * (size_t)k, tw + 6 * ca, tw + 6 * cb,
                        zero, zero, 0.0, f, NULL);
    for (int i = 0; i < 6; i++) acc[6 * ca + i] -= f[i], acc[6 * cb + i] -= f[6 + i];
  }
  memcpy(b1, acc, sizeof(double) * n6);
  if ((st = accel_carriers(d, time, H, tw, xs, spd, 0, err))) return st;
  memcpy(x, acc, sizeof(double) * n6);
  coupled_mass_mv(m, x, q);
  for (size_t i = 0; i < n6; i++) r[i] = b1[i] - q[i];
  memcpy(acc, r, sizeof(double) * n6);
  if ((st = accel_carriers(d, time, H, tw, xs, spd, 1, err))) return st;
  carrier_mass_mv(m, acc, r);
  memcpy(p, acc, sizeof(double) * n6);
  double rz = phm_dot(r, acc, (int)n6), rz0 = rz, xmx = phm_dot(x, q, (int)n6);
  if (rz < 0)
    return PHM_FAIL(err, PHM_ESOLVER, "consistent initial values at t = %.6g s: the carriers' own inertias are not positive on the constraint manifold (conjugate gradients cannot start)", time);
  int it = 0, maxit = 10 * (int)n6 + 100;
  /* converged when the energy norm of the preconditioned residual is 1e-14 of the solution's */
  for (; rz > 1e-28 * fmax(xmx, rz0); it++) {
    if (it == maxit)
      return PHM_FAIL(err, PHM_ESOLVER, "consistent initial values at t = %.6g s: the accelerations with consistent element masses did not converge in %d conjugate-gradient iterations", time, maxit);
    coupled_mass_mv(m, p, q);
    double pq = phm_dot(p, q, (int)n6);
    if (!(pq > 0)) return PHM_FAIL(err, PHM_ESINGULAR, "consistent initial values at t = %.6g s: the mass with consistent elements is not positive definite on the constraint manifold", time);
    double alpha = rz / pq;
    for (size_t i = 0; i < n6; i++) x[i] += alpha * p[i], r[i] -= alpha * q[i];
    memcpy(acc, r, sizeof(double) * n6);
    if ((st = accel_carriers(d, time, H, tw, xs, spd, 1, err))) return st;
    carrier_mass_mv(m, acc, r);
    double rzn = phm_dot(r, acc, (int)n6), beta = rzn / rz;
    if (rzn < 0) /* the lumped solve is positive definite on the manifold: round-off beyond it */
      return PHM_FAIL(err, PHM_ESOLVER, "consistent initial values at t = %.6g s: the accelerations with consistent element masses lost positivity at %.3g of the start's residual after %d conjugate-gradient iterations", time, sqrt(-rzn / fmax(rz0, 1e-300)), it + 1);
    rz = rzn;
    for (size_t i = 0; i < n6; i++) p[i] = acc[i] + beta * p[i];
  }
  /* the final residual, exactly, and its lumped solve: t' += z (G z = 0), lambda */
  coupled_mass_mv(m, x, q);
  for (size_t i = 0; i < n6; i++) acc[i] = b1[i] - q[i];
  if ((st = accel_carriers(d, time, H, tw, xs, spd, 1, err))) return st;
  for (size_t i = 0; i < n6; i++) acc[i] += x[i];
  return PHM_OK;
}


/* Project poses H (nc x 16) onto g = 0 and twists tw onto G t = vt (minimum-norm corrections);
 * then solve the acceleration-level system for t' and lambda. Writes y (carrier blocks and lambda,
 * mu = 0) and yp (all but the ledger values in y, which the caller sets). qprev: previous
 * quaternions for sign continuity.
 * Structure: G only touches the carriers of the pairs (cmap), so the corrections vanish
 * elsewhere; the acceleration level eliminates the block-diagonal mass: S lambda = b2 - G M^-1
 * b1 with S = G M^-1 G^T, t' = M^-1 (b1 + G^T lambda). Every level is solved sparsely first
 * (ic_schur.c); where S is singular (dependent rows at this configuration), or a constrained
 * carrier's inertia is singular (the KKT system), densely. */
phm_status dae_consistent_ic(dae_t *d, double time, double *H, double *tw, const double *qprev,
                             const double *xs, int check_x0, double *y, double *yp,
                             phm_error *err) {
  if (d->pl) /* the start's (a planar restart is dae_planar_restart's) */
    return dae_planar_consistent_ic(d, time, H, tw, xs, check_x0, y, yp, err);
  const phm_model *m = d->m;
  dae_ic_work *w = &d->data.ic;
  int nc = m->nc, nk = m->ncons;
  phm_status st = PHM_OK;
  const int *cmap = w->cmap;
  double *Lc = w->Lc, *acc = w->acc, *lam = w->lam;
  if (nk > 0) {
    st = sparse_positions_velocities(d, time, H, tw, xs, err);
    if (st == PHM_ESINGULAR) st = w->dense ? dense_positions_velocities(d, time, H, tw, xs, err)
                                           : singular_here(time, err);
    if (st) goto done;
  }
  /* acceleration level: [M -G^T; G 0] [t'; lambda] = [b1; b2], b1 = ad^T M t + w, b2 = -dc/dt */
  phm_applied(m, H, tw, xs, time, d->tref, 1.0, d->data.wr, NULL, NULL, NULL, NULL, NULL);
  /* the components' internal states: the model's z0 at the start, carried over at a restart */
  const double *zs = qprev ? qprev + d->iz : NULL;
  if (m->ncomp)
    phm_components_apply(m, NULL, H, tw, xs, zs, NULL, time, d->tref, d->data.wr, NULL, NULL,
                         NULL, NULL, NULL);
  for (int ic = 0; ic < m->ncomp; ic++)
    for (int j = 0; j < phm_component_nstates(&m->comp[ic]); j++)
      y[d->iz + m->comp_z[ic] + j] = zs ? zs[m->comp_z[ic] + j] : m->comp[ic].z0[j];
  int spd = 1;
  for (int c = 0; c < nc; c++) {
    const double *M = m->car[c].M;
    double Mt[6], adm[6];
    phm_mv6(M, tw + 6 * c, Mt);
    phm_ad_dual_apply(tw + 6 * c, Mt, adm);
    for (int i = 0; i < 6; i++) acc[6 * c + i] = adm[i] + d->data.wr[6 * c + i];
    w->lcfail[c] = phm_chol6(M, 0.0, 1e-10, Lc + 36 * c) != 0;
    if (w->lcfail[c] && cmap[c] >= 0 && nk > 0) spd = 0;
  }
  if (m->nmc == 0) {
    st = accel_carriers(d, time, H, tw, xs, spd, 0, err);
    if (st) goto done;
  } else if ((st = accel_coupled(d, time, H, tw, xs, spd, err))) goto done;
  /* write y and yp */
  for (int c = 0; c < nc; c++) {
    double *yc = y + PHM_NSTATE * c, *ypc = yp + PHM_NSTATE * c;
    phm_H_to_qp_near(H + 16 * c, qprev ? qprev + PHM_NSTATE * c : NULL, yc, yc + 4);
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
    y[d->il + r] = d->data.lref[r] = lam[r];
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
  if (d->pl) return dae_planar_restart(d, t, tpiece, nbp, y, yp, err);
  double *H = d->data.ic.H, *tw = d->data.ic.tw, *qprev = d->data.ic.qprev;
  d->tref = phm_model_tref(d->m, tpiece, nbp);
  dae_unpack(d->m, y, H, tw);
  memcpy(qprev, y, sizeof(double) * (size_t)d->n);
  phm_status st = dae_consistent_ic(d, t, H, tw, qprev, qprev + d->ix, 0, y, yp, err);
  if (st) return st;
  for (int i = d->ie; i < d->il; i++) y[i] = qprev[i];
  return PHM_OK;
}
