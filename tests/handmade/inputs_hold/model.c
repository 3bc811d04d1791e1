/* inputs_hold: x' = d for a discrete input d, y = u for a continuous input u and
   k_out = k for an Integer input k, FMI 2
   Model Exchange and Co-Simulation. Whatever an importer feeds d between events shows
   in x (a held d makes x piecewise linear), and whatever it feeds u and k at a point
   shows in y and k_out there; the Co-Simulation step integrates x exactly for the d set before it. */
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"
#define HANDMADE_CS
#define HANDMADE_ME
#define OWN_fmi2GetInteger
#define OWN_fmi2SetInteger
#define OWN_fmi2GetNominalsOfContinuousStates
#include "../fmi2_defaults.h"

typedef struct {
    double time, u, d, x;
    int k;
} Instance;

#define UNUSED(x) (void)(x)

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                              fmi2String location, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean logging) {
    UNUSED(name); UNUSED(type); UNUSED(guid); UNUSED(location); UNUSED(functions);
    UNUSED(visible); UNUSED(logging);
    return calloc(1, sizeof(Instance));
}
fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDef, fmi2Real tol, fmi2Real t0,
                               fmi2Boolean stopDef, fmi2Real t1) {
    UNUSED(tolDef); UNUSED(tol); UNUSED(stopDef); UNUSED(t1);
    ((Instance *)c)->time = t0; return fmi2OK;
}
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { UNUSED(c); return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) { memset(c, 0, sizeof(Instance)); return fmi2OK; }

static double *slot(Instance *s, fmi2ValueReference vr) {
    switch (vr) {
    case 0: return &s->u;
    case 1: return &s->d;
    case 2: return &s->x;
    default: return NULL;
    }
}
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] == 3) v[i] = s->d;
        else if (vr[i] == 4) v[i] = s->u;
        else if (slot(s, vr[i])) v[i] = *slot(s, vr[i]);
        else return fmi2Error;
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (!slot(s, vr[i])) return fmi2Error;
        *slot(s, vr[i]) = v[i];
    }
    return fmi2OK;
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != 5 && vr[i] != 6) return fmi2Error;
        v[i] = s->k;
    }
    return fmi2OK;
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != 5) return fmi2Error;
        s->k = v[i];
    }
    return fmi2OK;
}

/* Model Exchange */
fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) { ((Instance *)c)->time = t; return fmi2OK; }
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t n) {
    if (n != 1) return fmi2Error;
    ((Instance *)c)->x = x[0]; return fmi2OK;
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t n) {
    if (n != 1) return fmi2Error;
    dx[0] = ((Instance *)c)->d; return fmi2OK;
}
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
    if (n != 1) return fmi2Error;
    x[0] = ((Instance *)c)->x; return fmi2OK;
}
fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
    UNUSED(c);
    if (n != 1) return fmi2Error;
    x[0] = 1.0; return fmi2OK;
}

/* Co-Simulation: d is constant over a step, so x moves by d h exactly */
fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetPrior) {
    Instance *s = c;
    UNUSED(noSetPrior);
    s->x += s->d * h;
    s->time = t + h;
    return fmi2OK;
}
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind k, fmi2Real *v) {
    UNUSED(c); UNUSED(k); UNUSED(v); return fmi2Discard;
}
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind k, fmi2Boolean *v) {
    UNUSED(c); UNUSED(k); UNUSED(v); return fmi2Discard;
}
