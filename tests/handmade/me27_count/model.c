/* me27_count: an undamped oscillator x' = v, v' = -w^2 x (x(0) = 1, v(0) = 0: x = cos wt),
   FMI 2 Model Exchange, that counts how an importer takes it through events: entered =
   fmi2EnterEventMode calls, updated = fmi2NewDiscreteStates calls, misplaced = calls
   its state machine forbids where they come (event mode entered from anywhere but
   continuous-time mode, discrete updates or continuous-time mode outside event mode).
   One event indicator: with period > 0, cos(pi t / period), an event that changes
   nothing every period from period / 2; else 2 + sin t, which never crosses zero. With
   tick > 0, a time event (that changes nothing) at every multiple of tick. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"
#define HANDMADE_CS
#define HANDMADE_ME
#define OWN_fmi2EnterEventMode
#define OWN_fmi2EnterContinuousTimeMode
#define OWN_fmi2NewDiscreteStates
#define OWN_fmi2GetEventIndicators
#include "../fmi2_defaults.h"

enum { VR_X, VR_V, VR_DX, VR_DV, VR_W, VR_PERIOD, VR_POS, VR_ENTERED, VR_UPDATED,
       VR_MISPLACED, VR_TICK, N_VR };
enum { MODE_SETUP, MODE_EVENT, MODE_CONTINUOUS };

typedef struct {
    double time, v[N_VR];
    int mode;
} Instance;

static void reset(Instance *s)
{
    memset(s, 0, sizeof *s);
    s->v[VR_X] = 1.0;
    s->v[VR_W] = 2.0;
}

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                              fmi2String location, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean logging) {
    (void)name; (void)guid; (void)location; (void)functions; (void)visible; (void)logging;
    if (type != fmi2ModelExchange) return NULL;
    Instance *s = calloc(1, sizeof *s);
    if (s) reset(s);
    return s;
}
fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDef, fmi2Real tol, fmi2Real t0,
                               fmi2Boolean stopDef, fmi2Real t1) {
    (void)tolDef; (void)tol; (void)stopDef; (void)t1;
    ((Instance *)c)->time = t0; return fmi2OK;
}
/* FMI 2 ME: initialization is left into event mode */
fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    ((Instance *)c)->mode = MODE_EVENT; return fmi2OK;
}
fmi2Status fmi2Reset(fmi2Component c) { reset(c); return fmi2OK; }
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *s = c;
    s->v[VR_DX] = s->v[VR_V];
    s->v[VR_DV] = -s->v[VR_W] * s->v[VR_W] * s->v[VR_X];
    s->v[VR_POS] = s->v[VR_X];
    for (size_t i = 0; i < n; i++) {
        if (vr[i] >= N_VR) return fmi2Error;
        v[i] = s->v[vr[i]];
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != VR_X && vr[i] != VR_V && vr[i] != VR_W && vr[i] != VR_PERIOD &&
            vr[i] != VR_TICK)
            return fmi2Error;
        s->v[vr[i]] = v[i];
    }
    return fmi2OK;
}
fmi2Status fmi2EnterEventMode(fmi2Component c) {
    Instance *s = c;
    s->v[VR_ENTERED] += 1.0;
    if (s->mode != MODE_CONTINUOUS) s->v[VR_MISPLACED] += 1.0;
    s->mode = MODE_EVENT;
    return fmi2OK;
}
fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info) {
    Instance *s = c;
    s->v[VR_UPDATED] += 1.0;
    if (s->mode != MODE_EVENT) s->v[VR_MISPLACED] += 1.0;
    memset(info, 0, sizeof *info);
    if (s->v[VR_TICK] > 0.0) { /* the next multiple after the time it stands at */
        const double tick = s->v[VR_TICK];
        info->nextEventTimeDefined = fmi2True;
        info->nextEventTime = (floor(s->time / tick + 1e-9) + 1.0) * tick;
    }
    return fmi2OK;
}
fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) {
    Instance *s = c;
    if (s->mode != MODE_EVENT) s->v[VR_MISPLACED] += 1.0;
    s->mode = MODE_CONTINUOUS;
    return fmi2OK;
}
fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) { ((Instance *)c)->time = t; return fmi2OK; }
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    Instance *s = c;
    if (nx != 2) return fmi2Error;
    s->v[VR_X] = x[0];
    s->v[VR_V] = x[1];
    return fmi2OK;
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t nx) {
    Instance *s = c;
    if (nx != 2) return fmi2Error;
    dx[0] = s->v[VR_V];
    dx[1] = -s->v[VR_W] * s->v[VR_W] * s->v[VR_X];
    return fmi2OK;
}
fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real z[], size_t nz) {
    Instance *s = c;
    if (nz != 1) return fmi2Error;
    z[0] = s->v[VR_PERIOD] > 0.0 ? cos(3.14159265358979323846 * s->time / s->v[VR_PERIOD])
                                 : 2.0 + sin(s->time);
    return fmi2OK;
}
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    Instance *s = c;
    if (nx != 2) return fmi2Error;
    x[0] = s->v[VR_X];
    x[1] = s->v[VR_V];
    return fmi2OK;
}

/* Co-Simulation functions: not this FMU's interface */
fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetPrior) {
    (void)c; (void)t; (void)h; (void)noSetPrior; return fmi2Error;
}
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind k, fmi2Real *v) {
    (void)c; (void)k; (void)v; return fmi2Discard;
}
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind k, fmi2Boolean *v) {
    (void)c; (void)k; (void)v; return fmi2Discard;
}
