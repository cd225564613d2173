/* fmu.h -- one instance of phmech's FMU (csrc/fmi/fmu.c: the model file, the model and its state,
 * a step), shared by the FMI 2.0 functions (fmi2.c) and the FMI 3.0 ones (fmi3.c) on the same
 * instance. The FMI standard headers are in third_party/ (csrc/fmi/README.md). */
#ifndef PHM_FMU_H
#define PHM_FMU_H

#include <stddef.h>
#include <stdint.h>

#include "fmi2Functions.h"
#include "fmi3Functions.h"
#include "phmech.h"

typedef struct {
  char *key;
  uint64_t n;
  double *v;
} record;

/* Output kinds (python/phmech/fmu.py, _OUT_*). */
enum { OUT_JOINT = 0, OUT_RATE = 1, OUT_POSITION = 2, OUT_ENERGY = 3 };
/* Input kinds (python/phmech/fmu.py, _IN_*). */
enum { IN_ACTUATOR = 0, IN_LOAD = 1 };

typedef struct {
  int kind, index, comp;
  double T[16];
} output_var;

typedef struct {
  fmi2CallbackFunctions cb;
  fmi3LogMessageCallback log3; /* FMI 3.0: the logger and its environment */
  fmi3InstanceEnvironment env3;
  char *name;
  int logging;
  record *rec;
  int nrec;
  /* the description (arrays point into rec or into blocks freed with the instance) */
  phm_model_desc desc;
  phm_law *law_nodes[8]; /* expression node blocks: one per component kind */
  phm_model *model;
  phm_sim_options opt;
  int nc, nj, npairs;
  int nin, nout;
  int *in_kind, *in_index;
  double *u;          /* current input values */
  output_var *outv;
  double *y;          /* current output values */
  double *H, *T, *x, *xd; /* state at time t: poses, twists, joints, rates */
  double *x0;         /* npairs x 6 branch references */
  double t, tstart;
  int initialized;    /* fmi2ExitInitializationMode done: steps allowed */
  int outputs_ready;  /* y holds the outputs of the state at t */
} fmu;

/* Log a message through the importer's logger (FMI 3.0's when instantiated by fmi3, else FMI
 * 2.0's; nothing without a logger). */
void fmu_log(fmu *c, fmi2Status st, const char *fmt, ...);
/* The record `key` of the model file (NULL if absent). */
const record *fmu_record(const fmu *c, const char *key);
/* A new instance named `name` (NULL: "phmech"), nothing loaded; NULL without memory. */
fmu *fmu_new(const char *name, int logging);
/* Read the model file in the folder `resources` (a file:// URI or a path), build the model and
 * the state: c, or NULL (c freed) after logging why -- at once with `refusal` (not NULL), what
 * the importer asked that the FMU cannot do. */
fmu *fmu_load(fmu *c, const char *resources, const char *refusal);
/* Free an instance and all it holds (NULL: nothing). */
void fmu_free(fmu *c);
/* Integrate from c->t to t1, or only project the initial state (t1 = c->t); the state and the
 * outputs become those at t1. */
fmi2Status fmu_advance(fmu *c, double t1);

#endif
