/* law.h -- the time laws' breakpoints and validation (phm_law_eval is public: phmech.h). */
#ifndef PHM_LAW_H
#define PHM_LAW_H

#include "phmech.h"

/* Breakpoints of a law (times where a piece starts or ends) into out, or only their count when
 * out is NULL; returns the count. */
int phm_law_breakpoints(const phm_law *law, double *out);
/* PHM_OK, or PHM_EINVAL naming `what idx` (e.g. "pair 3") and the bad parameter. */
phm_status phm_law_check(const phm_law *law, const char *what, int idx, phm_error *err);

#endif
