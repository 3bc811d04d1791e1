/* ml2_affine: a direct-feedthrough affine block, FMI 2 Model Exchange:
       y = a u + b,   x' = y,   x(0) = 0.
   Two of them fed from each other (u1 = y2, u2 = y1) form a linear algebraic loop with
   the exact solution y1 = (a1 b2 + b1) / (1 - a1 a2), y2 = a2 y1 + b2, and x = y t;
   with a1 a2 = 1 the loop has no unique solution (I - dy/du is singular).
   fmi2GetDirectionalDerivative gives dy/du = a and dx'/du = a, times dd_factor (1; 0
   lies as a broken exporter would, and Newton on the wrong matrix cannot converge where
   the loop's gain exceeds one); ml2_affine_fd offers none, so that the loop's matrix
   comes from differences. */
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"
#define HANDMADE_CS
#define HANDMADE_ME
#define OWN_fmi2GetDirectionalDerivative
#include "../fmi2_defaults.h"

enum { VR_X = 0, VR_DX = 1, VR_U = 2, VR_Y = 3, VR_A = 4, VR_B = 5, VR_DD = 6, N_VR = 7 };

typedef struct {
    double time, v[N_VR];
    fmi2CallbackFunctions cb;
} Instance;

static void outputs(Instance *s)
{
    s->v[VR_Y] = s->v[VR_A] * s->v[VR_U] + s->v[VR_B];
    s->v[VR_DX] = s->v[VR_Y];
}

static void reset(Instance *s)
{
    fmi2CallbackFunctions cb = s->cb;
    memset(s, 0, sizeof *s);
    s->cb = cb;
    s->v[VR_A] = 0.5;
    s->v[VR_B] = 1.0;
    s->v[VR_DD] = 1.0;
    outputs(s);
}

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                              fmi2String location, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean logging) {
    (void)name; (void)guid; (void)location; (void)visible; (void)logging;
    if (type != fmi2ModelExchange) return NULL;
    Instance *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    if (functions) s->cb = *functions;
    reset(s);
    return s;
}
fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDef, fmi2Real tol, fmi2Real t0,
                               fmi2Boolean stopDef, fmi2Real t1) {
    (void)tolDef; (void)tol; (void)stopDef; (void)t1;
    ((Instance *)c)->time = t0; return fmi2OK;
}
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { outputs(c); return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) { reset(c); return fmi2OK; }
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *s = c;
    outputs(s);
    for (size_t i = 0; i < n; i++) {
        if (vr[i] >= N_VR) return fmi2Error;
        v[i] = s->v[vr[i]];
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] >= N_VR || vr[i] == VR_DX || vr[i] == VR_Y) return fmi2Error;
        s->v[vr[i]] = v[i];
    }
    return fmi2OK;
}
/* d(y, x')/d(u, x) times the seed: both unknowns move with u alone, by a */
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference unknown[],
                                        size_t n_unknown, const fmi2ValueReference known[],
                                        size_t n_known, const fmi2Real seed[],
                                        fmi2Real value[]) {
    Instance *s = c;
    for (size_t i = 0; i < n_unknown; i++) {
        if (unknown[i] != VR_Y && unknown[i] != VR_DX) return fmi2Error;
        value[i] = 0.0;
        for (size_t j = 0; j < n_known; j++) {
            if (known[j] != VR_U && known[j] != VR_X) return fmi2Error;
            if (known[j] == VR_U) value[i] += s->v[VR_DD] * s->v[VR_A] * seed[j];
        }
    }
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) { ((Instance *)c)->time = t; return fmi2OK; }
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    Instance *s = c;
    if (nx != 1) return fmi2Error;
    s->v[VR_X] = x[0];
    return fmi2OK;
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t nx) {
    Instance *s = c;
    if (nx != 1) return fmi2Error;
    outputs(s);
    dx[0] = s->v[VR_DX];
    return fmi2OK;
}
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    Instance *s = c;
    if (nx != 1) return fmi2Error;
    x[0] = s->v[VR_X];
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
