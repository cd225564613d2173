/* py_model.h -- shared by the binding files of a model (csrc/pyext/py_model.c: the capsule and
 * the description's columns; py_laws.c, py_simulate.c, py_analyses.c, py_planar.c): the model's
 * capsule, the column tables that read a description (python/phmech/_marshal.py) into the core's
 * description structs, and the law parser. Only csrc/pyext/ includes it. */
#ifndef PHM_PY_MODEL_H
#define PHM_PY_MODEL_H

#include "pyext.h"

#include <stddef.h>

#define PHM_PY_MODEL_CAPSULE "phmech.model"

/* The model in a capsule made by model_new, or NULL with an exception set. */
phm_model *phm_py_get_model(PyObject *cap);

/* The (ncarriers, 4, 4) poses of model m given as `po` (named `what` in messages), a new array in
 * *P; when `optional`, None gives NULL (the model's initial poses). 0, or -1 with an exception
 * set. */
int phm_py_model_poses(const phm_model *m, PyObject *po, const char *what, int optional, PyArrayObject **P);

/* v as a whole int (the `what` of row i in the message), 0; or -1 with ModelError set. */
int phm_py_to_int(double v, const char *what, npy_intp i, int *out);

/* ---------------------------------------------------------------- model_new
 * One description per component kind: a dict of columns, each with one row per component (see
 * python/phmech/_marshal.py). The tables below say, for each column, its key, its name in
 * messages, how its values are read and where they go in the core's description struct
 * (csrc/phmech.h, phm_*_desc). The first column of a kind gives the number of components. */
typedef enum {
  COL_REALS, /* doubles, copied                                                       */
  COL_INDEX, /* whole numbers to int fields (indices, codes); a tail (2) fills two fields */
  COL_FLAG,  /* nonzero -> 1                                                          */
  COL_DROP,  /* redundant-row mask, an integer in [0, 64)                             */
  COL_LAW,   /* a list with one law tuple (or None, see law_rule) per component          */
  COL_XLAWS  /* pairs: a list with, per pair, None or k entries (a law tuple or None per
              * joint coordinate): the coordinates that follow a law (xdriven, xlaw)     */
} column_kind;

typedef enum {
  LAW_ALWAYS,    /* every component has a law                                  */
  LAW_OR_NONE,   /* None: no law (actuators that use none)                     */
  LAW_IF_DRIVEN  /* read for driven pairs only (their `driven` column comes first) */
} law_rule;

typedef struct {
  const char *key;   /* key in the component's dict                                      */
  const char *what;  /* name in messages                                                 */
  column_kind kind;
  int ntail;         /* shape of one row                                                 */
  npy_intp tail[2];
  size_t offset[2];  /* where the row goes in the struct (COL_INDEX with tail (2): two fields) */
  const char *label; /* COL_INDEX: "<label> <i>: expected a whole number"; COL_LAW: the law's name */
  law_rule rule;     /* COL_LAW                                                          */
} column;

typedef struct {
  const char *name;  /* argument of model_new                                            */
  const char *noun;  /* one component, in messages                                       */
  size_t size;       /* sizeof its description struct                                    */
  const column *columns;
  int ncolumns;
} component;

#define SCALAR(key, what, st, field) {key, what, COL_REALS, 0, {0}, {offsetof(st, field), 0}, NULL, 0}
#define VECTOR(key, what, st, field, n) {key, what, COL_REALS, 1, {n}, {offsetof(st, field), 0}, NULL, 0}
#define MATRIX(key, what, st, field, r, c) \
  {key, what, COL_REALS, 2, {r, c}, {offsetof(st, field), 0}, NULL, 0}
#define INDEX(key, what, st, field, label) \
  {key, what, COL_INDEX, 0, {0}, {offsetof(st, field), 0}, label, 0}
#define INDEX2(key, what, st, a, b, label) \
  {key, what, COL_INDEX, 1, {2}, {offsetof(st, a), offsetof(st, b)}, label, 0}
#define FLAG(key, what, st, field) {key, what, COL_FLAG, 0, {0}, {offsetof(st, field), 0}, NULL, 0}
#define KIND(name, noun, st, cols) {name, noun, sizeof(st), cols, (int)(sizeof cols / sizeof cols[0])}
#define LAW(key, what, st, field, label, rule) \
  {key, what, COL_LAW, 0, {0}, {offsetof(st, field), 0}, label, rule}
#define XLAWS(key, what, st, field, label) {key, what, COL_XLAWS, 0, {0}, {offsetof(st, field), 0}, label, 0}
#define DROP(key, what, st, field) {key, what, COL_DROP, 0, {0}, {offsetof(st, field), 0}, NULL, 0}

/* THE columns of each kind, in the order they are read (the first gives the count), each once:
 * MODEL(c) marks a column only model_new reads (py_model.c), BOTH(c) one the planar check reads
 * too (planar_check, py_planar.c). Each file expands a list with the marks it keeps
 * (PHM_PY_KEEP) or passes over (PHM_PY_SKIP), so that a column is written in one place. */
#define PHM_PY_KEEP(column) column,
#define PHM_PY_SKIP(column)

#define PHM_PY_CARRIER_COLUMNS(MODEL, BOTH)                         \
  BOTH(SCALAR("mass", "carrier masses", phm_carrier_desc, mass))    \
  BOTH(MATRIX("M", "carrier inertias", phm_carrier_desc, M, 6, 6))  \
  BOTH(VECTOR("com", "centres of mass", phm_carrier_desc, com, 3))  \
  MODEL(MATRIX("H0", "carrier poses", phm_carrier_desc, H0, 4, 4))  \
  MODEL(VECTOR("t0", "carrier twists", phm_carrier_desc, t0, 6))

#define PHM_PY_ELEMENT_COLUMNS(MODEL, BOTH)                                                  \
  MODEL(SCALAR("h", "element lengths", phm_element_desc, h))                                 \
  MODEL(INDEX2("nodes", "element nodes", phm_element_desc, a, b, "element"))                 \
  BOTH(MATRIX("K", "element stiffness", phm_element_desc, K, 6, 6))                          \
  BOTH(MATRIX("D", "element damping", phm_element_desc, D, 6, 6))                            \
  BOTH(VECTOR("eps_hat", "element unstressed strain", phm_element_desc, eps_hat, 6))         \
  MODEL(INDEX("mass", "element mass kinds", phm_element_desc, mass, "mass kind of element")) \
  BOTH(MATRIX("Ms", "element section inertias", phm_element_desc, Ms, 6, 6))                 \
  BOTH(MATRIX("Mc", "element mass couplings", phm_element_desc, Mc, 12, 12))

#define PHM_PY_PAIR_COLUMNS(MODEL, BOTH)                                                      \
  MODEL(INDEX("type", "pair types", phm_pair_desc, type, "pair type of pair"))                \
  BOTH(INDEX2("carriers", "pair carriers", phm_pair_desc, a, b, "pair"))                      \
  MODEL(MATRIX("Ta", "pair frames Ta", phm_pair_desc, Ta, 4, 4))                              \
  MODEL(MATRIX("Tb", "pair frames Tb", phm_pair_desc, Tb, 4, 4))                              \
  BOTH(FLAG("driven", "pair driven flags", phm_pair_desc, driven))                            \
  MODEL(VECTOR("axis", "pair motion axes", phm_pair_desc, axis, 6))                           \
  MODEL(LAW("law", "pair laws", phm_pair_desc, law, "pair motion law", LAW_IF_DRIVEN))        \
  BOTH(XLAWS("xlaws", "pair joint laws", phm_pair_desc, xlaw, "pair joint law"))              \
  MODEL(SCALAR("pitch", "pair pitches", phm_pair_desc, pitch))                                \
  MODEL(VECTOR("x0", "pair initial coordinates", phm_pair_desc, x0, 6))                       \
  MODEL(FLAG("has_x0", "pair x0 flags", phm_pair_desc, has_x0))                               \
  MODEL(DROP("drop", "pair drop masks", phm_pair_desc, drop))

#define PHM_PY_LOAD_COLUMNS(MODEL, BOTH)                                                  \
  MODEL(INDEX("carrier", "load carriers", phm_load_desc, carrier, "load"))                \
  MODEL(FLAG("world", "load frames", phm_load_desc, world))                               \
  BOTH(VECTOR("point", "load points", phm_load_desc, point, 3))                           \
  BOTH(VECTOR("w", "load wrenches", phm_load_desc, w, 6))                                 \
  MODEL(LAW("law", "load laws", phm_load_desc, law, "load law", LAW_ALWAYS))              \
  MODEL(INDEX("reaction", "load reactions", phm_load_desc, reaction, "reaction of load"))

#define PHM_PY_ACTUATOR_COLUMNS(MODEL, BOTH)                                                  \
  BOTH(INDEX("pair", "actuator pairs", phm_actuator_desc, pair, "pair of actuator"))          \
  MODEL(INDEX("kind", "actuator kinds", phm_actuator_desc, kind, "kind of actuator"))         \
  MODEL(VECTOR("vec", "actuator vectors", phm_actuator_desc, vec, 6))                         \
  MODEL(VECTOR("kp", "actuator kp", phm_actuator_desc, kp, 6))                                \
  MODEL(VECTOR("kd", "actuator kd", phm_actuator_desc, kd, 6))                                \
  MODEL(VECTOR("x_set", "actuator set points", phm_actuator_desc, x_set, 6))                  \
  MODEL(LAW("law", "actuator laws", phm_actuator_desc, law, "actuator law", LAW_OR_NONE))

#define PHM_PY_SPRING_COLUMNS(MODEL, BOTH)                                          \
  MODEL(SCALAR("k", "spring stiffnesses", phm_spring_desc, k))                      \
  BOTH(INDEX2("carriers", "spring carriers", phm_spring_desc, a, b, "spring"))      \
  BOTH(VECTOR("pa", "spring points a", phm_spring_desc, pa, 3))                     \
  BOTH(VECTOR("pb", "spring points b", phm_spring_desc, pb, 3))                     \
  MODEL(SCALAR("c", "spring damping coefficients", phm_spring_desc, c))             \
  MODEL(SCALAR("rest_length", "spring rest lengths", phm_spring_desc, d0))

/* The kinds, in model_new's argument order; the planar check reads the first six. */
#define PHM_PY_COMPONENT_KINDS(MODEL, BOTH)                            \
  BOTH(KIND("carriers", "carrier", phm_carrier_desc, carrier_columns)) \
  BOTH(KIND("elements", "element", phm_element_desc, element_columns)) \
  BOTH(KIND("pairs", "pair", phm_pair_desc, pair_columns))             \
  BOTH(KIND("loads", "load", phm_load_desc, load_columns))             \
  BOTH(KIND("actuators", "actuator", phm_actuator_desc, actuator_columns)) \
  BOTH(KIND("springs", "spring", phm_spring_desc, spring_columns))     \
  MODEL(KIND("couplings", "coupling", phm_coupling_desc, coupling_columns)) \
  MODEL(KIND("components", "component", phm_component_desc, component_columns))

/* The components of kind `cp` described by the dict `d` (csrc/pyext/py_model.c). */
int phm_py_parse_component(const component *cp, PyObject *d, PyObject *keep, int strict, npy_intp *n,
                           void **out);

/* Laws (csrc/pyext/py_laws.c): a law tuple into *law (what it points to kept in `keep`); the
 * laws of column `col` into n structs; the first exception a CALLBACK law's callable kept
 * (re-raised: -1), for the list `keep` or the capsule of a model. */
int phm_py_parse_law(PyObject *obj, phm_law *law, PyObject *keep, const char *what, int depth);
int phm_py_control_callback(void *ctx, double t, double x, double v, int nder, double out[3]);
int phm_py_fill_laws(const component *cp, const column *col, PyObject *list, npy_intp n, char *items,
                     PyObject *keep);
int phm_py_law_error(PyObject *keep);
int phm_py_model_law_error(PyObject *cap);

/* A run's callbacks (csrc/pyext/py_run.c): the record a run hands the core as its ctx, and the
 * core's monitor, interrupt and progress callbacks that read it. */
typedef struct {
  PyObject *cb;    /* progress callable(t, iout) -> truthy to stop, or None */
  int interrupted; /* Ctrl-C seen */
  int failed;      /* the callback raised */
  PyObject *et, *ev, *etb;
  PyObject *mon;   /* monitor callable(t, steps, h) -> truthy to stop, or None */
  int cb_stop;     /* the progress callable's answer at this output (phm_py_interrupt_cb asks it) */
} phm_py_run;
int phm_py_monitor_cb(void *vctx, double t, long nsteps, double h);
int phm_py_interrupt_cb(void *vctx, double t, int iout);
int phm_py_progress_cb(void *vctx, double t, int iout);

#endif
