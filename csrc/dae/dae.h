/* dae.h -- the stabilized index-2 DAE of a model (docs/method.md section 6) and its workspace.
 * State layout y (n entries): per carrier (q[4], p[3], t[6]) (PHM_NSTATE each); then the joint
 * coordinates (nj, integrated from their rates; they select the branch of multi-turn angles);
 * then the energy ledger integrals (dissipated, supplied, one per port); then lambda (ncons);
 * then mu (ncons). Residual F(t, y, y') = 0 (residual.c), consistent initial values
 * (initial.c), the sparsity pattern and coloured finite-difference Jacobian (jacobian.c), the
 * outputs (output.c). Everything a residual, Jacobian, output or restart needs is allocated by
 * dae_init and dae_jacobian_pattern: no allocation after set-up. */
#ifndef PHM_DAE_H
#define PHM_DAE_H

#include "model.h"
#include "sundials_compat.h"

#define PHM_NSTATE 13 /* per carrier: q (4), p (3), t (6) */

typedef struct {
  const phm_model *m;
  int n, ix, ie, il, im; /* sizes and offsets of the state blocks */
  double tref;
  double *H, *tw, *wr, *gl, *gm, *pport, *eff; /* scratch, allocated at set-up */
  char idamsg[256];         /* IDA's last error message, through idasink (csrc/solve/ida.c) */
  phm_sun_errsink idasink; /* here, not in run_ida: SUNDIALS 7 keeps it on the context */
  /* KLU: sparsity pattern (CSC) and column colouring for the finite-difference Jacobian */
  int nnz, ncolor;
  sunindextype *colptr, *rowind;
  int *color;
  double *ytmp, *yptmp, *rtmp, *r0;
} dae_t;

/* ---------------------------------------------------------------- residual.c */
phm_status dae_init(dae_t *d, const phm_model *m, phm_error *err);
void dae_free(dae_t *d);
/* Carrier poses H (nc x 16) and twists tw (nc x 6) from the state vector y. */
void dae_unpack(const phm_model *m, const double *y, double *H, double *tw);
/* F(time, y, y'); 0 on success. No allocation. */
int dae_residual(dae_t *d, double time, const double *y, const double *yp, double *F);
/* The pairs' rows of F (joint-coordinate rates, velocity and position constraints) at the poses
 * and twists already unpacked into d->H, d->tw; accumulates G^T lambda and G^T mu per carrier
 * into d->gl, d->gm. */
void dae_pair_rows(dae_t *d, double time, const double *y, const double *yp, double *F);
/* Absolute tolerance of state i for the error weights (the multipliers' own floors). */
double dae_state_atol(const dae_t *d, int i, double atol);
/* State i is a carrier's twist component. */
int dae_is_twist(const dae_t *d, int i);

/* ---------------------------------------------------------------- initial.c */
/* Project poses H and twists tw onto the constraints (minimum-norm corrections), then solve the
 * acceleration level for t' and lambda; writes y and y' (all but the ledger values in y). qprev:
 * previous state for quaternion sign continuity (NULL at the start). check_x0: compare the
 * projected joint coordinates with the given x0. */
phm_status dae_consistent_ic(dae_t *d, double time, double *H, double *tw, const double *qprev,
                             const double *xs, int check_x0, double *y, double *yp, phm_error *err);
/* New piece of the laws at time t (tpiece: the time that selects the piece): consistent values
 * from the current state, ledger integrals carried over; *nbp = next breakpoint. H, tw, qprev:
 * scratch (nc x 16, nc x 6, n). */
phm_status dae_restart_at_breakpoint(dae_t *d, double t, double tpiece, double *nbp, double *y,
                                     double *yp, double *H, double *tw, double *qprev,
                                     phm_error *err);

/* ---------------------------------------------------------------- jacobian.c */
/* The CSC pattern of dF/dy + cj dF/dy' and its column colouring (into d). */
phm_status dae_jacobian_pattern(dae_t *d, phm_error *err);
/* J = dF/dy + cj dF/dy' at (t, y, y') with residual r0 = F(t, y, y'), by coloured forward
 * differences into the sparse matrix J (pattern from dae_jacobian_pattern). 0 on success. */
int dae_jacobian(dae_t *d, double t, double cj, const double *y, const double *yp,
                 const double *r0, SUNMatrix J);

/* ---------------------------------------------------------------- output.c */
/* Store output iout (state y at time t; E0: the energy at output 0, set there), check that it is
 * finite and call the user's callbacks: PHM_EINTERRUPT if the interrupt callback asks; *stop = 1
 * if the progress callback asks to stop quietly. */
phm_status dae_emit_output(dae_t *d, const double *y, phm_sim_output *out, int iout, double E0[1],
                           double t, const phm_sim_options *opt, int *stop, phm_error *err);

#endif
