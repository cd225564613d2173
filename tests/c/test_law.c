/* test_law.c -- csrc/util/law.c, the scalar time laws s(t): each kind against its closed form,
 * ds and dds against central finite differences, the piece chosen by tref, the breakpoints, and
 * the messages of phm_law_check. */
#include "check.h"
#include "law.h"

static phm_law law_of(int kind, double amplitude, double t0, double duration) {
  return (phm_law){.kind = kind, .amplitude = amplitude, .t0 = t0, .duration = duration};
}

/* |ds - FD(s)| and |dds - FD(ds)| (central differences, step h) at t inside one piece (tref = t),
 * relative to scale1 and scale2. */
static void check_derivatives(const char *what, const phm_law *l, double t, double h,
                              double scale1, double scale2, double tol) {
  char name[128];
  double ds, dds, dsp, dsm;
  phm_law_eval(l, t, t, &ds, &dds);
  double sp = phm_law_eval(l, t + h, t, &dsp, NULL), sm = phm_law_eval(l, t - h, t, &dsm, NULL);
  snprintf(name, sizeof name, "%s: ds = ds/dt (central FD)", what);
  check(name, fabs(ds - (sp - sm) / (2 * h)) / scale1, tol);
  snprintf(name, sizeof name, "%s: dds = d(ds)/dt (central FD)", what);
  check(name, fabs(dds - (dsp - dsm) / (2 * h)) / scale2, tol);
}

static void constant_step_and_pulse_are_piecewise_constant(void) {
  phm_law c = law_of(PHM_LAW_CONSTANT, 2.5, 0, 0), st = law_of(PHM_LAW_STEP, -1.5, 0.4, 0),
          pu = law_of(PHM_LAW_PULSE, 3.0, 0.2, 0.5);
  for (int i = 0; i < 50; i++) {
    double t = 2 * rand11(), ds = 1, dds = 1, s;
    s = phm_law_eval(&c, t, t, &ds, &dds);
    check("constant: s = amplitude, ds = dds = 0", fabs(s - 2.5) + fabs(ds) + fabs(dds), 0.0);
    ds = dds = 1;
    s = phm_law_eval(&st, t, t, &ds, &dds);
    check("step: s = amplitude for t >= t0, else 0; ds = dds = 0",
          fabs(s - (t >= 0.4 ? -1.5 : 0.0)) + fabs(ds) + fabs(dds), 0.0);
    ds = dds = 1;
    s = phm_law_eval(&pu, t, t, &ds, &dds);
    check("pulse: s = amplitude on [t0, t0 + duration), else 0; ds = dds = 0",
          fabs(s - (t >= 0.2 && t < 0.7 ? 3.0 : 0.0)) + fabs(ds) + fabs(dds), 0.0);
  }
  /* the piece is chosen by tref, at the breakpoints themselves too */
  check("step: value at t0 (tref = t0) is the amplitude", fabs(phm_law_eval(&st, 0.4, 0.4, NULL, NULL) + 1.5), 0.0);
  check("step: tref after t0 selects the amplitude at any t", fabs(phm_law_eval(&st, 0.3, 0.5, NULL, NULL) + 1.5), 0.0);
  check("step: tref before t0 selects 0 at any t", fabs(phm_law_eval(&st, 0.5, 0.3, NULL, NULL)), 0.0);
  check("pulse: on at t0", fabs(phm_law_eval(&pu, 0.2, 0.2, NULL, NULL) - 3.0), 0.0);
  check("pulse: off at t0 + duration", fabs(phm_law_eval(&pu, 0.7, 0.7, NULL, NULL)), 0.0);
}

static void sine_matches_its_closed_form_and_derivatives(void) {
  for (int i = 0; i < 50; i++) {
    phm_law l = law_of(PHM_LAW_SINE, (rand01() < 0.5 ? -1 : 1) * (0.5 + 1.5 * rand01()), 0, 0);
    l.frequency = 0.1 + 3 * rand01();
    l.phase = 3 * rand11();
    l.offset = rand11();
    double t = 5 * rand11(), ds, dds, w = 2 * CHECK_PI * l.frequency, a = w * t + l.phase;
    double s = phm_law_eval(&l, t, t, &ds, &dds), A = fabs(l.amplitude);
    check("sine: s = offset + amplitude sin(2 pi f t + phase)",
          fabs(s - (l.offset + l.amplitude * sin(a))), 1e-14 * (1 + A));
    check("sine: ds = amplitude w cos(w t + phase)", fabs(ds - l.amplitude * w * cos(a)), 1e-14 * (1 + A * w));
    check("sine: dds = -amplitude w^2 sin(w t + phase)", fabs(dds + l.amplitude * w * w * sin(a)),
          1e-14 * (1 + A * w * w));
    check_derivatives("sine", &l, t, 1e-5, A * w, A * w * w, 1e-7);
  }
}

static void table_interpolates_linearly_within_the_piece_of_tref(void) {
  const double T[] = {0.0, 1.0, 1.0, 3.0, 3.0, 2.0, 4.0, 2.0};
  phm_law l = law_of(PHM_LAW_TABLE, 0, 0, 0);
  l.table = T;
  l.ntable = 4;
  for (int i = 0; i < 50; i++) {
    double t = -1 + 6 * rand01(), ds, dds, s = phm_law_eval(&l, t, t, &ds, &dds), ref, slope;
    if (t < 0) { /* constant outside */
      ref = 1.0;
      slope = 0;
    } else if (t < 1) {
      ref = 1 + 2 * t;
      slope = 2;
    } else if (t < 3) {
      ref = 3 - 0.5 * (t - 1);
      slope = -0.5;
    } else {
      ref = 2.0;
      slope = 0;
    }
    check("table: s = linear interpolation (constant outside)", fabs(s - ref), 1e-15 * 4);
    check("table: ds = slope of the piece, dds = 0", fabs(ds - slope) + fabs(dds), 1e-15 * 4);
  }
  const double inside[] = {0.3, 0.77, 1.5, 2.2, 2.9}; /* h = 1e-3 from the breakpoints */
  for (int i = 0; i < 5; i++) check_derivatives("table", &l, inside[i], 1e-3, 2.0, 1.0, 1e-12);
  /* the piece of tref, its formula evaluated at t (extrapolated): */
  check("table: tref in piece 0, t in piece 1 -> piece 0 extrapolated",
        fabs(phm_law_eval(&l, 1.2, 0.9, NULL, NULL) - 3.4), 1e-15 * 4);
  check("table: tref at a breakpoint selects the piece that starts there",
        fabs(phm_law_eval(&l, 1.0, 1.0, NULL, NULL) - 3.0), 0.0);
  check("table: tref at the last time: the last value", fabs(phm_law_eval(&l, 4.0, 4.0, NULL, NULL) - 2.0), 0.0);
  l.ntable = 1;
  check("table of one point: its value everywhere",
        fabs(phm_law_eval(&l, -3.0, -3.0, NULL, NULL) - 1.0) + fabs(phm_law_eval(&l, 5.0, 5.0, NULL, NULL) - 1.0), 0.0);
}

/* s = A (u - sin(2 pi u)/(2 pi)), u = (t - t0)/T on [t0, t0 + T]: 0 -> A with ds = dds = 0 at
 * both ends (C2). */
static void cycloidal_ramp_is_c2_with_closed_form_values(void) {
  const double A = 1.7, t0 = 0.3, T = 0.8;
  phm_law l = law_of(PHM_LAW_CYCLOIDAL, A, t0, T);
  double ds, dds, s;
  s = phm_law_eval(&l, t0 + T / 2, t0 + T / 2, &ds, &dds);
  check("cycloidal at mid-ramp: s = A/2, ds = 2A/T, dds = 0",
        fabs(s - A / 2) + fabs(ds - 2 * A / T) + fabs(dds) * T * T, 1e-14);
  s = phm_law_eval(&l, t0 + T / 4, t0 + T / 4, &ds, &dds);
  check("cycloidal at a quarter: s = A (1/4 - 1/(2 pi)), ds = A/T, dds = 2 pi A/T^2",
        fabs(s - A * (0.25 - 1 / (2 * CHECK_PI))) + fabs(ds - A / T) * T + fabs(dds - 2 * CHECK_PI * A / (T * T)) * T * T, 1e-14);
  s = phm_law_eval(&l, t0, t0 + 1e-9, &ds, &dds);
  check("cycloidal at t0 (ramp piece): s = ds = dds = 0", fabs(s) + fabs(ds) * T + fabs(dds) * T * T, 1e-15);
  s = phm_law_eval(&l, t0 + T, t0 + T - 1e-9, &ds, &dds);
  check("cycloidal at t0 + T (ramp piece): s = A, ds = dds = 0",
        fabs(s - A) + fabs(ds) * T + fabs(dds) * T * T, 1e-14);
  s = phm_law_eval(&l, t0 - 0.1, t0 - 0.1, &ds, &dds);
  check("cycloidal before t0: 0", fabs(s) + fabs(ds) + fabs(dds), 0.0);
  s = phm_law_eval(&l, t0 + T, t0 + T, &ds, &dds);
  check("cycloidal from t0 + T on: A", fabs(s - A) + fabs(ds) + fabs(dds), 0.0);
  for (int i = 0; i < 20; i++)
    check_derivatives("cycloidal", &l, t0 + T * (0.02 + 0.96 * rand01()), 1e-5, A / T,
                      2 * CHECK_PI * A / (T * T), 1e-7);
}

static void breakpoints_are_where_pieces_start_or_end(void) {
  const double T[] = {0.0, 1.0, 1.0, 3.0, 3.5, 2.0};
  phm_law table = law_of(PHM_LAW_TABLE, 0, 0, 0), sine = law_of(PHM_LAW_SINE, 1, 0, 0);
  table.table = T;
  table.ntable = 3;
  const struct {
    phm_law law;
    int n;
    double bp[3];
  } cases[] = {{law_of(PHM_LAW_CONSTANT, 1, 0.5, 1), 0, {0}},
               {law_of(PHM_LAW_STEP, 1, 0.5, 1), 1, {0.5}},
               {law_of(PHM_LAW_PULSE, 1, 0.5, 0.25), 2, {0.5, 0.75}},
               {sine, 0, {0}},
               {table, 3, {0.0, 1.0, 3.5}},
               {law_of(PHM_LAW_CYCLOIDAL, 1, 0.5, 2), 2, {0.5, 2.5}}};
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    double bp[3] = {-1, -1, -1};
    int n0 = phm_law_breakpoints(&cases[c].law, NULL), n = phm_law_breakpoints(&cases[c].law, bp);
    CHECK(n0 == cases[c].n && n == cases[c].n && maxdiff(n, bp, cases[c].bp) == 0,
          "law kind %d: %d breakpoints (counted %d, listed %d)", cases[c].law.kind, cases[c].n, n0, n);
  }
}

static void invalid_laws_are_refused_with_a_message(void) {
  const double good[] = {0.0, 1.0, 1.0, 2.0}, equal_times[] = {0.0, 1.0, 0.0, 2.0},
               nan_entry[] = {0.0, 1.0, 1.0, NAN};
  phm_error err;
  phm_law l = law_of(PHM_LAW_SINE, INFINITY, 0, 0);
  check_refused("non-finite parameter", phm_law_check(&l, "pair", 3, &err), PHM_EINVAL, &err,
                "pair 3: time law has a non-finite parameter");
  l = law_of(PHM_LAW_STEP, 1, NAN, 0);
  check_refused("non-finite t0", phm_law_check(&l, "load", 4, &err), PHM_EINVAL, &err,
                "load 4: time law has a non-finite parameter");
  l = law_of(PHM_LAW_PULSE, 1, 0, 0);
  check_refused("pulse of zero duration", phm_law_check(&l, "actuator", 0, &err), PHM_EINVAL, &err,
                "actuator 0: time law duration must be > 0 (got 0 s)");
  l = law_of(PHM_LAW_CYCLOIDAL, 1, 0, -1);
  check_refused("cycloidal of negative duration", phm_law_check(&l, "pair", 1, &err), PHM_EINVAL,
                &err, "duration must be > 0 (got -1 s)");
  l = law_of(PHM_LAW_TABLE, 0, 0, 0);
  l.table = good;
  l.ntable = 0;
  check_refused("table without points", phm_law_check(&l, "load", 2, &err), PHM_EINVAL, &err,
                "load 2: table law needs at least one (t, value) point");
  l.ntable = 2;
  l.table = NULL;
  check_refused("table without its array", phm_law_check(&l, "load", 2, &err), PHM_EINVAL, &err,
                "table law needs at least one (t, value) point");
  l.table = nan_entry;
  check_refused("table with a NaN value", phm_law_check(&l, "load", 2, &err), PHM_EINVAL, &err,
                "table law has a non-finite entry");
  l.table = equal_times;
  check_refused("table with repeated times", phm_law_check(&l, "load", 2, &err), PHM_EINVAL, &err,
                "table law times must be strictly increasing");
  l = law_of(17, 1, 0, 0);
  check_refused("unknown kind", phm_law_check(&l, "actuator", 5, &err), PHM_EINVAL, &err,
                "actuator 5: unknown time law kind 17");
  /* valid laws of every kind pass */
  phm_law ok[6] = {law_of(PHM_LAW_CONSTANT, 1, 0, 0), law_of(PHM_LAW_STEP, 1, -2, 0),
                   law_of(PHM_LAW_PULSE, 1, 0, 1e-9), law_of(PHM_LAW_SINE, 1, 0, 0),
                   law_of(PHM_LAW_TABLE, 0, 0, 0), law_of(PHM_LAW_CYCLOIDAL, 1, 0, 2)};
  ok[4].table = good;
  ok[4].ntable = 2;
  for (int k = 0; k < 6; k++) {
    phm_status st = phm_law_check(&ok[k], "pair", 0, &err);
    CHECK(st == PHM_OK, "valid law of kind %d accepted (status %d: %s)", k, st, st ? err.msg : "");
  }
}

/* Linear, a piecewise polynomial (a C1 joint and a C2 one), a postfix expression and a callback:
 * values against their closed forms, derivatives against central differences, the piece chosen
 * by t (by tref within round-off of a break), breakpoints only where s, s' or s'' jumps. */
static int cb_calls;
static int square_cb(void *ctx, double t, int nder, double out[3]) {
  (void)nder;
  cb_calls++;
  double a = *(const double *)ctx;
  if (t > 10) return 1; /* fails beyond 10 s */
  out[0] = a * t * t;
  out[1] = 2 * a * t;
  out[2] = 2 * a;
  return 0;
}

static void linear_ppoly_expression_and_callback_laws(void) {
  phm_law lin = law_of(PHM_LAW_LINEAR, 2.5, 0, 0);
  lin.offset = -1.0;
  double ds, dds, s = phm_law_eval(&lin, 0.8, 0.8, &ds, &dds);
  check("linear: s = offset + rate t, ds = rate, dds = 0", fabs(s - 1.0) + fabs(ds - 2.5) + fabs(dds), 1e-15);
  /* pieces on [0, 1), [1, 2), [2, 3): s = t^2 (C1 at 1 with 2t - 1 + (t-1)^2... ) */
  const double P[] = {0.0, 1.0, 2.0, 3.0,
                      /* t^3 on [0, 1) */ 1, 0, 0, 0,
                      /* 1 + 3u + 3u^2 + u^3 = t^3 on [1, 2): C-infinity at 1 */ 1, 3, 3, 1,
                      /* 8 + 12u + 0 u^2: C1 at 2 (s'' jumps from 12 to 0) */ 0, 0, 12, 8};
  phm_law pp = law_of(PHM_LAW_PPOLY, 0, 0, 0);
  pp.table = P;
  pp.ntable = 3;
  pp.order = 4;
  for (int i = 0; i < 40; i++) {
    double t = -0.5 + 4 * rand01(), ref, r1, r2;
    if (t < 2) { ref = t * t * t; r1 = 3 * t * t; r2 = 6 * t; }
    else { ref = 8 + 12 * (t - 2); r1 = 12; r2 = 0; }
    s = phm_law_eval(&pp, t, t + 0.3, &ds, &dds); /* tref beyond t: the piece is t's */
    check("ppoly: s, ds, dds of the piece of t (first and last continued)",
          fabs(s - ref) + fabs(ds - r1) + fabs(dds - r2), 1e-12 * (1 + fabs(ref) + fabs(r1) + fabs(r2)));
  }
  check_derivatives("ppoly", &pp, 0.6, 1e-5, 3.0, 6.0, 1e-8);
  check("ppoly: at a break, tref before it selects the piece that ends there",
        fabs(phm_law_eval(&pp, 2.0, 1.9, NULL, &dds) - 8.0) + fabs(dds - 12.0), 1e-12);
  double bp[4];
  int nb = phm_law_breakpoints(&pp, bp);
  CHECK(nb == 1 && bp[0] == 2.0, "ppoly: one breakpoint, at the C1 break 2 (got %d)", nb);
  /* expression: (sine * linear) + 3 * cycloidal, postfix: sine linear * 3 cyc * + */
  phm_law nodes[7] = {law_of(PHM_LAW_SINE, 0.7, 0, 0), lin, law_of(PHM_LAW_PRODUCT, 0, 0, 0),
                      law_of(PHM_LAW_CONSTANT, 3.0, 0, 0), law_of(PHM_LAW_CYCLOIDAL, 1.5, 0.2, 1.0),
                      law_of(PHM_LAW_PRODUCT, 0, 0, 0), law_of(PHM_LAW_SUM, 0, 0, 0)};
  nodes[0].frequency = 1.3;
  nodes[0].phase = 0.2;
  phm_law ex = law_of(PHM_LAW_EXPR, 0, 0, 0);
  ex.nodes = nodes;
  ex.nnodes = 7;
  phm_error err;
  CHECK(phm_law_check(&ex, "load", 0, &err) == PHM_OK, "expression accepted");
  for (int i = 0; i < 20; i++) {
    double t = 0.25 + 0.9 * rand01(), a[3], b[3], c[3];
    a[0] = phm_law_eval(&nodes[0], t, t, &a[1], &a[2]);
    b[0] = phm_law_eval(&lin, t, t, &b[1], &b[2]);
    c[0] = phm_law_eval(&nodes[4], t, t, &c[1], &c[2]);
    s = phm_law_eval(&ex, t, t, &ds, &dds);
    check("expression: s = a b + 3 c", fabs(s - (a[0] * b[0] + 3 * c[0])), 1e-14);
    check("expression: ds by the product rule", fabs(ds - (a[1] * b[0] + a[0] * b[1] + 3 * c[1])), 1e-13);
    check("expression: dds by the Leibniz rule",
          fabs(dds - (a[2] * b[0] + 2 * a[1] * b[1] + a[0] * b[2] + 3 * c[2])), 1e-12);
    check_derivatives("expression", &ex, t, 1e-5, 10.0, 50.0, 1e-8);
  }
  nb = phm_law_breakpoints(&ex, bp);
  CHECK(nb == 2 && bp[0] == 0.2 && bp[1] == 1.2, "expression: its cycloid's breakpoints (got %d)", nb);
  ex.nnodes = 6; /* leaves two values */
  check_refused("expression leaving two values", phm_law_check(&ex, "load", 1, &err), PHM_EINVAL, &err,
                "load 1: expression law leaves 2 values, not one");
  ex.nodes = nodes + 2;
  ex.nnodes = 1;
  check_refused("operator without operands", phm_law_check(&ex, "load", 1, &err), PHM_EINVAL, &err,
                "operator at node 0 has fewer than two operands");
  phm_law deep[PHM_LAW_STACK + 1];
  for (int i = 0; i <= PHM_LAW_STACK; i++) deep[i] = law_of(PHM_LAW_CONSTANT, 1, 0, 0);
  ex.nodes = deep;
  ex.nnodes = PHM_LAW_STACK + 1;
  check_refused("expression deeper than the stack", phm_law_check(&ex, "load", 1, &err), PHM_EINVAL,
                &err, "needs a stack deeper than");
  /* callback: its values; a failure is NaN; its breakpoints */
  double a = 1.5, cbp[2] = {0.5, 2.0};
  phm_law cb = law_of(PHM_LAW_CALLBACK, 0, 0, 0);
  cb.fn = square_cb;
  cb.ctx = &a;
  cb.table = cbp;
  cb.ntable = 2;
  CHECK(phm_law_check(&cb, "pair", 0, &err) == PHM_OK, "callback law accepted");
  cb_calls = 0;
  s = phm_law_eval(&cb, 2.0, 2.0, &ds, &dds);
  check("callback: s, ds, dds of the function", fabs(s - 6.0) + fabs(ds - 6.0) + fabs(dds - 3.0), 0.0);
  CHECK(cb_calls == 1, "callback: one call per evaluation (%d)", cb_calls);
  s = phm_law_eval(&cb, 11.0, 11.0, &ds, NULL);
  CHECK(isnan(s) && isnan(ds), "callback: a failed call gives NaN");
  nb = phm_law_breakpoints(&cb, bp);
  CHECK(nb == 2 && bp[0] == 0.5 && bp[1] == 2.0, "callback: its listed breakpoints");
  cb.fn = NULL;
  check_refused("callback without a function", phm_law_check(&cb, "pair", 2, &err), PHM_EINVAL, &err,
                "pair 2: callback law without a function");
  /* a deep copy: the expression's nodes and the polynomial's data move to the arenas */
  size_t nn = 0, nd = 0;
  phm_law e2 = law_of(PHM_LAW_EXPR, 0, 0, 0), leaves[3] = {pp, lin, law_of(PHM_LAW_SUM, 0, 0, 0)};
  e2.nodes = leaves;
  e2.nnodes = 3;
  phm_law_extent(&e2, &nn, &nd);
  CHECK(nn == 3 && nd == 4 + 12, "extent: 3 nodes and 16 doubles (got %zu, %zu)", nn, nd);
  phm_law arena[3], *ap = arena, copy = e2;
  double data[16], *dp = data;
  phm_law_copy(&copy, &ap, &dp);
  CHECK(copy.nodes == arena && arena[0].table == data && ap == arena + 3 && dp == data + 16,
        "copy: nodes and tables in the arenas");
  check("copy evaluates as the original", fabs(phm_law_eval(&copy, 1.3, 1.3, NULL, NULL) -
                                                 phm_law_eval(&e2, 1.3, 1.3, NULL, NULL)), 0.0);
}

CHECK_MAIN(CHECK_CASE(constant_step_and_pulse_are_piecewise_constant),
           CHECK_CASE(sine_matches_its_closed_form_and_derivatives),
           CHECK_CASE(table_interpolates_linearly_within_the_piece_of_tref),
           CHECK_CASE(cycloidal_ramp_is_c2_with_closed_form_values),
           CHECK_CASE(breakpoints_are_where_pieces_start_or_end),
           CHECK_CASE(invalid_laws_are_refused_with_a_message),
           CHECK_CASE(linear_ppoly_expression_and_callback_laws))
