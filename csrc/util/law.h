/* law.h -- the time laws' breakpoints and copies (phm_law_eval and phm_law_check are public:
 * phmech.h). */
#ifndef PHM_LAW_H
#define PHM_LAW_H

#include <stddef.h>

#include "phmech.h"

/* Breakpoints of a law (times where a piece starts or ends: s, s' or s'' may jump there) into
 * out, or only their count when out is NULL; returns the count (an expression: its leaves', not
 * sorted, possibly repeated). */
int phm_law_breakpoints(const phm_law *law, double *out);
/* What a deep copy of a (checked) law needs: adds its expression nodes to *nnodes and the
 * doubles of its tables (points, pieces, breakpoints) to *ndoubles. */
void phm_law_extent(const phm_law *law, size_t *nnodes, size_t *ndoubles);
/* Make *law (a shallow copy of a checked law) own its data: its nodes and tables are copied to
 * *nodes and *doubles, which advance past them (room from phm_law_extent). */
void phm_law_copy(phm_law *law, phm_law **nodes, double **doubles);

#endif
