/* model.c -- the immutable model: carriers, se3 beam elements, kinematic pairs, applied loads,
 * time laws; the kernels used by the DAE residual, linearization and statics. */
#include "model_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* ---------------------------------------------------------------- small dense helpers */
static void mv6(const double A[36], const double x[6], double y[6]) { /* y = A x */
  for (int i = 0; i < 6; i++) {
    double s = 0;
    for (int j = 0; j < 6; j++) s += A[6 * i + j] * x[j];
    y[i] = s;
  }
}
static void mtv6(const double A[36], const double x[6], double y[6]) { /* y = A^T x */
  for (int i = 0; i < 6; i++) {
    double s = 0;
    for (int j = 0; j < 6; j++) s += A[6 * j + i] * x[j];
    y[i] = s;
  }
}
static double dot(const double *a, const double *b, int n) {
  double s = 0;
  for (int i = 0; i < n; i++) s += a[i] * b[i];
  return s;
}

/* ---------------------------------------------------------------- time laws */
double phm_law_eval(const phm_law *l, double t, double tref, double *ds, double *dds) {
  double s = 0, d1 = 0, d2 = 0;
  switch (l->kind) {
  case PHM_LAW_CONSTANT: s = l->amplitude; break;
  case PHM_LAW_STEP: s = tref >= l->t0 ? l->amplitude : 0.0; break;
  case PHM_LAW_PULSE: s = (tref >= l->t0 && tref < l->t0 + l->duration) ? l->amplitude : 0.0; break;
  case PHM_LAW_SINE: {
    double w = 2 * PI * l->frequency, a = w * t + l->phase;
    s = l->offset + l->amplitude * sin(a);
    d1 = l->amplitude * w * cos(a);
    d2 = -l->amplitude * w * w * sin(a);
  } break;
  case PHM_LAW_TABLE: {
    const double *T = l->table;
    int n = l->ntable;
    if (n == 1 || tref < T[0]) {
      s = T[1];
    } else if (tref >= T[2 * (n - 1)]) {
      s = T[2 * (n - 1) + 1];
    } else {
      int i = 0;
      while (i < n - 2 && tref >= T[2 * (i + 1)]) i++;
      double slope = (T[2 * i + 3] - T[2 * i + 1]) / (T[2 * i + 2] - T[2 * i]);
      s = T[2 * i + 1] + slope * (t - T[2 * i]);
      d1 = slope;
    }
  } break;
  case PHM_LAW_CYCLOIDAL: {
    if (tref < l->t0) {
      s = 0;
    } else if (tref >= l->t0 + l->duration) {
      s = l->amplitude;
    } else {
      double u = (t - l->t0) / l->duration, A = l->amplitude, T = l->duration;
      s = A * (u - sin(2 * PI * u) / (2 * PI));
      d1 = A / T * (1 - cos(2 * PI * u));
      d2 = A / (T * T) * 2 * PI * sin(2 * PI * u);
    }
  } break;
  default: break;
  }
  if (ds) *ds = d1;
  if (dds) *dds = d2;
  return s;
}

static int law_breakpoints(const phm_law *l, double *out) { /* out may be NULL: count only */
  int n = 0;
  switch (l->kind) {
  case PHM_LAW_STEP:
    if (out) out[n] = l->t0;
    n++;
    break;
  case PHM_LAW_PULSE:
  case PHM_LAW_CYCLOIDAL:
    if (out) { out[n] = l->t0; out[n + 1] = l->t0 + l->duration; }
    n += 2;
    break;
  case PHM_LAW_TABLE:
    for (int i = 0; i < l->ntable; i++) {
      if (out) out[n] = l->table[2 * i];
      n++;
    }
    break;
  default: break;
  }
  return n;
}

static phm_status law_check(const phm_law *l, const char *what, int idx, phm_error *err) {
  double v[6] = {l->amplitude, l->t0, l->duration, l->frequency, l->phase, l->offset};
  for (int i = 0; i < 6; i++)
    if (!isfinite(v[i])) return phm_error_set(err, PHM_EINVAL, "%s %d: time law has a non-finite parameter", what, idx);
  switch (l->kind) {
  case PHM_LAW_CONSTANT: case PHM_LAW_STEP: case PHM_LAW_SINE: return PHM_OK;
  case PHM_LAW_PULSE: case PHM_LAW_CYCLOIDAL:
    if (!(l->duration > 0))
      return phm_error_set(err, PHM_EINVAL, "%s %d: time law duration must be > 0 (got %g s)", what, idx, l->duration);
    return PHM_OK;
  case PHM_LAW_TABLE:
    if (l->ntable < 1 || !l->table)
      return phm_error_set(err, PHM_EINVAL, "%s %d: table law needs at least one (t, value) point", what, idx);
    for (int i = 0; i < l->ntable; i++) {
      if (!isfinite(l->table[2 * i]) || !isfinite(l->table[2 * i + 1]))
        return phm_error_set(err, PHM_EINVAL, "%s %d: table law has a non-finite entry", what, idx);
      if (i > 0 && !(l->table[2 * i] > l->table[2 * i - 2]))
        return phm_error_set(err, PHM_EINVAL, "%s %d: table law times must be strictly increasing", what, idx);
    }
    return PHM_OK;
  default:
    return phm_error_set(err, PHM_EINVAL, "%s %d: unknown time law kind %d", what, idx, l->kind);
  }
}

/* ---------------------------------------------------------------- pair types */
const phm_pair_type_info phm_pair_types[] = {
    {"fixed", 6},     {"revolute", 5},  {"prismatic", 5}, {"helical", 5}, {"cylindrical", 4},
    {"universal", 4}, {"spherical", 3}, {"planar", 3},    {"free", 0},
};
const int phm_npair_types = (int)(sizeof phm_pair_types / sizeof phm_pair_types[0]);

static double wrap_pi(double a) { return a - 2 * PI * floor((a + PI) / (2 * PI)); }
static double near_angle(double a, const double *xref, int i) { return xref ? xref[i] + wrap_pi(a - xref[i]) : a; }

/* Column c of a 6x6 row-major basis: set entries (rows r0..r0+2) to v. */
static void setcol(double *B, int c, int r0, double v0, double v1, double v2) {
  B[6 * r0 + c] = v0;
  B[6 * (r0 + 1) + c] = v1;
  B[6 * (r0 + 2) + c] = v2;
}

/* Position constraints are written so that dg = W^T t_rel at g = 0 (up to a unit-triangular
 * factor for helical/cylindrical): rotations through the z axis of F_a seen in F_b, R^T e_z, whose
 * rate is e_z x omega; translations through R^T p (rate v - omega x R^T p) or p (rate R v). */
void phm_pair_kin(int type, double pitch, const double h[16], const double *xref, double *g,
                  double *W, double *Phi, double *x) {
#define R(i, j) h[4 * (i) + (j)]
  double p[3] = {h[3], h[7], h[11]}, q[3]; /* q = R^T p */
  for (int i = 0; i < 3; i++) q[i] = R(0, i) * p[0] + R(1, i) * p[1] + R(2, i) * p[2];
  double gg[6] = {0}, xx[6] = {0}, Wl[36] = {0}, Pl[36] = {0};
  double th = atan2(R(1, 0), R(0, 0));
  switch (type) {
  case PHM_PAIR_FIXED:
    phm_se3_log(h, gg);
    for (int i = 0; i < 6; i++) Wl[7 * i] = 1;
    break;
  case PHM_PAIR_REVOLUTE:
    gg[0] = R(2, 1); gg[1] = -R(2, 0); gg[2] = q[0]; gg[3] = q[1]; gg[4] = q[2];
    setcol(Wl, 0, 0, 1, 0, 0); setcol(Wl, 1, 0, 0, 1, 0);
    setcol(Wl, 2, 3, 1, 0, 0); setcol(Wl, 3, 3, 0, 1, 0); setcol(Wl, 4, 3, 0, 0, 1);
    setcol(Pl, 0, 0, 0, 0, 1);
    xx[0] = near_angle(th, xref, 0);
    break;
  case PHM_PAIR_PRISMATIC: {
    double Rm[9], w[3];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) Rm[3 * i + j] = R(i, j);
    phm_so3_log(Rm, w);
    gg[0] = w[0]; gg[1] = w[1]; gg[2] = w[2]; gg[3] = p[0]; gg[4] = p[1];
    setcol(Wl, 0, 0, 1, 0, 0); setcol(Wl, 1, 0, 0, 1, 0); setcol(Wl, 2, 0, 0, 0, 1);
    setcol(Wl, 3, 3, 1, 0, 0); setcol(Wl, 4, 3, 0, 1, 0);
    setcol(Pl, 0, 3, 0, 0, 1);
    xx[0] = p[2];
  } break;
  case PHM_PAIR_HELICAL: {
    double a = near_angle(th, xref, 0), s = 1.0 / sqrt(1 + pitch * pitch), s2 = 1.0 / (1 + pitch * pitch);
    gg[0] = R(2, 1); gg[1] = -R(2, 0); gg[2] = q[0]; gg[3] = q[1]; gg[4] = s * (q[2] - pitch * a);
    setcol(Wl, 0, 0, 1, 0, 0); setcol(Wl, 1, 0, 0, 1, 0);
    setcol(Wl, 2, 3, 1, 0, 0); setcol(Wl, 3, 3, 0, 1, 0);
    setcol(Wl, 4, 0, 0, 0, -pitch * s); setcol(Wl, 4, 3, 0, 0, s);
    setcol(Pl, 0, 0, 0, 0, s2); setcol(Pl, 0, 3, 0, 0, pitch * s2);
    xx[0] = a;
  } break;
  case PHM_PAIR_CYLINDRICAL:
    gg[0] = R(2, 1); gg[1] = -R(2, 0); gg[2] = q[0]; gg[3] = q[1];
    setcol(Wl, 0, 0, 1, 0, 0); setcol(Wl, 1, 0, 0, 1, 0);
    setcol(Wl, 2, 3, 1, 0, 0); setcol(Wl, 3, 3, 0, 1, 0);
    setcol(Pl, 0, 0, 0, 0, 1); setcol(Pl, 1, 3, 0, 0, 1);
    xx[0] = near_angle(th, xref, 0);
    xx[1] = q[2];
    break;
  case PHM_PAIR_UNIVERSAL:
    /* a = R^T e_x (first axis seen in F_b), second axis e_y; x of F_a stays normal to y of F_b */
    gg[0] = -R(0, 1); gg[1] = q[0]; gg[2] = q[1]; gg[3] = q[2];
    setcol(Wl, 0, 0, -R(0, 2), 0, R(0, 0)); /* a x e_y */
    setcol(Wl, 1, 3, 1, 0, 0); setcol(Wl, 2, 3, 0, 1, 0); setcol(Wl, 3, 3, 0, 0, 1);
    setcol(Pl, 0, 0, R(0, 0), R(0, 1), R(0, 2)); setcol(Pl, 1, 0, 0, 1, 0);
    xx[0] = near_angle(atan2(R(2, 1), R(1, 1)), xref, 0);
    xx[1] = near_angle(atan2(R(0, 2), R(0, 0)), xref, 1);
    break;
  case PHM_PAIR_SPHERICAL: {
    double Rm[9];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) Rm[3 * i + j] = R(i, j);
    phm_so3_log(Rm, xx);
    gg[0] = q[0]; gg[1] = q[1]; gg[2] = q[2];
    setcol(Wl, 0, 3, 1, 0, 0); setcol(Wl, 1, 3, 0, 1, 0); setcol(Wl, 2, 3, 0, 0, 1);
    setcol(Pl, 0, 0, 1, 0, 0); setcol(Pl, 1, 0, 0, 1, 0); setcol(Pl, 2, 0, 0, 0, 1);
  } break;
  case PHM_PAIR_PLANAR:
    gg[0] = R(2, 1); gg[1] = -R(2, 0); gg[2] = p[2];
    setcol(Wl, 0, 0, 1, 0, 0); setcol(Wl, 1, 0, 0, 1, 0); setcol(Wl, 2, 3, 0, 0, 1);
    setcol(Pl, 0, 0, 0, 0, 1);
    setcol(Pl, 1, 3, R(0, 0), R(0, 1), R(0, 2)); setcol(Pl, 2, 3, R(1, 0), R(1, 1), R(1, 2));
    xx[0] = near_angle(th, xref, 0);
    xx[1] = p[0];
    xx[2] = p[1];
    break;
  case PHM_PAIR_FREE:
  default: {
    double Rm[9];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) Rm[3 * i + j] = R(i, j);
    phm_so3_log(Rm, xx);
    xx[3] = p[0]; xx[4] = p[1]; xx[5] = p[2];
    setcol(Pl, 0, 0, 1, 0, 0); setcol(Pl, 1, 0, 0, 1, 0); setcol(Pl, 2, 0, 0, 0, 1);
    for (int j = 0; j < 3; j++) setcol(Pl, 3 + j, 3, R(j, 0), R(j, 1), R(j, 2));
  } break;
  }
#undef R
  int mm = (type >= 0 && type < phm_npair_types) ? phm_pair_types[type].m : 0;
  if (g) memcpy(g, gg, sizeof(double) * (size_t)mm);
  if (x) memcpy(x, xx, sizeof(double) * (size_t)(6 - mm));
  if (W) memcpy(W, Wl, sizeof Wl);
  if (Phi) memcpy(Phi, Pl, sizeof Pl);
}

/* ---------------------------------------------------------------- model */
static int finite_n(const double *x, int n) {
  for (int i = 0; i < n; i++)
    if (!isfinite(x[i])) return 0;
  return 1;
}

static phm_status check_pose(const double H[16], const char *what, int idx, phm_error *err) {
  if (!finite_n(H, 16)) return phm_error_set(err, PHM_EINVAL, "%s %d: pose has a non-finite entry", what, idx);
  double e = 0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double s = 0;
      for (int k = 0; k < 3; k++) s += H[4 * k + i] * H[4 * k + j];
      e = fmax(e, fabs(s - (i == j)));
    }
  double det = H[0] * (H[5] * H[10] - H[6] * H[9]) - H[1] * (H[4] * H[10] - H[6] * H[8]) +
               H[2] * (H[4] * H[9] - H[5] * H[8]);
  if (e > 1e-6 || det < 0)
    return phm_error_set(err, PHM_EINVAL, "%s %d: pose rotation is not orthonormal with det +1 (|R^T R - I| = %.2e)", what, idx, e);
  if (fabs(H[12]) + fabs(H[13]) + fabs(H[14]) + fabs(H[15] - 1) > 1e-12)
    return phm_error_set(err, PHM_EINVAL, "%s %d: pose last row must be (0, 0, 0, 1)", what, idx);
  return PHM_OK;
}

/* Cholesky test: symmetric positive (semi)definite within a relative tolerance. */
static int spd6(const double A[36], int semi) {
  double L[36] = {0}, scale = 0;
  for (int i = 0; i < 6; i++) scale = fmax(scale, fabs(A[7 * i]));
  for (int i = 0; i < 6; i++)
    for (int j = 0; j < 6; j++)
      if (fabs(A[6 * i + j] - A[6 * j + i]) > 1e-9 * (scale + 1e-300)) return 0;
  if (semi) {
    for (int i = 0; i < 6; i++)
      if (A[7 * i] < 0) return 0;
    /* semidefinite: test A + tiny I */
  }
  for (int j = 0; j < 6; j++) {
    double d = A[7 * j] + (semi ? 1e-12 * scale + 1e-300 : 0);
    for (int k = 0; k < j; k++) d -= L[6 * j + k] * L[6 * j + k];
    if (!(d > 0)) return 0;
    L[7 * j] = sqrt(d);
    for (int i = j + 1; i < 6; i++) {
      double s = A[6 * i + j];
      for (int k = 0; k < j; k++) s -= L[6 * i + k] * L[6 * j + k];
      L[6 * i + j] = s / L[7 * j];
    }
  }
  return 1;
}

void phm_model_free(phm_model *m) {
  if (!m) return;
  free(m->car);
  free(m->el);
  free(m->pair);
  free(m->pair_row);
  free(m->pair_m);
  free(m->pair_j);
  free(m->pair_k);
  free(m->pair_sel);
  free(m->pair_rowf);
  free(m->pair_AdTbi);
  free(m->xref0);
  free(m->act);
  free(m->spr);
  free(m->load);
  free(m->bp);
  free(m->tables);
  free(m);
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

phm_status phm_model_create(const phm_model_desc *d, phm_model **out, phm_error *err) {
  phm_error_clear(err);
  if (!d || !out) return phm_error_set(err, PHM_EINVAL, "phm_model_create: NULL argument");
  *out = NULL;
  if (d->ncarriers < 1) return phm_error_set(err, PHM_EINVAL, "model has no carrier (body or beam node)");
  if (d->nelements < 0 || d->npairs < 0 || d->nloads < 0)
    return phm_error_set(err, PHM_EINVAL, "negative element, pair or load count");
  if (!finite_n(d->gravity, 3)) return phm_error_set(err, PHM_EINVAL, "gravity has a non-finite entry");
  phm_status st;
  for (int i = 0; i < d->ncarriers; i++) {
    const phm_carrier_desc *c = &d->carriers[i];
    if (!finite_n(c->M, 36) || !isfinite(c->mass) || !finite_n(c->com, 3) || !finite_n(c->t0, 6))
      return phm_error_set(err, PHM_EINVAL, "carrier %d: non-finite inertia, mass, centre of mass or twist", i);
    if (!(c->mass > 0)) return phm_error_set(err, PHM_EINVAL, "carrier %d: mass must be > 0 (got %g kg)", i, c->mass);
    if (!spd6(c->M, 0)) return phm_error_set(err, PHM_EINVAL, "carrier %d: spatial inertia is not symmetric positive definite", i);
    if ((st = check_pose(c->H0, "carrier", i, err))) return st;
  }
  for (int i = 0; i < d->nelements; i++) {
    const phm_element_desc *e = &d->elements[i];
    if (e->a < 0 || e->a >= d->ncarriers || e->b < 0 || e->b >= d->ncarriers || e->a == e->b)
      return phm_error_set(err, PHM_EINVAL, "element %d: carriers (%d, %d) out of range or equal", i, e->a, e->b);
    if (!(e->h > 0) || !isfinite(e->h)) return phm_error_set(err, PHM_EINVAL, "element %d: length must be > 0 (got %g m)", i, e->h);
    if (!finite_n(e->K, 36) || !finite_n(e->D, 36) || !finite_n(e->eps_hat, 6))
      return phm_error_set(err, PHM_EINVAL, "element %d: non-finite stiffness, damping or unstressed strain", i);
    if (!spd6(e->K, 0)) return phm_error_set(err, PHM_EINVAL, "element %d: section stiffness is not symmetric positive definite", i);
    if (!spd6(e->D, 1)) return phm_error_set(err, PHM_EINVAL, "element %d: section damping is not symmetric positive semidefinite", i);
  }
  for (int i = 0; i < d->npairs; i++) {
    const phm_pair_desc *p = &d->pairs[i];
    if (p->type < 0 || p->type >= phm_npair_types) return phm_error_set(err, PHM_EINVAL, "pair %d: unknown pair type %d", i, p->type);
    if (p->a < -1 || p->a >= d->ncarriers || p->b < -1 || p->b >= d->ncarriers || p->a == p->b)
      return phm_error_set(err, PHM_EINVAL, "pair %d: carriers (%d, %d) out of range or equal", i, p->a, p->b);
    if ((st = check_pose(p->Ta, "pair frame Ta of pair", i, err))) return st;
    if ((st = check_pose(p->Tb, "pair frame Tb of pair", i, err))) return st;
    if (p->driven) {
      if (p->type != PHM_PAIR_FIXED)
        return phm_error_set(err, PHM_EINVAL, "pair %d: only fixed pairs can be driven by a prescribed motion (use a PD actuator on a %s pair)", i, phm_pair_types[p->type].name);
      if (!finite_n(p->axis, 6)) return phm_error_set(err, PHM_EINVAL, "pair %d: non-finite motion axis", i);
      if ((st = law_check(&p->law, "pair", i, err))) return st;
    }
    if (!isfinite(p->pitch)) return phm_error_set(err, PHM_EINVAL, "pair %d: non-finite pitch", i);
    if (p->drop < 0 || p->drop >= (1 << phm_pair_types[p->type].m))
      return phm_error_set(err, PHM_EINVAL, "pair %d: drop mask %d names rows beyond the %d constraint rows of a %s pair", i, p->drop, phm_pair_types[p->type].m, phm_pair_types[p->type].name);
    if (p->has_x0 && !finite_n(p->x0, 6 - phm_pair_types[p->type].m))
      return phm_error_set(err, PHM_EINVAL, "pair %d: non-finite initial joint coordinates", i);
  }
  if (d->nactuators < 0 || d->nsprings < 0) return phm_error_set(err, PHM_EINVAL, "negative actuator or spring count");
  for (int i = 0; i < d->nactuators; i++) {
    const phm_actuator_desc *a = &d->actuators[i];
    if (a->pair < 0 || a->pair >= d->npairs) return phm_error_set(err, PHM_EINVAL, "actuator %d: pair %d out of range", i, a->pair);
    int k = 6 - phm_pair_types[d->pairs[a->pair].type].m;
    if (k == 0) return phm_error_set(err, PHM_EINVAL, "actuator %d: pair %d is fixed (no allowed direction to actuate)", i, a->pair);
    if (a->kind < PHM_ACT_EFFORT || a->kind > PHM_ACT_SPRING) return phm_error_set(err, PHM_EINVAL, "actuator %d: unknown kind %d", i, a->kind);
    if (!finite_n(a->vec, k) || !finite_n(a->kp, k) || !finite_n(a->kd, k) || !finite_n(a->x_set, k))
      return phm_error_set(err, PHM_EINVAL, "actuator %d: non-finite direction, gain or set point", i);
    if (a->kind != PHM_ACT_EFFORT)
      for (int j = 0; j < k; j++)
        if (a->kp[j] < 0 || a->kd[j] < 0) return phm_error_set(err, PHM_EINVAL, "actuator %d: gains must be >= 0 (kp %g, kd %g)", i, a->kp[j], a->kd[j]);
    if (a->kind != PHM_ACT_SPRING && (st = law_check(&a->law, "actuator", i, err))) return st;
  }
  for (int i = 0; i < d->nsprings; i++) {
    const phm_spring_desc *sp = &d->springs[i];
    if (sp->a < -1 || sp->a >= d->ncarriers || sp->b < -1 || sp->b >= d->ncarriers || sp->a == sp->b)
      return phm_error_set(err, PHM_EINVAL, "spring %d: carriers (%d, %d) out of range or equal", i, sp->a, sp->b);
    if (!finite_n(sp->pa, 3) || !finite_n(sp->pb, 3) || !isfinite(sp->k) || !isfinite(sp->c) || !isfinite(sp->d0))
      return phm_error_set(err, PHM_EINVAL, "spring %d: non-finite point or parameter", i);
    if (sp->k < 0 || sp->c < 0 || sp->d0 < 0)
      return phm_error_set(err, PHM_EINVAL, "spring %d: stiffness, damping and rest length must be >= 0 (got %g, %g, %g)", i, sp->k, sp->c, sp->d0);
  }
  for (int i = 0; i < d->nloads; i++) {
    const phm_load_desc *l = &d->loads[i];
    if (l->carrier < 0 || l->carrier >= d->ncarriers) return phm_error_set(err, PHM_EINVAL, "load %d: carrier %d out of range", i, l->carrier);
    if (l->reaction < -1 || l->reaction >= d->ncarriers || l->reaction == l->carrier)
      return phm_error_set(err, PHM_EINVAL, "load %d: reaction carrier %d out of range or equal to the loaded one", i, l->reaction);
    if (!finite_n(l->w, 6) || !finite_n(l->point, 3)) return phm_error_set(err, PHM_EINVAL, "load %d: non-finite wrench or point", i);
    if ((st = law_check(&l->law, "load", i, err))) return st;
  }

  phm_model *m = calloc(1, sizeof *m);
  if (!m) return phm_error_set(err, PHM_ENOMEM, "out of memory");
  m->nc = d->ncarriers;
  m->ne = d->nelements;
  m->np = d->npairs;
  m->nl = d->nloads;
  m->na = d->nactuators;
  m->ns = d->nsprings;
  memcpy(m->gravity, d->gravity, sizeof m->gravity);
  m->car = malloc(sizeof *m->car * (size_t)m->nc);
  m->el = malloc(sizeof *m->el * (size_t)(m->ne + 1));
  m->pair = malloc(sizeof *m->pair * (size_t)(m->np + 1));
  m->pair_row = malloc(sizeof(int) * (size_t)(m->np + 1));
  m->pair_m = malloc(sizeof(int) * (size_t)(m->np + 1));
  m->load = malloc(sizeof *m->load * (size_t)(m->nl + 1));
  m->pair_j = malloc(sizeof(int) * (size_t)(m->np + 1));
  m->pair_k = malloc(sizeof(int) * (size_t)(m->np + 1));
  m->xref0 = calloc((size_t)(6 * m->np + 1), sizeof(double));
  m->pair_sel = calloc((size_t)(6 * m->np + 1), sizeof(int));
  m->pair_rowf = calloc((size_t)(m->np + 1), sizeof(int));
  m->pair_AdTbi = malloc(sizeof(double) * (size_t)(36 * m->np + 1));
  m->act = malloc(sizeof *m->act * (size_t)(m->na + 1));
  m->spr = malloc(sizeof *m->spr * (size_t)(m->ns + 1));
  int ntab = 0, nbp = 0;
  for (int i = 0; i < m->na; i++)
    if (d->actuators[i].kind != PHM_ACT_SPRING) {
      nbp += law_breakpoints(&d->actuators[i].law, NULL);
      if (d->actuators[i].law.kind == PHM_LAW_TABLE) ntab += d->actuators[i].law.ntable;
    }
  for (int i = 0; i < m->np; i++)
    if (d->pairs[i].driven) {
      nbp += law_breakpoints(&d->pairs[i].law, NULL);
      if (d->pairs[i].law.kind == PHM_LAW_TABLE) ntab += d->pairs[i].law.ntable;
    }
  for (int i = 0; i < m->nl; i++) {
    nbp += law_breakpoints(&d->loads[i].law, NULL);
    if (d->loads[i].law.kind == PHM_LAW_TABLE) ntab += d->loads[i].law.ntable;
  }
  m->bp = malloc(sizeof(double) * (size_t)(nbp + 1));
  m->tables = malloc(sizeof(double) * (size_t)(2 * ntab + 1));
  if (!m->car || !m->el || !m->pair || !m->pair_row || !m->pair_m || !m->load || !m->bp || !m->tables ||
      !m->pair_j || !m->pair_k || !m->xref0 || !m->act || !m->spr || !m->pair_sel || !m->pair_rowf || !m->pair_AdTbi) {
    phm_model_free(m);
    return phm_error_set(err, PHM_ENOMEM, "out of memory");
  }
  memcpy(m->car, d->carriers, sizeof *m->car * (size_t)m->nc);
  if (m->ne) memcpy(m->el, d->elements, sizeof *m->el * (size_t)m->ne);
  if (m->np) memcpy(m->pair, d->pairs, sizeof *m->pair * (size_t)m->np);
  for (int i = 0; i < m->np; i++) { /* constant: computed once, read by every pair evaluation */
    double Tbi[16];
    phm_se3_inverse(m->pair[i].Tb, Tbi);
    phm_se3_Ad(Tbi, m->pair_AdTbi + 36 * i);
  }
  if (m->nl) memcpy(m->load, d->loads, sizeof *m->load * (size_t)m->nl);
  if (m->na) memcpy(m->act, d->actuators, sizeof *m->act * (size_t)m->na);
  if (m->ns) memcpy(m->spr, d->springs, sizeof *m->spr * (size_t)m->ns);
  double *tp = m->tables;
  for (int i = 0; i < m->na; i++) {
    phm_law *l = &m->act[i].law;
    if (m->act[i].kind != PHM_ACT_SPRING && l->kind == PHM_LAW_TABLE) {
      memcpy(tp, l->table, sizeof(double) * 2 * (size_t)l->ntable);
      l->table = tp;
      tp += 2 * l->ntable;
    } else if (m->act[i].kind == PHM_ACT_SPRING) {
      memset(l, 0, sizeof *l);
    }
  }
  for (int i = 0; i < m->np; i++) {
    phm_law *l = &m->pair[i].law;
    if (m->pair[i].driven && l->kind == PHM_LAW_TABLE) {
      memcpy(tp, l->table, sizeof(double) * 2 * (size_t)l->ntable);
      l->table = tp;
      tp += 2 * l->ntable;
    } else if (!m->pair[i].driven) {
      memset(l, 0, sizeof *l);
    }
  }
  for (int i = 0; i < m->nl; i++) {
    phm_law *l = &m->load[i].law;
    if (l->kind == PHM_LAW_TABLE) {
      memcpy(tp, l->table, sizeof(double) * 2 * (size_t)l->ntable);
      l->table = tp;
      tp += 2 * l->ntable;
    }
  }
  int row = 0, jt = 0, rowf = 0;
  for (int i = 0; i < m->np; i++) {
    int mt = phm_pair_types[m->pair[i].type].m, kept = 0;
    for (int r = 0; r < mt; r++)
      if (!(m->pair[i].drop & (1 << r))) m->pair_sel[6 * i + kept++] = r;
    m->pair_row[i] = row;
    m->pair_rowf[i] = rowf;
    m->pair_m[i] = kept;
    row += kept;
    rowf += mt;
    m->pair_j[i] = jt;
    m->pair_k[i] = 6 - mt;
    if (m->pair[i].has_x0) memcpy(m->xref0 + jt, m->pair[i].x0, sizeof(double) * (size_t)m->pair_k[i]);
    jt += m->pair_k[i];
  }
  m->ncons = row;
  m->ncons_full = rowf;
  m->nj = jt;
  m->nport = m->na + m->nl + m->ns;
  nbp = 0;
  for (int i = 0; i < m->na; i++)
    if (m->act[i].kind != PHM_ACT_SPRING) nbp += law_breakpoints(&m->act[i].law, m->bp + nbp);
  for (int i = 0; i < m->np; i++)
    if (m->pair[i].driven) nbp += law_breakpoints(&m->pair[i].law, m->bp + nbp);
  for (int i = 0; i < m->nl; i++) nbp += law_breakpoints(&m->load[i].law, m->bp + nbp);
  qsort(m->bp, (size_t)nbp, sizeof(double), cmp_double);
  int k = 0;
  for (int i = 0; i < nbp; i++)
    if (k == 0 || m->bp[i] > m->bp[k - 1]) m->bp[k++] = m->bp[i];
  m->nbp = k;
  double lref = 0;
  for (int i = 0; i < m->ne; i++) lref = fmax(lref, m->el[i].h);
  m->lref = lref > 0 ? lref : 1.0;
  *out = m;
  return PHM_OK;
}

int phm_model_ncarriers(const phm_model *m) { return m->nc; }
int phm_model_nconstraints(const phm_model *m) { return m->ncons; }
int phm_model_npairs(const phm_model *m) { return m->np; }
int phm_model_njoints(const phm_model *m) { return m->nj; }
int phm_model_nports(const phm_model *m) { return m->nport; }
void phm_model_pair_layout(const phm_model *m, int ip, int *row, int *mc, int *joint, int *k) {
  if (row) *row = m->pair_row[ip];
  if (mc) *mc = m->pair_m[ip];
  if (joint) *joint = m->pair_j[ip];
  if (k) *k = m->pair_k[ip];
}

double phm_model_tref(const phm_model *m, double t, double *next_bp) {
  for (int i = 0; i < m->nbp; i++)
    if (m->bp[i] > t * (1 + 1e-14) + 1e-300 && m->bp[i] > t) {
      if (next_bp) *next_bp = m->bp[i];
      return 0.5 * (t + m->bp[i]);
    }
  if (next_bp) *next_bp = INFINITY;
  return t + 1.0;
}

/* ---------------------------------------------------------------- poses */
void phm_qp_to_H(const double q[4], const double p[3], double H[16]) {
  double R[9];
  phm_quat_to_rot(q, R);
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++) H[4 * i + j] = R[3 * i + j];
    H[4 * i + 3] = p[i];
  }
  H[12] = H[13] = H[14] = 0;
  H[15] = 1;
}

void phm_H_to_qp(const double H[16], double q[4], double p[3]) {
  double R[9];
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++) R[3 * i + j] = H[4 * i + j];
    p[i] = H[4 * i + 3];
  }
  phm_quat_from_rot(R, q);
}

void phm_retract(double H[16], const double delta[6]) {
  double E[16], HE[16];
  phm_se3_exp(delta, E);
  phm_se3_compose(H, E, HE);
  memcpy(H, HE, sizeof HE);
}

/* ---------------------------------------------------------------- beam element */
void phm_element_eval(const phm_element_desc *e, const double Ha[16], const double Hb[16],
                      const double ta[6], const double tb[6], double wa[6], double wb[6],
                      double *V, double *P) {
  double Hai[16], Hab[16], X[6], A[9], L[9], sig[6], de[6];
  /* Hab = Ha^-1 Hb. Written as Ra^T (pb - pa) its position is 4x more accurate (measured on
   * strains of 1e-6), yet that made IDA's every-state reference of the leaf spring crawl (30 ->
   * 170 000 steps over 0.05 s, tests/test_scenes.py): IDA's Newton there is sensitive to the
   * residual's round-off (docs/integrators.md, Limits), so this form is kept. */
  phm_se3_inverse(Ha, Hai);
  phm_se3_compose(Hai, Hb, Hab);
  /* X = log(Hab); dexp_X^-1 = [[A, 0], [L, A]], dexp_{-X}^-1 = [[A^T, 0], [L^T, A^T]] */
  phm_se3_log_dexp_inv(Hab, X, A, L);
  for (int i = 0; i < 6; i++) de[i] = X[i] / e->h - e->eps_hat[i];
  mv6(e->K, de, sig);
  if (V) *V = 0.5 * e->h * dot(de, sig, 6);
  double pd = 0;
  if (ta && tb) {
    double ed[6], s2[6];
    /* strain rate h eps' = dexp_{-X}^-1 t_b - dexp_X^-1 t_a */
    for (int i = 0; i < 3; i++) {
      double xaw = A[3 * i] * ta[0] + A[3 * i + 1] * ta[1] + A[3 * i + 2] * ta[2];
      double xav = L[3 * i] * ta[0] + L[3 * i + 1] * ta[1] + L[3 * i + 2] * ta[2] +
                   A[3 * i] * ta[3] + A[3 * i + 1] * ta[4] + A[3 * i + 2] * ta[5];
      double xbw = A[i] * tb[0] + A[3 + i] * tb[1] + A[6 + i] * tb[2];
      double xbv = L[i] * tb[0] + L[3 + i] * tb[1] + L[6 + i] * tb[2] +
                   A[i] * tb[3] + A[3 + i] * tb[4] + A[6 + i] * tb[5];
      ed[i] = (xbw - xaw) / e->h;
      ed[3 + i] = (xbv - xav) / e->h;
    }
    mv6(e->D, ed, s2);
    pd = e->h * dot(ed, s2, 6);
    for (int i = 0; i < 6; i++) sig[i] += s2[i];
  }
  if (P) *P = pd;
  /* w_a = dexp_X^-T sigma, w_b = -dexp_{-X}^-T sigma */
  for (int i = 0; i < 3; i++) {
    wa[i] = A[i] * sig[0] + A[3 + i] * sig[1] + A[6 + i] * sig[2] +
            L[i] * sig[3] + L[3 + i] * sig[4] + L[6 + i] * sig[5];
    wa[3 + i] = A[i] * sig[3] + A[3 + i] * sig[4] + A[6 + i] * sig[5];
    wb[i] = -(A[3 * i] * sig[0] + A[3 * i + 1] * sig[1] + A[3 * i + 2] * sig[2] +
              L[3 * i] * sig[3] + L[3 * i + 1] * sig[4] + L[3 * i + 2] * sig[5]);
    wb[3 + i] = -(A[3 * i] * sig[3] + A[3 * i + 1] * sig[4] + A[3 * i + 2] * sig[5]);
  }
}

/* ---------------------------------------------------------------- pairs */
/* Frames of pair ip: B = H_b Tb, h = (H_a Ta)^-1 B, AdTbi = Ad_{Tb^-1}, AdBa = Ad_{B^-1 H_a}, so
 * that the relative twist is t_rel = AdTbi t_b - AdBa t_a (in F_b). */
static void pair_frames(const phm_model *m, int ip, const double *Ha, const double *Hb, double h[16],
                        double AdTbi[36], double AdBa[36]) {
  const phm_pair_desc *pr = &m->pair[ip];
  double A[16], B[16], Ai[16], Bi[16], T[16];
  if (Ha) phm_se3_compose(Ha, pr->Ta, A); else memcpy(A, pr->Ta, sizeof A);
  if (Hb) phm_se3_compose(Hb, pr->Tb, B); else memcpy(B, pr->Tb, sizeof B);
  phm_se3_inverse(A, Ai);
  phm_se3_compose(Ai, B, h);
  if (AdTbi) memcpy(AdTbi, m->pair_AdTbi + 36 * ip, 36 * sizeof(double));
  if (AdBa) {
    phm_se3_inverse(B, Bi);
    if (Ha) phm_se3_compose(Bi, Ha, T); else memcpy(T, Bi, sizeof T);
    phm_se3_Ad(T, AdBa);
  }
}

static void rel_twist(const double AdTbi[36], const double AdBa[36], const double *ta,
                      const double *tb, double tr[6]) {
  double u[6] = {0}, v[6] = {0};
  if (tb) mv6(AdTbi, tb, u);
  if (ta) mv6(AdBa, ta, v);
  for (int i = 0; i < 6; i++) tr[i] = u[i] - v[i];
}

/* Keep the rows of pair ip that its drop mask leaves in the DAE: g[r] = g[sel r], W column r =
 * W column sel r (sel increasing, so the forward in-place copy is safe). */
static void select_rows(const phm_model *m, int ip, double *g, double W[36]) {
  if (!m->pair[ip].drop) return;
  const int *sel = m->pair_sel + 6 * ip;
  for (int r = 0; r < m->pair_m[ip]; r++) {
    if (g) g[r] = g[sel[r]];
    for (int i = 0; i < 6; i++) W[6 * i + r] = W[6 * i + sel[r]];
  }
}

static void pair_eval_rows(const phm_model *m, int ip, const double *Ha, const double *Hb,
                           const double *xref, double time, double tref, double *g, double *Ga,
                           double *Gb, double *vt, int all) {
  const phm_pair_desc *pr = &m->pair[ip];
  int mc = all ? phm_pair_types[pr->type].m : m->pair_m[ip];
  double h[16], W[36], AdTbi[36], AdBa[36];
  if (!xref) xref = m->xref0 + m->pair_j[ip];
  pair_frames(m, ip, Ha, Hb, h, (Ga || Gb) ? AdTbi : NULL, Ga ? AdBa : NULL);
  double s = 0, ds = 0;
  if (pr->driven) s = phm_law_eval(&pr->law, time, tref, &ds, NULL);
  double gf[6];
  if (pr->driven && g) {
    double x[6], r[16], ri[16], E[16];
    for (int i = 0; i < 6; i++) x[i] = s * pr->axis[i];
    phm_se3_exp(x, r);
    phm_se3_inverse(r, ri);
    phm_se3_compose(ri, h, E);
    phm_pair_kin(pr->type, pr->pitch, E, xref, gf, W, NULL, NULL);
  } else {
    phm_pair_kin(pr->type, pr->pitch, h, xref, gf, W, NULL, NULL);
  }
  if (!all) select_rows(m, ip, gf, W);
  if (g) memcpy(g, gf, sizeof(double) * (size_t)mc);
  /* G_b = W^T Ad_{Tb^-1},  G_a = -W^T Ad_{(H_b Tb)^-1 H_a} */
  for (int r = 0; r < mc; r++)
    for (int j = 0; j < 6; j++) {
      double sb = 0, sa = 0;
      for (int k = 0; k < 6; k++) {
        if (Gb) sb += W[6 * k + r] * AdTbi[6 * k + j];
        if (Ga) sa += W[6 * k + r] * AdBa[6 * k + j];
      }
      if (Gb) Gb[6 * r + j] = sb;
      if (Ga) Ga[6 * r + j] = -sa;
    }
  if (vt) {
    for (int r = 0; r < mc; r++) {
      double acc = 0;
      if (pr->driven)
        for (int k = 0; k < 6; k++) acc += W[6 * k + r] * ds * pr->axis[k];
      vt[r] = acc;
    }
  }
}

void phm_pair_eval(const phm_model *m, int ip, const double *Ha, const double *Hb,
                   const double *xref, double time, double tref, double *g, double *Ga,
                   double *Gb, double *vt) {
  pair_eval_rows(m, ip, Ha, Hb, xref, time, tref, g, Ga, Gb, vt, 0);
}

void phm_pair_wrench(const phm_model *m, int ip, const double *Ha, const double *Hb,
                     const double *xref, double time, double tref, const double *lam, double w[6]) {
  const phm_pair_desc *pr = &m->pair[ip];
  double h[16], W[36];
  if (!xref) xref = m->xref0 + m->pair_j[ip];
  pair_frames(m, ip, Ha, Hb, h, NULL, NULL);
  phm_pair_kin(pr->type, pr->pitch, h, xref, NULL, W, NULL, NULL); /* driven: fixed, W = I */
  select_rows(m, ip, NULL, W);
  (void)time;
  (void)tref;
  for (int i = 0; i < 6; i++) {
    double acc = 0;
    for (int r = 0; r < m->pair_m[ip]; r++) acc += W[6 * i + r] * lam[r];
    w[i] = acc;
  }
}

void phm_pair_joint(const phm_model *m, int ip, const double *Ha, const double *Hb,
                    const double *ta, const double *tb, const double *xref, double *x,
                    double *xdot) {
  const phm_pair_desc *pr = &m->pair[ip];
  int k = m->pair_k[ip];
  double h[16], Phi[36], AdTbi[36], AdBa[36], tr[6];
  if (!xref) xref = m->xref0 + m->pair_j[ip];
  pair_frames(m, ip, Ha, Hb, h, AdTbi, AdBa);
  phm_pair_kin(pr->type, pr->pitch, h, xref, NULL, NULL, Phi, x);
  if (xdot) {
    rel_twist(AdTbi, AdBa, ta, tb, tr);
    for (int c = 0; c < k; c++) {
      double acc = 0;
      for (int i = 0; i < 6; i++) acc += Phi[6 * i + c] * tr[i];
      xdot[c] = acc;
    }
  }
}

void phm_constraints_columns(const phm_model *m, const double *H, const double *xs, double time,
                             double tref, const int *cmap, int n, double *g, double *G,
                             double *vt) {
  if (G) memset(G, 0, sizeof(double) * (size_t)m->ncons * (size_t)n);
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int r0 = m->pair_row[ip], mc = m->pair_m[ip];
    double Ga[36], Gb[36];
    phm_pair_eval(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                  xs ? xs + m->pair_j[ip] : NULL, time, tref, g ? g + r0 : NULL, Ga, Gb,
                  vt ? vt + r0 : NULL);
    if (G)
      for (int r = 0; r < mc; r++)
        for (int j = 0; j < 6; j++) {
          if (pr->a >= 0) G[(size_t)(r0 + r) * n + 6 * (cmap ? cmap[pr->a] : pr->a) + j] += Ga[6 * r + j];
          if (pr->b >= 0) G[(size_t)(r0 + r) * n + 6 * (cmap ? cmap[pr->b] : pr->b) + j] += Gb[6 * r + j];
        }
  }
}

void phm_constraints_dense(const phm_model *m, const double *H, const double *xs, double time,
                           double tref, double *g, double *G, double *vt) {
  phm_constraints_columns(m, H, xs, time, tref, NULL, 6 * m->nc, g, G, vt);
}

int phm_model_nconstraints_full(const phm_model *m) { return m->ncons_full; }

void phm_constraints_full(const phm_model *m, const double *H, const double *xs, double time,
                          double *g, double *G, double *W) {
  int n = 6 * m->nc;
  double tref = phm_model_tref(m, time, NULL);
  if (G) memset(G, 0, sizeof(double) * (size_t)m->ncons_full * (size_t)n);
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int r0 = m->pair_rowf[ip], mc = phm_pair_types[pr->type].m;
    const double *Ha = pr->a >= 0 ? H + 16 * pr->a : NULL, *Hb = pr->b >= 0 ? H + 16 * pr->b : NULL;
    const double *xr = xs ? xs + m->pair_j[ip] : NULL;
    double Ga[36], Gb[36], gl[6];
    pair_eval_rows(m, ip, Ha, Hb, xr, time, tref, gl, Ga, Gb, NULL, 1);
    if (g) memcpy(g + r0, gl, sizeof(double) * (size_t)mc);
    if (G)
      for (int r = 0; r < mc; r++)
        for (int j = 0; j < 6; j++) {
          if (pr->a >= 0) G[(size_t)(r0 + r) * n + 6 * pr->a + j] += Ga[6 * r + j];
          if (pr->b >= 0) G[(size_t)(r0 + r) * n + 6 * pr->b + j] += Gb[6 * r + j];
        }
    if (W) {
      double h[16];
      pair_frames(m, ip, Ha, Hb, h, NULL, NULL);
      phm_pair_kin(pr->type, pr->pitch, h, xr ? xr : m->xref0 + m->pair_j[ip], NULL, W + 36 * ip, NULL, NULL);
    }
  }
}

void phm_model_joints(const phm_model *m, const double *H, const double *xs, double *x) {
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    if (m->pair_k[ip] == 0) continue;
    phm_pair_joint(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                   NULL, NULL, xs ? xs + m->pair_j[ip] : NULL, x + m->pair_j[ip], NULL);
  }
}

/* ---------------------------------------------------------------- applied wrenches */
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

/* Point-to-point spring-damper: tension f, elastic energy, damping power (>= 0). */
static void spring_eval(const phm_spring_desc *sp, const double *H, const double *tw, double *wr,
                        double *V, double *Pd) {
  double xa[3], va[3], xb[3], vb[3], n[3], F[3], T[3] = {0, 0, 0};
  point_state(H, tw, sp->a, sp->pa, xa, va);
  point_state(H, tw, sp->b, sp->pb, xb, vb);
  for (int i = 0; i < 3; i++) n[i] = xb[i] - xa[i];
  double d = sqrt(dot(n, n, 3));
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

void phm_applied(const phm_model *m, const double *H, const double *tw, const double *xs,
                 double time, double tref, double scale, double *wr, double *Vel, double *Pdiss,
                 double *Psupp, double *Pport, double *effort) {
  memset(wr, 0, sizeof(double) * 6 * (size_t)m->nc);
  if (effort && m->nj) memset(effort, 0, sizeof(double) * (size_t)m->nj);
  double V = 0, Pd = 0, Ps = 0;
  for (int ie = 0; ie < m->ne; ie++) {
    const phm_element_desc *e = &m->el[ie];
    double wa[6], wb[6], v, p;
    phm_element_eval(e, H + 16 * e->a, H + 16 * e->b, tw ? tw + 6 * e->a : NULL,
                     tw ? tw + 6 * e->b : NULL, wa, wb, &v, &p);
    V += v;
    Pd += p;
    for (int i = 0; i < 6; i++) {
      wr[6 * e->a + i] += wa[i];
      wr[6 * e->b + i] += wb[i];
    }
  }
  double gn = fabs(m->gravity[0]) + fabs(m->gravity[1]) + fabs(m->gravity[2]);
  if (gn > 0)
    for (int c = 0; c < m->nc; c++) {
      const double *Hc = H + 16 * c;
      const phm_carrier_desc *cd = &m->car[c];
      double f[3];
      for (int i = 0; i < 3; i++) /* R^T m g */
        f[i] = scale * cd->mass *
               (Hc[i] * m->gravity[0] + Hc[4 + i] * m->gravity[1] + Hc[8 + i] * m->gravity[2]);
      const double *r = cd->com;
      double *w = wr + 6 * c;
      w[0] += r[1] * f[2] - r[2] * f[1];
      w[1] += r[2] * f[0] - r[0] * f[2];
      w[2] += r[0] * f[1] - r[1] * f[0];
      w[3] += f[0];
      w[4] += f[1];
      w[5] += f[2];
    }
  /* actuators */
  for (int ia = 0; ia < m->na; ia++) {
    const phm_actuator_desc *ac = &m->act[ia];
    int ip = ac->pair, k = m->pair_k[ip], j0 = m->pair_j[ip];
    const phm_pair_desc *pr = &m->pair[ip];
    const double *Ha = pr->a >= 0 ? H + 16 * pr->a : NULL, *Hb = pr->b >= 0 ? H + 16 * pr->b : NULL;
    const double *ta = (tw && pr->a >= 0) ? tw + 6 * pr->a : NULL, *tb = (tw && pr->b >= 0) ? tw + 6 * pr->b : NULL;
    double h[16], Phi[36], AdTbi[36], AdBa[36], tr[6], x[6], xd[6] = {0}, u[6] = {0}, s = 0, ds = 0;
    pair_frames(m, ip, Ha, Hb, h, AdTbi, AdBa);
    phm_pair_kin(pr->type, pr->pitch, h, xs ? xs + j0 : m->xref0 + j0, NULL, NULL, Phi, x);
    rel_twist(AdTbi, AdBa, ta, tb, tr);
    for (int c = 0; c < k; c++) {
      double acc = 0;
      for (int i = 0; i < 6; i++) acc += Phi[6 * i + c] * tr[i];
      xd[c] = acc;
    }
    if (ac->kind != PHM_ACT_SPRING) s = phm_law_eval(&ac->law, time, tref, &ds, NULL);
    for (int c = 0; c < k; c++) {
      if (ac->kind == PHM_ACT_EFFORT) u[c] = scale * s * ac->vec[c];
      else if (ac->kind == PHM_ACT_PD)
        u[c] = -ac->kp[c] * (x[c] - ac->x_set[c] - s * ac->vec[c]) - ac->kd[c] * (xd[c] - ds * ac->vec[c]);
      else u[c] = -ac->kp[c] * (x[c] - ac->x_set[c]) - ac->kd[c] * xd[c];
      if (effort) effort[j0 + c] += u[c];
    }
    double wB[6], wv[6];
    for (int i = 0; i < 6; i++) {
      double acc = 0;
      for (int c = 0; c < k; c++) acc += Phi[6 * i + c] * u[c];
      wB[i] = acc;
    }
    if (Hb) {
      mtv6(AdTbi, wB, wv);
      for (int i = 0; i < 6; i++) wr[6 * pr->b + i] += wv[i];
    }
    if (pr->a >= 0) {
      mtv6(AdBa, wB, wv);
      for (int i = 0; i < 6; i++) wr[6 * pr->a + i] -= wv[i];
    }
    double P = dot(u, xd, k);
    Ps += P;
    if (Pport) Pport[ia] = P;
  }
  /* external wrenches and interactions */
  for (int il = 0; il < m->nl; il++) {
    const phm_load_desc *l = &m->load[il];
    double s = scale * phm_law_eval(&l->law, time, tref, NULL, NULL);
    if (Pport) Pport[m->na + il] = 0;
    if (s == 0) continue;
    const double *Hc = H + 16 * l->carrier;
    double tau[3], f[3], w[6];
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
    double P = tw ? dot(w, tw + 6 * l->carrier, 6) : 0;
    if (l->reaction >= 0) {
      double x[3], v[3], F[3], T[3], before[6];
      point_state(H, NULL, l->carrier, r, x, v);
      for (int i = 0; i < 3; i++) { /* world force and torque (about x), reversed */
        F[i] = -(Hc[4 * i] * f[0] + Hc[4 * i + 1] * f[1] + Hc[4 * i + 2] * f[2]);
        T[i] = -(Hc[4 * i] * tau[0] + Hc[4 * i + 1] * tau[1] + Hc[4 * i + 2] * tau[2]);
      }
      memcpy(before, wr + 6 * l->reaction, sizeof before);
      add_world_wrench(H, l->reaction, x, F, T, wr);
      if (tw)
        for (int i = 0; i < 6; i++) P += (wr[6 * l->reaction + i] - before[i]) * tw[6 * l->reaction + i];
    }
    Ps += P;
    if (Pport) Pport[m->na + il] = P;
  }
  for (int is = 0; is < m->ns; is++) {
    double v = 0, p = 0;
    spring_eval(&m->spr[is], H, tw, wr, &v, &p);
    V += v;
    Pd += p;
    if (Pport) Pport[m->na + m->nl + is] = -p;
  }
  if (Vel) *Vel = V;
  if (Pdiss) *Pdiss = Pd;
  if (Psupp) *Psupp = Ps;
}

void phm_model_energy(const phm_model *m, const double *H, const double *t, double e[3]) {
  double K = 0, Vg = 0, Vel = 0;
  for (int c = 0; c < m->nc; c++) {
    if (t) {
      double Mt[6];
      mv6(m->car[c].M, t + 6 * c, Mt);
      K += 0.5 * dot(Mt, t + 6 * c, 6);
    }
    const double *Hc = H + 16 * c, *r = m->car[c].com;
    for (int i = 0; i < 3; i++) {
      double x = Hc[4 * i + 3] + Hc[4 * i] * r[0] + Hc[4 * i + 1] * r[1] + Hc[4 * i + 2] * r[2];
      Vg -= m->car[c].mass * m->gravity[i] * x;
    }
  }
  for (int ie = 0; ie < m->ne; ie++) {
    const phm_element_desc *el = &m->el[ie];
    double wa[6], wb[6], v;
    phm_element_eval(el, H + 16 * el->a, H + 16 * el->b, NULL, NULL, wa, wb, &v, NULL);
    Vel += v;
  }
  for (int is = 0; is < m->ns; is++) {
    double v = 0;
    spring_eval(&m->spr[is], H, NULL, NULL, &v, NULL);
    Vel += v;
  }
  e[0] = K;
  e[1] = Vel;
  e[2] = Vg;
}

/* ---------------------------------------------------------------- LAPACK */
extern void dgelss_(const int *m, const int *n, const int *nrhs, double *a, const int *lda,
                    double *b, const int *ldb, double *s, const double *rcond, int *rank,
                    double *work, const int *lwork, int *info);

phm_status phm_lstsq(int rows, int cols, double *A, double *b, int *rank, phm_error *err) {
  /* row-major A (rows x cols) is column-major A^T; transpose into column-major A. */
  int ld = rows > cols ? rows : cols, one = 1, info = 0, rk = 0, lwork = -1;
  if (rows == 0 || cols == 0) {
    if (rank) *rank = 0;
    for (int i = 0; i < cols; i++) b[i] = 0;
    return PHM_OK;
  }
  double *Ac = malloc(sizeof(double) * (size_t)rows * (size_t)cols);
  double *s = malloc(sizeof(double) * (size_t)(rows < cols ? rows : cols));
  double wq, rcond = 1e-12;
  if (!Ac || !s) {
    free(Ac);
    free(s);
    return phm_error_set(err, PHM_ENOMEM, "out of memory");
  }
  for (int i = 0; i < rows; i++)
    for (int j = 0; j < cols; j++) Ac[(size_t)j * rows + i] = A[(size_t)i * cols + j];
  dgelss_(&rows, &cols, &one, Ac, &rows, b, &ld, s, &rcond, &rk, &wq, &lwork, &info);
  lwork = (int)wq + 1;
  double *work = malloc(sizeof(double) * (size_t)lwork);
  if (!work) {
    free(Ac);
    free(s);
    return phm_error_set(err, PHM_ENOMEM, "out of memory");
  }
  dgelss_(&rows, &cols, &one, Ac, &rows, b, &ld, s, &rcond, &rk, work, &lwork, &info);
  free(work);
  free(Ac);
  free(s);
  if (rank) *rank = rk;
  if (info != 0) return phm_error_set(err, PHM_ESINGULAR, "least-squares solve failed (LAPACK dgelss info %d)", info);
  return PHM_OK;
}
