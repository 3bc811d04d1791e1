/*
 * FMI 3.0 adapter: every function of fmi3Functions.h, translated onto the
 * version-independent core in runtime.c. No behaviour lives here.
 */
#include "fmi3Functions.h"
#include "runtime.h"

#define INST(i) ((mf_instance *)(i))
#define ST(s) ((fmi3Status)(s))

static void dispatch(mf_generic_fn callback, void *environment, const char *instance_name,
                     mf_status status, const char *category, const char *message)
{
    (void)instance_name; /* FMI 3 identifies the instance by its environment */
    ((fmi3LogMessageCallback)callback)(environment, (fmi3Status)status, category, message);
}

static void event_dispatch(mf_generic_fn callback, void *environment, double t)
{
    fmi3Boolean early_return_requested = fmi3False;
    fmi3Float64 early_return_time = t;
    /* outputs may be read, nothing may be set, the step is not finished, and this
       FMU does not return early */
    ((fmi3IntermediateUpdateCallback)callback)(environment, t, fmi3False, fmi3True, fmi3False,
                                               fmi3False, &early_return_requested,
                                               &early_return_time);
}

static mf_host host(fmi3InstanceEnvironment env, fmi3LogMessageCallback log)
{
    mf_host h;
    h.event_dispatch = event_dispatch;
    h.event_callback = NULL;
    h.early_return_allowed = 0;
    h.float_type = "Float64";
    h.int_type = "Int32";
    h.token_name = "instantiationToken";
    h.reset_hint = "fmi3Reset or fmi3SetFMUState";
    h.dispatch = dispatch;
    h.callback = (mf_generic_fn)log;
    h.environment = env;
    return h;
}

/* --- common -------------------------------------------------------------- */

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[])
{
    return ST(mf_set_debug_logging(INST(instance), "fmi3SetDebugLogging", loggingOn, nCategories,
                                   categories));
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible,
                                          fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage)
{
    mf_host h = host(instanceEnvironment, logMessage);
    (void)visible;
    return mf_create(&MF_MODEL, "fmi3InstantiateModelExchange", instanceName, instantiationToken,
                     resourcePath, MF_MODEL_EXCHANGE, loggingOn, 0, &h);
}

fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3Boolean eventModeUsed,
    fmi3Boolean earlyReturnAllowed, const fmi3ValueReference requiredIntermediateVariables[],
    size_t nRequiredIntermediateVariables, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3IntermediateUpdateCallback intermediateUpdate)
{
    mf_host h = host(instanceEnvironment, logMessage);
    (void)visible;
    h.early_return_allowed = earlyReturnAllowed;
    (void)requiredIntermediateVariables;
    (void)nRequiredIntermediateVariables;
    h.event_callback = (mf_generic_fn)intermediateUpdate;
    return mf_create(&MF_MODEL, "fmi3InstantiateCoSimulation", instanceName, instantiationToken,
                     resourcePath, MF_CO_SIMULATION, loggingOn, eventModeUsed, &h);
}

fmi3Instance fmi3InstantiateScheduledExecution(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
    fmi3LockPreemptionCallback lockPreemption, fmi3UnlockPreemptionCallback unlockPreemption)
{
    (void)instanceName; (void)instantiationToken; (void)resourcePath; (void)visible;
    (void)loggingOn; (void)clockUpdate; (void)lockPreemption; (void)unlockPreemption;
    if (logMessage)
        logMessage(instanceEnvironment, fmi3Error, "logStatusError",
                   "fmi3InstantiateScheduledExecution: Scheduled Execution is not supported by "
                   "this FMU (only Model Exchange and Co-Simulation)");
    return NULL;
}

void fmi3FreeInstance(fmi3Instance instance) { mf_free(INST(instance)); }

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined,
                                       fmi3Float64 tolerance, fmi3Float64 startTime,
                                       fmi3Boolean stopTimeDefined, fmi3Float64 stopTime)
{
    mf_status s = mf_setup_experiment(INST(instance), "fmi3EnterInitializationMode",
                                      toleranceDefined, tolerance, startTime, stopTimeDefined,
                                      stopTime);
    if (s != MF_OK) return ST(s);
    return ST(mf_enter_initialization_mode(INST(instance), "fmi3EnterInitializationMode"));
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance)
{
    return ST(mf_exit_initialization_mode(INST(instance), "fmi3ExitInitializationMode"));
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance)
{
    return ST(mf_enter_event_mode(INST(instance), "fmi3EnterEventMode"));
}

fmi3Status fmi3Terminate(fmi3Instance instance)
{
    return ST(mf_terminate(INST(instance), "fmi3Terminate"));
}

fmi3Status fmi3Reset(fmi3Instance instance) { return ST(mf_reset(INST(instance), "fmi3Reset")); }

/* --- getting and setting variables --------------------------------------- */

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, fmi3Float64 values[], size_t nValues)
{
    return ST(mf_get_float(INST(instance), "fmi3GetFloat64", valueReferences, nValueReferences,
                           values, nValues));
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, const fmi3Float64 values[], size_t nValues)
{
    return ST(mf_set_float(INST(instance), "fmi3SetFloat64", valueReferences, nValueReferences,
                           values, nValues));
}

fmi3Status fmi3GetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, fmi3Int32 values[], size_t nValues)
{
    return ST(mf_get_int(INST(instance), "fmi3GetInt32", valueReferences, nValueReferences,
                         values, nValues));
}

fmi3Status fmi3SetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, const fmi3Int32 values[], size_t nValues)
{
    return ST(mf_set_int(INST(instance), "fmi3SetInt32", valueReferences, nValueReferences,
                         values, nValues));
}

/* Types this FMU never has variables of. */
#define NO_TYPE(fn, type)                                                                     \
    return ST(mf_unsupported(INST(instance), fn,                                             \
                             "it has no " type " variables, only Float64 and Int32"))

fmi3Status fmi3GetFloat32(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          fmi3Float32 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3GetFloat32", "Float32");
}

fmi3Status fmi3GetInt8(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                       fmi3Int8 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3GetInt8", "Int8");
}

fmi3Status fmi3GetUInt8(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                        fmi3UInt8 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3GetUInt8", "UInt8");
}

fmi3Status fmi3GetInt16(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                        fmi3Int16 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3GetInt16", "Int16");
}

fmi3Status fmi3GetUInt16(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                         fmi3UInt16 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3GetUInt16", "UInt16");
}

fmi3Status fmi3GetUInt32(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                         fmi3UInt32 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3GetUInt32", "UInt32");
}

fmi3Status fmi3GetInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                        fmi3Int64 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3GetInt64", "Int64");
}

fmi3Status fmi3GetUInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                         fmi3UInt64 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3GetUInt64", "UInt64");
}

fmi3Status fmi3GetBoolean(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          fmi3Boolean values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3GetBoolean", "Boolean");
}

fmi3Status fmi3GetString(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                         fmi3String values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3GetString", "String");
}

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                         size_t valueSizes[], fmi3Binary values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)valueSizes; (void)values; (void)nValues;
    NO_TYPE("fmi3GetBinary", "Binary");
}

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                        fmi3Clock values[])
{
    (void)vr; (void)nvr; (void)values;
    NO_TYPE("fmi3GetClock", "Clock");
}

fmi3Status fmi3SetFloat32(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          const fmi3Float32 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3SetFloat32", "Float32");
}

fmi3Status fmi3SetInt8(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                       const fmi3Int8 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3SetInt8", "Int8");
}

fmi3Status fmi3SetUInt8(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                        const fmi3UInt8 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3SetUInt8", "UInt8");
}

fmi3Status fmi3SetInt16(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                        const fmi3Int16 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3SetInt16", "Int16");
}

fmi3Status fmi3SetUInt16(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                         const fmi3UInt16 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3SetUInt16", "UInt16");
}

fmi3Status fmi3SetUInt32(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                         const fmi3UInt32 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3SetUInt32", "UInt32");
}

fmi3Status fmi3SetInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                        const fmi3Int64 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3SetInt64", "Int64");
}

fmi3Status fmi3SetUInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                         const fmi3UInt64 values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3SetUInt64", "UInt64");
}

fmi3Status fmi3SetBoolean(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          const fmi3Boolean values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3SetBoolean", "Boolean");
}

fmi3Status fmi3SetString(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                         const fmi3String values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)values; (void)nValues;
    NO_TYPE("fmi3SetString", "String");
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                         const size_t valueSizes[], const fmi3Binary values[], size_t nValues)
{
    (void)vr; (void)nvr; (void)valueSizes; (void)values; (void)nValues;
    NO_TYPE("fmi3SetBinary", "Binary");
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                        const fmi3Clock values[])
{
    (void)vr; (void)nvr; (void)values;
    NO_TYPE("fmi3SetClock", "Clock");
}

/* --- dependencies, FMU state, derivatives --------------------------------- */

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance,
                                               fmi3ValueReference valueReference,
                                               size_t *nDependencies)
{
    (void)valueReference; (void)nDependencies;
    return ST(mf_unsupported(INST(instance), "fmi3GetNumberOfVariableDependencies",
                             "dependencies are listed in modelDescription.xml"));
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[],
                                       fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[],
                                       fmi3DependencyKind dependencyKinds[],
                                       size_t nDependencies)
{
    (void)dependent; (void)elementIndicesOfDependent; (void)independents;
    (void)elementIndicesOfIndependents; (void)dependencyKinds; (void)nDependencies;
    return ST(mf_unsupported(INST(instance), "fmi3GetVariableDependencies",
                             "dependencies are listed in modelDescription.xml"));
}

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{
    return ST(mf_get_state(INST(instance), "fmi3GetFMUState", FMUState));
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState)
{
    return ST(mf_set_state(INST(instance), "fmi3SetFMUState", FMUState));
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{
    return ST(mf_free_state(INST(instance), "fmi3FreeFMUState", FMUState));
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t *size)
{
    return ST(mf_serialized_state_size(INST(instance), "fmi3SerializedFMUStateSize", FMUState,
                                       size));
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState,
                                 fmi3Byte serializedState[], size_t size)
{
    return ST(mf_serialize_state(INST(instance), "fmi3SerializeFMUState", FMUState,
                                 serializedState, size));
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[],
                                   size_t size, fmi3FMUState *FMUState)
{
    return ST(mf_deserialize_state(INST(instance), "fmi3DeserializeFMUState", serializedState,
                                   size, FMUState));
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[],
                                        size_t nUnknowns, const fmi3ValueReference knowns[],
                                        size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
                                        fmi3Float64 sensitivity[], size_t nSensitivity)
{
    return ST(mf_partial_derivatives(INST(instance), "fmi3GetDirectionalDerivative", 0, unknowns,
                                     nUnknowns, knowns, nKnowns, seed, nSeed, sensitivity,
                                     nSensitivity));
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[],
                                    size_t nUnknowns, const fmi3ValueReference knowns[],
                                    size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
                                    fmi3Float64 sensitivity[], size_t nSensitivity)
{
    return ST(mf_partial_derivatives(INST(instance), "fmi3GetAdjointDerivative", 1, unknowns,
                                     nUnknowns, knowns, nKnowns, seed, nSeed, sensitivity,
                                     nSensitivity));
}

/* --- configuration, clocks --------------------------------------------------- */

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance)
{
    return ST(mf_unsupported(INST(instance), "fmi3EnterConfigurationMode",
                             "it has no structural parameters"));
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance)
{
    return ST(mf_unsupported(INST(instance), "fmi3ExitConfigurationMode",
                             "it has no structural parameters"));
}

#define NO_CLOCKS(fn) return ST(mf_unsupported(INST(instance), fn, "it has no clocks"))

fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                  fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[])
{
    (void)vr; (void)nvr; (void)intervals; (void)qualifiers;
    NO_CLOCKS("fmi3GetIntervalDecimal");
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[],
                                   size_t nvr, fmi3UInt64 counters[], fmi3UInt64 resolutions[],
                                   fmi3IntervalQualifier qualifiers[])
{
    (void)vr; (void)nvr; (void)counters; (void)resolutions; (void)qualifiers;
    NO_CLOCKS("fmi3GetIntervalFraction");
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                               fmi3Float64 shifts[])
{
    (void)vr; (void)nvr; (void)shifts;
    NO_CLOCKS("fmi3GetShiftDecimal");
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                fmi3UInt64 counters[], fmi3UInt64 resolutions[])
{
    (void)vr; (void)nvr; (void)counters; (void)resolutions;
    NO_CLOCKS("fmi3GetShiftFraction");
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                  const fmi3Float64 intervals[])
{
    (void)vr; (void)nvr; (void)intervals;
    NO_CLOCKS("fmi3SetIntervalDecimal");
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[],
                                   size_t nvr, const fmi3UInt64 counters[],
                                   const fmi3UInt64 resolutions[])
{
    (void)vr; (void)nvr; (void)counters; (void)resolutions;
    NO_CLOCKS("fmi3SetIntervalFraction");
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                               const fmi3Float64 shifts[])
{
    (void)vr; (void)nvr; (void)shifts;
    NO_CLOCKS("fmi3SetShiftDecimal");
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    (void)vr; (void)nvr; (void)counters; (void)resolutions;
    NO_CLOCKS("fmi3SetShiftFraction");
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance)
{
    NO_CLOCKS("fmi3EvaluateDiscreteStates");
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime)
{
    (void)clockReference; (void)activationTime;
    return ST(mf_unsupported(INST(instance), "fmi3ActivateModelPartition",
                             "it does not implement Scheduled Execution"));
}

/* --- events ------------------------------------------------------------------ */

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation,
                                    fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged,
                                    fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime)
{
    int changed = 0, terminate = 0;
    mf_status s = mf_update_discrete_states(INST(instance), "fmi3UpdateDiscreteStates", &changed,
                                            &terminate);
    /* event iteration runs to its fixed point inside, and there are no time events */
    if (discreteStatesNeedUpdate) *discreteStatesNeedUpdate = fmi3False;
    if (terminateSimulation) *terminateSimulation = terminate != 0;
    if (nominalsOfContinuousStatesChanged) *nominalsOfContinuousStatesChanged = fmi3False;
    if (valuesOfContinuousStatesChanged) *valuesOfContinuousStatesChanged = changed != 0;
    if (nextEventTimeDefined) *nextEventTimeDefined = fmi3False;
    if (nextEventTime) *nextEventTime = 0.0;
    return ST(s);
}

/* --- Model Exchange ------------------------------------------------------- */

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance)
{
    return ST(mf_enter_continuous_time_mode(INST(instance), "fmi3EnterContinuousTimeMode"));
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance,
                                       fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode,
                                       fmi3Boolean *terminateSimulation)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    /* the importer finds events from the indicators; no step events here */
    if (enterEventMode) *enterEventMode = fmi3False;
    if (terminateSimulation) *terminateSimulation = fmi3False;
    return ST(mf_completed_integrator_step(INST(instance), "fmi3CompletedIntegratorStep"));
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time)
{
    return ST(mf_set_time(INST(instance), "fmi3SetTime", time));
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[],
                                   size_t nContinuousStates)
{
    return ST(mf_set_continuous_states(INST(instance), "fmi3SetContinuousStates",
                                       continuousStates, nContinuousStates));
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[],
                                             size_t nContinuousStates)
{
    return ST(mf_get_derivatives(INST(instance), "fmi3GetContinuousStateDerivatives",
                                 derivatives, nContinuousStates));
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[],
                                  size_t nEventIndicators)
{
    return ST(mf_get_event_indicators(INST(instance), "fmi3GetEventIndicators", eventIndicators,
                                      nEventIndicators));
}

/* Not FMI: mechfmu's engine looks this up by name in an FMU it runs alone and, where it
   is there, calls it for each right-hand side and indicator sample instead of
   fmi3SetTime, fmi3SetContinuousStates and the reads: one call through the library
   boundary instead of four, each through the engine's and this file's wrappers and
   checks, which cost more than a small model's right-hand side. derivatives or
   eventIndicators NULL: not read. The runtime's mf_evaluate_at does the ordinary case;
   where it declines (a point one of the four would refuse, or a runtime without it: an
   assembly's), the four calls follow here, and say why they refuse. */
__attribute__((visibility("default"))) fmi3Status
mfEvaluateAt(fmi3Instance instance, fmi3Float64 time, const fmi3Float64 continuousStates[],
             size_t nContinuousStates, fmi3Float64 derivatives[], fmi3Float64 eventIndicators[],
             size_t nEventIndicators)
{
    mf_instance *I = INST(instance);
    mf_status st, next;
    if (mf_evaluate_at(I, time, continuousStates, nContinuousStates, derivatives,
                       eventIndicators, nEventIndicators) == MF_OK)
        return fmi3OK;
    st = mf_set_time(I, "fmi3SetTime", time);
    /* a warning goes on, as it would between the four calls; the worst status is returned */
    if (st <= MF_WARNING) {
        next = mf_set_continuous_states(I, "fmi3SetContinuousStates", continuousStates,
                                        nContinuousStates);
        st = next > st ? next : st;
    }
    if (st <= MF_WARNING && derivatives) {
        next = mf_get_derivatives(I, "fmi3GetContinuousStateDerivatives", derivatives,
                                  nContinuousStates);
        st = next > st ? next : st;
    }
    if (st <= MF_WARNING && eventIndicators) {
        next = mf_get_event_indicators(I, "fmi3GetEventIndicators", eventIndicators,
                                       nEventIndicators);
        st = next > st ? next : st;
    }
    return ST(st);
}

/* Not FMI: mfEvaluateAt without moving the instance (mf_evaluate_off). The engine's
   integrator asks for the derivatives at six trial points per step and the indicators at
   a few more, points the instance is never needed at: mfEvaluateAt stores each point in
   the instance and drops what it had computed, and that bookkeeping costs about as much
   as a small model's right-hand side. 0, or 1 (nothing logged) wherever mfEvaluateAt
   would have to make the separate calls: the caller makes them, and they say why. The
   arrays hold as many values as the model has states and indicators. Plain C types, so
   that the engine calls it through a pointer of exactly its type. */
__attribute__((visibility("default"))) int
mfEvaluateOff(void *instance, double time, const double continuousStates[], double derivatives[],
              double eventIndicators[])
{
    return mf_evaluate_off(INST(instance), time, continuousStates, derivatives,
                           eventIndicators) == MF_OK ? 0 : 1;
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[],
                                   size_t nContinuousStates)
{
    return ST(mf_get_continuous_states(INST(instance), "fmi3GetContinuousStates",
                                       continuousStates, nContinuousStates));
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[],
                                             size_t nContinuousStates)
{
    return ST(mf_get_nominals(INST(instance), "fmi3GetNominalsOfContinuousStates", nominals,
                              nContinuousStates));
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators)
{
    return ST(mf_get_number_of_event_indicators(INST(instance), "fmi3GetNumberOfEventIndicators",
                                                nEventIndicators));
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates)
{
    return ST(mf_get_number_of_states(INST(instance), "fmi3GetNumberOfContinuousStates",
                                      nContinuousStates));
}

/* --- Co-Simulation ---------------------------------------------------------- */

fmi3Status fmi3EnterStepMode(fmi3Instance instance)
{
    return ST(mf_enter_step_mode(INST(instance), "fmi3EnterStepMode"));
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference vr[],
                                    size_t nvr, const fmi3Int32 orders[], fmi3Float64 values[],
                                    size_t nValues)
{
    (void)vr; (void)nvr; (void)orders; (void)values; (void)nValues;
    return ST(mf_unsupported(INST(instance), "fmi3GetOutputDerivatives", "output derivatives are not provided"));
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                      fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime)
{
    double reached = currentCommunicationPoint;
    int terminate = 0, early = 0;
    mf_status s;
    (void)noSetFMUStatePriorToCurrentPoint;
    s = mf_do_step(INST(instance), "fmi3DoStep", currentCommunicationPoint, communicationStepSize,
                   &reached, &terminate, &early);
    /* events are handled inside the step, also when it returns early at one */
    if (eventHandlingNeeded) *eventHandlingNeeded = fmi3False;
    if (terminateSimulation) *terminateSimulation = terminate != 0;
    if (earlyReturn) *earlyReturn = early != 0;
    if (lastSuccessfulTime) *lastSuccessfulTime = reached;
    return ST(s);
}
