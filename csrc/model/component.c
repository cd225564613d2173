/* component.c -- components with internal states on a pair's joint coordinate (docs/method.md
 * section 4.11): friction (viscous, regularized Coulomb, Stribeck, LuGre with its bristle state),
 * the DC motor with gearbox (its current a state) and the linear state-space controller (its
 * states; it may measure another pair than it drives). Each is a port-Hamiltonian system whose
 * mechanical port is (u, v = xdot_c) of one coordinate; its internal states z are integrated by
 * the DAE after the joint coordinates (csrc/dae/dae.h). Here: validation and copy (grouped by
 * pair, so that each pair's states are consecutive), the motors' reflected inertia, the
 * constitutive laws with their closed-form derivatives, the wrenches and ledger terms, and the
 * tangent the DAE's Jacobian reads. Nothing here allocates after phm_components_copy. */
#include "model.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "law.h"
#include "linalg.h"
#include "phm_check.h"

static const char *const kind_name[PHM_NCOMP_KINDS] = {"viscous friction", "Coulomb friction",
                                                        "Stribeck friction", "LuGre friction",
                                                        "DC motor", "linear controller",
                                                        "callback controller",
                                                        "port-Hamiltonian controller"};

int phm_component_nstates(const phm_component_desc *c) {
  if (c->kind == PHM_COMP_LUGRE) return 1;
  if (c->kind == PHM_COMP_MOTOR) return c->input == 0 ? 1 : 0;
  if (c->kind == PHM_COMP_LINEAR || c->kind == PHM_COMP_PH) return c->nx;
  return 0;
}

/* par[i] is finite and >= lo (strict: > lo). */
static int par_ok(double v, double lo, int strict) { return isfinite(v) && (strict ? v > lo : v >= lo); }

phm_status phm_components_validate(const phm_model_desc *d, phm_error *err) {
  PHM_CHECK(d->ncomponents >= 0 && (d->ncomponents == 0 || d->components), err, PHM_EINVAL,
            "model description: a component count is positive but its array is NULL");
  for (int i = 0; i < d->ncomponents; i++) {
    const phm_component_desc *c = &d->components[i];
    PHM_CHECK(c->kind >= 0 && c->kind < PHM_NCOMP_KINDS, err, PHM_EINVAL,
              "component %d: kind %d out of range", i, c->kind);
    const char *kn = kind_name[c->kind];
    PHM_CHECK(c->pair >= 0 && c->pair < d->npairs, err, PHM_EINVAL,
              "component %d (%s): pair %d out of range", i, kn, c->pair);
    const char *tn = phm_pair_type(d->pairs[c->pair].type)->name;
    PHM_CHECK(!strcmp(tn, "revolute") || !strcmp(tn, "prismatic"), err, PHM_EINVAL,
              "component %d (%s): on a %s pair; friction and motors act on revolute and prismatic "
              "pairs only", i, kn, tn);
    PHM_CHECK(c->coord == 0, err, PHM_EINVAL, "component %d (%s): coordinate %d of a one-coordinate pair", i, kn, c->coord);
    const double *p = c->par;
    int ok = 1;
    switch (c->kind) {
    case PHM_COMP_VISCOUS: ok = par_ok(p[0], 0, 0); break;
    case PHM_COMP_COULOMB: ok = par_ok(p[0], 0, 0) && par_ok(p[1], 0, 1); break;
    case PHM_COMP_STRIBECK:
      ok = par_ok(p[0], 0, 0) && par_ok(p[1], 0, 0) && par_ok(p[2], 0, 1) && par_ok(p[3], 0, 0) &&
           par_ok(p[4], 0, 1);
      break;
    case PHM_COMP_LUGRE:
      ok = par_ok(p[0], 0, 1) && par_ok(p[1], 0, 0) && par_ok(p[2], 0, 0) && par_ok(p[3], 0, 1) &&
           par_ok(p[4], 0, 1) && par_ok(p[5], 0, 1);
      break;
    case PHM_COMP_LINEAR:
      ok = c->nx >= 0 && c->nx <= PHM_COMP_MAXZ && phm_all_finite(p, PHM_COMP_NPAR);
      if (c->spair >= 0) {
        PHM_CHECK(c->spair < d->npairs, err, PHM_EINVAL, "component %d (%s): sensor pair %d out of range", i, kn, c->spair);
        int ks = 6 - phm_pair_type(d->pairs[c->spair].type)->m;
        PHM_CHECK(c->scoord >= 0 && c->scoord < ks, err, PHM_EINVAL,
                  "component %d (%s): sensor coordinate %d of a pair with %d", i, kn, c->scoord, ks);
      }
      break;
    case PHM_COMP_CALLBACK: ok = c->fn != NULL; break;
    case PHM_COMP_PH: /* J skew, R and Q symmetric positive semidefinite: checked in Python */
      ok = c->nx >= 1 && c->nx <= PHM_COMP_PH_MAXZ && phm_all_finite(p, PHM_COMP_NPAR) &&
           p[3 * c->nx * c->nx + c->nx] >= 0;
      break;
    case PHM_COMP_MOTOR:
      ok = (c->input == 0 || c->input == 1) && par_ok(p[0], 0, c->input == 0) && par_ok(p[1], 0, 0) &&
           par_ok(p[2], 0, 1) && isfinite(p[3]) && p[3] != 0 && par_ok(p[4], 0, 1) && p[4] <= 1 &&
           par_ok(p[5], 0, 0);
      break;
    }
    PHM_CHECK(ok, err, PHM_EINVAL, "component %d (%s): a parameter is missing, not finite or out of "
              "range (docs/method.md section 4.11 lists them)", i, kn);
    PHM_CHECK(phm_all_finite(c->z0, PHM_COMP_MAXZ), err, PHM_EINVAL,
              "component %d (%s): non-finite initial state", i, kn);
  }
  return PHM_OK;
}

/* The unit effort's wrench directions of a revolute or prismatic pair's coordinate: its rate is
 * xdot = cb . t_b - ca . t_a with ca = Ad_{Ta^-1}^T Phi, cb = Ad_{Tb^-1}^T Phi, constant (the
 * joint axis is z in both frames, and rotation about z, translation along z, leave the axis'
 * rate component alone). */
static void rate_rows(const phm_model *m, int ip, double ca[6], double cb[6]) {
  const phm_pair_desc *pr = &m->pair[ip];
  double I[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, Phi[36], Ti[16], A[36];
  phm_pair_kin(pr->type, pr->pitch, I, NULL, NULL, NULL, Phi, NULL);
  double ph[6];
  for (int i = 0; i < 6; i++) ph[i] = Phi[6 * i];
  phm_se3_inverse(pr->Ta, Ti);
  phm_se3_Ad(Ti, A);
  phm_mtv6(A, ph, ca);
  phm_mtv6(m->pair_AdTbi + 36 * ip, ph, cb);
}

int phm_components_ncouplings(const phm_model_desc *d) {
  int n = 0;
  for (int i = 0; i < d->ncomponents; i++) {
    const phm_component_desc *c = &d->components[i];
    n += c->kind == PHM_COMP_MOTOR && c->par[5] > 0 && d->pairs[c->pair].a >= 0 &&
         d->pairs[c->pair].b >= 0;
  }
  return n;
}

void phm_components_inertia(phm_model *m, int k0) {
  int k = k0;
  for (int i = 0; i < m->ncomp; i++) {
    const phm_component_desc *c = &m->comp[i];
    if (c->kind != PHM_COMP_MOTOR || !(c->par[5] > 0)) continue;
    double Jr = c->par[5] * c->par[3] * c->par[3], ca[6], cb[6];
    const phm_pair_desc *pr = &m->pair[c->pair];
    rate_rows(m, c->pair, ca, cb);
    if (pr->a >= 0 && pr->b >= 0) { /* T = 1/2 Jr (cb . tb - ca . ta)^2 */
      double r[12];
      for (int j = 0; j < 6; j++) {
        r[j] = -ca[j];
        r[6 + j] = cb[j];
      }
      m->mc_a[k] = pr->a;
      m->mc_b[k] = pr->b;
      for (int a = 0; a < 12; a++)
        for (int b = 0; b < 12; b++) m->mc[144 * (size_t)k + 12 * a + b] = Jr * r[a] * r[b];
      k++;
    } else { /* one side on the ground: the other carrier's inertia */
      int cc = pr->b >= 0 ? pr->b : pr->a;
      const double *r = pr->b >= 0 ? cb : ca;
      if (cc < 0) continue;
      for (int a = 0; a < 6; a++)
        for (int b = 0; b < 6; b++) m->car[cc].M[6 * a + b] += Jr * r[a] * r[b];
    }
  }
}

int phm_components_copy(phm_model *m, const phm_model_desc *d) {
  int n = d->ncomponents;
  m->ncomp = n;
  m->comp = malloc(sizeof *m->comp * (size_t)(n + 1));
  m->comp_z = malloc(sizeof(int) * (size_t)(n + 1));
  m->pair_z = calloc((size_t)(m->np + 1), sizeof(int));
  m->pair_nz = calloc((size_t)(m->np + 1), sizeof(int));
  if (!m->comp || !m->comp_z || !m->pair_z || !m->pair_nz) return -1;
  /* grouped by pair, in the given order within a pair (a stable counting sort) */
  int k = 0, z = 0;
  for (int ip = 0; ip < m->np; ip++) {
    m->pair_z[ip] = z;
    for (int i = 0; i < n; i++) {
      if (d->components[i].pair != ip) continue;
      m->comp[k] = d->components[i];
      m->comp_z[k] = z;
      z += phm_component_nstates(&m->comp[k]);
      k++;
    }
    m->pair_nz[ip] = z - m->pair_z[ip];
  }
  m->nz = z;
  return 0;
}

int phm_components_sensor_edges(const phm_model *m, int *ea, int *eb, int pairs) {
  int k = 0;
  for (int i = 0; i < m->ncomp; i++) {
    const phm_component_desc *c = &m->comp[i];
    if (c->kind != PHM_COMP_LINEAR || c->spair < 0 || c->spair == c->pair) continue;
    const phm_pair_desc *pa = &m->pair[c->pair], *ps = &m->pair[c->spair];
    int ca[2] = {pa->a, pa->b}, cs[2] = {ps->a, ps->b};
    for (int r = 0; r < 2; r++)
      for (int s = 0; s < 2; s++) { /* the driven carriers' forces move with the sensed ones */
        if (ea) { ea[k] = ca[r]; eb[k] = cs[s]; }
        k++;
      }
    for (int s = 0; pairs && s < 2; s++) { /* the states (the driven pair's vertex) too */
      if (ea) { ea[k] = m->nc + c->pair; eb[k] = cs[s]; }
      k++;
    }
  }
  return k;
}

/* g(v) = Fc + (Fs - Fc) exp(-(v/vs)^2) and its derivative */
static double stribeck(double Fc, double Fs, double vs, double v, double *dg) {
  double r = v / vs, e = exp(-r * r);
  *dg = (Fs - Fc) * e * (-2.0 * r / vs);
  return Fc + (Fs - Fc) * e;
}

void phm_component_eval(const phm_component_desc *c, double x, double v, const double *z,
                        double time, double tref, phm_comp_eval *e) {
  const double *p = c->par;
  (void)x;
  memset(e, 0, sizeof *e);
  switch (c->kind) {
  case PHM_COMP_VISCOUS:
    e->u = -p[0] * v;
    e->du_v = -p[0];
    e->Pd = p[0] * v * v;
    break;
  case PHM_COMP_COULOMB: {
    double th = tanh(v / p[1]);
    e->u = -p[0] * th;
    e->du_v = -p[0] * (1 - th * th) / p[1];
    e->Pd = -e->u * v;
    break;
  }
  case PHM_COMP_STRIBECK: {
    double dg, g = stribeck(p[0], p[1], p[2], v, &dg), th = tanh(v / p[4]);
    e->u = -g * th - p[3] * v;
    e->du_v = -dg * th - g * (1 - th * th) / p[4] - p[3];
    e->Pd = -e->u * v;
    break;
  }
  case PHM_COMP_LUGRE: { /* z' = v - s0 |v| z / g(v); F = s0 z + s1 z' + s2 v; u = -F */
    double s0 = p[0], s1 = p[1], s2 = p[2], dg, g = stribeck(p[3], p[4], p[5], v, &dg);
    double av = fabs(v), sv = (v > 0) - (v < 0), zz = z[0];
    double f = v - s0 * av * zz / g;
    double f_v = 1.0 - s0 * zz * (sv * g - av * dg) / (g * g), f_z = -s0 * av / g;
    double F = s0 * zz + s1 * f + s2 * v;
    e->f[0] = f;
    e->df_v[0] = f_v;
    e->df_z[0] = f_z;
    e->u = -F;
    e->du_v = -(s1 * f_v + s2);
    e->du_z[0] = -(s0 + s1 * f_z);
    e->V = 0.5 * s0 * zz * zz;
    e->Pd = F * v - s0 * zz * f; /* the power F v it takes less the rate of its storage */
    break;
  }
  case PHM_COMP_MOTOR: { /* L i' = V - R i - k n v; u = eta n k i */
    double L = p[0], R = p[1], k = p[2], n = p[3], eta = p[4];
    double di = 0, s = phm_law_eval(&c->law, time, tref, &di, NULL), i, V;
    if (c->input == 0) {
      i = z[0];
      V = s;
      e->f[0] = (V - R * i - k * n * v) / L;
      e->df_v[0] = -k * n / L;
      e->df_z[0] = -R / L;
      e->du_z[0] = eta * n * k;
    } else {
      i = s;
      V = R * i + L * di + k * n * v;
    }
    e->u = eta * n * k * i;
    e->V = 0.5 * L * i * i;
    e->Ps = V * i;
    e->Pd = R * i * i + (1 - eta) * n * k * i * v; /* copper, and the gear's loss */
    break;
  }
  case PHM_COMP_LINEAR: { /* xc' = A xc + B y, u = C xc + D y, y = (x - r(t), v) */
    int nx = c->nx;
    const double *A = p, *B = p + nx * nx, *C = B + 2 * nx, *D = C + nx;
    double r = phm_law_eval(&c->law, time, tref, NULL, NULL), y0 = x - r;
    for (int i = 0; i < nx; i++) {
      double f = B[2 * i] * y0 + B[2 * i + 1] * v;
      for (int j = 0; j < nx; j++) {
        f += A[nx * i + j] * z[j];
        e->df_z[PHM_COMP_MAXZ * i + j] = A[nx * i + j];
      }
      e->f[i] = f;
      e->df_x[i] = B[2 * i];
      e->df_v[i] = B[2 * i + 1];
      e->du_z[i] = C[i];
    }
    e->u = D[0] * y0 + D[1] * v;
    for (int i = 0; i < nx; i++) e->u += C[i] * z[i];
    e->du_x = D[0];
    e->du_v = D[1]; /* its power, u times the driven rate, is phm_components_apply's */
    break;
  }
  case PHM_COMP_CALLBACK: { /* u = fn(t, x, v); its derivatives: phm_component_tangent's */
    double out[3] = {0, 0, 0};
    e->u = c->fn(c->ctx, time, x, v, 0, out) ? NAN : out[0];
    break;
  }
  case PHM_COMP_PH: { /* e = xc - xc*: xc' = (J - R) Q e + B v, u = -B^T Q e - d v */
    int nx = c->nx;
    const double *J = p, *R = J + nx * nx, *Q = R + nx * nx, *B = Q + nx * nx;
    double d = B[nx], ee[PHM_COMP_PH_MAXZ], Qe[PHM_COMP_PH_MAXZ];
    const double *xs = B + nx + 1;
    for (int i = 0; i < nx; i++) ee[i] = z[i] - xs[i];
    for (int i = 0; i < nx; i++) {
      Qe[i] = 0;
      for (int j = 0; j < nx; j++) Qe[i] += Q[nx * i + j] * ee[j];
    }
    e->u = -d * v;
    e->du_v = -d;
    e->Pd = d * v * v;
    for (int i = 0; i < nx; i++) {
      double f = B[i] * v;
      for (int j = 0; j < nx; j++) {
        double a = 0; /* ((J - R) Q)_ij */
        for (int k = 0; k < nx; k++) a += (J[nx * i + k] - R[nx * i + k]) * Q[nx * k + j];
        f += a * ee[j];
        e->df_z[PHM_COMP_MAXZ * i + j] = a;
        e->Pd += Qe[i] * R[nx * i + j] * Qe[j];
      }
      e->f[i] = f;
      e->df_v[i] = B[i];
      e->u -= B[i] * Qe[i];
      e->V += 0.5 * ee[i] * Qe[i];
    }
    for (int j = 0; j < nx; j++) { /* du/dz_j = -(B^T Q)_j */
      double s = 0;
      for (int i = 0; i < nx; i++) s += B[i] * Q[nx * i + j];
      e->du_z[j] = -s;
    }
    break; /* passive: no source (Ps = 0); dV/dt = -u v - Pd */
  }
  }
}

/* A callback controller's evaluation with its derivatives du/dx, du/dv (its function asked with
 * nder 1: one call where phm_component_eval and a second call for them would take two). */
static void callback_eval(const phm_component_desc *c, double x, double v, double time,
                          phm_comp_eval *e) {
  double out[3] = {0, 0, 0};
  memset(e, 0, sizeof *e);
  if (c->fn(c->ctx, time, x, v, 1, out)) out[0] = out[1] = out[2] = NAN;
  e->u = out[0];
  e->du_x = out[1];
  e->du_v = out[2];
}

/* Pair ip's evaluation: pd's, or *own evaluated at H, tw, xs (joint coordinates and rates). */
static const phm_pair_data *pair_at(const phm_model *m, int ip, const phm_pair_data *pd,
                                    const double *H, const double *tw, const double *xs,
                                    double time, double tref, phm_pair_data *own) {
  if (pd) return pd + ip;
  const phm_pair_desc *pr = &m->pair[ip];
  phm_pair_evaluate(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                    (tw && pr->a >= 0) ? tw + 6 * pr->a : NULL, (tw && pr->b >= 0) ? tw + 6 * pr->b : NULL,
                    xs ? xs + m->pair_j[ip] : NULL, time, tref, PHM_PAIR_JOINT, own);
  return own;
}

static const double *comp_states(const phm_model *m, int ic, const double *z) {
  return z ? z + m->comp_z[ic] : m->comp[ic].z0;
}

/* The pair and coordinate a component measures: its sensor's (LINEAR with spair >= 0), else its
 * own. */
static void sensor_of(const phm_component_desc *c, int *ip, int *cc) {
  int own = c->kind != PHM_COMP_LINEAR || c->spair < 0;
  *ip = own ? c->pair : c->spair;
  *cc = own ? c->coord : c->scoord;
}

void phm_components_apply(const phm_model *m, const phm_pair_data *pd, const double *H,
                          const double *tw, const double *xs, const double *z, const double *zp,
                          double time, double tref, double *wr, double *effort, double *Fz,
                          double *V, double *Pd, double *Ps) {
  for (int ic = 0; ic < m->ncomp; ic++) {
    const phm_component_desc *c = &m->comp[ic];
    int sp, sc;
    sensor_of(c, &sp, &sc);
    phm_pair_data own, sown;
    const phm_pair_data *p = pair_at(m, c->pair, pd, H, tw, xs, time, tref, &own);
    const phm_pair_data *ps = sp == c->pair ? p : pair_at(m, sp, pd, H, tw, xs, time, tref, &sown);
    phm_comp_eval e;
    phm_component_eval(c, ps->x[sc], ps->xdot[sc], comp_states(m, ic, z), time, tref, &e);
    double u[6] = {0};
    u[c->coord] = e.u;
    if (wr) phm_pair_effort_wrench(m, c->pair, p, u, wr);
    if (effort) effort[m->pair_j[c->pair] + c->coord] += e.u;
    int nzc = phm_component_nstates(c), z0 = m->comp_z[ic];
    if (Fz)
      for (int j = 0; j < nzc; j++) Fz[z0 + j] = zp[z0 + j] - e.f[j];
    if (V) *V += e.V;
    if (Pd) *Pd += e.Pd;
    /* a controller's power is its effort's on the pair it drives (a source, as an actuator) */
    if (Ps) *Ps += c->kind == PHM_COMP_LINEAR || c->kind == PHM_COMP_CALLBACK ? e.u * p->xdot[c->coord] : e.Ps;
  }
}

/* B = [-AdBa^T Phi_c; AdTbi^T Phi_c] (12) of pair ip's coordinate cc at its evaluation t: the
 * wrenches of a unit effort on (a, b), and the coordinate's rate in [ta; tb] (B^T). */
static void effort_rows(const phm_model *m, int ip, int cc, const phm_pair_data *t, double B[12]) {
  const double *AdTbi = m->pair_AdTbi + 36 * ip;
  for (int i = 0; i < 6; i++) {
    double sa = 0, sb = 0;
    for (int l = 0; l < 6; l++) {
      sa += t->AdBa[6 * l + i] * t->Phi[6 * l + cc];
      sb += AdTbi[6 * l + i] * t->Phi[6 * l + cc];
    }
    B[i] = -sa;
    B[6 + i] = sb;
  }
}

/* Pair ip's tangent at the state (poses, twists, branch references xs) with efforts u: its
 * evaluation with derivatives *t, dx and dxd (k x 12) and Ku (12 x 12; u may be NULL). */
static void pair_tangent_at(const phm_model *m, int ip, const double *H, const double *tw,
                            const double *xs, double time, double tref, const double *u,
                            phm_pair_data *t, double dx[72], double dxd[72], double Ku[144]) {
  const phm_pair_desc *pr = &m->pair[ip];
  phm_pair_tangent(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                   (tw && pr->a >= 0) ? tw + 6 * pr->a : NULL, (tw && pr->b >= 0) ? tw + 6 * pr->b : NULL,
                   xs ? xs + m->pair_j[ip] : NULL, time, tref, NULL, NULL, u, t, NULL, NULL, dx, dxd,
                   NULL, NULL, u ? Ku : NULL);
}

void phm_component_tangent(const phm_model *m, int ic, const phm_pair_data *pd, const double *H,
                           const double *tw, const double *xs, const double *z, double time,
                           double tref, double w[12], double Ku[144], double B[12], double gq[12],
                           double gt[12], double *Kz, double *Fx, double *Ft, double *Fz) {
  const phm_component_desc *c = &m->comp[ic];
  int ip = c->pair, nzc = phm_component_nstates(c), sp, sc;
  sensor_of(c, &sp, &sc);
  phm_pair_data own, sown;
  const phm_pair_data *p = pair_at(m, ip, pd, H, tw, xs, time, tref, &own);
  const phm_pair_data *ps = sp == ip ? p : pair_at(m, sp, pd, H, tw, xs, time, tref, &sown);
  phm_comp_eval e;
  if (c->kind == PHM_COMP_CALLBACK) callback_eval(c, ps->x[sc], ps->xdot[sc], time, &e);
  else phm_component_eval(c, ps->x[sc], ps->xdot[sc], comp_states(m, ic, z), time, tref, &e);
  double u[6] = {0}, dx[72], dxd[72], Bs[12];
  u[c->coord] = e.u;
  phm_pair_data t, ts;
  pair_tangent_at(m, ip, H, tw, xs, time, tref, u, &t, dx, dxd, Ku);
  effort_rows(m, ip, c->coord, &t, B);
  if (sp != ip) pair_tangent_at(m, sp, H, tw, xs, time, tref, NULL, &ts, dx, dxd, NULL);
  effort_rows(m, sp, sc, sp != ip ? &ts : &t, Bs); /* the measured rate: Bs^T [ta; tb] */
  for (int i = 0; i < 12; i++) {
    w[i] = B[i] * e.u;
    for (int j = 0; j < nzc; j++) Kz[nzc * i + j] = B[i] * e.du_z[j];
  }
  for (int j = 0; j < 12; j++) { /* du in the sensor pair's [da; db] and [ta; tb] */
    gq[j] = e.du_x * dx[12 * sc + j] + e.du_v * dxd[12 * sc + j];
    gt[j] = e.du_v * Bs[j];
  }
  for (int r = 0; r < nzc; r++) {
    for (int j = 0; j < 12; j++) {
      Fx[12 * r + j] = e.df_x[r] * dx[12 * sc + j] + e.df_v[r] * dxd[12 * sc + j];
      Ft[12 * r + j] = e.df_v[r] * Bs[j];
    }
    for (int j = 0; j < nzc; j++) Fz[nzc * r + j] = e.df_z[PHM_COMP_MAXZ * r + j];
  }
}
