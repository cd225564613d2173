/* watch.c -- the constraints watched at every accepted step: the position residual of every
 * pair, its dropped (redundant) rows included, against the stated tolerance (docs/method.md
 * section 6.8, docs/user_guide.md "Constraints"). The redundant rows are chosen once, at the
 * initial configuration (python/phmech/topology.py); a row that was redundant there need not
 * stay so (a spatial loop through a configuration where its axes are momentarily dependent), and
 * the DAE, which no longer holds it, would let the pair open without a word. */
#include "dae.h"

#include <math.h>
#include <string.h>

#include "phm_check.h"
#include "pose.h"

/* The mechanism's size [m] that scales the translation tolerance: the extent (bounding-box
 * diagonal) of the carriers' initial origins, with the world origin when a pair uses the ground,
 * and the pairs' frame offsets; 1 m when all are zero (python/phmech/topology.py's length_scale
 * without the links' lengths, which their nodes' extent stands for). */
double dae_length_scale(const phm_model *m) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, L = 0;
  int ground = 0;
  for (int k = 0; k < m->np; k++) {
    const phm_pair_desc *pr = &m->pair[k];
    ground |= pr->a < 0 || pr->b < 0;
    double a = 0, b = 0;
    for (int i = 0; i < 3; i++) {
      a += pr->Ta[4 * i + 3] * pr->Ta[4 * i + 3];
      b += pr->Tb[4 * i + 3] * pr->Tb[4 * i + 3];
    }
    L = fmax(L, sqrt(fmax(a, b)));
  }
  for (int c = -1; c < m->nc; c++) {
    if (c < 0 && !ground) continue;
    for (int i = 0; i < 3; i++) {
      double x = c < 0 ? 0.0 : m->car[c].H0[4 * i + 3];
      lo[i] = fmin(lo[i], x);
      hi[i] = fmax(hi[i], x);
    }
  }
  if (m->nc > 0 || ground) {
    double e = 0;
    for (int i = 0; i < 3; i++) e += (hi[i] - lo[i]) * (hi[i] - lo[i]);
    L = fmax(L, sqrt(e));
  }
  return L > 0 && isfinite(L) ? L : 1.0;
}

phm_status dae_step_accepted(dae_t *d, double t, const double *y, double atol, phm_error *err) {
  dae_t *f = dae_full(d);
  const phm_model *m = f->m;
  if (d->pl) y = dae_planar_state(d, y);
  double tol_m = fmax(DAE_CONSTRAINT_TOL * f->lscale, atol), tol_r = fmax(DAE_CONSTRAINT_TOL, atol);
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int mc = phm_pair_rows_full(pr);
    if (mc == 0) continue;
    double Ha[16], Hb[16], g[PHM_MAXCON], W[36];
    if (pr->a >= 0) phm_qp_to_H(y + PHM_NSTATE * pr->a, y + PHM_NSTATE * pr->a + 4, Ha);
    if (pr->b >= 0) phm_qp_to_H(y + PHM_NSTATE * pr->b, y + PHM_NSTATE * pr->b + 4, Hb);
    phm_pair_eval_full(m, ip, pr->a >= 0 ? Ha : NULL, pr->b >= 0 ? Hb : NULL,
                       y + f->ix + m->pair_j[ip], t, f->tref, g, NULL, NULL, W);
    for (int r = 0; r < mc; r++) {
      /* a row whose wrench direction has a force part is a translation [m], else a rotation */
      int trans = W[6 * 3 + r] != 0 || W[6 * 4 + r] != 0 || W[6 * 5 + r] != 0;
      double tol = trans ? tol_m : tol_r;
      if (!(fabs(g[r]) <= tol))
        return PHM_FAIL(err, PHM_ESOLVER, "constraint opened: pair #%d row %d (%s): position "
                        "residual %.3g %s above the tolerance %.3g %s at t = %.9g s", ip, r,
                        (pr->drop >> r & 1) ? "redundant at the start, not held" : "held",
                        fabs(g[r]), trans ? "m" : "rad", tol, trans ? "m" : "rad", t);
    }
  }
  return PHM_OK;
}
