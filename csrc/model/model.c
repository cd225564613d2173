/* model.c -- the immutable model: validation of a description (phm_model_desc), its copy, the
 * layout of constraint rows and joint coordinates per pair, the laws' breakpoints. Built once
 * per analysis; every later stage only reads it. */
#include "model.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "law.h"
#include "linalg.h"

static phm_status check_pose(const double H[16], const char *what, int idx, phm_error *err) {
  if (!phm_all_finite(H, 16)) return PHM_FAIL(err, PHM_EINVAL, "%s %d: pose has a non-finite entry", what, idx);
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
    return PHM_FAIL(err, PHM_EINVAL, "%s %d: pose rotation is not orthonormal with det +1 (|R^T R - I| = %.2e)", what, idx, e);
  if (fabs(H[12]) + fabs(H[13]) + fabs(H[14]) + fabs(H[15] - 1) > 1e-12)
    return PHM_FAIL(err, PHM_EINVAL, "%s %d: pose last row must be (0, 0, 0, 1)", what, idx);
  return PHM_OK;
}

/* Symmetric positive (semi)definite within a relative tolerance: a Cholesky factorization of A
 * (semidefinite: of A + 1e-12 max|A_ii| I) succeeds. */
static int spd6(const double A[36], int semi) {
  double L[36], scale = 0;
  for (int i = 0; i < 6; i++) scale = fmax(scale, fabs(A[7 * i]));
  for (int i = 0; i < 6; i++)
    for (int j = 0; j < 6; j++)
      if (fabs(A[6 * i + j] - A[6 * j + i]) > 1e-9 * (scale + 1e-300)) return 0;
  if (semi)
    for (int i = 0; i < 6; i++)
      if (A[7 * i] < 0) return 0;
  return !phm_chol6(A, semi ? 1e-12 * scale + 1e-300 : 0.0, 0.0, L);
}

void phm_model_free(phm_model *m) {
  if (!m) return;
  free(m->car);
  free(m->el);
  free(m->el_damped);
  free(m->el_ab);
  free(m->car_u);
  free(m->el_sec);
  free(m->mc_u);
  free(m->mc_a);
  free(m->mc_b);
  free(m->mc);
  free(m->mc_rows);
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
  free(m->lawnodes);
  free(m->comp);
  free(m->comp_z);
  free(m->pair_z);
  free(m->pair_nz);
  free(m);
}

/* Constraint rows (kept and full) and joint coordinates of every pair, from the types and drop
 * masks; the branch references xref0 from the given x0. */
static void pair_layout(phm_model *m) {
  int row = 0, jt = 0, rowf = 0;
  for (int i = 0; i < m->np; i++) {
    int mt = phm_pair_rows_full(&m->pair[i]), kept = 0;
    for (int r = 0; r < mt; r++)
      if (!(m->pair[i].drop & (1 << r))) m->pair_sel[6 * i + kept++] = r;
    m->pair_row[i] = row;
    m->pair_rowf[i] = rowf;
    m->pair_m[i] = kept;
    row += kept;
    rowf += mt;
    m->pair_j[i] = jt;
    m->pair_k[i] = 6 - phm_pair_type(m->pair[i].type)->m;
    if (m->pair[i].has_x0) memcpy(m->xref0 + jt, m->pair[i].x0, sizeof(double) * (size_t)m->pair_k[i]);
    jt += m->pair_k[i];
  }
  m->ncons = row;
  m->ncons_full = rowf;
  m->nj = jt;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* A 12 x 12 coupling is symmetric to round-off. */
static int symmetric12(const double Mc[144]) {
  for (int r = 0; r < 12; r++)
    for (int c = 0; c < r; c++)
      if (fabs(Mc[12 * r + c] - Mc[12 * c + r]) > 1e-12 * (fabs(Mc[12 * r + c]) + fabs(Mc[12 * c + r]))) return 0;
  return 1;
}

/* A given coupling with its nodes' inertias, diag(M_a, M_b) + Mc, passes a Cholesky
 * factorization (12 x 12, no tolerance): the kinetic energy of the element's two nodes alone is
 * positive for every motion. Couplings that share a carrier are not checked together (a modal
 * link's element has its own two carriers; the initial accelerations' conjugate gradients stop
 * with an error if the whole mass is not positive). */
static int coupled_mass_spd(int a, int b, const double Mc[144], const phm_carrier_desc *car) {
  double A[144];
  memcpy(A, Mc, sizeof A);
  for (int i = 0; i < 6; i++)
    for (int j = 0; j < 6; j++) {
      A[12 * i + j] += car[a].M[6 * i + j];
      A[12 * (6 + i) + 6 + j] += car[b].M[6 * i + j];
    }
  for (int j = 0; j < 12; j++) {
    double s = A[13 * j];
    for (int k = 0; k < j; k++) s -= A[12 * j + k] * A[12 * j + k];
    if (!(s > 0)) return 0;
    double r = sqrt(s);
    A[13 * j] = r;
    for (int i = j + 1; i < 12; i++) {
      double t = A[12 * i + j];
      for (int k = 0; k < j; k++) t -= A[12 * i + k] * A[12 * j + k];
      A[12 * i + j] = t / r;
    }
  }
  return 1;
}

/* ---------------------------------------------------------------- phm_model_create, by stage
 * validate the description (its counts, the masses, the pairs, the forces), allocate the model,
 * copy the components, compute the mass couplings, copy the laws and their breakpoints, lay out
 * the pairs' rows. Each check refuses with the first failure, in this order. */

/* The counts and arrays of the description, and gravity. */
static phm_status validate_counts(const phm_model_desc *d, phm_error *err) {
  if (d->ncarriers < 1) return PHM_FAIL(err, PHM_EINVAL, "model has no carrier (body or beam node)");
  PHM_CHECK(d->carriers && (d->nelements <= 0 || d->elements) && (d->npairs <= 0 || d->pairs) &&
                (d->nloads <= 0 || d->loads) && (d->nactuators <= 0 || d->actuators) &&
                (d->nsprings <= 0 || d->springs) && (d->ncouplings <= 0 || d->couplings),
            err, PHM_EINVAL, "model description: a component count is positive but its array is NULL");
  if (d->nelements < 0 || d->npairs < 0 || d->nloads < 0 || d->ncouplings < 0)
    return PHM_FAIL(err, PHM_EINVAL, "negative element, pair, load or coupling count");
  if (!phm_all_finite(d->gravity, 3)) return PHM_FAIL(err, PHM_EINVAL, "gravity has a non-finite entry");
  return PHM_OK;
}

/* Carriers, elements and couplings: finite, in range, their inertias positive definite. */
static phm_status validate_masses(const phm_model_desc *d, phm_error *err) {
  phm_status st;
  for (int i = 0; i < d->ncarriers; i++) {
    const phm_carrier_desc *c = &d->carriers[i];
    if (!phm_all_finite(c->M, 36) || !isfinite(c->mass) || !phm_all_finite(c->com, 3) || !phm_all_finite(c->t0, 6))
      return PHM_FAIL(err, PHM_EINVAL, "carrier %d: non-finite inertia, mass, centre of mass or twist", i);
    /* the mass gravity pulls (the inertia is M): zero for a modal link's slider whose mode has no
     * weight (python/phmech/fidelity.py, modal_sliders) */
    if (!(c->mass >= 0)) return PHM_FAIL(err, PHM_EINVAL, "carrier %d: mass must be >= 0 (got %g kg)", i, c->mass);
    if (!spd6(c->M, 0)) return PHM_FAIL(err, PHM_EINVAL, "carrier %d: spatial inertia is not symmetric positive definite", i);
    if ((st = check_pose(c->H0, "carrier", i, err))) return st;
  }
  for (int i = 0; i < d->nelements; i++) {
    const phm_element_desc *e = &d->elements[i];
    if (e->a < 0 || e->a >= d->ncarriers || e->b < 0 || e->b >= d->ncarriers || e->a == e->b)
      return PHM_FAIL(err, PHM_EINVAL, "element %d: carriers (%d, %d) out of range or equal", i, e->a, e->b);
    if (!(e->h > 0) || !isfinite(e->h)) return PHM_FAIL(err, PHM_EINVAL, "element %d: length must be > 0 (got %g m)", i, e->h);
    if (!phm_all_finite(e->K, 36) || !phm_all_finite(e->D, 36) || !phm_all_finite(e->eps_hat, 6))
      return PHM_FAIL(err, PHM_EINVAL, "element %d: non-finite stiffness, damping or unstressed strain", i);
    if (!spd6(e->K, 0)) return PHM_FAIL(err, PHM_EINVAL, "element %d: section stiffness is not symmetric positive definite", i);
    if (!spd6(e->D, 1)) return PHM_FAIL(err, PHM_EINVAL, "element %d: section damping is not symmetric positive semidefinite", i);
    if (e->mass != PHM_MASS_LUMPED && e->mass != PHM_MASS_CONSISTENT && e->mass != PHM_MASS_GIVEN)
      return PHM_FAIL(err, PHM_EINVAL, "element %d: unknown mass kind %d (0 lumped, 1 consistent, 2 given)", i, e->mass);
    if (e->mass == PHM_MASS_CONSISTENT && (!phm_all_finite(e->Ms, 36) || !spd6(e->Ms, 0)))
      return PHM_FAIL(err, PHM_EINVAL, "element %d: consistent mass needs a finite, symmetric positive definite section inertia", i);
    if (e->mass == PHM_MASS_GIVEN) {
      if (!phm_all_finite(e->Mc, 144)) return PHM_FAIL(err, PHM_EINVAL, "element %d: non-finite mass coupling", i);
      if (!symmetric12(e->Mc)) return PHM_FAIL(err, PHM_EINVAL, "element %d: the mass coupling is not symmetric", i);
      if (!coupled_mass_spd(e->a, e->b, e->Mc, d->carriers))
        return PHM_FAIL(err, PHM_EINVAL, "element %d: its nodes' inertias plus its mass coupling are not positive definite", i);
    }
  }
  for (int i = 0; i < d->ncouplings; i++) {
    const phm_coupling_desc *c = &d->couplings[i];
    if (c->a < 0 || c->a >= d->ncarriers || c->b < 0 || c->b >= d->ncarriers || c->a == c->b)
      return PHM_FAIL(err, PHM_EINVAL, "coupling %d: carriers (%d, %d) out of range or equal", i, c->a, c->b);
    if (!phm_all_finite(c->Mc, 144)) return PHM_FAIL(err, PHM_EINVAL, "coupling %d: non-finite mass coupling", i);
    if (!symmetric12(c->Mc)) return PHM_FAIL(err, PHM_EINVAL, "coupling %d: the mass coupling is not symmetric", i);
    if (!coupled_mass_spd(c->a, c->b, c->Mc, d->carriers))
      return PHM_FAIL(err, PHM_EINVAL, "coupling %d: its carriers' inertias plus the coupling are not positive definite", i);
  }
  return PHM_OK;
}

/* Pairs: type, carriers, frames, the motion or joint laws that drive them, drop masks. */
static phm_status validate_pairs(const phm_model_desc *d, phm_error *err) {
  phm_status st;
  for (int i = 0; i < d->npairs; i++) {
    const phm_pair_desc *p = &d->pairs[i];
    if (p->type < 0 || p->type >= phm_pair_type_count()) return PHM_FAIL(err, PHM_EINVAL, "pair %d: unknown pair type %d", i, p->type);
    if (p->a < -1 || p->a >= d->ncarriers || p->b < -1 || p->b >= d->ncarriers || p->a == p->b)
      return PHM_FAIL(err, PHM_EINVAL, "pair %d: carriers (%d, %d) out of range or equal", i, p->a, p->b);
    if ((st = check_pose(p->Ta, "pair frame Ta of pair", i, err))) return st;
    if ((st = check_pose(p->Tb, "pair frame Tb of pair", i, err))) return st;
    if (p->driven) {
      if (!phm_pair_type(p->type)->drivable)
        return PHM_FAIL(err, PHM_EINVAL, "pair %d: only fixed pairs can be driven by a prescribed motion (use a PD actuator on a %s pair)", i, phm_pair_type(p->type)->name);
      if (!phm_all_finite(p->axis, 6)) return PHM_FAIL(err, PHM_EINVAL, "pair %d: non-finite motion axis", i);
      if ((st = phm_law_check(&p->law, "pair", i, err))) return st;
    }
    if (p->xdriven) {
      const phm_pair_type_info *ti = phm_pair_type(p->type);
      if (p->xdriven < 0 || p->xdriven >= (1 << (6 - ti->m)))
        return PHM_FAIL(err, PHM_EINVAL, "pair %d: driven coordinates %#x beyond the %d joint coordinates of a %s pair", i, (unsigned)p->xdriven, 6 - ti->m, ti->name);
      if (p->xdriven & ~ti->xdrivable)
        return PHM_FAIL(err, PHM_EINVAL, "pair %d: a %s pair's joint coordinates %#x cannot follow a law (their rates are not their time derivatives; drivable: %#x)", i, ti->name, (unsigned)(p->xdriven & ~ti->xdrivable), (unsigned)ti->xdrivable);
      if (p->driven) return PHM_FAIL(err, PHM_EINVAL, "pair %d: driven both by a motion and by joint laws", i);
      for (int c = 0; c < 6 - ti->m; c++)
        if ((p->xdriven >> c & 1) && (st = phm_law_check(&p->xlaw[c], "pair", i, err))) return st;
    }
    if (!isfinite(p->pitch)) return PHM_FAIL(err, PHM_EINVAL, "pair %d: non-finite pitch", i);
    if (p->drop < 0 || p->drop >= (1 << phm_pair_rows_full(p)))
      return PHM_FAIL(err, PHM_EINVAL, "pair %d: drop mask %d names rows beyond the %d constraint rows of a %s pair", i, p->drop, phm_pair_rows_full(p), phm_pair_type(p->type)->name);
    if (p->has_x0 && !phm_all_finite(p->x0, 6 - phm_pair_type(p->type)->m))
      return PHM_FAIL(err, PHM_EINVAL, "pair %d: non-finite initial joint coordinates", i);
  }
  return PHM_OK;
}

/* Actuators, springs and loads. */
static phm_status validate_forces(const phm_model_desc *d, phm_error *err) {
  phm_status st;
  if (d->nactuators < 0 || d->nsprings < 0) return PHM_FAIL(err, PHM_EINVAL, "negative actuator or spring count");
  for (int i = 0; i < d->nactuators; i++) {
    const phm_actuator_desc *a = &d->actuators[i];
    if (a->pair < 0 || a->pair >= d->npairs) return PHM_FAIL(err, PHM_EINVAL, "actuator %d: pair %d out of range", i, a->pair);
    int k = 6 - phm_pair_type(d->pairs[a->pair].type)->m;
    if (k == 0) return PHM_FAIL(err, PHM_EINVAL, "actuator %d: pair %d is fixed (no allowed direction to actuate)", i, a->pair);
    if (a->kind < PHM_ACT_EFFORT || a->kind > PHM_ACT_SPRING) return PHM_FAIL(err, PHM_EINVAL, "actuator %d: unknown kind %d", i, a->kind);
    if (!phm_all_finite(a->vec, k) || !phm_all_finite(a->kp, k) || !phm_all_finite(a->kd, k) || !phm_all_finite(a->x_set, k))
      return PHM_FAIL(err, PHM_EINVAL, "actuator %d: non-finite direction, gain or set point", i);
    if (a->kind != PHM_ACT_EFFORT)
      for (int j = 0; j < k; j++)
        if (a->kp[j] < 0 || a->kd[j] < 0) return PHM_FAIL(err, PHM_EINVAL, "actuator %d: gains must be >= 0 (kp %g, kd %g)", i, a->kp[j], a->kd[j]);
    if (a->kind != PHM_ACT_SPRING && (st = phm_law_check(&a->law, "actuator", i, err))) return st;
  }
  for (int i = 0; i < d->nsprings; i++) {
    const phm_spring_desc *sp = &d->springs[i];
    if (sp->a < -1 || sp->a >= d->ncarriers || sp->b < -1 || sp->b >= d->ncarriers || sp->a == sp->b)
      return PHM_FAIL(err, PHM_EINVAL, "spring %d: carriers (%d, %d) out of range or equal", i, sp->a, sp->b);
    if (!phm_all_finite(sp->pa, 3) || !phm_all_finite(sp->pb, 3) || !isfinite(sp->k) || !isfinite(sp->c) || !isfinite(sp->d0))
      return PHM_FAIL(err, PHM_EINVAL, "spring %d: non-finite point or parameter", i);
    if (sp->k < 0 || sp->c < 0 || sp->d0 < 0)
      return PHM_FAIL(err, PHM_EINVAL, "spring %d: stiffness, damping and rest length must be >= 0 (got %g, %g, %g)", i, sp->k, sp->c, sp->d0);
  }
  for (int i = 0; i < d->nloads; i++) {
    const phm_load_desc *l = &d->loads[i];
    if (l->carrier < 0 || l->carrier >= d->ncarriers) return PHM_FAIL(err, PHM_EINVAL, "load %d: carrier %d out of range", i, l->carrier);
    if (l->reaction < -1 || l->reaction >= d->ncarriers || l->reaction == l->carrier)
      return PHM_FAIL(err, PHM_EINVAL, "load %d: reaction carrier %d out of range or equal to the loaded one", i, l->reaction);
    if (!phm_all_finite(l->w, 6) || !phm_all_finite(l->point, 3)) return PHM_FAIL(err, PHM_EINVAL, "load %d: non-finite wrench or point", i);
    if ((st = phm_law_check(&l->law, "load", i, err))) return st;
  }
  return PHM_OK;
}

/* The model's arrays for the components of a valid description (not filled), or NULL when out of
 * memory. */
static phm_model *model_alloc(const phm_model_desc *d) {
  phm_model *m = calloc(1, sizeof *m);
  if (!m) return NULL;
  m->nc = d->ncarriers;
  m->ne = d->nelements;
  m->np = d->npairs;
  m->nl = d->nloads;
  m->na = d->nactuators;
  m->ns = d->nsprings;
  memcpy(m->gravity, d->gravity, sizeof m->gravity);
  m->car = malloc(sizeof *m->car * (size_t)m->nc);
  m->el = malloc(sizeof *m->el * (size_t)(m->ne + 1));
  m->el_damped = calloc((size_t)(m->ne + 1), 1);
  m->el_ab = malloc(sizeof(int) * (size_t)(2 * m->ne + 1));
  m->car_u = malloc(sizeof(int) * (size_t)(m->nc + 1));
  m->el_sec = malloc(sizeof(int) * (size_t)(m->ne + 1));
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
  if (!m->car || !m->car_u || !m->el || !m->el_damped || !m->el_ab || !m->el_sec || !m->pair || !m->pair_row || !m->pair_m || !m->load ||
      !m->pair_j || !m->pair_k || !m->xref0 || !m->act || !m->spr || !m->pair_sel || !m->pair_rowf || !m->pair_AdTbi) {
    phm_model_free(m);
    return NULL;
  }
  return m;
}

/* The components copied from the description, with what is constant in them (damped elements,
 * the pairs' Ad_{Tb^-1}). */
static void copy_components(phm_model *m, const phm_model_desc *d) {
  memcpy(m->car, d->carriers, sizeof *m->car * (size_t)m->nc);
  if (m->ne) memcpy(m->el, d->elements, sizeof *m->el * (size_t)m->ne);
  for (int i = 0; i < m->ne; i++)
    for (int k = 0; k < 36; k++) m->el_damped[i] |= m->el[i].D[k] != 0.0;
  for (int i = 0; i < m->ne; i++) {
    m->el_ab[2 * i] = m->el[i].a;
    m->el_ab[2 * i + 1] = m->el[i].b;
    /* the section data the element's kernels read, shared with the last distinct element's when
     * bit-identical (a mesh's neighbours: one comparison per element, no search) */
    const phm_element_desc *e = &m->el[i], *u = i > 0 ? &m->el[m->el_sec[i - 1]] : NULL;
    m->el_sec[i] = u && !memcmp(&e->h, &u->h, sizeof e->h) && !memcmp(e->K, u->K, sizeof e->K) &&
                           !memcmp(e->D, u->D, sizeof e->D) && !memcmp(e->eps_hat, u->eps_hat, sizeof e->eps_hat)
                       ? m->el_sec[i - 1] : i;
  }
  if (m->np) memcpy(m->pair, d->pairs, sizeof *m->pair * (size_t)m->np);
  for (int i = 0; i < m->np; i++) { /* constant: computed once, read by every pair evaluation */
    double Tbi[16];
    phm_se3_inverse(m->pair[i].Tb, Tbi);
    phm_se3_Ad(Tbi, m->pair_AdTbi + 36 * i);
  }
  if (m->nl) memcpy(m->load, d->loads, sizeof *m->load * (size_t)m->nl);
  if (m->na) memcpy(m->act, d->actuators, sizeof *m->act * (size_t)m->na);
  if (m->ns) memcpy(m->spr, d->springs, sizeof *m->spr * (size_t)m->ns);
}

/* The mass couplings: consistent and given element masses, then the couplings; 0, or -1 when out
 * of memory. */
static int mass_couplings(phm_model *m, const phm_model_desc *d) {
  for (int i = 0; i < m->ne; i++) m->nmc += m->el[i].mass != PHM_MASS_LUMPED;
  m->nmc += d->ncouplings;
  int nmotor = phm_components_ncouplings(d); /* rotor inertias between two carriers */
  m->nmc += nmotor;
  m->mc_a = malloc(sizeof(int) * (size_t)(m->nmc + 1));
  m->mc_b = malloc(sizeof(int) * (size_t)(m->nmc + 1));
  m->mc = malloc(sizeof(double) * 144 * (size_t)(m->nmc + 1));
  m->mc_rows = malloc(sizeof(unsigned short) * 12 * (size_t)(m->nmc + 1));
  m->mc_u = malloc(sizeof(int) * (size_t)(m->nmc + 1));
  if (!m->mc_a || !m->mc_b || !m->mc || !m->mc_rows || !m->mc_u) return -1;
  int k = 0;
  for (int i = 0; i < m->ne; i++)
    if (m->el[i].mass != PHM_MASS_LUMPED) {
      const phm_element_desc *e = &m->el[i];
      m->mc_a[k] = e->a;
      m->mc_b[k] = e->b;
      if (e->mass == PHM_MASS_GIVEN) memcpy(m->mc + 144 * (size_t)k++, e->Mc, 144 * sizeof(double));
      else phm_element_mass(e->h, e->Ms, e->eps_hat, m->mc + 144 * (size_t)k++);
    }
  for (int i = 0; i < d->ncouplings; i++, k++) {
    m->mc_a[k] = d->couplings[i].a;
    m->mc_b[k] = d->couplings[i].b;
    memcpy(m->mc + 144 * (size_t)k, d->couplings[i].Mc, 144 * sizeof(double));
  }
  phm_components_inertia(m, k);
  for (k = 0; k < m->nmc; k++) {
    phm_mass_rows(m->mc + 144 * (size_t)k, m->mc_rows + 12 * (size_t)k);
    /* shared with the last distinct coupling's when bit-identical (see el_sec) */
    int u = k > 0 ? m->mc_u[k - 1] : -1;
    m->mc_u[k] = u >= 0 && !memcmp(m->mc + 144 * (size_t)k, m->mc + 144 * (size_t)u, 144 * sizeof(double)) ? u : k;
  }
  return 0;
}

/* The laws: each copied with its nodes and tables into two arrays the model owns, and the sorted
 * breakpoints of them all (each once); 0, or -1 when out of memory. */
static int copy_laws(phm_model *m, const phm_model_desc *d) {
  /* every law the model keeps, to count and copy them in one loop */
  int nlaws = 0;
  for (int i = 0; i < m->na; i++) nlaws += d->actuators[i].kind != PHM_ACT_SPRING;
  for (int i = 0; i < m->np; i++) {
    nlaws += d->pairs[i].driven != 0;
    for (int c = 0; c < 6; c++) nlaws += d->pairs[i].xdriven >> c & 1;
  }
  nlaws += m->nl;
  for (int i = 0; i < m->ncomp; i++)
    nlaws += m->comp[i].kind == PHM_COMP_MOTOR || m->comp[i].kind == PHM_COMP_LINEAR;
  size_t nnodes = 0, ndoubles = 0;
  int nbp = 0;
  phm_law **laws = malloc(sizeof(phm_law *) * (size_t)(nlaws + 1));
  if (!laws) return -1;
  nlaws = 0;
  for (int i = 0; i < m->na; i++) {
    if (m->act[i].kind == PHM_ACT_SPRING) memset(&m->act[i].law, 0, sizeof(phm_law));
    else laws[nlaws++] = &m->act[i].law;
  }
  for (int i = 0; i < m->np; i++) {
    phm_pair_desc *pr = &m->pair[i];
    if (pr->driven) laws[nlaws++] = &pr->law;
    else memset(&pr->law, 0, sizeof(phm_law));
    for (int c = 0; c < 6; c++) {
      if (pr->xdriven >> c & 1) laws[nlaws++] = &pr->xlaw[c];
      else memset(&pr->xlaw[c], 0, sizeof(phm_law));
    }
  }
  for (int i = 0; i < m->nl; i++) laws[nlaws++] = &m->load[i].law;
  for (int i = 0; i < m->ncomp; i++) {
    if (m->comp[i].kind == PHM_COMP_MOTOR || m->comp[i].kind == PHM_COMP_LINEAR)
      laws[nlaws++] = &m->comp[i].law;
    else memset(&m->comp[i].law, 0, sizeof(phm_law));
  }
  for (int i = 0; i < nlaws; i++) {
    phm_law_extent(laws[i], &nnodes, &ndoubles);
    nbp += phm_law_breakpoints(laws[i], NULL);
  }
  m->lawnodes = malloc(sizeof(phm_law) * (nnodes + 1));
  m->tables = malloc(sizeof(double) * (ndoubles + 1));
  m->bp = malloc(sizeof(double) * (size_t)(nbp + 1));
  if (!m->lawnodes || !m->tables || !m->bp) {
    free(laws);
    return -1;
  }
  phm_law *np_ = m->lawnodes;
  double *tp = m->tables;
  for (int i = 0; i < nlaws; i++) phm_law_copy(laws[i], &np_, &tp);
  nbp = 0;
  for (int i = 0; i < nlaws; i++) nbp += phm_law_breakpoints(laws[i], m->bp + nbp);
  free(laws);
  qsort(m->bp, (size_t)nbp, sizeof(double), cmp_double);
  int k = 0;
  for (int i = 0; i < nbp; i++)
    if (k == 0 || m->bp[i] > m->bp[k - 1]) m->bp[k++] = m->bp[i];
  m->nbp = k;
  return 0;
}

phm_status phm_model_create(const phm_model_desc *d, phm_model **out, phm_error *err) {
  phm_error_clear(err);
  if (!d || !out) return PHM_FAIL(err, PHM_EINVAL, "phm_model_create: NULL argument");
  *out = NULL;
  phm_status st;
  if ((st = validate_counts(d, err)) || (st = validate_masses(d, err)) || (st = validate_pairs(d, err)) ||
      (st = validate_forces(d, err)) || (st = phm_components_validate(d, err)))
    return st;
  phm_model *m = model_alloc(d);
  if (!m) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  copy_components(m, d);
  if (phm_components_copy(m, d) || mass_couplings(m, d) || copy_laws(m, d)) {
    phm_model_free(m);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
  for (int c = 0; c < m->nc; c++) { /* after the components' rotor inertias (mass_couplings) */
    const phm_carrier_desc *a = &m->car[c], *u = c > 0 ? &m->car[m->car_u[c - 1]] : NULL;
    m->car_u[c] = u && !memcmp(a->M, u->M, sizeof a->M) && !memcmp(&a->mass, &u->mass, sizeof a->mass) &&
                          !memcmp(a->com, u->com, sizeof a->com)
                      ? m->car_u[c - 1] : c;
  }
  pair_layout(m);
  m->nport = m->na + m->nl + m->ns;
  double lref = 0;
  for (int i = 0; i < m->ne; i++) lref = fmax(lref, m->el[i].h);
  m->lref = lref > 0 ? lref : 1.0;
  *out = m;
  return PHM_OK;
}

int phm_model_ncarriers(const phm_model *m) { return m->nc; }
int phm_model_nconstraints(const phm_model *m) { return m->ncons; }
int phm_model_npairs(const phm_model *m) { return m->np; }
int phm_model_nelements(const phm_model *m) { return m->ne; }
int phm_model_njoints(const phm_model *m) { return m->nj; }
int phm_model_nports(const phm_model *m) { return m->nport; }
int phm_model_ncompstates(const phm_model *m) { return m->nz; }
int phm_model_nloads(const phm_model *m) { return m->nl; }
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

phm_status phm_model_set_spin(phm_model *m, const double S[6], phm_error *err) {
  phm_error_clear(err);
  PHM_CHECK(m && S, err, PHM_EINVAL, "phm_model_set_spin: NULL argument");
  PHM_CHECK(phm_all_finite(S, 6), err, PHM_EINVAL, "steady rotation: non-finite twist");
  m->has_spin = 0;
  for (int i = 0; i < 6; i++) {
    m->spin[i] = S[i];
    m->has_spin |= S[i] != 0;
  }
  return PHM_OK;
}

phm_status phm_model_set_initial(phm_model *m, const double *H0, const double *t0,
                                 const double *x0, const int *drop, phm_error *err) {
  phm_error_clear(err);
  PHM_CHECK(m && H0, err, PHM_EINVAL, "phm_model_set_initial: NULL argument");
  phm_status st;
  for (int c = 0; c < m->nc; c++) {
    if ((st = check_pose(H0 + 16 * c, "carrier", c, err))) return st;
    PHM_CHECK(!t0 || phm_all_finite(t0 + 6 * c, 6), err, PHM_EINVAL, "carrier %d: non-finite twist", c);
  }
  for (int i = 0; i < m->np; i++) {
    int mt = phm_pair_rows_full(&m->pair[i]), k = 6 - phm_pair_type(m->pair[i].type)->m;
    PHM_CHECK(!x0 || phm_all_finite(x0 + 6 * i, k), err, PHM_EINVAL,
              "pair %d: non-finite initial joint coordinates", i);
    PHM_CHECK(!drop || (drop[i] >= 0 && drop[i] < (1 << mt)), err, PHM_EINVAL,
              "pair %d: drop mask %d names rows beyond the %d constraint rows of a %s pair", i,
              drop ? drop[i] : 0, mt, phm_pair_type(m->pair[i].type)->name);
  }
  for (int c = 0; c < m->nc; c++) {
    memcpy(m->car[c].H0, H0 + 16 * c, sizeof(double) * 16);
    if (t0) memcpy(m->car[c].t0, t0 + 6 * c, sizeof(double) * 6);
  }
  for (int i = 0; i < m->np; i++) {
    if (x0) memcpy(m->pair[i].x0, x0 + 6 * i, sizeof(double) * 6);
    if (drop) m->pair[i].drop = drop[i];
  }
  pair_layout(m);
  return PHM_OK;
}
