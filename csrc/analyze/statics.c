/* statics.c -- static equilibrium: Newton on [df/ddelta G^T; G 0] with sparse LU (KLU), steps
 * retracted along the element chains, the factorization reused while it contracts, and load
 * stepping (halved on failure, grown back after fast convergence); at Newton's first failure, the
 * search for loads doing work on a motion nothing resists (static_free.c), which ends the solve. */
#include "analyze.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"
#include "pose.h"

/* The static residual at poses H and multipliers L->lam: forces f (6 nc, applied x scale +
 * G^T lambda), then the constraints g (nk). */
static void static_residual(lin_t *L, const double *H, double *R) {
  const phm_model *m = L->m;
  lin_total_force(L, H, R);
  if (m->ncons) phm_constraints_dense(m, H, NULL, L->time, L->tref, R + 6 * m->nc, NULL, NULL);
}

/* Work arrays of one Newton solve (allocated once by phm_static). */
typedef struct {
  double *R, *Gp, *Hsave, *lsave, *x, *Hold;
  double *Hptc, *lptc; /* ptc's start (newton, which ptc calls, keeps its own in Hsave, lsave) */
  int *order, *via;    /* the chain retraction's walk (chain_build) */
} static_work_t;

/* The size of a step x (6 nc carrier components, then nk multipliers): its largest rotation
 * (rad) and translation in units of the element length lref; *rot: the largest rotation. */
static double step_size(const phm_model *m, const double *x, double *rot) {
  double sn = 0, sr = 0;
  for (int c = 0; c < m->nc; c++)
    for (int j = 0; j < 6; j++) {
      double a = fabs(x[6 * c + j]);
      sn = fmax(sn, j < 3 ? a : a / m->lref);
      if (j < 3) sr = fmax(sr, a);
    }
  if (rot) *rot = sr;
  return sn;
}

/* The walk of the chain retraction (take_step): a spanning forest of the carriers linked by
 * elements, breadth first from roots taken first among the carriers paired with the ground, then
 * among those in any pair, then in index order (a root keeps its own step, and the second-order
 * part of the step collects away from it: best where the mechanism is held). order[]: the
 * carriers, each after the one it is reached from; via[c]: the element that reaches c (-1: a
 * root). adj: scratch of nc + 1 + 2 ne ints. */
static void chain_build(const phm_model *m, int *order, int *via, int *adj) {
  int nc = m->nc, *ptr = adj, *lst = adj + nc + 1, n = 0;
  for (int c = 0; c <= nc; c++) ptr[c] = 0;
  for (int e = 0; e < m->ne; e++) ptr[m->el[e].a + 1]++, ptr[m->el[e].b + 1]++;
  for (int c = 0; c < nc; c++) ptr[c + 1] += ptr[c];
  for (int e = 0; e < m->ne; e++) lst[ptr[m->el[e].a]++] = e, lst[ptr[m->el[e].b]++] = e;
  for (int c = nc; c > 0; c--) ptr[c] = ptr[c - 1];
  ptr[0] = 0;
  for (int c = 0; c < nc; c++) via[c] = -2; /* not reached yet */
  for (int pass = 0; pass < 3; pass++)
    for (int r = 0; r < (pass < 2 ? m->np : nc); r++) {
      const phm_pair_desc *pr = pass < 2 ? &m->pair[r] : NULL;
      int cands[2] = {pr ? pr->a : r, pr ? pr->b : -1};
      if (pass == 0 && pr->a >= 0 && pr->b >= 0) continue;
      for (int ic = 0; ic < 2; ic++) {
        int c0 = cands[ic];
        if (c0 < 0 || via[c0] != -2) continue;
        via[c0] = -1;
        int head = n;
        order[n++] = c0;
        while (head < n) { /* breadth first: the tree's depth stays the shortest path */
          int c = order[head++];
          for (int k = ptr[c]; k < ptr[c + 1]; k++) {
            int e = lst[k], o = m->el[e].a == c ? m->el[e].b : m->el[e].a;
            if (via[o] != -2) continue;
            via[o] = e;
            order[n++] = o;
          }
        }
      }
    }
}

/* (H, lam) <- (H o a x, lam + a x) for the carriers' and multipliers' parts of x, o the chain
 * retraction: H exp(delta) at the roots of the element forest (chain_build), and from there each
 * element's relative pose exp(X) becomes exp(X + dX), dX = dexp_{-X}^-1 delta_b - dexp_X^-1
 * delta_a its first-order change (docs/method.md section 4.2). The step then moves the elements'
 * strains by their linear prediction and its second-order part goes into rigid motions of the
 * chain, where H exp(delta) on every carrier stretches the elements of a bending beam at second
 * order (the force of that stretch, times a stiff section's axial stiffness, is what made the
 * stiff roll-up of benchmarks/statics_newton.py take 1158 iterations). Both agree to first order,
 * so Newton stays quadratic; carriers without elements (rigid bodies) take H exp(delta). */
static void take_step(const phm_model *m, const static_work_t *w, double *H, double *lam,
                      const double *x, double a) {
  int nc = m->nc;
  memcpy(w->Hold, H, sizeof(double) * 16 * (size_t)nc);
  for (int k = 0; k < nc; k++) {
    int c = w->order[k], e = w->via[c];
    double d[6];
    for (int j = 0; j < 6; j++) d[j] = a * x[6 * c + j];
    if (e < 0) {
      phm_retract(H + 16 * c, d);
      continue;
    }
    int ea = m->el[e].a, eb = m->el[e].b;
    double Hi[16], Hab[16], X[6], Ai[9], Lb[9], da[6], db[6], E[16];
    for (int j = 0; j < 6; j++) da[j] = a * x[6 * ea + j], db[j] = a * x[6 * eb + j];
    phm_se3_inverse(w->Hold + 16 * ea, Hi);
    phm_se3_compose(Hi, w->Hold + 16 * eb, Hab);
    phm_se3_log_dexp_inv(Hab, X, Ai, Lb);
    /* X += B db - A da: A = [[Ai, 0], [L, Ai]], B = [[Ai^T, 0], [L^T, Ai^T]] */
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        X[i] += Ai[3 * j + i] * db[j] - Ai[3 * i + j] * da[j];
        X[3 + i] += Lb[3 * j + i] * db[j] + Ai[3 * j + i] * db[3 + j] - Lb[3 * i + j] * da[j] -
                    Ai[3 * i + j] * da[3 + j];
      }
    if (c == ea)
      for (int j = 0; j < 6; j++) X[j] = -X[j];
    phm_se3_exp(X, E);
    phm_se3_compose(H + 16 * (c == ea ? eb : ea), E, H + 16 * c);
  }
  for (int i = 0; i < m->ncons; i++) lam[i] += a * x[6 * nc + i];
}

/* A simplified (chord) correction, with a factorization made at an earlier iterate, is taken
 * while it contracts: |x_k| <= NEWTON_THETA |x_(k-1)|; otherwise a new tangent is made there. */
#define NEWTON_THETA 0.1

/* The poses and multipliers newton_steps saved on entry, back (a failed load step). */
static void back_to_saved(const static_work_t *w, int nc, int nk, double *H, double *lam) {
  memcpy(H, w->Hsave, sizeof(double) * 16 * (size_t)nc);
  if (nk) memcpy(lam, w->lsave, sizeof(double) * (size_t)nk);
}

/* A tangent KLU finds exactly singular: some motion has no stiffness at all (a free body, a
 * revolute without a load or spring: their blocks of df/ddelta are structurally zero). Where the
 * loads have no part along such a motion the state may still be an equilibrium, one of many:
 * solve instead with [df/ddelta - mu M, G^T; G, 0] (mu M: ptc's inertia term M/dtau with a
 * pseudo time step dtau = 1/mu), mu = 1e-12 tr|K| / tr M (1 /s^2 without stiffness), far below
 * the stiffness of any resisted motion, so that the step is Newton's there and M^-1 r / mu along
 * the free motions. Returns 1 (x: that step) when the step is below tol -- the residual along
 * the free motions is then below about mu m tol, and the state an equilibrium --, else 0, and the
 * caller fails as it did before this fallback: it only turns failures into convergence where the
 * state is already an equilibrium (tests/test_statics.py: a body held by nothing, a revolute
 * and a free link without load). L->Kb is overwritten. */
static int singular_converged(lin_t *L, lin_kkt_t *S, const double *Gp, const double *R,
                              double *x, double tol) {
  const phm_model *m = L->m;
  int nc = m->nc, N = 6 * nc + m->ncons;
  const int *ptr = L->ptr, *nbr = L->nbr;
  double trK = 0, trM = 0;
  for (int r = 0; r < nc; r++)
    for (int q = ptr[r]; q < ptr[r + 1]; q++)
      if (nbr[q] == r)
        for (int i = 0; i < 6; i++) {
          trK += fabs(L->Kb[36 * (size_t)q + 7 * i]);
          trM += m->car[r].M[7 * i];
        }
  if (!(trM > 0)) return 0;
  double mu = trK > 0 ? 1e-12 * trK / trM : 1.0;
  for (int r = 0; r < nc; r++)
    for (int q = ptr[r]; q < ptr[r + 1]; q++)
      if (nbr[q] == r)
        for (int i = 0; i < 36; i++) L->Kb[36 * (size_t)q + i] -= mu * m->car[r].M[i];
  for (int i = 0; i < N; i++) x[i] = -R[i];
  if (lin_kkt_factor(S, L->Kb, Gp) || lin_kkt_solve(S, x)) return 0;
  return step_size(m, x, NULL) < tol;
}

/* Newton from (H, lam) at the load scale L->scale; 0 on convergence (H, lam updated, and *have
 * set when S holds a tangent's factorization made in this solve: not after singular_converged),
 * 1 on failure (H, lam restored, *have 0). With
 * *have on entry, the tangent predictor first: S's factorization (of the last load's solve) on
 * this load's residual, one step (for a load increment dF that is K^-1 dF). Then corrections at
 * each iterate: a new tangent [K G^T; G 0] (in closed form, csrc/analyze/linearize.c) factored by
 * KLU, or, while they contract by
 * NEWTON_THETA, simplified ones with the last factorization (one residual and solve each); each
 * step scaled down to at most 1 rad of rotation and taken by the chain retraction (take_step).
 * Converged when a correction is below tol (rad, and lengths in units of the element length
 * lref; it is then applied) -- one made with the tangent of the previous iterate, or a
 * contracting simplified one -- or when one with the previous iterate's tangent stalls at
 * round-off below 1e3 tol. Failure (non-finite steps, maxit tangents) lets the caller cut the
 * load step.
 * Measured (benchmarks/statics_newton.py, iterations = tangents; a cantilever under P L^2/EI = 3
 * in 10 load steps at N = 20 and 1000, the same 1e4 times stiffer at N = 200, the roll-up by
 * 2 pi EI in 8 load steps at N = 21 and 200, and stiff at N = 21). With the finite-difference
 * tangent the steps were also capped at one element length lref: 54, 858, 1018, 81, 582, 2319.
 * With the exact tangent and without the length cap: 41, 42, 72, 64, 64, 1158 (doubling the
 * load step beyond 1/steps after fast convergence gave 22 and 24 for the first two, but jumped
 * past the bifurcation of the imperfect elastica of tests/hard/test_hard_statics.py). A line
 * search by the natural monotonicity test (Deuflhard 2004, section 3.3) on top halved the soft
 * cases' counts no further and quadrupled the stiff ones' (the simplified correction of a stiff
 * beam's stretched trial state is huge); a secant predictor on every carrier's pose cost the
 * roll-up 40 % more. The stiff roll-up's trace showed why: after each tangent step of a load
 * step of 1/64 (0.1 rad at the tip) the force residual rose from 5e2 to 5e7 (the stretched
 * elements), and Newton needed 6 tangents per load step and load steps of 1/128. Then, each
 * measured alone and together: the chain retraction 31, 38, 36, 10, 17, 17 (the roll-ups' strains
 * are constant, so one tangent step solves a load step: two tangents, the second to confirm at
 * round-off); simplified corrections with NEWTON_THETA = 0.1 on H exp(delta): 21, 21, 65, 50, 49,
 * 951; with the predictor too: 15, 15, 76, 78, 44, 893; the chain retraction with the predictor
 * (no simplified corrections): 29, 31, 31, 9, 9, 12; all three: 12, 12, 21, 9, 9, 12, CPU -45 %
 * at N = 1000 (a simplified correction costs a residual and a solve, a tangent then cost the
 * coloured differences of the pairs and loads and a factorization; the pairs', loads' and
 * springs' tangents have been closed form since). NEWTON_THETA = 0.03: 16, 16, 21, 9, 9,
 * 12; 0.3: 11, 11, 21, 9, 9, 15. Simplified corrections right after the predictor (a
 * factorization from the last load, before the whole load increment) went astray on stiff beams
 * (the stiff roll-up 20, the stiff tip load 33): after the predictor a new tangent is made.
 * Doubling the load step beyond 1/steps (up to 1) after one that took a single tangent: 7, 7,
 * 21, 9, 9, 14, and the hard statics cases still passed; not kept, since `steps` bounds the
 * increment the caller asked for (see phm_static_monitored). */
static int newton_steps(lin_t *L, lin_kkt_t *S, double *H, double *lam, double tol, int maxit,
                        static_work_t *w, int *iters, int *have) {
  const phm_model *m = L->m;
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk;
  double *R = w->R, *x = w->x, rot = 0.0, sn = INFINITY;
  memcpy(w->Hsave, H, sizeof(double) * 16 * (size_t)nc);
  if (nk) memcpy(w->lsave, lam, sizeof(double) * (size_t)nk);
  L->lam = lam;
  static_residual(L, H, R);
  if (*have) { /* the tangent predictor: the last factorization on this load's residual */
    for (int i = 0; i < N; i++) x[i] = -R[i];
    sn = lin_kkt_solve(S, x) ? INFINITY : step_size(m, x, &rot);
    if (sn < tol) {
      take_step(m, w, H, lam, x, 1.0);
      return 0;
    }
    if (isfinite(sn)) {
      take_step(m, w, H, lam, x, rot > 1.0 ? 1.0 / rot : 1.0);
      static_residual(L, H, R);
    }
  }
  *have = 0;
  /* age: steps since the factorization in S (0: none made here yet); sprev: the last step */
  int age = 0, tangents = 0;
  double sprev = INFINITY;
  for (int k = 0; k < 4 * maxit; k++) {
    if (age > 0) { /* the simplified (chord) correction: S's factorization, this residual */
      for (int i = 0; i < N; i++) x[i] = -R[i];
      sn = lin_kkt_solve(S, x) ? INFINITY : step_size(m, x, &rot);
      if (isfinite(sn) && ((sn < tol && (age == 1 || sn <= NEWTON_THETA * sprev)) ||
                           (age == 1 && sn < 1e3 * tol && sn > 0.25 * sprev))) {
        take_step(m, w, H, lam, x, 1.0);
        *have = 1;
        return 0;
      }
    }
    if (age == 0 || !(sn <= NEWTON_THETA * sprev)) { /* a new tangent */
      if (tangents++ == maxit) break;
      (*iters)++;
      lin_force_jacobian_blocks(L, H);
      if (nk) lin_constraint_blocks(L, H, w->Gp);
      for (int i = 0; i < N; i++) x[i] = -R[i];
      if (lin_kkt_factor(S, L->Kb, w->Gp)) {
        if (!singular_converged(L, S, w->Gp, R, x, tol)) break;
        take_step(m, w, H, lam, x, 1.0); /* S holds no tangent now: no predictor from it */
        return 0;
      }
      if (lin_kkt_solve(S, x)) break;
      sn = step_size(m, x, &rot);
      if (!isfinite(sn)) break; /* diverging: let the caller cut the load step */
      age = 0;
      if (sn < tol) {
        take_step(m, w, H, lam, x, 1.0);
        *have = 1;
        return 0;
      }
    }
    double a = rot > 1.0 ? 1.0 / rot : 1.0;
    take_step(m, w, H, lam, x, a);
    sprev = a * sn;
    age++;
    static_residual(L, H, R);
  }
  back_to_saved(w, nc, nk, H, lam);
  return 1;
}

/* newton_steps, and a "converged" state that is not finite (a step small in the norm of the
 * poses whose multipliers or exponential overflowed: found by tests/test_fuzz.py on a free
 * link under a huge load) is a failure: the state goes back to the one before, so that the
 * caller cuts the load step and, failing, hands back the last finite equilibrium. */
static int newton(lin_t *L, lin_kkt_t *S, double *H, double *lam, double tol, int maxit,
                  static_work_t *w, int *iters, int *have) {
  int nc = L->m->nc, nk = L->m->ncons;
  if (newton_steps(L, S, H, lam, tol, maxit, w, iters, have)) return 1;
  if (phm_all_finite(H, 16 * (size_t)nc) && (!nk || phm_all_finite(lam, (size_t)nk))) return 0;
  back_to_saved(w, nc, nk, H, lam);
  *have = 0;
  return 1;
}

/* Pseudo-transient continuation at the load scale L->scale from (H, lam), for where Newton's
 * tangent is singular or misleading (a pendulum started horizontal: gravity has no stiffness
 * there, and Newton's step is infinite): Newton on an implicit Euler step of the overdamped
 * motion M d(delta)/dtau = f, i.e. [df/ddelta - M/dtau, G^T; G, 0] x = -R, with the pseudo time
 * step dtau grown as the residual falls (switched evolution relaxation: dtau *= |R_prev| / |R|,
 * at most x10 per step). Far from equilibrium it moves downhill, near it it is Newton, so it
 * ends at a stable equilibrium as a rule: after each step that moved less than 1e-2 (rad, element
 * lengths) newton() is tried from there. 0 on convergence, 1 on failure (H, lam restored). */
static int ptc(lin_t *L, lin_kkt_t *S, double *H, double *lam, double tol, int maxit,
               static_work_t *w, int *iters) {
  const phm_model *m = L->m;
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk;
  const int *ptr = L->ptr, *nbr = L->nbr;
  double *R = w->R;
  memcpy(w->Hptc, H, sizeof(double) * 16 * (size_t)nc);
  if (nk) memcpy(w->lptc, lam, sizeof(double) * (size_t)nk);
  L->lam = lam;
  double trM = 0;
  for (int c = 0; c < nc; c++)
    for (int i = 0; i < 6; i++) trM += m->car[c].M[7 * i];
  double dtau = 0, rn = 0;
  static_residual(L, H, R);
  for (int i = 0; i < N; i++) rn += R[i] * R[i];
  rn = sqrt(rn);
  for (int it = 0; it < maxit && isfinite(rn); it++) {
    (*iters)++;
    lin_force_jacobian_blocks(L, H);
    if (nk) lin_constraint_blocks(L, H, w->Gp);
    if (it == 0) { /* the first step: the inertia term 100 times the stiffness */
      double trK = 0;
      for (int r = 0; r < nc; r++)
        for (int q = ptr[r]; q < ptr[r + 1]; q++)
          if (nbr[q] == r)
            for (int i = 0; i < 6; i++) trK += fabs(L->Kb[36 * (size_t)q + 7 * i]);
      dtau = trK > 0 && trM > 0 ? 1e-2 * trM / trK : 1e-2;
    }
    for (int r = 0; r < nc; r++)
      for (int q = ptr[r]; q < ptr[r + 1]; q++)
        if (nbr[q] == r)
          for (int i = 0; i < 36; i++) L->Kb[36 * (size_t)q + i] -= m->car[r].M[i] / dtau;
    for (int i = 0; i < N; i++) R[i] = -R[i];
    if (lin_kkt_factor(S, L->Kb, w->Gp) || lin_kkt_solve(S, R)) {
      dtau *= 0.1;
      static_residual(L, H, R);
      continue;
    }
    double rot, sn = step_size(m, R, &rot);
    if (!isfinite(sn)) break;
    take_step(m, w, H, lam, R, rot > 1.0 ? 1.0 / rot : 1.0);
    static_residual(L, H, R);
    double rnew = 0;
    for (int i = 0; i < N; i++) rnew += R[i] * R[i];
    rnew = sqrt(rnew);
    if (!isfinite(rnew)) break;
    /* switched evolution relaxation, growing at least x2 (x10 while the steps are tiny) while
     * the residual does not grow: a pendulum's torque hardly changes over its first small
     * steps, and SER alone stalls there */
    dtau *= rnew > rn ? 0.5 : fmin(10.0, fmax(sn < 1e-4 ? 10.0 : 2.0, rnew > 0 ? rn / rnew : 10.0));
    rn = rnew;
    /* near an equilibrium: Newton (which restores the state when it fails) */
    if (sn < 1e-2) {
      int v = 0;
      if (!newton(L, S, H, lam, tol, 8, w, iters, &v)) return 0;
    }
  }
  memcpy(H, w->Hptc, sizeof(double) * 16 * (size_t)nc);
  if (nk) memcpy(lam, w->lptc, sizeof(double) * (size_t)nk);
  return 1;
}

/* PHM_ESOLVER with a message when the loads do work on a motion nothing resists at poses H
 * (phm_static_free, csrc/analyze/static_free.c: then no equilibrium exists, and step halving and
 * pseudo-transient continuation would only fail slowly), else PHM_OK (or PHM_ENOMEM). Called at
 * Newton's first failure: a solve that converges never pays for it, and one that fails would
 * fail anyway -- the motions are proved free from the structure, not guessed from a singular
 * tangent, which a pendulum started horizontal also has. */
static phm_status no_equilibrium(const phm_model *m, const double *H, double time, phm_error *err) {
  phm_free_motion fm[4];
  int n = 0;
  phm_status st = phm_static_free(m, H, time, 4, fm, NULL, NULL, &n, err);
  if (st || n == 0) return st;
  const phm_free_motion *f = &fm[0];
  int rot = f->twist[0] != 0 || f->twist[1] != 0 || f->twist[2] != 0;
  const char *unit = rot ? "N m" : "N";
  char what[160];
  if (f->pair >= 0) {
    const phm_pair_type_info *ti = phm_pair_type(m->pair[f->pair].type);
    unit = ti && ti->units[f->coord] && strcmp(ti->units[f->coord], "m") == 0 ? "N" : "N m";
    snprintf(what, sizeof what, "pair %d (%s), joint coordinate %d, moves the side of carrier %d "
             "freely", f->pair, ti ? ti->name : "?", f->coord, f->carrier);
  } else
    snprintf(what, sizeof what, "carrier %d and what is linked to it, held by nothing, %s freely",
             f->carrier, rot ? "turn" : "move");
  return PHM_FAIL(err, PHM_ESOLVER, "no static equilibrium: the loads do work on a "
                  "motion nothing resists: %s under a generalized force of %.6g %s (actuator "
                  "effort %.6g, gravity %.6g, applied wrenches %.6g)%s. Hold it (%s) or "
                  "simulate() instead", what, f->force, unit, f->effort, f->gravity,
                  f->force - f->effort - f->gravity, n > 1 ? "; and other such motions" : "",
                  f->pair >= 0 ? "a spring or a PD actuator on the pair, a driven coordinate, a "
                  "Fixed pair" : "a pair or a spring to the ground");
}

phm_status phm_static(const phm_model *m, const double *poses, double time, int steps, double tol,
                      double *poses_out, double *lambda_out, int *iters, phm_error *err) {
  return phm_static_monitored(m, poses, time, steps, tol, NULL, NULL, poses_out, lambda_out, iters,
                              NULL, err);
}

phm_status phm_static_monitored(const phm_model *m, const double *poses, double time, int steps,
                                double tol, phm_monitor monitor, void *ctx, double *poses_out,
                                double *lambda_out, int *iters, double *reached, phm_error *err) {
  phm_error_clear(err);
  if (!m || !poses_out) return PHM_FAIL(err, PHM_EINVAL, "phm_static: NULL argument");
  if (steps < -1) return PHM_FAIL(err, PHM_EINVAL, "load steps must be >= -1 (got %d)", steps);
  if (!(tol > 0)) return PHM_FAIL(err, PHM_EINVAL, "tolerance must be > 0 (got %g)", tol);
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk, it = 0;
  double s = 0; /* the load factor reached */
  phm_status st = PHM_OK;
  lin_t L = {0};
  lin_kkt_t S;
  memset(&S, 0, sizeof S);
  static_work_t w = {
      .R = malloc(sizeof(double) * (size_t)N),
      .Gp = malloc(sizeof(double) * 12 * (size_t)(nk + 1)),
      .Hsave = malloc(sizeof(double) * 16 * (size_t)nc), .lsave = malloc(sizeof(double) * (size_t)(nk + 1)),
      .x = malloc(sizeof(double) * (size_t)N), .Hold = malloc(sizeof(double) * 16 * (size_t)nc),
      .Hptc = malloc(sizeof(double) * 16 * (size_t)nc), .lptc = malloc(sizeof(double) * (size_t)(nk + 1)),
      .order = malloc(sizeof(int) * (size_t)nc), .via = malloc(sizeof(int) * (size_t)nc)};
  int *adj = malloc(sizeof(int) * (size_t)(nc + 1 + 2 * m->ne));
  double *lam = calloc((size_t)(nk + 1), sizeof(double));
  if (!w.R || !w.Gp || !w.Hsave || !w.lsave || !w.x || !w.Hold || !w.Hptc ||
      !w.lptc || !w.order || !w.via || !adj || !lam) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  chain_build(m, w.order, w.via, adj);
  if ((st = lin_alloc(&L, m, err)) || (st = lin_graph(&L, err))) goto done;
  if ((st = lin_kkt_build(&S, &L, err))) goto done;
  L.time = time;
  L.tref = phm_model_tref(m, time, NULL);
  L.comps = 1; /* the components' efforts at rest (Python refuses those with states) */
  for (int c = 0; c < nc; c++) memcpy(poses_out + 16 * c, poses ? poses + 16 * c : m->car[c].H0, 16 * sizeof(double));
  int have = 0; /* S holds the factorization of the last Newton solve that converged */
  int pre_failed = 0;
  if (steps <= 0) {
    /* no load stepping: Newton at the full load from the start, pseudo-transient continuation
     * if it fails (whether the start is an equilibrium: Mechanism.modes' check; with load
     * stepping, an unloaded state would be found first, and one full load step from there can
     * land on another branch than the start's, as from the post-buckled elastica's); steps = -1:
     * Newton only (the equilibrium next to a start that rings, python/phmech/_modes.py: a
     * continuation's would be far from it, and found slowly) */
    L.scale = 1.0;
    /* (steps = -1 asks for an equilibrium next to the start: Newton's quadratic convergence
     * reaches it in a few iterations -- the README's strip released from 0.1 N at its tip: 3 --
     * and a start that needs more is not next to one) */
    if (newton(&L, &S, poses_out, lam, tol, steps < 0 ? 12 : 50, &w, &it, &have)) {
      if (steps < 0) {
        st = PHM_FAIL(err, PHM_ESOLVER, "static equilibrium: Newton at the full load from the "
                      "start failed (%d iterations; no continuation asked)", it);
        goto done;
      }
      if ((st = no_equilibrium(m, poses_out, time, err))) goto done;
      if (ptc(&L, &S, poses_out, lam, tol, 500, &w, &it)) {
        st = PHM_FAIL(err, PHM_ESOLVER, "static equilibrium: Newton at the full load from the "
                      "start failed, and pseudo-transient continuation too (%d iterations)", it);
        goto done;
      }
    }
    s = 1.0;
  } else {
    /* meet the constraints without load first (a mechanism with a free degree of freedom is
     * singular without load: then go on directly) */
    L.scale = 0.0;
    pre_failed = newton(&L, &S, poses_out, lam, tol, 50, &w, &it, &have);
  }
  /* load stepping from the unloaded equilibrium: a step is halved when Newton fails to converge
   * in 12 tangents (with the exact tangent, one that has not converged by then rarely does; 30
   * cost the stiff roll-up of benchmarks/statics_newton.py 1501 iterations instead of 1158 under
   * H exp(delta)) and doubled after one that took at most 4, up to 1/steps: `steps` bounds the
   * increment (a larger one can pass a bifurcation unseen) */
  double ds = steps ? 1.0 / steps : 1.0;
  int failed = 0; /* Newton has failed in this solve: no_equilibrium has been asked */
  while (s < 1.0) {
    double snew = s + ds > 1.0 - 1e-12 ? 1.0 : s + ds; /* ten steps of 0.1 add up to 1 - 1e-16 */
    L.scale = snew;
    int it0 = it;
    if (newton(&L, &S, poses_out, lam, tol, 12, &w, &it, &have)) {
      if (!failed++ && (st = no_equilibrium(m, poses_out, time, err))) goto done;
      ds *= 0.5;
      if (ds < 1e-4 / steps) {
        /* Newton cannot take even a tiny load step: its tangent is singular or misleading here
         * (a mechanism away from any equilibrium); pseudo-transient continuation instead */
        have = 0;
        if (!ptc(&L, &S, poses_out, lam, tol, 500, &w, &it)) {
          s = snew;
          ds = 1.0 / steps;
          continue;
        }
        st = PHM_FAIL(err, PHM_ESOLVER, "static equilibrium: Newton failed at load factor %.6g after step halving, and pseudo-transient continuation too (%d iterations)%s", snew, it,
                           pre_failed ? "; it also failed without load (unconstrained rigid-body motion or incompatible constraints?)" : "");
        goto done;
      }
      continue;
    }
    s = snew;
    if (it - it0 <= 4) ds = fmin(2.0 * ds, 1.0 / steps);
    if (monitor && monitor(ctx, s, it, ds)) {
      st = PHM_FAIL(err, PHM_EINTERRUPT, "static equilibrium: stopped by the caller at load factor %.6g", s);
      goto done;
    }
  }
  /* Here the poses and multipliers are finite: s reaches 1 only through a newton() or ptc() that
   * returned 0, and each of those is a newton() that found its state finite (a non-finite one is
   * its failure: the state goes back); after it only the monitor runs, which is given neither
   * poses_out nor lam. (A final check here, from before newton() had its own, could not fail.) */
done:
  /* also after a failure: the last converged state, at load factor *reached */
  if (lam && lambda_out && nk) memcpy(lambda_out, lam, sizeof(double) * (size_t)nk);
  if (reached) *reached = s;
  if (iters) *iters = it;
  lin_free(&L);
  lin_kkt_free(&S);
  free(w.R); free(w.Gp);
  free(w.Hsave); free(w.lsave); free(w.x); free(w.Hold);
  free(w.Hptc); free(w.lptc); free(w.order); free(w.via); free(adj); free(lam);
  return st;
}
