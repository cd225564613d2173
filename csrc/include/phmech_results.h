/* phmech_results.h -- what a simulation hands back: THE table of result quantities and the
 * caller-allocated output phm_sim_output (included by phmech_types.h). */
#ifndef PHMECH_RESULTS_H
#define PHMECH_RESULTS_H

/* ---------------------------------------------------------------- result quantities
 * THE table of what a simulation hands back at each output, one row per array:
 *   X(NAME, name, over, item, unit, noun, text)
 * From it come phm_sim_output's member `name`, the position PHM_RESULT_NAME, the array's name
 * and shape in Python (csrc/util/codes.c, csrc/pyext/py_simulate.c, phmech._core.result_fields),
 * the finite check (csrc/dae/output.c) and the SimulationResult attribute with its netCDF
 * variable (python/phmech/results.py, _resultfile.py). One output of an array holds one `item`
 * per entry of `over` (phm_result_shape, csrc/dae/output.c); `unit`, and `text` (one line: the
 * docstring and the netCDF long_name) say what it holds, `noun` names it in messages. A new
 * quantity: its row here and the code that fills it in record() of csrc/dae/output.c. */
#define PHM_RESULT_FIELDS(X)                                                                         \
  X(POSES, poses, PHM_OVER_RECORDED, PHM_ITEM_POSE, "1 (rotation), m (translation)", "poses",         \
    "world pose of each carrier frame (4x4 homogeneous)")                                            \
  X(TWISTS, twists, PHM_OVER_RECORDED, PHM_ITEM_SCREW, "rad/s (ang), m/s (lin)", "twists",            \
    "body twist (omega, v)")                                                                          \
  X(CONSTRAINT_WRENCHES, constraint_wrenches, PHM_OVER_CONSTRAINTS, PHM_ITEM_SCALAR, "N m or N",      \
    "constraint wrenches", "constraint multipliers")                                                  \
  X(ENERGY, energy, PHM_OVER_ENERGIES, PHM_ITEM_SCALAR, "J", "energies",                              \
    "energies and the energy ledger residual")                                                        \
  X(JOINTS, joints, PHM_OVER_JOINTS, PHM_ITEM_SCALAR, "rad or m (joint_unit)", "joint coordinates",   \
    "joint coordinates")                                                                              \
  X(JOINT_RATES, joint_rates, PHM_OVER_JOINTS, PHM_ITEM_SCALAR, "rad/s or m/s (joint_unit per s)",    \
    "joint rates", "joint rates")                                                                     \
  X(EFFORTS, efforts, PHM_OVER_JOINTS, PHM_ITEM_SCALAR, "N m or N", "actuator efforts",               \
    "actuator efforts on the joint coordinates")                                                      \
  X(PAIR_WRENCHES, pair_wrenches, PHM_OVER_PAIRS, PHM_ITEM_SCREW, "N m (ang), N (lin)",               \
    "pair wrenches", "constraint wrench on frame b of each pair, in F_b")                             \
  X(PORT_ENERGY, port_energy, PHM_OVER_PORTS, PHM_ITEM_SCALAR, "J", "port energies",                  \
    "energy supplied through each port")                                                              \
  X(COMPONENTS, components, PHM_OVER_COMPONENT_STATES, PHM_ITEM_SCALAR, "A, m, rad, ...",             \
    "component states", "components' internal states")                                                \
  X(CONSTRAINT_RESIDUAL, constraint_residual, PHM_OVER_PAIRS, PHM_ITEM_SCALAR, "rad or m (per row)",  \
    "constraint residuals", "largest position constraint residual abs(g) of each pair's kept rows") \
  X(STRAIN_ENERGY, strain_energy, PHM_OVER_ELEMENTS, PHM_ITEM_SCALAR, "J", "strain energies",         \
    "elastic strain energy of each beam element (the links' elements in the order added, each "       \
    "link's from its start); with the springs' and components' they sum to energy['elastic']")

/* What one output's entries of a result array run over; their count: phm_result_shape. */
typedef enum {
  PHM_OVER_RECORDED,         /* the recorded carriers (phm_sim_output.record; all: ncarriers)  */
  PHM_OVER_CONSTRAINTS,      /* the DAE's constraint rows (phm_model_nconstraints)             */
  PHM_OVER_ENERGIES,         /* the PHM_NENERGY energies                                        */
  PHM_OVER_JOINTS,           /* the joint coordinates of all pairs (phm_model_njoints)          */
  PHM_OVER_PAIRS,            /* the pairs                                                       */
  PHM_OVER_PORTS,            /* the ports (phm_model_nports)                                    */
  PHM_OVER_COMPONENT_STATES, /* the components' internal states (phm_model_ncompstates)        */
  PHM_OVER_ELEMENTS          /* the beam elements (phm_model_nelements)                         */
} phm_result_over;
/* What each entry is. */
typedef enum {
  PHM_ITEM_SCALAR, /* one number                                        */
  PHM_ITEM_SCREW,  /* 6: a twist (omega, v) or a wrench (tau, f), angular first */
  PHM_ITEM_POSE    /* 4x4, row-major                                    */
} phm_result_item;

/* The arrays' positions, in the table's order. */
enum {
#define PHM_RESULT_ENUM(NAME, name, over, item, unit, noun, text) PHM_RESULT_##NAME,
  PHM_RESULT_FIELDS(PHM_RESULT_ENUM)
#undef PHM_RESULT_ENUM
  PHM_NRESULT_FIELDS
};

/* One row of the table (phm_result_field_at, csrc/util/codes.c). */
typedef struct {
  const char *name, *unit, *noun, *text;
  phm_result_over over;
  phm_result_item item;
} phm_result_field;

/* Caller-allocated output for nout times (arrays may be NULL to skip). */
typedef struct {
  const int *record; /* carriers stored in poses/twists, in this order; NULL: all, nrecord = nc */
  int nrecord;
  /* The arrays, [nout][one output's shape] (PHM_RESULT_FIELDS above; e.g. pair_wrenches
   * [nout][npairs][6]): by name (out->joints) or by position (out->field[PHM_RESULT_JOINTS]). */
  union {
    struct {
#define PHM_RESULT_MEMBER(NAME, name, over, item, unit, noun, text) double *name;
      PHM_RESULT_FIELDS(PHM_RESULT_MEMBER)
#undef PHM_RESULT_MEMBER
    };
    double *field[PHM_NRESULT_FIELDS];
  };
  int nout_done;   /* outputs filled                                    */
  long nsteps, nres, njac, nniters, netf, nncf; /* integrator statistics (IDA or GALPHA) */
  long nfloor;     /* adaptive GALPHA: steps accepted above the tolerance (at the refinement's
                    * limit, 1/(PHM_REFINE_MAX PHM_BAND_STEPS band))                  */
  double err_ratio, t_err_ratio; /* adaptive GALPHA: the largest error estimate of an accepted
                    * step over its tolerance (per unit step: <= 1 keeps the contract) and
                    * the time that step ended [s]                                      */
  double min_step; /* adaptive GALPHA: the shortest step taken [s]                      */
  long nnoise;     /* adaptive GALPHA: steps accepted with an estimate above the tolerance
                    * per unit step but at the level of Newton's noise (galpha.c)         */
  double err_est;  /* adaptive GALPHA: sum over steps of the max-norm local error estimate of
                    * the configuration (m, rad-like units): a bound of the global error
                    * without error propagation                                       */
  double err_sum;  /* adaptive GALPHA: sum over steps of the local error estimate in tolerances
                    * (WRMS, weights rtol |y| + atol): the accumulated error without error
                    * propagation, <= 1 when the contract holds (Newton's noise-accepted
                    * steps included: a systematic Newton error adds up step after step) */
  double err_sum_max; /* adaptive GALPHA: sum over steps of the largest state's local error
                    * estimate in its own tolerance: a bound on any one configuration state's
                    * accumulated error without error propagation (err_sum averages each step's
                    * over every state, idle ones included)                              */
  double glob_err, t_glob_err; /* adaptive GALPHA: the largest global error estimate over the
                    * run (the local estimates propagated along the linearized steps,
                    * csrc/integrate/galpha_global.c), in tolerances (max over the
                    * configuration states of |e| / (rtol max|y| + atol)), when [s], and
                    * that state's index in the DAE's state vector (-1 with flexible links:
                    * not estimated)                                                    */
  long glob_state;
  double glob_err_abs, glob_scale; /* adaptive GALPHA: at that estimate, the state's estimated
                    * error |e| and its max|y| over the run so far (the state's units; its
                    * tolerance is glob_err_abs / glob_err)                              */
  long nglob_stiff; /* adaptive GALPHA: the global estimate's stiff blocks, each followed by
                    * steps propagated one by one (galpha_global.c, GALPHA_GLOBAL_STIFF)  */
  double newton_rtol; /* adaptive GALPHA: Newton's relative tolerance at the end (PHM_NEWTON_RTOL,
                    * tightened while the summed estimates run ahead: galpha.c)          */
  double last_step; int last_order;             /* last step [s] and order (BDF order; GALPHA: 2) */
  double max_mu;   /* the largest |mu| at the outputs (the position constraints' multipliers,
                    * docs/method.md section 6.2: 0 for the exact solution, rad/s and m/s) */
  double wall_time;                             /* seconds             */
} phm_sim_output;

#endif /* PHMECH_RESULTS_H */
