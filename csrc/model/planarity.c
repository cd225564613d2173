/* planarity.c -- is a scene planar (issue 13)? The checks of python/phmech/planar.py (its module
 * docstring says what each means), in its order and words: gravity; every carrier's start
 * rotation about the normal k; per carrier its start twist, inertia and weight; per element its
 * K, D, Ms, consistent mass and unstressed curvature; per inertial coupling; per load its wrench
 * and point; per spring its points; per actuated or driven pair its one free direction; per pair
 * its constraint rows (each in-plane or out-of-plane, the latter dropped: phm_planar_rows).
 * Every check is one of exact zeros, taken as zero up to PHM_PLANAR_ZERO times the scale of its
 * array: per item (a twist, a vector), per matrix, per constraint row. The simulation then
 * solves the planar DAE (csrc/dae/planar.c). Nothing here allocates but phm_planar_check for a
 * model with many constraint rows (the rows' blocks, beyond a stack buffer). */
#include "model.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"

#define ZERO PHM_PLANAR_ZERO

static const char AXES[] = "xyz";

/* The largest |x_i| (NaN if any is: a NaN fails every check). */
static double max_abs(const double *x, int n) {
  double s = 0;
  for (int i = 0; i < n; i++) {
    double a = fabs(x[i]);
    if (a > s || a != a) s = a;
    if (s != s) return s;
  }
  return s;
}

/* Component i of a twist, wrench or strain (omega/kappa first) is in-plane for normal k. */
static int inside(int i, int k) { return i < 3 ? i == k : i - 3 != k; }

/* The out-of-plane components for normal k, in planar.py's order (outplane). */
static void outplane(int k, int O[3]) {
  int n = 0;
  for (int i = 0; i < 3; i++)
    if (i != k) O[n++] = i;
  O[n] = 3 + k;
}

/* Every out-of-plane component of x (6) is zero up to ZERO times max |x|. */
static int zero_out(const double x[6], int k) {
  double s = ZERO * max_abs(x, 6);
  int O[3];
  outplane(k, O);
  for (int i = 0; i < 3; i++)
    if (!(fabs(x[O[i]]) <= s)) return 0;
  return 1;
}

/* No entry of the n x n matrix A (n = 6 or 12, blocks of 6) couples in-plane with out-of-plane
 * components, up to ZERO times its largest entry. */
static int decoupled(const double *A, int n, int k) {
  double s = ZERO * max_abs(A, n * n);
  for (int r = 0; r < n; r++)
    for (int c = 0; c < n; c++)
      if (inside(r % 6, k) != inside(c % 6, k) && !(fabs(A[n * r + c]) <= s)) return 0;
  return 1;
}

/* ---------------------------------------------------------------- messages */
/* A double as Python's repr writes it: the shortest digits that read back, fixed notation for
 * exponents -4 .. 15, else d.ddde+XX. */
static void repr_double(double x, char *out, size_t n) {
  if (x != x) {
    snprintf(out, n, "nan");
    return;
  }
  if (isinf(x)) {
    snprintf(out, n, x < 0 ? "-inf" : "inf");
    return;
  }
  char e[48], dig[24];
  int p;
  for (p = 0; p < 17; p++) {
    snprintf(e, sizeof e, "%.*e", p, x);
    if (strtod(e, NULL) == x) break;
  }
  const char *s = e + (e[0] == '-');
  int nd = 0;
  for (const char *c = s; *c && *c != 'e'; c++)
    if (*c != '.') dig[nd++] = *c;
  dig[nd] = '\0';
  int ex = atoi(strchr(e, 'e') + 1);
  const char *sign = e[0] == '-' ? "-" : "";
  if (ex < -4 || ex >= 16) {
    snprintf(out, n, "%s%c%s%.*se%c%02d", sign, dig[0], nd > 1 ? "." : "", nd - 1, dig + 1,
             ex < 0 ? '-' : '+', abs(ex));
  } else if (ex < 0) {
    snprintf(out, n, "%s0.%.*s%s", sign, -ex - 1, "0000", dig);
  } else if (nd <= ex + 1) {
    snprintf(out, n, "%s%s%.*s.0", sign, dig, ex + 1 - nd, "0000000000000000");
  } else {
    snprintf(out, n, "%s%.*s.%s", sign, ex + 1, dig, dig + ex + 1);
  }
}

/* A vector as NumPy prints a float array: at most 8 decimals, the trailing zeros dropped (a whole
 * number ends in '.'), the entries aligned on their points; scientific when an entry is >= 1e8,
 * a nonzero one < 1e-4, or their ratio > 1e3. */
static void numpy_str(const double *x, int n, char *out, size_t nout) {
  char txt[6][40];
  double big = 0, small = INFINITY;
  for (int i = 0; i < n; i++) {
    double a = fabs(x[i]);
    if (!isfinite(a) || a == 0) continue;
    if (a > big) big = a;
    if (a < small) small = a;
  }
  int sci = big >= 1e8 || (big > 0 && (small < 1e-4 || big / small > 1e3));
  int wi = 0, wf = 0, ip[6];
  for (int i = 0; i < n; i++) {
    char *t = txt[i];
    if (!isfinite(x[i])) snprintf(t, 40, "%s", x[i] != x[i] ? "nan" : x[i] < 0 ? "-inf" : "inf");
    else if (sci) {
      int p;
      for (p = 0; p <= 8; p++) {
        snprintf(t, 40, "%.*e", p, x[i]);
        if (strtod(t, NULL) == x[i]) break;
      }
      char *e = strchr(t, 'e'), ex[8];
      snprintf(ex, sizeof ex, "%s", e);
      if (!strchr(t, '.')) { /* 1e-05 -> 1.e-05 */
        *e = '\0';
        strcat(t, ".");
        strcat(t, ex);
      }
    } else {
      char r[48];
      repr_double(x[i], r, sizeof r);
      char *dot = strchr(r, '.');
      if (dot && strlen(dot + 1) > 8) snprintf(r, sizeof r, "%.8f", x[i]);
      size_t L = strlen(r);
      while (L > 0 && r[L - 1] == '0' && strchr(r, '.')) r[--L] = '\0';
      snprintf(t, 40, "%s", r);
    }
    const char *d = strchr(t, '.');
    const char *e = strchr(t, 'e');
    ip[i] = d ? (int)(d - t) : (int)strlen(t);
    int f = d ? (int)((e ? e : t + strlen(t)) - d - 1) : 0;
    if (ip[i] > wi) wi = ip[i];
    if (f > wf) wf = f;
  }
  size_t o = 0;
  o += (size_t)snprintf(out + o, nout - o, "[");
  for (int i = 0; i < n && o < nout; i++) {
    const char *t = txt[i], *d = strchr(t, '.'), *e = strchr(t, 'e');
    int f = d ? (int)((e ? e : t + strlen(t)) - d - 1) : 0;
    int mant = e ? (int)(e - t) : (int)strlen(t);
    /* the fraction padded to a common width: with spaces, in scientific notation with zeros */
    o += (size_t)snprintf(out + o, nout - o, "%s%*s%.*s%.*s%*s%s", i ? " " : "", wi - ip[i], "",
                          mant, t, e && d ? wf - f : 0, "00000000", e || !d ? 0 : wf - f, "",
                          e ? e : "");
  }
  if (o < nout) snprintf(out + o, nout - o, "]");
}

static void say(char *why, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void say(char *why, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(why, PHM_PLANAR_WHY, fmt, ap);
  va_end(ap);
}

/* A pair's name as Python's repr quotes it ('name', or "name" when it holds a ' alone). */
static void pair_name(const phm_planar_scene *s, int ip, char *out, size_t n) {
  const char *nm = s->names ? s->names[ip] : NULL;
  if (!nm) snprintf(out, n, "%d", ip);
  else if (strchr(nm, '\'') && !strchr(nm, '"')) snprintf(out, n, "\"%s\"", nm);
  else snprintf(out, n, "'%s'", nm);
}

/* ---------------------------------------------------------------- the constraint rows */
/* Row r: (no in-plane component, no out-of-plane component), each zero up to ZERO times the
 * row's largest entry. */
static void row_parts(const phm_planar_scene *s, int r, int k, int *no_in, int *no_out) {
  const double *g = s->G + (size_t)r * (size_t)s->nblk * 6;
  const int *car = s->Gcar + (size_t)r * (size_t)s->nblk;
  double m = 0;
  for (int b = 0; b < s->nblk; b++)
    if (car[b] >= 0) {
      double a = max_abs(g + 6 * b, 6);
      if (a > m || a != a) m = a;
    }
  double tol = ZERO * m;
  *no_in = *no_out = 1;
  for (int b = 0; b < s->nblk; b++) {
    if (car[b] < 0) continue;
    for (int i = 0; i < 6; i++)
      if (!(fabs(g[6 * b + i]) <= tol)) *(inside(i, k) ? no_in : no_out) = 0;
  }
}

/* The direction the 5 rows A (5 x 6, row-major) leave free: the last column of Q in the QR
 * factorization A^T = Q R (Householder), a unit vector orthogonal to every row (planar.py takes
 * the last right singular vector, the same line when the rows are independent). */
static void free_direction(const double A[30], double z[6]) {
  double B[30], V[5][6];           /* B = A^T (6 x 5), V: the reflectors */
  int used[5];
  for (int i = 0; i < 6; i++)
    for (int j = 0; j < 5; j++) B[5 * i + j] = A[6 * j + i];
  for (int j = 0; j < 5; j++) {
    double nrm = 0;
    for (int i = j; i < 6; i++) nrm += B[5 * i + j] * B[5 * i + j];
    nrm = sqrt(nrm);
    used[j] = 0;
    if (nrm == 0) continue;
    double alpha = B[5 * j + j] > 0 ? -nrm : nrm, vv = 0;
    for (int i = 0; i < 6; i++) V[j][i] = i < j ? 0.0 : B[5 * i + j];
    V[j][j] -= alpha;
    for (int i = j; i < 6; i++) vv += V[j][i] * V[j][i];
    if (vv == 0) continue;
    for (int i = j; i < 6; i++) V[j][i] /= sqrt(vv);
    used[j] = 1;
    for (int c = j; c < 5; c++) { /* B -= 2 v (v^T B) */
      double d = 0;
      for (int i = j; i < 6; i++) d += V[j][i] * B[5 * i + c];
      for (int i = j; i < 6; i++) B[5 * i + c] -= 2 * d * V[j][i];
    }
  }
  for (int i = 0; i < 6; i++) z[i] = i == 5;
  for (int j = 4; j >= 0; j--) { /* z = H_0 ... H_4 e_5 */
    if (!used[j]) continue;
    double d = 0;
    for (int i = j; i < 6; i++) d += V[j][i] * z[i];
    for (int i = j; i < 6; i++) z[i] -= 2 * d * V[j][i];
  }
}

/* ---------------------------------------------------------------- the scene's checks */
static int in_range(int c, int n) { return c >= -1 && c < n; }

/* The scene's counts and indices in range: its rows and layout, and with `all` the rest. */
static phm_status scene_valid(const phm_planar_scene *s, int all, phm_error *err) {
  if (!s) return PHM_FAIL(err, PHM_EINVAL, "planar check: NULL scene");
  PHM_CHECK(s->nc >= 0 && s->ne >= 0 && s->ncoup >= 0 && s->nl >= 0 && s->ns >= 0 && s->na >= 0 &&
                s->np >= 0 && s->nrow >= 0 && s->nblk >= 0,
            err, PHM_EINVAL, "planar check: a negative count");
  PHM_CHECK((!s->np || (s->pair_row && s->pair_m && s->pair_k)) && (!s->nrow || !s->nblk || (s->G && s->Gcar)),
            err, PHM_EINVAL, "planar check: NULL array");
  for (int ip = 0; ip < s->np; ip++)
    PHM_CHECK(s->pair_row[ip] >= 0 && s->pair_m[ip] >= 0 && s->pair_m[ip] <= s->nrow - s->pair_row[ip],
              err, PHM_EINVAL, "planar check: pair %d: rows out of range", ip);
  for (long i = 0; i < (long)s->nrow * s->nblk; i++)
    PHM_CHECK(in_range(s->Gcar[i], s->nc), err, PHM_EINVAL,
              "planar check: constraint row %ld: carrier out of range", i / s->nblk);
  if (!all) return PHM_OK;
  PHM_CHECK((!s->nc || (s->H && s->t && s->car)) && (!s->ne || s->el) &&
                (!s->ncoup || s->coupling_Mc) && (!s->nl || s->load) && (!s->ns || s->spr) &&
                (!s->na || s->act) && (!s->np || s->pair),
            err, PHM_EINVAL, "planar check: NULL array");
  for (int i = 0; i < s->ns; i++)
    PHM_CHECK(in_range(s->spr[i].a, s->nc) && in_range(s->spr[i].b, s->nc), err, PHM_EINVAL,
              "planar check: spring %d: carrier out of range", i);
  for (int i = 0; i < s->na; i++)
    PHM_CHECK(s->act[i].pair >= 0 && s->act[i].pair < s->np, err, PHM_EINVAL,
              "planar check: actuator %d: pair out of range", i);
  for (int ip = 0; ip < s->np; ip++) {
    const phm_pair_desc *p = &s->pair[ip];
    PHM_CHECK(in_range(p->a, s->nc) && in_range(p->b, s->nc) && (p->a >= 0 || p->b >= 0), err,
              PHM_EINVAL, "planar check: pair %d: carriers out of range", ip);
  }
  return PHM_OK;
}

phm_status phm_planar_rows(const phm_planar_scene *s, int k, int *drop, phm_error *err) {
  PHM_CALL(scene_valid(s, 0, err));
  PHM_CHECK(k >= 0 && k <= 2 && drop, err, PHM_EINVAL, "planar check: axis %d or drop NULL", k);
  for (int ip = 0; ip < s->np; ip++) {
    drop[ip] = 0;
    for (int r = 0; r < s->pair_m[ip] && r < 31; r++) {
      int no_in, no_out;
      row_parts(s, s->pair_row[ip] + r, k, &no_in, &no_out);
      if (no_in) drop[ip] |= 1 << r;
    }
  }
  return PHM_OK;
}

/* The checks of the carriers, elements, couplings, loads and springs: 1 and the message in why
 * for the first that fails, else 0. */
static int first_failing(const phm_planar_scene *s, int k, char *why) {
  char ax = AXES[k], v[160];
  int O[3];
  outplane(k, O);
  const double *g = s->gravity;
  if (!(fabs(g[k]) <= ZERO * max_abs(g, 3))) {
    char a[3][40];
    for (int i = 0; i < 3; i++) repr_double(g[i], a[i], sizeof a[i]);
    say(why, "gravity (%s, %s, %s) has a component along %c", a[0], a[1], a[2], ax);
    return 1;
  }
  int i1 = k == 0 ? 1 : 0, i2 = k == 2 ? 1 : 2; /* the two other axes */
  for (int c = 0; c < s->nc; c++) { /* first and alone: it rejects the other axes of most scenes */
    const double *H = s->H + 16 * c;
    if (!(fabs(H[5 * k] - 1.0) <= ZERO && fabs(H[4 * k + i1]) <= ZERO && fabs(H[4 * k + i2]) <= ZERO &&
          fabs(H[4 * i1 + k]) <= ZERO && fabs(H[4 * i2 + k]) <= ZERO)) {
      say(why, "carrier %d's initial rotation is not about %c", c, ax);
      return 1;
    }
  }
  double tscale = ZERO * max_abs(s->t, 6 * s->nc);
  int gravity = g[0] != 0 || g[1] != 0 || g[2] != 0;
  for (int c = 0; c < s->nc; c++) {
    const double *t = s->t + 6 * c;
    const phm_carrier_desc *cd = &s->car[c];
    if (!(fabs(t[O[0]]) <= tscale && fabs(t[O[1]]) <= tscale && fabs(t[O[2]]) <= tscale)) {
      double to[3] = {t[O[0]], t[O[1]], t[O[2]]};
      numpy_str(to, 3, v, sizeof v);
      say(why, "carrier %d's initial twist has out-of-plane components %s", c, v);
      return 1;
    }
    if (!decoupled(cd->M, 6, k)) {
      say(why, "carrier %d's inertia couples in-plane and out-of-plane motion", c);
      return 1;
    }
    if (!(cd->mass <= 0 || !gravity || fabs(cd->com[k]) <= ZERO * max_abs(cd->com, 3))) {
      say(why, "carrier %d's centre of mass is off the plane (its weight would tilt it)", c);
      return 1;
    }
  }
  for (int e = 0; e < s->ne; e++) {
    const phm_element_desc *el = &s->el[e];
    const double *mats[3] = {el->K, el->D, el->Ms};
    const char *keys[3] = {"K", "D", "Ms"};
    for (int i = 0; i < 3; i++)
      if (!decoupled(mats[i], 6, k)) {
        say(why, "element %d's %s couples in-plane and out-of-plane strains", e, keys[i]);
        return 1;
      }
    if (!decoupled(el->Mc, 12, k)) {
      say(why, "element %d's consistent mass couples in-plane and out-of-plane motion", e);
      return 1;
    }
    if (!zero_out(el->eps_hat, k)) {
      say(why, "element %d's unstressed curvature is not about %c", e, ax);
      return 1;
    }
  }
  for (int c = 0; c < s->ncoup; c++)
    if (!decoupled(s->coupling_Mc + 144 * (size_t)c, 12, k)) {
      say(why, "inertial coupling %d couples in-plane and out-of-plane motion", c);
      return 1;
    }
  for (int i = 0; i < s->nl; i++) {
    const double *w = s->load[i].w, *p = s->load[i].point;
    if (!zero_out(w, k)) {
      double wo[3] = {w[O[0]], w[O[1]], w[O[2]]};
      numpy_str(wo, 3, v, sizeof v);
      say(why, "load %d has out-of-plane components %s", i, v);
      return 1;
    }
    int force = w[3] != 0 || w[4] != 0 || w[5] != 0;
    if (force && !(fabs(p[k]) <= ZERO * max_abs(p, 3))) {
      say(why, "load %d acts at a point off the plane", i);
      return 1;
    }
  }
  for (int i = 0; i < s->ns; i++) {
    const phm_spring_desc *sp = &s->spr[i];
    double wab[6];
    for (int e = 0; e < 2; e++) {
      int c = e ? sp->b : sp->a;
      const double *p = e ? sp->pb : sp->pa, *H = c >= 0 ? s->H + 16 * c : NULL;
      for (int r = 0; r < 3; r++)
        wab[3 * e + r] = H ? H[4 * r] * p[0] + H[4 * r + 1] * p[1] + H[4 * r + 2] * p[2] + H[4 * r + 3] : p[r];
    }
    if ((sp->a >= 0 && !(fabs(sp->pa[k]) <= ZERO * max_abs(sp->pa, 3))) ||
        (sp->b >= 0 && !(fabs(sp->pb[k]) <= ZERO * max_abs(sp->pb, 3))) ||
        !(fabs(wab[k] - wab[3 + k]) <= ZERO * max_abs(wab, 6))) {
      say(why, "spring %d has its points off the plane", i);
      return 1;
    }
  }
  return 0;
}

/* The pairs' checks: an actuated or driven pair moves along one in-plane direction; no row mixes
 * in-plane with out-of-plane motion. 1 and the message for the first that fails, else 0. */
static int pair_failing(const phm_planar_scene *s, int k, char *why) {
  char nm[PHM_PLANAR_WHY / 2];
  for (int ip = 0; ip < s->np; ip++) {
    const phm_pair_desc *p = &s->pair[ip];
    int moved = p->driven || p->xdriven;
    for (int i = 0; i < s->na && !moved; i++) moved = s->act[i].pair == ip;
    if (!moved) continue;
    pair_name(s, ip, nm, sizeof nm);
    if (s->pair_k[ip] != 1) {
      say(why, "pair %s is actuated or driven along more than one coordinate", nm);
      return 1;
    }
    /* the direction its effort or law moves: free of its type's 5 rows on one of its carriers
     * (a carrier's body axes: rotated about k, so in and out of the plane as the world's); a
     * driven coordinate's row, dropped as out-of-plane, would silently leave the law undone */
    int c = p->b >= 0 ? p->b : p->a;
    double A[30] = {0}, z[6];
    for (int r = 0; r < 5 && r < s->pair_m[ip]; r++) {
      int row = s->pair_row[ip] + r;
      for (int b = 0; b < s->nblk; b++)
        if (s->Gcar[(size_t)row * (size_t)s->nblk + (size_t)b] == c)
          for (int j = 0; j < 6; j++) A[6 * r + j] += s->G[((size_t)row * (size_t)s->nblk + (size_t)b) * 6 + (size_t)j];
    }
    free_direction(A, z);
    if (!zero_out(z, k)) {
      say(why, "pair %s is actuated or driven along an out-of-plane axis", nm);
      return 1;
    }
  }
  for (int ip = 0; ip < s->np; ip++)
    for (int r = 0; r < s->pair_m[ip]; r++) {
      int no_in, no_out;
      row_parts(s, s->pair_row[ip] + r, k, &no_in, &no_out);
      if (!no_in && !no_out) {
        pair_name(s, ip, nm, sizeof nm);
        say(why, "pair %s's constraint row %d mixes in-plane and out-of-plane motion", nm, r);
        return 1;
      }
    }
  return 0;
}

phm_status phm_planar_check_scene(const phm_planar_scene *s, int k, int *drop,
                                  char why[PHM_PLANAR_WHY], phm_error *err) {
  PHM_CALL(scene_valid(s, 1, err));
  PHM_CHECK(k >= 0 && k <= 2 && why, err, PHM_EINVAL, "planar check: axis %d or why NULL", k);
  why[0] = '\0';
  if (first_failing(s, k, why) || pair_failing(s, k, why)) return PHM_OK;
  return drop ? phm_planar_rows(s, k, drop, err) : PHM_OK;
}

/* ---------------------------------------------------------------- a model's scene */
#define STACK_ROWS 48 /* rows whose blocks a model's check keeps on the stack */

phm_status phm_planar_check(const phm_model *m, const double *H, const double *t,
                            const char *const *names, int *axis, int *drop,
                            char why[3][PHM_PLANAR_WHY], phm_error *err) {
  PHM_CHECK(m && H && t && axis && why && (drop || !m->np), err, PHM_EINVAL, "planar check: NULL argument");
  *axis = -1;
  int nrow = m->ncons_full, np = m->np;
  double Gs[STACK_ROWS * 12];
  int ints_s[STACK_ROWS * 2 + STACK_ROWS];
  double *G = Gs;
  int *ints = ints_s;
  if (nrow > STACK_ROWS || np > STACK_ROWS) {
    G = malloc(sizeof(double) * 12 * (size_t)(nrow + 1));
    ints = malloc(sizeof(int) * (size_t)(2 * nrow + np + 1));
    if (!G || !ints) {
      free(G);
      free(ints);
      return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
    }
  }
  int *Gcar = ints, *pair_m = ints + 2 * nrow;
  double tref = phm_model_tref(m, 0.0, NULL);
  for (int ip = 0; ip < np; ip++) {
    const phm_pair_desc *pr = &m->pair[ip];
    int r0 = m->pair_rowf[ip], mf = phm_pair_rows_full(pr);
    double Ga[36], Gb[36];
    phm_pair_eval_full(m, ip, pr->a >= 0 ? H + 16 * pr->a : NULL, pr->b >= 0 ? H + 16 * pr->b : NULL,
                       NULL, 0.0, tref, NULL, Ga, Gb, NULL);
    pair_m[ip] = mf;
    for (int r = 0; r < mf; r++) {
      double *g = G + 12 * (r0 + r);
      int *car = Gcar + 2 * (r0 + r);
      memcpy(g, Ga + 6 * r, 6 * sizeof(double));
      memcpy(g + 6, Gb + 6 * r, 6 * sizeof(double));
      car[0] = pr->a; /* a != b (phm_model_create) */
      car[1] = pr->b;
    }
  }
  int nmass = 0;
  for (int e = 0; e < m->ne; e++) nmass += m->el[e].mass != PHM_MASS_LUMPED;
  phm_planar_scene s = {.gravity = {m->gravity[0], m->gravity[1], m->gravity[2]}, .nc = m->nc,
                        .H = H, .t = t, .car = m->car, .ne = m->ne, .el = m->el,
                        .ncoup = m->nmc - nmass, .coupling_Mc = m->mc + 144 * (size_t)nmass,
                        .nl = m->nl, .load = m->load, .ns = m->ns, .spr = m->spr, .na = m->na,
                        .act = m->act, .np = np, .pair = m->pair, .pair_row = m->pair_rowf,
                        .pair_m = pair_m, .pair_k = m->pair_k, .names = names, .nrow = nrow,
                        .nblk = 2, .G = G, .Gcar = Gcar};
  phm_status st = PHM_OK;
  for (int k = 2; k >= 0; k--) {
    if ((st = phm_planar_check_scene(&s, k, drop, why[k], err)) != PHM_OK) break;
    if (!why[k][0]) {
      *axis = k;
      break;
    }
  }
  if (G != Gs) {
    free(G);
    free(ints);
  }
  return st;
}
