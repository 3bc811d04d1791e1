/* stair2: a counter of whole seconds, FMI 2 Co-Simulation, that ends its run the FMI 2
   way: a doStep reaching t = 5 s returns fmi2Discard at t = 5 and fmi2GetBooleanStatus
   (fmi2Terminated) then says true, fmi2GetRealStatus(fmi2LastSuccessfulTime) 5. */
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"
#define HANDMADE_CS
#define OWN_fmi2GetInteger
#include "../fmi2_defaults.h"

#define T_END 5.0

typedef struct {
    double time;
    int counter;
    int terminated;
    fmi2CallbackFunctions cb;
} Instance;

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                              fmi2String location, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean logging) {
    (void)name; (void)guid; (void)location; (void)visible; (void)logging;
    if (type != fmi2CoSimulation) return NULL;
    Instance *s = calloc(1, sizeof *s);
    if (s && functions) s->cb = *functions;
    return s;
}
fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDef, fmi2Real tol, fmi2Real t0,
                               fmi2Boolean stopDef, fmi2Real t1) {
    (void)tolDef; (void)tol; (void)stopDef; (void)t1;
    ((Instance *)c)->time = t0; return fmi2OK;
}
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) {
    Instance *s = c; s->time = 0; s->counter = 0; s->terminated = 0; return fmi2OK;
}
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != 2) return fmi2Error;
        v[i] = s->time;
    }
    return fmi2OK;
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != 1) return fmi2Error;
        v[i] = s->counter;
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    (void)c; (void)vr; (void)v; return n ? fmi2Error : fmi2OK;
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetPrior) {
    Instance *s = c;
    (void)noSetPrior;
    if (s->terminated) return fmi2Error;
    double target = t + h;
    if (target >= T_END - 1e-12) {
        s->time = T_END;
        s->counter = (int)T_END;
        s->terminated = 1;
        if (s->cb.logger)
            s->cb.logger(s->cb.componentEnvironment, "stair2", fmi2Discard, "logStatusDiscard",
                         "the staircase ends at t = 5 s");
        return fmi2Discard;
    }
    s->time = target;
    s->counter = (int)(target + 1e-9);
    return fmi2OK;
}
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind k, fmi2Real *v) {
    Instance *s = c;
    if (k != fmi2LastSuccessfulTime) return fmi2Discard;
    *v = s->time; return fmi2OK;
}
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind k, fmi2Boolean *v) {
    Instance *s = c;
    if (k != fmi2Terminated) return fmi2Discard;
    *v = s->terminated; return fmi2OK;
}
