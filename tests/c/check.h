/* check.h -- the one header the C tests share (tests/c/test_*.c, one test file per file of
 * csrc/): checks that count and print only failures, a runner for a file's test cases, a
 * deterministic random generator, random twists and poses, and the small dense helpers the
 * references are built from. Everything is static inline: each test file is one translation unit.
 * (Not to be confused with csrc/util/check.h, the library's error macros: this header includes
 * only the public phmech.h and uses other names and another include guard.)
 *
 * A test file:
 *     static void element_wrenches_are_minus_energy_gradient(void) { ... check(...); ... }
 *     CHECK_MAIN(CHECK_CASE(element_wrenches_are_minus_energy_gradient), ...)
 * Its executable runs every case (or those named on the command line), prints each failed check
 * and one summary line, and exits non-zero if any check failed or none ran. `-v` also lists every
 * check that passed and the worst error of each check_worst name. The random generator is
 * reseeded from the case's name before each case (a case draws the same numbers alone or with
 * the others); the environment variable CHECK_SEED (a number) changes the seed of a run. */
#ifndef PHM_TESTS_CHECK_H
#define PHM_TESTS_CHECK_H

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "phmech.h"

#define CHECK_PI 3.14159265358979323846

/* ---------------------------------------------------------------- checks */
static int check_npass, check_nfail, check_verbose;
static const char *check_case_name = "";

/* Pass when err <= tol (a NaN error fails); returns 1 on pass. */
static inline int check(const char *name, double err, double tol) {
  if (err <= tol) {
    check_npass++;
    if (check_verbose) printf("  pass %s: %s\n", check_case_name, name);
    return 1;
  }
  check_nfail++;
  printf("FAIL %s: %s: error %.3e > tol %.1e\n", check_case_name, name, err, tol);
  return 0;
}

/* A condition with a printf-style description; CHECK(cond, ...) adds the file and line. */
static inline int check_that_at(int ok, const char *file, int line, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static inline int check_that_at(int ok, const char *file, int line, const char *fmt, ...) {
  if (ok) check_npass++;
  else check_nfail++;
  if (ok && !check_verbose) return 1;
  const char *base = strrchr(file, '/');
  va_list ap;
  va_start(ap, fmt);
  printf("%s %s (%s:%d): ", ok ? "  pass" : "FAIL", check_case_name, base ? base + 1 : file, line);
  vprintf(fmt, ap);
  printf("\n");
  va_end(ap);
  return ok;
}
#define CHECK(cond, ...) check_that_at(!!(cond), __FILE__, __LINE__, __VA_ARGS__)

/* A failure that has no passing counterpart (a set-up step that should not fail). */
static inline void check_fail(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static inline void check_fail(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  check_nfail++;
  printf("FAIL %s: ", check_case_name);
  vprintf(fmt, ap);
  printf("\n");
  va_end(ap);
}

/* A call refused as it should be: status `want` and a message containing `part`. */
static inline int check_refused(const char *name, phm_status got, phm_status want,
                                const phm_error *err, const char *part) {
  int ok = got == want && err && strstr(err->msg, part) != NULL;
  if (ok) {
    check_npass++;
    if (check_verbose) printf("  pass %s: %s\n", check_case_name, name);
    return 1;
  }
  check_nfail++;
  printf("FAIL %s: %s: status %d (want %d), message \"%s\" (want it to contain \"%s\")\n",
         check_case_name, name, (int)got, (int)want, err ? err->msg : "", part);
  return 0;
}

/* check() that also keeps the worst error of each name (listed with -v). */
#define CHECK_NWORST 64
static const char *check_worst_name[CHECK_NWORST];
static double check_worst_err[CHECK_NWORST];
static int check_nworst;
static inline int check_worst(const char *name, double err, double tol) {
  int i = 0;
  while (i < check_nworst && strcmp(check_worst_name[i], name) != 0) i++;
  if (i == check_nworst && check_nworst < CHECK_NWORST) {
    check_worst_name[check_nworst] = name;
    check_worst_err[check_nworst++] = 0.0;
  }
  if (i < CHECK_NWORST && !(err <= check_worst_err[i])) check_worst_err[i] = err;
  return check(name, err, tol);
}

/* ---------------------------------------------------------------- random numbers (splitmix64) */
static unsigned long long check_rng;
static inline void rand_seed(unsigned long long seed) { check_rng = seed; }
static inline double rand01(void) { /* uniform in [0, 1) */
  unsigned long long z = (check_rng += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}
static inline double rand11(void) { return 2.0 * rand01() - 1.0; } /* uniform in [-1, 1) */
static inline double randn(void) {                                 /* standard normal (Box-Muller) */
  double u = rand01(), v = rand01();
  return sqrt(-2.0 * log(1.0 - u)) * cos(2.0 * CHECK_PI * v);
}
static inline void rand_unit3(double n[3]) { /* uniform on the unit sphere */
  double s;
  do {
    for (int i = 0; i < 3; i++) n[i] = randn();
    s = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  } while (s < 1e-3);
  for (int i = 0; i < 3; i++) n[i] /= s;
}
/* Symmetric positive definite 6x6: A A^T + diag I, A uniform in [-1, 1). */
static inline void rand_spd6(double K[36], double diag) {
  double A[36];
  for (int i = 0; i < 36; i++) A[i] = rand11();
  for (int i = 0; i < 6; i++)
    for (int j = 0; j < 6; j++) {
      double s = (i == j) ? diag : 0;
      for (int k = 0; k < 6; k++) s += A[6 * i + k] * A[6 * j + k];
      K[6 * i + j] = s;
    }
}

/* ---------------------------------------------------------------- dense matrices (row-major) */
static inline void matmul(int n, const double *A, const double *B, double *C) { /* C = A B, n <= 8; C may alias */
  double T[64];
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) {
      double s = 0.0;
      for (int k = 0; k < n; k++) s += A[n * i + k] * B[n * k + j];
      T[n * i + j] = s;
    }
  memcpy(C, T, sizeof(double) * (size_t)(n * n));
}
static inline void eye(int n, double *I) {
  memset(I, 0, sizeof(double) * (size_t)(n * n));
  for (int i = 0; i < n; i++) I[n * i + i] = 1.0;
}
static inline double maxdiff(int m, const double *A, const double *B) { /* max |A - B| */
  double e = 0.0;
  for (int i = 0; i < m; i++) e = fmax(e, fabs(A[i] - B[i]));
  return e;
}
static inline double maxabs(int m, const double *A) {
  double e = 0.0;
  for (int i = 0; i < m; i++) e = fmax(e, fabs(A[i]));
  return e;
}
/* Matrix exponential by scaling and squaring of a Taylor series (n <= 8): a reference that does
 * not use csrc/util/se3.c. */
static inline void expm(int n, const double *A, double *E) {
  double nrm = maxabs(n * n, A);
  int s = 0;
  while (nrm * n > 0.25) {
    nrm *= 0.5;
    s++;
  }
  double S[64], T[64], Tk[64];
  double scale = ldexp(1.0, -s);
  for (int i = 0; i < n * n; i++) S[i] = A[i] * scale;
  eye(n, E);
  eye(n, Tk);
  for (int k = 1; k <= 20; k++) {
    matmul(n, Tk, S, T);
    for (int i = 0; i < n * n; i++) {
      Tk[i] = T[i] / k;
      E[i] += Tk[i];
    }
  }
  for (int k = 0; k < s; k++) matmul(n, E, E, E);
}

/* ---------------------------------------------------------------- twists and poses */
/* Rotation angle in [0, pi): class 0 uniform, 1 within 1e-8 of 0, 2 within 1e-8 of pi, 3 tiny
 * (< 1e-12) or exactly 0. */
static inline double rand_angle(int cls) {
  switch (cls) {
  case 1: return 1e-8 * rand01();
  case 2: return CHECK_PI - 1e-8 * (rand01() + 1e-3);
  case 3: return rand01() < 0.3 ? 0.0 : 1e-12 * rand01();
  default: return CHECK_PI * rand01();
  }
}
/* Twist (omega, v): rotation of a class-cls angle about a random axis, v normal with sigma 2. */
static inline void rand_twist(int cls, double x[6]) {
  double n[3], th = rand_angle(cls);
  rand_unit3(n);
  for (int i = 0; i < 3; i++) {
    x[i] = th * n[i];
    x[3 + i] = 2.0 * randn();
  }
}
/* H = exp(hat x) by expm, its rotation made orthogonal to rounding level (two steps of
 * R <- R (3 I - R^T R)/2): a pose built without csrc/util/se3.c. */
static inline void pose_expm(const double x[6], double H[16]) {
  double X[16] = {0, -x[2], x[1], x[3], x[2], 0, -x[0], x[4], -x[1], x[0], 0, x[5], 0, 0, 0, 0};
  expm(4, X, H);
  for (int it = 0; it < 2; it++) {
    double R[9], RtR[9], Rn[9];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) R[3 * i + j] = H[4 * i + j];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++)
        RtR[3 * i + j] = -0.5 * (R[i] * R[j] + R[3 + i] * R[3 + j] + R[6 + i] * R[6 + j]);
    RtR[0] += 1.5;
    RtR[4] += 1.5;
    RtR[8] += 1.5;
    matmul(3, R, RtR, Rn);
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) H[4 * i + j] = Rn[3 * i + j];
  }
  H[12] = H[13] = H[14] = 0.0;
  H[15] = 1.0;
}
/* Random pose: pose_expm of a class-cls twist (rand_twist). */
static inline void rand_pose_class(int cls, double H[16]) {
  double x[6];
  rand_twist(cls, x);
  pose_expm(x, H);
}
/* Random pose: pose_expm of a twist uniform in [-scale, scale)^6. */
static inline void rand_pose(double H[16], double scale) {
  double x[6];
  for (int i = 0; i < 6; i++) x[i] = scale * rand11();
  pose_expm(x, H);
}
/* out = H exp(s d): H moved along the body twist d for a time s. */
static inline void perturbed(const double H[16], const double d[6], double s, double out[16]) {
  double x[6], E[16];
  for (int i = 0; i < 6; i++) x[i] = s * d[i];
  phm_se3_exp(x, E);
  phm_se3_compose(H, E, out);
}

/* World position x of the point p of carrier c at poses H (c = -1: the ground, p is a world
 * point). */
static inline void point_world(const double *H, int c, const double p[3], double x[3]) {
  for (int i = 0; i < 3; i++) {
    const double *row = c < 0 ? NULL : H + 16 * c + 4 * i;
    x[i] = row ? row[3] + row[0] * p[0] + row[1] * p[1] + row[2] * p[2] : p[i];
  }
}

/* Distance between a spring-damper's two points at poses H. */
static inline double spring_length(const phm_spring_desc *sp, const double *H) {
  double xa[3], xb[3];
  point_world(H, sp->a, sp->pa, xa);
  point_world(H, sp->b, sp->pb, xb);
  return sqrt((xb[0] - xa[0]) * (xb[0] - xa[0]) + (xb[1] - xa[1]) * (xb[1] - xa[1]) +
              (xb[2] - xa[2]) * (xb[2] - xa[2]));
}

/* Carrier b's pose that puts a pair's frames at relative pose h: H_b = H_a Ta h Tb^-1 (Ha NULL:
 * ground). */
static inline void place_b(const double *Ha, const double Ta[16], const double Tb[16],
                           const double h[16], double Hb[16]) {
  double A[16], B[16], Tbi[16];
  if (Ha) phm_se3_compose(Ha, Ta, A);
  else memcpy(A, Ta, sizeof A);
  phm_se3_compose(A, h, B);
  phm_se3_inverse(Tb, Tbi);
  phm_se3_compose(B, Tbi, Hb);
}

/* ---------------------------------------------------------------- model descriptions */
/* A unit carrier: M = I, mass 1 kg, centre of mass at the origin, at rest at the identity. */
static inline void carrier_unit(phm_carrier_desc *c) {
  memset(c, 0, sizeof *c);
  for (int i = 0; i < 6; i++) c->M[7 * i] = 1.0;
  c->mass = 1.0;
  for (int i = 0; i < 4; i++) c->H0[5 * i] = 1.0;
}
/* The row of the pair table (csrc/model/pair_types.c) named `name`, or -1. */
static inline int pair_code(const char *name) {
  for (int t = 0; t < phm_pair_type_count(); t++)
    if (strcmp(phm_pair_type(t)->name, name) == 0) return t;
  return -1;
}

/* A straight beam of n elements along x from the origin, L long: n + 1 unit carriers
 * (carrier_unit) at x = c L / n, n elements of diagonal stiffness k (torsion, bending y and z,
 * axial, shear y and z; no damping, no mass of their own) unstrained when straight, and in
 * `clamp` (may be NULL) a fixed pair of the ground to carrier 0 at identity frames. */
static inline void straight_beam(int n, double L, const double k[6], phm_carrier_desc *car,
                                 phm_element_desc *el, phm_pair_desc *clamp) {
  double h = L / n;
  for (int c = 0; c <= n; c++) {
    carrier_unit(&car[c]);
    car[c].H0[3] = c * h;
  }
  for (int e = 0; e < n; e++) {
    memset(&el[e], 0, sizeof el[e]);
    el[e].a = e;
    el[e].b = e + 1;
    el[e].h = h;
    for (int i = 0; i < 6; i++) el[e].K[7 * i] = k[i];
    el[e].eps_hat[3] = 1.0;
  }
  if (clamp) {
    memset(clamp, 0, sizeof *clamp);
    for (int i = 0; i < 4; i++) clamp->Ta[5 * i] = clamp->Tb[5 * i] = 1.0;
    clamp->type = pair_code("fixed");
    clamp->a = -1;
    clamp->b = 0;
  }
}

/* The model of a description; NULL, and a failure recorded, if phm_model_create refuses it. */
static inline phm_model *create_model(const phm_model_desc *d) {
  phm_model *m = NULL;
  phm_error err;
  if (phm_model_create(d, &m, &err) == PHM_OK) return m;
  check_fail("phm_model_create: %s", err.msg);
  return NULL;
}

/* A model of two unit carriers (carrier_unit) joined by `pair`, with `nact` actuators (may be
 * 0); NULL if refused (create_model). Free with phm_model_free. */
static inline phm_model *two_carrier_model(const phm_pair_desc *pair, const phm_actuator_desc *act,
                                           int nact) {
  phm_carrier_desc car[2];
  carrier_unit(&car[0]);
  carrier_unit(&car[1]);
  phm_model_desc d = {.ncarriers = 2, .carriers = car, .npairs = 1, .pairs = pair,
                      .nactuators = nact, .actuators = act};
  return create_model(&d);
}

/* A pair of type `type` from carrier 0 (trial % 3 == 0: from the ground) to carrier 1, with
 * random frames Ta, Tb and, for a helical pair, a random pitch in [-0.3, 0.3). */
static inline void rand_pair(int type, int trial, phm_pair_desc *pr) {
  memset(pr, 0, sizeof *pr);
  pr->type = type;
  pr->a = trial % 3 == 0 ? -1 : 0;
  pr->b = 1;
  pr->pitch = type == pair_code("helical") ? 0.3 * rand11() : 0.0;
  rand_pose(pr->Ta, 1.0);
  rand_pose(pr->Tb, 1.0);
}

/* The pair types whose first joint angle may wind several turns. */
static inline int pair_winds(int type) {
  return type == pair_code("revolute") || type == pair_code("helical") ||
         type == pair_code("cylindrical") || type == pair_code("planar");
}

/* Joint coordinates uniform in [-1.2, 1.2), a winding angle moved by `turns` turns. */
static inline void rand_joint_coordinates(int type, int turns, double x[6]) {
  for (int i = 0; i < 6; i++) x[i] = 1.2 * rand11();
  if (pair_winds(type)) x[0] += 2 * CHECK_PI * turns;
}

/* ---------------------------------------------------------------- the runner */
typedef struct {
  const char *name;
  void (*run)(void);
} check_case;
#define CHECK_CASE(fn) {#fn, fn}

static inline unsigned long long check_hash(const char *s) { /* FNV-1a */
  unsigned long long h = 0xcbf29ce484222325ULL;
  for (; *s; s++) h = (h ^ (unsigned char)*s) * 0x100000001b3ULL;
  return h;
}

/* Run the cases named in argv (all when none is named; "-v": verbose); print the failures and a
 * summary; non-zero when a check failed, none ran, or a named case does not exist. */
static inline int check_main(const char *file, const check_case *cases, int ncases, int argc,
                             char **argv) {
  const char *base = strrchr(file, '/'), *env = getenv("CHECK_SEED");
  unsigned long long seed = env && *env ? strtoull(env, NULL, 0) : 0x1234567887654321ULL;
  int nnamed = 0, nrun = 0, nfailed_cases = 0;
  base = base ? base + 1 : file;
  for (int a = 1; a < argc; a++) {
    if (strcmp(argv[a], "-v") == 0) {
      check_verbose = 1;
      continue;
    }
    nnamed++;
    int found = 0;
    for (int c = 0; c < ncases; c++) found |= strcmp(argv[a], cases[c].name) == 0;
    if (!found) {
      printf("%s: no test case named %s\n", base, argv[a]);
      return 2;
    }
  }
  for (int c = 0; c < ncases; c++) {
    int wanted = nnamed == 0;
    for (int a = 1; a < argc; a++) wanted |= strcmp(argv[a], cases[c].name) == 0;
    if (!wanted) continue;
    int nfail0 = check_nfail;
    check_case_name = cases[c].name;
    rand_seed(seed ^ check_hash(cases[c].name));
    cases[c].run();
    nrun++;
    nfailed_cases += check_nfail > nfail0;
  }
  if (check_verbose)
    for (int i = 0; i < check_nworst; i++) printf("  worst %-50s %.3e\n", check_worst_name[i], check_worst_err[i]);
  printf("%s: %d passed, %d failed (%d test case%s", base, check_npass, check_nfail, nrun, nrun == 1 ? "" : "s");
  if (nfailed_cases) printf(", %d failing; seed %#llx", nfailed_cases, seed);
  printf(")\n");
  return check_nfail != 0 || check_npass == 0;
}

#define CHECK_MAIN(...)                                                                          \
  int main(int argc, char **argv) {                                                              \
    static const check_case cases[] = {__VA_ARGS__};                                             \
    return check_main(__FILE__, cases, (int)(sizeof cases / sizeof cases[0]), argc, argv);       \
  }

#endif /* PHM_TESTS_CHECK_H */
