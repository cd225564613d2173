/* klu.c -- what both integrators do with SUNDIALS' KLU solver: the closed-form Jacobian without
 * its exact zeros (dae_jacobian_prune, csrc/dae/jacobian.c), KLU's analysis redone when the kept
 * pattern grows (ida.c's ida_jac, galpha.c's iteration matrix). */
#include "integrate.h"

int phm_klu_prune(dae_t *d, SUNMatrix J, SUNLinearSolver LS) {
  return dae_jacobian_prune(d, J) &&
         SUNLinSol_KLUReInit(LS, J, (sunindextype)d->nnz, SUNKLU_REINIT_PARTIAL) != PHM_SUN_SUCCESS;
}
