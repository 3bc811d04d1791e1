/* me_cached: an undamped oscillator x' = v, v' = -w^2 x (x(0) = 1, v(0) = 0: x = cos wt,
   v = -w sin wt), FMI 2 Model Exchange, whose outputs behave like some exporters'
   caches: with cache_outputs = 1 they are computed in fmi2SetTime alone, from the
   states the FMU holds at that moment. An importer that sets the time and then the
   states reads outputs of the states it set before (the last stage it evaluated)
   unless it sets the time once more. cache_outputs = 0: computed on every read.
   Outputs: pos = x, energy = (v^2 + w^2 x^2) / 2 (= w^2 / 2 for ever). One event
   indicator, 2 + sin t, moves with time and never crosses zero; with t_cross > 0 it is
   t_cross - t instead, an event (that changes nothing) at t_cross. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"
#define HANDMADE_CS
#define HANDMADE_ME
#define OWN_fmi2GetEventIndicators
#include "../fmi2_defaults.h"

enum { VR_X, VR_V, VR_DX, VR_DV, VR_W, VR_CACHE, VR_POS, VR_ENERGY, VR_CROSS, N_VR };

typedef struct {
    double time, v[N_VR];
} Instance;

static void outputs(Instance *s)
{
    const double x = s->v[VR_X], v = s->v[VR_V], w = s->v[VR_W];
    s->v[VR_POS] = x;
    s->v[VR_ENERGY] = 0.5 * (v * v + w * w * x * x);
}

static void derivatives(Instance *s)
{
    s->v[VR_DX] = s->v[VR_V];
    s->v[VR_DV] = -s->v[VR_W] * s->v[VR_W] * s->v[VR_X];
}

static void reset(Instance *s)
{
    memset(s, 0, sizeof *s);
    s->v[VR_X] = 1.0;
    s->v[VR_W] = 2.0;
    s->v[VR_CACHE] = 1.0;
    s->v[VR_CROSS] = -1.0;
    derivatives(s);
    outputs(s);
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
fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    derivatives(c); outputs(c); return fmi2OK;
}
fmi2Status fmi2Reset(fmi2Component c) { reset(c); return fmi2OK; }
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *s = c;
    derivatives(s);
    if (s->v[VR_CACHE] == 0.0) outputs(s);
    for (size_t i = 0; i < n; i++) {
        if (vr[i] >= N_VR) return fmi2Error;
        v[i] = s->v[vr[i]];
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != VR_X && vr[i] != VR_V && vr[i] != VR_W && vr[i] != VR_CACHE &&
            vr[i] != VR_CROSS)
            return fmi2Error;
        s->v[vr[i]] = v[i];
    }
    return fmi2OK;
}

/* the cache: the outputs of the states held now, which the states set next replace */
fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) {
    Instance *s = c;
    s->time = t;
    outputs(s);
    return fmi2OK;
}
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    Instance *s = c;
    if (nx != 2) return fmi2Error;
    s->v[VR_X] = x[0];
    s->v[VR_V] = x[1];
    if (s->v[VR_CACHE] == 0.0) outputs(s);
    return fmi2OK;
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t nx) {
    Instance *s = c;
    if (nx != 2) return fmi2Error;
    derivatives(s);
    dx[0] = s->v[VR_DX];
    dx[1] = s->v[VR_DV];
    return fmi2OK;
}
fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real z[], size_t nz) {
    Instance *s = c;
    if (nz != 1) return fmi2Error;
    z[0] = s->v[VR_CROSS] > 0.0 ? s->v[VR_CROSS] - s->time : 2.0 + sin(s->time);
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
