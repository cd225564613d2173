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
  (void)n;
  (void)cats;
  if (!inst) return fmi3Error;
  ((fmu *)inst)->logging = on;
  return fmi3OK;
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

fmi3Status fmi3EnterEventMode(fmi3Instance instance) {
  
  return unsupported3(instance, "fmi3EnterEventMode");
}

fmi3Status fmi3GetFloat32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Float32 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3GetFloat32");
}

fmi3Status fmi3GetInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Int8 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3GetInt8");
}

fmi3Status fmi3GetUInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt8 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3GetUInt8");
}

fmi3Status fmi3GetInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Int16 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3GetInt16");
}

fmi3Status fmi3GetUInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt16 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3GetUInt16");
}

fmi3Status fmi3GetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Int32 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3GetInt32");
}

fmi3Status fmi3GetUInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt32 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3GetUInt32");
}

fmi3Status fmi3GetInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Int64 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3GetInt64");
}

fmi3Status fmi3GetUInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt64 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3GetUInt64");
}

fmi3Status fmi3GetBoolean(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Boolean values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3GetBoolean");
}

fmi3Status fmi3GetString(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3String values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3GetString");
}

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, size_t valueSizes[], fmi3Binary values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)valueSizes; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3GetBinary");
}

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Clock values[]) {
  (void)valueReferences; (void)nValueReferences; (void)values;
  return unsupported3(instance, "fmi3GetClock");
}

fmi3Status fmi3SetFloat32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Float32 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3SetFloat32");
}

fmi3Status fmi3SetInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int8 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3SetInt8");
}

fmi3Status fmi3SetUInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt8 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3SetUInt8");
}

fmi3Status fmi3SetInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int16 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3SetInt16");
}

fmi3Status fmi3SetUInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt16 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3SetUInt16");
}

fmi3Status fmi3SetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int32 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3SetInt32");
}

fmi3Status fmi3SetUInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt32 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3SetUInt32");
}

fmi3Status fmi3SetInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int64 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3SetInt64");
}

fmi3Status fmi3SetUInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt64 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3SetUInt64");
}

fmi3Status fmi3SetBoolean(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Boolean values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3SetBoolean");
}

fmi3Status fmi3SetString(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3String values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3SetString");
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const size_t valueSizes[], const fmi3Binary values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)valueSizes; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3SetBinary");
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Clock values[]) {
  (void)valueReferences; (void)nValueReferences; (void)values;
  return unsupported3(instance, "fmi3SetClock");
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference valueReference, size_t* nDependencies) {
  (void)valueReference; (void)nDependencies;
  return unsupported3(instance, "fmi3GetNumberOfVariableDependencies");
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent, size_t elementIndicesOfDependent[], fmi3ValueReference independents[], size_t elementIndicesOfIndependents[], fmi3DependencyKind dependencyKinds[], size_t nDependencies) {
  (void)dependent; (void)elementIndicesOfDependent; (void)independents; (void)elementIndicesOfIndependents; (void)dependencyKinds; (void)nDependencies;
  return unsupported3(instance, "fmi3GetVariableDependencies");
}

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState* FMUState) {
  (void)FMUState;
  return unsupported3(instance, "fmi3GetFMUState");
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState) {
  (void)FMUState;
  return unsupported3(instance, "fmi3SetFMUState");
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState* FMUState) {
  (void)FMUState;
  return unsupported3(instance, "fmi3FreeFMUState");
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t* size) {
  (void)FMUState; (void)size;
  return unsupported3(instance, "fmi3SerializedFMUStateSize");
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState, fmi3Byte serializedState[], size_t size) {
  (void)FMUState; (void)serializedState; (void)size;
  return unsupported3(instance, "fmi3SerializeFMUState");
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size, fmi3FMUState* FMUState) {
  (void)serializedState; (void)size; (void)FMUState;
  return unsupported3(instance, "fmi3DeserializeFMUState");
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns, const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[], size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
  (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns; (void)seed; (void)nSeed; (void)sensitivity; (void)nSensitivity;
  return unsupported3(instance, "fmi3GetDirectionalDerivative");
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns, const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[], size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
  (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns; (void)seed; (void)nSeed; (void)sensitivity; (void)nSensitivity;
  return unsupported3(instance, "fmi3GetAdjointDerivative");
}

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance) {
  
  return unsupported3(instance, "fmi3EnterConfigurationMode");
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) {
  
  return unsupported3(instance, "fmi3ExitConfigurationMode");
}

fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[]) {
  (void)valueReferences; (void)nValueReferences; (void)intervals; (void)qualifiers;
  return unsupported3(instance, "fmi3GetIntervalDecimal");
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[]) {
  (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions; (void)qualifiers;
  return unsupported3(instance, "fmi3GetIntervalFraction");
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Float64 shifts[]) {
  (void)valueReferences; (void)nValueReferences; (void)shifts;
  return unsupported3(instance, "fmi3GetShiftDecimal");
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[]) {
  (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions;
  return unsupported3(instance, "fmi3GetShiftFraction");
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Float64 intervals[]) {
  (void)valueReferences; (void)nValueReferences; (void)intervals;
  return unsupported3(instance, "fmi3SetIntervalDecimal");
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt64 counters[], const fmi3UInt64 resolutions[]) {
  (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions;
  return unsupported3(instance, "fmi3SetIntervalFraction");
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Float64 shifts[]) {
  (void)valueReferences; (void)nValueReferences; (void)shifts;
  return unsupported3(instance, "fmi3SetShiftDecimal");
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt64 counters[], const fmi3UInt64 resolutions[]) {
  (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions;
  return unsupported3(instance, "fmi3SetShiftFraction");
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) {
  
  return unsupported3(instance, "fmi3EvaluateDiscreteStates");
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean* discreteStatesNeedUpdate, fmi3Boolean* terminateSimulation, fmi3Boolean* nominalsOfContinuousStatesChanged, fmi3Boolean* valuesOfContinuousStatesChanged, fmi3Boolean* nextEventTimeDefined, fmi3Float64* nextEventTime) {
  (void)discreteStatesNeedUpdate; (void)terminateSimulation; (void)nominalsOfContinuousStatesChanged; (void)valuesOfContinuousStatesChanged; (void)nextEventTimeDefined; (void)nextEventTime;
  return unsupported3(instance, "fmi3UpdateDiscreteStates");
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
  
  return unsupported3(instance, "fmi3EnterContinuousTimeMode");
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint, fmi3Boolean* enterEventMode, fmi3Boolean* terminateSimulation) {
  (void)noSetFMUStatePriorToCurrentPoint; (void)enterEventMode; (void)terminateSimulation;
  return unsupported3(instance, "fmi3CompletedIntegratorStep");
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
  (void)time;
  return unsupported3(instance, "fmi3SetTime");
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[], size_t nContinuousStates) {
  (void)continuousStates; (void)nContinuousStates;
  return unsupported3(instance, "fmi3SetContinuousStates");
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[], size_t nContinuousStates) {
  (void)derivatives; (void)nContinuousStates;
  return unsupported3(instance, "fmi3GetContinuousStateDerivatives");
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[], size_t nEventIndicators) {
  (void)eventIndicators; (void)nEventIndicators;
  return unsupported3(instance, "fmi3GetEventIndicators");
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[], size_t nContinuousStates) {
  (void)continuousStates; (void)nContinuousStates;
  return unsupported3(instance, "fmi3GetContinuousStates");
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t nContinuousStates) {
  (void)nominals; (void)nContinuousStates;
  return unsupported3(instance, "fmi3GetNominalsOfContinuousStates");
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t* nEventIndicators) {
  (void)nEventIndicators;
  return unsupported3(instance, "fmi3GetNumberOfEventIndicators");
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t* nContinuousStates) {
  (void)nContinuousStates;
  return unsupported3(instance, "fmi3GetNumberOfContinuousStates");
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int32 orders[], fmi3Float64 values[], size_t nValues) {
  (void)valueReferences; (void)nValueReferences; (void)orders; (void)values; (void)nValues;
  return unsupported3(instance, "fmi3GetOutputDerivatives");
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference, fmi3Float64 activationTime) {
  (void)clockReference; (void)activationTime;
  return unsupported3(instance, "fmi3ActivateModelPartition");
}
