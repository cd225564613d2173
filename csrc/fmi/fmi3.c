/* fmi3.c -- the FMI 3.0 co-simulation functions of phmech's FMU: the same instance (fmu.h) and
 * model file as FMI 2.0's (fmi2.c, whose functions most of these call); value references as in
 * FMI 2.0 (inputs, then outputs), all Float64. Event mode, clocks, intermediate updates, FMU state
 * and derivatives are not supported (their functions return fmi3Error, the model description says
 * so); their stubs below are what the FMI 3.0 API requires an FMU to export. */
#include "fmu.h"

const char *fmi3GetVersion(void) { return fmi3Version; }

static fmi3Status unsupported3(fmi3Instance inst, const char *what) {
  fmu_log(inst, fmi2Error, "%s is not supported by phmech FMUs", what);
  return fmi3Error;
}

fmi3Status fmi3SetDebugLogging(fmi3Instance inst, fmi3Boolean on, size_t n, const fmi3String cats[]) {
  return (fmi3Status)fmi2SetDebugLogging(inst, on, n, cats);
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String name, fmi3String token, fmi3String resources,
                                         fmi3Boolean visible, fmi3Boolean logging, fmi3Boolean eventModeUsed,
                                         fmi3Boolean earlyReturnAllowed, const fmi3ValueReference req[],
                                         size_t nreq, fmi3InstanceEnvironment env,
                                         fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback intermediateUpdate) {
  (void)token; (void)visible; (void)earlyReturnAllowed; (void)req; (void)nreq; (void)intermediateUpdate;
  fmu *c = fmu_new(name, logging);
  if (!c) return NULL;
  c->log3 = logMessage;
  c->env3 = env;
  return fmu_load(c, resources,
                  eventModeUsed ? "phmech FMUs have no event mode (eventModeUsed must be false)" : NULL);
}

void fmi3FreeInstance(fmi3Instance inst) { fmu_free((fmu *)inst); }

fmi3Status fmi3EnterInitializationMode(fmi3Instance inst, fmi3Boolean tolDefined, fmi3Float64 tol,
                                       fmi3Float64 tstart, fmi3Boolean stopDefined, fmi3Float64 tstop) {
  if (fmi2SetupExperiment(inst, tolDefined, tol, tstart, stopDefined, tstop) != fmi2OK) return fmi3Error;
  return (fmi3Status)fmi2EnterInitializationMode(inst);
}
fmi3Status fmi3ExitInitializationMode(fmi3Instance inst) { return (fmi3Status)fmi2ExitInitializationMode(inst); }
fmi3Status fmi3EnterStepMode(fmi3Instance inst) { return inst ? fmi3OK : fmi3Error; }
fmi3Status fmi3Terminate(fmi3Instance inst) { return inst ? fmi3OK : fmi3Error; }
fmi3Status fmi3Reset(fmi3Instance inst) { return (fmi3Status)fmi2Reset(inst); }

fmi3Status fmi3GetFloat64(fmi3Instance inst, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 v[],
                          size_t nv) {
  if (nv != nvr) return unsupported3(inst, "fmi3GetFloat64 of array variables");
  return (fmi3Status)fmi2GetReal(inst, vr, nvr, v);
}
fmi3Status fmi3SetFloat64(fmi3Instance inst, const fmi3ValueReference vr[], size_t nvr,
                          const fmi3Float64 v[], size_t nv) {
  if (nv != nvr) return unsupported3(inst, "fmi3SetFloat64 of array variables");
  return (fmi3Status)fmi2SetReal(inst, vr, nvr, v);
}

fmi3Status fmi3DoStep(fmi3Instance inst, fmi3Float64 t, fmi3Float64 h, fmi3Boolean noSetPrior,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                      fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime) {
  fmi3Status st = (fmi3Status)fmi2DoStep(inst, t, h, noSetPrior);
  if (eventHandlingNeeded) *eventHandlingNeeded = fmi3False;
  if (terminateSimulation) *terminateSimulation = st != fmi3OK;
  if (earlyReturn) *earlyReturn = fmi3False;
  if (lastSuccessfulTime && inst) *lastSuccessfulTime = ((fmu *)inst)->t;
  return st;
}

/* the rest of FMI 3.0's functions: not supported */
fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment, fmi3LogMessageCallback logMessage) {
  (void)instantiationToken; (void)resourcePath; (void)visible; (void)loggingOn; (void)instanceEnvironment; (void)logMessage;
  (void)instanceName;
  return NULL; /* co-simulation only */
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment, fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate, fmi3LockPreemptionCallback lockPreemption, fmi3UnlockPreemptionCallback unlockPreemption) {
  (void)instantiationToken; (void)resourcePath; (void)visible; (void)loggingOn; (void)instanceEnvironment; (void)logMessage; (void)clockUpdate; (void)lockPreemption; (void)unlockPreemption;
  (void)instanceName;
  return NULL; /* co-simulation only */
}

/* ---------------------------------------------------------------- unsupported
 * The rest of the FMI 3.0 API, which an FMU must export: each function logs its name (__func__)
 * and returns fmi3Error; their parameters are unused. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"

/* get and set of the variable types other than Float64, Binary and Clock (phmech's FMUs have
 * only Float64 variables) */
#define FMI3_OTHER_TYPES(X) \
  X(Float32) X(Int8) X(UInt8) X(Int16) X(UInt16) X(Int32) X(UInt32) X(Int64) X(UInt64) X(Boolean) X(String)
#define GET_AND_SET_UNSUPPORTED(T)                                                                   \
  fmi3Status fmi3Get##T(fmi3Instance instance, const fmi3ValueReference valueReferences[],          \
                        size_t nValueReferences, fmi3##T values[], size_t nValues) {                \
    return unsupported3(instance, __func__);                                                         \
  }                                                                                                  \
  fmi3Status fmi3Set##T(fmi3Instance instance, const fmi3ValueReference valueReferences[],          \
                        size_t nValueReferences, const fmi3##T values[], size_t nValues) {          \
    return unsupported3(instance, __func__);                                                         \
  }
FMI3_OTHER_TYPES(GET_AND_SET_UNSUPPORTED)

fmi3Status fmi3EnterEventMode(fmi3Instance instance) { return unsupported3(instance, __func__); }
fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, size_t valueSizes[], fmi3Binary values[],
                         size_t nValues) { return unsupported3(instance, __func__); }
fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, fmi3Clock values[]) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, const size_t valueSizes[],
                         const fmi3Binary values[], size_t nValues) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, const fmi3Clock values[]) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance,
                                               fmi3ValueReference valueReference,
                                               size_t* nDependencies) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[],
                                       fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[],
                                       fmi3DependencyKind dependencyKinds[], size_t nDependencies) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState* FMUState) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState* FMUState) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t* size) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState,
                                 fmi3Byte serializedState[], size_t size) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[],
                                   size_t size, fmi3FMUState* FMUState) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[],
                                        size_t nUnknowns, const fmi3ValueReference knowns[],
                                        size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
                                        fmi3Float64 sensitivity[], size_t nSensitivity) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[],
                                    size_t nUnknowns, const fmi3ValueReference knowns[],
                                    size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
                                    fmi3Float64 sensitivity[], size_t nSensitivity) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, fmi3Float64 intervals[],
                                  fmi3IntervalQualifier qualifiers[]) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3GetIntervalFraction(fmi3Instance instance,
                                   const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, fmi3UInt64 counters[],
                                   fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[]) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, fmi3Float64 shifts[]) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, fmi3UInt64 counters[],
                                fmi3UInt64 resolutions[]) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, const fmi3Float64 intervals[]) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3SetIntervalFraction(fmi3Instance instance,
                                   const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, const fmi3UInt64 counters[],
                                   const fmi3UInt64 resolutions[]) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, const fmi3Float64 shifts[]) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, const fmi3UInt64 counters[],
                                const fmi3UInt64 resolutions[]) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean* discreteStatesNeedUpdate,
                                    fmi3Boolean* terminateSimulation,
                                    fmi3Boolean* nominalsOfContinuousStatesChanged,
                                    fmi3Boolean* valuesOfContinuousStatesChanged,
                                    fmi3Boolean* nextEventTimeDefined, fmi3Float64* nextEventTime) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance,
                                       fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean* enterEventMode,
                                       fmi3Boolean* terminateSimulation) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[],
                                   size_t nContinuousStates) {
  return unsupported3(instance, __func__);
}
/* model exchange's arrays of states, their derivatives and nominals, and event indicators */
#define FMI3_MODEL_EXCHANGE_ARRAYS(X) \
  X(GetContinuousStates) X(GetContinuousStateDerivatives) X(GetNominalsOfContinuousStates) X(GetEventIndicators)
#define GET_ARRAY_UNSUPPORTED(F)                                                                     \
  fmi3Status fmi3##F(fmi3Instance instance, fmi3Float64 values[], size_t nValues) {                 \
    return unsupported3(instance, __func__);                                                         \
  }
FMI3_MODEL_EXCHANGE_ARRAYS(GET_ARRAY_UNSUPPORTED)
fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t* nEventIndicators) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t* nContinuousStates) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance,
                                    const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Int32 orders[],
                                    fmi3Float64 values[], size_t nValues) {
  return unsupported3(instance, __func__);
}
fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime) {
  return unsupported3(instance, __func__);
}

#pragma GCC diagnostic pop
