/* law.c -- scalar time laws s(t): evaluation, breakpoints and validation (kinds: phm_law_kind in
 * csrc/include/phmech_types.h). */
#include "law.h"

#include <math.h>

#include "phm_check.h"
#include "linalg.h"

double phm_law_eval(const phm_law *l, double t, double tref, double *ds, double *dds) {
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
  default: break;
  }
  if (ds) *ds = d1;
  if (dds) *dds = d2;
  return s;
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
  default: break;
  }
  return n;
}

phm_status phm_law_check(const phm_law *l, const char *what, int idx, phm_error *err) {
  double v[6] = {l->amplitude, l->t0, l->duration, l->frequency, l->phase, l->offset};
  for (int i = 0; i < 6; i++)
    if (!isfinite(v[i])) return PHM_FAIL(err, PHM_EINVAL, "%s %d: time law has a non-finite parameter", what, idx);
  switch (l->kind) {
  case PHM_LAW_CONSTANT: case PHM_LAW_STEP: case PHM_LAW_SINE: return PHM_OK;
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
  default:
    return PHM_FAIL(err, PHM_EINVAL, "%s %d: unknown time law kind %d", what, idx, l->kind);
  }
}
