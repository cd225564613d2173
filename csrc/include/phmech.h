/* phmech.h -- the public C API of phmech: a table of contents, one line per function, in the
 * order of the data path (docs/architecture.md):
 *   description (phm_model_desc) -> model (immutable, csrc/model/) -> per-evaluation data and
 *   the DAE residual/Jacobian (csrc/dae/) -> integrators (csrc/integrate/) or analyses:
 *   linearization, modes, statics (csrc/analyze/) -> results (caller-allocated arrays).
 * The types, their units and conventions are in phmech_types.h. The library never prints, exits
 * or aborts: a function that can fail returns a phm_status and leaves a message in a phm_error. */
#ifndef PHMECH_H
#define PHMECH_H

#include "phmech_types.h"

/* PHM_VERSION, the version string, is defined by meson.build from its project() version (the one
 * place it is written). */
#ifndef PHM_VERSION
#error "PHM_VERSION is defined by meson.build (-DPHM_VERSION=...)"
#endif

/* ---------------------------------------------------------------- errors (csrc/util/error.c) */
phm_status phm_error_set(phm_error *err, phm_status code, const char *fmt, ...); /* record code and message; returns code */
void phm_error_clear(phm_error *err);                                             /* PHM_OK, empty message            */

/* ---------------------------------------------------------------- SO(3), SE(3), quaternions (csrc/util/se3.c, quat.c, se3_dexp_partials.c) */
void phm_so3_hat(const double w[3], double W[9]);        /* W = hat(w), W x = w cross x          */
void phm_so3_vee(const double W[9], double w[3]);        /* inverse of hat (skew part)           */
void phm_so3_exp(const double w[3], double R[9]);        /* Rodrigues, series near 0             */
void phm_so3_log(const double R[9], double w[3]);        /* |w| in [0, pi], robust near pi       */
void phm_so3_jac(const double w[3], double A[9]);        /* sum_k hat(w)^k/(k+1)! (left Jacobian) */
void phm_so3_jac_inv(const double w[3], double Ai[9]);   /* inverse of phm_so3_jac, |w| < 2 pi   */
void phm_se3_hat(const double x[6], double X[16]);       /* 4x4 matrix of twist coordinates      */
void phm_se3_vee(const double X[16], double x[6]);       /* inverse of hat                       */
void phm_se3_exp(const double x[6], double H[16]);
void phm_se3_log(const double H[16], double x[6]);       /* |omega| in [0, pi]                   */
void phm_se3_compose(const double A[16], const double B[16], double AB[16]);
void phm_se3_inverse(const double H[16], double Hi[16]);
void phm_se3_Ad(const double H[16], double A[36]);       /* Ad_H                                 */
void phm_se3_Ad_dual(const double H[16], double A[36]);  /* Ad*_H = Ad_H^T (wrenches)            */
void phm_se3_ad(const double x[6], double a[36]);        /* ad_x                                 */
void phm_se3_ad_dual(const double x[6], double a[36]);   /* ad*_x = ad_x^T                       */
void phm_se3_dexp(const double x[6], double D[36]);      /* sum_k ad_x^k/(k+1)!                  */
void phm_se3_dexp_inv(const double x[6], double Di[36]); /* its inverse, |omega| < 2 pi          */
void phm_se3_log_dexp_inv(const double H[16], double x[6], double Ai[9], double L[9]); /* x = log H, dexp_x^-1 = [[Ai,0],[L,Ai]], dexp_{-x}^-1 = [[Ai^T,0],[L^T,Ai^T]] */
void phm_se3_dexp_inv_partials(const double x[6], double dAi[6][9], double dL[6][9]); /* d/dx_k of those blocks Ai, L (closed form) */
void phm_quat_to_rot(const double q[4], double R[9]);    /* q need not be normalized             */
void phm_quat_from_rot(const double R[9], double q[4]);  /* Shepperd; returns q with w >= 0      */

/* ---------------------------------------------------------------- time laws (csrc/util/law.c) */
/* s(t) and its first two derivatives (ds, dds may be NULL); the piece of a piecewise law is
 * chosen by tref (a time inside the current breakpoint interval), its formula evaluated at t. */
double phm_law_eval(const phm_law *law, double t, double tref, double *ds, double *dds);
/* PHM_OK, or PHM_EINVAL naming `what idx` (e.g. "pair 3") and the bad parameter: check a law
 * before evaluating it (phm_model_create checks every law of a description). */
phm_status phm_law_check(const phm_law *law, const char *what, int idx, phm_error *err);

/* ---------------------------------------------------------------- code tables (csrc/util/codes.c) */
int phm_code_table_count(void);                                  /* number of code tables          */
const phm_code_table *phm_code_table_at(int i);                  /* table i; NULL if out of range   */
const phm_code_table *phm_code_table_named(const char *name);    /* by name ("law_kinds"); NULL if unknown */

/* ---------------------------------------------------------------- mixed finite element (csrc/model/mixed.c) */
phm_status phm_mixed_check(const phm_mixed_beam *beam, phm_error *err);                  /* finite, positive, N in range, alpha in [0, 1) */
phm_status phm_mixed_bc_from_name(const char *name, phm_mixed_bc *bc, phm_error *err);   /* "clamped-free", "clamped-clamped", "pinned-pinned", "clamped-pinned" */
void phm_mixed_bc_ports(phm_mixed_bc bc, int constrained[4]);                            /* per port of u: 0 input = 0, 1 output = 0 */
phm_status phm_mixed_element(double h, double EI, double kGA, double rhoA, double rhoI,  /* one element's J, Q, B, D (4x4) */
                             double alpha, double J[16], double Q[16], double B[16], double D[16],
                             phm_error *err);
phm_status phm_mixed_assemble(const phm_mixed_beam *beam, double *J, double *Q, double *B, /* the chain (outputs may be NULL) */
                              double *D, phm_error *err);
/* The first n natural frequencies [rad/s], ascending, 1 <= n <= 2N: the positive imaginary parts
 * of the eigenvalues of Q^1/2 J Q^1/2 on the constraint subspace, as singular values (LAPACK
 * dgesvd) of its momentum-strain block; zero frequencies of rigid-body or constraint modes are
 * skipped. */
phm_status phm_mixed_frequencies(const phm_mixed_beam *beam, phm_mixed_bc bc, int n, double *omega,
                                 phm_error *err);

/* ---------------------------------------------------------------- the model (csrc/model/model.c) */
phm_status phm_model_create(const phm_model_desc *desc, phm_model **out, phm_error *err); /* validate and copy; free with phm_model_free */
void phm_model_free(phm_model *model);
int phm_model_ncarriers(const phm_model *model);
int phm_model_nconstraints(const phm_model *model);   /* rows of G (lambda's length)             */
int phm_model_npairs(const phm_model *model);
int phm_model_nelements(const phm_model *model);      /* se3 beam elements                       */
int phm_model_njoints(const phm_model *model);        /* joint coordinates, all pairs (sum of k) */
int phm_model_nports(const phm_model *model);         /* ports: actuators, loads, springs, in order */
int phm_model_ncompstates(const phm_model *model);    /* components' internal states, all (section 4.11) */
int phm_model_nloads(const phm_model *model);         /* applied wrenches and interactions       */
void phm_model_pair_layout(const phm_model *model, int ip, int *row, int *m, int *joint, int *k); /* first row, rows, first joint coordinate, k of pair ip */
/* Reset the initial poses H0 (nc x 16), twists t0 (nc x 6; NULL: keep), joint coordinates x0
 * (npairs x 6; NULL: keep; they become branch references only for pairs created with has_x0)
 * and redundant-row masks drop (npairs; NULL: keep) of a model without rebuilding it (the loop
 * closure changes only these). */
phm_status phm_model_set_initial(phm_model *model, const double *H0, const double *t0,
                                 const double *x0, const int *drop, phm_error *err);
/* The analyses (statics, modes, the linear model; not simulate) about a steady rotation with the
 * world twist S (omega [rad/s], v [m/s] at the world origin; zero: none), in the frame that turns
 * with it (docs/method.md section 7.6): every carrier's motion s_c = Ad_{H_c^-1} S adds the
 * centrifugal wrenches ad*_{s_c} (M s)_c to the forces and their stiffness to the tangent, and
 * the linear model gets the gyroscopic (Coriolis) matrix (phm_linear_components.G). */
phm_status phm_model_set_spin(phm_model *model, const double S[6], phm_error *err);

/* ---------------------------------------------------------------- pairs (csrc/model/pair_types.c, pair.c) */
int phm_pair_type_count(void);                                   /* number of pair types          */
const phm_pair_type_info *phm_pair_type(int type);               /* the pair table: names, k, m, units, directions; NULL if unknown */
/* Relative pose h (4x4) of a pair type's frames at joint coordinates x (k of them). */
void phm_pair_type_pose(int type, double pitch, const double *x, double h[16]);
/* Joint coordinates x (k) of a relative pose h, angles nearest xref (NULL: principal values). */
void phm_pair_type_coordinates(int type, double pitch, const double h[16], const double *xref, double *x);
int phm_model_nconstraints_full(const phm_model *model);      /* rows before dropping redundant ones */
/* All constraint rows, dropped ones included, at poses H (nc x 16), joint branch references xs
 * (nj; NULL: x0) and time: g (nfull), G (nfull x 6nc, row-major), W (npairs x 36: each pair's
 * full W^C in F_b, first m columns used); any output may be NULL. */
void phm_constraints_full(const phm_model *model, const double *H, const double *xs, double time,
                          double *g, double *G, double *W);
void phm_model_joints(const phm_model *model, const double *H, const double *xs, double *x); /* joint coordinates (nj) at poses H */

/* ---------------------------------------------------------------- elements (csrc/model/element.c) */
/* Stress resultants sigma = K (eps - eps_hat) + D eps' (6 per element, body frame of node a's
 * element chart) of every element at poses H (nc x 16) and twists t (nc x 6; NULL: no damping part). */
void phm_model_stress_resultants(const phm_model *model, const double *H, const double *t, double *sigma);
/* The mass coupling Mc (12 x 12, row-major, symmetric) a PHM_MASS_CONSISTENT element of length h,
 * section inertia Ms (per unit length) and unstressed strain eps_hat adds in the body twists
 * (t_a, t_b) of its nodes (phmech_types.h, phm_element_mass_kind): kinetic energy 1/2 t^T Mc t. */
void phm_element_mass(double h, const double Ms[36], const double eps_hat[6], double Mc[144]);

/* ---------------------------------------------------------------- energy (csrc/model/energy.c) */
/* e[0] kinetic, e[1] elastic (elements and point-to-point springs; joint springs are ports),
 * e[2] gravity, at poses H (nc x 16) and twists t (nc x 6). */
void phm_model_energy(const phm_model *model, const double *H, const double *t, double e[3]);

/* ---------------------------------------------------------------- planar scenes (csrc/model/planarity.c) */
/* Is the scene planar about world axis k (0, 1, 2: the plane's normal) at its start? PHM_OK with
 * why = "" when it is, drop (np, may be NULL) then its out-of-plane rows per pair (bits, as
 * phm_planar_rows); else why = the first check that fails, in words (python/phmech/planar.py).
 * PHM_EINVAL for a malformed scene (an index out of range). No allocation. */
phm_status phm_planar_check_scene(const phm_planar_scene *scene, int k, int *drop,
                                  char why[PHM_PLANAR_WHY], phm_error *err);
/* drop (np): per pair, the bits of its rows without an in-plane component about axis k. */
phm_status phm_planar_rows(const phm_planar_scene *scene, int k, int *drop, phm_error *err);
/* The same for a model at poses H (nc x 16) and body twists t (nc x 6), its pairs' rows there
 * (every row, dropped ones too; joint references x0, time 0), names: np pair names or NULL. The
 * axes are tried in the order z, y, x: *axis = the first the scene is planar about, drop (np)
 * its out-of-plane rows; or -1, with why[k] the first failing check about each axis k. */
phm_status phm_planar_check(const phm_model *model, const double *H, const double *t,
                            const char *const *names, int *axis, int *drop,
                            char why[3][PHM_PLANAR_WHY], phm_error *err);

/* ---------------------------------------------------------------- simulation (csrc/integrate/simulate.c) */
/* Integrate from tout[0] (initial poses/twists: poses0/twists0, or the model's H0/t0 if NULL)
 * after a consistent-initial-value projection, sampling at the increasing times tout[0..nout);
 * the integrator opt->integrator of the table of integrators (csrc/integrate/integrators.c:
 * ida.c, galpha.c). A non-finite output stops the run with PHM_ESOLVER (out->nout_done counts
 * the finite outputs before it). */
phm_status phm_simulate(const phm_model *model, const double *poses0, const double *twists0,
                        const double *tout, int nout, const phm_sim_options *opt,
                        phm_sim_output *out, phm_error *err);
/* The result quantities (csrc/include/phmech_results.h, PHM_RESULT_FIELDS): row `f` of the table
 * (csrc/util/codes.c; NULL if out of range), and one output's shape of array `f` for `model`
 * with `nrecord` recorded carriers (< 0: all): dims[0] entries of `over`, then an item's dims,
 * with the dimensions' names (csrc/dae/output.c). Returns the number of dims (1 to 3); 0 for an
 * unknown field. model NULL: the names only (dims 0 where they depend on the model). */
const phm_result_field *phm_result_field_at(int f);
int phm_result_shape(const phm_model *model, int nrecord, int f, long dims[3], const char *names[3]);

/* ---------------------------------------------------------------- integrators (csrc/integrate/integrators.c) */
int phm_integrator_count(void);                  /* rows of the table of integrators (codes 0..count-1) */
const char *phm_integrator_name(int integrator); /* "ida", "generalized-alpha"; NULL if unknown    */
/* Options with the integrator's sub-struct at its defaults and every other field 0 (set rtol,
 * atol and the rest by name); PHM_EINVAL for an unknown integrator. */
phm_status phm_sim_defaults(int integrator, phm_sim_options *opt, phm_error *err);

/* ---------------------------------------------------------------- modes (csrc/analyze/modes.c, modes_sparse.c) */
/* Linearized modes at poses (NULL: H0) with constraint wrenches lambda (NULL: zero), loads at
 * `time`: the nmodes lowest omega [rad/s], damping ratios zeta, shapes [nmodes][nc][6] (tangent
 * coordinates, mass-normalized); *nfound modes returned (<= nmodes, limited by the free DOF).
 * method: PHM_MODES_AUTO (dense below PHM_SPARSE_MODES_MIN + 6 nmodes carrier coordinates), _DENSE,
 * _SPARSE.
 * The sparse path checks its result against the count of eigenvalues below its shift
 * (phm_modes_count): when eigenvalues lie below the shift that its iteration did not find (an
 * unstable mode far from the shift, docs/validation.md finding 9), AUTO redoes it densely up to
 * PHM_DENSE_MODES_MAX manifold coordinates, and beyond them, or with _SPARSE, lowers the shift
 * until nothing is below it (spectrum slicing); a count that cannot be certified is then an
 * error (PHM_ESOLVER), never an unverified result. stats (NULL: not wanted): the path taken,
 * the sparse path's iterations and shifts (phm_modes_stats). */
phm_status phm_modes(const phm_model *model, const double *poses, const double *lambda,
                     double time, int nmodes, int method, double *omega, double *zeta,
                     double *shapes, int *nfound, phm_modes_stats *stats, phm_error *err);

/* How many eigenvalues lambda = omega^2 [(rad/s)^2] of the linearization at poses (NULL: H0)
 * with constraint wrenches lambda (NULL: zero), loads at `time`, lie below `shift`: the inertia
 * of the sparse KKT matrix [K - shift M, G^T; G, 0] (Sylvester; csrc/analyze/linearize.c). *check:
 * the count's certificate, ||E||_1 est(||KKT^-1||_1) for the residual E of its LDL'
 * factorization; the count is exact when it is < 1 (up to the condition estimate's accuracy:
 * phm_modes trusts it below PHM_INERTIA_CHECK).
 * PHM_ESINGULAR when that matrix is singular (shift on an eigenvalue, dependent constraint
 * rows) or the factorization met a zero pivot. */
phm_status phm_modes_count(const phm_model *model, const double *poses, const double *lambda,
                           double time, double shift, int *below, double *check, phm_error *err);

/* ---------------------------------------------------------------- linear port-Hamiltonian model (csrc/analyze/linear_model.c) */
/* The linear port-Hamiltonian model at poses (NULL: H0) with constraint wrenches lambda (NULL:
 * zero), loads at `time`, on the null space Z of the constraint Jacobian (the dense reduction of
 * phm_modes): *nr reduced coordinates, stiffness K, damping D and mass M (nr x nr, symmetrized,
 * row-major), Z (6 nc x nr, row-major, may be NULL) and the input matrix B = Z^T F (nr x
 * phm_linear_port_columns) of the ports' generalized forces F. Caller-allocated: K, D, M, Z with
 * room for (6 nc)^2 values, B for 6 nc x columns. */
phm_status phm_linear_model(const phm_model *model, const double *poses, const double *lambda,
                            double time, int nports, const phm_linear_port *ports, int *nr,
                            double *K, double *D, double *M, double *Z, double *B, phm_error *err);
int phm_linear_port_columns(const phm_model *model, int nports, const phm_linear_port *ports); /* inputs of the ports */
/* phm_linear_model with the components' linearized laws into *comp (phm_linear_components; NULL:
 * phm_linear_model). */
phm_status phm_linear_closed_loop(const phm_model *model, const double *poses,
                                  const double *lambda, double time, int nports,
                                  const phm_linear_port *ports, int *nr, double *K, double *D,
                                  double *M, double *Z, double *B, phm_linear_components *comp,
                                  phm_error *err);

/* ---------------------------------------------------------------- statics (csrc/analyze/statics.c) */
/* Static equilibrium under the loads and gravity at `time`, scaled from 0 to 1 in `steps` load
 * steps (halved on failure) from the unloaded equilibrium nearest the start, or with steps = 0
 * at the full load directly from the start (pseudo-transient continuation where Newton fails),
 * or with steps = -1 the same without the continuation (an equilibrium next to the start, or
 * PHM_ESOLVER after at most 12 iterations); Newton, sparse LU (KLU). poses: start (NULL: H0);
 * results in poses_out (nc x 16) and lambda_out (nconstraints); *iters = total Newton
 * iterations (tangents). At Newton's first failure it asks phm_static_free whether the loads do
 * work on a motion nothing resists: then no equilibrium exists, and it stops there with
 * PHM_ESOLVER and a message naming the first such motion ("no static equilibrium: ..."). */
phm_status phm_static(const phm_model *model, const double *poses, double time, int steps,
                      double tol, double *poses_out, double *lambda_out, int *iters,
                      phm_error *err);
/* The same, calling monitor(ctx, load factor reached, Newton iterations so far, load step) after
 * each accepted load step (monitor may be NULL); a non-zero return stops with PHM_EINTERRUPT.
 * On any failure poses_out and lambda_out hold the last converged state and *reached (may be
 * NULL) its load factor. */
phm_status phm_static_monitored(const phm_model *model, const double *poses, double time,
                                int steps, double tol, phm_monitor monitor, void *ctx,
                                double *poses_out, double *lambda_out, int *iters,
                                double *reached, phm_error *err);

/* ---------------------------------------------------------------- no equilibrium (csrc/analyze/static_free.c) */
/* Motions nothing resists on which the loads (gravity, applied wrenches, effort actuators, at
 * load factor 1 and `time`) do work at a rate independent of the configuration: each proves
 * that the mechanism has no static equilibrium (docs/method.md section 7.3, "No equilibrium").
 * Found from the mechanism's structure (a pair whose removal separates a part from the ground,
 * or a part linked to the ground by nothing) and the kinds of its loads, and checked at the poses
 * given (NULL: H0) with the model's own forces: the work rate equals the loads' generalized
 * force there and at two poses along the motion, and the constraints still hold there. A
 * mechanism for which none is found may still have no equilibrium (a closed loop driven round).
 * Up to nmax motions into out, their number in *nfound; moving (may be NULL): nmax x nc bytes,
 * 1 where the carrier moves in motion k (row k); load_work (may be NULL): nmax x nloads, each
 * applied wrench's part of the force. Allocates; no output is touched beyond *nfound rows. */
phm_status phm_static_free(const phm_model *model, const double *poses, double time, int nmax,
                           phm_free_motion *out, unsigned char *moving, double *load_work,
                           int *nfound, phm_error *err);

#endif /* PHMECH_H */
