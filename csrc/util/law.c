/* law.c -- scalar time laws s(t): evaluation (leaves and postfix expressions), breakpoints,
 * validation, and the deep copy a model keeps (kinds: phm_law_kind in
 * csrc/include/phmech_types.h; the Python classes: python/phmech/laws.py). */
#include "law.h"

#include <math.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"

/* PPOLY: the piece of time tref (the first before the breaks, the last after them). */
static int ppoly_find(const phm_law *l, double tref) {
  const double *x = l->table;
  int lo = 0, hi = l->ntable - 1; /* the piece i with x_i <= tref < x_i+1, clamped */
  if (tref < x[1]) return 0;
  if (tref >= x[hi]) return hi;
  while (hi - lo > 1) { /* invariant: x[lo] <= tref < x[hi] */
    int mid = (lo + hi) / 2;
    if (tref >= x[mid]) lo = mid; else hi = mid;
  }
  return lo;
}

/* PPOLY: the piece of t; within round-off (1e-9 of the piece) of a break, the side of tref. A
 * break where the law is C2 is no breakpoint (the integrators step across it, tref may lie
 * beyond it), so the piece is chosen by t; at a reported breakpoint the integrators stop and
 * tref says on which side the current interval lies. */
static int ppoly_piece(const phm_law *l, double t, double tref) {
  const double *x = l->table;
  int i = ppoly_find(l, t), n = l->ntable;
  if (i + 1 < n && x[i + 1] - t <= 1e-9 * (x[i + 1] - x[i]) && tref >= x[i + 1]) return i + 1;
  if (i > 0 && t - x[i] <= 1e-9 * (x[i + 1] - x[i]) && tref < x[i]) return i - 1;
  return i;
}

/* PPOLY piece i at local time u = t - x_i: value and two derivatives (Horner). */
static void ppoly_piece_eval(const phm_law *l, int i, double u, double out[3]) {
  const double *c = l->table + (l->ntable + 1) + (size_t)i * (size_t)l->order;
  double s = 0, d1 = 0, d2 = 0;
  for (int j = 0; j < l->order; j++) {
    d2 = d2 * u + 2 * d1;
    d1 = d1 * u + s;
    s = s * u + c[j];
  }
  out[0] = s;
  out[1] = d1;
  out[2] = d2;
}

/* A leaf law (any kind but EXPR and its operators): s, s', s'' into out; nder: how many
 * derivatives the caller reads (a callback is asked for no more). */
static void leaf_eval(const phm_law *l, double t, double tref, int nder, double out[3]) {
  double s = 0, d1 = 0, d2 = 0;
  switch (l->kind) {
  case PHM_LAW_CONSTANT: s = l->amplitude; break;
  case PHM_LAW_STEP: s = tref >= l->t0 ? l->amplitude : 0.0; break;
  case PHM_LAW_PULSE: s = (tref >= l->t0 && tref < l->t0 + l->duration) ? l->amplitude : 0.0; break;
  case PHM_LAW_SINE: {
    double w = 2 * PHM_PI * l->frequency, a = w * t + l->phase;
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
      s = A * (u - sin(2 * PHM_PI * u) / (2 * PHM_PI));
      d1 = A / T * (1 - cos(2 * PHM_PI * u));
      d2 = A / (T * T) * 2 * PHM_PI * sin(2 * PHM_PI * u);
    }
  } break;
  case PHM_LAW_LINEAR:
    s = l->offset + l->amplitude * t;
    d1 = l->amplitude;
    break;
  case PHM_LAW_PPOLY: {
    int i = ppoly_piece(l, t, tref);
    ppoly_piece_eval(l, i, t - l->table[i], out);
    return;
  }
  case PHM_LAW_CALLBACK: {
    double v[3] = {0, 0, 0};
    if (!l->fn || l->fn(l->ctx, t, nder, v) != 0) v[0] = v[1] = v[2] = NAN;
    s = v[0];
    d1 = nder >= 1 ? v[1] : 0;
    d2 = nder >= 2 ? v[2] : 0;
  } break;
  default: break;
  }
  out[0] = s;
  out[1] = d1;
  out[2] = d2;
}

double phm_law_eval(const phm_law *l, double t, double tref, double *ds, double *dds) {
  int nder = dds ? 2 : ds ? 1 : 0;
  double v[3];
  if (l->kind != PHM_LAW_EXPR) {
    leaf_eval(l, t, tref, nder, v);
  } else {
    /* postfix: a leaf pushes (s, s', s''), an operator pops two and pushes their result;
     * phm_law_check guarantees the depth and that one entry is left */
    double st[PHM_LAW_STACK][3];
    int sp = 0;
    for (int i = 0; i < l->nnodes; i++) {
      const phm_law *nd = &l->nodes[i];
      if (nd->kind == PHM_LAW_SUM || nd->kind == PHM_LAW_PRODUCT) {
        double *a = st[sp - 2], *b = st[sp - 1];
        if (nd->kind == PHM_LAW_SUM) {
          for (int k = 0; k < 3; k++) a[k] += b[k];
        } else {
          double s = a[0] * b[0], d1 = a[1] * b[0] + a[0] * b[1],
                 d2 = a[2] * b[0] + 2 * a[1] * b[1] + a[0] * b[2];
          a[0] = s;
          a[1] = d1;
          a[2] = d2;
        }
        sp--;
      } else {
        leaf_eval(nd, t, tref, nder, st[sp++]);
      }
    }
    memcpy(v, st[0], sizeof v);
  }
  if (ds) *ds = v[1];
  if (dds) *dds = v[2];
  return v[0];
}

/* PPOLY: its interior breaks where s, s' or s'' jumps (beyond 1e-9 of the largest magnitude of
 * that derivative at the breaks): a C2 spline has none. */
static int ppoly_breakpoints(const phm_law *l, double *out) {
  const double *x = l->table;
  int n = 0;
  double scale[3] = {0, 0, 0};
  for (int pass = 0; pass < 2; pass++)
    for (int i = 1; i < l->ntable; i++) {
      double left[3], right[3];
      ppoly_piece_eval(l, i - 1, x[i] - x[i - 1], left);
      ppoly_piece_eval(l, i, 0.0, right);
      int jump = 0;
      for (int k = 0; k < 3; k++) {
        if (pass == 0) scale[k] = fmax(scale[k], fmax(fabs(left[k]), fabs(right[k])));
        else if (fabs(left[k] - right[k]) > 1e-9 * scale[k]) jump = 1;
      }
      if (jump) {
        if (out) out[n] = x[i];
        n++;
      }
    }
  return n;
}

int phm_law_breakpoints(const phm_law *l, double *out) { /* out may be NULL: count only */
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
  case PHM_LAW_PPOLY: n = ppoly_breakpoints(l, out); break;
  case PHM_LAW_CALLBACK:
    for (int i = 0; i < l->ntable; i++) {
      if (out) out[n] = l->table[i];
      n++;
    }
    break;
  case PHM_LAW_EXPR:
    for (int i = 0; i < l->nnodes; i++) n += phm_law_breakpoints(&l->nodes[i], out ? out + n : NULL);
    break;
  default: break;
  }
  return n;
}

static phm_status leaf_check(const phm_law *l, const char *what, int idx, phm_error *err) {
  double v[6] = {l->amplitude, l->t0, l->duration, l->frequency, l->phase, l->offset};
  for (int i = 0; i < 6; i++)
    if (!isfinite(v[i])) return PHM_FAIL(err, PHM_EINVAL, "%s %d: time law has a non-finite parameter", what, idx);
  switch (l->kind) {
  case PHM_LAW_CONSTANT: case PHM_LAW_STEP: case PHM_LAW_SINE: case PHM_LAW_LINEAR: return PHM_OK;
  case PHM_LAW_PULSE: case PHM_LAW_CYCLOIDAL:
    if (!(l->duration > 0))
      return PHM_FAIL(err, PHM_EINVAL, "%s %d: time law duration must be > 0 (got %g s)", what, idx, l->duration);
    return PHM_OK;
  case PHM_LAW_TABLE:
    if (l->ntable < 1 || !l->table)
      return PHM_FAIL(err, PHM_EINVAL, "%s %d: table law needs at least one (t, value) point", what, idx);
    for (int i = 0; i < l->ntable; i++) {
      if (!isfinite(l->table[2 * i]) || !isfinite(l->table[2 * i + 1]))
        return PHM_FAIL(err, PHM_EINVAL, "%s %d: table law has a non-finite entry", what, idx);
      if (i > 0 && !(l->table[2 * i] > l->table[2 * i - 2]))
        return PHM_FAIL(err, PHM_EINVAL, "%s %d: table law times must be strictly increasing", what, idx);
    }
    return PHM_OK;
  case PHM_LAW_PPOLY: {
    if (l->ntable < 1 || !l->table || l->order < 1 || l->order > PHM_LAW_MAXORDER)
      return PHM_FAIL(err, PHM_EINVAL, "%s %d: piecewise polynomial law needs at least one piece and 1..%d coefficients per piece (got %d pieces, %d)", what, idx, PHM_LAW_MAXORDER, l->ntable, l->order);
    size_t nd = (size_t)(l->ntable + 1) + (size_t)l->ntable * (size_t)l->order;
    for (size_t i = 0; i < nd; i++)
      if (!isfinite(l->table[i]))
        return PHM_FAIL(err, PHM_EINVAL, "%s %d: piecewise polynomial law has a non-finite break or coefficient", what, idx);
    for (int i = 1; i <= l->ntable; i++)
      if (!(l->table[i] > l->table[i - 1]))
        return PHM_FAIL(err, PHM_EINVAL, "%s %d: piecewise polynomial law breaks must be strictly increasing", what, idx);
    return PHM_OK;
  }
  case PHM_LAW_CALLBACK:
    if (!l->fn) return PHM_FAIL(err, PHM_EINVAL, "%s %d: callback law without a function", what, idx);
    if (l->ntable < 0 || (l->ntable > 0 && !l->table))
      return PHM_FAIL(err, PHM_EINVAL, "%s %d: callback law breakpoints missing", what, idx);
    for (int i = 0; i < l->ntable; i++) {
      if (!isfinite(l->table[i]))
        return PHM_FAIL(err, PHM_EINVAL, "%s %d: callback law has a non-finite breakpoint", what, idx);
      if (i > 0 && !(l->table[i] > l->table[i - 1]))
        return PHM_FAIL(err, PHM_EINVAL, "%s %d: callback law breakpoints must be strictly increasing", what, idx);
    }
    return PHM_OK;
  default:
    return PHM_FAIL(err, PHM_EINVAL, "%s %d: unknown time law kind %d", what, idx, l->kind);
  }
}

phm_status phm_law_check(const phm_law *l, const char *what, int idx, phm_error *err) {
  if (l->kind != PHM_LAW_EXPR) {
    if (l->kind == PHM_LAW_SUM || l->kind == PHM_LAW_PRODUCT)
      return PHM_FAIL(err, PHM_EINVAL, "%s %d: a sum or product operator outside an expression law", what, idx);
    return leaf_check(l, what, idx, err);
  }
  if (l->nnodes < 1 || !l->nodes)
    return PHM_FAIL(err, PHM_EINVAL, "%s %d: expression law without nodes", what, idx);
  int sp = 0;
  for (int i = 0; i < l->nnodes; i++) {
    const phm_law *nd = &l->nodes[i];
    phm_status st;
    if (nd->kind == PHM_LAW_SUM || nd->kind == PHM_LAW_PRODUCT) {
      if (sp < 2) return PHM_FAIL(err, PHM_EINVAL, "%s %d: expression law: operator at node %d has fewer than two operands", what, idx, i);
      sp--;
    } else if (nd->kind == PHM_LAW_EXPR) {
      return PHM_FAIL(err, PHM_EINVAL, "%s %d: expression law: node %d is itself an expression (flatten it)", what, idx, i);
    } else {
      if ((st = leaf_check(nd, what, idx, err))) return st;
      if (++sp > PHM_LAW_STACK)
        return PHM_FAIL(err, PHM_EINVAL, "%s %d: expression law needs a stack deeper than %d", what, idx, PHM_LAW_STACK);
    }
  }
  if (sp != 1) return PHM_FAIL(err, PHM_EINVAL, "%s %d: expression law leaves %d values, not one", what, idx, sp);
  return PHM_OK;
}

static size_t leaf_doubles(const phm_law *l) {
  switch (l->kind) {
  case PHM_LAW_TABLE: return 2 * (size_t)l->ntable;
  case PHM_LAW_PPOLY: return (size_t)(l->ntable + 1) + (size_t)l->ntable * (size_t)l->order;
  case PHM_LAW_CALLBACK: return (size_t)l->ntable;
  default: return 0;
  }
}

void phm_law_extent(const phm_law *l, size_t *nnodes, size_t *ndoubles) {
  if (l->kind == PHM_LAW_EXPR) {
    *nnodes += (size_t)l->nnodes;
    for (int i = 0; i < l->nnodes; i++) *ndoubles += leaf_doubles(&l->nodes[i]);
  } else {
    *ndoubles += leaf_doubles(l);
  }
}

static void leaf_copy(phm_law *l, double **doubles) {
  size_t n = leaf_doubles(l);
  if (n) {
    memcpy(*doubles, l->table, n * sizeof(double));
    l->table = *doubles;
    *doubles += n;
  }
}

void phm_law_copy(phm_law *l, phm_law **nodes, double **doubles) {
  if (l->kind == PHM_LAW_EXPR) {
    memcpy(*nodes, l->nodes, (size_t)l->nnodes * sizeof(phm_law));
    l->nodes = *nodes;
    *nodes += l->nnodes;
    for (int i = 0; i < l->nnodes; i++) leaf_copy((phm_law *)&l->nodes[i], doubles);
  } else {
    leaf_copy(l, doubles);
  }
}
