/* static_free.c -- why a static solve cannot succeed: motions that nothing resists and on which
 * the loads do work at a rate that is the same in every configuration (docs/method.md section
 * 7.3, "No equilibrium"). Along such a motion the generalized force never vanishes, so no
 * configuration is an equilibrium; Newton's tangent is singular along it and the step halving and
 * pseudo-transient continuation of statics.c can only fail, slowly and without saying why.
 *
 * The tangent alone cannot tell: a zero-stiffness direction with a load along it is also what a
 * pendulum started horizontal shows (gravity's stiffness vanishes there, but it hangs at rest
 * further on), and benchmarks/scenes.py's double pendulum, which static() solves, has two of
 * them at its horizontal start. So the motions are taken from the structure, where the argument
 * holds in every configuration, and the tangent's numbers only confirm them:
 *
 * - a pair whose removal separates a part S from the ground (a bridge of the graph whose edges
 *   are the elements, pairs, springs, interactions and mass couplings): S moving along one of
 *   the pair's joint coordinates j, all else at rest, keeps every constraint (the relative pose
 *   of the pair moves along its allowed twist psi_j; within S nothing moves relative to anything)
 *   and every internal force's work at zero (S moves rigidly; nothing else touches it). The loads'
 *   work rate is then the pair's actuator effort u_j (Phi^T psi_j = e_j, whatever the pose) plus
 *   what gravity and the applied wrenches on S do, which is the same in every configuration only
 *   when the pair's other frame is the ground, psi_j's direction is fixed in it (the pair table's
 *   axes_a, axes_b) and, for a rotation, each force is parallel to the axis; a body-frame load
 *   turns with its carrier and is refused. An actuator with a stiffness on coordinate j (PD or
 *   joint spring with kp_j != 0) holds it: refused.
 * - a part linked to the ground by nothing: its translation along the net force of gravity and
 *   the world-frame forces on it (constant), or, when no force acts, its rotation about the net
 *   world-frame moment.
 *
 * Each motion found is then checked with the model's own forces (phm_applied_pairs, all
 * internal forces included) at the poses given and at two poses along it, where the constraints
 * must still hold: a motion the structure proposes but the forces do not confirm is dropped. */
#include "analyze.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "linalg.h"
#include "phm_check.h"

/* A work rate is zero when below this fraction of the sum of its parts' magnitudes (gravity
 * normal to a slider's axis gives round-off, not a push). */
#define FREE_ZERO 1e-9
/* The model's forces must give the work rate to this, relative to the magnitudes summed (the
 * internal forces cancel to round-off). */
#define FREE_CHECK 1e-7
/* A force is parallel to a rotation axis when |f x omega| <= this |f| |omega|. */
#define FREE_ALIGN 1e-9

/* The work rate of body wrench w on a carrier at pose Hc under the world twist X = (omega, v):
 * its body twist is (R^T omega, R^T (omega x p + v)). *mag (may be NULL) += sum |t_i w_i|. */
static double work(const double *Hc, const double X[6], const double w[6], double *mag) {
  const double *om = X, *v = X + 3, p[3] = {Hc[3], Hc[7], Hc[11]};
  double u[3] = {om[1] * p[2] - om[2] * p[1] + v[0], om[2] * p[0] - om[0] * p[2] + v[1],
                 om[0] * p[1] - om[1] * p[0] + v[2]};
  double s = 0, a = 0;
  for (int i = 0; i < 3; i++) {
    double tw = Hc[i] * om[0] + Hc[4 + i] * om[1] + Hc[8 + i] * om[2]; /* R^T omega */
    double tv = Hc[i] * u[0] + Hc[4 + i] * u[1] + Hc[8 + i] * u[2];
    s += tw * w[i] + tv * w[3 + i];
    a += fabs(tw * w[i]) + fabs(tv * w[3 + i]);
  }
  if (mag) *mag += a;
  return s;
}

static double norm3(const double *a) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/* |a x b| <= FREE_ALIGN |a| |b| */
static int parallel(const double *a, const double *b) {
  double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  return norm3(c) <= FREE_ALIGN * norm3(a) * norm3(b);
}

/* psi with A psi = e_r for A (6x6 row-major) by Gaussian elimination with partial pivoting; 0 on
 * success, 1 if A is singular. */
static int solve6(double A[36], int r, double psi[6]) {
  double b[6] = {0};
  b[r] = 1.0;
  for (int k = 0; k < 6; k++) {
    int piv = k;
    for (int i = k + 1; i < 6; i++)
      if (fabs(A[6 * i + k]) > fabs(A[6 * piv + k])) piv = i;
    if (!(fabs(A[6 * piv + k]) > 0)) return 1;
    if (piv != k) {
      for (int j = 0; j < 6; j++) {
        double t = A[6 * k + j];
        A[6 * k + j] = A[6 * piv + j];
        A[6 * piv + j] = t;
      }
      double t = b[k];
      b[k] = b[piv];
      b[piv] = t;
    }
    for (int i = k + 1; i < 6; i++) {
      double f = A[6 * i + k] / A[6 * k + k];
      for (int j = k; j < 6; j++) A[6 * i + j] -= f * A[6 * k + j];
      b[i] -= f * b[k];
    }
  }
  for (int k = 5; k >= 0; k--) {
    double s = b[k];
    for (int j = k + 1; j < 6; j++) s -= A[6 * k + j] * psi[j];
    psi[k] = s / A[6 * k + k];
  }
  return 0;
}

/* The graph of what holds what: vertices the carriers and the ground (nc), edges the elements,
 * pairs (edge ne + ip), springs, interactions and mass couplings; a depth-first search from the
 * ground, then from each carrier not reached, in preorder (tin), with the low-link values that
 * find the bridges (Tarjan). The subtree of v is the carriers c with tin[v] <= tin[c] < tin[v] +
 * size[v]. */
typedef struct {
  int nv, *ptr, *adj;                   /* adjacency: (neighbour, edge) pairs                 */
  int *tin, *low, *size, *parent, *pedge, *root, *stack, *it;
} hold_t;

static void hold_free(hold_t *G) {
  free(G->ptr); free(G->adj); free(G->tin); free(G->low); free(G->size); free(G->parent);
  free(G->pedge); free(G->root); free(G->stack); free(G->it);
}

static phm_status hold_build(const phm_model *m, hold_t *G, phm_error *err) {
  int nc = m->nc, nv = nc + 1, ne = m->ne + m->np + m->ns + m->nl + m->nmc, n = 0;
  memset(G, 0, sizeof *G);
  G->nv = nv;
  int *ea = malloc(sizeof(int) * (size_t)(ne + 1)), *eb = malloc(sizeof(int) * (size_t)(ne + 1));
  G->ptr = calloc((size_t)nv + 1, sizeof(int));
  G->adj = malloc(sizeof(int) * 4 * (size_t)(ne + 1));
  int **arr[8] = {&G->tin, &G->low, &G->size, &G->parent, &G->pedge, &G->root, &G->stack, &G->it};
  for (int i = 0; i < 8; i++) *arr[i] = malloc(sizeof(int) * (size_t)nv);
  int ok = ea && eb && G->ptr && G->adj;
  for (int i = 0; i < 8; i++) ok = ok && *arr[i];
  if (!ok) {
    free(ea); free(eb);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
#define V(c) ((c) < 0 ? nc : (c))
  for (int e = 0; e < m->ne; e++, n++) ea[n] = m->el[e].a, eb[n] = m->el[e].b;
  for (int p = 0; p < m->np; p++, n++) ea[n] = V(m->pair[p].a), eb[n] = V(m->pair[p].b);
  for (int s = 0; s < m->ns; s++, n++) ea[n] = V(m->spr[s].a), eb[n] = V(m->spr[s].b);
  /* a load whose reaction is the ground holds nothing (a self-loop, left out below): only an
   * interaction links two carriers */
  for (int l = 0; l < m->nl; l++, n++) {
    const phm_load_desc *ld = &m->load[l];
    ea[n] = ld->carrier, eb[n] = ld->reaction >= 0 ? ld->reaction : ld->carrier;
  }
  for (int k = 0; k < m->nmc; k++, n++) ea[n] = m->mc_a[k], eb[n] = m->mc_b[k];
#undef V
  for (int e = 0; e < ne; e++)
    if (ea[e] != eb[e]) G->ptr[ea[e] + 1]++, G->ptr[eb[e] + 1]++;
  for (int v = 0; v < nv; v++) G->ptr[v + 1] += G->ptr[v];
  for (int v = 0; v < nv; v++) G->it[v] = G->ptr[v];
  for (int e = 0; e < ne; e++) /* self-loops (an element or load on one carrier) hold nothing */
    if (ea[e] != eb[e]) {
      int *x = G->adj + 2 * G->it[ea[e]]++, *y = G->adj + 2 * G->it[eb[e]]++;
      x[0] = eb[e], x[1] = e, y[0] = ea[e], y[1] = e;
    }
  free(ea);
  free(eb);
  /* iterative depth-first search (a chain of thousands of carriers would overflow recursion) */
  for (int v = 0; v < nv; v++) G->tin[v] = -1;
  int timer = 0;
  for (int k = 0; k < nv; k++) {
    int r = k == 0 ? nc : k - 1, sp = 0; /* the ground first */
    if (G->tin[r] >= 0) continue;
    G->parent[r] = G->pedge[r] = -1;
    G->tin[r] = G->low[r] = timer++;
    G->root[r] = r;
    G->it[r] = G->ptr[r];
    G->stack[sp++] = r;
    while (sp) {
      int v = G->stack[sp - 1];
      if (G->it[v] < G->ptr[v + 1]) {
        int w = G->adj[2 * G->it[v]], e = G->adj[2 * G->it[v] + 1];
        G->it[v]++;
        if (e == G->pedge[v]) continue; /* the edge it came by; a parallel one is a cycle */
        if (G->tin[w] < 0) {
          G->parent[w] = v;
          G->pedge[w] = e;
          G->tin[w] = G->low[w] = timer++;
          G->root[w] = r;
          G->it[w] = G->ptr[w];
          G->stack[sp++] = w;
        } else if (G->tin[w] < G->low[v])
          G->low[v] = G->tin[w];
      } else {
        sp--;
        G->size[v] = timer - G->tin[v];
        int u = G->parent[v];
        if (u >= 0 && G->low[v] < G->low[u]) G->low[u] = G->low[v];
      }
    }
  }
  return PHM_OK;
}

/* What one search needs: the model, the state and its forces at load factor 1. */
typedef struct {
  const phm_model *m;
  const hold_t *G;
  const double *H;
  double time, tref;
  double *wr, *eff, *wg, *wl, *g0, *Ht, *gt, *wt, *et; /* forces, efforts, gravity's, loads' */
  double *sl;                                         /* each load's law value at `time`   */
} search_t;

static int in_sub(const hold_t *G, int c, int v) {
  return G->tin[c] >= G->tin[v] && G->tin[c] < G->tin[v] + G->size[v];
}

/* The candidate motion X (a world twist) of the subtree of v: its work rate at load factor 1 from
 * gravity, the applied wrenches on it (into lw, nl) and the effort E; 0 when it is not a motion
 * whose work rate is the same in every configuration (see the file's comment; `fixed`: its
 * direction is fixed in the world in every configuration) or the rate is zero, else 1 with *F,
 * *Fg, *mass. Then checked against the model's forces here and along the motion. */
static int candidate(search_t *S, int v, const double X[6], int fixed, double E, double *lw,
                     double *F, double *Fg, double *mass) {
  const phm_model *m = S->m;
  const hold_t *G = S->G;
  int nc = m->nc;
  const double *om = X;
  int rot = norm3(om) > 0, grav = norm3(m->gravity) > 0;
  double M = 0, Gw = 0, gs = 0, Lw = 0, ls = 0;
  for (int c = 0; c < nc; c++)
    if (in_sub(G, c, v) && m->car[c].mass > 0) {
      M += m->car[c].mass;
      if (grav) Gw += work(S->H + 16 * c, X, S->wg + 6 * c, &gs);
    }
  if (grav && M > 0 && (!fixed || (rot && !parallel(m->gravity, om)))) return 0;
  for (int il = 0; il < m->nl; il++) {
    const phm_load_desc *l = &m->load[il];
    lw[il] = 0;
    int ci = in_sub(G, l->carrier, v), ri = l->reaction >= 0 && in_sub(G, l->reaction, v);
    if (S->sl[il] == 0 || (!ci && !ri)) continue;
    if (l->reaction >= 0) {
      if (ci != ri) return 0; /* not reached: an interaction is an edge, a bridge is not one */
      continue;               /* between two carriers of S: its work cancels */
    }
    double tau[3], f[3];
    for (int i = 0; i < 3; i++) tau[i] = S->sl[il] * l->w[i], f[i] = S->sl[il] * l->w[3 + i];
    int hasf = norm3(f) > 0, hast = norm3(tau) > 0;
    if (!hasf && !hast) continue;
    if (!l->world) { /* turns with its carrier: its work depends on the configuration */
      if (hasf || rot) return 0;
    } else if (hasf && (!fixed || (rot && !parallel(f, om))))
      return 0;
    else if (hast && rot && !fixed)
      return 0;
    lw[il] = work(S->H + 16 * l->carrier, X, S->wl + 6 * il, &ls);
    Lw += lw[il];
  }
  *F = Gw + Lw + E;
  *Fg = Gw;
  *mass = M;
  if (!isfinite(*F) || !(fabs(*F) > FREE_ZERO * (gs + ls + fabs(E)))) return 0;
  /* the model's own forces (internal ones included) here, then at two poses along the motion:
   * the same work rate, and the constraints hold as here */
  const double ts[3] = {0.0, 0.5, -1.7};
  for (int k = 0; k < 3; k++) {
    const double *Ht = S->H, *wt = S->wr;
    if (k > 0) {
      double E6[16], x[6];
      for (int i = 0; i < 6; i++) x[i] = ts[k] * X[i];
      phm_se3_exp(x, E6);
      memcpy(S->Ht, S->H, sizeof(double) * 16 * (size_t)nc);
      double reach = 1.0;
      for (int c = 0; c < nc; c++)
        if (in_sub(G, c, v)) {
          phm_se3_compose(E6, S->H + 16 * c, S->Ht + 16 * c);
          reach = fmax(reach, fabs(S->Ht[16 * c + 3]) + fabs(S->Ht[16 * c + 7]) + fabs(S->Ht[16 * c + 11]));
        }
      if (m->ncons) {
        phm_constraints_dense(m, S->Ht, NULL, S->time, S->tref, S->gt, NULL, NULL);
        for (int r = 0; r < m->ncons; r++)
          if (!(fabs(S->gt[r] - S->g0[r]) <= 1e-8 * reach)) return 0;
      }
      phm_applied_pairs(m, NULL, S->Ht, NULL, NULL, S->time, S->tref, 1.0, S->wt, NULL, NULL, NULL,
                        NULL, S->et);
      Ht = S->Ht;
      wt = S->wt;
    }
    double Fm = 0, mag = 0;
    for (int c = 0; c < nc; c++)
      if (in_sub(G, c, v)) Fm += work(Ht + 16 * c, X, wt + 6 * c, &mag);
    if (!(fabs(Fm - *F) <= FREE_CHECK * (mag + gs + ls + fabs(E)))) return 0;
  }
  return 1;
}

/* Motion number k (fm, its twist X, the loads' parts lw) into the outputs: the moving part is
 * the subtree of fm.carrier. */
static void record(const search_t *S, phm_free_motion fm, const double X[6], const double *lw, int k,
                   phm_free_motion *out, unsigned char *moving, double *load_work) {
  int nc = S->m->nc, nl = S->m->nl;
  memcpy(fm.twist, X, sizeof fm.twist);
  out[k] = fm;
  if (moving)
    for (int c = 0; c < nc; c++) moving[(size_t)k * nc + c] = (unsigned char)in_sub(S->G, c, fm.carrier);
  if (load_work) memcpy(load_work + (size_t)k * nl, lw, sizeof(double) * (size_t)nl);
}

/* The parts held by nothing (phm_static_free) from motion number found on, up to nmax; returns
 * the new count. */
static int free_parts(search_t *S, int found, int nmax, double *lw, phm_free_motion *out,
                      unsigned char *moving, double *load_work) {
  const phm_model *m = S->m;
  const double *H = S->H;
  int nc = m->nc, nl = m->nl;
  /* parts held by nothing: the roots of the search other than the ground */
  for (int r = 0; r < nc && found < nmax; r++) {
    if (S->G->root[r] != r) continue;
    double Fn[3] = {0, 0, 0}, Tn[3] = {0, 0, 0}, M = 0, mc[3] = {0, 0, 0};
    int body_force = 0, body_load = 0;
    for (int c = 0; c < nc; c++)
      if (in_sub(S->G, c, r) && m->car[c].mass > 0) {
        const double *Hc = H + 16 * c, *x = m->car[c].com;
        M += m->car[c].mass;
        for (int i = 0; i < 3; i++) {
          Fn[i] += m->car[c].mass * m->gravity[i];
          mc[i] += m->car[c].mass * (Hc[4 * i + 3] + Hc[4 * i] * x[0] + Hc[4 * i + 1] * x[1] + Hc[4 * i + 2] * x[2]);
        }
      }
    for (int il = 0; il < nl; il++) {
      const phm_load_desc *l = &m->load[il];
      if (l->reaction >= 0 || S->sl[il] == 0 || !in_sub(S->G, l->carrier, r)) continue;
      double f[3] = {S->sl[il] * l->w[3], S->sl[il] * l->w[4], S->sl[il] * l->w[5]};
      if (!l->world) {
        body_force |= norm3(f) > 0;
        body_load |= norm3(f) > 0 || norm3(l->w) * fabs(S->sl[il]) > 0;
        continue;
      }
      for (int i = 0; i < 3; i++) Fn[i] += f[i], Tn[i] += S->sl[il] * l->w[i];
    }
    double X[6] = {0, 0, 0, 0, 0, 0}, F, Fg, mass;
    double fn = norm3(Fn), tn = norm3(Tn);
    if (fn > 0 && !body_force) /* a translation along the net force */
      for (int i = 0; i < 3; i++) X[3 + i] = Fn[i] / fn;
    else if (fn == 0 && tn > 0 && !body_load) { /* no force at all: a rotation about the moment */
      double o[3] = {H[16 * r + 3], H[16 * r + 7], H[16 * r + 11]};
      if (M > 0)
        for (int i = 0; i < 3; i++) o[i] = mc[i] / M;
      for (int i = 0; i < 3; i++) X[i] = Tn[i] / tn;
      X[3] = o[1] * X[2] - o[2] * X[1]; /* v = o x omega: the axis through o */
      X[4] = o[2] * X[0] - o[0] * X[2];
      X[5] = o[0] * X[1] - o[1] * X[0];
    } else
      continue;
    if (!candidate(S, r, X, 1, 0.0, lw, &F, &Fg, &mass)) continue;
    record(S, (phm_free_motion){.pair = -1, .coord = -1, .carrier = r, .force = F, .gravity = Fg,
                                .effort = 0.0, .mass = mass},
           X, lw, found++, out, moving, load_work);
  }
  return found;
}

/* The pairs' coordinates nothing holds (phm_static_free), as free_parts. */
static int free_pairs(search_t *S, int found, int nmax, double *lw, phm_free_motion *out,
                      unsigned char *moving, double *load_work) {
  const phm_model *m = S->m;
  const double *H = S->H;
  int nc = m->nc;
  /* pairs that separate a part from the rest: bridges of the search tree */
  for (int v = 0; v < nc && found < nmax; v++) {
    int u = S->G->parent[v], e = S->G->pedge[v] - m->ne;
    if (u < 0 || e < 0 || e >= m->np || !(S->G->low[v] > S->G->tin[u])) continue;
    int ip = e, k = m->pair_k[ip];
    const phm_pair_desc *pr = &m->pair[ip];
    const phm_pair_type_info *ti = phm_pair_type(pr->type);
    if (k == 0 || !ti) continue;
    int side_b = v == pr->b; /* the part moves with F_b; else with F_a */
    int ground = side_b ? pr->a < 0 : pr->b < 0;
    const double *Ha = pr->a >= 0 ? H + 16 * pr->a : NULL, *Hb = pr->b >= 0 ? H + 16 * pr->b : NULL;
    double h[16], W[36], Phi[36], Fb[16], AdFb[36];
    phm_pair_frames(m, ip, Ha, Hb, h, NULL, NULL);
    phm_pair_kin(pr->type, pr->pitch, h, m->xref0 + m->pair_j[ip], NULL, W, Phi, NULL);
    if (Hb) phm_se3_compose(Hb, pr->Tb, Fb);
    else memcpy(Fb, pr->Tb, sizeof Fb);
    phm_se3_Ad(Fb, AdFb);
    for (int j = 0; j < k && found < nmax; j++) {
      if (pr->xdriven >> j & 1) continue; /* its coordinate follows a law: held */
      int held = 0;
      for (int ia = 0; ia < m->na; ia++)
        if (m->act[ia].pair == ip && m->act[ia].kind != PHM_ACT_EFFORT && m->act[ia].kp[j] != 0) held = 1;
      if (held) continue;
      /* psi_j: W^C^T psi = 0, Phi^T psi = e_j (rows of A: the columns of [W^C Phi]) */
      double A[36], psi[6], X[6];
      int mr = ti->m;
      for (int i = 0; i < 6; i++)
        for (int q = 0; q < 6; q++) A[6 * i + q] = i < mr ? W[6 * q + i] : Phi[6 * q + (i - mr)];
      if (solve6(A, mr + j, psi)) continue;
      phm_mv6(AdFb, psi, X); /* the part on F_b's side moves by Ad_Fb psi; on F_a's by -Ad_Fb psi */
      if (!side_b)
        for (int i = 0; i < 6; i++) X[i] = -X[i];
      int fixed = ground && ((side_b ? ti->axes_a : ti->axes_b) >> j & 1);
      double F, Fg, mass, E = S->eff[m->pair_j[ip] + j];
      if (!candidate(S, v, X, fixed, E, lw, &F, &Fg, &mass)) continue;
      record(S, (phm_free_motion){.pair = ip, .coord = j, .carrier = v, .force = F, .gravity = Fg,
                                  .effort = E, .mass = mass},
             X, lw, found++, out, moving, load_work);
    }
  }
  return found;
}

phm_status phm_static_free(const phm_model *m, const double *poses, double time, int nmax,
                           phm_free_motion *out, unsigned char *moving, double *load_work,
                           int *nfound, phm_error *err) {
  phm_error_clear(err);
  if (!m || !nfound || (nmax > 0 && !out)) return PHM_FAIL(err, PHM_EINVAL, "phm_static_free: NULL argument");
  *nfound = 0;
  int nc = m->nc, nl = m->nl, found = 0;
  const double *H = poses ? poses : NULL;
  hold_t G;
  search_t S = {.m = m, .G = &G, .time = time, .tref = phm_model_tref(m, time, NULL)};
  double *H0 = NULL, *lw = malloc(sizeof(double) * (size_t)(nl + 1));
  phm_status st = hold_build(m, &G, err);
  if (st) goto done;
  if (!H) {
    H0 = malloc(sizeof(double) * 16 * (size_t)nc);
    if (!H0) goto oom;
    for (int c = 0; c < nc; c++) memcpy(H0 + 16 * c, m->car[c].H0, sizeof(double) * 16);
    H = H0;
  }
  S.H = H;
  size_t n6 = 6 * (size_t)nc;
  S.wr = malloc(sizeof(double) * n6);
  S.wt = malloc(sizeof(double) * n6);
  S.wg = calloc(n6, sizeof(double));
  S.wl = calloc(6 * (size_t)(nl + 1), sizeof(double));
  S.sl = calloc((size_t)nl + 1, sizeof(double));
  S.eff = calloc((size_t)m->nj + 1, sizeof(double));
  S.et = calloc((size_t)m->nj + 1, sizeof(double));
  S.g0 = calloc((size_t)m->ncons + 1, sizeof(double));
  S.gt = calloc((size_t)m->ncons + 1, sizeof(double));
  S.Ht = malloc(sizeof(double) * 16 * (size_t)nc);
  if (!lw || !S.wr || !S.wt || !S.wg || !S.wl || !S.sl || !S.eff || !S.et || !S.g0 || !S.gt || !S.Ht)
    goto oom;
  phm_applied_pairs(m, NULL, H, NULL, NULL, time, S.tref, 1.0, S.wr, NULL, NULL, NULL, NULL, S.eff);
  if (m->ncons) phm_constraints_dense(m, H, NULL, time, S.tref, S.g0, NULL, NULL);
  for (int c = 0; c < nc; c++) phm_gravity_tangent(m, c, H + 16 * c, 1.0, S.wg + 6 * c, NULL);
  for (int il = 0; il < nl; il++) {
    double wre[6];
    S.sl[il] = phm_law_eval(&m->load[il].law, time, S.tref, NULL, NULL);
    phm_load_wrench(m, il, H, S.sl[il], NULL, S.wl + 6 * il, wre);
  }
  found = free_parts(&S, found, nmax, lw, out, moving, load_work);
  found = free_pairs(&S, found, nmax, lw, out, moving, load_work);
  *nfound = found;
  goto done;
oom:
  st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
done:
  hold_free(&G);
  free(H0); free(lw);
  free(S.wr); free(S.wt); free(S.wg); free(S.wl); free(S.sl); free(S.eff); free(S.et);
  free(S.g0); free(S.gt); free(S.Ht);
  return st;
}
