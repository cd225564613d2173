/* model_internal.h -- private to model.c, dae.c, linearize.c and the C unit tests. */
#ifndef PHM_MODEL_INTERNAL_H
#define PHM_MODEL_INTERNAL_H

#include "phmech.h"

#define PHM_NSTATE 13 /* per carrier: q (4), p (3), t (6) */
#define PHM_MAXCON 6  /* constraint rows per pair, at most */

struct phm_model {
  int nc, ne, np, nl, ncons;
  phm_carrier_desc *car;
  phm_element_desc *el;
  phm_pair_desc *pair;
  int *pair_row;    /* first constraint row of each pair */
  int *pair_m;      /* constraint rows of each pair      */
  phm_load_desc *load;
  double gravity[3];
  double *bp;       /* sorted distinct breakpoints of all laws */
  int nbp;
  double *tables;   /* owned copies of the law tables */
  double lref;      /* length scale for finite differences, m */
};

/* Pair types: number of constraint rows and the constraint-wrench basis W^C (6 x m, frame Tb). */
typedef struct {
  const char *name;
  int m;
} phm_pair_type_info;
extern const phm_pair_type_info phm_pair_types[];
extern const int phm_npair_types;

/* Beam element: body wrenches on its nodes (wa, wb), elastic energy *V, dissipated power *P.
 * ta, tb may be NULL (no damping). */
void phm_element_eval(const phm_element_desc *e, const double Ha[16], const double Hb[16],
                      const double ta[6], const double tb[6], double wa[6], double wb[6],
                      double *V, double *P);

/* Pair ip: position constraint g (m), velocity blocks Ga, Gb (m x 6, row-major) such that the
 * velocity constraint is Ga ta + Gb tb = vt (m). Ha or Hb NULL = ground (identity). */
void phm_pair_eval(const phm_model *m, int ip, const double *Ha, const double *Hb, double time,
                   double tref, double *g, double *Ga, double *Gb, double *vt);

/* Applied wrenches (elastic + damping + gravity + external x scale) on every carrier, body frame:
 * wr (nc x 6). tw may be NULL (static). Optional outputs (may be NULL): elastic energy, dissipated
 * power, power supplied by external wrenches (needs tw). */
void phm_applied(const phm_model *m, const double *H, const double *tw, double time, double tref,
                 double scale, double *wr, double *Vel, double *Pdiss, double *Psupp);

/* Dense constraint data at poses H: g (ncons), G (ncons x 6nc), vt (ncons); any may be NULL. */
void phm_constraints_dense(const phm_model *m, const double *H, double time, double tref,
                           double *g, double *G, double *vt);

/* Pose <-> (q, p) and the retraction H exp(delta) on (q, p). */
void phm_qp_to_H(const double q[4], const double p[3], double H[16]);
void phm_H_to_qp(const double H[16], double q[4], double p[3]);
void phm_retract(double H[16], const double delta[6]);

/* tref for the interval [t, ...): midpoint between t and the next breakpoint (or t + 1). */
double phm_model_tref(const phm_model *m, double t, double *next_bp);

/* Min-norm least squares A x = b (A: rows x cols, row-major, overwritten); b has max(rows, cols)
 * entries and holds x on return; rank in *rank (may be NULL). Allocates; not for inner loops. */
phm_status phm_lstsq(int rows, int cols, double *A, double *b, int *rank, phm_error *err);

#endif
