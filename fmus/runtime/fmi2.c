/*
 * FMI 2.0 adapter: every function of fmi2Functions.h, translated onto the
 * version-independent core in runtime.c. No behaviour lives here: one FMU
 * carries Model Exchange and Co-Simulation, and fmi2Instantiate's fmuType picks.
 */
#include "fmi2Functions.h"
#include "runtime.h"

#include <stdint.h>

#define INST(c) ((mf_instance *)(c))
#define ST(s) ((fmi2Status)(s))

/* The runtime takes value references as uint32_t and integers as int32_t; FMI 2
   declares them as unsigned int and int. Refuse to compile where they differ
   rather than reinterpret arrays of another width. */
typedef char vr_is_32_bits[sizeof(fmi2ValueReference) == sizeof(uint32_t) ? 1 : -1];
typedef char integer_is_32_bits[sizeof(fmi2Integer) == sizeof(int32_t) ? 1 : -1];

/* fmi2CallbackLogger is printf-like: the message goes through "%s", so that a '%'
   in it (a variable name, a unit) is never read as a conversion. */
static void dispatch(mf_generic_fn callback, void *environment, const char *instance_name,
                     mf_status status, const char *category, const char *message)
{
    ((fmi2CallbackLogger)callback)(environment, instance_name, (fmi2Status)status, category,
                                   "%s", message);
}

static mf_host host(const fmi2CallbackFunctions *functions)
{
    mf_host h;
    h.float_type = "Real";
    h.int_type = "Integer";
    h.token_name = "GUID";
    h.reset_hint = "fmi2Reset or fmi2SetFMUstate";
    h.dispatch = dispatch;
    h.callback = functions ? (mf_generic_fn)functions->logger : NULL;
    h.environment = functions ? functions->componentEnvironment : NULL;
    h.event_dispatch = NULL; /* FMI 2 has no intermediate update, nor early return */
    h.early_return_allowed = 0;
    h.event_callback = NULL;
    return h;
}

/* --- common -------------------------------------------------------------- */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[])
{
    return ST(mf_set_debug_logging(INST(c), "fmi2SetDebugLogging", loggingOn, nCategories,
                                   categories));
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation,
                              const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                              fmi2Boolean loggingOn)
{
    mf_host h = host(functions);
    mf_interface iface;
    (void)visible;
    if (fmuType == fmi2ModelExchange) {
        iface = MF_MODEL_EXCHANGE;
    } else if (fmuType == fmi2CoSimulation) {
        iface = MF_CO_SIMULATION;
    } else {
        /* there is no instance yet to log through, so the logger is called directly */
        if (h.callback)
            functions->logger(functions->componentEnvironment, instanceName ? instanceName : "",
                              fmi2Error, "logStatusError",
                              "fmi2Instantiate: fmuType %d is neither fmi2ModelExchange (0) nor "
                              "fmi2CoSimulation (1)", (int)fmuType);
        return NULL;
    }
    /* the GUID is our instantiation token; mf_create refuses a mismatch */
    return mf_create(&MF_MODEL, "fmi2Instantiate", instanceName, fmuGUID, fmuResourceLocation,
                     iface, loggingOn, 0, &h);
}

void fmi2FreeInstance(fmi2Component c) { mf_free(INST(c)); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    return ST(mf_setup_experiment(INST(c), "fmi2SetupExperiment", toleranceDefined, tolerance,
                                  startTime, stopTimeDefined, stopTime));
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    return ST(mf_enter_initialization_mode(INST(c), "fmi2EnterInitializationMode"));
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    return ST(mf_exit_initialization_mode(INST(c), "fmi2ExitInitializationMode"));
}

fmi2Status fmi2Terminate(fmi2Component c) { return ST(mf_terminate(INST(c), "fmi2Terminate")); }

fmi2Status fmi2Reset(fmi2Component c) { return ST(mf_reset(INST(c), "fmi2Reset")); }

/* --- getting and setting variables --------------------------------------- */

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       fmi2Real value[])
{
    return ST(mf_get_float(INST(c), "fmi2GetReal", vr, nvr, value, nvr));
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Integer value[])
{
    return ST(mf_get_int(INST(c), "fmi2GetInteger", vr, nvr, value, nvr));
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       const fmi2Real value[])
{
    return ST(mf_set_float(INST(c), "fmi2SetReal", vr, nvr, value, nvr));
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Integer value[])
{
    return ST(mf_set_int(INST(c), "fmi2SetInteger", vr, nvr, value, nvr));
}

/* Types this FMU never has variables of. */
#define NO_TYPE(fn, type)                                                                     \
    return ST(mf_unsupported(INST(c), fn, "it has no " type " variables, only Real and Integer"))

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Boolean value[])
{
    (void)vr; (void)nvr; (void)value;
    NO_TYPE("fmi2GetBoolean", "Boolean");
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         fmi2String value[])
{
    (void)vr; (void)nvr; (void)value;
    NO_TYPE("fmi2GetString", "String");
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Boolean value[])
{
    (void)vr; (void)nvr; (void)value;
    NO_TYPE("fmi2SetBoolean", "Boolean");
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         const fmi2String value[])
{
    (void)vr; (void)nvr; (void)value;
    NO_TYPE("fmi2SetString", "String");
}

/* --- FMU state, derivatives ------------------------------------------------ */

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    return ST(mf_get_state(INST(c), "fmi2GetFMUstate", FMUstate));
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate)
{
    return ST(mf_set_state(INST(c), "fmi2SetFMUstate", FMUstate));
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    return ST(mf_free_state(INST(c), "fmi2FreeFMUstate", FMUstate));
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size)
{
    return ST(mf_serialized_state_size(INST(c), "fmi2SerializedFMUstateSize", FMUstate, size));
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[],
                                 size_t size)
{
    return ST(mf_serialize_state(INST(c), "fmi2SerializeFMUstate", FMUstate,
                                 (unsigned char *)serializedState, size));
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *FMUstate)
{
    return ST(mf_deserialize_state(INST(c), "fmi2DeSerializeFMUstate",
                                   (const unsigned char *)serializedState, size, FMUstate));
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[],
                                        size_t nUnknown, const fmi2ValueReference vKnown_ref[],
                                        size_t nKnown, const fmi2Real dvKnown[],
                                        fmi2Real dvUnknown[])
{
    /* dvUnknown = J dvKnown: one seed per known, one result per unknown */
    return ST(mf_partial_derivatives(INST(c), "fmi2GetDirectionalDerivative", 0, vUnknown_ref,
                                     nUnknown, vKnown_ref, nKnown, dvKnown, nKnown, dvUnknown,
                                     nUnknown));
}

/* --- Model Exchange -------------------------------------------------------- */

fmi2Status fmi2EnterEventMode(fmi2Component c)
{
    return ST(mf_enter_event_mode(INST(c), "fmi2EnterEventMode"));
}

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *eventInfo)
{
    int changed = 0, terminate = 0;
    mf_status s = mf_update_discrete_states(INST(c), "fmi2NewDiscreteStates", &changed,
                                            &terminate);
    if (eventInfo) {
        /* event iteration runs to its fixed point inside, and there are no time events */
        eventInfo->newDiscreteStatesNeeded = fmi2False;
        eventInfo->terminateSimulation = terminate != 0;
        eventInfo->nominalsOfContinuousStatesChanged = fmi2False;
        eventInfo->valuesOfContinuousStatesChanged = changed != 0;
        eventInfo->nextEventTimeDefined = fmi2False;
        eventInfo->nextEventTime = 0.0;
    }
    return ST(s);
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c)
{
    return ST(mf_enter_continuous_time_mode(INST(c), "fmi2EnterContinuousTimeMode"));
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c,
                                       fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode,
                                       fmi2Boolean *terminateSimulation)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    /* the importer finds events from the indicators; no step events here */
    if (enterEventMode) *enterEventMode = fmi2False;
    if (terminateSimulation) *terminateSimulation = fmi2False;
    return ST(mf_completed_integrator_step(INST(c), "fmi2CompletedIntegratorStep"));
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time)
{
    return ST(mf_set_time(INST(c), "fmi2SetTime", time));
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx)
{
    return ST(mf_set_continuous_states(INST(c), "fmi2SetContinuousStates", x, nx));
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx)
{
    return ST(mf_get_derivatives(INST(c), "fmi2GetDerivatives", derivatives, nx));
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni)
{
    return ST(mf_get_event_indicators(INST(c), "fmi2GetEventIndicators", eventIndicators, ni));
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx)
{
    return ST(mf_get_continuous_states(INST(c), "fmi2GetContinuousStates", x, nx));
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx)
{
    return ST(mf_get_nominals(INST(c), "fmi2GetNominalsOfContinuousStates", x_nominal, nx));
}

/* --- Co-Simulation ---------------------------------------------------------- */

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    (void)vr; (void)nvr; (void)order; (void)value;
    /* canInterpolateInputs="false": a moving flange's velocity input already
       carries the derivative of its position */
    return ST(mf_unsupported(INST(c), "fmi2SetRealInputDerivatives",
                             "canInterpolateInputs is false; set the velocity and acceleration "
                             "inputs of a flange instead"));
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[])
{
    (void)vr; (void)nvr; (void)order; (void)value;
    return ST(mf_unsupported(INST(c), "fmi2GetRealOutputDerivatives",
                             "maxOutputDerivativeOrder is 0"));
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                      fmi2Real communicationStepSize, fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    double reached = currentCommunicationPoint;
    int terminate = 0;
    mf_status s;
    (void)noSetFMUStatePriorToCurrentPoint;
    s = mf_do_step(INST(c), "fmi2DoStep", currentCommunicationPoint, communicationStepSize,
                   &reached, &terminate, NULL);
    /* FMI 2 reports a model that ended the run as Discard; the master then asks
       fmi2GetBooleanStatus(fmi2Terminated) and fmi2GetRealStatus(fmi2LastSuccessfulTime) */
    if (s == MF_OK && terminate) return fmi2Discard;
    return ST(s);
}

fmi2Status fmi2CancelStep(fmi2Component c)
{
    return ST(mf_unsupported(INST(c), "fmi2CancelStep",
                             "fmi2DoStep never returns fmi2Pending, so there is no step to cancel"));
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value)
{
    (void)s; (void)value;
    return ST(mf_unsupported(INST(c), "fmi2GetStatus",
                             "fmi2DoStep is synchronous; its return value is the status"));
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value)
{
    if (s != fmi2LastSuccessfulTime)
        return ST(mf_unsupported(INST(c), "fmi2GetRealStatus",
                                 "only fmi2LastSuccessfulTime is a Real status"));
    return ST(mf_get_time(INST(c), "fmi2GetRealStatus", value));
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value)
{
    (void)s; (void)value;
    return ST(mf_unsupported(INST(c), "fmi2GetIntegerStatus", "there is no Integer status"));
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value)
{
    int terminated = 0;
    mf_status st;
    if (s != fmi2Terminated)
        return ST(mf_unsupported(INST(c), "fmi2GetBooleanStatus",
                                 "only fmi2Terminated is a Boolean status"));
    /* the runtime checks `value` for NULL through its own int */
    st = mf_get_terminated(INST(c), "fmi2GetBooleanStatus", value ? &terminated : NULL);
    if (st == MF_OK) *value = terminated ? fmi2True : fmi2False;
    return ST(st);
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value)
{
    (void)s; (void)value;
    return ST(mf_unsupported(INST(c), "fmi2GetStringStatus",
                             "fmi2DoStep is synchronous; there is no pending status"));
}
