/* analyze.h -- the analyses of a model at a configuration (csrc/model/; not the DAE): the
 * linearization shared by modes and statics (linearize.c: generalized forces, their closed-form
 * Jacobian blocks, the sparse KKT matrix and its inertia), the modes (modes*.c), statics
 * (statics.c, static_free.c). */
#ifndef PHM_ANALYZE_H
#define PHM_ANALYZE_H

#include <klu.h>

#include "model.h"

/* ---------------------------------------------------------------- linearization (linearize.c) */
/* The linearization's data: the model, the point (time, load scale, multipliers) and the carrier
 * graph with its 6x6 blocks. Not the DAE's phm_data (csrc/dae/dae.h): an analysis needs none of
 * its buffers and the graph blocks are not among them, and dae_init costs 5-6 % of a modes call
 * (measured: docs/architecture.md, "One workspace per model?"). */
typedef struct {
  const phm_model *m;
  double time, tref, scale;
  const double *lam; /* constraint wrenches added to the forces (may be NULL) */
  /* carrier coupling graph (CSR) and the force Jacobian blocks (lin_graph; modes and statics) */
  int *ptr, *nbr;
  double *Kb;
  double *Mb; /* the mass in the same slots: carriers' inertias, consistent elements' couplings */
  double *sp; /* a steady rotation's (phm_model_set_spin) scratch: s_c, then (M s)_c (12 nc) */
  int comps;  /* statics: the components' efforts at rest (their states at z0, x scale) join the
               * forces and their stiffness the tangent (docs/method.md section 7.5) */
} lin_t;

/* L for model m (its graph and blocks: lin_graph). Allocates nothing (the four dense buffers it
 * allocated, ncons x 6 nc doubles among them, were never read); PHM_OK. */
phm_status lin_alloc(lin_t *L, const phm_model *m, phm_error *err);
/* The slot of block (row carrier r, column carrier c) in L's coupling graph (lin_graph), or -1
 * when they are not neighbours. */
int lin_slot(const lin_t *L, int r, int c);
void lin_free(lin_t *L);
/* The coupling graph of L's model, room for the force Jacobian blocks and the mass blocks Mb
 * (filled: they are constant). */
phm_status lin_graph(lin_t *L, phm_error *err);
/* Generalized forces at poses H: applied wrenches (x L->scale) + G^T L->lam (nc x 6, body frame). */
void lin_total_force(lin_t *L, const double *H, double *f);
/* Adds a steady rotation's centrifugal wrenches ad*_{s_c} (M s)_c (x L->scale) to f (nc x 6;
 * phm_model_set_spin; nothing without). */
void lin_spin_force(const lin_t *L, const double *H, double *f);
/* L->Kb[q] = d f_r / d delta_c for block q = (row carrier r, column carrier nbr[q]) of the
 * coupling graph, in closed form (lin_closed_form_blocks). */
void lin_force_jacobian_blocks(lin_t *L, const double *H);
/* Add the closed-form blocks at poses H (the se3 elements', gravity's, the pairs' G^T lambda, the
 * actuators', loads' and springs') to Kb (df/ddelta; if not NULL) and their twist derivatives to
 * Db (df/dt: the damping; if not NULL). */
void lin_closed_form_blocks(const lin_t *L, const double *H, double *Kb, double *Db);
/* A steady rotation's gyroscopic blocks (docs/method.md section 7.6) at poses H into Gb (36 per
 * graph slot, zeroed first): d f/d t of the inertial wrenches in the turning frame,
 * ad*_{t_c} (M t)_c - (M ad_t s)_c at t = s. Zero without spin. */
void lin_gyro_blocks(const lin_t *L, const double *H, double *Gb);
/* K (6 x 6, row-major, leading dimension 6) += Kw (ldk; NULL: none) - 1/2 ad*_(.) w: a
 * carrier's own block of f_c(delta) = dexp_{-delta}^T w_c(H_c exp(delta)) for a wrench w. */
void lin_add_own_block(double *K, const double *Kw, int ldk, const double w[6]);

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
/* lin_kkt_factor in steps: the values, then the factorization (0 on success, 1 if singular). */
void lin_kkt_values(lin_kkt_t *S, const double *Kb, const double *Gp);
int lin_kkt_refactor(lin_kkt_t *S);
/* Symmetric equilibration of S's values (three passes of Ruiz's: rows and columns divided by the
 * square root of their largest entry): S's matrix becomes diag(sc) KKT diag(sc), the same
 * inertia (a congruence) and KKT^-1 = diag(sc) S^-1 diag(sc). sc, work: n each. */
void lin_kkt_equilibrate(lin_kkt_t *S, double *sc, double *work);
/* x <- KKT^-1 x with the last factorization; 0 on success. */
int lin_kkt_solve(lin_kkt_t *S, double *x);
/* The inertia of the KKT matrix (Sylvester): a symmetric LDL' factorization without pivoting
 * (SuiteSparse's LDL) of P KKT P^T, P eliminating the carriers in AMD order of the carrier
 * graph and each constraint row right after the later of its pair's carriers (a row's zero
 * diagonal is then its Schur complement -g A^-1 g^T, not a zero pivot). */
typedef struct {
  int n, *P, *Pinv, *Lp, *Parent, *Lnz, *Li, *Flag, *Pattern; /* LDL's (ldl.h) */
  double *Lx, *D, *Y;
  int *Rp, *Rj;     /* L by rows (the residual's check) */
  double *Rx, *cs;
} lin_ldl_t;

/* The ordering and symbolic factorization of S's pattern (lin_kkt_build). */
phm_status lin_ldl_analyze(lin_ldl_t *F, const lin_t *L, const lin_kkt_t *S, phm_error *err);
void lin_ldl_free(lin_ldl_t *F);
/* The number of negative pivots of the LDL' factorization of S's values (S factored by
 * lin_kkt_factor: its KLU factors give the condition estimate), and in *check the certificate
 * ||E||_1 est(||KKT^-1||_1) of the factorization's residual E = P KKT P^T - L D L^T: the
 * computed inertia is exactly KKT + P^T E P's, and that is KKT's (Weyl: the symmetric E moves no
 * eigenvalue by more than ||E||_2 <= ||E||_1, and none is closer to 0 than 1/||KKT^-1||_2 >=
 * 1/||KKT^-1||_1) when *check < 1, up to the condition estimate's accuracy. Returns -1 (check
 * INFINITY) on a zero pivot. O(N) for the carriers' graphs, like the KLU factorization. */
int lin_ldl_negative(lin_ldl_t *F, lin_kkt_t *S, double *check);

/* The pairs' constraint Jacobian blocks at poses H: row r holds G_a in Gp[12 r ..] and G_b in
 * Gp[12 r + 6 ..] (12 per constraint row). */
void lin_constraint_blocks(const lin_t *L, const double *H, double *Gp);

/* ---------------------------------------------------------------- the reduction (reduce.c) */
/* The linearization at poses H shared by the modes and the linear port-Hamiltonian model: the
 * stiffness K = -df/ddelta and damping D = -df/dt as blocks on the carrier coupling graph
 * (closed form, csrc/analyze/linearize.c), and, for the dense path, their reduction to
 * the null space of the constraint Jacobian G. G touches only the carriers of the pairs, so the
 * null-space basis is Z = diag(U0, I): U0 from the SVD of G restricted to the constrained
 * carriers, identity on the free ones. Reduced coordinates: first the n0 null-space directions
 * of the constrained carriers (U0 = columns rank.. of U), then 6 per free carrier in carrier
 * order (red[c]: first index; -1 for a constrained carrier, cmap[c]: its place among them). */
typedef struct {
  lin_t L;
  double *H, *Db;           /* poses (nc x 16), damping blocks (36 per graph slot); K in L.Kb */
  int *cmap, *red;          /* constrained carriers' places, free carriers' first reduced index */
  int n6c, n0, nr;          /* constrained carriers' coordinates, their null space, reduced size */
  double *U;                /* n6c x n6c, column-major; U0 = U + rank n6c (column a contiguous) */
  const double *U0;
  double *Kr, *Dr, *Mr;     /* reduced stiffness, damping, mass (nr x nr, symmetrized) */
  double *Gb, *Gr;          /* a steady rotation's gyroscopic blocks and -Z^T Gb Z (not
                             * symmetrized; NULL without spin) */
} lin_red_t;

void lin_red_free(lin_red_t *R);
/* K and D blocks at poses (NULL: H0) with constraint wrenches lambda (NULL: none), loads at time. */
phm_status lin_red_blocks(lin_red_t *R, const phm_model *m, const double *poses,
                          const double *lambda, double time, phm_error *err);
/* The null space of G and the reduced Kr, Dr, Mr (symmetrized) from the blocks. */
phm_status lin_red_reduce(lin_red_t *R, const phm_model *m, phm_error *err);
/* x = Z y: a reduced vector y (nr) as carrier tangent coordinates x (6 nc). */
void lin_red_expand(const lin_red_t *R, int nc, const double *y, double *x);
/* y = Z^T f: carrier wrenches f (6 nc) as reduced generalized forces y (nr). */
void lin_red_project(const lin_red_t *R, int nc, const double *f, double *y);

/* ---------------------------------------------------------------- dense modes (modes.c) */
/* The nf (<= nr) lowest eigenpairs of Kr y = lambda Mr y (nr x nr, symmetric) into ev (nr) and Y
 * (nr x nf, column-major, unit modal mass), ascending: dsygvx on the pencil shift-inverted, the
 * unresolved modes on the direct one (modes.c). split: solved block by block on the connected
 * components of the coupling graph of Kr and Mr (entries below DBL_EPSILON sqrt(|X_aa X_bb|) do
 * not couple: modes.c's SPLIT_TOL), each block's nf lowest merged (a block whose solve fails:
 * the whole problem instead); 0: as one problem. *nblocks (may be NULL): the number of blocks
 * solved. */
phm_status modes_dense_eigs(int nr, const double *Kr, const double *Mr, int nf, int split,
                            double *ev, double *Y, int *nblocks, phm_error *err);

/* ---------------------------------------------------------------- sparse modes (modes_sparse.c) */
/* The nf lowest modes of R's blocks (lin_red_blocks) on the sparse path with a block of b
 * vectors, verified by the count of eigenvalues below its shift; *ok = 0: not verified and not
 * sliced (slice = 0), for the dense path to redo. PHM_ESINGULAR (no message): the KKT matrix at
 * the shift is singular. *stats: its iterations and shifts (phm_modes_stats; method not set). */
phm_status modes_sparse_path(lin_red_t *R, const phm_model *m, int nf, int b, int slice,
                             double *omega, double *zeta, double *shapes, int *ok,
                             phm_modes_stats *stats, phm_error *err);

#endif
