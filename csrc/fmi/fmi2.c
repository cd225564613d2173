/* fmi2.c -- the FMI 2.0 co-simulation functions of phmech's FMU, on the instance of fmu.h
 * (csrc/fmi/fmu.c: the model file, the model, a step). Value references: the inputs, then the
 * outputs, all Real. FMU state, derivatives and the non-Real variable types are not supported
 * (the model description says so). */
#include "fmu.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component comp, fmi2Boolean on, size_t n, const fmi2String cats[]) {
  (void)n;
  (void)cats;
  if (!comp) return fmi2Error;
  ((fmu *)comp)->logging = on;
  return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String resources,
                              const fmi2CallbackFunctions *cb, fmi2Boolean visible, fmi2Boolean logging) {
  (void)guid;
  (void)visible;
  fmu *c = fmu_new(name, logging);
  if (!c) return NULL;
  if (cb) c->cb = *cb;
  return fmu_load(c, resources, type != fmi2CoSimulation
                                    ? "phmech FMUs are co-simulation FMUs only (fmi2CoSimulation)"
                                    : NULL);
}

void fmi2FreeInstance(fmi2Component comp) { fmu_free((fmu *)comp); }

fmi2Status fmi2SetupExperiment(fmi2Component comp, fmi2Boolean tolDefined, fmi2Real tol,
                               fmi2Real tstart, fmi2Boolean stopDefined, fmi2Real tstop) {
  (void)tolDefined;
  (void)tol;
  (void)stopDefined;
  (void)tstop;
  fmu *c = comp;
  if (!c) return fmi2Error;
  c->t = c->tstart = tstart;
  return fmi2OK;
}

/* The outputs at the start are those of the consistent initial state (they do not depend on the
 * inputs): computed here already, so that an importer may read them in initialization mode. */
fmi2Status fmi2EnterInitializationMode(fmi2Component comp) {
  fmu *c = comp;
  if (!c) return fmi2Error;
  fmi2Status st = fmu_advance(c, c->t);
  c->initialized = 0;
  c->outputs_ready = st == fmi2OK;
  return st;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component comp) {
  fmu *c = comp;
  if (!c) return fmi2Error;
  fmi2Status st = fmu_advance(c, c->t); /* the consistent initial state and its outputs */
  c->initialized = c->outputs_ready = st == fmi2OK;
  return st;
}

fmi2Status fmi2Terminate(fmi2Component comp) { return comp ? fmi2OK : fmi2Error; }

fmi2Status fmi2Reset(fmi2Component comp) {
  fmu *c = comp;
  if (!c) return fmi2Error;
  for (int i = 0; i < c->nc; i++) {
    memcpy(c->H + 16 * i, c->desc.carriers[i].H0, 16 * sizeof(double));
    memcpy(c->T + 6 * i, c->desc.carriers[i].t0, 6 * sizeof(double));
  }
  for (int i = 0; i < c->npairs; i++) memcpy(c->x0 + 6 * i, c->desc.pairs[i].x0, 6 * sizeof(double));
  phm_error err;
  if (phm_model_set_initial(c->model, c->H, c->T, c->x0, NULL, &err) != PHM_OK) return fmi2Error;
  const record *in = fmu_record(c, "inputs");
  for (int i = 0; i < c->nin; i++) c->u[i] = in->v[3 * i + 2];
  c->t = c->tstart;
  c->initialized = c->outputs_ready = 0;
  return fmi2OK;
}

/* Value references: 0 .. nin-1 the inputs, nin .. nin+nout-1 the outputs. */
fmi2Status fmi2GetReal(fmi2Component comp, const fmi2ValueReference vr[], size_t n, fmi2Real value[]) {
  fmu *c = comp;
  if (!c) return fmi2Error;
  for (size_t i = 0; i < n; i++) {
    if (vr[i] < (unsigned)c->nin) value[i] = c->u[vr[i]];
    else if (vr[i] < (unsigned)(c->nin + c->nout) && !c->outputs_ready) {
      fmu_log(c, fmi2Error, "fmi2GetReal: the outputs are known from fmi2EnterInitializationMode on");
      return fmi2Error;
    } else if (vr[i] < (unsigned)(c->nin + c->nout)) value[i] = c->y[vr[i] - c->nin];
    else if (vr[i] == (unsigned)(c->nin + c->nout)) value[i] = c->t; /* FMI 3.0's independent variable */
    else {
      fmu_log(c, fmi2Error, "fmi2GetReal: unknown value reference %u", vr[i]);
      return fmi2Error;
    }
  }
  return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component comp, const fmi2ValueReference vr[], size_t n, const fmi2Real value[]) {
  fmu *c = comp;
  if (!c) return fmi2Error;
  for (size_t i = 0; i < n; i++) {
    if (vr[i] >= (unsigned)c->nin) {
      fmu_log(c, fmi2Error, "fmi2SetReal: value reference %u is not an input", vr[i]);
      return fmi2Error;
    }
    if (!isfinite(value[i])) {
      fmu_log(c, fmi2Error, "fmi2SetReal: input %u set to a non-finite value", vr[i]);
      return fmi2Error;
    }
    c->u[vr[i]] = value[i];
  }
  return fmi2OK;
}

static fmi2Status none(fmi2Component comp, size_t n) {
  if (!comp) return fmi2Error;
  if (n) {
    fmu_log(comp, fmi2Error, "this FMU has Real variables only");
    return fmi2Error;
  }
  return fmi2OK;
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[]) {
  (void)vr; (void)v;
  return none(c, n);
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean v[]) {
  (void)vr; (void)v;
  return none(c, n);
}
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2String v[]) {
  (void)vr; (void)v;
  return none(c, n);
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[]) {
  (void)vr; (void)v;
  return none(c, n);
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[]) {
  (void)vr; (void)v;
  return none(c, n);
}
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2String v[]) {
  (void)vr; (void)v;
  return none(c, n);
}

/* Not supported (the model description says so: canGetAndSetFMUstate etc. are false). */
static fmi2Status unsupported(fmi2Component comp, const char *what) {
  fmu_log(comp, fmi2Error, "%s is not supported by phmech FMUs", what);
  return fmi2Error;
}
/* Each logs its name (__func__) and returns fmi2Error; their parameters are unused. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s) { return unsupported(c, __func__); }
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) { return unsupported(c, __func__); }
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s) { return unsupported(c, __func__); }
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *n) {
  return unsupported(c, __func__);
}
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t n) {
  return unsupported(c, __func__);
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t n, fmi2FMUstate *s) {
  return unsupported(c, __func__);
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference z[], size_t nz,
                                        const fmi2Real dv[], fmi2Real dz[]) {
  return unsupported(c, __func__);
}
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                       const fmi2Integer order[], const fmi2Real v[]) {
  return unsupported(c, __func__);
}
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                        const fmi2Integer order[], fmi2Real v[]) {
  return unsupported(c, __func__);
}
#pragma GCC diagnostic pop

fmi2Status fmi2DoStep(fmi2Component comp, fmi2Real t, fmi2Real h, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
  (void)noSetFMUStatePriorToCurrentPoint;
  fmu *c = comp;
  if (!c) return fmi2Error;
  if (!c->initialized) {
    fmu_log(c, fmi2Error, "fmi2DoStep before fmi2ExitInitializationMode");
    return fmi2Error;
  }
  if (!(h > 0)) {
    fmu_log(c, fmi2Error, "fmi2DoStep: step %g s must be > 0", h);
    return fmi2Error;
  }
  if (fabs(t - c->t) > 1e-9 * fmax(1.0, fabs(t))) {
    fmu_log(c, fmi2Error, "fmi2DoStep: t = %.17g s, but the FMU is at %.17g s", t, c->t);
    return fmi2Error;
  }
  return fmu_advance(c, c->t + h);
}

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
fmi2Status fmi2CancelStep(fmi2Component c) { return unsupported(c, __func__); }
fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind k, fmi2Status *v) {
  return unsupported(c, __func__);
}
fmi2Status fmi2GetRealStatus(fmi2Component comp, const fmi2StatusKind k, fmi2Real *v) {
  fmu *c = comp;
  if (!c) return fmi2Error;
  if (k == fmi2LastSuccessfulTime) {
    *v = c->t;
    return fmi2OK;
  }
  return unsupported(c, "fmi2GetRealStatus");
}
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind k, fmi2Integer *v) {
  return unsupported(c, __func__);
}
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind k, fmi2Boolean *v) {
  return unsupported(c, __func__);
}
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind k, fmi2String *v) {
  return unsupported(c, __func__);
}
#pragma GCC diagnostic pop
