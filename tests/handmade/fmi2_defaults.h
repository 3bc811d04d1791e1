/* fmi2_defaults.h: the FMI 2 functions a hand-written test FMU leaves at their plainest,
   written once. Each answers as an FMU without that capability must: the variables of a
   type it has none of, FMU state and directional derivatives (capabilities its
   description does not declare) are an Error when asked for values, lifecycle calls
   that have nothing to do return OK.

   Include it after fmi2Functions.h. A model writes its own version of any of these by
   defining OWN_<function> first (term_decay restores its state, so it defines
   OWN_fmi2GetFMUstate and the rest); HANDMADE_CS and HANDMADE_ME add the functions of
   each interface the model implements, so that its library exports what it did when
   each model spelled them out. */
#ifndef HANDMADE_FMI2_DEFAULTS_H
#define HANDMADE_FMI2_DEFAULTS_H

#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"

#ifndef OWN_fmi2GetTypesPlatform
const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
#endif
#ifndef OWN_fmi2GetVersion
const char *fmi2GetVersion(void) { return fmi2Version; }
#endif
#ifndef OWN_fmi2SetDebugLogging
fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String cat[]) {
    (void)c; (void)on; (void)n; (void)cat; return fmi2OK;
}
#endif
#ifndef OWN_fmi2FreeInstance
void fmi2FreeInstance(fmi2Component c) { free(c); }
#endif
#ifndef OWN_fmi2EnterInitializationMode
fmi2Status fmi2EnterInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
#endif
#ifndef OWN_fmi2Terminate
fmi2Status fmi2Terminate(fmi2Component c) { (void)c; return fmi2OK; }
#endif
#ifndef OWN_fmi2GetInteger
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[]) {
    (void)c; (void)vr; (void)v; return n ? fmi2Error : fmi2OK;
}
#endif
#ifndef OWN_fmi2GetBoolean
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean v[]) {
    (void)c; (void)vr; (void)v; return n ? fmi2Error : fmi2OK;
}
#endif
#ifndef OWN_fmi2GetString
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2String v[]) {
    (void)c; (void)vr; (void)v; return n ? fmi2Error : fmi2OK;
}
#endif
#ifndef OWN_fmi2SetInteger
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[]) {
    (void)c; (void)vr; (void)v; return n ? fmi2Error : fmi2OK;
}
#endif
#ifndef OWN_fmi2SetBoolean
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[]) {
    (void)c; (void)vr; (void)v; return n ? fmi2Error : fmi2OK;
}
#endif
#ifndef OWN_fmi2SetString
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2String v[]) {
    (void)c; (void)vr; (void)v; return n ? fmi2Error : fmi2OK;
}
#endif
#ifndef OWN_fmi2GetFMUstate
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *st) { (void)c; (void)st; return fmi2Error; }
#endif
#ifndef OWN_fmi2SetFMUstate
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate st) { (void)c; (void)st; return fmi2Error; }
#endif
#ifndef OWN_fmi2FreeFMUstate
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *st) { (void)c; (void)st; return fmi2Error; }
#endif
#ifndef OWN_fmi2SerializedFMUstateSize
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate st, size_t *n) {
    (void)c; (void)st; (void)n; return fmi2Error;
}
#endif
#ifndef OWN_fmi2SerializeFMUstate
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate st, fmi2Byte b[], size_t n) {
    (void)c; (void)st; (void)b; (void)n; return fmi2Error;
}
#endif
#ifndef OWN_fmi2DeSerializeFMUstate
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t n, fmi2FMUstate *st) {
    (void)c; (void)b; (void)n; (void)st; return fmi2Error;
}
#endif
#ifndef OWN_fmi2GetDirectionalDerivative
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference k[], size_t nk,
                                        const fmi2Real dk[], fmi2Real du[]) {
    (void)c; (void)u; (void)nu; (void)k; (void)nk; (void)dk; (void)du; return fmi2Error;
}
#endif

#ifdef HANDMADE_CS
#ifndef OWN_fmi2SetRealInputDerivatives
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                       const fmi2Integer o[], const fmi2Real v[]) {
    (void)c; (void)vr; (void)n; (void)o; (void)v; return fmi2Error;
}
#endif
#ifndef OWN_fmi2GetRealOutputDerivatives
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                        const fmi2Integer o[], fmi2Real v[]) {
    (void)c; (void)vr; (void)n; (void)o; (void)v; return fmi2Error;
}
#endif
#ifndef OWN_fmi2CancelStep
fmi2Status fmi2CancelStep(fmi2Component c) { (void)c; return fmi2Error; }
#endif
#ifndef OWN_fmi2GetStatus
fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind k, fmi2Status *v) {
    (void)c; (void)k; (void)v; return fmi2Discard;
}
#endif
#ifndef OWN_fmi2GetIntegerStatus
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind k, fmi2Integer *v) {
    (void)c; (void)k; (void)v; return fmi2Discard;
}
#endif
#ifndef OWN_fmi2GetStringStatus
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind k, fmi2String *v) {
    (void)c; (void)k; (void)v; return fmi2Discard;
}
#endif
#endif

#ifdef HANDMADE_ME
#ifndef OWN_fmi2EnterEventMode
fmi2Status fmi2EnterEventMode(fmi2Component c) { (void)c; return fmi2OK; }
#endif
#ifndef OWN_fmi2EnterContinuousTimeMode
fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) { (void)c; return fmi2OK; }
#endif
#ifndef OWN_fmi2CompletedIntegratorStep
fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetPrior,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminate) {
    (void)c; (void)noSetPrior; *enterEventMode = fmi2False; *terminate = fmi2False; return fmi2OK;
}
#endif
#ifndef OWN_fmi2GetNominalsOfContinuousStates
fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    (void)c;
    for (size_t i = 0; i < nx; i++) x[i] = 1.0;
    return fmi2OK;
}
#endif
/* no discrete states: an event changes nothing and schedules no time event */
#ifndef OWN_fmi2NewDiscreteStates
fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info) {
    (void)c;
    memset(info, 0, sizeof *info);
    return fmi2OK;
}
#endif
/* no event indicators: asking for any is an error */
#ifndef OWN_fmi2GetEventIndicators
fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real z[], size_t nz) {
    (void)c; (void)z; return nz ? fmi2Error : fmi2OK;
}
#endif
#endif

#endif
