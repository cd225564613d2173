/* applied.c -- the applied wrenches on every carrier: beam elements, gravity, actuators on pairs,
 * external wrenches and interactions, point-to-point springs; with the elastic energy, the
 * dissipated power and the power of every port (the energy ledger's inputs). */
#include "model.h"

#include <math.h>
#include <string.h>

#include "linalg.h"

/* World position and velocity of body point r of carrier c (-1: ground, r is a world point). */
static void point_state(const double *H, const double *tw, int c, const double r[3], double x[3],
                        double v[3]) {
  if (c < 0) {
    for (int i = 0; i < 3; i++) { x[i] = r[i]; v[i] = 0; }
    return;
  }
  const double *Hc = H + 16 * c;
  double vb[3] = {0, 0, 0};
  if (tw) {
    const double *w = tw + 6 * c, *u = w + 3;
    vb[0] = u[0] + w[1] * r[2] - w[2] * r[1];
    vb[1] = u[1] + w[2] * r[0] - w[0] * r[2];
    vb[2] = u[2] + w[0] * r[1] - w[1] * r[0];
  }
  for (int i = 0; i < 3; i++) {
    x[i] = Hc[4 * i + 3] + Hc[4 * i] * r[0] + Hc[4 * i + 1] * r[1] + Hc[4 * i + 2] * r[2];
    v[i] = Hc[4 * i] * vb[0] + Hc[4 * i + 1] * vb[1] + Hc[4 * i + 2] * vb[2];
  }
}

/* Add the world force F and world torque T (about the world point x) to carrier c's body wrench. */
static void add_world_wrench(const double *H, int c, const double x[3], const double F[3],
                             const double T[3], double *wr) {
  if (c < 0) return;
  const double *Hc = H + 16 * c;
  double f[3], t[3], d[3], r[3];
  for (int i = 0; i < 3; i++) d[i] = x[i] - Hc[4 * i + 3];
  for (int i = 0; i < 3; i++) {
    f[i] = Hc[i] * F[0] + Hc[4 + i] * F[1] + Hc[8 + i] * F[2];
    t[i] = Hc[i] * T[0] + Hc[4 + i] * T[1] + Hc[8 + i] * T[2];
    r[i] = Hc[i] * d[0] + Hc[4 + i] * d[1] + Hc[8 + i] * d[2];
  }
  double *w = wr + 6 * c;
  w[0] += t[0] + r[1] * f[2] - r[2] * f[1];
  w[1] += t[1] + r[2] * f[0] - r[0] * f[2];
  w[2] += t[2] + r[0] * f[1] - r[1] * f[0];
  w[3] += f[0];
  w[4] += f[1];
  w[5] += f[2];
}

/* Point-to-point spring-damper: tension f = k (d - d0) + c dd/dt along the line of its points. */
void phm_spring_eval(const phm_spring_desc *sp, const double *H, const double *tw, double *wr,
                     double *V, double *Pd) {
  double xa[3], va[3], xb[3], vb[3], n[3], F[3], T[3] = {0, 0, 0};
  point_state(H, tw, sp->a, sp->pa, xa, va);
  point_state(H, tw, sp->b, sp->pb, xb, vb);
  for (int i = 0; i < 3; i++) n[i] = xb[i] - xa[i];
  double d = sqrt(phm_dot(n, n, 3));
  double dd = 0;
  if (d > 0) {
    for (int i = 0; i < 3; i++) n[i] /= d;
    for (int i = 0; i < 3; i++) dd += n[i] * (vb[i] - va[i]);
  }
  double f = sp->k * (d - sp->d0) + sp->c * dd;
  if (V) *V = 0.5 * sp->k * (d - sp->d0) * (d - sp->d0);
  if (Pd) *Pd = sp->c * dd * dd;
  if (!wr || d == 0) return;
  for (int i = 0; i < 3; i++) F[i] = -f * n[i];
  add_world_wrench(H, sp->b, xb, F, T, wr);
  for (int i = 0; i < 3; i++) F[i] = f * n[i];
  add_world_wrench(H, sp->a, xa, F, T, wr);
}

void phm_pair_effort_wrench(const phm_model *m, int ip, const phm_pair_data *p, const double *u,
                            double *wr) {
  const phm_pair_desc *pr = &m->pair[ip];
  int k = m->pair_k[ip];
  double wB[6], wv[6];
  for (int i = 0; i < 6; i++) {
    double acc = 0;
    for (int c = 0; c < k; c++) acc += p->Phi[6 * i + c] * u[c];
    wB[i] = acc;
  }
  if (pr->b >= 0) {
    phm_mtv6(m->pair_AdTbi + 36 * ip, wB, wv);
    for (int i = 0; i < 6; i++) wr[6 * pr->b + i] += wv[i];
  }
  if (pr->a >= 0) {
    phm_mtv6(p->AdBa, wB, wv);
    for (int i = 0; i < 6; i++) wr[6 * pr->a + i] -= wv[i];
  }
}

void phm_load_wrench(const phm_model *m, int il, const double *H, double s, double *wr,
                     double w[6], double wre[6]) {
  const phm_load_desc *l = &m->load[il];
  const double *Hc = H + 16 * l->carrier;
  double tau[3], f[3];
  for (int i = 0; i < 3; i++) {
    if (l->world) {
      tau[i] = s * (Hc[i] * l->w[0] + Hc[4 + i] * l->w[1] + Hc[8 + i] * l->w[2]);
      f[i] = s * (Hc[i] * l->w[3] + Hc[4 + i] * l->w[4] + Hc[8 + i] * l->w[5]);
    } else {
      tau[i] = s * l->w[i];
      f[i] = s * l->w[3 + i];
    }
  }
  const double *r = l->point;
  w[0] = tau[0] + r[1] * f[2] - r[2] * f[1];
  w[1] = tau[1] + r[2] * f[0] - r[0] * f[2];
  w[2] = tau[2] + r[0] * f[1] - r[1] * f[0];
  w[3] = f[0];
  w[4] = f[1];
  w[5] = f[2];
  for (int i = 0; i < 6; i++) wr[6 * l->carrier + i] += w[i];
  memset(wre, 0, 6 * sizeof(double));
  if (l->reaction >= 0) {
    double x[3], v[3], F[3], T[3], before[6];
    point_state(H, NULL, l->carrier, r, x, v);
    for (int i = 0; i < 3; i++) { /* world force and torque (about x), reversed */
      F[i] = -(Hc[4 * i] * f[0] + Hc[4 * i + 1] * f[1] + Hc[4 * i + 2] * f[2]);
      T[i] = -(Hc[4 * i] * tau[0] + Hc[4 * i + 1] * tau[1] + Hc[4 * i + 2] * tau[2]);
    }
    memcpy(before, wr + 6 * l->reaction, sizeof before);
    add_world_wrench(H, l->reaction, x, F, T, wr);
    for (int i = 0; i < 6; i++) wre[i] = wr[6 * l->reaction + i] - before[i];
  }
}

/* Gravity on carrier c at pose Hc: f = scale m R^T g at its centre of mass r, w = (r x f, f); and
 * Kg = dw/ddelta for Hc exp(delta) (6 x 6, row-major; may be NULL): d(R^T g) = hat(R^T g) domega,
 * so df/domega = scale m hat(R^T g) =: F, d(r x f)/domega = hat(r) F, nothing in translation. */
void phm_gravity_tangent(const phm_model *m, int c, const double Hc[16], double scale, double w[6],
                         double Kg[36]) {
  const phm_carrier_desc *cd = &m->car[c];
  const double *g = m->gravity, *r = cd->com;
  double f[3], gb[3];
  for (int i = 0; i < 3; i++) { /* R^T g */
    gb[i] = Hc[i] * g[0] + Hc[4 + i] * g[1] + Hc[8 + i] * g[2];
    f[i] = scale * cd->mass * gb[i];
  }
  w[0] = r[1] * f[2] - r[2] * f[1];
  w[1] = r[2] * f[0] - r[0] * f[2];
  w[2] = r[0] * f[1] - r[1] * f[0];
  w[3] = f[0];
  w[4] = f[1];
  w[5] = f[2];
  if (!Kg) return;
  double F[9], RF[9], k = scale * cd->mass;
  phm_so3_hat(gb, F);
  for (int i = 0; i < 9; i++) F[i] *= k;
  for (int i = 0; i < 3; i++) /* hat(r) F */
    for (int j = 0; j < 3; j++) {
      int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
      RF[3 * i + j] = r[i1] * F[3 * i2 + j] - r[i2] * F[3 * i1 + j];
    }
  memset(Kg, 0, 36 * sizeof(double));
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      Kg[6 * i + j] = RF[3 * i + j];
      Kg[6 * (3 + i) + j] = F[3 * i + j];
    }
}

void phm_applied(const phm_model *m, const double *H, const double *tw, const double *xs,
                 double time, double tref, double scale, double *wr, double *Vel, double *Pdiss,
                 double *Psupp, double *Pport, double *effort) {
  phm_applied_pairs(m, NULL, H, tw, xs, time, tref, scale, 0, wr, Vel, Pdiss, Psupp, Pport, effort);
}

void phm_applied_pairs(const phm_model *m, const phm_pair_data *pd, const double *H,
                       const double *tw, const double *xs, double time, double tref, double scale,
                       int remainder, double *wr, double *Vel, double *Pdiss, double *Psupp,
                       double *Pport, double *effort) {
  memset(wr, 0, sizeof(double) * 6 * (size_t)m->nc);
  if (effort && m->nj) memset(effort, 0, sizeof(double) * (size_t)m->nj);
  double V = 0, Pd = 0, Ps = 0;
  for (int ie = 0; !remainder && ie < m->ne; ie++) {
    const phm_element_desc *e = &m->el[ie];
    double wa[6], wb[6], v, p;
    phm_element_eval(e, H + 16 * e->a, H + 16 * e->b, tw ? tw + 6 * e->a : NULL,
                     tw ? tw + 6 * e->b : NULL, wa, wb, &v, &p, NULL);
    V += v;
    Pd += p;
    for (int i = 0; i < 6; i++) {
      wr[6 * e->a + i] += wa[i];
      wr[6 * e->b + i] += wb[i];
    }
  }
  double gn = fabs(m->gravity[0]) + fabs(m->gravity[1]) + fabs(m->gravity[2]);
  if (gn > 0 && !remainder)
    for (int c = 0; c < m->nc; c++) {
      double w[6];
      phm_gravity_tangent(m, c, H + 16 * c, scale, w, NULL);
      for (int i = 0; i < 6; i++) wr[6 * c + i] += w[i];
    }
  /* actuators */
  for (int ia = 0; ia < m->na; ia++) {
    const phm_actuator_desc *ac = &m->act[ia];
    int ip = ac->pair, k = m->pair_k[ip], j0 = m->pair_j[ip];
    const phm_pair_desc *pr = &m->pair[ip];
    phm_pair_data own;
    if (!pd) { /* evaluated here: frames, joint coordinates and rates (no constraint rows) */
      phm_pair_evaluate(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                        (tw && pr->a >= 0) ? tw + 6 * pr->a : NULL, (tw && pr->b >= 0) ? tw + 6 * pr->b : NULL,
                        xs ? xs + j0 : NULL, time, tref, 0, &own);
    }
    const phm_pair_data *p = pd ? pd + ip : &own;
    const double *x = p->x, *xd = p->xdot;
    double u[6] = {0}, s = 0, ds = 0;
    if (ac->kind != PHM_ACT_SPRING) s = phm_law_eval(&ac->law, time, tref, &ds, NULL);
    for (int c = 0; c < k; c++) {
      if (ac->kind == PHM_ACT_EFFORT) u[c] = scale * s * ac->vec[c];
      else if (ac->kind == PHM_ACT_PD)
        u[c] = -ac->kp[c] * (x[c] - ac->x_set[c] - s * ac->vec[c]) - ac->kd[c] * (xd[c] - ds * ac->vec[c]);
      else u[c] = -ac->kp[c] * (x[c] - ac->x_set[c]) - ac->kd[c] * xd[c];
      if (effort) effort[j0 + c] += u[c];
    }
    phm_pair_effort_wrench(m, ip, p, u, wr);
    double P = phm_dot(u, xd, k);
    Ps += P;
    if (Pport) Pport[ia] = P;
  }
  /* external wrenches and interactions */
  for (int il = 0; il < m->nl; il++) {
    const phm_load_desc *l = &m->load[il];
    double s = scale * phm_law_eval(&l->law, time, tref, NULL, NULL);
    if (Pport) Pport[m->na + il] = 0;
    if (s == 0) continue;
    double w[6], wre[6];
    phm_load_wrench(m, il, H, s, wr, w, wre);
    double P = tw ? phm_dot(w, tw + 6 * l->carrier, 6) : 0;
    if (tw && l->reaction >= 0) P += phm_dot(wre, tw + 6 * l->reaction, 6);
    Ps += P;
    if (Pport) Pport[m->na + il] = P;
  }
  for (int is = 0; is < m->ns; is++) {
    double v = 0, p = 0;
    phm_spring_eval(&m->spr[is], H, tw, wr, &v, &p);
    V += v;
    Pd += p;
    if (Pport) Pport[m->na + m->nl + is] = -p;
  }
  if (Vel) *Vel = V;
  if (Pdiss) *Pdiss = Pd;
  if (Psupp) *Psupp = Ps;
}

void phm_remainder_carriers(const phm_model *m, int *mark) {
  for (int c = 0; c < m->nc; c++) mark[c] = 0;
  for (int is = 0; is < m->ns; is++) {
    if (m->spr[is].a >= 0) mark[m->spr[is].a] = 1;
    if (m->spr[is].b >= 0) mark[m->spr[is].b] = 1;
  }
  for (int il = 0; il < m->nl; il++) {
    mark[m->load[il].carrier] = 1;
    if (m->load[il].reaction >= 0) mark[m->load[il].reaction] = 1;
  }
  for (int ia = 0; ia < m->na; ia++) {
    const phm_pair_desc *pr = &m->pair[m->act[ia].pair];
    if (pr->a >= 0) mark[pr->a] = 1;
    if (pr->b >= 0) mark[pr->b] = 1;
  }
}
