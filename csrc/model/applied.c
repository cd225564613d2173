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

/* The body wrench w = (t + r x f, f) of a torque t and a force f at body point r. */
static void body_wrench(const double t[3], const double f[3], const double r[3], double w[6]) {
  w[0] = t[0] + r[1] * f[2] - r[2] * f[1];
  w[1] = t[1] + r[2] * f[0] - r[0] * f[2];
  w[2] = t[2] + r[0] * f[1] - r[1] * f[0];
  w[3] = f[0];
  w[4] = f[1];
  w[5] = f[2];
}

/* Carrier c's body wrench w of the world force F and world torque T (about the world point x). */
static void world_wrench(const double *H, int c, const double x[3], const double F[3],
                         const double T[3], double w[6]) {
  const double *Hc = H + 16 * c;
  double f[3], t[3], d[3], r[3];
  for (int i = 0; i < 3; i++) d[i] = x[i] - Hc[4 * i + 3];
  for (int i = 0; i < 3; i++) {
    f[i] = Hc[i] * F[0] + Hc[4 + i] * F[1] + Hc[8 + i] * F[2];
    t[i] = Hc[i] * T[0] + Hc[4 + i] * T[1] + Hc[8 + i] * T[2];
    r[i] = Hc[i] * d[0] + Hc[4 + i] * d[1] + Hc[8 + i] * d[2];
  }
  body_wrench(t, f, r, w);
}

/* Add the world force F and world torque T (about the world point x) to carrier c's body wrench. */
static void add_world_wrench(const double *H, int c, const double x[3], const double F[3],
                             const double T[3], double *wr) {
  if (c < 0) return;
  double w[6];
  world_wrench(H, c, x, F, T, w);
  for (int i = 0; i < 6; i++) wr[6 * c + i] += w[i];
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

/* A load's torque and force in its carrier's body axes at carrier pose Hc, s times its vector. */
static void load_body(const phm_load_desc *l, const double *Hc, double s, double tau[3],
                      double f[3]) {
  for (int i = 0; i < 3; i++) {
    if (l->world) {
      tau[i] = s * (Hc[i] * l->w[0] + Hc[4 + i] * l->w[1] + Hc[8 + i] * l->w[2]);
      f[i] = s * (Hc[i] * l->w[3] + Hc[4 + i] * l->w[4] + Hc[8 + i] * l->w[5]);
    } else {
      tau[i] = s * l->w[i];
      f[i] = s * l->w[3 + i];
    }
  }
}

void phm_load_wrench(const phm_model *m, int il, const double *H, double s, double *wr,
                     double w[6], double wre[6]) {
  const phm_load_desc *l = &m->load[il];
  const double *Hc = H + 16 * l->carrier;
  double tau[3], f[3];
  load_body(l, Hc, s, tau, f);
  const double *r = l->point;
  body_wrench(tau, f, r, w);
  if (wr)
    for (int i = 0; i < 6; i++) wr[6 * l->carrier + i] += w[i];
  memset(wre, 0, 6 * sizeof(double));
  if (l->reaction >= 0) {
    double x[3], v[3], F[3], T[3];
    point_state(H, NULL, l->carrier, r, x, v);
    for (int i = 0; i < 3; i++) { /* world force and torque (about x), reversed */
      F[i] = -(Hc[4 * i] * f[0] + Hc[4 * i + 1] * f[1] + Hc[4 * i + 2] * f[2]);
      T[i] = -(Hc[4 * i] * tau[0] + Hc[4 * i + 1] * tau[1] + Hc[4 * i + 2] * tau[2]);
    }
    world_wrench(H, l->reaction, x, F, T, wre);
    if (wr)
      for (int i = 0; i < 6; i++) wr[6 * l->reaction + i] += wre[i];
  }
}

/* Gravity on carrier c at pose Hc: f = scale m R^T g at its centre of mass r, w = (r x f, f); and
 * Kg = dw/ddelta for Hc exp(delta) (6 x 6, row-major; may be NULL): d(R^T g) = hat(R^T g) domega,
 * so df/domega = scale m hat(R^T g) =: F, d(r x f)/domega = hat(r) F, nothing in translation. */
void phm_gravity_tangent(const phm_model *m, int c, const double Hc[16], double scale, double w[6],
                         double Kg[36]) {
  const phm_carrier_desc *cd = &m->car[m->car_u[c]]; /* its mass and com: shared when identical */
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
  phm_applied_pairs(m, NULL, H, tw, xs, time, tref, scale, wr, Vel, Pdiss, Psupp, Pport, effort);
}

/* Actuator ac's generalized efforts u (k) at its pair's evaluation p (section 4.4 of
 * docs/method.md): effort sources x scale, PD and joint springs from x and xdot. */
static void actuator_effort(const phm_model *m, const phm_actuator_desc *ac, const phm_pair_data *p,
                            double time, double tref, double scale, double u[6]) {
  const double *x = p->x, *xd = p->xdot;
  double s = 0, ds = 0;
  memset(u, 0, 6 * sizeof(double));
  if (ac->kind != PHM_ACT_SPRING) s = phm_law_eval(&ac->law, time, tref, &ds, NULL);
  for (int c = 0; c < m->pair_k[ac->pair]; c++) {
    if (ac->kind == PHM_ACT_EFFORT) u[c] = scale * s * ac->vec[c];
    else if (ac->kind == PHM_ACT_PD)
      u[c] = -ac->kp[c] * (x[c] - ac->x_set[c] - s * ac->vec[c]) - ac->kd[c] * (xd[c] - ds * ac->vec[c]);
    else u[c] = -ac->kp[c] * (x[c] - ac->x_set[c]) - ac->kd[c] * xd[c];
  }
}

void phm_applied_pairs(const phm_model *m, const phm_pair_data *pd, const double *H,
                       const double *tw, const double *xs, double time, double tref, double scale,
                       double *wr, double *Vel, double *Pdiss, double *Psupp,
                       double *Pport, double *effort) {
  memset(wr, 0, sizeof(double) * 6 * (size_t)m->nc);
  if (effort && m->nj) memset(effort, 0, sizeof(double) * (size_t)m->nj);
  double V = 0, Pd = 0, Ps = 0;
  for (int ie = 0; ie < m->ne; ie++) {
    /* its section data from the first bit-identical element's (phm_model.el_sec) */
    const phm_element_desc *e = &m->el[m->el_sec[ie]];
    const int a = m->el_ab[2 * ie], b = m->el_ab[2 * ie + 1];
    double wa[6], wb[6], v, p;
    /* an undamped element's twists only make its (zero) viscous stress and power: not passed */
    int tv = tw && m->el_damped[ie];
    phm_element_eval(e, H + 16 * a, H + 16 * b, tv ? tw + 6 * a : NULL, tv ? tw + 6 * b : NULL,
                     wa, wb, &v, &p, NULL);
    V += v;
    Pd += p;
    for (int i = 0; i < 6; i++) {
      wr[6 * a + i] += wa[i];
      wr[6 * b + i] += wb[i];
    }
  }
  double gn = fabs(m->gravity[0]) + fabs(m->gravity[1]) + fabs(m->gravity[2]);
  if (gn > 0)
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
                        xs ? xs + j0 : NULL, time, tref, PHM_PAIR_JOINT, &own);
    }
    const phm_pair_data *p = pd ? pd + ip : &own;
    double u[6];
    actuator_effort(m, ac, p, time, tref, scale, u);
    for (int c = 0; effort && c < k; c++) effort[j0 + c] += u[c];
    phm_pair_effort_wrench(m, ip, p, u, wr);
    double P = phm_dot(u, p->xdot, k);
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


void phm_applied_dpower(const phm_model *m, const phm_pair_data *pd, const double *H,
                        const double *dtw, double time, double tref, double *dPs,
                        double *dPport) {
  for (int ia = 0; ia < m->na; ia++) { /* P = u . xdot, u = u(x, xdot) */
    const phm_actuator_desc *ac = &m->act[ia];
    int ip = ac->pair, k = m->pair_k[ip];
    const phm_pair_desc *pr = &m->pair[ip];
    const phm_pair_data *p = pd + ip;
    double u[6], tr[6], P = 0;
    actuator_effort(m, ac, p, time, tref, 1.0, u);
    phm_pair_rel_twist(m->pair_AdTbi + 36 * ip, p->AdBa, pr->a >= 0 ? dtw + 6 * pr->a : NULL,
                       pr->b >= 0 ? dtw + 6 * pr->b : NULL, tr);
    for (int c = 0; c < k; c++) {
      double dxd = 0, du = 0;
      for (int i = 0; i < 6; i++) dxd += p->Phi[6 * i + c] * tr[i];
      if (ac->kind != PHM_ACT_EFFORT) du = -ac->kd[c] * dxd;
      P += u[c] * dxd + (p->xdot[c] + dxd) * du; /* (u + du)(xdot + dxd) - u xdot */
    }
    *dPs += P;
    dPport[ia] = P;
  }
  for (int il = 0; il < m->nl; il++) { /* P = w . t at the load's wrench of the pose */
    const phm_load_desc *l = &m->load[il];
    double s = phm_law_eval(&l->law, time, tref, NULL, NULL), w[6], wre[6], P = 0;
    if (s != 0) {
      phm_load_wrench(m, il, H, s, NULL, w, wre);
      P = phm_dot(w, dtw + 6 * l->carrier, 6);
      if (l->reaction >= 0) P += phm_dot(wre, dtw + 6 * l->reaction, 6);
    }
    *dPs += P;
    dPport[m->na + il] = P;
  }
}

/* ---------------------------------------------------------------- closed-form tangents */
/* The body wrench w = (t + r x f, f) of a torque t and a force f at body point r, and the skew
 * matrices of t, f, r (their derivatives' building blocks). */
static void wrench_at(const double t[3], const double f[3], const double r[3], double th[9],
                      double fh[9], double rh[9], double w[6]) {
  phm_so3_hat(t, th);
  phm_so3_hat(f, fh);
  phm_so3_hat(r, rh);
  for (int i = 0; i < 3; i++) {
    w[i] = t[i] + rh[3 * i] * f[0] + rh[3 * i + 1] * f[1] + rh[3 * i + 2] * f[2];
    w[3 + i] = f[i];
  }
}

/* The body wrench on carrier pose Hc of a world force F and torque T (may be NULL) at the world
 * point x (add_world_wrench) into w, and its derivative Jw (6 x nz) from those of x, F, T (Jx,
 * JF, JT: 3 x nz each, JT may be NULL) and of the carrier's own perturbation Hc exp(delta), whose
 * columns start at col: with f = R^T F, t = R^T T, r = R^T (x - p), d(R^T a) = hat(R^T a) dw
 * and dr = hat(r) dw - dv + R^T dx, so d(r x f) = r x df - f x dr. */
static void world_wrench_tangent(const double *Hc, int col, const double x[3], const double F[3],
                                 const double *T, const double *Jx, const double *JF,
                                 const double *JT, int nz, double w[6], double *Jw) {
  double f[3], t[3] = {0, 0, 0}, r[3], d[3];
  for (int i = 0; i < 3; i++) d[i] = x[i] - Hc[4 * i + 3];
  for (int i = 0; i < 3; i++) {
    f[i] = Hc[i] * F[0] + Hc[4 + i] * F[1] + Hc[8 + i] * F[2];
    if (T) t[i] = Hc[i] * T[0] + Hc[4 + i] * T[1] + Hc[8 + i] * T[2];
    r[i] = Hc[i] * d[0] + Hc[4 + i] * d[1] + Hc[8 + i] * d[2];
  }
  double fh[9], th[9], rh[9];
  wrench_at(t, f, r, th, fh, rh, w);
  for (int j = 0; j < nz; j++) {
    double df[3], dt[3], dr[3];
    for (int i = 0; i < 3; i++) { /* R^T times the columns */
      df[i] = dt[i] = dr[i] = 0;
      for (int l = 0; l < 3; l++) {
        df[i] += Hc[4 * l + i] * JF[nz * l + j];
        if (JT) dt[i] += Hc[4 * l + i] * JT[nz * l + j];
        dr[i] += Hc[4 * l + i] * Jx[nz * l + j];
      }
    }
    if (j >= col && j < col + 3)
      for (int i = 0; i < 3; i++) {
        df[i] += fh[3 * i + j - col];
        dt[i] += th[3 * i + j - col];
        dr[i] += rh[3 * i + j - col];
      }
    if (j >= col + 3 && j < col + 6) dr[j - col - 3] -= 1.0;
    for (int i = 0; i < 3; i++) {
      double a = 0, b = 0;
      for (int l = 0; l < 3; l++) {
        a += rh[3 * i + l] * df[l];
        b += fh[3 * i + l] * dr[l];
      }
      Jw[nz * i + j] = dt[i] + a - b;
      Jw[nz * (3 + i) + j] = df[i];
    }
  }
}

/* The world position of body point r of carrier pose Hc and its derivative Jx (3 x nz) in the
 * carrier's perturbation (columns col..col+5): dx = R (dv - r x dw). */
static void point_tangent(const double *Hc, const double r[3], int col, int nz, double *Jx) {
  double rh[9];
  phm_so3_hat(r, rh);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double s = 0;
      for (int l = 0; l < 3; l++) s += Hc[4 * i + l] * rh[3 * l + j];
      Jx[nz * i + col + j] = -s;
      Jx[nz * i + col + 3 + j] = Hc[4 * i + j];
    }
}

/* A spring-damper's wrenches w (12: on a, on b) and their derivatives Kx in [da; db], Kt in
 * [ta; tb] (12 x 12 each): the tension f = k (d - d0) + c dd/dt along n, with dd = n . (dx_b -
 * dx_a), dn = (I - n n^T) (dx_b - dx_a)/d and d(dd/dt) = dn . (v_b - v_a) + n . (dv_b - dv_a),
 * v = R (u + w x r): dv = -R hat(u + w x r) dw in the pose, R [-hat(r), I] in the twist. */
static void spring_tangent(const phm_spring_desc *sp, const double *H, const double *tw,
                           double w[12], double Kx[144], double Kt[144]) {
  enum { NZ = 24 }; /* columns: da, db, ta, tb */
  double x[2][3], v[2][3], Jx[2][3 * NZ], Jv[2][3 * NZ];
  int cs[2] = {sp->a, sp->b};
  const double *rs[2] = {sp->pa, sp->pb};
  memset(Jx, 0, sizeof Jx);
  memset(Jv, 0, sizeof Jv);
  memset(w, 0, 12 * sizeof(double));
  memset(Kx, 0, 144 * sizeof(double));
  memset(Kt, 0, 144 * sizeof(double));
  for (int s = 0; s < 2; s++) {
    point_state(H, tw, cs[s], rs[s], x[s], v[s]);
    if (cs[s] < 0) continue;
    const double *Hc = H + 16 * cs[s];
    point_tangent(Hc, rs[s], 6 * s, NZ, Jx[s]);
    static const double rest[6] = {0, 0, 0, 0, 0, 0};
    const double *t = tw ? tw + 6 * cs[s] : rest, *r = rs[s];
    double vb[3] = {t[3] + t[1] * r[2] - t[2] * r[1], t[4] + t[2] * r[0] - t[0] * r[2],
                    t[5] + t[0] * r[1] - t[1] * r[0]}, vh[9];
    phm_so3_hat(vb, vh);
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 6; j++) {
        double s1 = 0;
        for (int l = 0; l < 3 && j < 3; l++) s1 += Hc[4 * i + l] * vh[3 * l + j];
        if (j < 3) Jv[s][NZ * i + 6 * s + j] = -s1;
        Jv[s][NZ * i + 12 + 6 * s + j] = Jx[s][NZ * i + 6 * s + j]; /* R [-hat(r), I] */
      }
  }
  double e[3], vr[3], n[3], d;
  for (int i = 0; i < 3; i++) {
    e[i] = x[1][i] - x[0][i];
    vr[i] = v[1][i] - v[0][i];
  }
  d = sqrt(phm_dot(e, e, 3));
  if (d == 0) return; /* no direction: phm_spring_eval applies nothing */
  for (int i = 0; i < 3; i++) n[i] = e[i] / d;
  double dd = phm_dot(n, vr, 3), f = sp->k * (d - sp->d0) + sp->c * dd;
  double Jn[3 * NZ], Jf[NZ], JF[2][3 * NZ];
  for (int j = 0; j < NZ; j++) {
    double de[3], dv[3], nde = 0;
    for (int i = 0; i < 3; i++) {
      de[i] = Jx[1][NZ * i + j] - Jx[0][NZ * i + j];
      dv[i] = Jv[1][NZ * i + j] - Jv[0][NZ * i + j];
      nde += n[i] * de[i];
    }
    double jdd = 0;
    for (int i = 0; i < 3; i++) {
      Jn[NZ * i + j] = (de[i] - n[i] * nde) / d;
      jdd += vr[i] * Jn[NZ * i + j] + n[i] * dv[i];
    }
    Jf[j] = sp->k * nde + sp->c * jdd;
  }
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < NZ; j++) {
      JF[0][NZ * i + j] = n[i] * Jf[j] + f * Jn[NZ * i + j]; /* +f n on a, -f n on b */
      JF[1][NZ * i + j] = -JF[0][NZ * i + j];
    }
  for (int s = 0; s < 2; s++) {
    if (cs[s] < 0) continue;
    double F[3] = {s ? -f * n[0] : f * n[0], s ? -f * n[1] : f * n[1], s ? -f * n[2] : f * n[2]};
    double Jw[6 * NZ];
    world_wrench_tangent(H + 16 * cs[s], 6 * s, x[s], F, NULL, Jx[s], JF[s], NULL, NZ, w + 6 * s, Jw);
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 12; j++) {
        Kx[12 * (6 * s + i) + j] = Jw[NZ * i + j];
        Kt[12 * (6 * s + i) + j] = Jw[NZ * i + 12 + j];
      }
  }
}

/* Load il's wrenches w (12: on its carrier, on its reaction carrier) at the law's value s and
 * their derivative Kx (12 x 12) in [dc; de] (no twist enters): world axes, d(R^T a) =
 * hat(R^T a) dw on the carrier (body axes: constant); the reaction, the opposite world force and
 * torque through the carrier's material point (world_wrench_tangent). */
static void load_tangent(const phm_model *m, int il, const double *H, double s, double w[12],
                         double Kx[144]) {
  enum { NZ = 12 };
  const phm_load_desc *l = &m->load[il];
  const double *Hc = H + 16 * l->carrier, *r = l->point;
  double tau[3], f[3], th[9], fh[9], rh[9];
  load_body(l, Hc, s, tau, f);
  memset(w, 0, 12 * sizeof(double));
  memset(Kx, 0, 144 * sizeof(double));
  wrench_at(tau, f, r, th, fh, rh, w);
  for (int i = 0; i < 3; i++) {
    for (int j = 0; l->world && j < 3; j++) {
      double a = 0;
      for (int q = 0; q < 3; q++) a += rh[3 * i + q] * fh[3 * q + j];
      Kx[12 * i + j] = th[3 * i + j] + a;
      Kx[12 * (3 + i) + j] = fh[3 * i + j];
    }
  }
  if (l->reaction < 0) return;
  double x[3], vv[3], F[3], T[3], Jx[3 * NZ] = {0}, JF[3 * NZ] = {0}, JT[3 * NZ] = {0}, Jw[6 * NZ];
  point_state(H, NULL, l->carrier, r, x, vv);
  point_tangent(Hc, r, 0, NZ, Jx);
  for (int i = 0; i < 3; i++) {
    F[i] = -(Hc[4 * i] * f[0] + Hc[4 * i + 1] * f[1] + Hc[4 * i + 2] * f[2]);
    T[i] = -(Hc[4 * i] * tau[0] + Hc[4 * i + 1] * tau[1] + Hc[4 * i + 2] * tau[2]);
    for (int j = 0; !l->world && j < 3; j++) /* body axes: d(-R a) = R hat(a) dw */
      for (int q = 0; q < 3; q++) {
        JF[NZ * i + j] += Hc[4 * i + q] * fh[3 * q + j];
        JT[NZ * i + j] += Hc[4 * i + q] * th[3 * q + j];
      }
  }
  world_wrench_tangent(H + 16 * l->reaction, 6, x, F, T, Jx, JF, JT, NZ, w + 6, Jw);
  for (int i = 0; i < 6; i++) memcpy(Kx + 12 * (6 + i), Jw + NZ * i, 12 * sizeof(double));
}

/* Actuator ia's wrenches w (12: on its pair's a and b) and their derivatives Kx in [da; db], Kt
 * in [ta; tb]: w = [-AdBa^T Phi u; AdTbi^T Phi u] with u = actuator_effort of the joint's x and
 * xdot, so dw = Ku (at fixed u, phm_pair_tangent) + [-AdBa^T Phi; AdTbi^T Phi] du, du = -kp dx -
 * kd dxdot (PD and spring; none for an effort), dxdot = dxd (pose) + Phi^T [-AdBa, AdTbi] dt. */
static void actuator_tangent(const phm_model *m, int ia, const phm_pair_data *pd, const double *H,
                             const double *tw, const double *xs, double time, double tref,
                             double scale, double w[12], double Kx[144], double Kt[144]) {
  const phm_actuator_desc *ac = &m->act[ia];
  int ip = ac->pair, k = m->pair_k[ip], j0 = m->pair_j[ip];
  const phm_pair_desc *pr = &m->pair[ip];
  const double *Ha = pr->a >= 0 ? H + 16 * pr->a : NULL, *Hb = pr->b >= 0 ? H + 16 * pr->b : NULL;
  const double *ta = (tw && pr->a >= 0) ? tw + 6 * pr->a : NULL;
  const double *tb = (tw && pr->b >= 0) ? tw + 6 * pr->b : NULL;
  const double *xr = xs ? xs + j0 : NULL;
  phm_pair_data own;
  if (!pd) phm_pair_evaluate(m, ip, Ha, Hb, ta, tb, xr, time, tref, PHM_PAIR_JOINT, &own);
  const phm_pair_data *p = pd ? pd + ip : &own;
  double u[6], dx[72], dxd[72], Ku[144], B[72];
  actuator_effort(m, ac, p, time, tref, scale, u);
  phm_pair_data pt;
  phm_pair_tangent(m, ip, Ha, Hb, ta, tb, xr, time, tref, NULL, NULL, u, &pt, NULL, NULL, dx, dxd,
                   NULL, NULL, Ku);
  const double *AdTbi = m->pair_AdTbi + 36 * ip;
  for (int i = 0; i < 6; i++) /* B = [-AdBa^T Phi; AdTbi^T Phi] (12 x k) */
    for (int c = 0; c < k; c++) {
      double sa = 0, sb = 0;
      for (int l = 0; l < 6; l++) {
        sa += pt.AdBa[6 * l + i] * pt.Phi[6 * l + c];
        sb += AdTbi[6 * l + i] * pt.Phi[6 * l + c];
      }
      B[k * i + c] = -sa;
      B[k * (6 + i) + c] = sb;
    }
  int pd_kind = ac->kind != PHM_ACT_EFFORT;
  double dup[72] = {0}, dut[72] = {0}; /* du in [da; db] and in [ta; tb] (k x 12) */
  for (int c = 0; c < k && pd_kind; c++)
    for (int j = 0; j < 12; j++) {
      double pt_j = 0; /* (Phi^T [-AdBa, AdTbi])_cj */
      for (int l = 0; l < 6; l++)
        pt_j += pt.Phi[6 * l + c] * (j < 6 ? -pt.AdBa[6 * l + j] : AdTbi[6 * l + j - 6]);
      dup[12 * c + j] = -ac->kp[c] * dx[12 * c + j] - ac->kd[c] * dxd[12 * c + j];
      dut[12 * c + j] = -ac->kd[c] * pt_j;
    }
  for (int i = 0; i < 12; i++) {
    double acc = 0;
    for (int c = 0; c < k; c++) acc += B[k * i + c] * u[c];
    w[i] = acc;
    for (int j = 0; j < 12; j++) {
      double sx = 0, st = 0;
      for (int c = 0; c < k; c++) {
        sx += B[k * i + c] * dup[12 * c + j];
        st += B[k * i + c] * dut[12 * c + j];
      }
      Kx[12 * i + j] = Ku[12 * i + j] + sx;
      Kt[12 * i + j] = st;
    }
  }
}

void phm_applied_tangent(const phm_model *m, const phm_pair_data *pd, const double *H,
                         const double *tw, const double *xs, double time, double tref,
                         double scale, phm_tangent_sink sink, void *ctx) {
  double w[12], Kx[144], Kt[144];
  for (int ia = 0; ia < m->na; ia++) {
    const phm_pair_desc *pr = &m->pair[m->act[ia].pair];
    actuator_tangent(m, ia, pd, H, tw, xs, time, tref, scale, w, Kx, Kt);
    sink(ctx, pr->a, pr->b, w, Kx, Kt);
  }
  for (int il = 0; il < m->nl; il++) {
    const phm_load_desc *l = &m->load[il];
    double s = scale * phm_law_eval(&l->law, time, tref, NULL, NULL);
    if (s == 0) continue;
    load_tangent(m, il, H, s, w, Kx);
    sink(ctx, l->carrier, l->reaction, w, Kx, NULL);
  }
  for (int is = 0; is < m->ns; is++) {
    spring_tangent(&m->spr[is], H, tw, w, Kx, Kt);
    sink(ctx, m->spr[is].a, m->spr[is].b, w, Kx, Kt);
  }
}
