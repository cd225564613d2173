/* jacobian.c -- the Jacobian dF/dy + cj dF/dy' of the DAE: its sparsity pattern from the block
 * structure (carriers couple through elements, pairs, springs and loads; a pair's multipliers
 * and joint coordinates through its two carriers: the coupling graph of csrc/model/graph.c), a
 * values, all in closed form: the carriers' own terms, the se3 elements', gravity's, the pairs'
 * (rows, G^T lambda, G^T mu) and the other applied wrenches' (actuators, loads, springs). */
#include "dae.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "linalg.h"
#include "phm_check.h"
#include "pose.h"

/* The rows of a column of block b, ascending, into rows (NULL: only count them): the states of
 * the blocks coupled to b (nb: b's coupling-graph neighbours sorted ascending, nnb of them). A
 * carrier's states come first (they precede the joint coordinates), then the pairs' joint
 * coordinates, multipliers lambda and mu, each range in pair order. A pair's own rows hold its
 * multipliers' diagonal (the regularization, dae_regularization), with or without joint
 * coordinates. */
static int block_rows(const dae_t *d, const int *nb, int nnb, sunindextype *rows) {
  const phm_model *m = d->m;
  int nc = m->nc, cnt = 0, q = 0;
  for (; q < nnb && nb[q] < nc; q++) {
    if (rows)
      for (int i = 0; i < PHM_NSTATE; i++) rows[cnt + i] = PHM_NSTATE * nb[q] + i;
    cnt += PHM_NSTATE;
  }
  int q0 = q;
  for (int part = 0; part < 4; part++) /* joints, components' states, lambda, mu */
    for (q = q0; q < nnb; q++) {
      int ip = nb[q] - nc, first, len;
      if (part == 0) first = d->ix + m->pair_j[ip], len = m->pair_k[ip];
      else if (part == 1) first = d->iz + m->pair_z[ip], len = m->pair_nz[ip];
      else first = (part == 2 ? d->il : d->im) + m->pair_row[ip], len = m->pair_m[ip];
      if (rows)
        for (int i = 0; i < len; i++) rows[cnt + i] = first + i;
      cnt += len;
    }
  return cnt;
}

/* The blocks of the state: carrier c's 13 states form block c; pair ip's joint coordinates,
 * lambda and mu form block nc + ip; the ledger belongs to none (no row depends on it). A
 * state's column couples to the rows of the blocks next to its block in the coupling graph of
 * carriers and pairs (csrc/model/graph.c); the ledger rows keep only their diagonal (their
 * dependence on the other states is left out of the Newton matrix: nothing else depends on
 * them, so this only delays their convergence by one iteration). */
phm_status dae_jacobian_pattern(dae_t *d, phm_error *err) {
  if (d->pl) return dae_planar_pattern(d, err);
  const phm_model *m = d->m;
  int n = d->n, nc = m->nc, nb = nc + m->np;
  int *ptr = NULL, *nbr = NULL, *srt = NULL, *fill = NULL, *blk = NULL;
  phm_status st = phm_carrier_graph(m, 1, &ptr, &nbr, err);
  if (st) return st;
  free(d->colptr);
  free(d->rowind);
  free(d->nzkeep);
  d->rowind = NULL;
  d->nzkeep = NULL;
  d->nzcnt = -1;
  srt = malloc(sizeof(int) * (size_t)(ptr[nb] + 1));
  fill = malloc(sizeof(int) * (size_t)(nb + 1));
  blk = malloc(sizeof(int) * (size_t)(n + 1));
  d->colptr = malloc(sizeof(sunindextype) * (size_t)(n + 1));
  if (!srt || !fill || !blk || !d->colptr) goto oom;
  /* every neighbour list in ascending order: the graph is symmetric, so listing v in the lists
   * of its neighbours for v = 0, 1, ... sorts them (one pass, no comparison sort) */
  for (int v = 0; v < nb; v++) fill[v] = ptr[v];
  for (int v = 0; v < nb; v++)
    for (int q = ptr[v]; q < ptr[v + 1]; q++) srt[fill[nbr[q]]++] = v;
  for (int i = 0; i < n; i++) blk[i] = -1; /* the ledger */
  for (int i = 0; i < d->ix; i++) blk[i] = i / PHM_NSTATE;
  for (int ip = 0; ip < m->np; ip++) {
    for (int c = 0; c < m->pair_k[ip]; c++) blk[d->ix + m->pair_j[ip] + c] = nc + ip;
    for (int c = 0; c < m->pair_nz[ip]; c++) blk[d->iz + m->pair_z[ip] + c] = nc + ip;
    for (int r = 0; r < m->pair_m[ip]; r++)
      blk[d->il + m->pair_row[ip] + r] = blk[d->im + m->pair_row[ip] + r] = nc + ip;
  }
  long nnz = 0;
  for (int j = 0; j < n; j++) {
    int bj = blk[j];
    nnz += bj < 0 ? 1 : block_rows(d, srt + ptr[bj], ptr[bj + 1] - ptr[bj], NULL);
  }
  if (nnz > 2147483647L) {
    st = PHM_FAIL(err, PHM_EINVAL, "the Jacobian has %ld nonzeros, more than KLU's int indices hold", nnz);
    goto fail;
  }
  d->nnz = (int)nnz;
  d->rowind = malloc(sizeof(sunindextype) * (size_t)(nnz + 1));
  d->nzkeep = calloc((size_t)(nnz + 1), 1);
  if (!d->rowind || !d->nzkeep) goto oom;
  long k = 0;
  for (int j = 0; j < n; j++) {
    d->colptr[j] = k;
    int bj = blk[j];
    if (bj < 0) d->rowind[k++] = j;
    else k += block_rows(d, srt + ptr[bj], ptr[bj + 1] - ptr[bj], d->rowind + k);
  }
  d->colptr[n] = k;
  goto done;
oom:
  st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
fail:
  free(d->colptr);
  free(d->rowind);
  free(d->nzkeep);
  d->colptr = d->rowind = NULL;
  d->nzkeep = NULL;
done:
  free(ptr);
  free(nbr);
  free(srt);
  free(fill);
  free(blk);
  return st;
}

/* The position of entry (row, col) in the pattern, -1 if it is not there (binary search: each
 * column's rows ascend). */
static sunindextype entry(const dae_t *d, int row, int col) {
  sunindextype lo = d->colptr[col], hi = d->colptr[col + 1] - 1;
  while (lo <= hi) {
    sunindextype mid = lo + (hi - lo) / 2;
    if (d->rowind[mid] == row) return mid;
    if (d->rowind[mid] < row) lo = mid + 1;
    else hi = mid - 1;
  }
  return -1;
}

/* val[(r0 + i, c0 + j)] += B[ldb i + j] for i < nr, j < ncl: a block inside one carrier's rows,
 * which are consecutive in every column that holds them. */
static void add_block(const dae_t *d, double *val, int r0, int nr, int c0, int ncl,
                      const double *B, int ldb) {
  for (int j = 0; j < ncl; j++) {
    sunindextype k = entry(d, r0, c0 + j);
    if (k < 0) continue; /* not reached: the pattern holds every carrier block it is given */
    for (int i = 0; i < nr; i++) val[k + i] += B[ldb * i + j];
  }
}

/* dxi/dq (3 x 4): the body rotation of a change dq of the (not necessarily unit) quaternion q,
 * dw = 2 vec(conj(q) (x) dq)/|q|^2 (phm_quat_to_rot normalizes q). */
static void quat_chart(const double q[4], double E[12]) {
  double s = 2.0 / (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  double Ev[12] = {-q[1], q[0], q[3], -q[2], -q[2], -q[3], q[0], q[1], -q[3], q[2], -q[1], q[0]};
  for (int i = 0; i < 12; i++) E[i] = s * Ev[i];
}

/* out (rows x 7, leading dimension ldo) = sign K [E 0; 0 R^T]: a derivative K (rows x 6, leading
 * dimension ldk) in the body perturbation of a carrier, carried to its states (q, p) through the
 * chart (E = quat_chart(q), R its pose's rotation, Hc). */
static void to_chart(const double *K, int ldk, int rows, const double E[12], const double *Hc,
                     double sign, double *out, int ldo) {
  for (int i = 0; i < rows; i++) {
    const double *k = K + ldk * i;
    double *b = out + ldo * i;
    for (int j = 0; j < 4; j++) b[j] = sign * (k[0] * E[j] + k[1] * E[4 + j] + k[2] * E[8 + j]);
    for (int j = 0; j < 3; j++) /* R^T: (R^T)_{l j} = R_{j l} */
      b[4 + j] = sign * (k[3] * Hc[4 * j] + k[4] * Hc[4 * j + 1] + k[5] * Hc[4 * j + 2]);
  }
}

/* Jw (4 x 3) = d/dw of q' - 1/2 q (x) (0, w): the quaternion rows' derivative in the angular
 * velocity they integrate (t's or G^T mu's). */
static void quat_rate(const double q[4], double Jw[12]) {
  double J[12] = {.5 * q[1], .5 * q[2], .5 * q[3],   -.5 * q[0], .5 * q[3], -.5 * q[2],
                  -.5 * q[3], -.5 * q[0], .5 * q[1], .5 * q[2], -.5 * q[1], -.5 * q[0]};
  memcpy(Jw, J, sizeof J);
}

/* kin (7 x 6): the kinematic rows' derivative in the twist correction (dw, dv) = (G^T mu)_c of
 * carrier c (quaternion q, pose Hc): [Jw 0; 0 -R] for q' = 1/2 q (x) (0, w + dw) and p' =
 * R (v + dv); in the body frame (body != 0, dae_body_kinematics) the constant [0; -I 0; 0 -I]. */
static void kin_rate(int body, const double q[4], const double *Hc, double kin[42]) {
  memset(kin, 0, sizeof(double) * 42);
  if (body) {
    for (int i = 0; i < 6; i++) kin[6 * (1 + i) + i] = -1.0;
    return;
  }
  double Jw[12];
  quat_rate(q, Jw);
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 3; j++) kin[6 * i + j] = Jw[3 * i + j];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) kin[6 * (4 + i) + 3 + j] = -Hc[4 * i + j];
}

/* Carrier c's body-frame kinematic rows (dae_body_kinematics) in its own states, into the block
 * B (13 x 13, row-major): 2 conj(q) (x) q' / |q|^2 - (0, w) and R^T p' - v. With P = conj(q)
 * (x) q' (bilinear) and s2 = 2 / |q|^2: d/dq = s2 dP/dq - s2^2 P q^T, d/dq' = s2 conj(q) (x)
 * (times cj), d/dw = -I; d(R^T p') = hat(R^T p') dtheta (R -> R exp(hat dtheta)) through the
 * chart E, cj R^T on p', -I on v. G^T mu's part is jacobian_pairs'. */
static void body_kinematics_block(const double q[4], const double a[7], const double *Hc,
                                  const double E[12], double cj, double *B) {
  double s2 = 2.0 / (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  double P[4] = {q[0] * a[0] + q[1] * a[1] + q[2] * a[2] + q[3] * a[3],
                 q[0] * a[1] - q[1] * a[0] - q[2] * a[3] + q[3] * a[2],
                 q[0] * a[2] - q[2] * a[0] - q[3] * a[1] + q[1] * a[3],
                 q[0] * a[3] - q[3] * a[0] - q[1] * a[2] + q[2] * a[1]};
  double dP[16] = {a[0], a[1], a[2], a[3],    a[1], -a[0], -a[3], a[2],
                   a[2], a[3], -a[0], -a[1],  a[3], -a[2], a[1], -a[0]};
  double L[16] = {q[0], q[1], q[2], q[3],     -q[1], q[0], q[3], -q[2],
                  -q[2], -q[3], q[0], q[1],   -q[3], q[2], -q[1], q[0]}; /* conj(q) (x) . */
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      B[PHM_NSTATE * i + j] = s2 * (dP[4 * i + j] - s2 * P[i] * q[j] + cj * L[4 * i + j]);
  for (int i = 0; i < 3; i++) B[PHM_NSTATE * (1 + i) + 7 + i] = -1.0;
  double u[3]; /* R^T p' */
  for (int i = 0; i < 3; i++) u[i] = Hc[i] * a[4] + Hc[4 + i] * a[5] + Hc[8 + i] * a[6];
  double U[9] = {0, -u[2], u[1], u[2], 0, -u[0], -u[1], u[0], 0};
  for (int i = 0; i < 3; i++) {
    double *b = B + PHM_NSTATE * (4 + i);
    for (int j = 0; j < 4; j++)
      b[j] = U[3 * i] * E[j] + U[3 * i + 1] * E[4 + j] + U[3 * i + 2] * E[8 + j];
    for (int j = 0; j < 3; j++) b[4 + j] = cj * Hc[4 * j + i];
    b[10 + i] = -1.0;
  }
}

/* A component's wrenches on carriers ca, cb (phm_tangent_sink): -Kx through the charts of the
 * columns' carriers and -Kt in their twists, into the momentum rows (F = M t' - ... - w). */
typedef struct {
  dae_t *d;
  const double *y;
  double *val;
} dae_sink;
static void add_wrench_tangent(void *ctx, int ca, int cb, const double w[12], const double Kx[144],
                               const double Kt[144]) {
  dae_sink *s = ctx;
  const phm_data *D = &s->d->data;
  int cr[2] = {ca, cb};
  (void)w;
  for (int bj = 0; bj < 2; bj++) {
    if (cr[bj] < 0) continue;
    double E[12];
    quat_chart(s->y + PHM_NSTATE * cr[bj], E);
    for (int bi = 0; bi < 2; bi++) {
      if (cr[bi] < 0) continue;
      double blk[6 * PHM_NSTATE]; /* -Kx_(bi, bj) [E 0; 0 R^T], then -Kt_(bi, bj) */
      to_chart(Kx + 12 * 6 * bi + 6 * bj, 12, 6, E, D->H + 16 * cr[bj], -1.0, blk, PHM_NSTATE);
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++)
          blk[PHM_NSTATE * i + 7 + j] = Kt ? -Kt[12 * (6 * bi + i) + 6 * bj + j] : 0.0;
      add_block(s->d, s->val, PHM_NSTATE * cr[bi] + 7, 6, PHM_NSTATE * cr[bj], PHM_NSTATE, blk,
                PHM_NSTATE);
    }
  }
}

/* The components' part (phm_component_tangent; docs/method.md section 4.11): their wrenches B u
 * at fixed u (as an actuator's, -Ku), u's change with the measured pair's carriers (the rows of
 * the driven pair's carriers: -B gq through the chart, -B gt in the twists) and with their own
 * states z (-B du/dz), and their rows z' - f: cj - df/dz on z, -df/d pose through the chart,
 * -df/dt in the twists of the measured pair's carriers. */
static void jacobian_components(dae_t *d, double time, double cj, const double *y, double *val,
                                dae_sink *sink) {
  const phm_model *m = d->m;
  const phm_data *D = &d->data;
  for (int ic = 0; ic < m->ncomp; ic++) {
    const phm_component_desc *c = &m->comp[ic];
    const phm_pair_desc *pr = &m->pair[c->pair];
    int sp = c->kind == PHM_COMP_LINEAR && c->spair >= 0 ? c->spair : c->pair;
    int nzc = phm_component_nstates(c), zc = d->iz + m->comp_z[ic];
    int ab[2] = {pr->a, pr->b}, cs[2] = {m->pair[sp].a, m->pair[sp].b};
    double w[12], Ku[144], B[12], gq[12], gt[12], Kz[12 * PHM_COMP_MAXZ], Fx[12 * PHM_COMP_MAXZ];
    double Ft[12 * PHM_COMP_MAXZ], Fz[PHM_COMP_MAXZ * PHM_COMP_MAXZ];
    phm_component_tangent(m, ic, D->pair, D->H, D->tw, y + d->ix, y + d->iz, time, d->tref, w, Ku,
                          B, gq, gt, Kz, Fx, Ft, Fz);
    add_wrench_tangent(sink, pr->a, pr->b, w, Ku, NULL);
    for (int s = 0; s < 2; s++) { /* the measured carrier c_s's states */
      if (cs[s] < 0) continue;
      double E[12];
      quat_chart(y + PHM_NSTATE * cs[s], E);
      for (int r = 0; r < 2; r++) { /* in the momentum rows of the driven carrier c_r */
        if (ab[r] < 0) continue;
        double K[36], blk[6 * PHM_NSTATE];
        for (int i = 0; i < 6; i++)
          for (int j = 0; j < 6; j++) K[6 * i + j] = B[6 * r + i] * gq[6 * s + j];
        to_chart(K, 6, 6, E, D->H + 16 * cs[s], -1.0, blk, PHM_NSTATE);
        for (int i = 0; i < 6; i++)
          for (int j = 0; j < 6; j++) blk[PHM_NSTATE * i + 7 + j] = -B[6 * r + i] * gt[6 * s + j];
        add_block(d, val, PHM_NSTATE * ab[r] + 7, 6, PHM_NSTATE * cs[s], PHM_NSTATE, blk, PHM_NSTATE);
      }
      if (nzc == 0) continue;
      double blk[PHM_COMP_MAXZ * 7], ft[PHM_COMP_MAXZ * 6];
      to_chart(Fx + 6 * s, 12, nzc, E, D->H + 16 * cs[s], -1.0, blk, 7);
      add_block(d, val, zc, nzc, PHM_NSTATE * cs[s], 7, blk, 7);
      for (int i = 0; i < nzc; i++)
        for (int j = 0; j < 6; j++) ft[6 * i + j] = -Ft[12 * i + 6 * s + j];
      add_block(d, val, zc, nzc, PHM_NSTATE * cs[s] + 7, 6, ft, 6);
    }
    if (nzc == 0) continue;
    for (int i = 0; i < nzc * nzc; i++) Fz[i] = -Fz[i];
    for (int i = 0; i < nzc; i++) Fz[nzc * i + i] += cj;
    add_block(d, val, zc, nzc, zc, nzc, Fz, nzc);
    for (int r = 0; r < 2; r++) { /* the driven carriers' momentum rows in z's columns */
      if (ab[r] < 0) continue;
      double mz[6 * PHM_COMP_MAXZ];
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < nzc; j++) mz[nzc * i + j] = -Kz[nzc * (6 * r + i) + j];
      add_block(d, val, PHM_NSTATE * ab[r] + 7, 6, zc, nzc, mz, nzc);
    }
  }
}

/* The closed-form part of the Jacobian at (y, y') (the poses, twists, pairs and G^T mu in
 * d->data): each carrier's kinematic rows q' = 1/2 q (x) (0, w + dw), p' = R (v + dv) ((dw, dv) =
 * G^T mu; or in its body frame, body_kinematics_block) and momentum rows M t' - ad*_t M t -
 * gravity in its own states, and each se3 element's wrenches (phm_element_tangent) and consistent
 * mass (phm_element_inertia, which reads the twists' rates yp) and each actuator's, load's and
 * spring's (phm_applied_tangent) in the states of its two carriers, through the chart (q, p) ->
 * body perturbation [dxi/dq, 0; 0, R^T]. */
static void jacobian_closed_form(dae_t *d, double time, double cj, const double *y,
                                 const double *yp, double *val) {
  const phm_model *m = d->m;
  const phm_data *D = &d->data;
  double gn = fabs(m->gravity[0]) + fabs(m->gravity[1]) + fabs(m->gravity[2]);
  for (int c = 0; c < m->nc; c++) {
    const double *q = y + PHM_NSTATE * c, *t = q + 7, *Hc = D->H + 16 * c, *M = m->car[m->car_u[c]].M;
    const double *gm = D->gm + 6 * c;
    int o = PHM_NSTATE * c;
    double B[PHM_NSTATE * PHM_NSTATE] = {0}; /* rows and columns: the carrier's 13 states */
#define JB(i, j) B[PHM_NSTATE * (i) + (j)]
    double E[12];
    quat_chart(q, E);
    if (d->kbody[c]) body_kinematics_block(q, yp + o, Hc, E, cj, B);
    else {
      double w[3] = {t[0] + gm[0], t[1] + gm[1], t[2] + gm[2]};
      double v[3] = {t[3] + gm[3], t[4] + gm[4], t[5] + gm[5]};
      double Jq[16] = {0, .5 * w[0], .5 * w[1], .5 * w[2],     -.5 * w[0], 0, -.5 * w[2], .5 * w[1],
                       -.5 * w[1], .5 * w[2], 0, -.5 * w[0],   -.5 * w[2], -.5 * w[1], .5 * w[0], 0};
      double Jw[12];
      quat_rate(q, Jw);
      for (int i = 0; i < 4; i++) {
        for (int j = 0; j < 4; j++) JB(i, j) = Jq[4 * i + j];
        for (int j = 0; j < 3; j++) JB(i, 7 + j) = Jw[3 * i + j];
      }
      /* p' = R v: d(R v) = -R hat(v) dw, dw = E dq */
      double RV[9];
      for (int i = 0; i < 3; i++) {
        double r[3] = {Hc[4 * i], Hc[4 * i + 1], Hc[4 * i + 2]};
        RV[3 * i] = r[1] * v[2] - r[2] * v[1]; /* row i of R hat(v): r x v, r = row i of R */
        RV[3 * i + 1] = r[2] * v[0] - r[0] * v[2];
        RV[3 * i + 2] = r[0] * v[1] - r[1] * v[0];
        for (int j = 0; j < 4; j++)
          JB(4 + i, j) = RV[3 * i] * E[j] + RV[3 * i + 1] * E[4 + j] + RV[3 * i + 2] * E[8 + j];
        for (int j = 0; j < 3; j++) JB(4 + i, 10 + j) = -r[j];
      }
      for (int i = 0; i < 7; i++) JB(i, i) += cj;
    }
    /* M t' - ad*_t (M t): cj M - ad*_(e_j) M t - ad*_t M e_j */
    double Mt[6];
    phm_mv6(M, t, Mt);
    for (int j = 0; j < 6; j++) {
      double ej[6] = {0}, Me[6], a1[6], a2[6];
      ej[j] = 1.0;
      for (int i = 0; i < 6; i++) Me[i] = M[6 * i + j];
      phm_ad_dual_apply(ej, Mt, a1);
      phm_ad_dual_apply(t, Me, a2);
      for (int i = 0; i < 6; i++) JB(7 + i, 7 + j) = cj * M[6 * i + j] - a1[i] - a2[i];
    }
    if (gn > 0) { /* gravity: -dw/ddelta [E 0; 0 R^T] on the momentum rows (rotation only) */
      double wg[6], Kg[36], Bg[6 * 7];
      phm_gravity_tangent(m, c, Hc, 1.0, wg, Kg);
      to_chart(Kg, 6, 6, E, Hc, -1.0, Bg, 7);
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 4; j++) JB(7 + i, j) += Bg[7 * i + j];
    }
#undef JB
    add_block(d, val, o, PHM_NSTATE, o, PHM_NSTATE, B, PHM_NSTATE);
  }
  dae_sink sink = {d, y, val};
  for (int ie = 0; ie < m->ne; ie++) { /* section data shared as in phm_applied_pairs */
    const phm_element_desc *e = &m->el[m->el_sec[ie]];
    const int a = m->el_ab[2 * ie], b = m->el_ab[2 * ie + 1];
    double w[12], Kx[144], Ct[144];
    phm_element_tangent(e, D->H + 16 * a, D->H + 16 * b, D->tw + 6 * a, D->tw + 6 * b, w, w + 6, Kx, Ct);
    add_wrench_tangent(&sink, a, b, w, Kx, Ct);
  }
  static const double Kzero[144];
  for (int k = 0; k < m->nmc; k++) { /* consistent masses: -Kt into the twists (a "wrench" -f) */
    const int ca = m->mc_a[k], cb = m->mc_b[k];
    double f[12], Kt[144];
    phm_element_inertia(phm_mc(m, k), phm_mc_rows(m, k), D->tw + 6 * ca, D->tw + 6 * cb,
                        yp + PHM_NSTATE * ca + 7, yp + PHM_NSTATE * cb + 7, cj, f, Kt);
    for (int i = 0; i < 144; i++) Kt[i] = -Kt[i];
    add_wrench_tangent(&sink, ca, cb, f, Kzero, Kt);
  }
  /* actuators, loads, springs: at the pairs' evaluation of this state (dae_pair_rows) */
  phm_applied_tangent(m, D->pair, D->H, D->tw, y + d->ix, time, d->tref, 1.0, add_wrench_tangent,
                      &sink);
  jacobian_components(d, time, cj, y, val, &sink);
}

/* The pairs' part of the Jacobian in closed form (phm_pair_tangent; docs/method.md sections 4.3,
 * 6.6) at the state y (the poses and twists in d->data), and the ledger rows' diagonal cj. Per
 * pair with carriers a (side 0) and b (side 1), each carrier c_s's states against:
 *   its momentum rows:    -d(G^T lambda)/d pose (Kl), -G_s^T in lambda's columns;
 *   its kinematic rows:   Jw d(G^T mu)_omega, -R d(G^T mu)_v (Km), and Jw G_s^T, -R G_s^T in mu's
 *                         (in the body frame -d(G^T mu) and -G_s^T: kin_rate);
 *   the velocity rows:    d(G t - vt)/d pose, G_s in the twist;
 *   the position rows:    dg/d pose;
 *   the joint rows:       x' - Phi^T t_rel: -d(Phi^T t_rel)/d pose, -Phi^T Ad_s in the twist
 *                         (Ad_b = AdTbi, Ad_a = -AdBa), cj on x. */
static void jacobian_pairs(dae_t *d, double time, double cj, const double *y, double *val) {
  const phm_model *m = d->m;
  phm_data *D = &d->data;
  for (int i = d->ie; i < d->il; i++) add_block(d, val, i, 1, i, 1, &cj, 1);
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int ab[2] = {pr->a, pr->b}, r0 = m->pair_row[ip], mc = m->pair_m[ip], k = m->pair_k[ip];
    int xj = d->ix + m->pair_j[ip], lj = d->il + r0, mj = d->im + r0;
    phm_pair_data *p = D->pair + ip;
    double dg[12 * PHM_MAXCON], dc[12 * PHM_MAXCON], dxd[72], Kl[144], Km[144];
    phm_pair_tangent(m, ip, ab[0] >= 0 ? D->H + 16 * ab[0] : NULL, ab[1] >= 0 ? D->H + 16 * ab[1] : NULL,
                     ab[0] >= 0 ? D->tw + 6 * ab[0] : NULL, ab[1] >= 0 ? D->tw + 6 * ab[1] : NULL,
                     y + xj, time, d->tref, y + lj, y + mj, NULL, p, dg, dc, NULL, dxd, Kl,
                     Km, NULL);
    for (int c = 0; c < k; c++) add_block(d, val, xj + c, 1, xj + c, 1, &cj, 1);
    /* the regularization's diagonal (dae_regularization) */
    for (int c = 0; c < mc; c++) {
      double lr = d->reg * D->lreg[r0 + c], mr = d->reg * D->mreg[r0 + c];
      add_block(d, val, lj + c, 1, lj + c, 1, &lr, 1);
      add_block(d, val, mj + c, 1, mj + c, 1, &mr, 1);
    }
    /* each side's kin_rate, once: both loops below read it (nothing between changes y or H) */
    double kin[2][7 * 6];
    for (int r = 0; r < 2; r++)
      if (ab[r] >= 0) kin_rate(d->kbody[ab[r]], y + PHM_NSTATE * ab[r], D->H + 16 * ab[r], kin[r]);
    for (int r = 0; r < 2; r++) { /* the multipliers' columns in carrier c_r's rows */
      int cr = ab[r];
      if (cr < 0) continue;
      const double *Gr = r ? p->Gb : p->Ga;
      double GT[7 * PHM_MAXCON], GL[6 * PHM_MAXCON]; /* kin G_r^T, -G_r^T */
      for (int i = 0; i < 7; i++)
        for (int rr = 0; rr < mc; rr++) {
          double acc = 0;
          for (int l = 0; l < 6; l++) acc += kin[r][6 * i + l] * Gr[6 * rr + l];
          GT[mc * i + rr] = acc;
        }
      for (int i = 0; i < 6; i++)
        for (int rr = 0; rr < mc; rr++) GL[mc * i + rr] = -Gr[6 * rr + i];
      add_block(d, val, PHM_NSTATE * cr, 7, mj, mc, GT, mc);
      add_block(d, val, PHM_NSTATE * cr + 7, 6, lj, mc, GL, mc);
    }
    for (int s = 0; s < 2; s++) {
      int cs = ab[s];
      if (cs < 0) continue;
      const double *Hs = D->H + 16 * cs, *Gs = s ? p->Gb : p->Ga;
      double E[12], blk[PHM_NSTATE * 12], Ad[36];
      quat_chart(y + PHM_NSTATE * cs, E);
      /* the rows of carrier c_r (side r) in c_s's states, and in the pair's lambda and mu */
      for (int r = 0; r < 2; r++) {
        int cr = ab[r];
        if (cr < 0) continue;
        double Km_r[36], Kl_r[36];
        for (int i = 0; i < 6; i++)
          for (int j = 0; j < 6; j++) {
            Km_r[6 * i + j] = Km[12 * (6 * r + i) + 6 * s + j];
            Kl_r[6 * i + j] = Kl[12 * (6 * r + i) + 6 * s + j];
          }
        double KK[PHM_NSTATE * 6]; /* rows of c_r against c_s's perturbation */
        for (int i = 0; i < 7; i++)
          for (int j = 0; j < 6; j++) {
            double acc = 0;
            for (int l = 0; l < 6; l++) acc += kin[r][6 * i + l] * Km_r[6 * l + j];
            KK[6 * i + j] = acc;
          }
        for (int i = 0; i < 6; i++)
          for (int j = 0; j < 6; j++) KK[6 * (7 + i) + j] = -Kl_r[6 * i + j];
        to_chart(KK, 6, PHM_NSTATE, E, Hs, 1.0, blk, 7);
        add_block(d, val, PHM_NSTATE * cr, PHM_NSTATE, PHM_NSTATE * cs, 7, blk, 7);
      }
      /* the pair's rows in c_s's states */
      to_chart(dc + 6 * s, 12, mc, E, Hs, 1.0, blk, 7);
      add_block(d, val, lj, mc, PHM_NSTATE * cs, 7, blk, 7);
      add_block(d, val, lj, mc, PHM_NSTATE * cs + 7, 6, Gs, 6);
      to_chart(dg + 6 * s, 12, mc, E, Hs, 1.0, blk, 7);
      add_block(d, val, mj, mc, PHM_NSTATE * cs, 7, blk, 7);
      if (k == 0) continue;
      to_chart(dxd + 6 * s, 12, k, E, Hs, -1.0, blk, 7);
      add_block(d, val, xj, k, PHM_NSTATE * cs, 7, blk, 7);
      const double *A = s ? m->pair_AdTbi + 36 * ip : p->AdBa;
      for (int c = 0; c < k; c++) /* -Phi^T AdTbi (b), +Phi^T AdBa (a) */
        for (int j = 0; j < 6; j++) {
          double acc = 0;
          for (int i = 0; i < 6; i++) acc += p->Phi[6 * i + c] * A[6 * i + j];
          Ad[6 * c + j] = s ? -acc : acc;
        }
      add_block(d, val, xj, k, PHM_NSTATE * cs + 7, 6, Ad, 6);
    }
  }
}

/* J = dF/dy + cj dF/dyp (no allocation), all in closed form: jacobian_closed_form and
 * jacobian_pairs at the state's poses, twists and pairs (dae_unpack, dae_pair_rows). r0, the
 * residual F(t, y, y'), is not needed. */
void dae_jacobian_values(dae_t *d, double t, double cj, const double *y, const double *ypv,
                         double *val) {
  memset(val, 0, sizeof(double) * (size_t)d->nnz);
  phm_data *D = &d->data;
  /* the poses, twists, pairs and G^T mu of the state (the pairs' rows go to scratch) */
  dae_unpack(d->m, y, D->H, D->tw);
  dae_pair_rows(d, t, y, ypv, D->rtmp);
  jacobian_closed_form(d, t, cj, y, ypv, val);
  jacobian_pairs(d, t, cj, y, val);
}

int dae_jacobian(dae_t *d, double t, double cj, const double *y, const double *ypv,
                 const double *r0, SUNMatrix J) {
  (void)r0;
  int n = d->n;
  sunindextype *cp = SUNSparseMatrix_IndexPointers(J), *ri = SUNSparseMatrix_IndexValues(J);
  for (int j = 0; j <= n; j++) cp[j] = d->colptr[j];
  for (int k = 0; k < d->nnz; k++) ri[k] = d->rowind[k];
  if (d->pl) dae_planar_jacobian_values(d, t, cj, y, ypv, SUNSparseMatrix_Data(J));
  else dae_jacobian_values(d, t, cj, y, ypv, SUNSparseMatrix_Data(J));
  return 0;
}

void dae_jacobian_to_dense(SUNMatrix Js, SUNMatrix A) {
  sunindextype n = SUNSparseMatrix_Columns(Js), lda = SUNDenseMatrix_Rows(A);
  const sunindextype *cp = SUNSparseMatrix_IndexPointers(Js), *ri = SUNSparseMatrix_IndexValues(Js);
  const double *val = SUNSparseMatrix_Data(Js);
  double *a = SUNDenseMatrix_Data(A); /* column-major, column j at a + lda j */
  /* a memset, not SUNMatZero: Debian's SUNDIALS is built without optimization
   * (csrc/integrate/nvector_ops.c) */
  memset(a, 0, sizeof(double) * (size_t)SUNDenseMatrix_LData(A));
  for (sunindextype j = 0; j < n; j++)
    for (sunindextype k = cp[j]; k < cp[j + 1]; k++) a[lda * j + ri[k]] = val[k];
}

/* The pattern above is made of whole blocks (a carrier's 13 states against each coupled
 * carrier's 13, a pair's multipliers against all of its carriers' states), and most of their
 * entries are zero: a carrier's kinematic rows hold nothing of another carrier but G^T mu's
 * geometric stiffness, the momentum rows nothing of mu, the position rows nothing of the
 * twists, and a planar motion or frames along the axes zero many more. Measured on the leaf
 * spring with modal leaves (examples/leaf_spring.py, 166 states): 5046 of the 6334 entries
 * zero, and a sparse LU of the nonzeros alone has 2100 entries against 9700, its solve 1.7 us
 * against 5.1 -- the solves were a third of a step's time there (two per step, the matrix kept
 * for hundreds of steps). Dropping exact zeros leaves the matrix as it is; only the pivot order
 * of its LU, and so the round-off of the solves, can change. The pattern kept only grows: an
 * entry once nonzero stays in it. Entries that are zero up to round-off (1e-35 .. 1e-19 in a
 * planar motion) flip between exactly zero and not, and a pattern that followed them needed a
 * fresh KLU analysis (which allocates inside KLU) on most Jacobians: 72 of 117 on the
 * impulsed cantilever of benchmarks/scenes.py; growing, 2-6 per run, at the same speed. */
int dae_jacobian_prune(dae_t *d, SUNMatrix J) {
  sunindextype *cp = SUNSparseMatrix_IndexPointers(J), *ri = SUNSparseMatrix_IndexValues(J);
  double *val = SUNSparseMatrix_Data(J);
  unsigned char *keep = d->nzkeep;
  int n = d->n, grew = d->nzcnt < 0;
  sunindextype k = 0, beg = cp[0];
  for (int j = 0; j < n; j++) {
    sunindextype end = cp[j + 1];
    for (sunindextype e = beg; e < end; e++) {
      if (val[e] != 0.0 && !keep[e]) { /* NaN is kept: the factorization or the iteration reports it */
        keep[e] = 1;
        grew = 1;
      }
      if (keep[e]) {
        ri[k] = ri[e];
        val[k++] = val[e];
      }
    }
    cp[j + 1] = k;
    beg = end;
  }
  d->nzcnt = (long)k;
  return grew;
}
