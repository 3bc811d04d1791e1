/* term_me2: a mass dropped from h0 = 2 m (h' = v, v' = -9.81), FMI 2 Model Exchange,
   that ends the run when it hits the ground, the FMI 2 ME way, as the parameter
   `how` says: 0 at the state event of its indicator h, from fmi2NewDiscreteStates
   (terminateSimulation); 1 from fmi2CompletedIntegratorStep at the first step end
   with h <= 0 (its indicator then never crosses). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"
#define HANDMADE_ME
#define OWN_fmi2GetInteger
#define OWN_fmi2SetInteger
#define OWN_fmi2CompletedIntegratorStep
#define OWN_fmi2GetNominalsOfContinuousStates
#define OWN_fmi2NewDiscreteStates
#define OWN_fmi2GetEventIndicators
#include "../fmi2_defaults.h"

#define G 9.81

typedef struct {
    double time, h, v, h0;
    int how, terminated;
    char name[64];
    fmi2CallbackFunctions cb;
} Instance;

static void say(Instance *s, const char *text) {
    if (s->cb.logger) s->cb.logger(s->cb.componentEnvironment, s->name, fmi2OK, "logEvents", text);
}

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                              fmi2String location, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean logging) {
    (void)guid; (void)location; (void)visible; (void)logging;
    if (type != fmi2ModelExchange) return NULL;
    Instance *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    if (functions) s->cb = *functions;
    snprintf(s->name, sizeof s->name, "%s", name ? name : "term_me2");
    s->h0 = s->h = 2.0;
    return s;
}
fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDef, fmi2Real tol, fmi2Real t0,
                               fmi2Boolean stopDef, fmi2Real t1) {
    (void)tolDef; (void)tol; (void)stopDef; (void)t1;
    ((Instance *)c)->time = t0; return fmi2OK;
}
fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    Instance *s = c; s->h = s->h0; s->v = 0; return fmi2OK;
}
fmi2Status fmi2Reset(fmi2Component c) {
    Instance *s = c;
    s->time = 0; s->h0 = s->h = 2.0; s->v = 0; s->how = 0; s->terminated = 0; return fmi2OK;
}
/* value references: 1 h, 2 v, 3 der(h), 4 der(v), 5 h0; Integer 6 how */
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        switch (vr[i]) {
        case 1: v[i] = s->h; break;
        case 2: case 3: v[i] = s->v; break;
        case 4: v[i] = -G; break;
        case 5: v[i] = s->h0; break;
        default: return fmi2Error;
        }
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != 5) return fmi2Error;
        s->h0 = v[i];
    }
    return fmi2OK;
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != 6) return fmi2Error;
        v[i] = s->how;
    }
    return fmi2OK;
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != 6 || v[i] < 0 || v[i] > 1) return fmi2Error;
        s->how = v[i];
    }
    return fmi2OK;
}

/* Model Exchange */
fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *e) {
    Instance *s = c;
    memset(e, 0, sizeof *e);
    if (s->how == 0 && s->h <= 0.0 && s->time > 0.0) {
        s->terminated = 1;
        e->terminateSimulation = fmi2True;
        say(s, "the mass hit the ground (state event)");
    }
    return fmi2OK;
}
fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetPrior,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminate) {
    Instance *s = c;
    (void)noSetPrior;
    *enterEventMode = fmi2False;
    *terminate = fmi2False;
    if (s->how == 1 && s->h <= 0.0) {
        s->terminated = 1;
        *terminate = fmi2True;
        say(s, "the mass hit the ground (step end)");
    }
    return fmi2OK;
}
fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) { ((Instance *)c)->time = t; return fmi2OK; }
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t n) {
    Instance *s = c;
    if (n != 2) return fmi2Error;
    s->h = x[0]; s->v = x[1]; return fmi2OK;
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t n) {
    Instance *s = c;
    if (n != 2) return fmi2Error;
    dx[0] = s->v; dx[1] = -G; return fmi2OK;
}
fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real z[], size_t n) {
    Instance *s = c;
    if (n != 1) return fmi2Error;
    z[0] = s->how == 0 ? s->h : 1.0;
    return fmi2OK;
}
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
    Instance *s = c;
    if (n != 2) return fmi2Error;
    x[0] = s->h; x[1] = s->v; return fmi2OK;
}
fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
    (void)c;
    for (size_t i = 0; i < n; i++) x[i] = 1.0;
    return fmi2OK;
}
