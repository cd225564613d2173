/* sundials_compat.h -- the SUNDIALS headers the core uses, and one spelling for what SUNDIALS 6
 * and 7 name differently (kept here only). */
#ifndef PHM_SUNDIALS_COMPAT_H
#define PHM_SUNDIALS_COMPAT_H

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#endif
