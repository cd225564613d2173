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
    {"fixed", 6},
    /* TODO(pairs): each new type adds {name, m} here, its basis W^C in pair_basis() and its
     * position constraint in pair_g(). */
};
const int phm_npair_types = (int)(sizeof phm_pair_types / sizeof phm_pair_types[0]);

/* Constraint-wrench basis W^C (6 x m, row-major) of a pair type, in frame Tb. */
static void pair_basis(int type, double *W) {
  switch (type) {
  case PHM_PAIR_FIXED:
  default:
    memset(W, 0, 36 * sizeof(double));
    for (int i = 0; i < 6; i++) W[6 * i + i] = 1.0;
    break;
  }
}

/* Position constraints g(E) of a pair type, E = r^-1 h the relative pose error. */
static void pair_g(int type, const double E[16], double *g) {
  switch (type) {
  case PHM_PAIR_FIXED:
  default: phm_se3_log(E, g); break;
  }
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
      if (!finite_n(p->axis, 6)) return phm_error_set(err, PHM_EINVAL, "pair %d: non-finite motion axis", i);
      if ((st = law_check(&p->law, "pair", i, err))) return st;
    }
  }
  for (int i = 0; i < d->nloads; i++) {
    const phm_load_desc *l = &d->loads[i];
    if (l->carrier < 0 || l->carrier >= d->ncarriers) return phm_error_set(err, PHM_EINVAL, "load %d: carrier %d out of range", i, l->carrier);
    if (!finite_n(l->w, 6) || !finite_n(l->point, 3)) return phm_error_set(err, PHM_EINVAL, "load %d: non-finite wrench or point", i);
    if ((st = law_check(&l->law, "load", i, err))) return st;
  }

  phm_model *m = calloc(1, sizeof *m);
  if (!m) return phm_error_set(err, PHM_ENOMEM, "out of memory");
  m->nc = d->ncarriers;
  m->ne = d->nelements;
  m->np = d->npairs;
  m->nl = d->nloads;
  memcpy(m->gravity, d->gravity, sizeof m->gravity);
  m->car = malloc(sizeof *m->car * (size_t)m->nc);
  m->el = malloc(sizeof *m->el * (size_t)(m->ne + 1));
  m->pair = malloc(sizeof *m->pair * (size_t)(m->np + 1));
  m->pair_row = malloc(sizeof(int) * (size_t)(m->np + 1));
  m->pair_m = malloc(sizeof(int) * (size_t)(m->np + 1));
  m->load = malloc(sizeof *m->load * (size_t)(m->nl + 1));
  int ntab = 0, nbp = 0;
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
  if (!m->car || !m->el || !m->pair || !m->pair_row || !m->pair_m || !m->load || !m->bp || !m->tables) {
    phm_model_free(m);
    return phm_error_set(err, PHM_ENOMEM, "out of memory");
  }
  memcpy(m->car, d->carriers, sizeof *m->car * (size_t)m->nc);
  if (m->ne) memcpy(m->el, d->elements, sizeof *m->el * (size_t)m->ne);
  if (m->np) memcpy(m->pair, d->pairs, sizeof *m->pair * (size_t)m->np);
  if (m->nl) memcpy(m->load, d->loads, sizeof *m->load * (size_t)m->nl);
  double *tp = m->tables;
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
  int row = 0;
  for (int i = 0; i < m->np; i++) {
    m->pair_row[i] = row;
    m->pair_m[i] = phm_pair_types[m->pair[i].type].m;
    row += m->pair_m[i];
  }
  m->ncons = row;
  nbp = 0;
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
  double Hai[16], Hab[16], X[6], mX[6], Da[36], Db[36], sig[6], de[6];
  phm_se3_inverse(Ha, Hai);
  phm_se3_compose(Hai, Hb, Hab);
  phm_se3_log(Hab, X);
  for (int i = 0; i < 6; i++) {
    mX[i] = -X[i];
    de[i] = X[i] / e->h - e->eps_hat[i];
  }
  phm_se3_dexp_inv(X, Da);  /* dexp_X^-1    */
  phm_se3_dexp_inv(mX, Db); /* dexp_{-X}^-1 */
  mv6(e->K, de, sig);
  if (V) *V = 0.5 * e->h * dot(de, sig, 6);
  double pd = 0;
  if (ta && tb) {
    double xa[6], xb[6], ed[6], s2[6];
    mv6(Da, ta, xa);
    mv6(Db, tb, xb);
    for (int i = 0; i < 6; i++) ed[i] = (xb[i] - xa[i]) / e->h; /* strain rate */
    mv6(e->D, ed, s2);
    pd = e->h * dot(ed, s2, 6);
    for (int i = 0; i < 6; i++) sig[i] += s2[i];
  }
  if (P) *P = pd;
  /* w_a = dexp_X^-T sigma, w_b = -dexp_{-X}^-T sigma */
  mtv6(Da, sig, wa);
  mtv6(Db, sig, wb);
  for (int i = 0; i < 6; i++) wb[i] = -wb[i];
}

/* ---------------------------------------------------------------- pairs */
void phm_pair_eval(const phm_model *m, int ip, const double *Ha, const double *Hb, double time,
                   double tref, double *g, double *Ga, double *Gb, double *vt) {
  const phm_pair_desc *pr = &m->pair[ip];
  int mc = m->pair_m[ip];
  double A[16], B[16], Ai[16], Bi[16], h[16], W[36];
  if (Ha) phm_se3_compose(Ha, pr->Ta, A); else memcpy(A, pr->Ta, sizeof A);
  if (Hb) phm_se3_compose(Hb, pr->Tb, B); else memcpy(B, pr->Tb, sizeof B);
  pair_basis(pr->type, W);
  double s = 0, ds = 0;
  if (pr->driven) s = phm_law_eval(&pr->law, time, tref, &ds, NULL);
  if (g) {
    phm_se3_inverse(A, Ai);
    phm_se3_compose(Ai, B, h);
    double E[16];
    if (pr->driven) {
      double x[6], r[16], ri[16];
      for (int i = 0; i < 6; i++) x[i] = s * pr->axis[i];
      phm_se3_exp(x, r);
      phm_se3_inverse(r, ri);
      phm_se3_compose(ri, h, E);
    } else {
      memcpy(E, h, sizeof E);
    }
    pair_g(pr->type, E, g);
  }
  if (Ga || Gb) {
    /* G_b = W^T Ad_{Tb^-1},  G_a = -W^T Ad_{(H_b Tb)^-1 H_a} */
    double Ti[16], Ad[36];
    if (Gb) {
      phm_se3_inverse(pr->Tb, Ti);
      phm_se3_Ad(Ti, Ad);
      for (int r = 0; r < mc; r++)
        for (int j = 0; j < 6; j++) {
          double acc = 0;
          for (int k = 0; k < 6; k++) acc += W[6 * k + r] * Ad[6 * k + j];
          Gb[6 * r + j] = acc;
        }
    }
    if (Ga) {
      double BiHa[16];
      phm_se3_inverse(B, Bi);
      if (Ha) phm_se3_compose(Bi, Ha, BiHa); else memcpy(BiHa, Bi, sizeof BiHa);
      phm_se3_Ad(BiHa, Ad);
      for (int r = 0; r < mc; r++)
        for (int j = 0; j < 6; j++) {
          double acc = 0;
          for (int k = 0; k < 6; k++) acc += W[6 * k + r] * Ad[6 * k + j];
          Ga[6 * r + j] = -acc;
        }
    }
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

void phm_constraints_dense(const phm_model *m, const double *H, double time, double tref,
                           double *g, double *G, double *vt) {
  int n = 6 * m->nc;
  if (G) memset(G, 0, sizeof(double) * (size_t)m->ncons * (size_t)n);
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int r0 = m->pair_row[ip], mc = m->pair_m[ip];
    double Ga[36], Gb[36];
    phm_pair_eval(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                  time, tref, g ? g + r0 : NULL, Ga, Gb, vt ? vt + r0 : NULL);
    if (G)
      for (int r = 0; r < mc; r++)
        for (int j = 0; j < 6; j++) {
          if (pr->a >= 0) G[(size_t)(r0 + r) * n + 6 * pr->a + j] += Ga[6 * r + j];
          if (pr->b >= 0) G[(size_t)(r0 + r) * n + 6 * pr->b + j] += Gb[6 * r + j];
        }
  }
}

/* ---------------------------------------------------------------- applied wrenches */
void phm_applied(const phm_model *m, const double *H, const double *tw, double time, double tref,
                 double scale, double *wr, double *Vel, double *Pdiss, double *Psupp) {
  memset(wr, 0, sizeof(double) * 6 * (size_t)m->nc);
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
  for (int il = 0; il < m->nl; il++) {
    const phm_load_desc *l = &m->load[il];
    double s = scale * phm_law_eval(&l->law, time, tref, NULL, NULL);
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
    if (tw) Ps += dot(w, tw + 6 * l->carrier, 6);
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
