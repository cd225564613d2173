/* dae.h -- the stabilized index-2 DAE of a model (docs/method.md section 6) and its data.
 * State layout y (n entries): per carrier (q[4], p[3], t[6]) (PHM_NSTATE each); then the joint
 * coordinates (nj, integrated from their rates; they select the branch of multi-turn angles);
 * then the components' internal states (nz: LuGre bristles, motor currents, grouped by pair,
 * csrc/model/component.c); then the energy ledger integrals (dissipated, supplied, one per port); then lambda (ncons);
 * then mu (ncons). Residual F(t, y, y') = 0 (residual.c), consistent initial values
 * (initial.c), the sparsity pattern and the Jacobian (jacobian.c, in closed form), the outputs
 * (output.c).
 *
 * Model and data, as MuJoCo's mjModel and mjData: the model (phm_model, csrc/model/model.h) is
 * immutable; everything a run writes lives in its phm_data, allocated once by dae_init from the
 * model's sizes. A residual evaluation fills it stage by stage -- the carriers' poses and twists
 * (dae_unpack), every pair once (dae_eval_pairs: frames, constraint rows, joint coordinates and
 * rates, read by the pair rows, the actuators and the outputs), the applied wrenches, G^T lambda
 * and G^T mu -- and the Jacobian, the outputs and the consistent initial values (at the start
 * and at every breakpoint of the laws) work in its scratch. After dae_init and
 * dae_jacobian_pattern nothing in csrc/dae/ allocates, nor the integrators after their set-up,
 * which allocates their own scratch (csrc/integrate/integrate.h; tests/c/test_no_alloc.c counts
 * it). */
#ifndef PHM_DAE_H
#define PHM_DAE_H

#include "linalg.h"
#include "model.h"
#include "sundials_compat.h"

#define PHM_NSTATE 13 /* per carrier: q (4), p (3), t (6) */
/* per carrier of a planar DAE (dae_planar_init; normal z: q_w, q_z, p_x, p_y, omega_z, v_x, v_y) */
#define PHM_NSTATE_PLANAR 7

/* Scratch of the consistent initial values (dae_consistent_ic), sized from the model. */
/* The dense fallback systems of the consistent initial values are kept up to this many doubles
 * per array (8 MB): a chain of 160 rigid bodies or a model of similar constraint count. */
#define PHM_IC_DENSE_MAX (1 << 20)

typedef struct {
  int ncc;          /* constrained carriers (those of the pairs; 0 without constraint rows)  */
  int *cmap;        /* nc: carrier -> its place among the constrained ones, -1 if free        */
  int *clist;       /* ncc: the constrained carriers in that order                            */
  int kkt;          /* a constrained carrier's inertia fails phm_chol6: the KKT system is
                     * solved instead of the Schur complement (so A and ls are sized for it)  */
  double *H, *tw;   /* poses and twists projected (nc x 16, nc x 6): the start's, a restart's */
  double *qprev;    /* n: the state before a restart (quaternion signs, joint branches, ledger) */
  double *Lc;       /* nc x 36: Cholesky factors of the inertias                              */
  int *lcfail;      /* nc: 1 where a carrier's inertia failed its Cholesky test                */
  double *b1c;      /* 6 ncc: the constrained carriers' b1, kept for the dense path            */
  double *cg;       /* 5 x 6 nc: conjugate gradients with consistent element masses (or NULL)  */
  double *acc;      /* 6 nc: accelerations t'                                                 */
  double *G, *X;    /* ncons x 6 ncc: G on the constrained carriers; M^-1 G^T (or dc/dt's G)  */
  double *A, *b;    /* least-squares matrix (the largest of the systems) and right-hand side  */
  double *g, *vt, *c1, *lam; /* ncons: g, prescribed rates, 2 ncons: dc/dt's sides, lambda    */
  double *Hp;       /* nc x 16: poses moved along the motion (dc/dt)                          */
  double *res;      /* n: a residual (the rates of joint coordinates and ledger)              */
  phm_lstsq_work ls; /* dgelss's memory for every system above                                */
  int dense;        /* the dense systems above are allocated (small models; csrc/dae/residual.c) */
  struct ic_schur *schur; /* the sparse Schur complement of the constraint rows (ic_schur.c)  */
} dae_ic_work;

/* The mutable data of a DAE: one residual evaluation's results and every scratch buffer. */
typedef struct {
  /* one evaluation (dae_residual; dae_pair_rows; the outputs) */
  double *H, *tw;        /* carrier poses (nc x 16) and twists (nc x 6) of the state          */
  phm_pair_data *pair;   /* np: every pair at that state (dae_eval_pairs)                      */
  double *wr;            /* nc x 6: applied wrenches (body frames)                             */
  double *gl, *gm;       /* nc x 6: G^T lambda and G^T mu per carrier                          */
  double *pport;         /* nport: power of every port                                         */
  double *eff;           /* nj: actuator efforts summed per joint coordinate (outputs)          */
  double *rtmp;          /* n: scratch rows (the pairs' rows dae_jacobian evaluates)           */
  double *dtw;           /* nc x 6: a change of the twists (dae_ledger_dpower)                 */
  double *lref;          /* ncons: the multipliers lambda of the last accepted step
                          * (dae_step_accepted; dae_consistent_ic's at a (re)start)          */
  double *lreg, *mreg;   /* ncons: each velocity and position row's compliance, the
                          * regularization of the rows of the pairs on a loop
                          * (dae_regularization, docs/method.md section 6.2); 0 elsewhere    */
  /* consistent initial values (dae_consistent_ic, dae_restart_at_breakpoint) */
  dae_ic_work ic;
} phm_data;

struct dae_planar; /* planar.c */

typedef struct {
  const phm_model *m;
  int n, ix, iz, ie, il, im; /* sizes and offsets of the state blocks (iz: the components'
                              * internal states, docs/method.md section 4.11) */
  int ns, nt0;           /* states per carrier (PHM_NSTATE, or PHM_NSTATE_PLANAR) and the first
                          * of its twist components among them */
  struct dae_planar *pl; /* non-NULL: the in-plane reduction of pl's full DAE (planar.c) */
  int nnorm, ncfg_drop;  /* the integrators' RMS norms count nnorm states (the full DAE's n)
                          * and the configuration error ncfg_drop more than it holds (3 per
                          * carrier when planar): the dropped states have no error, and
                          * counted as a 3-D solve counts them the norms, and so the steps
                          * and Newton's tests, are the 3-D solve's (n and 0 in 3-D) */
  double lscale;         /* the mechanism's size [m] (dae_length_scale): the constraint tolerance */
  double reg;            /* the regularization's factor (dae_regularization_scale): 1 by default */
  double stage_h;        /* the generalized-alpha's step [s] at its stage's residual (the bound
                          * on the workless constraint wrench's correction, residual.c; the
                          * global estimate's, galpha_global.c: its block stage's step); 0
                          * before the first, and never read by IDA */
  double tref;           /* reference time of the laws' current piece (phm_model_tref) */
  unsigned char *workless; /* np: pair ip's constraint wrench is made workless at the
                            * generalized-alpha's stage (residual.c, workless_pairs) */
  unsigned char *kbody;  /* nc: carrier c's kinematic rows in its body frame (1) or in the
                          * world's (0): dae_body_kinematics (a full DAE's; NULL when planar) */
  phm_data data;         /* allocated by dae_init */
  /* KLU: the Jacobian's sparsity pattern (CSC) */
  int nnz;
  sunindextype *colptr, *rowind;
  /* dae_jacobian_prune: the entries of the pattern ever nonzero (nnz bytes), and how many it
   * kept last (nzcnt < 0: none yet) */
  long nzcnt;
  unsigned char *nzkeep;
} dae_t;

/* ---------------------------------------------------------------- residual.c */
/* The layout of m's DAE and its data (every buffer of phm_data; the Jacobian's pattern is
 * dae_jacobian_pattern's). */
phm_status dae_init(dae_t *d, const phm_model *m, phm_error *err);
void dae_free(dae_t *d);
/* Carrier poses H (nc x 16) and twists tw (nc x 6) from the state vector y. */
void dae_unpack(const phm_model *m, const double *y, double *H, double *tw);
/* Every pair at the poses and twists in d->data (H, tw) and the joint-coordinate branches of y,
 * at time: into d->data.pair, the parts `what` asks for (PHM_PAIR_ROWS | PHM_PAIR_JOINT,
 * phm_pair_evaluate). */
void dae_eval_pairs(dae_t *d, double time, const double *y, int what);
/* F(time, y, y'); 0 on success. No allocation. */
int dae_residual(dae_t *d, double time, const double *y, const double *yp, double *F);
/* dae_residual, or without `crows` F but its constraint rows F[il..n) (left as they were, and
 * so the pairs' g in d->data, except a driven pair's): the generalized-alpha's stage residual,
 * whose constraint rows are taken at the step's end (dae_constraint_rows). */
int dae_residual_rows(dae_t *d, double time, const double *y, const double *yp, double *F,
                      int crows);
/* The pairs' rows of F (joint-coordinate rates, velocity and position constraints) at the poses
 * and twists already unpacked into d->data (H, tw): evaluates every pair (dae_eval_pairs) and
 * accumulates G^T lambda and G^T mu per carrier into d->data.gl, gm. */
void dae_pair_rows(dae_t *d, double time, const double *y, const double *yp, double *F);
/* Only the constraint rows of F (velocity and position: F[il..n)) at state y, the same numbers
 * as dae_unpack + dae_pair_rows give: unpacks only the carriers of the pairs into d->data (H, tw)
 * and evaluates only the pairs with kept rows, without their joint coordinates and rates; the
 * other carriers' H, tw, d->data.gl, gm and the pairs' joint fields are left as they were (a mix
 * of two states: read d->data only after a full evaluation). */
void dae_constraint_rows(dae_t *d, double time, const double *y, double *F);
/* Where a carrier's pose and twist sit among its d->ns states: first nq quaternion components
 * (qf: which of w, x, y, z), then npos position axes (pf: which of x, y, z), then from d->nt0
 * nt twist components (tf: which of omega, v). 3-D: 4, 3 and 6, all in order; planar
 * (dae_planar_init): w and the normal's component, the two in-plane axes, the rotation about
 * the normal and the two in-plane velocities. */
typedef struct {
  int nq, qf[4], npos, pf[3], nt, tf[6];
} dae_carrier_layout;
void dae_carrier_states(const dae_t *d, dae_carrier_layout *L);
/* The energy ledger's Newton rows hold only their diagonal (csrc/dae/jacobian.c), so their
 * corrections lag the others' by an iteration. dP[0 .. il - ie) = what they leave out: the
 * change of the ledger's power rates (Pd, Ps, the ports) for a correction dy (d's layout) of
 * the state y -- of the actuators' and loads' power (phm_applied_dpower) and of the constraint
 * wrenches' (G^T lambda . t; a workless pair's, residual.c, lambda . v_t) for the change `at` dy
 * of the twists (at: the stage's share of it) and dy of lambda, exact in those at the poses held (P is at most quadratic in them: a
 * linearization missed a damper's rate that a correction turns to its opposite, which leaves
 * P as it was). Spring and element damping are left out (0: they lag as before). At the state
 * of the last dae_residual and dae_constraint_rows (d's data: the pairs with constraint rows at
 * the latter's). No allocation. */
void dae_ledger_dpower(dae_t *d, double time, const double *y, const double *dy, double at,
                       double *dP);
/* The kinematic rows of the carriers that mu acts on (those of pairs with constraint rows) in
 * their body frames (on != 0), the others' and by default all in the world's: the same equations
 * premultiplied by an invertible matrix of the carrier's quaternion, whose Newton matrix has
 * mu's entries constant (residual.c). IDA takes them (csrc/integrate/ida.c says why). */
void dae_body_kinematics(dae_t *d, int on);
/* Absolute tolerance of state i for the error weights (the multipliers' own floors). */
double dae_state_atol(const dae_t *d, int i, double atol);
/* State i is a carrier's twist component. */
int dae_is_twist(const dae_t *d, int i);

/* ---------------------------------------------------------------- watch.c */
/* The pairs' position residuals are held within DAE_CONSTRAINT_TOL (rad) and DAE_CONSTRAINT_TOL
 * times the mechanism's size (m), or atol if larger (python/phmech/topology.py's POSE_TOL, the
 * tolerance the initial configuration is placed to). */
#define DAE_CONSTRAINT_TOL 1e-6
/* The regularization of the constraint rows (docs/method.md section 6.2, "Singular
 * configurations"): the velocity row r reads G_r t - v_t,r + c_r (lambda_r - lambda_ref,r) with
 * lambda_ref the multipliers of the last accepted step (dae_step_accepted) and the compliance
 * c_r = DAE_REG_TIME (G M^-1 G^T)_rr at the initial configuration (so c_r (lambda_r - lambda_ref)
 * is the change of velocity DAE_REG_TIME of the multiplier's change gives); the position row
 * reads g_r + DAE_REG_TIME mu_r. Without it the Newton matrix is singular where the rows become
 * dependent (a parallelogram's flat positions), and there the discrete equations have no
 * solution at all: the constraint's second-order residual in the self-stress direction has no
 * unknown to move it (G^T mu and G^T lambda vanish in it). */
#define DAE_REG_TIME 1e-9
/* The generalized-alpha's stage makes each pair's constraint wrench workless (residual.c,
 * workless_at_stage) by a wrench -kappa M t on its carriers, with kappa h at most this: the
 * carriers' kinetic energy moved by at most this fraction per step. On the A02 four-bar it
 * never acts (bounds of 1e-5 .. 1e-7 change none of its figures); near rest it does. */
#define DAE_WORKLESS_STEP 1e-4
/* d->data.lreg, mreg: for the rows of the pairs on a loop of the graph of carriers, ground and
 * pairs with constraint rows (only there can rows become dependent: an open chain's rows are
 * independent in every configuration, and left as they were), from the carriers' inertias and
 * the pairs' G at the initial poses; 0 for the others. Set-up only (allocates). */
phm_status dae_regularization(dae_t *d, phm_error *err);
/* The regularization for a run at relative tolerance rtol: scaled by min(1, rtol / 1e-8) when
 * lambda_ref follows every step (per_step: the generalized-alpha), min(1, rtol / 1e-6) when it
 * follows the outputs only (IDA, whose steps are internal), so that what it leaves in the
 * constraint rows (c (lambda - lambda_ref), DAE_REG_TIME mu) and the work it does shrink with
 * the tolerance asked. */
void dae_regularization_scale(dae_t *d, double rtol, int per_step);
/* The mechanism's size [m] from its carriers' initial origins and pair frames (1 if none). */
double dae_length_scale(const phm_model *m);
/* After each accepted step of an integrator (state y at time t, d's layout; output: t is an
 * output time): the position residual of every row of the pairs with rows dropped as redundant
 * (the DAE does not hold those) and, at outputs, of every pair's rows (the held rows are
 * Newton's, within its tolerance at every step), against the tolerance above; PHM_ESOLVER
 * naming the pair (its index), the row, the residual and the time when one is beyond it. Moves
 * the proximal reference lambda_ref. rel: the relative tolerance (DAE_CONSTRAINT_TOL, or IDA's
 * rtol where larger: IDA's Newton holds the constraint rows to its own tolerances, measured
 * 1.45e-6 m on a driven rod at rtol 1e-4). No allocation. */
phm_status dae_step_accepted(dae_t *d, double t, const double *y, double rel, double atol,
                             int output, phm_error *err);

/* ---------------------------------------------------------------- initial.c */
/* Project poses H and twists tw onto the constraints (minimum-norm corrections), then solve the
 * acceleration level for t' and lambda; writes y and y' (all but the ledger values in y). qprev:
 * previous state for quaternion sign continuity (NULL at the start). check_x0: compare the
 * projected joint coordinates with the given x0. */
phm_status dae_consistent_ic(dae_t *d, double time, double *H, double *tw, const double *qprev,
                             const double *xs, int check_x0, double *y, double *yp, phm_error *err);
/* New piece of the laws at time t (tpiece: the time that selects the piece): consistent values
 * from the current state, ledger integrals carried over; *nbp = next breakpoint. */
phm_status dae_restart_at_breakpoint(dae_t *d, double t, double tpiece, double *nbp, double *y,
                                     double *yp, phm_error *err);

/* ---------------------------------------------------------------- ic_schur.c */
/* The constraint systems of dae_consistent_ic in O(N): S = G D^-1 G^T (D = I or, with mass, the
 * carriers' inertias), sparse, through KLU. Set-up: the pattern and KLU's analysis (none without
 * constraint rows). */
phm_status ic_schur_alloc(dae_t *d, phm_error *err);
void ic_schur_free(dae_ic_work *w);
/* G's row blocks, g and the prescribed rates vt (either may be NULL) at poses H. */
void ic_schur_rows(dae_t *d, const double *H, const double *xs, double time, double *g,
                   double *vt);
/* out[r] = G_r t for twists tw (nc x 6), with the blocks of the last ic_schur_rows. */
void ic_schur_apply(const dae_t *d, const double *tw, double *out);
/* Assemble and factor S for the blocks of the last ic_schur_rows; 0, or 1 if S is singular or
 * too ill-conditioned (KLU's rcond <= 1e-12: dependent rows, a singular configuration). */
int ic_schur_factor(dae_t *d, int mass);
/* rhs <- S^-1 rhs (nk), then delta (6 nc) += D^-1 G^T rhs; 0 on success. */
int ic_schur_solve(dae_t *d, int mass, double *rhs, double *delta);

/* ---------------------------------------------------------------- jacobian.c */
/* The CSC pattern of dF/dy + cj dF/dy' (row indices ascending in each column; into d), from the
 * coupling graph of carriers and pairs (phm_carrier_graph): time and memory linear in the number
 * of nonzeros. */
phm_status dae_jacobian_pattern(dae_t *d, phm_error *err);
/* J = dF/dy + cj dF/dy' at (t, y, y') into the sparse matrix J (pattern from
 * dae_jacobian_pattern), in closed form: the carriers' own kinematic and momentum rows, the se3
 * elements' wrenches (phm_element_tangent), gravity (phm_gravity_tangent), the pairs' rows,
 * G^T lambda and G^T mu (phm_pair_tangent), actuators, loads and springs (phm_applied_tangent),
 * the ledger rows' diagonal. r0 (the residual F(t, y, y')) is not read. 0 on success. */
int dae_jacobian(dae_t *d, double t, double cj, const double *y, const double *yp,
                 const double *r0, SUNMatrix J);
/* The dense matrix A (n x n, SUNDenseMatrix) = the sparse Js (CSC, dae_jacobian's): every entry
 * outside Js's pattern zero, whatever A held. The dense LUs of both integrators take the
 * closed-form Jacobian this way (csrc/integrate/ida.c, galpha.c): one implementation of it, evaluated
 * on the sparse pattern. No allocation. */
void dae_jacobian_to_dense(SUNMatrix Js, SUNMatrix A);
/* Drop the entries of J (CSC, on the pattern of dae_jacobian_pattern) that have been exactly
 * zero in every call so far, in place; returns 1 if the pattern kept grew (or this is the first
 * call), 0 if it is the same: a sparse LU analysed for that pattern can then be refactored,
 * otherwise it needs a fresh analysis. No allocation. */
int dae_jacobian_prune(dae_t *d, SUNMatrix J);

/* The values of J = dF/dy + cj dF/dy' on the pattern of dae_jacobian_pattern (d->nnz of them)
 * into val, as dae_jacobian's (full DAE only). No allocation. */
void dae_jacobian_values(dae_t *d, double t, double cj, const double *y, const double *yp,
                         double *val);

/* ---------------------------------------------------------------- planar.c */
/* The planar DAE of m: every carrier moves in the plane normal to world axis `axis` (0, 1, 2:
 * x, y, z; rotation about it, in-plane twist; the caller checked it, with m's out-of-plane
 * constraint rows dropped). d holds only the in-plane carrier states (PHM_NSTATE_PLANAR per
 * carrier: q_w, q_axis, two positions, omega_axis, two body velocities), then the joint coordinates, ledger
 * and multipliers as the full DAE; its residual, Jacobian, initial values, restarts and outputs
 * expand d's vectors into the full DAE's (the out-of-plane states at their initial values, zero
 * rates), evaluate it and gather the in-plane rows. dae_free frees both. */
phm_status dae_planar_init(dae_t *d, const phm_model *m, int axis, phm_error *err);
/* The full DAE behind d (d itself when it is not planar): its data holds the poses and twists
 * of the carriers (d->data of a planar d is empty). */
dae_t *dae_full(dae_t *d);
/* The full DAE's state of the reduced y (expanded into the planar data's buffer). */
const double *dae_planar_state(dae_t *d, const double *y);
/* 1 when every constraint row of pair ip that the model dropped is out of d's plane (no entry of
 * its G on a kept twist component of either carrier: the rows python/phmech/planar.py's
 * out_of_plane_rows drops), which the reduction holds exactly (the out-of-plane states keep
 * their values); found at the full state yf (dae_planar_state) and time t on the pair's first
 * call and kept (an in-plane motion does not turn a row into the plane). No allocation. */
int dae_planar_drops_out_of_plane(dae_t *d, int ip, const double *yf, double t);
/* dae_carrier_states of a planar d (its kept states). */
void dae_planar_carrier_states(const dae_t *d, dae_carrier_layout *L);
int dae_planar_residual(dae_t *d, double time, const double *y, const double *yp, double *F,
                        int crows);
void dae_planar_constraint_rows(dae_t *d, double time, const double *y, double *F);
phm_status dae_planar_pattern(dae_t *d, phm_error *err);
/* dae_jacobian_values for the reduced pattern: the full DAE's, gathered through the entry map. */
void dae_planar_jacobian_values(dae_t *d, double t, double cj, const double *y, const double *yp,
                                double *val);
phm_status dae_planar_consistent_ic(dae_t *d, double time, double *H, double *tw,
                                    const double *xs, int check_x0, double *y, double *yp,
                                    phm_error *err);
phm_status dae_planar_restart(dae_t *d, double t, double tpiece, double *nbp, double *y,
                              double *yp, phm_error *err);
phm_status dae_planar_emit_output(dae_t *d, const double *y, phm_sim_output *out, int iout,
                                  double E0[1], double t, const phm_sim_options *opt, int *stop,
                                  phm_error *err);
void dae_planar_free(dae_t *d);

/* ---------------------------------------------------------------- output.c */
/* Store output iout (state y at time t; E0: the energy at output 0, set there), check that it is
 * finite and call the user's callbacks: PHM_EINTERRUPT if the interrupt callback asks; *stop = 1
 * if the progress callback asks to stop quietly. */
phm_status dae_emit_output(dae_t *d, const double *y, phm_sim_output *out, int iout, double E0[1],
                           double t, const phm_sim_options *opt, int *stop, phm_error *err);

#endif
