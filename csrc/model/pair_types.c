/* pair_types.c -- THE pair table: every kinematic pair type (its constraint rows, joint
 * coordinates, units, constraint-wrench directions, parameters and kinematics) is defined here and
 * only here; Python builds its pair classes from this table (phm_pair_type). Each type's
 * kinematics at a relative pose h: constraints g, wrench basis W^C, effort basis Phi, joint
 * coordinates x and their tangents along h exp(eta), through one switch of forward-mode dual
 * numbers (pair_kin), with closed forms for the revolute and the fixed pair; a type's pose from its
 * coordinates and back. The evaluation of a model's pairs from these kinematics is in pair.c.
 * Adding a pair type: docs/architecture.md. */
#include "model.h"

#include <math.h>
#include <string.h>

#include "linalg.h"
#include "pose.h"

/* Type codes: the rows of the table below, in this order. */
enum {
  PAIR_FIXED, PAIR_REVOLUTE, PAIR_PRISMATIC, PAIR_HELICAL, PAIR_CYLINDRICAL, PAIR_UNIVERSAL,
  PAIR_SPHERICAL, PAIR_PLANAR, PAIR_FREE, PAIR_SLOT, PAIR_NTYPES
};

static const phm_pair_type_info pair_table[PAIR_NTYPES] = {
    {"fixed", 6, "", {0}, {"tau_x", "tau_y", "tau_z", "f_x", "f_y", "f_z"}, 1, 0,
     "Fixed (welded) pair: 6 constraints, relative pose = identity (or the driven motion).",
     0, 0},
    {"revolute", 5, "axis=z", {"rad"}, {"tau_x", "tau_y", "f_x", "f_y", "f_z"}, 0, 1,
     "Revolute pair about ``axis`` (of both pair frames); x = angle [rad], multi-turn.",
     1, 1},
    {"prismatic", 5, "axis=z", {"m"}, {"tau_x", "tau_y", "tau_z", "f_x", "f_y"}, 0, 1,
     "Prismatic pair along ``axis``; x = displacement [m].",
     1, 1},
    {"helical", 5, "axis=z,pitch=0", {"rad"}, {"tau_x", "tau_y", "f_x", "f_y", "f_z-pitch*tau_z"}, 0, 1,
     "Helical (screw) pair about ``axis``: translation = ``pitch`` [m/rad] x angle; x = angle.",
     1, 1},
    {"cylindrical", 4, "axis=z", {"rad", "m"}, {"tau_x", "tau_y", "f_x", "f_y"}, 0, 3,
     "Cylindrical pair along ``axis``; x = (angle [rad], displacement [m]).",
     3, 3},
    {"universal", 4, "axis1=x,axis2=y", {"rad", "rad"}, {"tau_n", "f_x", "f_y", "f_z"}, 0, 3,
     "Universal (Cardan) pair: first axis ``axis1`` fixed in F_a, second ``axis2`` fixed in F_b "
     "(perpendicular when both frames coincide); x = (angle about axis1, angle about axis2) [rad], "
     "h = Rx(x0) Ry(x1) in the pair frames (x = axis1, y = axis2; tau_n = axis1 x axis2).",
     1, 2},
    {"spherical", 3, "", {"rad", "rad", "rad"}, {"f_x", "f_y", "f_z"}, 0, 0,
     "Spherical (ball) pair; x = rotation vector of F_b in F_a [rad], xdot = angular velocity "
     "(in F_b) -- a quasi-velocity, not dx/dt.",
     0, 7},
    {"planar", 3, "normal=z", {"rad", "m", "m"}, {"tau_x", "tau_y", "f_z"}, 0, 7,
     "Planar pair with plane ``normal``; x = (angle [rad], p_x, p_y [m]) with p the position of "
     "F_b's origin in F_a (x, y of the frame whose z is the normal).",
     7, 1},
    {"free", 0, "", {"rad", "rad", "rad", "m", "m", "m"}, {0}, 0, 0x38,
     "Free pair (no constraint): x = (rotation vector, position of F_b in F_a); xdot = (angular "
     "velocity in F_b, dp/dt in F_a). Useful to measure or actuate a relative motion.",
     0x38, 7},
    {"slot", 4, "", {"rad", "m"}, {"tau_x", "tau_y", "f_y_a", "f_z_a"}, 0, 3,
     "Slot pair: F_b turns about the common z axis and slides along F_a's x axis; x = (angle "
     "[rad], displacement [m]); its forces f_y_a, f_z_a are along F_a's y and z.",
     3, 1},
};

int phm_pair_type_count(void) { return PAIR_NTYPES; }
const phm_pair_type_info *phm_pair_type(int type) {
  return type >= 0 && type < PAIR_NTYPES ? &pair_table[type] : NULL;
}

static double wrap_pi(double a) { return a - 2 * PHM_PI * floor((a + PHM_PI) / (2 * PHM_PI)); }
static double near_angle(double a, const double *xref, int i) { return xref ? xref[i] + wrap_pi(a - xref[i]) : a; }

/* A quantity of a pair's kinematics with its derivatives along the body perturbations of the
 * relative pose, h exp(eta): d[j] = d/d eta_j (eta = (omega, v), docs/method.md section 3.7). The
 * table's g, W^C, Phi and x are built from the entries of R, p, q = R^T p, angles and logarithms,
 * so one switch gives the values and, when asked, their tangents (forward-mode differentiation). */
typedef struct {
  double v, d[6];
} pq;

static pq cst(double v) { return (pq){v, {0, 0, 0, 0, 0, 0}}; }
static pq lin2(double a, pq x, double b, pq y) {
  pq r = {a * x.v + b * y.v, {0}};
  for (int j = 0; j < 6; j++) r.d[j] = a * x.d[j] + b * y.d[j];
  return r;
}
/* inline: pair_kin is forced inline into its two callers, and GCC (-O3) then left neg out of line
 * -- 12 calls returning a 56-byte struct through memory per evaluation of the kinematics */
static inline pq neg(pq x) { return lin2(-1.0, x, 0.0, x); }
static pq atan2_pq(pq y, pq x, int tan) {
  double n = x.v * x.v + y.v * y.v, ni = n > 0 ? 1.0 / n : 0.0;
  pq r = {atan2(y.v, x.v), {0}};
  for (int j = 0; tan && j < 6; j++) r.d[j] = (x.v * y.d[j] - y.v * x.d[j]) * ni;
  return r;
}
static pq near_pq(pq a, const double *xref, int i) {
  a.v = near_angle(a.v, xref, i);
  return a;
}

/* Entry i of an output array: its value in v[i], its derivatives in D[6 i ..] (D may be NULL). */
static void put(double *v, double *D, int i, pq s) {
  v[i] = s.v;
  if (D) memcpy(D + 6 * i, s.d, sizeof s.d);
}
/* Column c of a 6x6 row-major basis (values B, derivatives D): entries of rows r0..r0+2. */
static void setcol(double *B, double *D, int c, int r0, pq v0, pq v1, pq v2) {
  put(B, D, 6 * r0 + c, v0);
  put(B, D, 6 * (r0 + 1) + c, v1);
  put(B, D, 6 * (r0 + 2) + c, v2);
}

/* log(R) of the rotation of h (so3) or log(h) (se3, n = 6), with its derivatives when tan:
 * d log/d eta = dexp_{-x}^-1 (docs/method.md section 3.6), whose blocks are the transposes of
 * dexp_x^-1's (phm_se3_log_dexp_inv). */
static void log_pq(const double h[16], int n, int tan, pq *out) {
  double x[6], Ai[9], L[9], Rm[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) Rm[3 * i + j] = h[4 * i + j];
  if (n == 6 && tan) phm_se3_log_dexp_inv(h, x, Ai, L);
  else if (n == 6) phm_se3_log(h, x);
  else {
    phm_so3_log(Rm, x);
    if (tan) phm_so3_jac_inv(x, Ai);
  }
  for (int i = 0; i < n; i++) {
    out[i] = cst(x[i]);
    for (int j = 0; tan && j < 3; j++) {
      if (i < 3) out[i].d[j] = Ai[3 * j + i];
      else {
        out[i].d[j] = L[3 * j + i - 3];
        out[i].d[j + 3] = Ai[3 * j + i - 3];
      }
    }
  }
}

#if defined(__GNUC__)
#define PAIR_KIN_INLINE static inline __attribute__((always_inline))
#else
#define PAIR_KIN_INLINE static inline
#endif

/* Joint coordinates 0..2 the rotation vector log(R) of h, their effort columns 0..2 of Phi the unit
 * torques (xdot = the angular velocity in F_b): the spherical pair's and the free pair's rotation. */
PAIR_KIN_INLINE void rotation_vector(const double h[16], int tan, double *xx, double *dx, double *Pl,
                                     double *dP) {
  pq lg[3];
  const pq c0 = cst(0), c1 = cst(1);
  log_pq(h, 3, tan, lg);
  for (int i = 0; i < 3; i++) put(xx, dx, i, lg[i]);
  setcol(Pl, dP, 0, 0, c1, c0, c0); setcol(Pl, dP, 1, 0, c0, c1, c0); setcol(Pl, dP, 2, 0, c0, c0, c1);
}

/* Position constraints are written so that dg = W^T t_rel at g = 0 (up to a unit-triangular
 * factor for helical/cylindrical): rotations through the z axis of F_a seen in F_b, R^T e_z, whose
 * rate is e_z x omega; translations through R^T p (rate v - omega x R^T p) or p (rate R v).
 * Derivatives (any may be NULL; all NULL: none computed) along h exp(eta): Dg (6 per row), DW and
 * DPhi (6 per entry of the 6x6 row-major bases), Dx (6 per coordinate). With h exp(eta):
 * dR = R hat(omega), dp = R v, dq = q x omega + v. Inlined into its two callers with tan a
 * constant, so that the values-only one (every residual's) drops the derivatives' work: called
 * out of line, the derivatives carried along cost a revolute pair 141 ns instead of 64 ns; inlined
 * 87 ns (a rigid four-bar's residual 1.43 us instead of 1.34 us before the tangents). */
PAIR_KIN_INLINE void pair_kin(int tan, int type, double pitch, const double h[16], const double *xref,
                         double *g, double *W, double *Phi, double *x, double *Dg, double *DW,
                         double *DPhi, double *Dx) {
  pq R[3][3], p[3], q[3], lg[6];
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++) { /* d R_ij/d omega_m = (R hat(e_m))_ij = eps_{mjk} R_ik */
      R[i][j] = cst(h[4 * i + j]);
      for (int mm = 0; tan && mm < 3; mm++)
        if (mm != j) R[i][j].d[mm] = ((j - mm + 3) % 3 == 1 ? 1.0 : -1.0) * h[4 * i + 3 - mm - j];
    }
    p[i] = cst(h[4 * i + 3]);
    for (int k = 0; tan && k < 3; k++) p[i].d[3 + k] = h[4 * i + k];
  }
  for (int i = 0; i < 3; i++) q[i] = cst(h[i] * h[3] + h[4 + i] * h[7] + h[8 + i] * h[11]);
  for (int i = 0; tan && i < 3; i++) { /* dq/d omega_m = q x e_m, dq/dv = I */
    int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    q[i].d[i2] = q[i1].v;  /* (q x e_{i2})_i = q_{i1} */
    q[i].d[i1] = -q[i2].v; /* (q x e_{i1})_i = -q_{i2} */
    q[i].d[3 + i] = 1.0;
  }
  double gg[6] = {0}, xx[6] = {0}, Wl[36] = {0}, Pl[36] = {0};
  double Dgl[36], Dxl[36], DWl[216], DPl[216];
  double *dg = tan ? Dgl : NULL, *dx = tan ? Dxl : NULL, *dW = tan ? DWl : NULL, *dP = tan ? DPl : NULL;
  if (tan) {
    memset(Dgl, 0, sizeof Dgl);
    memset(Dxl, 0, sizeof Dxl);
    memset(DWl, 0, sizeof DWl);
    memset(DPl, 0, sizeof DPl);
  }
  const pq c0 = cst(0), c1 = cst(1);
  pq th = atan2_pq(R[1][0], R[0][0], tan);
  switch (type) {
  case PAIR_FIXED:
    log_pq(h, 6, tan, lg);
    for (int i = 0; i < 6; i++) {
      put(gg, dg, i, lg[i]);
      Wl[7 * i] = 1;
    }
    break;
  case PAIR_REVOLUTE:
    put(gg, dg, 0, R[2][1]); put(gg, dg, 1, neg(R[2][0]));
    put(gg, dg, 2, q[0]); put(gg, dg, 3, q[1]); put(gg, dg, 4, q[2]);
    setcol(Wl, dW, 0, 0, c1, c0, c0); setcol(Wl, dW, 1, 0, c0, c1, c0);
    setcol(Wl, dW, 2, 3, c1, c0, c0); setcol(Wl, dW, 3, 3, c0, c1, c0); setcol(Wl, dW, 4, 3, c0, c0, c1);
    setcol(Pl, dP, 0, 0, c0, c0, c1);
    put(xx, dx, 0, near_pq(th, xref, 0));
    break;
  case PAIR_PRISMATIC:
    log_pq(h, 3, tan, lg);
    put(gg, dg, 0, lg[0]); put(gg, dg, 1, lg[1]); put(gg, dg, 2, lg[2]);
    put(gg, dg, 3, p[0]); put(gg, dg, 4, p[1]);
    setcol(Wl, dW, 0, 0, c1, c0, c0); setcol(Wl, dW, 1, 0, c0, c1, c0); setcol(Wl, dW, 2, 0, c0, c0, c1);
    setcol(Wl, dW, 3, 3, c1, c0, c0); setcol(Wl, dW, 4, 3, c0, c1, c0);
    setcol(Pl, dP, 0, 3, c0, c0, c1);
    put(xx, dx, 0, p[2]);
    break;
  case PAIR_HELICAL: {
    pq a = near_pq(th, xref, 0);
    double s = 1.0 / sqrt(1 + pitch * pitch), s2 = 1.0 / (1 + pitch * pitch);
    put(gg, dg, 0, R[2][1]); put(gg, dg, 1, neg(R[2][0]));
    put(gg, dg, 2, q[0]); put(gg, dg, 3, q[1]); put(gg, dg, 4, lin2(s, q[2], -s * pitch, a));
    setcol(Wl, dW, 0, 0, c1, c0, c0); setcol(Wl, dW, 1, 0, c0, c1, c0);
    setcol(Wl, dW, 2, 3, c1, c0, c0); setcol(Wl, dW, 3, 3, c0, c1, c0);
    setcol(Wl, dW, 4, 0, c0, c0, cst(-pitch * s)); setcol(Wl, dW, 4, 3, c0, c0, cst(s));
    setcol(Pl, dP, 0, 0, c0, c0, cst(s2)); setcol(Pl, dP, 0, 3, c0, c0, cst(pitch * s2));
    put(xx, dx, 0, a);
  } break;
  case PAIR_CYLINDRICAL:
    put(gg, dg, 0, R[2][1]); put(gg, dg, 1, neg(R[2][0])); put(gg, dg, 2, q[0]); put(gg, dg, 3, q[1]);
    setcol(Wl, dW, 0, 0, c1, c0, c0); setcol(Wl, dW, 1, 0, c0, c1, c0);
    setcol(Wl, dW, 2, 3, c1, c0, c0); setcol(Wl, dW, 3, 3, c0, c1, c0);
    setcol(Pl, dP, 0, 0, c0, c0, c1); setcol(Pl, dP, 1, 3, c0, c0, c1);
    put(xx, dx, 0, near_pq(th, xref, 0));
    put(xx, dx, 1, q[2]);
    break;
  case PAIR_UNIVERSAL:
    /* a = R^T e_x (first axis seen in F_b), second axis e_y; x of F_a stays normal to y of F_b */
    put(gg, dg, 0, neg(R[0][1])); put(gg, dg, 1, q[0]); put(gg, dg, 2, q[1]); put(gg, dg, 3, q[2]);
    setcol(Wl, dW, 0, 0, neg(R[0][2]), c0, R[0][0]); /* a x e_y */
    setcol(Wl, dW, 1, 3, c1, c0, c0); setcol(Wl, dW, 2, 3, c0, c1, c0); setcol(Wl, dW, 3, 3, c0, c0, c1);
    setcol(Pl, dP, 0, 0, R[0][0], R[0][1], R[0][2]); setcol(Pl, dP, 1, 0, c0, c1, c0);
    put(xx, dx, 0, near_pq(atan2_pq(R[2][1], R[1][1], tan), xref, 0));
    put(xx, dx, 1, near_pq(atan2_pq(R[0][2], R[0][0], tan), xref, 1));
    break;
  case PAIR_SPHERICAL:
    rotation_vector(h, tan, xx, dx, Pl, dP);
    put(gg, dg, 0, q[0]); put(gg, dg, 1, q[1]); put(gg, dg, 2, q[2]);
    setcol(Wl, dW, 0, 3, c1, c0, c0); setcol(Wl, dW, 1, 3, c0, c1, c0); setcol(Wl, dW, 2, 3, c0, c0, c1);
    break;
  case PAIR_PLANAR:
    put(gg, dg, 0, R[2][1]); put(gg, dg, 1, neg(R[2][0])); put(gg, dg, 2, p[2]);
    setcol(Wl, dW, 0, 0, c1, c0, c0); setcol(Wl, dW, 1, 0, c0, c1, c0); setcol(Wl, dW, 2, 3, c0, c0, c1);
    setcol(Pl, dP, 0, 0, c0, c0, c1);
    setcol(Pl, dP, 1, 3, R[0][0], R[0][1], R[0][2]); setcol(Pl, dP, 2, 3, R[1][0], R[1][1], R[1][2]);
    put(xx, dx, 0, near_pq(th, xref, 0));
    put(xx, dx, 1, p[0]);
    put(xx, dx, 2, p[1]);
    break;
  case PAIR_FREE:
    rotation_vector(h, tan, xx, dx, Pl, dP);
    put(xx, dx, 3, p[0]); put(xx, dx, 4, p[1]); put(xx, dx, 5, p[2]);
    for (int j = 0; j < 3; j++) setcol(Pl, dP, 3 + j, 3, R[j][0], R[j][1], R[j][2]);
    break;
  case PAIR_SLOT:
    put(gg, dg, 0, R[2][1]); put(gg, dg, 1, neg(R[2][0])); put(gg, dg, 2, p[1]); put(gg, dg, 3, p[2]);
    setcol(Wl, dW, 0, 0, c1, c0, c0); setcol(Wl, dW, 1, 0, c0, c1, c0);
    setcol(Wl, dW, 2, 3, R[1][0], R[1][1], R[1][2]); setcol(Wl, dW, 3, 3, R[2][0], R[2][1], R[2][2]);
    setcol(Pl, dP, 0, 0, c0, c0, c1); setcol(Pl, dP, 1, 3, R[0][0], R[0][1], R[0][2]);
    put(xx, dx, 0, near_pq(th, xref, 0));
    put(xx, dx, 1, p[0]);
    break;
  default: break; /* a type without its case here has no kinematics: phm_model_create refuses it */
  }
  int mm = (type >= 0 && type < PAIR_NTYPES) ? pair_table[type].m : 0;
  if (g) memcpy(g, gg, sizeof(double) * (size_t)mm);
  if (x) memcpy(x, xx, sizeof(double) * (size_t)(6 - mm));
  if (W) memcpy(W, Wl, sizeof Wl);
  if (Phi) memcpy(Phi, Pl, sizeof Pl);
  if (Dg) memcpy(Dg, Dgl, sizeof(double) * 6 * (size_t)mm);
  if (Dx) memcpy(Dx, Dxl, sizeof(double) * 6 * (size_t)(6 - mm));
  if (DW) memcpy(DW, DWl, sizeof DWl);
  if (DPhi) memcpy(DPhi, DPl, sizeof DPl);
}

/* A constant 0/1 basis (6x6 row-major) from its pattern of bytes: converted, not copied -- GCC
 * copied a table of doubles (and zeroed one) with `rep movsq` (`rep stosq`), slower than the
 * rest of this closed form. */
static inline void unit_basis(double B[36], const unsigned char pat[36]) {
  for (int e = 0; e < 36; e++) B[e] = pat[e];
}
/* The revolute row of the table in closed form: pair_kin's PAIR_REVOLUTE case with the values
 * and derivatives its pq primitives give, written out (the same arithmetic: the same numbers, an
 * exact zero's sign aside; tests/c/test_pair.c compares the two). g = (R_21, -R_20, q), W^C and Phi
 * constant (their derivatives vanish: DW, DPhi are zero-filled when asked), x = theta. */
static void revolute_kin(const double h[16], const double *xref, double *g, double *W,
                         double *Phi, double *x, double *Dg, double *Dx) {
  double q[3];
  for (int i = 0; i < 3; i++) q[i] = h[i] * h[3] + h[4 + i] * h[7] + h[8 + i] * h[11];
  if (g) {
    g[0] = h[9];
    g[1] = -h[8];
    g[2] = q[0];
    g[3] = q[1];
    g[4] = q[2];
  }
  static const unsigned char Wp[36] = {1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, /* [e0 e1 e3 e4 e5] */
                                       0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0,
                                       0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0},
                             Pp[36] = {[12] = 1}; /* Phi = e2 */
  if (W) unit_basis(W, Wp);
  if (Phi) unit_basis(Phi, Pp);
  if (x) x[0] = near_angle(atan2(h[4], h[0]), xref, 0);
  if (Dg) { /* dR = R hat(omega), dq = q x omega + v */
    static const double z[6] = {0, 0, 0, 0, 0, 0};
    for (int r = 0; r < 5; r++) memcpy(Dg + 6 * r, z, sizeof z);
    Dg[0] = h[10];  Dg[2] = -h[8];  /* R_21 */
    Dg[7] = h[10];  Dg[8] = -h[9];  /* -R_20 */
    Dg[13] = -q[2]; Dg[14] = q[1];  Dg[15] = 1; /* q_0 */
    Dg[18] = q[2];  Dg[20] = -q[0]; Dg[22] = 1; /* q_1 */
    Dg[24] = -q[1]; Dg[25] = q[0];  Dg[29] = 1; /* q_2 */
  }
  if (Dx) { /* theta = atan2(R_10, R_00) */
    double n = h[0] * h[0] + h[4] * h[4], ni = n > 0 ? 1.0 / n : 0.0;
    Dx[0] = Dx[3] = Dx[4] = Dx[5] = 0;
    Dx[1] = (h[0] * -h[6] - h[4] * -h[2]) * ni;
    Dx[2] = (h[0] * h[5] - h[4] * h[1]) * ni;
  }
}

/* The fixed row of the table without derivatives in closed form: g = log(h) (pair_kin's log_pq,
 * the same numbers), W = I, Phi = 0 (no coordinates). pair_kin's switch also set up its dual
 * numbers and an angle (atan2) the fixed pair does not read: a third of a clamped beam's pair. */
static void fixed_kin(const double h[16], double *g, double *W, double *Phi) {
  static const unsigned char Ip[36] = {1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0,
                                       0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1};
  if (g) phm_se3_log(h, g);
  if (W) unit_basis(W, Ip);
  if (Phi) memset(Phi, 0, 36 * sizeof(double));
}

/* The kinematics of a type: its closed form where it has one, else the table's switch (pair_kin);
 * csrc/model/model.h. */
void phm_pair_kin_eval(int general, int type, double pitch, const double h[16],
                       const double *xref, double *g, double *W, double *Phi, double *x, double *Dg,
                       double *DW, double *DPhi, double *Dx, int *constant) {
  int tan = Dg || DW || DPhi || Dx;
  if (!general && !tan && type == PAIR_FIXED) fixed_kin(h, g, W, Phi);
  else if (!general && type == PAIR_REVOLUTE) {
    revolute_kin(h, xref, g, W, Phi, x, Dg, Dx);
    if (constant) *constant = 1;
    else {
      if (DW) memset(DW, 0, 216 * sizeof(double));
      if (DPhi) memset(DPhi, 0, 216 * sizeof(double));
    }
  } else if (tan) pair_kin(1, type, pitch, h, xref, g, W, Phi, x, Dg, DW, DPhi, Dx);
  else pair_kin(0, type, pitch, h, xref, g, W, Phi, x, NULL, NULL, NULL, NULL);
}

void phm_pair_kin_tangent(int type, double pitch, const double h[16], const double *xref,
                          double *g, double *W, double *Phi, double *x, double *Dg, double *DW,
                          double *DPhi, double *Dx) {
  phm_pair_kin_eval(0, type, pitch, h, xref, g, W, Phi, x, Dg, DW, DPhi, Dx, NULL);
}

void phm_pair_kin_general(int type, double pitch, const double h[16], const double *xref,
                          double *g, double *W, double *Phi, double *x, double *Dg, double *DW,
                          double *DPhi, double *Dx) {
  phm_pair_kin_eval(1, type, pitch, h, xref, g, W, Phi, x, Dg, DW, DPhi, Dx, NULL);
}

void phm_pair_kin(int type, double pitch, const double h[16], const double *xref, double *g,
                  double *W, double *Phi, double *x) {
  phm_pair_kin_eval(0, type, pitch, h, xref, g, W, Phi, x, NULL, NULL, NULL, NULL, NULL);
}

/* ---------------------------------------------------------------- a type's kinematics alone */
void phm_pair_type_pose(int type, double pitch, const double *x, double h[16]) {
  double z[6] = {0}, A[16], B[16];
  switch (type) {
  case PAIR_REVOLUTE: z[2] = x[0]; break;
  case PAIR_PRISMATIC: z[5] = x[0]; break;
  case PAIR_HELICAL: z[2] = x[0]; z[5] = pitch * x[0]; break;
  case PAIR_CYLINDRICAL: z[2] = x[0]; z[5] = x[1]; break;
  case PAIR_UNIVERSAL: /* h = Rx(x0) Ry(x1) */
    z[0] = x[0];
    phm_se3_exp(z, A);
    z[0] = 0;
    z[1] = x[1];
    phm_se3_exp(z, B);
    phm_se3_compose(A, B, h);
    return;
  case PAIR_SPHERICAL: z[0] = x[0]; z[1] = x[1]; z[2] = x[2]; break;
  case PAIR_PLANAR: z[2] = x[0]; break;
  case PAIR_FREE: z[0] = x[0]; z[1] = x[1]; z[2] = x[2]; break;
  case PAIR_SLOT: z[2] = x[0]; break;
  default: break;
  }
  phm_se3_exp(z, h);
  if (type == PAIR_SLOT) h[3] = x[1];
  if (type == PAIR_PLANAR) { h[3] = x[1]; h[7] = x[2]; }
  if (type == PAIR_FREE) { h[3] = x[3]; h[7] = x[4]; h[11] = x[5]; }
}

void phm_pair_type_coordinates(int type, double pitch, const double h[16], const double *xref,
                               double *x) {
  if (type < 0 || type >= PAIR_NTYPES) return; /* unknown type: no coordinates */
  phm_pair_kin(type, pitch, h, xref, NULL, NULL, NULL, x);
  /* without a reference, a helical pair's turn is the one whose translation pitch * angle is
   * nearest to h's -- unless that angle is beyond 1e15 rad, where a double no longer tells one
   * turn from the next (the pose check then reports what the pair cannot reach) */
  if (type == PAIR_HELICAL && !xref && pitch != 0) {
    double turn = x[0] + 2 * PHM_PI * nearbyint((h[11] / pitch - x[0]) / (2 * PHM_PI));
    if (fabs(turn) <= 1e15) x[0] = turn;
  }
}
