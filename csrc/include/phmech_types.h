/* phmech_types.h -- the data types of phmech's public C API (csrc/include/phmech.h lists the
 * functions). Conventions (docs/method.md section 3):
 *   - every matrix is a row-major (C-ordered) array of doubles: a 3x3 is double[9],
 *     a 4x4 homogeneous pose is double[16], a 6x6 is double[36];
 *   - twist t = (omega, v), wrench w = (tau, f): angular part first;
 *   - pose H = [[R, p], [0, 1]]; body-frame twist: H^-1 dH/dt = hat(t);
 *   - ad_t = [[hat(w), 0], [hat(v), hat(w)]],  Ad_H = [[R, 0], [hat(p) R, R]];
 *     the duals ad*_t := ad_t^T and Ad*_H := Ad_H^T act on wrenches;
 *   - dexp_X = sum_k ad_X^k / (k+1)!, so that H = H0 exp(hat X) gives H^-1 dH/dt = dexp_{-X} dX/dt;
 *   - quaternions are scalar first: q = (w, x, y, z), unit norm.
 * Sections follow the data path: errors, the mixed element (a separate linear model), the
 * model description (time laws, carriers, elements, pairs, actuators, springs, loads), the
 * simulation options and outputs. */
#ifndef PHMECH_TYPES_H
#define PHMECH_TYPES_H

#include <stddef.h>

/* ---------------------------------------------------------------- errors */
typedef enum {
  PHM_OK = 0,
  PHM_EINVAL = 1,    /* bad model or argument (Python: ValueError subclass)      */
  PHM_ENOMEM = 2,    /* allocation failed (Python: MemoryError)                    */
  PHM_ESOLVER = 3,   /* integrator / nonlinear solver failure (Python: RuntimeError) */
  PHM_ESINGULAR = 4, /* singular or indefinite matrix (Python: RuntimeError)       */
  PHM_EINTERRUPT = 5 /* stopped by the caller's interrupt callback                  */
} phm_status;

typedef struct {
  phm_status code;
  char msg[512];
  const char *file; /* where in csrc/ the error was raised (PHM_FAIL), or NULL */
  int line;
} phm_error;

/* ---------------------------------------------------------------- mixed finite element (csrc/model/mixed.c) */
/* Golo's mixed finite element (alpha family; alpha = 1/2 is the paper's) for the LINEAR planar
 * Timoshenko beam: transverse displacement w, section rotation phi, s in [0, L].
 * State of element k (h = L/N), integrated energy variables, x_k = (P_t, E_s, P_r, K):
 *   transverse momentum, shear strain, angular momentum, curvature (each integrated over the element).
 * Hamiltonian H = x^T Q x / 2, Q = diag(1/(rhoA h), kGA/h, 1/(rhoI h), EI/h) per element; so the
 * co-energy (Q x)_k = (v, Qs, omega, M): velocity, shear force, angular velocity, bending moment.
 * Boundary ports of the chain: u = (v(0), omega(0), Qs(L), M(L)), y = (-Qs(0), -M(0), v(L), omega(L)),
 *   dx/dt = J Q x + B u,  y = B^T Q x + D u,  J = -J^T, D = -D^T,  so dH/dt = u^T y.
 * A boundary condition sets each of the four ports either "input = 0" (the port is dropped) or
 * "output = 0" (the input becomes a Lagrange multiplier lambda, dx/dt = J Q x + G lambda, G^T Q x = 0).
 * Matrices are row-major; sizes: n = 4N states, J and Q n x n, B n x 4, D 4 x 4. */
typedef enum {
  PHM_MIXED_CLAMPED_FREE = 0,    /* v = omega = 0 at s = 0; Qs = M = 0 at s = L (cantilever) */
  PHM_MIXED_CLAMPED_CLAMPED = 1, /* v = omega = 0 at both ends                               */
  PHM_MIXED_PINNED_PINNED = 2,   /* v = M = 0 at both ends (simply supported)                 */
  PHM_MIXED_CLAMPED_PINNED = 3   /* v = omega = 0 at s = 0; v = M = 0 at s = L               */
} phm_mixed_bc;

#define PHM_MIXED_NMAX 1000 /* dense matrices: 4N x 4N */

typedef struct {
  int N;                          /* number of elements, 1 <= N <= PHM_MIXED_NMAX          */
  double L;                       /* length [m]                                             */
  double EI, kGA;                 /* bending [N m^2] and shear [N] stiffness                */
  double rhoA, rhoI;              /* mass per length [kg/m], rotary inertia per length [kg m] */
  double alpha;                   /* Golo's weight, 0 <= alpha < 1 (paper: 1/2); alpha > 1/2
                                   * is refused when (alpha/(1-alpha))^N > 1e6 (ill-conditioned) */
} phm_mixed_beam;


/* ---------------------------------------------------------------- the model (csrc/model/) */

/* A model is built once from flat descriptions (copied; the caller may free them afterwards) and
 * is immutable. Carriers are rigid bodies and beam nodes alike: a frame with a 6x6 spatial inertia
 * M (body coordinates, centre of mass may be offset), the mass and centre of mass used for
 * gravity, an initial pose H0 and body twist t0. Carrier state: unit quaternion q (scalar first),
 * world position p, body twist t = (omega, v). Equations of motion (docs/method.md section 6, GGL form):
 *   q' = 1/2 q (x) (omega + dw),  p' = R (v + dv)        with (dw, dv) = this carrier's (G^T mu)
 *   M t' - ad_t^T (M t) = w(H, t, time) + (G^T lambda)  with ad*_t = ad_t^T (docs/method.md section 3)
 *   G(H) t = prescribed rate,  g(H, time) = 0.                                                  */

/* Scalar time laws s(t); an applied wrench or a prescribed motion is s(t) times a fixed vector.
 * A law is a leaf (CONSTANT ... CALLBACK) or an expression (EXPR): its `nodes` are leaves and the
 * operators SUM and PRODUCT in postfix order (a b SUM = a + b), evaluated with a stack of at most
 * PHM_LAW_STACK entries, so an expression needs no allocation when evaluated. Every kind gives s
 * and its first two time derivatives (zero where a law is piecewise constant). */
typedef enum {
  PHM_LAW_CONSTANT = 0,  /* s = amplitude                                                  */
  PHM_LAW_STEP = 1,      /* s = amplitude for t >= t0, else 0                              */
  PHM_LAW_PULSE = 2,     /* s = amplitude for t0 <= t < t0 + duration, else 0 ("impulse")  */
  PHM_LAW_SINE = 3,      /* s = offset + amplitude sin(2 pi frequency t + phase)           */
  PHM_LAW_TABLE = 4,     /* piecewise linear through (t_i, s_i), constant outside          */
  PHM_LAW_CYCLOIDAL = 5, /* smooth ramp 0 -> amplitude on [t0, t0 + duration] (C2)          */
  PHM_LAW_LINEAR = 6,    /* s = offset + amplitude t (a ramp; constant speed: angle law)   */
  PHM_LAW_PPOLY = 7,     /* piecewise polynomial (see phm_law.table); outside its breaks the
                          * first or last piece continues (C2 splines: python/phmech/laws.py) */
  PHM_LAW_CALLBACK = 8,  /* s, s', s'' from the caller's function fn(ctx, t, nder, out)       */
  PHM_LAW_EXPR = 9,      /* an expression: nodes[0..nnodes) in postfix order                */
  PHM_LAW_SUM = 10,      /* expression operator: the two entries on top of the stack, added */
  PHM_LAW_PRODUCT = 11   /* expression operator: their product (Leibniz rule for s', s'')   */
} phm_law_kind;

#define PHM_LAW_STACK 16    /* an expression's stack depth, at most                          */
#define PHM_LAW_MAXORDER 8  /* a PPOLY piece's coefficients (degree + 1), at most             */

/* CALLBACK: write s (out[0]) and, for nder >= 1 and 2, s' and s'' (out[1], out[2]) at time t;
 * non-zero return: the law failed (its value is then NaN, which the integrators reject). */
typedef int (*phm_law_fn)(void *ctx, double t, int nder, double out[3]);

typedef struct phm_law {
  int kind;                           /* phm_law_kind                                       */
  double amplitude, t0, duration;     /* see phm_law_kind                                   */
  double frequency, phase, offset;    /* sine: Hz, rad, offset; linear: offset              */
  int ntable;                         /* TABLE: points (>= 1); PPOLY: pieces (>= 1);
                                       * CALLBACK: breakpoints (>= 0)                       */
  const double *table;                /* TABLE: ntable (t, s) pairs, row-major [ntable][2],
                                       * times increasing; PPOLY: ntable + 1 increasing breaks
                                       * x_i, then ntable x order coefficients, c[i][j]
                                       * multiplying (t - x_i)^(order - 1 - j) on [x_i, x_i+1);
                                       * CALLBACK: its breakpoints (times where s, s' or s''
                                       * jumps), increasing                                  */
  int order;                          /* PPOLY: coefficients per piece, 1..PHM_LAW_MAXORDER  */
  phm_law_fn fn;                      /* CALLBACK                                           */
  void *ctx;                          /* CALLBACK: handed to fn                             */
  int nnodes;                         /* EXPR: number of nodes                              */
  const struct phm_law *nodes;        /* EXPR: leaves and SUM/PRODUCT, postfix; no EXPR     */
} phm_law;


typedef struct {
  double M[36];      /* spatial inertia at the carrier frame, body coordinates, kg, kg m, kg m^2 */
  double mass;       /* kg, for gravity (>= 0)                                           */
  double com[3];     /* centre of mass in body coordinates, m                            */
  double H0[16];     /* initial pose                                                      */
  double t0[6];      /* initial body twist (omega, v)                                     */
} phm_carrier_desc;

/* se3 beam element between carriers a (node k) and b (node k+1) (docs/method.md section 4). */
typedef struct {
  int a, b;          /* carrier indices                                                   */
  double h;          /* element length, m                                                 */
  double K[36];      /* section stiffness (symmetric positive definite)                   */
  double D[36];      /* section viscous damping (symmetric positive semidefinite)         */
  double eps_hat[6]; /* unstressed strain (kappa_hat, 1, 0, 0) for the curved/straight shape */
  int mass;          /* phm_element_mass_kind                                             */
  double Ms[36];     /* section inertia per unit length (kg m, kg; as a carrier's M, per metre),
                      * read when mass = PHM_MASS_CONSISTENT                               */
  double Mc[144];    /* mass = PHM_MASS_GIVEN: the coupling itself (symmetric; the nodes'
                      * inertias plus it must be positive definite)                       */
} phm_element_desc;

/* How an element's own kinetic energy reaches its nodes (docs/method.md section 4.2, "Mass").
 * LUMPED: the nodes' inertias carry it -- the builder gives each node h/2 Ms per adjacent element.
 * CONSISTENT: the nodes still carry h/2 Ms each, and the element adds the coupling
 * Mc = M_helix + (h/12) d^T Ms d - diag(h/2 Ms, h/2 Ms) (phm_element_mass) in the body twists of
 * its two nodes: the kinetic energy of its constant-strain (helix) field at the unstressed shape,
 * blended half-way with the lumped one. Constant in the body twists, so the energy balance stays
 * exact; its linearization has no leading dispersion error (docs/mass_matrix_study.md). */
/* GIVEN: the coupling Mc of the description (a reduced link's condensed mass, whose nodes are
 * interface frames: python/phmech/fidelity.py). */
typedef enum { PHM_MASS_LUMPED = 0, PHM_MASS_CONSISTENT = 1, PHM_MASS_GIVEN = 2 } phm_element_mass_kind;

/* A kinetic coupling of two carriers a != b without an element: T_c = 1/2 [t_a; t_b]^T Mc [t_a; t_b]
 * in their body twists, constant, like an element's given mass (its energy balance exact, momentum
 * conserved). A modal link's interior modes couple to its two ends this way: each modal
 * coordinate is carried by a slider frame on the link's start (docs/method.md section 4.10,
 * python/phmech/fidelity.py). The carriers' inertias plus Mc must be positive definite. */
typedef struct {
  int a, b;          /* carrier indices                                                   */
  double Mc[144];    /* symmetric 12 x 12 on [t_a; t_b]                                   */
} phm_coupling_desc;

/* A pair type: a row of THE pair table (csrc/model/pair_types.c, the only place that defines pair
 * types; phm_pair_type(i) returns row i, phm_pair_type_count() the number of rows; Python builds its
 * pair classes from it). Joint axis = local z of both pair frames unless the row says otherwise. */
typedef struct {
  const char *name;          /* lower case, e.g. "revolute"; Python's class is "Revolute"      */
  int m;                     /* constraint rows; k = 6 - m joint coordinates                   */
  const char *params;        /* constructor parameters with defaults, e.g. "axis=z,pitch=0"     */
  const char *units[6];      /* unit of each joint coordinate: "rad" or "m"                   */
  const char *directions[6]; /* name of each constraint-wrench direction (W^C column), in F_b  */
  int drivable;              /* 1: its relative pose can be prescribed (phm_pair_desc.driven)  */
  int xdrivable;             /* bit c: joint coordinate c can follow a law (phm_pair_desc.xdriven):
                              * those whose rate xdot_c = Phi_c^T t_rel is dx_c/dt           */
  const char *doc;           /* one sentence for the docstring (x, xdot and their meaning)     */
  int axes_a, axes_b;        /* bit c: the relative motion that moves joint coordinate c alone
                              * (the twist psi_c with W^C^T psi_c = 0, Phi^T psi_c = e_c) has
                              * a direction fixed in F_a (axes_a), in F_b (axes_b), at every
                              * relative pose: with that frame on the ground, the work of a
                              * dead load along it does not depend on the configuration
                              * (phm_static_free, csrc/analyze/static_free.c)                   */
} phm_pair_type_info;

/* A kinematic pair between frame Ta on carrier a and Tb on carrier b (-1 = ground). Frames
 * F_a = H_a Ta, F_b = H_b Tb; relative pose h = F_a^-1 F_b = (R, p); relative twist
 * t_rel = h^-1 dh/dt (in F_b). A type gives (all in F_b): the allowed directions psi (6 x k), the
 * dual effort basis Phi (psi^T Phi = I), the constraint-wrench basis W^C (6 x m, m = 6 - k),
 * position constraints g(h) (m) with dg = W^C^T t_rel at g = 0, joint coordinates x (k) and
 * rates xdot = Phi^T t_rel. Velocity constraint W^C^T t_rel = prescribed rate; constraint wrench
 * W^C lambda acts on b (in F_b) and equal and opposite on a. Only drivable types (fixed) can be driven
 * by a motion: reference r(t) = exp(law(t) axis), g = log(r^-1 h); a type with joint coordinates
 * can have some of them follow laws instead (xdriven). */
typedef struct {
  int type;          /* row of the pair table (phm_pair_type)                             */
  int a, b;          /* carriers, -1 = ground                                             */
  double Ta[16], Tb[16];
  int driven;        /* 0: r = identity; 1: r(t) = exp(law(t) * axis) (drivable types)      */
  double axis[6];    /* twist direction of the prescribed motion (omega, v)               */
  phm_law law;
  int xdriven;       /* bit c set: joint coordinate c follows xlaw[c] (types whose row has
                      * bit c in xdrivable): one more constraint row x_c - xlaw[c](t) = 0 per
                      * bit, after the type's rows, with W^C column Phi_c (its multiplier is
                      * the driving effort, torque or force, and its power a supplied one)  */
  phm_law xlaw[6];
  double pitch;      /* HELICAL: translation per rotation, m/rad                          */
  int has_x0;        /* 1: x0 gives the initial joint coordinates (checked at start)       */
  double x0[6];      /* initial joint coordinates; also the branch of multi-turn angles   */
  int drop;          /* bit r set: constraint row r of this pair (W^C column r; the type's
                      * rows, then the driven coordinates') is redundant
                      * and left out of the DAE (hyperconstrained mechanisms; see
                      * phm_constraints_full for the whole set). 0: all rows kept.          */
} phm_pair_desc;

/* Actuator on the allowed directions of a pair, generalized effort u (k) power-conjugate to xdot:
 *   EFFORT: u = law(t) vec;
 *   PD:     u = -kp (x - x_set - law(t) vec) - kd (xdot - law'(t) vec)   (elementwise gains);
 *   SPRING: u = -kp (x - x_set) - kd xdot  (joint elasticity; law unused).
 * u enters as the wrench Phi u on b (in F_b) and its opposite on a; its power u . xdot is a port. */
typedef enum { PHM_ACT_EFFORT = 0, PHM_ACT_PD = 1, PHM_ACT_SPRING = 2 } phm_actuator_kind;

typedef struct {
  int pair;          /* pair index                                                        */
  int kind;          /* phm_actuator_kind                                                 */
  double vec[6];     /* first k entries used                                              */
  double kp[6], kd[6], x_set[6];
  phm_law law;
} phm_actuator_desc;

/* Point-to-point spring-damper between point pa of carrier a and pb of carrier b (-1 = ground,
 * points then in world coordinates): tension f = k (d - d0) + c dd/dt, d the distance. */
typedef struct {
  int a, b;
  double pa[3], pb[3]; /* m, carrier (or world) coordinates */
  double k, c, d0;     /* N/m, N s/m, m                       */
} phm_spring_desc;

/* Applied wrench law(t) * w on a carrier at a point (body coordinates) of it; when reaction >= 0
 * the opposite wrench (same line of action, through the same material point of `carrier`) acts on
 * carrier `reaction` (an interaction between two frames); -1: the ground takes it. */
typedef struct {
  int carrier;
  int world;         /* 1: w = (tau, f) in world axes; 0: in body axes                    */
  double point[3];   /* point of application in body coordinates, m                       */
  double w[6];       /* (tau, f), N m and N                                               */
  phm_law law;
  int reaction;      /* carrier taking the opposite wrench, -1 = ground                    */
} phm_load_desc;

/* A component with internal states on one joint coordinate of a pair (docs/method.md section
 * 4.11): a port-Hamiltonian system whose mechanical port is (effort u, rate xdot) of coordinate
 * `coord` of pair `pair` (revolute or prismatic), with states z (their count per kind below) that
 * the DAE integrates after the joint coordinates. u enters as the wrench Phi_c u on b and its
 * opposite on a (as an actuator's); the component's storage, dissipated and supplied power enter
 * the energy ledger (storage with the elastic energy).
 *   VISCOUS  (0 states) u = -c v                                        par: c
 *   COULOMB  (0)        u = -Fc tanh(v / vreg)                          par: Fc, vreg
 *   STRIBECK (0)        u = -g(v) tanh(v / vreg) - s2 v                 par: Fc, Fs, vs, s2, vreg
 *   LUGRE    (1: z)     z' = v - s0 |v| z / g(v), u = -(s0 z + s1 z' + s2 v)
 *                                                                       par: s0, s1, s2, Fc, Fs, vs
 *   MOTOR    (1: i, or 0 with a current input) L i' = V(t) - R i - k n v, u = eta n k i
 *                                                                       par: L, R, k, n, eta, J
 *   LINEAR   (nx: xc) a linear controller on the measurement y = (x - r(t), v) of its own
 *            coordinate or of coordinate scoord of pair spair (any type):
 *                     xc' = A xc + B y, u = C xc + D y      par: A (nx x nx), B (nx x 2), C (nx), D (2)
 *   CALLBACK (0)        u = fn(t, x, v), the caller's function (fn, ctx) of its own coordinate
 *                       and rate, with du/dx, du/dv when asked (nder 1); a source, as LINEAR
 * with v = xdot_c and g(v) = Fc + (Fs - Fc) exp(-(v/vs)^2). A motor's rotor inertia J enters as
 * the reflected inertia J n^2 on the joint (a kinetic coupling, phm_model_create). A linear
 * controller is a source: its power u v is supplied (as an actuator's). */
typedef enum {
  PHM_COMP_VISCOUS = 0, PHM_COMP_COULOMB = 1, PHM_COMP_STRIBECK = 2, PHM_COMP_LUGRE = 3,
  PHM_COMP_MOTOR = 4, PHM_COMP_LINEAR = 5, PHM_COMP_CALLBACK = 6, PHM_COMP_PH = 7,
  PHM_NCOMP_KINDS = 8
} phm_component_kind;
#define PHM_COMP_NPAR 32 /* parameters per component                                       */
#define PHM_COMP_MAXZ 4 /* internal states per component, at most                          */
#define PHM_COMP_PH_MAXZ 2 /* a port-Hamiltonian controller's states: J, R, Q (n x n each),
                            * B (n), d, xc* (n) within PHM_COMP_NPAR                        */

typedef struct {
  int kind;          /* phm_component_kind                                                */
  int pair, coord;   /* the pair and its joint coordinate                                 */
  double par[PHM_COMP_NPAR];
  int input;         /* MOTOR: 0 the law is the voltage V(t) [V], 1 the current i(t) [A]  */
  int nx;            /* LINEAR: its states (0 .. PHM_COMP_MAXZ)                            */
  int spair, scoord; /* LINEAR: the pair and coordinate it measures (spair -1: its own)    */
  phm_law law;       /* MOTOR: its input; LINEAR: the reference r(t); unused otherwise    */
  double z0[PHM_COMP_MAXZ]; /* initial internal states                                    */
  /* CALLBACK: out[0] = u at (t, x, v), and with nder 1 out[1] = du/dx, out[2] = du/dv; non-zero
   * return: failed (u is then NaN, the run fails and the caller reports its function's error) */
  int (*fn)(void *ctx, double t, double x, double v, int nder, double out[3]);
  void *ctx;
} phm_component_desc;

typedef struct {
  int ncarriers;  const phm_carrier_desc *carriers;
  int nelements;  const phm_element_desc *elements;
  int npairs;     const phm_pair_desc *pairs;
  int nloads;     const phm_load_desc *loads;
  double gravity[3]; /* m/s^2, world */
  int nactuators; const phm_actuator_desc *actuators;
  int nsprings;   const phm_spring_desc *springs;
  int ncouplings; const phm_coupling_desc *couplings; /* kinetic couplings without an element */
  int ncomponents; const phm_component_desc *components; /* components with internal states */
} phm_model_desc;

typedef struct phm_model phm_model;

/* What the planar check reads of a scene (phm_planar_check_scene; phm_planar_check fills it from
 * a model): is the motion confined to the plane normal to a world axis k (python/phmech/planar.py
 * says what each check means)? Of the description structs only these fields are read: carriers'
 * M, mass, com; elements' K, D, Ms, Mc, eps_hat; loads' w, point; springs' a, b, pa, pb; pairs'
 * a, b, driven, xdriven (nonzero: some coordinate follows a law); actuators' pair. The constraint
 * rows are given as blocks: row r is nblk blocks of 6 (the columns of carrier Gcar[r nblk + j],
 * -1: an empty block; a carrier in at most one block of a row), G (nrow x nblk x 6). */
typedef struct {
  double gravity[3];
  int nc;                          /* carriers                                              */
  const double *H, *t;             /* nc x 16, nc x 6: the start poses and body twists      */
  const phm_carrier_desc *car;     /* nc                                                    */
  int ne;      const phm_element_desc *el;
  int ncoup;   const double *coupling_Mc;       /* ncoup x 144: couplings without an element */
  int nl;      const phm_load_desc *load;
  int ns;      const phm_spring_desc *spr;
  int na;      const phm_actuator_desc *act;
  int np;      const phm_pair_desc *pair;
  const int *pair_row, *pair_m, *pair_k; /* np each: every pair's first row, rows and joint
                                          * coordinates among the constraint rows below     */
  const char *const *names;        /* np pair names for the messages, or NULL ("pair 3")    */
  int nrow, nblk;
  const double *G;                 /* nrow x nblk x 6                                        */
  const int *Gcar;                 /* nrow x nblk                                            */
} phm_planar_scene;

#define PHM_PLANAR_ZERO 1e-12 /* every planar check: zero up to this times its array's scale */
#define PHM_PLANAR_WHY 512    /* the length of a planar check's message, with its '\0'     */


typedef int (*phm_callback)(void *ctx, double t, int iout); /* non-zero return stops the run */
/* Called during integration at least every PHM_MONITOR_STEPS steps (and at each output): time
 * reached, steps so far, last step [s]. Non-zero return stops the run with PHM_EINTERRUPT. */
typedef int (*phm_monitor)(void *ctx, double t, long nsteps, double h);
#define PHM_MONITOR_STEPS 100

/* Which differential states enter IDA's local error test. CONFIGURATION leaves the carriers'
 * twists out (they stay in the Newton convergence test): the step then follows the accuracy of
 * poses and joint coordinates only, and unresolved fast vibrations are damped by the integrator
 * instead of resolved; it needs a BDF order <= 2 (A-stable), which phm_simulate enforces. */
enum { PHM_ERRTEST_ALL = 0, PHM_ERRTEST_CONFIGURATION = 1 };

/* Time integrators. IDA: variable-order, variable-step BDF with local error control (rtol, atol,
 * error_test, max_*). GALPHA: generalized-alpha for first-order systems (Jansen, Whiting &
 * Hulbert 2000), spectral radius at infinity `rho_inf` in [0, 1] (1: no numerical dissipation;
 * < 1 damps what the step does not resolve); second order, the constraints hold at every step.
 * Fixed step (`adaptive` 0): step `step`, rtol/atol are its Newton tolerances, no error estimate.
 * Variable step (`adaptive` 1): `step` is the first step (<= 0: chosen from the band). The steps
 * resolve the band (band [Hz], the highest frequency to resolve): at least PHM_BAND_MAX_STEPS
 * steps per period of the band's highest frequency, i.e. h <= 1/(PHM_BAND_MAX_STEPS band) (and
 * <= max_step), the first step 1/(PHM_BAND_STEPS band) (or 1e-3 of the span if shorter). The
 * local error estimate of the configuration (poses, joint coordinates; h^3 y'''/12 from the
 * third difference of the poses, seen through a low-pass filter at PHM_FILTER_BAND band when
 * the model has beam elements), per unit step, is kept below rtol |y| + atol: a step above it
 * is redone shorter, down to 1/(PHM_REFINE_MAX PHM_BAND_STEPS band), and one that the estimate
 * allows to be 1.25x longer grows (<= 1.5x). At that limit a step is accepted above the
 * tolerance (counted in nfloor; simulate warns). What lies above the band is damped by rho_inf
 * instead of resolved. Steps land on the output times and the laws' breakpoints (shortened
 * evenly). docs/integrators.md gives the measurements. band <= 0: no window (max_step only). */
#define PHM_BAND_STEPS 20
#define PHM_BAND_MAX_STEPS 12
/* The error estimate's low-pass corner, in bands (galpha_error in csrc/integrate/galpha.c), and
 * how far below the band's floor 1/(PHM_BAND_STEPS band) a step above the tolerance is
 * refined before it is accepted above it (nfloor). */
#define PHM_FILTER_BAND 1.0
#define PHM_REFINE_MAX 1000.0
/* Variable step: Newton's relative tolerance on the differential states is min(rtol, this)
 * (the energy ledger needs it; measurements in csrc/integrate/galpha.c, run_galpha). */
#define PHM_NEWTON_RTOL 1e-7
/* ... tightened down to this while the run's summed error estimates run ahead of their share
 * of the tolerance (csrc/integrate/galpha.c, newton_min; the round-off of a stiff start is
 * ~1e-12 relative) */
#define PHM_NEWTON_RTOL_MIN 1e-11
/* The integrators' codes: the position of each in the table of integrators
 * (csrc/integrate/integrators.c; phm_integrator_name, phm_sim_defaults). */
/* TREE: a tree of rigid bodies in joint coordinates (no elements, loops, prescribed motions or
 * components with states; csrc/integrate/tree_aba.c lists what it takes), its articulated-body
 * dynamics integrated by the explicit Dormand-Prince 5(4) pair with local error control on
 * rtol, atol over the joint coordinates and rates (max_step, max_steps; no other option). */
enum { PHM_INTEGRATOR_IDA = 0, PHM_INTEGRATOR_GALPHA = 1, PHM_INTEGRATOR_TREE = 2 };

/* IDA's own options (phm_sim_options.ida). */
typedef struct {
  int max_order;          /* maximum BDF order 1..5; <= 0: 5                                */
  int error_test;         /* PHM_ERRTEST_ALL or PHM_ERRTEST_CONFIGURATION                   */
} phm_ida_options;

/* The generalized-alpha's own options (phm_sim_options.galpha). */
typedef struct {
  double step, rho_inf;   /* step [s] (> 0; adaptive: the first, <= 0 from the band),
                           * spectral radius at infinity [0, 1]                             */
  int adaptive;           /* 0 fixed step, 1 variable step with error control               */
  double band;            /* adaptive: highest frequency to resolve [Hz]; <= 0: none        */
} phm_galpha_options;

/* A simulation's options: those every integrator reads, then one sub-struct per integrator
 * (read by that integrator only). Fill it by field name (designated initializers; fields not
 * named are 0), or start from phm_sim_defaults(integrator). */
typedef struct {
  double rtol, atol;      /* error tolerances (atol scalar); GALPHA fixed step: Newton's   */
  int linear_solver;      /* 0 dense LU, 1 KLU (both with the closed-form Jacobian) */
  long max_steps;         /* per output interval (IDA and GALPHA); <= 0: 10^6               */
  double max_step;        /* <= 0: no limit                                                 */
  phm_callback interrupt; /* called at each output; non-zero: stop with PHM_EINTERRUPT      */
  phm_callback progress;  /* called at each output; non-zero: stop quietly (PHM_OK)         */
  void *ctx;
  int integrator;         /* PHM_INTEGRATOR_IDA (0), _GALPHA (1) or _TREE (2)               */
  phm_monitor monitor;    /* may be NULL; called with ctx                                   */
  int planar;             /* 0: 3-D; 1, 2, 3: the planar DAE, every carrier moving in the plane
                           * normal to world x, y, z (checked by the caller, who dropped the
                           * out-of-plane constraint rows; csrc/dae/planar.c)              */
  phm_ida_options ida;       /* integrator PHM_INTEGRATOR_IDA                              */
  phm_galpha_options galpha; /* integrator PHM_INTEGRATOR_GALPHA                           */
} phm_sim_options;

/* How phm_modes solves its eigenproblem: dense LAPACK on the reduced problem (O(N^3)), or
 * subspace iteration on the sparse KKT system (O(N) per iteration, its result checked against the
 * count of eigenvalues below its shift: docs/validation.md, finding 9); AUTO: sparse from
 * PHM_SPARSE_MODES_MIN + 6 nmodes carrier coordinates (6 per carrier) on, i.e. from 10 + nmodes
 * carriers, where it becomes the faster (its block, max(2 nmodes, nmodes + 8) vectors, grows with
 * nmodes) -- and only when the constraint manifold has at least twice the block's dimension.
 * Measured (core only, medians; dense / sparse ms), the Table I cantilever of N elements (6 (N + 1)
 * coordinates): 2 modes, N = 10 (66) 0.17 / 0.19, N = 11 (72) 0.22 / 0.21, N = 15 0.47 / 0.27,
 * N = 30 3.3 / 0.54, N = 49 12.1 / 0.88; 5 modes, N = 13 (84) 0.41 / 0.44, N = 14 (90) 0.48 /
 * 0.42, N = 30 3.5 / 0.95, N = 49 12.6 / 1.6; 20 modes, N = 20 (126) 3.3 / 5.6, N = 30 (186)
 * 8.3 / 7.8. A hanging chain of rigid bars (6 per bar; sparse once the manifold fits the block:
 * 20 bars for 2 modes, 26 for 5): 20 bars, 2 modes 1.8 / 0.68; 26 bars, 5 modes 4.7 / 1.3; 60
 * bars 53 / 2.2. The count costs 9-21 % of the sparse path (cantilever, 15-200 elements;
 * benchmarks/modes_crossover.py). */
enum { PHM_MODES_AUTO = 0, PHM_MODES_DENSE = 1, PHM_MODES_SPARSE = 2 };
#define PHM_SPARSE_MODES_MIN 60
/* AUTO: a sparse result that its count does not verify (eigenvalues below its shift that its
 * iteration did not find, or a count that cannot be certified) is redone densely up to this many
 * coordinates on the constraint manifold (dense: 0.15 s at 600, 0.4 s at 900 coordinates;
 * ~O(n^3)); beyond, the spectrum is sliced (csrc/analyze/modes_sparse.c). */
#define PHM_DENSE_MODES_MAX 1500
/* The sparse path's count of eigenvalues below its shift (the KKT matrix's inertia from an
 * LDL' factorization without pivoting, csrc/analyze/linearize.c) is trusted when its certificate
 * ||E||_1 est(||KKT^-1||_1) (E: the factorization's residual) is below this: 1 bounds it in
 * theory, 0.1 leaves a factor 10 for the condition estimate's error. */
#define PHM_INERTIA_CHECK 0.1
/* The dense path's shift-inverted pencil (csrc/analyze/modes.c) gives the modes whose
 * theta = 1/(lambda - sigma) is above this fraction of the first's: relative accuracy ~ eps/this. */
#define PHM_MODES_RESOLVED 1e-6
/* What phm_modes did (its optional `stats`): the path whose modes it returned and, on the
 * sparse path, its subspace iterations (every run: the first, and the spectrum slicing's), how
 * often the first run moved its shift towards the lowest eigenvalue (sparse_reshift,
 * csrc/analyze/modes_sparse.c) and its first and last shifts [(rad/s)^2]. Zeros on the dense
 * path. */
typedef struct {
  int method;     /* PHM_MODES_DENSE or PHM_MODES_SPARSE: the path that gave the modes */
  int iterations; /* subspace iterations of the sparse path                              */
  int reshifts;   /* moves of its shift during the first run                             */
  double shift0;  /* its first shift, -1e-9 tr K / tr M [(rad/s)^2]                      */
  double shift;   /* the shift of its last iteration [(rad/s)^2]                         */
} phm_modes_stats;

/* A port of the linear port-Hamiltonian model (phm_linear_model, docs/method.md section 7.4):
 * the generalized forces per unit input of the joint efforts of pair `index` (k inputs, the
 * pair's joint-coordinate units: N m or N), of load `index`'s wrench per unit of its law (1
 * input), or of a wrench (tau [N m], f [N]) in the axes of the frame T (4x4 offset on carrier
 * `index`) at its origin (6 inputs). Their collocated outputs are the joint rates, the load's
 * power-conjugate velocity and the frame's body twist (omega, v). */
enum { PHM_PORT_PAIR = 0, PHM_PORT_LOAD = 1, PHM_PORT_FRAME = 2 };
typedef struct {
  int kind;    /* PHM_PORT_PAIR, PHM_PORT_LOAD or PHM_PORT_FRAME */
  int index;   /* pair, load or carrier index */
  double T[16]; /* PHM_PORT_FRAME: the frame's offset on its carrier (row-major 4x4) */
} phm_linear_port;

/* The components' part of a linear model (phm_linear_closed_loop; docs/method.md section 7.5):
 * their laws (csrc/model/component.c) linearized at the point, at rest, in the reduced
 * coordinates q of phm_linear_model: with f_c = Z^T (the components' wrenches) their reduced
 * generalized forces and z (nz) their states, d f_c = -Kc dq - Dc dq' + Kz dz and
 * dz' = Fq dq + Fv dq' + Fz dz. Caller-allocated, row-major: Kc, Dc with room for (6 nc)^2
 * values, Kz for 6 nc x nz, Fq, Fv for nz x 6 nc, Fz nz x nz; f, fc: 6 nc (Z^T of all the
 * generalized forces at the point, the mechanism's and the components', and the components'
 * alone: the rest residual), zdot: nz (the states' rates there). z: the states at the point
 * (NULL: the components' initial states). */
typedef struct {
  const double *z;
  double *Kc, *Dc, *Kz, *Fq, *Fv, *Fz, *f, *fc, *zdot;
  double *G; /* nr x nr (room for (6 nc)^2; may be NULL): a steady rotation's gyroscopic matrix
              * (phm_model_set_spin; zero without): M q'' + (D + G) q' + K q = 0 */
  double fmax; /* out: the largest entry of the carriers' wrenches at the point (f's scale) */
} phm_linear_components;

/* A motion of a mechanism that nothing resists and on which the loads do work at a rate that is
 * the same in every configuration (phm_static_free, csrc/analyze/static_free.c): then the
 * mechanism has no static equilibrium under those loads. Either the side of a pair away from the
 * ground moving along one of the pair's joint coordinates (pair >= 0), or a part held by nothing
 * (no pair, element, spring or interaction links it to the ground: pair = -1) moving rigidly. */
typedef struct {
  int pair;         /* the pair, or -1: a part held by nothing                                */
  int coord;        /* the joint coordinate it moves (pair >= 0), else -1                     */
  int carrier;      /* a carrier of the moving part: the pair's carrier on that side, or the
                     * part's first carrier                                                   */
  double twist[6];  /* the motion per unit of the coordinate (per rad or m), a world twist
                     * (omega, v) at the poses given                                          */
  double force;     /* the generalized force along it at load factor 1 (the loads' work per
                     * unit: N m per rad, N per m); never 0                                    */
  double gravity;   /* its parts: gravity's, the pair's actuators' (both at load factor 1);
                     * the applied wrenches' are load_work's (phm_static_free)               */
  double effort;
  double mass;      /* of the moving part, kg                                                 */
} phm_free_motion;

#define PHM_NENERGY 7 /* kinetic, elastic, gravity, dissipated, supplied, total, ledger residual */

/* The result quantities (PHM_RESULT_FIELDS) and a simulation's output, phm_sim_output. */
#include "phmech_results.h"

/* ---------------------------------------------------------------- code tables (csrc/util/codes.c) */
/* One named value of an enum (name lower case, as the enum's). */
typedef struct {
  const char *name;
  int value;
} phm_code;

/* A named table of codes: "law_kinds", "integrators", "actuator_kinds", "mass_kinds",
 * "result_fields" (the pair types: phm_pair_type). */
typedef struct {
  const char *name;
  const phm_code *rows;
  int nrows;
} phm_code_table;

#endif /* PHMECH_TYPES_H */
