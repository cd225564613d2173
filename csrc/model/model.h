/* model.h -- the immutable model (struct phm_model) and the kernels every later stage reads:
 * pair types (csrc/model/pair_types.c), pairs (pair.c), the se3 beam element (element.c), applied wrenches (applied.c),
 * energy (energy.c), the coupling graph of carriers and pairs (graph.c). Private to csrc/ and the
 * C tests. */
#ifndef PHM_MODEL_H
#define PHM_MODEL_H

#include "phmech.h"

#define PHM_MAXCON 6 /* constraint rows per pair, at most */

struct phm_model {
  int nc, ne, np, nl, ncons, na, ns, nj, nport;
  phm_carrier_desc *car;
  phm_element_desc *el;
  unsigned char *el_damped; /* ne: the element's section damping D is not zero */
  int *car_u;       /* nc: the first carrier whose M, mass and com are bit-identical to this one's:
                     * the residual's inertia and gravity read those at car_u[c] (see el_sec) */
  int *el_ab;       /* 2 per element: its carriers a, b (el[i].a, .b, packed for the hot loops) */
  int *el_sec;      /* ne: the first element whose h, K, D and eps_hat are bit-identical to this
                     * one's (phm_model_share): the residual reads those from el[el_sec[i]], so a
                     * uniform mesh's loop reads one element's 2 kB, not N of them (measured:
                     * docs/perf_scaling.md, "Memory per step") */
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
  double *tables;   /* owned copies of the laws' tables (points, pieces, breakpoints) */
  phm_law *lawnodes; /* owned copies of the expression laws' nodes */
  double lref;      /* length scale for finite differences, m */
  int pair_general; /* 0 (phm_model_create): pairs through their closed forms and structural
                     * shortcuts (pair_types.c, pair.c); 1: the table's general path alone -- the C tests
                     * set it to compare the two                                           */
  int nmc;          /* mass couplings: the elements' (CONSISTENT or GIVEN, in element order),
                     * then the description's couplings without an element                */
  int *mc_a, *mc_b; /* nmc: the two carriers of each                                    */
  double *mc;       /* nmc x 144: their couplings Mc (phm_element_mass, or given), once  */
  unsigned short *mc_rows; /* nmc x 12: row i's nonzero columns j of Mc (bit j); a straight
                            * element's couple 40 of the 144 pairs of twist components       */
  int *mc_u;        /* nmc: the first coupling whose Mc is bit-identical to this one's: the hot
                     * loops read Mc and its rows at mc_u[k] (see el_sec)                   */
  int ncomp;        /* components with internal states (component.c), grouped by pair   */
  phm_component_desc *comp;
  int *comp_z;      /* ncomp: the first of its internal states among the nz                */
  int *pair_z, *pair_nz; /* np: the first internal state of the pair's components, and their count */
  int nz;           /* internal states of all components                                 */
  int has_spin;     /* the analyses about a steady rotation (phm_model_set_spin)          */
  double spin[6];   /* its world twist S (omega, v at the world origin); zero: none       */
};

/* Coupling k's Mc and its rows as the hot loops read them: the first bit-identical one's. */
static inline const double *phm_mc(const phm_model *m, int k) { return m->mc + 144 * (size_t)m->mc_u[k]; }
static inline const unsigned short *phm_mc_rows(const phm_model *m, int k) {
  return m->mc_rows + 12 * (size_t)m->mc_u[k];
}

/* tref for the interval [t, ...): midpoint between t and the next breakpoint (or t + 1). */
double phm_model_tref(const phm_model *m, double t, double *next_bp);

/* ---------------------------------------------------------------- pair types (pair_types.c) */
/* Kinematics of a pair type at relative pose h (docs/method.md section 4): position constraints
 * g (m), constraint-wrench basis W (6 x 6 row-major, first m columns used), dual effort basis Phi
 * (6 x 6, first k columns), joint coordinates x (k), angles nearest xref (NULL: principal
 * values). Any output may be NULL. Fixed pairs: g = log(h). */
void phm_pair_kin(int type, double pitch, const double h[16], const double *xref, double *g,
                  double *W, double *Phi, double *x);
/* The same with derivatives along the body perturbations of h, h exp(eta) (eta = (omega, v)):
 * Dg (6 per constraint row), DW and DPhi (6 per entry of the 6x6 bases: d B[e]/d eta_j at
 * 6 e + j), Dx (6 per joint coordinate); any may be NULL (all NULL: phm_pair_kin). */
void phm_pair_kin_tangent(int type, double pitch, const double h[16], const double *xref,
                          double *g, double *W, double *Phi, double *x, double *Dg, double *DW,
                          double *DPhi, double *Dx);

/* phm_pair_kin_tangent through the table's general switch (forward-mode pq) for every type,
 * without the closed forms phm_pair_kin_tangent takes for some: what the C tests compare them
 * against. */
void phm_pair_kin_general(int type, double pitch, const double h[16], const double *xref,
                          double *g, double *W, double *Phi, double *x, double *Dg, double *DW,
                          double *DPhi, double *Dx);

/* The kinematics of a type as a model's pair evaluates it (pair.c): the closed form where the
 * type has one (general = 0), else the table's switch. DW, DPhi of a closed form with constant
 * bases are zero-filled, or, with constant (not NULL), left as they are and *constant = 1 (the
 * pair's rows then skip them). phm_pair_kin_tangent is this with general = 0, constant NULL. */
void phm_pair_kin_eval(int general, int type, double pitch, const double h[16],
                       const double *xref, double *g, double *W, double *Phi, double *x, double *Dg,
                       double *DW, double *DPhi, double *Dx, int *constant);

/* ---------------------------------------------------------------- pairs (pair.c) */
/* Constraint rows of a pair before any is dropped: its type's m, plus one per joint coordinate
 * that follows a law (xdriven; those rows come after the type's, in coordinate order). */
int phm_pair_rows_full(const phm_pair_desc *pr);

/* Frames of pair ip at carrier poses Ha, Hb (NULL = ground): relative pose h = F_a^-1 F_b,
 * AdTbi = Ad_{Tb^-1}, AdBa = Ad_{F_b^-1 H_a} (either may be NULL), so that the relative twist is
 * t_rel = AdTbi t_b - AdBa t_a (in F_b). */
void phm_pair_frames(const phm_model *m, int ip, const double *Ha, const double *Hb, double h[16],
                     double AdTbi[36], double AdBa[36]);
/* t_rel = AdTbi tb - AdBa ta (ta, tb NULL = at rest). */
void phm_pair_rel_twist(const double AdTbi[36], const double AdBa[36], const double *ta,
                        const double *tb, double tr[6]);

/* What one evaluation of pair ip at one state yields (phm_pair_evaluate): its frames, its kept
 * constraint rows and its joint coordinates. The DAE keeps one per pair in its per-evaluation
 * data (phm_data in csrc/dae/dae.h), filled once per residual and read by the pair rows, the
 * actuators (phm_applied_pairs) and the outputs, which otherwise would each recompute the frames
 * and kinematics. */
typedef struct {
  double h[16];                  /* relative pose F_a^-1 F_b                                     */
  double AdBa[36];               /* Ad_{F_b^-1 H_a}: t_rel = AdTbi t_b - AdBa t_a, with AdTbi =
                                  * Ad_{Tb^-1} of the model (pair_AdTbi)                         */
  double g[PHM_MAXCON];          /* position constraints (m kept rows)                            */
  double Ga[6 * PHM_MAXCON], Gb[6 * PHM_MAXCON]; /* velocity blocks (m x 6, row-major)            */
  double vt[PHM_MAXCON];         /* prescribed rates of the velocity constraints                  */
  double W[36];                  /* constraint-wrench basis (6 x 6 row-major, first m columns);
                                  * a pair driven by a motion: at its prescribed pose (driven pairs
                                  * are fixed ones, whose basis is the identity at any pose); a
                                  * driven joint coordinate c: Phi's column c                      */
  double Phi[36];                /* dual effort basis (6 x 6 row-major, first k columns)          */
  double x[6], xdot[6];          /* joint coordinates and rates (first k)                         */
} phm_pair_data;

/* What phm_pair_evaluate fills besides the frames (h, AdBa), as bit flags. */
enum {
  PHM_PAIR_ROWS = 1, /* the constraint rows g, Ga, Gb, vt, W                                    */
  PHM_PAIR_JOINT = 2, /* the joint coordinates x, their effort basis Phi and rates xdot         */
  PHM_PAIR_NO_G = 4   /* with ROWS: not g (left as it was), unless the pair is driven by a motion */
};

/* Evaluate pair ip at carrier poses Ha, Hb (NULL = ground) and twists ta, tb (NULL = at rest) into
 * *pd: its frames and, as `what` asks (PHM_PAIR_ROWS | PHM_PAIR_JOINT), its constraint rows at
 * (time, tref) (g, Ga, Gb, vt, W; the same numbers as phm_pair_eval) and its joint coordinates x
 * (nearest the branch references xref, k values; NULL: the model's x0), Phi and rates xdot; the
 * fields not asked for are left as they were. The kinematics of the pair type is evaluated once
 * for both (twice for a pair driven by a motion with its joint asked for: g at the prescribed
 * pose, x at h). The rows alone serve the generalized-alpha's constraint rows at the step's end,
 * which read neither coordinates nor rates (csrc/dae/residual.c, dae_constraint_rows). */
void phm_pair_evaluate(const phm_model *m, int ip, const double *Ha, const double *Hb,
                       const double *ta, const double *tb, const double *xref, double time,
                       double tref, int what, phm_pair_data *pd);

/* The closed-form tangent of pair ip's kept rows and joint (docs/method.md section 4.3) at poses
 * Ha, Hb (NULL = ground) and twists ta, tb (NULL = at rest), for the perturbations Ha exp(da),
 * Hb exp(db), columns [da; db] (12, row-major): dg (mc x 12) of the position constraints, dc
 * (mc x 12) of the velocity constraints Ga ta + Gb tb - vt at fixed twists, dx (k x 12) of the
 * joint coordinates, dxd (k x 12) of the joint rates Phi^T t_rel at fixed twists, Kl (12 x 12)
 * of the constraint wrenches [Ga^T lam; Gb^T lam] on (a, b) for multipliers lam (mc), Km the
 * same for mu (their geometric stiffness), Ku (12 x 12) of the effort wrenches
 * [-AdBa^T Phi u; AdTbi^T Phi u] (phm_pair_effort_wrench) at fixed efforts u (k). Outputs may be
 * NULL (Kl, Km, Ku also when lam, mu, u are). pd (may be NULL) gets the evaluation
 * phm_pair_evaluate would give with rows. No allocation. */
void phm_pair_tangent(const phm_model *m, int ip, const double *Ha, const double *Hb,
                      const double *ta, const double *tb, const double *xref, double time,
                      double tref, const double *lam, const double *mu, const double *u,
                      phm_pair_data *pd, double *dg, double *dc, double *dx, double *dxd,
                      double *Kl, double *Km, double *Ku);

/* Pair ip: position constraint g (m), velocity blocks Ga, Gb (m x 6, row-major) such that the
 * velocity constraint is Ga ta + Gb tb = vt (m). Ha or Hb NULL = ground (identity). xref: branch
 * reference of this pair's joint coordinates (k values; NULL: the model's x0). */
void phm_pair_eval(const phm_model *m, int ip, const double *Ha, const double *Hb,
                   const double *xref, double time, double tref, double *g, double *Ga,
                   double *Gb, double *vt);
/* The same for every row of the pair, dropped ones included (phm_pair_rows_full of them), with
 * its whole constraint-wrench basis W (6 x 6, may be NULL). */
void phm_pair_eval_full(const phm_model *m, int ip, const double *Ha, const double *Hb,
                        const double *xref, double time, double tref, double *g, double *Ga,
                        double *Gb, double W[36]);
/* Joint coordinates x and rates xdot (k each; xdot needs ta/tb, NULL = at rest) of pair ip. */
void phm_pair_joint(const phm_model *m, int ip, const double *Ha, const double *Hb,
                    const double *ta, const double *tb, const double *xref, double *x,
                    double *xdot);
/* Constraint wrench W^C lambda (6, frame F_b) of pair ip for its multipliers lam (m), from its
 * evaluation pd (phm_pair_evaluate with rows). */
void phm_pair_wrench(const phm_model *m, int ip, const phm_pair_data *pd, const double *lam,
                     double w[6]);
/* Pair constraints g (ncons), their Jacobian G (ncons x n, row-major; carrier c's 6 columns at
 * 6 cmap[c], or 6 c when cmap is NULL) and prescribed rates vt; any output may be NULL. */
void phm_constraints_columns(const phm_model *m, const double *H, const double *xs, double time,
                             double tref, const int *cmap, int n, double *g, double *G,
                             double *vt);
/* The same with every carrier's columns (n = 6 nc). */
void phm_constraints_dense(const phm_model *m, const double *H, const double *xs, double time,
                           double tref, double *g, double *G, double *vt);
/* f += G^T lam: the constraint wrenches of multipliers lam (ncons) on every carrier (nc x 6). */
void phm_constraint_forces(const phm_model *m, const double *H, double time, double tref,
                           const double *lam, double *f);

/* ---------------------------------------------------------------- se3 beam element (element.c) */
/* Body wrenches on its nodes (wa, wb), elastic energy *V, dissipated power *P, stress resultant
 * sigma (6; any of V, P, sigma may be NULL). ta, tb may be NULL (no damping). */
void phm_element_eval(const phm_element_desc *e, const double Ha[16], const double Hb[16],
                      const double ta[6], const double tb[6], double wa[6], double wb[6],
                      double *V, double *P, double *sigma);
/* Its elastic energy alone (phm_element_eval's *V, the same number, without the wrenches). */
double phm_element_energy(const phm_element_desc *e, const double Ha[16], const double Hb[16]);
/* phm_model_energy (phmech.h) with each element's strain energy in Ve (ne; NULL: not wanted),
 * the parts e[1] sums, in the order it sums them: the outputs' strain_energy at no extra log */
void phm_model_energy_parts(const phm_model *m, const double *H, const double *t, double e[3],
                            double *Ve);

/* The element's wrenches (as phm_element_eval) and their tangent: Kx (12 x 12, row-major) =
 * d[wa; wb]/d[da; db] for the perturbations Ha exp(da), Hb exp(db) (elastic, geometric and, with
 * twists, damping parts), Ct (12 x 12) = d[wa; wb]/d[ta; tb] (zero without twists; may be NULL).
 * Closed form, no allocation (docs/method.md section 4.2). */
void phm_element_tangent(const phm_element_desc *e, const double Ha[16], const double Hb[16],
                         const double ta[6], const double tb[6], double wa[6], double wb[6],
                         double Kx[144], double Ct[144]);

/* A mass coupling Mc (phm_element_mass) in the momentum balances of its element's nodes a, b:
 * f = [(Mc t')_a - ad*_{t_a} (Mc t)_a; (Mc t')_b - ad*_{t_b} (Mc t)_b] (12) at twists ta, tb and
 * their rates dta, dtb, and (Kt not NULL) Kt = df/d[ta; tb] + cj df/d[dta; dtb] (12 x 12).
 * rows: Mc's nonzero pattern (phm_model.mc_rows; phm_mass_rows). */
void phm_element_inertia(const double Mc[144], const unsigned short rows[12], const double ta[6],
                         const double tb[6], const double dta[6], const double dtb[6], double cj,
                         double f[12], double Kt[144]);
/* Its kinetic energy 1/2 [ta; tb]^T Mc [ta; tb]. */
double phm_element_kinetic(const double Mc[144], const unsigned short rows[12], const double ta[6],
                           const double tb[6]);
/* rows[i] = the columns j of row i where Mc is not zero, as bits. */
void phm_mass_rows(const double Mc[144], unsigned short rows[12]);

/* ---------------------------------------------------------------- applied wrenches (applied.c) */
/* Applied wrenches (elastic + damping + gravity + springs + actuators + external x scale) on every
 * carrier, body frame: wr (nc x 6). tw may be NULL (static: rates zero). xs: joint-coordinate
 * branch references (nj; NULL: the model's x0). Optional outputs (may be NULL): elastic energy,
 * dissipated power, power supplied by external wrenches and actuators (needs tw), the power of
 * every port (nport, needs tw), the actuator efforts summed per joint coordinate (nj). Effort
 * sources, loads and gravity are scaled by `scale`; springs and PD actuators are not. */
void phm_applied(const phm_model *m, const double *H, const double *tw, const double *xs,
                 double time, double tref, double scale, double *wr, double *Vel, double *Pdiss,
                 double *Psupp, double *Pport, double *effort);
/* The same with every pair already evaluated at H, tw, xs (pd: np results of phm_pair_evaluate):
 * the actuators read their pair's frames, joint coordinates and rates from pd. pd NULL:
 * phm_applied, which evaluates the actuated pairs itself. */
void phm_applied_pairs(const phm_model *m, const phm_pair_data *pd, const double *H,
                       const double *tw, const double *xs, double time, double tref, double scale,
                       double *wr, double *Vel, double *Pdiss, double *Psupp,
                       double *Pport, double *effort);
/* One component's wrenches w (12: on carrier ca, then on cb; -1 = none, those entries zero) and
 * their closed-form derivatives Kx = d w/d[da; db] for Hca exp(da), Hcb exp(db) and Kt =
 * d w/d[t_ca; t_cb] (12 x 12 row-major each; Kt NULL: none), handed to a sink by
 * phm_applied_tangent. */
typedef void (*phm_tangent_sink)(void *ctx, int ca, int cb, const double w[12],
                                 const double Kx[144], const double Kt[144]);
/* The closed-form tangent of the applied wrenches without their own tangent kernel -- actuators
 * (through phm_pair_tangent), loads and interactions, spring-dampers (docs/method.md sections
 * 4.4-4.6) --, one sink call per component, at the state of phm_applied_pairs (pd may be NULL; tw
 * NULL: at rest; efforts and loads x scale). Elements and gravity: phm_element_tangent,
 * phm_gravity_tangent. No allocation. */
void phm_applied_tangent(const phm_model *m, const phm_pair_data *pd, const double *H,
                         const double *tw, const double *xs, double time, double tref,
                         double scale, phm_tangent_sink sink, void *ctx);
/* Gravity (x scale) on carrier c at pose Hc: its body wrench w and w's derivative Kg (6 x 6,
 * row-major, may be NULL) for Hc exp(delta) (docs/method.md section 4.6). */
void phm_gravity_tangent(const phm_model *m, int c, const double Hc[16], double scale, double w[6],
                         double Kg[36]);
/* Adds to wr (nc x 6) the wrenches of joint efforts u (k) on pair ip evaluated in p: Phi u on
 * carrier b (through Ad_{Tb^-1}^T), its reaction on carrier a (through AdBa^T). */
void phm_pair_effort_wrench(const phm_model *m, int ip, const phm_pair_data *p, const double *u,
                            double *wr);
/* Adds to wr (nc x 6; NULL: only returns them) load il's wrench at poses H, s times its vector
 * (the law's value s): w on its carrier (body frame, also returned in w) and, for an
 * interaction, the opposite wrench on its reaction carrier (returned in wre, its body frame;
 * zero without reaction). */
void phm_load_wrench(const phm_model *m, int il, const double *H, double s, double *wr,
                     double w[6], double wre[6]);
/* The change of the powers of the actuators and loads (as phm_applied_pairs counts them, scale 1)
 * for a change dtw (nc x 6) of the twists at the poses H and the pairs' evaluation pd: exact in
 * the twists (an actuator's u(x, xdot) . xdot is quadratic in them through a PD's or a joint
 * spring's damping, a load's w . t linear); u's dependence on x, which moves by about h xdot
 * (kp h / kd of it), and a world load's turn with the pose are left out. Added to *dPs (the
 * supplied power) and per port into dPport[0 .. na + nl) (actuators, then loads): what the
 * energy ledger's Newton rows leave out (dae_ledger_dpower). No allocation. */
void phm_applied_dpower(const phm_model *m, const phm_pair_data *pd, const double *H,
                        const double *dtw, double time, double tref, double *dPs,
                        double *dPport);
/* Point-to-point spring-damper: adds its wrenches to wr (may be NULL), elastic energy *V and
 * damping power *Pd (>= 0; either may be NULL). tw NULL: at rest. */
void phm_spring_eval(const phm_spring_desc *sp, const double *H, const double *tw, double *wr,
                     double *V, double *Pd);

/* ---------------------------------------------------------------- components (component.c) */
/* Set-up (phm_model_create): the description's components checked (ModelError-like messages
 * naming the component), copied into m grouped by pair (comp_z, pair_z, pair_nz, nz; -1 when out
 * of memory), the count of the motors' rotor inertias between two carriers (mass couplings), and
 * the rotor inertias J n^2 added: to the carrier's inertia when the pair's other side is the
 * ground, else as the mass couplings from index k0 on. */
phm_status phm_components_validate(const phm_model_desc *d, phm_error *err);
int phm_components_copy(phm_model *m, const phm_model_desc *d);
int phm_components_ncouplings(const phm_model_desc *d);
void phm_components_inertia(phm_model *m, int k0);
/* Internal states of a component of its kind (and motor input). */
int phm_component_nstates(const phm_component_desc *c);
/* One component's constitutive law at its coordinate's x, v = xdot and its states z: effort u,
 * rates f (z' = f), stored energy V, dissipated and supplied power Pd, Ps, and (deriv != 0) their
 * derivatives in x, v and z (docs/method.md section 4.11). No allocation. */
typedef struct {
  double u, du_x, du_v, du_z[PHM_COMP_MAXZ];
  double f[PHM_COMP_MAXZ], df_x[PHM_COMP_MAXZ], df_v[PHM_COMP_MAXZ];
  double df_z[PHM_COMP_MAXZ * PHM_COMP_MAXZ]; /* row-major: d f_i / d z_j at MAXZ i + j      */
  double V, Pd, Ps;
} phm_comp_eval;
void phm_component_eval(const phm_component_desc *c, double x, double v, const double *z,
                        double time, double tref, phm_comp_eval *e);
/* Every component at the pairs' evaluation pd (NULL: evaluated here at H, tw, xs) and states z
 * (nz; NULL: the model's z0): adds its wrench to wr (nc x 6, may be NULL) and its effort to
 * effort (nj, may be NULL), its rows z' - f into Fz (nz, with zp; may be NULL), and its stored
 * energy, dissipated and supplied power to *V, *Pd, *Ps (may be NULL). No allocation. */
void phm_components_apply(const phm_model *m, const phm_pair_data *pd, const double *H,
                          const double *tw, const double *xs, const double *z, const double *zp,
                          double time, double tref, double *wr, double *effort, double *Fz,
                          double *V, double *Pd, double *Ps);
/* Component ic's closed-form tangent at pair evaluation pd and states z: its wrenches w (12: on
 * its pair's a, b) = B u, Ku = dw/d[da; db] at fixed u (12 x 12), B (12), and u's derivatives in
 * the measured pair's carriers (its own, or a controller's sensor pair): gq = du/d[da; db], gt =
 * du/d[ta; tb] (12 each), Kz = dw/dz (12 x nzc, row-major); of its rates f, in the measured
 * pair's carriers: Fx = df/d[da; db], Ft = df/d[ta; tb] (nzc x 12), and Fz = df/dz (nzc x nzc).
 * No allocation. */
void phm_component_tangent(const phm_model *m, int ic, const phm_pair_data *pd, const double *H,
                           const double *tw, const double *xs, const double *z, double time,
                           double tref, double w[12], double Ku[144], double B[12], double gq[12],
                           double gt[12], double *Kz, double *Fx, double *Ft, double *Fz);
/* The coupling-graph edges (ea[k], eb[k]) of the controllers that measure another pair than
 * they drive: the driven pair's carriers with the sensed pair's, and (pairs != 0) the driven
 * pair's vertex (nc + pair) with the sensed carriers; their count (ea NULL: only counted). */
int phm_components_sensor_edges(const phm_model *m, int *ea, int *eb, int pairs);

/* ---------------------------------------------------------------- coupling graph (graph.c) */
/* The coupling graph (CSR) of the model's carriers and, with pairs != 0, of its pairs too:
 * vertices 0..nc-1 are the carriers, nc + ip pair ip. Two carriers are neighbours when they share
 * an element, pair, spring or load (a perturbation of carrier c changes only the forces of its
 * neighbours); a pair is the neighbour of its carriers (its multipliers and joint coordinates
 * couple to their states only). Every vertex lists itself first, then its neighbours once each,
 * in the order of the components that couple them (elements, pairs, loads, springs, then pair
 * vertices). Time and memory linear in the number of components. Allocates *ptr_out (vertices
 * + 1) and *nbr_out. */
phm_status phm_carrier_graph(const phm_model *m, int pairs, int **ptr_out, int **nbr_out,
                             phm_error *err);

#endif
