/* integrate.h -- the integrators of a model's DAE (csrc/dae/): the table of integrators
 * (integrators.c), one file each (ida.c, galpha.c, tree.c), the driver that sets a run up and hands it to
 * one of them (simulate.c), and what they share (klu.c: the pruned KLU pattern; nvector_ops.c). */
#ifndef PHM_INTEGRATE_H
#define PHM_INTEGRATE_H

#include "dae.h"

/* ---------------------------------------------------------------- the table of integrators */
/* One row per integrator (integrators.c, indexed by its code PHM_INTEGRATOR_*). Adding one: its
 * code and option sub-struct (phmech_types.h), its row in integrators.c, its four functions
 * declared with the types below, its file (and meson.build); docs/architecture.md, "What a change
 * touches". */

/* PHM_OK, or PHM_EINVAL naming the first bad option of its sub-struct */
typedef phm_status phm_integrator_check_fn(const phm_sim_options *opt, phm_error *err);
/* Its scratch for a run of d (*work; NULL if none), allocated at set-up, before the first output:
 * nothing of phmech's allocates after it (tests/c/test_no_alloc.c). */
typedef phm_status phm_integrator_setup_fn(dae_t *d, const phm_sim_options *opt, void **work,
                                           phm_error *err);
typedef void phm_integrator_release_fn(void *work);
/* Integrate from the consistent state in yy, yp at tout[0] (output 0 already emitted; E0 its
 * energy) to tout[nout - 1], emitting outputs 1..nout-1. d: set up with its Jacobian pattern
 * (dae_jacobian_pattern: the implicit integrators' linear solvers evaluate the closed-form
 * Jacobian on it); nbp: the next breakpoint of the laws; work: its setup's. */
typedef phm_status phm_integrator_run_fn(dae_t *d, const phm_sim_options *opt, void *work,
                                         SUNContext ctx, N_Vector yy, N_Vector yp,
                                         const double *tout, int nout, double E0[1], double nbp,
                                         phm_sim_output *out, phm_error *err);

typedef struct {
  const char *name;         /* its name in phmech._core.codes()["integrators"]                 */
  phm_sim_options defaults; /* its sub-struct's defaults (the other fields 0)                  */
  int per_step;             /* the regularization's lambda_ref follows every step (1) or only
                             * the outputs (0): dae_regularization_scale                        */
  phm_integrator_check_fn *check;
  phm_integrator_setup_fn *setup;
  phm_integrator_release_fn *release;
  phm_integrator_run_fn *run;
} phm_integrator;

/* The integrator of code `integrator`, or NULL if there is none. */
const phm_integrator *phm_integrator_get(int integrator);

/* ---------------------------------------------------------------- the integrators */
/* ida.c: SUNDIALS IDA (variable-order BDF) */
phm_integrator_check_fn ida_check;
phm_integrator_setup_fn ida_setup;
phm_integrator_release_fn ida_release;
phm_integrator_run_fn run_ida;
/* galpha.c: the generalized-alpha, adaptive (the default) or fixed-step */
phm_integrator_check_fn galpha_check;
phm_integrator_setup_fn galpha_setup;
phm_integrator_release_fn galpha_release;
phm_integrator_run_fn run_galpha;
/* tree.c (tree_aba.c): rigid trees in joint coordinates, explicit Dormand-Prince 5(4) */
phm_integrator_check_fn tree_check;
phm_integrator_setup_fn tree_setup;
phm_integrator_release_fn tree_release;
phm_integrator_run_fn run_tree;

/* ---------------------------------------------------------------- klu.c */
/* After a Jacobian into J, the matrix of the KLU solver LS: drop its entries zero in every call
 * so far (dae_jacobian_prune) and, when the kept pattern grew, have KLU analyse it again. 0 on
 * success, 1 if KLU could not. */
int phm_klu_prune(dae_t *d, SUNMatrix J, SUNLinearSolver LS);

/* ---------------------------------------------------------------- nvector_ops.c */
/* Install phmech's compiled copies of the serial N_Vector operations IDA spends its time in on v
 * (N_VNew_Serial's; its clones inherit them), and of the zero on the sparse matrix A: the same
 * numbers, bit for bit, as SUNDIALS's (whose Debian build is unoptimized). */
void phm_nvector_ops(N_Vector v);
void phm_sparse_matrix_ops(SUNMatrix A);

#endif
