/* solve.h -- what reads the DAE and the model to produce results: the integrators (ida.c,
 * galpha.c, dispatched by simulate.c) and the linearization shared by modes.c and statics.c. */
#ifndef PHM_SOLVE_H
#define PHM_SOLVE_H

#include <klu.h>

#include "dae.h"

/* ---------------------------------------------------------------- integrators */
/* Integrate from the consistent state in yy, yp at tout[0] (output 0 already emitted; E0 its
 * energy) to tout[nout - 1], emitting outputs 1..nout-1. d: set up with its Jacobian pattern
 * (dae_jacobian_pattern; IDA's dense solver needs none); nbp: the next breakpoint of the laws. */
phm_status run_ida(dae_t *d, const phm_sim_options *opt, SUNContext ctx, N_Vector yy, N_Vector yp,
                   const double *tout, int nout, double E0[1], double nbp, phm_sim_output *out,
                   phm_error *err);
phm_status run_galpha(dae_t *d, const phm_sim_options *opt, SUNContext ctx, N_Vector yy,
                      N_Vector yp, const double *tout, int nout, double E0[1], double nbp,
                      phm_sim_output *out, phm_error *err);

/* ---------------------------------------------------------------- nvector_ops.c */
/* Install phmech's compiled copies of the serial N_Vector operations IDA spends its time in on v
 * (N_VNew_Serial's; its clones inherit them), and of the zero on the sparse matrix A: the same
 * numbers, bit for bit, as SUNDIALS's (whose Debian build is unoptimized). */
void phm_nvector_ops(N_Vector v);
void phm_sparse_matrix_ops(SUNMatrix A);

/* ---------------------------------------------------------------- linearization (linearize.c) */
typedef struct {
  const phm_model *m;
  double time, tref, scale;
  const double *lam; /* constraint wrenches added to the forces (may be NULL) */
  double *wr, *gl, *G, *Hp;
  /* carrier coupling graph (CSR) and the force Jacobian blocks (lin_graph; modes and statics) */
  int *ptr, *nbr;
  double *Kb;
  double *Mb; /* the mass in the same slots: carriers' inertias, consistent elements' couplings */
} lin_t;

phm_status lin_alloc(lin_t *L, const phm_model *m, phm_error *err);
void lin_free(lin_t *L);
/* The coupling graph of L's model, room for the force Jacobian blocks and the mass blocks Mb
 * (filled: they are constant). */
phm_status lin_graph(lin_t *L, phm_error *err);
/* Generalized forces at poses H: applied wrenches (x L->scale) + G^T L->lam (nc x 6, body frame). */
void lin_total_force(lin_t *L, const double *H, double *f);
/* L->Kb[q] = d f_r / d delta_c for block q = (row carrier r, column carrier nbr[q]) of the
 * coupling graph, in closed form (lin_closed_form_blocks). */
void lin_force_jacobian_blocks(lin_t *L, const double *H);
/* Add the closed-form blocks at poses H (the se3 elements', gravity's, the pairs' G^T lambda, the
 * actuators', loads' and springs') to Kb (df/ddelta; if not NULL) and their twist derivatives to
 * Db (df/dt: the damping; if not NULL). */
void lin_closed_form_blocks(const lin_t *L, const double *H, double *Kb, double *Db);

/* The KKT matrix [K G^T; G 0] of the linearization (K: 6x6 blocks on the slots of the carrier
 * graph, G: the pairs' constraint rows) in compressed columns, with the source of every entry,
 * factored by KLU: the blocks only couple neighbouring carriers and G only the carriers of each
 * pair, so a factorization costs O(N) where a dense LU was O(N^3). Statics (Newton matrix
 * [df/ddelta G^T; G 0]) and sparse modes (K - sigma M) share it. */
typedef struct {
  int n, *Ap, *Ai, *src; /* src >= 0: Kb[src]; src < 0: Gp[-src - 1] (lin_constraint_blocks) */
  double *Ax;
  klu_symbolic *sym;
  klu_numeric *num;
  klu_common common;
} lin_kkt_t;

/* The pattern of L's KKT matrix (needs lin_graph) and its KLU analysis. */
phm_status lin_kkt_build(lin_kkt_t *S, const lin_t *L, phm_error *err);
void lin_kkt_free(lin_kkt_t *S);
/* Values from the blocks Kb (36 per graph slot) and Gp, then a KLU factorization with fresh
 * pivoting; 0 on success, 1 if singular. */
int lin_kkt_factor(lin_kkt_t *S, const double *Kb, const double *Gp);
/* x <- KKT^-1 x with the last factorization; 0 on success. */
int lin_kkt_solve(lin_kkt_t *S, double *x);
/* The pairs' constraint Jacobian blocks at poses H: row r holds G_a in Gp[12 r ..] and G_b in
 * Gp[12 r + 6 ..] (12 per constraint row). */
void lin_constraint_blocks(const lin_t *L, const double *H, double *Gp);

#endif
