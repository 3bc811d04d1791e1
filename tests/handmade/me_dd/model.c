/* me_dd: a stiff linear pair, FMI 2 Model Exchange, whose directional derivatives are
   broken as one exporter's are:
       x1' = -a x1,  x2' = b (x1 - x2),  x(0) = (1, 0),
   x1 = exp(-a t), x2 = b / (b - a) (exp(-a t) - exp(-b t)); a = 1, b = 1000.
   dd_mode = 0: fmi2GetDirectionalDerivative is right; 1: d x2'/d x2 comes back as +b
   instead of -b (wrong values, status OK); 2: the call returns fmi2Error. */
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"
#define HANDMADE_CS
#define HANDMADE_ME
#define OWN_fmi2GetDirectionalDerivative
#include "../fmi2_defaults.h"

#define NX 2
enum { VR_X = 0, VR_DX = 2, VR_A = 4, VR_B = 5, VR_MODE = 6, N_VR = 7 };

typedef struct {
    double time, v[N_VR];
    fmi2CallbackFunctions cb;
} Instance;

static void derivatives(Instance *s)
{
    const double *x = s->v + VR_X;
    s->v[VR_DX] = -s->v[VR_A] * x[0];
    s->v[VR_DX + 1] = s->v[VR_B] * (x[0] - x[1]);
}

static void reset(Instance *s)
{
    fmi2CallbackFunctions cb = s->cb;
    memset(s, 0, sizeof *s);
    s->cb = cb;
    s->v[VR_X] = 1.0;
    s->v[VR_A] = 1.0;
    s->v[VR_B] = 1000.0;
    derivatives(s);
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
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { derivatives(c); return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) { reset(c); return fmi2OK; }
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *s = c;
    derivatives(s);
    for (size_t i = 0; i < n; i++) {
        if (vr[i] >= N_VR) return fmi2Error;
        v[i] = s->v[vr[i]];
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] >= N_VR || (vr[i] >= VR_DX && vr[i] < VR_A)) return fmi2Error;
        s->v[vr[i]] = v[i];
    }
    return fmi2OK;
}
/* d(dx)/dx times the seed: the unknowns are derivatives, the knowns states */
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference k[], size_t nk,
                                        const fmi2Real dk[], fmi2Real du[]) {
    Instance *s = c;
    const double a = s->v[VR_A], b = s->v[VR_B];
    const double J[NX][NX] = {{-a, 0.0}, {b, s->v[VR_MODE] == 1.0 ? b : -b}};
    if (s->v[VR_MODE] == 2.0) {
        if (s->cb.logger)
            s->cb.logger(s->cb.componentEnvironment, "me_dd", fmi2Error, "logStatusError",
                         "directional derivatives are not available in this mode");
        return fmi2Error;
    }
    for (size_t i = 0; i < nu; i++) {
        if (u[i] < VR_DX || u[i] >= VR_DX + NX) return fmi2Error;
        du[i] = 0;
        for (size_t j = 0; j < nk; j++) {
            if (k[j] >= VR_X + NX) return fmi2Error;
            du[i] += J[u[i] - VR_DX][k[j]] * dk[j];
        }
    }
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) { ((Instance *)c)->time = t; return fmi2OK; }
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    Instance *s = c;
    if (nx != NX) return fmi2Error;
    memcpy(s->v + VR_X, x, sizeof(double) * NX);
    return fmi2OK;
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t nx) {
    Instance *s = c;
    if (nx != NX) return fmi2Error;
    derivatives(s);
    memcpy(dx, s->v + VR_DX, sizeof(double) * NX);
    return fmi2OK;
}
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    Instance *s = c;
    if (nx != NX) return fmi2Error;
    memcpy(x, s->v + VR_X, sizeof(double) * NX);
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
