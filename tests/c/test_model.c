/* test_model.c -- csrc/model/model.c, the immutable model: descriptions refused with a message
 * naming the component and the fault, the layout of constraint rows and joint coordinates, the
 * laws' breakpoints and tref, copies of the caller's law tables, and phm_model_set_initial (the
 * layout recomputed when drop masks change; bad inputs refused with a message, the model left
 * as it was). */
#include "check.h"
#include "model.h"

/* Three carriers; pairs: revolute ground-0 (5 rows, 1 coordinate), spherical 0-1 (3, 3, with
 * x0), fixed 1-2 driven by a pulse (6, 0); an effort actuator on the revolute pair (step law), a
 * load on carrier 2 (table law), a spring 0-2; an element 0-1. */
typedef struct {
  phm_carrier_desc car[3];
  phm_element_desc el;
  phm_pair_desc pr[3];
  phm_actuator_desc ac;
  phm_load_desc ld;
  phm_spring_desc sp;
  phm_coupling_desc cp; /* a kinetic coupling without an element, used by the faults only */
  double table[6];
  phm_model_desc d;
} desc3;

static void desc3_init(desc3 *s) {
  memset(s, 0, sizeof *s);
  for (int c = 0; c < 3; c++) {
    carrier_unit(&s->car[c]);
    s->car[c].H0[3] = c; /* 1 m apart along x */
  }
  s->el.a = 0;
  s->el.b = 1;
  s->el.h = 1.0;
  for (int i = 0; i < 6; i++) {
    s->el.K[7 * i] = 10.0;
    s->el.D[7 * i] = 0.1;
  }
  s->el.eps_hat[3] = 1.0;
  const int type[3] = {pair_code("revolute"), pair_code("spherical"), pair_code("fixed")};
  for (int i = 0; i < 3; i++) {
    s->pr[i].type = type[i];
    s->pr[i].a = i - 1;
    s->pr[i].b = i;
    memcpy(s->pr[i].Ta, s->car[0].H0, sizeof s->pr[i].Ta);
    memcpy(s->pr[i].Tb, s->car[0].H0, sizeof s->pr[i].Tb);
  }
  s->pr[1].has_x0 = 1;
  s->pr[1].x0[0] = 0.1;
  s->pr[2].driven = 1;
  s->pr[2].axis[5] = 1.0;
  s->pr[2].law.kind = PHM_LAW_PULSE;
  s->pr[2].law.amplitude = 0.1;
  s->pr[2].law.t0 = 0.5;
  s->pr[2].law.duration = 0.25;
  s->ac.pair = 0;
  s->ac.kind = PHM_ACT_EFFORT;
  s->ac.vec[0] = 1.0;
  s->ac.law.kind = PHM_LAW_STEP;
  s->ac.law.amplitude = 2.0;
  s->ac.law.t0 = 0.5;
  const double table[6] = {0.0, 1.0, 0.75, 2.0, 2.0, 0.0};
  memcpy(s->table, table, sizeof table);
  s->ld.carrier = 2;
  s->ld.reaction = -1;
  s->ld.w[5] = -1.0;
  s->ld.law.kind = PHM_LAW_TABLE;
  s->ld.law.table = s->table;
  s->ld.law.ntable = 3;
  s->sp.a = 0;
  s->sp.b = 2;
  s->sp.k = 5.0;
  s->sp.d0 = 2.0;
  s->d.ncarriers = 3;
  s->d.carriers = s->car;
  s->d.nelements = 1;
  s->d.elements = &s->el;
  s->d.npairs = 3;
  s->d.pairs = s->pr;
  s->d.nactuators = 1;
  s->d.actuators = &s->ac;
  s->d.nloads = 1;
  s->d.loads = &s->ld;
  s->d.nsprings = 1;
  s->d.springs = &s->sp;
}

/* The model of a fresh desc3 (NULL, and a failure recorded, if refused). */
static phm_model *desc3_model(desc3 *s) {
  desc3_init(s);
  return create_model(&s->d);
}

/* The layout of every pair: (first row, rows, first joint coordinate, k). */
static int layout_is(const phm_model *m, const int want[][4], int nconstraints, int njoints) {
  int ok = phm_model_nconstraints(m) == nconstraints && phm_model_njoints(m) == njoints;
  for (int ip = 0; ip < phm_model_npairs(m); ip++) {
    int got[4];
    phm_model_pair_layout(m, ip, &got[0], &got[1], &got[2], &got[3]);
    for (int j = 0; j < 4; j++) ok &= got[j] == want[ip][j];
  }
  return ok;
}

static void a_valid_description_gives_sizes_layout_and_breakpoints(void) {
  desc3 s;
  phm_model *m = desc3_model(&s);
  if (!m) return;
  const int layout[3][4] = {{0, 5, 0, 1}, {5, 3, 1, 3}, {8, 6, 4, 0}};
  CHECK(phm_model_ncarriers(m) == 3 && phm_model_npairs(m) == 3 && phm_model_nports(m) == 3,
        "3 carriers, 3 pairs, 3 ports (actuator, load, spring)");
  CHECK(layout_is(m, layout, 14, 4) && phm_model_nconstraints_full(m) == 14,
        "rows 5 + 3 + 6 = 14, joint coordinates 1 + 3 + 0 = 4, in pair order");
  /* breakpoints: step 0.5; pulse 0.5, 0.75; table 0, 0.75, 2 -> sorted, distinct */
  const double bp[4] = {0.0, 0.5, 0.75, 2.0};
  CHECK(m->nbp == 4 && maxdiff(4, m->bp, bp) == 0, "breakpoints of all laws sorted and distinct (%d)",
        m->nbp);
  double next, tr, t_below = 0.75 * (1 - 1e-16);
  tr = phm_model_tref(m, 0.6, &next);
  check("tref between breakpoints: the midpoint to the next", fabs(tr - 0.675) + fabs(next - 0.75), 1e-15);
  tr = phm_model_tref(m, 0.5, &next);
  check("tref at a breakpoint: the interval that starts there", fabs(tr - 0.625) + fabs(next - 0.75), 1e-15);
  tr = phm_model_tref(m, t_below, &next);
  check("tref within 1e-14 (relative) below a breakpoint: the interval after it",
        fabs(tr - 0.5 * (t_below + 2.0)) + fabs(next - 2.0), 1e-15);
  tr = phm_model_tref(m, 2.0, &next);
  CHECK(tr == 3.0 && isinf(next), "after the last breakpoint: tref = t + 1, next = inf");
  /* the model owns copies: the caller's description may change or go */
  s.table[3] = 99.0;
  s.car[0].H0[3] = 42.0;
  CHECK(m->load[0].law.table != s.table && m->load[0].law.table[3] == 2.0 && m->car[0].H0[3] == 0.0,
        "the model keeps its own copy of the law tables and carriers");
  CHECK(m->xref0[1] == 0.1 && m->xref0[0] == 0.0, "branch references: x0 where given, else 0");
  phm_model_free(m);
  phm_model_free(NULL);
}

/* Fault number `fault` of desc3 (d may become NULL); returns the message that must name it. */
static const char *apply_fault(desc3 *s, int fault, const phm_model_desc **d) {
  switch (fault) {
  case 0: *d = NULL; return "phm_model_create: NULL argument";
  case 1: s->d.ncarriers = 0; return "model has no carrier";
  case 2: s->d.nelements = -1; return "negative element, pair, load or coupling count";
  case 3: s->d.gravity[1] = NAN; return "gravity has a non-finite entry";
  case 4: s->car[1].mass = -1; return "carrier 1: mass must be >= 0 (got -1 kg)";
  case 5: s->car[0].M[1] = 0.5; return "carrier 0: spatial inertia is not symmetric positive definite";
  case 6: s->car[2].H0[0] = 1.1; return "carrier 2: pose rotation is not orthonormal with det +1";
  case 7: /* a reflection: orthonormal, det -1 */
    s->car[2].H0[0] = s->car[2].H0[5] = s->car[2].H0[10] = -1;
    return "carrier 2: pose rotation is not orthonormal with det +1";
  case 8: s->car[0].H0[12] = 1e-9; return "carrier 0: pose last row must be (0, 0, 0, 1)";
  case 9: s->el.b = 0; return "element 0: carriers (0, 0) out of range or equal";
  case 10: s->el.h = 0; return "element 0: length must be > 0 (got 0 m)";
  case 11: s->el.K[7 * 4] = -1; return "element 0: section stiffness is not symmetric positive definite";
  case 12: s->el.D[7 * 2] = -1e-3; return "element 0: section damping is not symmetric positive semidefinite";
  case 13: s->pr[1].type = 99; return "pair 1: unknown pair type 99";
  case 14: s->pr[0].b = 5; return "pair 0: carriers (-1, 5) out of range or equal";
  case 15: s->pr[1].Tb[7] = NAN; return "pair frame Tb of pair 1: pose has a non-finite entry";
  case 16:
    s->pr[0].driven = 1;
    return "pair 0: only fixed pairs can be driven by a prescribed motion (use a PD actuator on a revolute pair)";
  case 17: s->pr[2].law.duration = 0; return "pair 2: time law duration must be > 0";
  case 18: s->pr[0].drop = 32; return "pair 0: drop mask 32 names rows beyond the 5 constraint rows of a revolute pair";
  case 19: s->pr[1].x0[2] = INFINITY; return "pair 1: non-finite initial joint coordinates";
  case 20: s->ac.pair = 2; return "actuator 0: pair 2 is fixed (no allowed direction to actuate)";
  case 21: s->ac.kind = 7; return "actuator 0: unknown kind 7";
  case 22: s->ac.kind = PHM_ACT_PD; s->ac.kd[0] = -1; return "actuator 0: gains must be >= 0 (kp 0, kd -1)";
  case 23: s->sp.d0 = -1; return "spring 0: stiffness, damping and rest length must be >= 0 (got 5, 0, -1)";
  case 24: s->ld.reaction = 2; return "load 0: reaction carrier 2 out of range or equal to the loaded one";
  case 25: s->table[2] = -1.0; return "load 0: table law times must be strictly increasing";
  case 26: s->el.mass = 3; return "element 0: unknown mass kind 3 (0 lumped, 1 consistent, 2 given)";
  case 27: s->el.mass = PHM_MASS_CONSISTENT; return "element 0: consistent mass needs a finite, symmetric positive definite section inertia";
  case 28: /* a given coupling that is not symmetric */
    s->el.mass = PHM_MASS_GIVEN;
    s->el.Mc[1] = 0.1;
    return "element 0: the mass coupling is not symmetric";
  case 29: /* symmetric, but it takes more than the nodes' unit inertias have */
    s->el.mass = PHM_MASS_GIVEN;
    s->el.Mc[0] = -1.0;
    return "element 0: its nodes' inertias plus its mass coupling are not positive definite";
  case 30: /* couplings without an element: carriers 0 and 2 (no element between them) */
  case 31:
  case 32:
  case 33:
    s->cp.a = 0;
    s->cp.b = 2;
    s->d.ncouplings = 1;
    s->d.couplings = &s->cp;
    if (fault == 30) { s->cp.b = 0; return "coupling 0: carriers (0, 0) out of range or equal"; }
    if (fault == 31) { s->cp.Mc[5] = NAN; return "coupling 0: non-finite mass coupling"; }
    if (fault == 32) { s->cp.Mc[12 * 3 + 9] = 0.1; return "coupling 0: the mass coupling is not symmetric"; }
    s->cp.Mc[6] = s->cp.Mc[72] = 1.0; /* rotation x of a with rotation x of b, at the unit inertias */
    return "coupling 0: its carriers' inertias plus the coupling are not positive definite";
  case 34: s->d.ncouplings = 1; return "a component count is positive but its array is NULL";
  default: return NULL;
  }
}

/* One fault per description, each refused with PHM_EINVAL and a message naming it; a refusal
 * hands back no model (the caller's pointer is set to NULL). */
static void invalid_descriptions_are_refused_with_a_message(void) {
  desc3 ok;
  phm_model *valid = desc3_model(&ok);
  if (!valid) return;
  for (int fault = 0;; fault++) {
    desc3 s;
    desc3_init(&s);
    const phm_model_desc *d = &s.d;
    const char *want = apply_fault(&s, fault, &d);
    if (!want) break;
    phm_model *m = valid;
    phm_error err;
    phm_status st = phm_model_create(d, &m, &err);
    check_refused(want, st, PHM_EINVAL, &err, want);
    if (st == PHM_OK) phm_model_free(m);
    else if (d) CHECK(m == NULL, "%s: no model handed back", want);
  }
  phm_model_free(valid);
}

/* The model's initial poses and twists are H0 (3 x 16) and t0 (3 x 6). */
static int initial_state_is(const phm_model *m, const double *H0, const double *t0) {
  int same = 1;
  for (int c = 0; c < 3; c++)
    same &= maxdiff(16, m->car[c].H0, H0 + 16 * c) == 0 && maxdiff(6, m->car[c].t0, t0 + 6 * c) == 0;
  return same;
}

static void set_initial_recomputes_the_layout_and_refuses_bad_input(void) {
  desc3 s;
  phm_model *m = desc3_model(&s);
  if (!m) return;
  phm_error err;
  double H0[48], t0[18], x0[18] = {0};
  for (int c = 0; c < 3; c++) {
    rand_pose(H0 + 16 * c, 1.0);
    for (int i = 0; i < 6; i++) t0[6 * c + i] = rand11();
  }
  x0[6] = 0.3; /* pair 1 (spherical, has x0) */
  x0[7] = -0.2;
  /* drop rows 0 and 1 of the revolute pair and row 0 of the fixed one */
  int drop[3] = {0x3, 0, 0x1};
  phm_status st = phm_model_set_initial(m, H0, t0, x0, drop, &err);
  const int dropped[3][4] = {{0, 3, 0, 1}, {3, 3, 1, 3}, {6, 5, 4, 0}};
  CHECK(st == PHM_OK && layout_is(m, dropped, 11, 4) && phm_model_nconstraints_full(m) == 14,
        "drop masks 0x3, 0, 0x1: rows 3 + 3 + 5 = 11 (full set still 14)");
  CHECK(initial_state_is(m, H0, t0), "initial poses and twists replaced");
  CHECK(m->xref0[1] == 0.3 && m->xref0[2] == -0.2, "branch references follow the new x0");
  double g[11], G[11 * 18], gf[14];
  phm_constraints_dense(m, H0, NULL, 0.0, 0.25, g, G, NULL);
  phm_constraints_full(m, H0, NULL, 0.0, gf, NULL, NULL);
  const int kept[11] = {2, 3, 4, 5, 6, 7, 9, 10, 11, 12, 13};
  double e = 0;
  for (int r = 0; r < 11; r++) e = fmax(e, fabs(g[r] - gf[kept[r]]));
  check("the constraints follow the new layout (kept rows of the full set)", e, 0.0);
  /* masks back to zero: the original layout; NULL twists and x0: kept */
  int none[3] = {0, 0, 0};
  st = phm_model_set_initial(m, H0, NULL, NULL, none, &err);
  const int full[3][4] = {{0, 5, 0, 1}, {5, 3, 1, 3}, {8, 6, 4, 0}};
  CHECK(st == PHM_OK && layout_is(m, full, 14, 4), "drop masks cleared: 14 rows again");
  CHECK(maxdiff(6, m->car[1].t0, t0 + 6) == 0 && m->xref0[1] == 0.3,
        "NULL twists and x0 keep the previous ones");

  /* refusals leave the model as it was */
  double Hbad[48], tbad[18], xbad[18];
  int dbad[3] = {0, 0, 0};
  memcpy(Hbad, H0, sizeof Hbad);
  Hbad[16 * 2 + 5] = 2.0;
  st = phm_model_set_initial(m, Hbad, NULL, NULL, drop, &err);
  check_refused("set_initial: a pose that is not a rotation", st, PHM_EINVAL, &err,
                "carrier 2: pose rotation is not orthonormal");
  memcpy(tbad, t0, sizeof tbad);
  tbad[6 + 4] = NAN;
  st = phm_model_set_initial(m, H0, tbad, NULL, drop, &err);
  check_refused("set_initial: a non-finite twist", st, PHM_EINVAL, &err, "carrier 1: non-finite twist");
  memcpy(xbad, x0, sizeof xbad);
  xbad[8] = INFINITY;
  st = phm_model_set_initial(m, H0, NULL, xbad, drop, &err);
  check_refused("set_initial: non-finite joint coordinates", st, PHM_EINVAL, &err,
                "pair 1: non-finite initial joint coordinates");
  dbad[0] = 32;
  st = phm_model_set_initial(m, H0, NULL, NULL, dbad, &err);
  check_refused("set_initial: a drop mask beyond the rows", st, PHM_EINVAL, &err,
                "pair 0: drop mask 32 names rows beyond the 5 constraint rows of a revolute pair");
  dbad[0] = 0;
  dbad[2] = -1;
  st = phm_model_set_initial(m, H0, NULL, NULL, dbad, &err);
  check_refused("set_initial: a negative drop mask", st, PHM_EINVAL, &err,
                "pair 2: drop mask -1 names rows beyond the 6 constraint rows of a fixed pair");
  st = phm_model_set_initial(m, NULL, NULL, NULL, NULL, &err);
  check_refused("set_initial: no poses", st, PHM_EINVAL, &err, "phm_model_set_initial: NULL argument");
  CHECK(layout_is(m, full, 14, 4) && m->xref0[1] == 0.3 && initial_state_is(m, H0, t0),
        "refused calls leave poses, twists, x0 and layout unchanged");
  phm_model_free(m);
}

CHECK_MAIN(CHECK_CASE(a_valid_description_gives_sizes_layout_and_breakpoints),
           CHECK_CASE(invalid_descriptions_are_refused_with_a_message),
           CHECK_CASE(set_initial_recomputes_the_layout_and_refuses_bad_input))
