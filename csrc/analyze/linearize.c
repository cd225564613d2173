/* linearize.c -- linearization on the tangent space (docs/method.md section 7): the generalized
 * forces f(H) = applied + G^T lambda at poses H and their Jacobian blocks df/ddelta over the
 * carrier coupling graph (csrc/model/graph.c), all in closed form: the se3 elements', gravity's,
 * the pairs' G^T lambda and the actuators', loads' and springs' blocks (phm_element_tangent,
 * phm_gravity_tangent, phm_pair_tangent, phm_applied_tangent); read by modes (modes.c) and
 * statics (statics.c).
 * Set-up time code: allocates. */
#include "analyze.h"

#include <amd.h>
#include <ldl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"
#include "pose.h"

/* A steady rotation S (phm_model_set_spin): each carrier's motion s_c = Ad_{H_c^-1} S and its
 * momentum (M s)_c over the mass blocks into L->sp (s_c at 6 c, (M s)_c at 6 (nc + c)). */
static void spin_motion(const lin_t *L, const double *H) {
  const phm_model *m = L->m;
  double *s = L->sp, *ms = L->sp + 6 * (size_t)m->nc;
  for (int c = 0; c < m->nc; c++) {
    double Hi[16], A[36];
    phm_se3_inverse(H + 16 * c, Hi);
    phm_se3_Ad(Hi, A);
    phm_mv6(A, m->spin, s + 6 * c);
  }
  for (int c = 0; c < m->nc; c++)
    for (int i = 0; i < 6; i++) {
      double sum = 0;
      for (int q = L->ptr[c]; q < L->ptr[c + 1]; q++)
        for (int j = 0; j < 6; j++) sum += L->Mb[36 * (size_t)q + 6 * i + j] * s[6 * L->nbr[q] + j];
      ms[6 * c + i] = sum;
    }
}

/* Generalized forces at poses H: applied wrenches + G^T lambda (nc x 6, body frame), and with a
 * steady rotation the centrifugal wrenches ad*_{s_c} (M s)_c (x L->scale). */
void lin_total_force(lin_t *L, const double *H, double *f) {
  const phm_model *m = L->m;
  phm_applied_pairs(m, NULL, H, NULL, NULL, L->time, L->tref, L->scale, f, NULL, NULL, NULL, NULL,
                    NULL);
  if (L->lam && m->ncons) phm_constraint_forces(m, H, L->time, L->tref, L->lam, f);
  if (L->comps && m->ncomp) { /* at rest, their states at z0 (sp as scratch) */
    memset(L->sp, 0, sizeof(double) * 6 * (size_t)m->nc);
    phm_components_apply(m, NULL, H, NULL, NULL, NULL, NULL, L->time, L->tref, L->sp, NULL, NULL,
                         NULL, NULL, NULL);
    for (int i = 0; i < 6 * m->nc; i++) f[i] += L->scale * L->sp[i];
  }
  lin_spin_force(L, H, f);
}

void lin_spin_force(const lin_t *L, const double *H, double *f) {
  const phm_model *m = L->m;
  if (!m->has_spin) return;
  spin_motion(L, H);
  for (int c = 0; c < m->nc; c++) {
    double w[6];
    phm_ad_dual_apply(L->sp + 6 * c, L->sp + 6 * ((size_t)m->nc + c), w);
    for (int i = 0; i < 6; i++) f[6 * c + i] += L->scale * w[i];
  }
}

int lin_slot(const lin_t *L, int r, int c) {
  for (int q = L->ptr[r]; q < L->ptr[r + 1]; q++)
    if (L->nbr[q] == c) return q;
  return -1;
}

/* out = X Y (6 x 6 row-major), or out += when add. */
static void mm6(const double *X, const double *Y, double *out, int add) {
  for (int i = 0; i < 6; i++)
    for (int j = 0; j < 6; j++) {
      double t = 0;
      for (int k = 0; k < 6; k++) t += X[6 * i + k] * Y[6 * k + j];
      out[6 * i + j] = add ? out[6 * i + j] + t : t;
    }
}

/* The steady rotation's blocks at poses H (spin_motion done): with A_c = ad_{s_c}, Q_c = ad*_{s_c}
 * and P_c x = ad*_x (M s)_c, the centrifugal wrenches' stiffness (x scale) into Kb -- slot
 * (c, d): Q_c M_cd A_d, and on c's own P_c A_c with the chart factor of C_c = ad*_{s_c} (M s)_c
 * -- or (Kb NULL) the gyroscopic blocks into Gb -- slot (c, d): Q_c M_cd - M_cd A_d, and on c's
 * own P_c. */
static void spin_blocks(const lin_t *L, double scale, double *Kb, double *Gb) {
  const phm_model *m = L->m;
  const double *s = L->sp, *ms = L->sp + 6 * (size_t)m->nc;
  for (int c = 0; c < m->nc; c++) {
    double Qc[36], Pc[36], Cc[6];
    phm_se3_ad_dual(s + 6 * c, Qc);
    for (int j = 0; j < 6; j++) {
      double ej[6] = {0}, z[6];
      ej[j] = 1.0;
      phm_ad_dual_apply(ej, ms + 6 * c, z);
      for (int i = 0; i < 6; i++) Pc[6 * i + j] = z[i];
    }
    phm_ad_dual_apply(s + 6 * c, ms + 6 * c, Cc);
    for (int q = L->ptr[c]; q < L->ptr[c + 1]; q++) {
      int d = L->nbr[q];
      const double *Mq = L->Mb + 36 * (size_t)q;
      double Ad[36], T[36], U[36];
      phm_se3_ad(s + 6 * d, Ad);
      mm6(Qc, Mq, T, 0);                  /* Q_c M_cd */
      if (Kb) {
        mm6(T, Ad, U, 0);                 /* Q_c M_cd A_d */
        if (d == c) mm6(Pc, Ad, U, 1);    /* + P_c A_c */
        for (int i = 0; i < 36; i++) Kb[36 * (size_t)q + i] += scale * U[i];
        if (d == c) {
          double w[6];
          for (int i = 0; i < 6; i++) w[i] = scale * Cc[i];
          lin_add_own_block(Kb + 36 * (size_t)q, NULL, 0, w);
        }
      } else {
        mm6(Mq, Ad, U, 0);                /* M_cd A_d */
        for (int i = 0; i < 36; i++) Gb[36 * (size_t)q + i] = T[i] - U[i] + (d == c ? Pc[i] : 0.0);
      }
    }
  }
}

void lin_gyro_blocks(const lin_t *L, const double *H, double *Gb) {
  memset(Gb, 0, sizeof(double) * 36 * (size_t)L->ptr[L->m->nc]);
  if (!L->m->has_spin) return;
  spin_motion(L, H);
  spin_blocks(L, 1.0, NULL, Gb);
}

/* K += dw/ddelta (6 x 6) - 1/2 ad*_(.) w: a carrier's own block of f_c(delta) =
 * dexp_{-delta}^T w_c(H_c exp(delta)) for a wrench w (with its derivative Kw, NULL: none). */
void lin_add_own_block(double *K, const double *Kw, int ldk, const double w[6]) {
  for (int j = 0; j < 6; j++) {
    double ej[6] = {0}, z[6];
    ej[j] = 1.0;
    phm_ad_dual_apply(ej, w, z);
    for (int i = 0; i < 6; i++) K[6 * i + j] += (Kw ? Kw[ldk * i + j] : 0.0) - 0.5 * z[i];
  }
}

/* One component's blocks (phm_tangent_sink) into Kb (d f/d delta: Kx, with f_c's chart factor
 * dexp_{-delta}^T, whose derivative is -1/2 ad*_(.) w_c, on the diagonal blocks; if not NULL)
 * and Db (d f/d t: Kt; if not NULL). */
typedef struct {
  const lin_t *L;
  double *Kb, *Db;
} lin_sink;
static void add_lin_tangent(void *ctx, int ca, int cb, const double w[12], const double Kx[144],
                            const double Kt[144]) {
  lin_sink *s = ctx;
  int cr[2] = {ca, cb};
  for (int bi = 0; bi < 2; bi++)
    for (int bj = 0; bj < 2; bj++) {
      if (cr[bi] < 0 || cr[bj] < 0) continue;
      int q = lin_slot(s->L, cr[bi], cr[bj]);
      if (q < 0) continue;
      const double *kx = Kx + 12 * 6 * bi + 6 * bj;
      if (s->Db && Kt)
        for (int i = 0; i < 6; i++)
          for (int j = 0; j < 6; j++) s->Db[36 * (size_t)q + 6 * i + j] += Kt[12 * (6 * bi + i) + 6 * bj + j];
      if (!s->Kb) continue;
      double *K = s->Kb + 36 * (size_t)q;
      if (bi == bj) lin_add_own_block(K, kx, 12, w + 6 * bi);
      else
        for (int i = 0; i < 6; i++)
          for (int j = 0; j < 6; j++) K[6 * i + j] += kx[12 * i + j];
    }
}

/* Add the blocks at poses H (at rest), all in closed form -- the se3 elements'
 * (phm_element_tangent), gravity's (phm_gravity_tangent, x L->scale), the pairs' constraint
 * wrenches G^T L->lam (phm_pair_tangent: their geometric stiffness) and the actuators', loads'
 * and springs' (phm_applied_tangent) -- to Kb (if not NULL; d f/d delta, with f_c's chart factor
 * dexp_{-delta}^T: its derivative -1/2 ad*_(.) w_c on the diagonal blocks) and, if Db is not
 * NULL, their derivatives in the twists to Db (d f/d t: the damping, the same at any twist since
 * the wrenches are affine in them). */
void lin_closed_form_blocks(const lin_t *L, const double *H, double *Kb, double *Db) {
  const phm_model *m = L->m;
  static const double zero[6] = {0};
  lin_sink sink = {L, Kb, Db};
  for (int ie = 0; ie < m->ne; ie++) {
    const phm_element_desc *e = &m->el[ie];
    double w[12], Kx[144], Ct[144];
    phm_element_tangent(e, H + 16 * e->a, H + 16 * e->b, zero, zero, w, w + 6, Kx, Db ? Ct : NULL);
    add_lin_tangent(&sink, e->a, e->b, w, Kx, Db ? Ct : NULL);
  }
  phm_applied_tangent(m, NULL, H, NULL, NULL, L->time, L->tref, L->scale, add_lin_tangent, &sink);
  if (!Kb) return;
  if (m->has_spin) {
    spin_motion(L, H);
    spin_blocks(L, L->scale, Kb, NULL);
  }
  for (int ic = 0; L->comps && ic < m->ncomp; ic++) { /* statics: the components at rest */
    const phm_component_desc *c = &m->comp[ic];
    int sp = c->kind == PHM_COMP_LINEAR && c->spair >= 0 ? c->spair : c->pair;
    int ab[2] = {m->pair[c->pair].a, m->pair[c->pair].b}, cs[2] = {m->pair[sp].a, m->pair[sp].b};
    double w[12], Ku[144], B[12], gq[12], gt[12], Kz[12 * PHM_COMP_MAXZ], Fx[12 * PHM_COMP_MAXZ];
    double Ft[12 * PHM_COMP_MAXZ], Fz[PHM_COMP_MAXZ * PHM_COMP_MAXZ];
    phm_component_tangent(m, ic, NULL, H, NULL, NULL, NULL, L->time, L->tref, w, Ku, B, gq, gt, Kz,
                          Fx, Ft, Fz);
    for (int i = 0; i < 12; i++) w[i] *= L->scale;
    for (int i = 0; i < 144; i++) Ku[i] *= L->scale;
    add_lin_tangent(&sink, ab[0], ab[1], w, Ku, NULL); /* B u at fixed u, with the charts */
    for (int r = 0; r < 2; r++) /* B du/d[delta] of the measured carriers */
      for (int q = 0; q < 2; q++) {
        int slot = ab[r] >= 0 && cs[q] >= 0 ? lin_slot(L, ab[r], cs[q]) : -1;
        if (slot < 0) continue;
        for (int i = 0; i < 6; i++)
          for (int j = 0; j < 6; j++) Kb[36 * (size_t)slot + 6 * i + j] += L->scale * B[6 * r + i] * gq[6 * q + j];
      }
  }
  double gn = fabs(m->gravity[0]) + fabs(m->gravity[1]) + fabs(m->gravity[2]);
  for (int c = 0; gn > 0 && c < m->nc; c++) {
    double w[6], Kg[36];
    phm_gravity_tangent(m, c, H + 16 * c, L->scale, w, Kg);
    lin_add_own_block(Kb + 36 * (size_t)lin_slot(L, c, c), Kg, 6, w);
  }
  for (int ip = 0; L->lam && ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    const double *lam = L->lam + m->pair_row[ip];
    phm_pair_data pd;
    double Kl[144], w[12] = {0};
    phm_pair_tangent(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                     NULL, NULL, NULL, L->time, L->tref, lam, NULL, NULL, &pd, NULL, NULL, NULL, NULL,
                     Kl, NULL, NULL);
    for (int r = 0; r < m->pair_m[ip]; r++) /* the wrenches G_a^T lam, G_b^T lam */
      for (int j = 0; j < 6; j++) {
        w[j] += pd.Ga[6 * r + j] * lam[r];
        w[6 + j] += pd.Gb[6 * r + j] * lam[r];
      }
    add_lin_tangent(&sink, pr->a, pr->b, w, Kl, NULL);
  }
}

phm_status lin_alloc(lin_t *L, const phm_model *m, phm_error *err) {
  (void)err;
  L->m = m;
  return PHM_OK;
}
void lin_free(lin_t *L) {
  free(L->ptr);
  free(L->nbr);
  free(L->Kb);
  free(L->Mb);
  free(L->sp);
}

/* The coupling graph of L's model and room for the force Jacobian blocks. */
phm_status lin_graph(lin_t *L, phm_error *err) {
  const phm_model *m = L->m;
  phm_status st = phm_carrier_graph(m, 0, &L->ptr, &L->nbr, err);
  if (st) return st;
  L->Kb = calloc(36 * (size_t)L->ptr[m->nc] + 1, sizeof(double));
  L->Mb = calloc(36 * (size_t)L->ptr[m->nc] + 1, sizeof(double));
  L->sp = calloc(12 * (size_t)m->nc + 1, sizeof(double));
  if (!L->Kb || !L->Mb || !L->sp) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  for (int c = 0; c < m->nc; c++) {
    int q = lin_slot(L, c, c);
    if (q < 0) return PHM_FAIL(err, PHM_EINVAL, "carrier graph: carrier %d has no diagonal slot", c);
    memcpy(L->Mb + 36 * (size_t)q, m->car[c].M, 36 * sizeof(double));
  }
  for (int k = 0; k < m->nmc; k++) { /* an element's coupling: its nodes are neighbours */
    const int ca = m->mc_a[k], cb = m->mc_b[k];
    const double *Mc = m->mc + 144 * (size_t)k;
    int ab[2] = {ca, cb};
    for (int bi = 0; bi < 2; bi++)
      for (int bj = 0; bj < 2; bj++) {
        int q = lin_slot(L, ab[bi], ab[bj]);
        if (q < 0) return PHM_FAIL(err, PHM_EINVAL, "carrier graph: mass coupling %d's carriers are not neighbours", k);
        for (int i = 0; i < 6; i++)
          for (int j = 0; j < 6; j++) L->Mb[36 * (size_t)q + 6 * i + j] += Mc[12 * (6 * bi + i) + 6 * bj + j];
      }
  }
  return PHM_OK;
}

/* Kb[q] = d f_r / d delta_c for block q = (row carrier r, column carrier nbr[q]) of the coupling
 * graph (6 x 6, row-major), f = lin_total_force on the perturbed carriers' charts, f_c(delta) =
 * dexp_{-delta}^T w_c(H_c exp(delta)), in closed form (lin_closed_form_blocks). Into L->Kb. */
void lin_force_jacobian_blocks(lin_t *L, const double *H) {
  memset(L->Kb, 0, sizeof(double) * 36 * (size_t)L->ptr[L->m->nc]);
  lin_closed_form_blocks(L, H, L->Kb, NULL);
}

void lin_kkt_free(lin_kkt_t *S) {
  if (S->num) klu_free_numeric(&S->num, &S->common);
  if (S->sym) klu_free_symbolic(&S->sym, &S->common);
  free(S->Ap); free(S->Ai); free(S->src); free(S->Ax);
}

static int cmp_int(const void *a, const void *b) { return (*(const int *)a > *(const int *)b) - (*(const int *)a < *(const int *)b); }

phm_status lin_kkt_build(lin_kkt_t *S, const lin_t *L, phm_error *err) {
  const phm_model *m = L->m;
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk;
  const int *ptr = L->ptr, *nbr = L->nbr;
  memset(S, 0, sizeof *S);
  klu_defaults(&S->common);
  S->n = N;
  /* entries: force blocks 36 per graph slot, G and G^T: 2 x 6 per row and carrier of its pair */
  size_t cap = 36 * (size_t)ptr[nc] + 12 * 2 * (size_t)nk + 1;
  S->Ap = malloc(sizeof(int) * (size_t)(N + 1));
  S->Ai = malloc(sizeof(int) * cap);
  S->src = malloc(sizeof(int) * cap);
  S->Ax = malloc(sizeof(double) * cap);
  int *rows = malloc(sizeof(int) * (size_t)(ptr[nc] + 1));
  if (!S->Ap || !S->Ai || !S->src || !S->Ax || !rows) {
    free(rows);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
  int k = 0;
  for (int c = 0; c < nc; c++) {
    int deg = ptr[c + 1] - ptr[c];
    memcpy(rows, nbr + ptr[c], sizeof(int) * (size_t)deg); /* the graph is symmetric */
    qsort(rows, (size_t)deg, sizeof(int), cmp_int);
    for (int j = 0; j < 6; j++) {
      S->Ap[6 * c + j] = k;
      for (int t = 0; t < deg; t++) {
        int r = rows[t], q = ptr[r];
        while (nbr[q] != c) q++; /* block (row r, column c) in r's list */
        for (int i = 0; i < 6; i++) {
          S->Ai[k] = 6 * r + i;
          S->src[k++] = 36 * q + 6 * i + j;
        }
      }
      for (int ip = 0; ip < m->np; ip++) /* pairs in order: their rows ascend */
        if (m->pair[ip].a == c || m->pair[ip].b == c)
          for (int rr = 0; rr < m->pair_m[ip]; rr++) {
            int r = m->pair_row[ip] + rr;
            S->Ai[k] = n6 + r;
            S->src[k++] = -(12 * r + 6 * (m->pair[ip].b == c) + j) - 1;
          }
    }
  }
  for (int ip = 0; ip < m->np; ip++)
    for (int rr = 0; rr < m->pair_m[ip]; rr++) {
      int r = m->pair_row[ip] + rr, a = m->pair[ip].a, b = m->pair[ip].b;
      int lo = a < b ? a : b, hi = a < b ? b : a;
      S->Ap[n6 + r] = k;
      for (int side = 0; side < 2; side++) {
        int c = side ? hi : lo;
        if (c < 0) continue;
        for (int i = 0; i < 6; i++) {
          S->Ai[k] = 6 * c + i;
          S->src[k++] = -(12 * r + 6 * (b == c) + i) - 1;
        }
      }
    }
  S->Ap[N] = k;
  free(rows);
  S->sym = klu_analyze(N, S->Ap, S->Ai, &S->common);
  if (!S->sym) return PHM_FAIL(err, PHM_ESOLVER, "static equilibrium: KLU analysis failed (status %d)", S->common.status);
  return PHM_OK;
}

/* The pairs' constraint Jacobian blocks at poses H: row r of pair ip holds G_a in Gp[12 r ..] and
 * G_b in Gp[12 r + 6 ..] (O(N) storage and work; a dense G would be O(N^2)). */
void lin_constraint_blocks(const lin_t *L, const double *H, double *Gp) {
  const phm_model *m = L->m;
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    double Ga[6 * PHM_MAXCON], Gb[6 * PHM_MAXCON];
    phm_pair_eval(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                  NULL, L->time, L->tref, NULL, Ga, Gb, NULL);
    for (int rr = 0; rr < m->pair_m[ip]; rr++) {
      double *row = Gp + 12 * (m->pair_row[ip] + rr);
      memcpy(row, Ga + 6 * rr, 6 * sizeof(double));
      memcpy(row + 6, Gb + 6 * rr, 6 * sizeof(double));
    }
  }
}

void lin_kkt_values(lin_kkt_t *S, const double *Kb, const double *Gp) {
  for (int k = 0; k < S->Ap[S->n]; k++) S->Ax[k] = S->src[k] >= 0 ? Kb[S->src[k]] : Gp[-S->src[k] - 1];
}

void lin_kkt_equilibrate(lin_kkt_t *S, double *sc, double *work) {
  int n = S->n;
  for (int i = 0; i < n; i++) sc[i] = 1.0;
  for (int it = 0; it < 3; it++) {
    for (int i = 0; i < n; i++) work[i] = 0;
    for (int j = 0; j < n; j++)
      for (int p = S->Ap[j]; p < S->Ap[j + 1]; p++) work[j] = fmax(work[j], fabs(S->Ax[p]));
    for (int i = 0; i < n; i++) work[i] = work[i] > 0 && isfinite(work[i]) ? 1.0 / sqrt(work[i]) : 1.0;
    for (int j = 0; j < n; j++)
      for (int p = S->Ap[j]; p < S->Ap[j + 1]; p++) S->Ax[p] *= work[j] * work[S->Ai[p]];
    for (int i = 0; i < n; i++) sc[i] *= work[i];
  }
}

int lin_kkt_factor(lin_kkt_t *S, const double *Kb, const double *Gp) {
  lin_kkt_values(S, Kb, Gp);
  return lin_kkt_refactor(S);
}

int lin_kkt_refactor(lin_kkt_t *S) {
  if (S->num) klu_free_numeric(&S->num, &S->common);
  S->num = klu_factor(S->Ap, S->Ai, S->Ax, S->sym, &S->common);
  return !S->num || S->common.status != KLU_OK;
}

int lin_kkt_solve(lin_kkt_t *S, double *x) { return !klu_solve(S->sym, S->num, S->n, 1, x, &S->common); }

/* ---------------------------------------------------------------- the KKT matrix's inertia */
void lin_ldl_free(lin_ldl_t *F) {
  free(F->P); free(F->Pinv); free(F->Lp); free(F->Parent); free(F->Lnz); free(F->Li);
  free(F->Flag); free(F->Pattern); free(F->Lx); free(F->D); free(F->Y);
  free(F->Rp); free(F->Rj); free(F->Rx); free(F->cs);
  memset(F, 0, sizeof *F);
}

phm_status lin_ldl_analyze(lin_ldl_t *F, const lin_t *L, const lin_kkt_t *S, phm_error *err) {
  const phm_model *m = L->m;
  int nc = m->nc, n6 = 6 * nc, N = S->n;
  memset(F, 0, sizeof *F);
  F->n = N;
  int *order = malloc(sizeof(int) * (size_t)(nc + 1)), *pos = malloc(sizeof(int) * (size_t)(nc + 1));
  int *head = malloc(sizeof(int) * (size_t)(nc + 1));
  int *next = malloc(sizeof(int) * (size_t)(m->np + 1));
  F->P = malloc(sizeof(int) * (size_t)N);
  F->Pinv = malloc(sizeof(int) * (size_t)N);
  F->Lp = malloc(sizeof(int) * (size_t)(N + 1));
  F->Parent = malloc(sizeof(int) * (size_t)N);
  F->Lnz = malloc(sizeof(int) * (size_t)N);
  F->Flag = malloc(sizeof(int) * (size_t)N);
  F->Pattern = malloc(sizeof(int) * (size_t)N);
  F->D = malloc(sizeof(double) * (size_t)N);
  F->Y = calloc((size_t)N, sizeof(double));
  phm_status st = PHM_OK;
  if (!order || !pos || !head || !next || !F->P || !F->Pinv || !F->Lp || !F->Parent ||
      !F->Lnz || !F->Flag || !F->Pattern || !F->D || !F->Y) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  /* the carriers in AMD order of their graph (which holds the pairs' edges) */
  double info[AMD_INFO];
  int a = amd_order(nc, L->ptr, L->nbr, order, NULL, info);
  if (a != AMD_OK && a != AMD_OK_BUT_JUMBLED) {
    st = PHM_FAIL(err, a == AMD_OUT_OF_MEMORY ? PHM_ENOMEM : PHM_ESOLVER, "modes: AMD ordering failed (status %d)", a);
    goto done;
  }
  for (int k = 0; k < nc; k++) { pos[order[k]] = k; head[k] = -1; }
  /* each pair's rows after the later of its carriers (pairs bucketed by that carrier, in order) */
  for (int ip = m->np - 1; ip >= 0; ip--) {
    int pa = m->pair[ip].a, pb = m->pair[ip].b;
    int c = pa < 0 ? pb : pb < 0 ? pa : pos[pa] > pos[pb] ? pa : pb;
    next[ip] = head[c];
    head[c] = ip;
  }
  int k = 0;
  for (int t = 0; t < nc; t++) {
    int c = order[t];
    for (int i = 0; i < 6; i++) F->P[k++] = 6 * c + i;
    for (int ip = head[c]; ip >= 0; ip = next[ip])
      for (int r = 0; r < m->pair_m[ip]; r++) F->P[k++] = n6 + m->pair_row[ip] + r;
  }
  if (k != N) {
    st = PHM_FAIL(err, PHM_ESOLVER, "modes: KKT ordering covers %d of %d unknowns", k, N);
    goto done;
  }
  ldl_symbolic(N, S->Ap, S->Ai, F->Lp, F->Parent, F->Lnz, F->Flag, F->P, F->Pinv);
  size_t nnz = (size_t)F->Lp[N] + 1;
  F->Li = malloc(sizeof(int) * nnz);
  F->Lx = malloc(sizeof(double) * nnz);
  F->Rj = malloc(sizeof(int) * nnz);
  F->Rx = malloc(sizeof(double) * nnz);
  F->Rp = malloc(sizeof(int) * (size_t)(N + 1));
  F->cs = malloc(sizeof(double) * (size_t)N);
  if (!F->Li || !F->Lx || !F->Rj || !F->Rx || !F->Rp || !F->cs) st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
done:
  free(order); free(pos); free(head); free(next);
  return st;
}

int lin_ldl_negative(lin_ldl_t *F, lin_kkt_t *S, double *check) {
  int N = F->n;
  *check = INFINITY;
  if (ldl_numeric(N, S->Ap, S->Ai, S->Ax, F->Lp, F->Parent, F->Lnz, F->Li, F->Lx, F->D, F->Y,
                  F->Pattern, F->Flag, F->P, F->Pinv) != N)
    return -1;
  int neg = 0;
  for (int k = 0; k < N; k++) neg += F->D[k] < 0;
  /* ||E||_1 column by column in permuted indices: column k of L D L^T on and below the
   * diagonal is the sum over the nonzeros L(k, j), j <= k (L(k, k) = 1), of d_j L(k, j) L(i, j),
   * i >= k; E's lower triangle gives the column sums of |E| (symmetric). Row k of L from the
   * transpose (rp, rj, rx); w: the dense column, touched: its nonzeros. */
  double *w = F->Y, *rx = F->Rx, *cs = F->cs;
  int nnz = F->Lp[N], *rp = F->Rp, *rj = F->Rj, *touched = F->Pattern, *mark = F->Flag;
  memset(cs, 0, sizeof(double) * (size_t)N);
  memset(rp, 0, sizeof(int) * (size_t)(N + 1));
  for (int p = 0; p < nnz; p++) rp[F->Li[p] + 1]++;
  for (int i = 0; i < N; i++) rp[i + 1] += rp[i];
  for (int j = 0; j < N; j++)
    for (int p = F->Lp[j]; p < F->Lp[j] + F->Lnz[j]; p++) {
      int q = rp[F->Li[p]]++;
      rj[q] = j;
      rx[q] = F->Lx[p];
    }
  for (int i = N; i > 0; i--) rp[i] = rp[i - 1];
  rp[0] = 0;
  for (int i = 0; i < N; i++) { w[i] = 0; mark[i] = -1; }
  for (int k = 0; k < N; k++) {
    int nt = 0;
    /* + P A P^T (i >= k): column P[k] of A, rows Pinv[.] */
    for (int p = S->Ap[F->P[k]]; p < S->Ap[F->P[k] + 1]; p++) {
      int i = F->Pinv[S->Ai[p]];
      if (i < k) continue;
      if (mark[i] != k) { mark[i] = k; touched[nt++] = i; }
      w[i] += S->Ax[p];
    }
    /* - L D L^T (i >= k) */
    for (int t = rp[k]; t <= rp[k + 1]; t++) {
      int j = t < rp[k + 1] ? rj[t] : k;
      double c = F->D[j] * (t < rp[k + 1] ? rx[t] : 1.0);
      if (j == k) {
        if (mark[k] != k) { mark[k] = k; touched[nt++] = k; }
        w[k] -= c;
      }
      for (int p = F->Lp[j]; p < F->Lp[j] + F->Lnz[j]; p++) {
        int i = F->Li[p];
        if (i < k) continue;
        if (mark[i] != k) { mark[i] = k; touched[nt++] = i; }
        w[i] -= c * F->Lx[p];
      }
    }
    for (int t = 0; t < nt; t++) {
      int i = touched[t];
      double e = fabs(w[i]);
      cs[k] += e;
      if (i != k) cs[i] += e;
      w[i] = 0;
    }
  }
  double enorm = 0;
  for (int i = 0; i < N; i++) enorm = fmax(enorm, cs[i]);
  /* est ||KKT^-1||_1 = condest / ||KKT||_1 (KLU's estimate on S's factors) */
  double anorm = 0;
  for (int j = 0; j < N; j++) {
    double s = 0;
    for (int p = S->Ap[j]; p < S->Ap[j + 1]; p++) s += fabs(S->Ax[p]);
    anorm = fmax(anorm, s);
  }
  if (S->num && klu_condest(S->Ap, S->Ax, S->sym, S->num, &S->common) && anorm > 0)
    *check = enorm * S->common.condest / anorm;
  return neg;
}
