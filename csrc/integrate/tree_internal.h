/* tree_internal.h -- the "tree" integrator (tree.c: its row, the Dormand-Prince run and the
 * outputs; tree_aba.c: the model's eligibility, the joint-coordinate kinematics and the
 * articulated-body algorithm). A rigid tree in joint coordinates: the same model as the DAE's
 * carrier equations M t' - ad*_t (M t) = wr + G^T lambda with every constraint row a tree joint's,
 * so the state is the joint coordinates q, their rates qd and the energy ledger's integrals. */
#ifndef PHM_TREE_INTERNAL_H
#define PHM_TREE_INTERNAL_H

#include "integrate.h"

#define TREE_MAXK 2 /* joint coordinates per pair, at most (cylindrical) */

typedef struct {
  const phm_model *m;
  int nb, nj, nled, N; /* bodies (= carriers), joint coordinates, ledger states, ODE states */
  /* the tree: carriers in an order where every parent comes before its children */
  int *order, *par, *pair, *k, *j0;
  double *S;          /* 6 TREE_MAXK per carrier: its joint's motion subspace in its body frame */
  /* its pair's local transform L = Ta h(q) Tb^-1 = K0 + cos(th) K1 + sin(th) K2 + d K3 (16 each,
   * 64 per carrier), the angle th = q[ti] (ti < 0: th = 0) and the slide d = ds q[di] (di < 0:
   * d = 0) of its joint coordinates (h = rotation th about z, translation d along z) */
  double *K, *ds;
  int *ti, *di;
  /* one evaluation (tree_eval); per carrier */
  double *H, *v, *cb, *X, *IA, *pA, *U, *Dinv, *u, *acc, *wr, *pport;
  /* the Runge-Kutta's vectors (N each) */
  double *y, *y1, *yt, *ks[7], *rc[5], *err;
  double *ydae;       /* the DAE's state of an output (d->n) */
  int *isrt;          /* scratch */
} tree_work;

/* tree_aba.c */
/* The model's eligibility for the tree integrator (PHM_EINVAL naming the reason) and, if it is
 * eligible, the tree's tables into w (allocated here; tree_free frees them). */
phm_status tree_build(const dae_t *d, tree_work *w, phm_error *err);
void tree_free(tree_work *w);
/* dY = f(t, Y): the poses, twists and accelerations of every body from the joint coordinates and
 * rates in Y (forward kinematics, the articulated-body algorithm) into w, the ledger's power
 * rates. 0, or 1 where a joint's articulated inertia is not positive. */
int tree_eval(tree_work *w, double t, double tref, const double *Y, double *dY);
/* After tree_eval at a state: every pair's multipliers lambda (least squares of G_b^T lambda =
 * the joint's wrench on its body b) into lam (ncons). */
void tree_lambda(tree_work *w, double t, double tref, const double *Y, double *lam);

#endif
