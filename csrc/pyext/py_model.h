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
