/* watch.c -- the constraints watched at every accepted step: the position residual of every
 * pair, its dropped (redundant) rows included, against the stated tolerance (docs/method.md
 * section 6.8, docs/user_guide.md "Constraints"). The redundant rows are chosen once, at the
 * initial configuration (python/phmech/topology.py); a row that was redundant there need not
 * stay so (a spatial loop through a configuration where its axes are momentarily dependent), and
 * the DAE, which no longer holds it, would let the pair open without a word. */
#include "dae.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "linalg.h"
#include "phm_check.h"
#include "pose.h"

/* s += G_r M^-1 G_r^T for one side: G (m x 6 rows), L the carrier inertia's Cholesky factor. */
static void add_schur_diag(const double *G, int mc, const double L[36], double *s) {
  for (int r = 0; r < mc; r++) {
    double x[6];
    memcpy(x, G + 6 * r, sizeof x);
    phm_chol6_solve(L, x);
    for (int j = 0; j < 6; j++) s[r] += G[6 * r + j] * x[j];
  }
}

void dae_regularization_scale(dae_t *d, double rtol, int per_step) {
  dae_full(d)->reg = fmin(1.0, rtol / (per_step ? 1e-8 : 1e-6));
}

/* The root of v in the union-find forest par (path halving). */
static int uf_root(int *par, int v) {
  while (par[v] != v) v = par[v] = par[par[v]];
  return v;
}

/* onloop[ip] = 1 for the pairs (with constraint rows) on a cycle of the graph whose vertices are
 * the carriers and the ground (vertex nc) and whose edges are those pairs: a spanning forest by
 * union-find, then for every pair outside it the forest's path between its ends (up to their
 * common ancestor, by depth). Work: the pairs times the forest's depth at most. */
static phm_status pairs_on_loops(const phm_model *m, unsigned char *onloop, phm_error *err) {
  int nv = m->nc + 1, np = m->np;
  int *par = malloc(sizeof(int) * (size_t)nv), *tree = calloc((size_t)np + 1, sizeof(int));
  int *head = malloc(sizeof(int) * (size_t)nv), *next = malloc(sizeof(int) * (size_t)(2 * np + 1));
  int *up = malloc(sizeof(int) * (size_t)nv), *upe = malloc(sizeof(int) * (size_t)nv);
  int *depth = malloc(sizeof(int) * (size_t)nv), *queue = malloc(sizeof(int) * (size_t)nv);
  phm_status st = PHM_OK;
  if (!par || !tree || !head || !next || !up || !upe || !depth || !queue) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
#define VTX(c) ((c) < 0 ? m->nc : (c))
  for (int v = 0; v < nv; v++) par[v] = v, head[v] = -1, depth[v] = -1;
  for (int ip = 0; ip < np; ip++) {
    onloop[ip] = 0;
    if (phm_pair_rows_full(&m->pair[ip]) == 0) continue;
    int a = VTX(m->pair[ip].a), b = VTX(m->pair[ip].b), ra = uf_root(par, a), rb = uf_root(par, b);
    if (ra == rb) continue;
    par[ra] = rb;
    tree[ip] = 1; /* a forest edge, listed at both ends (entries 2 ip and 2 ip + 1) */
    next[2 * ip] = head[a], head[a] = 2 * ip;
    next[2 * ip + 1] = head[b], head[b] = 2 * ip + 1;
  }
  for (int r = 0; r < nv; r++) { /* parents and depths by breadth-first search per tree */
    if (depth[r] >= 0) continue;
    int qh = 0, qt = 0;
    depth[r] = 0, up[r] = -1, upe[r] = -1, queue[qt++] = r;
    while (qh < qt) {
      int v = queue[qh++];
      for (int e = head[v]; e >= 0; e = next[e]) {
        int ip = e / 2, w = (e % 2) ? VTX(m->pair[ip].a) : VTX(m->pair[ip].b);
        if (depth[w] >= 0) continue;
        depth[w] = depth[v] + 1, up[w] = v, upe[w] = ip, queue[qt++] = w;
      }
    }
  }
  for (int ip = 0; ip < np; ip++) {
    if (tree[ip] || phm_pair_rows_full(&m->pair[ip]) == 0) continue;
    onloop[ip] = 1;
    int a = VTX(m->pair[ip].a), b = VTX(m->pair[ip].b);
    while (a != b) {
      if (depth[a] < depth[b]) { int t = a; a = b; b = t; }
      onloop[upe[a]] = 1;
      a = up[a];
    }
  }
#undef VTX
done:
  free(par), free(tree), free(head), free(next), free(up), free(upe), free(depth), free(queue);
  return st;
}

phm_status dae_regularization(dae_t *d, phm_error *err) {
  const phm_model *m = d->m;
  double *c = d->data.lreg, *cm = d->data.mreg, sum = 0;
  int cnt = 0;
  unsigned char *onloop = malloc((size_t)m->np + 1);
  if (!onloop) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  phm_status st = pairs_on_loops(m, onloop, err);
  for (int r = 0; r < m->ncons; r++) c[r] = cm[r] = 0.0;
  for (int ip = 0; !st && ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int mc = m->pair_m[ip], r0 = m->pair_row[ip];
    if (mc == 0 || !onloop[ip]) continue;
    double g[PHM_MAXCON], Ga[6 * PHM_MAXCON], Gb[6 * PHM_MAXCON], vt[PHM_MAXCON];
    phm_pair_eval(m, ip, pr->a >= 0 ? m->car[pr->a].H0 : NULL, pr->b >= 0 ? m->car[pr->b].H0 : NULL,
                  NULL, 0.0, 0.0, g, Ga, Gb, vt);
    double s[PHM_MAXCON] = {0}, L[36];
    /* a carrier whose inertia is not positive definite (a node of consistent mass, whose
     * inertia its neighbours share) adds nothing: the others' give the scale */
    if (pr->a >= 0 && phm_chol6(m->car[pr->a].M, 0.0, 1e-12, L) == 0) add_schur_diag(Ga, mc, L, s);
    if (pr->b >= 0 && phm_chol6(m->car[pr->b].M, 0.0, 1e-12, L) == 0) add_schur_diag(Gb, mc, L, s);
    for (int r = 0; r < mc; r++) {
      c[r0 + r] = DAE_REG_TIME * s[r];
      cm[r0 + r] = DAE_REG_TIME;
      if (s[r] > 0 && isfinite(s[r])) sum += s[r], cnt++;
    }
  }
  /* rows on a loop with no scale of their own: the mean of the others' */
  for (int r = 0; r < m->ncons; r++)
    if (cm[r] > 0 && !(c[r] > 0 && isfinite(c[r]))) c[r] = cnt ? DAE_REG_TIME * sum / cnt : DAE_REG_TIME;
  free(onloop);
  return st;
}

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

phm_status dae_step_accepted(dae_t *d, double t, const double *y, double rel, double atol,
                              int output, phm_error *err) {
  dae_t *f = dae_full(d);
  const phm_model *m = f->m;
  if (d->pl) y = dae_planar_state(d, y);
  memcpy(f->data.lref, y + f->il, sizeof(double) * (size_t)m->ncons);
  double tol_m = fmax(rel * f->lscale, atol), tol_r = fmax(rel, atol);
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int mc = phm_pair_rows_full(pr);
    if (mc == 0 || (!output && !pr->drop)) continue; /* held rows: Newton's, checked at outputs */
    /* a planar DAE's out-of-plane rows hold exactly: between outputs only a pair that dropped an
     * in-plane (redundant) row is checked. On the chain of benchmarks/bench_scaling.py (n = 30,
     * every revolute's three out-of-plane rows dropped) the check was 8 % of the run */
    if (!output && d->pl && dae_planar_drops_out_of_plane(d, ip, y, t)) continue;
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
