/* sp_relay: y = u + 1 (direct feedthrough) beside a decay x' = -x (x(0) = 1), FMI 2
   Model Exchange. init_sets counts the fmi2SetReal calls that set u between
   fmi2EnterInitializationMode and fmi2ExitInitializationMode: a chain of relays shows
   how often an importer sets every input to settle the chain's outputs before the run. */
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"
#define HANDMADE_ME
#define OWN_fmi2EnterInitializationMode
#include "../fmi2_defaults.h"

enum { VR_X, VR_DX, VR_U, VR_Y, VR_SETS, N_VR };

typedef struct {
    double time, v[N_VR];
    int initializing;
} Instance;

static void reset(Instance *s)
{
    memset(s, 0, sizeof *s);
    s->v[VR_X] = 1.0;
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
fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    ((Instance *)c)->initializing = 1; return fmi2OK;
}
fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    ((Instance *)c)->initializing = 0; return fmi2OK;
}
fmi2Status fmi2Reset(fmi2Component c) { reset(c); return fmi2OK; }
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *s = c;
    s->v[VR_DX] = -s->v[VR_X];
    s->v[VR_Y] = s->v[VR_U] + 1.0;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] >= N_VR) return fmi2Error;
        v[i] = s->v[vr[i]];
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != VR_X && vr[i] != VR_U) return fmi2Error;
        if (vr[i] == VR_U && s->initializing) s->v[VR_SETS] += 1.0;
        s->v[vr[i]] = v[i];
    }
    return fmi2OK;
}
fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) { ((Instance *)c)->time = t; return fmi2OK; }
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    if (nx != 1) return fmi2Error;
    ((Instance *)c)->v[VR_X] = x[0];
    return fmi2OK;
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t nx) {
    if (nx != 1) return fmi2Error;
    dx[0] = -((Instance *)c)->v[VR_X];
    return fmi2OK;
}
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    if (nx != 1) return fmi2Error;
    x[0] = ((Instance *)c)->v[VR_X];
    return fmi2OK;
}
