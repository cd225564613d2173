/* phmech.h -- the public C API of phmech, one section per concept.
 *
 * Conventions (DESIGN.md section 3):
 *   - every matrix is a row-major (C-ordered) array of doubles: a 3x3 is double[9],
 *     a 4x4 homogeneous pose is double[16], a 6x6 is double[36];
 *   - twist t = (omega, v), wrench w = (tau, f): angular part first;
 *   - pose H = [[R, p], [0, 1]]; body-frame twist: H^-1 dH/dt = hat(t);
 *   - ad_t = [[hat(w), 0], [hat(v), hat(w)]],  Ad_H = [[R, 0], [hat(p) R, R]];
 *     the duals ad*_t := ad_t^T and Ad*_H := Ad_H^T act on wrenches;
 *   - dexp_X = sum_k ad_X^k / (k+1)!, so that H = H0 exp(hat X) gives H^-1 dH/dt = dexp_{-X} dX/dt;
 *   - quaternions are scalar first: q = (w, x, y, z), unit norm.
 * The library never prints, exits or aborts: functions that can fail return a phm_status and
 * leave a message in a phm_error.
 */
#ifndef PHMECH_H
#define PHMECH_H

#include <stddef.h>

#define PHM_VERSION "0.1.0"

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
} phm_error;

/* Record code and a printf-style message in err (err may be NULL); returns code. */
phm_status phm_error_set(phm_error *err, phm_status code, const char *fmt, ...);
/* Reset err to PHM_OK with an empty message. */
void phm_error_clear(phm_error *err);

/* ---------------------------------------------------------------- so(3) / SO(3) */
void phm_so3_hat(const double w[3], double W[9]);        /* W = hat(w), W x = w cross x   */
void phm_so3_vee(const double W[9], double w[3]);        /* inverse of hat (skew part)    */
void phm_so3_exp(const double w[3], double R[9]);        /* Rodrigues, series near 0      */
void phm_so3_log(const double R[9], double w[3]);        /* |w| in [0, pi], robust near pi */
void phm_so3_jac(const double w[3], double A[9]);        /* sum_k hat(w)^k/(k+1)! (left Jacobian) */
void phm_so3_jac_inv(const double w[3], double Ai[9]);   /* inverse of phm_so3_jac, |w| < 2 pi */

/* ---------------------------------------------------------------- se(3) / SE(3) */
void phm_se3_hat(const double x[6], double X[16]);       /* 4x4 matrix of twist coordinates */
void phm_se3_vee(const double X[16], double x[6]);
void phm_se3_exp(const double x[6], double H[16]);
void phm_se3_log(const double H[16], double x[6]);       /* |omega| in [0, pi]               */
void phm_se3_compose(const double A[16], const double B[16], double AB[16]);
void phm_se3_inverse(const double H[16], double Hi[16]);
void phm_se3_Ad(const double H[16], double A[36]);       /* Ad_H                          */
void phm_se3_Ad_dual(const double H[16], double A[36]);  /* Ad*_H = Ad_H^T (wrenches)      */
void phm_se3_ad(const double x[6], double a[36]);        /* ad_x                          */
void phm_se3_ad_dual(const double x[6], double a[36]);   /* ad*_x = ad_x^T                 */
void phm_se3_dexp(const double x[6], double D[36]);      /* sum_k ad_x^k/(k+1)!            */
void phm_se3_dexp_inv(const double x[6], double Di[36]); /* its inverse, |omega| < 2 pi    */
void phm_se3_log_dexp_inv(const double H[16], double x[6], double Ai[9], double L[9]); /* x = log H, dexp_x^-1 = [[Ai,0],[L,Ai]]; dexp_{-x}^-1 = [[Ai^T,0],[L^T,Ai^T]] */

/* ---------------------------------------------------------------- quaternions */
void phm_quat_to_rot(const double q[4], double R[9]);    /* q need not be normalized       */
void phm_quat_from_rot(const double R[9], double q[4]);  /* Shepperd; returns q with w >= 0 */

/* ---------------------------------------------------------------- mixed finite element (beam_mixed.c) */
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

/* Validate the parameters (finite, positive, N in range, alpha in [0, 1)). */
phm_status phm_mixed_check(const phm_mixed_beam *beam, phm_error *err);
/* Parse "clamped-free", "clamped-clamped", "pinned-pinned", "clamped-pinned". */
phm_status phm_mixed_bc_from_name(const char *name, phm_mixed_bc *bc, phm_error *err);
/* For each of the four ports of u: 0 = input set to zero, 1 = output constrained to zero. */
void phm_mixed_bc_ports(phm_mixed_bc bc, int constrained[4]);
/* One element of length h, ports u = (v_a, omega_a, Qs_b, M_b), y = (-Qs_a, -M_a, v_b, omega_b):
 * J, Q, B, D are 4x4 (Q diagonal, stored full). */
phm_status phm_mixed_element(double h, double EI, double kGA, double rhoA, double rhoI,
                             double alpha, double J[16], double Q[16], double B[16], double D[16],
                             phm_error *err);
/* The chain of N elements interconnected through their node ports (any output may be NULL). */
phm_status phm_mixed_assemble(const phm_mixed_beam *beam, double *J, double *Q, double *B,
                              double *D, phm_error *err);
/* The first n natural frequencies [rad/s], ascending, of the beam under bc, 1 <= n <= 2N: the
 * positive imaginary parts of the eigenvalues of Q^1/2 J Q^1/2 on the constraint subspace,
 * computed as singular values (LAPACK dgesvd) of its momentum-strain block; zero frequencies of
 * rigid-body or constraint modes are skipped. */
phm_status phm_mixed_frequencies(const phm_mixed_beam *beam, phm_mixed_bc bc, int n, double *omega,
                                 phm_error *err);


/* ---------------------------------------------------------------- model, simulation, modes (model.c) */

/* A model is built once from flat descriptions (copied; the caller may free them afterwards) and
 * is immutable. Carriers are rigid bodies and beam nodes alike: a frame with a 6x6 spatial inertia
 * M (body coordinates, centre of mass may be offset), the mass and centre of mass used for
 * gravity, an initial pose H0 and body twist t0. Carrier state: unit quaternion q (scalar first),
 * world position p, body twist t = (omega, v). Equations of motion (DESIGN section 6, GGL form):
 *   q' = 1/2 q (x) (omega + dw),  p' = R (v + dv)        with (dw, dv) = this carrier's (G^T mu)
 *   M t' - ad_t^T (M t) = w(H, t, time) + (G^T lambda)  with ad*_t = ad_t^T (DESIGN section 3)
 *   G(H) t = prescribed rate,  g(H, time) = 0.                                                  */

/* Scalar time laws s(t); an applied wrench or a prescribed motion is s(t) times a fixed vector. */
typedef enum {
  PHM_LAW_CONSTANT = 0,  /* s = amplitude                                                  */
  PHM_LAW_STEP = 1,      /* s = amplitude for t >= t0, else 0                              */
  PHM_LAW_PULSE = 2,     /* s = amplitude for t0 <= t < t0 + duration, else 0 ("impulse")  */
  PHM_LAW_SINE = 3,      /* s = offset + amplitude sin(2 pi frequency t + phase)           */
  PHM_LAW_TABLE = 4,     /* piecewise linear through (t_i, s_i), constant outside          */
  PHM_LAW_CYCLOIDAL = 5  /* smooth ramp 0 -> amplitude on [t0, t0 + duration] (C2)          */
} phm_law_kind;

typedef struct {
  int kind;                           /* phm_law_kind                                       */
  double amplitude, t0, duration;     /* see phm_law_kind                                   */
  double frequency, phase, offset;    /* sine: Hz, rad, offset                              */
  int ntable;                         /* table: number of points (>= 1), times increasing   */
  const double *table;                /* table: ntable (t, s) pairs, row-major [ntable][2]   */
} phm_law;

/* s(t) and its first two derivatives (ds, dds may be NULL). The piece of a piecewise law is
 * chosen by tref (a time inside the current breakpoint interval), its formula evaluated at t. */
double phm_law_eval(const phm_law *law, double t, double tref, double *ds, double *dds);

typedef struct {
  double M[36];      /* spatial inertia at the carrier frame, body coordinates, kg, kg m, kg m^2 */
  double mass;       /* kg, for gravity                                                  */
  double com[3];     /* centre of mass in body coordinates, m                            */
  double H0[16];     /* initial pose                                                      */
  double t0[6];      /* initial body twist (omega, v)                                     */
} phm_carrier_desc;

/* se3 beam element between carriers a (node k) and b (node k+1) (DESIGN section 4). */
typedef struct {
  int a, b;          /* carrier indices                                                   */
  double h;          /* element length, m                                                 */
  double K[36];      /* section stiffness (symmetric positive definite)                   */
  double D[36];      /* section viscous damping (symmetric positive semidefinite)         */
  double eps_hat[6]; /* unstressed strain (kappa_hat, 1, 0, 0) for the curved/straight shape */
} phm_element_desc;

typedef enum {
  PHM_PAIR_FIXED = 0,       /* k = 0: relative pose = r(t) (identity unless driven)           */
  PHM_PAIR_REVOLUTE = 1,    /* k = 1: rotation about z; x = angle [rad] (multi-turn)           */
  PHM_PAIR_PRISMATIC = 2,   /* k = 1: translation along z; x = displacement [m]                */
  PHM_PAIR_HELICAL = 3,     /* k = 1: screw about z, p_z = pitch * angle; x = angle [rad]      */
  PHM_PAIR_CYLINDRICAL = 4, /* k = 2: x = (angle about z, displacement along z)                */
  PHM_PAIR_UNIVERSAL = 5,   /* k = 2: h = Rx(x0) Ry(x1): first axis x of F_a, second y of F_b  */
  PHM_PAIR_SPHERICAL = 6,   /* k = 3: x = rotation vector log(R) [rad]; xdot = omega (F_b)     */
  PHM_PAIR_PLANAR = 7,      /* k = 3: normal z; x = (angle, p_x, p_y) with p in F_a            */
  PHM_PAIR_FREE = 8         /* k = 6: x = (log R, p in F_a); xdot = (omega in F_b, dp/dt in F_a) */
} phm_pair_type;

/* A kinematic pair between frame Ta on carrier a and Tb on carrier b (-1 = ground). Frames
 * F_a = H_a Ta, F_b = H_b Tb; relative pose h = F_a^-1 F_b = (R, p); relative twist
 * t_rel = h^-1 dh/dt (in F_b). A type gives (all in F_b): the allowed directions psi (6 x k), the
 * dual effort basis Phi (psi^T Phi = I), the constraint-wrench basis W^C (6 x m, m = 6 - k),
 * position constraints g(h) (m) with dg = W^C^T t_rel at g = 0, joint coordinates x (k) and
 * rates xdot = Phi^T t_rel. Velocity constraint W^C^T t_rel = prescribed rate; constraint wrench
 * W^C lambda acts on b (in F_b) and equal and opposite on a. Only FIXED pairs can be driven:
 * reference r(t) = exp(law(t) axis), g = log(r^-1 h). */
typedef struct {
  int type;          /* phm_pair_type                                                     */
  int a, b;          /* carriers, -1 = ground                                             */
  double Ta[16], Tb[16];
  int driven;        /* 0: r = identity; 1: r(t) = exp(law(t) * axis) (FIXED only)         */
  double axis[6];    /* twist direction of the prescribed motion (omega, v)               */
  phm_law law;
  double pitch;      /* HELICAL: translation per rotation, m/rad                          */
  int has_x0;        /* 1: x0 gives the initial joint coordinates (checked at start)       */
  double x0[6];      /* initial joint coordinates; also the branch of multi-turn angles   */
  int drop;          /* bit r set: constraint row r of this type (W^C column r) is redundant
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

typedef struct {
  int ncarriers;  const phm_carrier_desc *carriers;
  int nelements;  const phm_element_desc *elements;
  int npairs;     const phm_pair_desc *pairs;
  int nloads;     const phm_load_desc *loads;
  double gravity[3]; /* m/s^2, world */
  int nactuators; const phm_actuator_desc *actuators;
  int nsprings;   const phm_spring_desc *springs;
} phm_model_desc;

typedef struct phm_model phm_model;

/* Validate and copy a description into a new model (*out); free with phm_model_free. */
phm_status phm_model_create(const phm_model_desc *desc, phm_model **out, phm_error *err);
void phm_model_free(phm_model *model);
int phm_model_ncarriers(const phm_model *model);
int phm_model_nconstraints(const phm_model *model);   /* rows of G (lambda's length)      */
int phm_model_npairs(const phm_model *model);
int phm_model_njoints(const phm_model *model);        /* joint coordinates, all pairs (sum of k) */
int phm_model_nports(const phm_model *model);         /* ports: actuators, loads, springs, in order */
/* First constraint row, constraint rows m, first joint coordinate and k of pair ip. */
void phm_model_pair_layout(const phm_model *model, int ip, int *row, int *m, int *joint, int *k);

/* ---- topology helpers (owner: graphs/initial configuration) ----
 * All constraint rows of every pair type, including the rows dropped as redundant (phm_pair_desc
 * drop), at poses H (nc x 16), joint branch references xs (nj; NULL: x0) and time: g (nfull),
 * G (nfull x 6nc, row-major), W (npairs x 36: each pair's full W^C, frame F_b, first m columns
 * used); any output may be NULL. nfull = sum over pairs of the type's constraint count. */
int phm_model_nconstraints_full(const phm_model *model);
void phm_constraints_full(const phm_model *model, const double *H, const double *xs, double time,
                          double *g, double *G, double *W);
/* Joint coordinates x (nj) of every pair at poses H, angles on the branch of xs (NULL: x0). */
void phm_model_joints(const phm_model *model, const double *H, const double *xs, double *x);

/* Energies at poses H (nc x 16) and twists t (nc x 6): e[0] kinetic, e[1] elastic (beam elements
 * and point-to-point springs; not joint springs, whose power is a port), e[2] gravity. */
void phm_model_energy(const phm_model *model, const double *H, const double *t, double e[3]);

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
 * resolve the band (band [Hz], the highest frequency to resolve): between PHM_BAND_MAX_STEPS and
 * PHM_BAND_STEPS steps per period of the band's highest frequency, i.e. in [1/(PHM_BAND_STEPS
 * band), 1/(PHM_BAND_MAX_STEPS band)] (and <= max_step). Within that window the local error
 * estimate of the configuration (poses, joint coordinates; h^3 y'''/12 from the third
 * difference of the poses) is kept below rtol |y| + atol: a step above it is redone shorter,
 * and one that the estimate allows to be 1.25x longer grows (<= 1.5x). At the window's floor a
 * step is accepted even above the tolerance (counted in nfloor): what lies above the band is
 * damped by rho_inf instead of resolved. Steps land on the output times and the laws'
 * breakpoints (shortened evenly). docs/integrators.md gives the measurements behind the window.
 * band <= 0: no window (max_step only). */
#define PHM_BAND_STEPS 20
#define PHM_BAND_MAX_STEPS 12
/* Variable step: Newton's relative tolerance on the differential states is min(rtol, this)
 * (the energy ledger needs it; measurements in csrc/dae.c, run_galpha). */
#define PHM_NEWTON_RTOL 1e-7
enum { PHM_INTEGRATOR_IDA = 0, PHM_INTEGRATOR_GALPHA = 1 };

typedef struct {
  double rtol, atol;      /* IDA tolerances (atol scalar)                                  */
  int linear_solver;      /* 0 dense (IDA difference-quotient Jacobian), 1 KLU (coloured FD) */
  long max_steps;         /* per output interval (IDA and GALPHA); <= 0: 10^6               */
  double max_step;        /* <= 0: no limit                                                 */
  int max_order;          /* maximum BDF order 1..5; <= 0: 5                                */
  int error_test;         /* PHM_ERRTEST_ALL or PHM_ERRTEST_CONFIGURATION                   */
  phm_callback interrupt; /* called at each output; non-zero: stop with PHM_EINTERRUPT      */
  phm_callback progress;  /* called at each output; non-zero: stop quietly (PHM_OK)         */
  void *ctx;
  int integrator;         /* PHM_INTEGRATOR_IDA (0) or PHM_INTEGRATOR_GALPHA                */
  double step, rho_inf;   /* GALPHA: step [s] (> 0), spectral radius at infinity [0, 1]     */
  int adaptive;           /* GALPHA: 0 fixed step, 1 variable step with error control       */
  double band;            /* GALPHA adaptive: highest frequency to resolve [Hz]; <= 0: none */
  phm_monitor monitor;    /* may be NULL; called with ctx                                   */
} phm_sim_options;

#define PHM_NENERGY 7 /* kinetic, elastic, gravity, dissipated, supplied, total, ledger residual */

/* Caller-allocated output for nout times (arrays may be NULL to skip). */
typedef struct {
  const int *record; /* carriers stored in poses/twists, in this order; NULL: all, nrecord = nc */
  int nrecord;
  double *poses;   /* [nout][nrecord][16]                              */
  double *twists;  /* [nout][nrecord][6]                               */
  double *lambda;  /* [nout][nconstraints]                             */
  double *energy;  /* [nout][PHM_NENERGY]                              */
  double *joints;  /* [nout][njoints] joint coordinates x              */
  double *jrates;  /* [nout][njoints] joint rates xdot                 */
  double *efforts; /* [nout][njoints] sum of the actuators' efforts u  */
  double *pwrench; /* [nout][npairs][6] constraint wrench W^C lambda on b, frame F_b */
  double *ports;   /* [nout][nports] energy supplied through each port, J (actuators: int u.xdot;
                    * loads: int w.t; springs: minus the dissipated energy)              */
  int nout_done;   /* outputs filled                                    */
  long nsteps, nres, njac, nniters, netf, nncf; /* IDA statistics      */
  long nfloor;     /* adaptive GALPHA: steps accepted at the band floor above the tolerance */
  double err_est;  /* adaptive GALPHA: sum over steps of the max-norm local error estimate of
                    * the configuration (m, rad-like units): a bound of the global error
                    * without error propagation                                       */
  double last_step; int last_order;             /* IDA's last step [s] and BDF order */
  double wall_time;                             /* seconds             */
} phm_sim_output;

/* Integrate from tout[0] (initial poses/twists: poses0/twists0, or the model's H0/t0 if NULL),
 * after a consistent-initial-value projection, and sample at the increasing times tout[0..nout).
 * An output with a non-finite value stops the run with PHM_ESOLVER (out->nout_done counts only
 * the finite outputs before it). */
phm_status phm_simulate(const phm_model *model, const double *poses0, const double *twists0,
                        const double *tout, int nout, const phm_sim_options *opt,
                        phm_sim_output *out, phm_error *err);

/* Linearized modes at poses (NULL: H0) with constraint wrenches lambda (NULL: zero), loads at
 * `time`: nmodes lowest omega (rad/s), damping ratios zeta, shapes [nmodes][nc][6] (tangent
 * coordinates, mass-normalized); *nfound = modes returned (<= nmodes, limited by the free DOF).
 * A non-finite linearization or result is PHM_ESOLVER, never returned. */
phm_status phm_modes(const phm_model *model, const double *poses, const double *lambda,
                     double time, int nmodes, double *omega, double *zeta, double *shapes,
                     int *nfound, phm_error *err);

/* Static equilibrium under the loads and gravity at `time`, scaled from 0 to 1 in `steps` load
 * steps (halved on failure); Newton with dense LU. poses: start (NULL: H0); results in poses_out
 * (nc x 16) and lambda_out (nconstraints); *iters = total Newton iterations. */
phm_status phm_static(const phm_model *model, const double *poses, double time, int steps,
                      double tol, double *poses_out, double *lambda_out, int *iters,
                      phm_error *err);

#endif /* PHMECH_H */
