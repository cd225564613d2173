/* model_internal.h -- private to model.c, dae.c, linearize.c and the C unit tests. */
#ifndef PHM_MODEL_INTERNAL_H
#define PHM_MODEL_INTERNAL_H

#include "phmech.h"

#define PHM_NSTATE 13 /* per carrier: q (4), p (3), t (6) */
#define PHM_MAXCON 6  /* constraint rows per pair, at most */

struct phm_model {
  int nc, ne, np, nl, ncons, na, ns, nj, nport;
  phm_carrier_desc *car;
  phm_element_desc *el;
  phm_pair_desc *pair;
  int *pair_row;    /* first constraint row of each pair */
  int *pair_m;      /* constraint rows of each pair      */
  int *pair_j;      /* first joint coordinate of each pair */
  int *pair_k;      /* joint coordinates of each pair    */
  int *pair_sel;    /* 6 per pair: the type's row index of each kept constraint row (drop mask) */
  int *pair_rowf;   /* first row of each pair in the full (undropped) constraint set */
  double *pair_AdTbi; /* 36 per pair: Ad of the inverse of frame b's fixed offset Tb (row-major) */
  int ncons_full;   /* constraint rows before dropping redundant ones */
  double *xref0;    /* nj: branch references (x0 or 0) for statics, modes and the start */
  phm_actuator_desc *act;
  phm_spring_desc *spr;
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
} phm_pair_type_info; /* k = 6 - m */
extern const phm_pair_type_info phm_pair_types[];
extern const int phm_npair_types;

/* Beam element: body wrenches on its nodes (wa, wb), elastic energy *V, dissipated power *P.
 * ta, tb may be NULL (no damping). */
void phm_element_eval(const phm_element_desc *e, const double Ha[16], const double Hb[16],
                      const double ta[6], const double tb[6], double wa[6], double wb[6],
                      double *V, double *P);

/* Kinematics of a pair type at relative pose h (DESIGN section 4; see phm_pair_type): position
 * constraints g (m), constraint-wrench basis W (6 x 6 row-major, first m columns used), dual effort
 * basis Phi (6 x 6, first k columns), joint coordinates x (k), angles nearest xref (NULL: principal
 * values). Any output may be NULL. Fixed pairs: g = log(h). */
void phm_pair_kin(int type, double pitch, const double h[16], const double *xref, double *g,
                  double *W, double *Phi, double *x);

/* Pair ip: position constraint g (m), velocity blocks Ga, Gb (m x 6, row-major) such that the
 * velocity constraint is Ga ta + Gb tb = vt (m). Ha or Hb NULL = ground (identity). xref: branch
 * reference of this pair's joint coordinates (k values; NULL: the model's x0). */
void phm_pair_eval(const phm_model *m, int ip, const double *Ha, const double *Hb,
                   const double *xref, double time, double tref, double *g, double *Ga,
                   double *Gb, double *vt);

/* Joint coordinates x and rates xdot (k each; xdot needs ta/tb, NULL = at rest) of pair ip. */
void phm_pair_joint(const phm_model *m, int ip, const double *Ha, const double *Hb,
                    const double *ta, const double *tb, const double *xref, double *x,
                    double *xdot);

/* Constraint wrench W^C lambda (6, frame F_b) of pair ip for its multipliers lam (m). */
void phm_pair_wrench(const phm_model *m, int ip, const double *Ha, const double *Hb,
                     const double *xref, double time, double tref, const double *lam, double w[6]);

/* Applied wrenches (elastic + damping + gravity + springs + actuators + external x scale) on every
 * carrier, body frame: wr (nc x 6). tw may be NULL (static: rates zero). xs: joint-coordinate
 * branch references (nj; NULL: the model's x0). Optional outputs (may be NULL): elastic energy,
 * dissipated power, power supplied by external wrenches and actuators (needs tw), the power of
 * every port (nport, needs tw), the actuator efforts summed per joint coordinate (nj). Effort
 * sources and loads are scaled by `scale`; springs and PD actuators are not. */
void phm_applied(const phm_model *m, const double *H, const double *tw, const double *xs,
                 double time, double tref, double scale, double *wr, double *Vel, double *Pdiss,
                 double *Psupp, double *Pport, double *effort);

/* Dense constraint data at poses H (xs: joint branch references, NULL = x0): g (ncons), G (ncons x 6nc), vt (ncons); any may be NULL. */
/* Pair constraints g (ncons), their Jacobian G (ncons x n, row-major; carrier c's 6 columns at
 * 6 cmap[c], or 6 c when cmap is NULL) and prescribed rates vt; any output may be NULL. */
void phm_constraints_columns(const phm_model *m, const double *H, const double *xs, double time,
                             double tref, const int *cmap, int n, double *g, double *G,
                             double *vt);
void phm_constraints_dense(const phm_model *m, const double *H, const double *xs, double time,
                           double tref, double *g, double *G, double *vt);

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
