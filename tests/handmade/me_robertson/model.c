/* me_robertson: Robertson's chemical kinetics, the classic stiff test problem, as an
   FMI 2 Model Exchange FMU with directional derivatives:
       y1' = -k1 y1 + k3 y2 y3,  y2' = k1 y1 - k3 y2 y3 - k2 y2^2,  y3' = k2 y2^2,
   k1 = 0.04, k2 = 3e7, k3 = 1e4, y(0) = (1, 0, 0). Its eigenvalues reach about -1e4
   within milliseconds while the solution creeps over thousands of seconds. */
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"
#define HANDMADE_CS
#define HANDMADE_ME
#define OWN_fmi2GetDirectionalDerivative
#include "../fmi2_defaults.h"

#define NX 3
enum { VR_Y = 0, VR_DY = 3, VR_K1 = 6, VR_K2 = 7, VR_K3 = 8, N_VR = 9 };

typedef struct {
    double time, v[N_VR]; /* y, dy (computed), k1, k2, k3 */
} Instance;

static void derivatives(Instance *s)
{
    const double *y = s->v + VR_Y, k1 = s->v[VR_K1], k2 = s->v[VR_K2], k3 = s->v[VR_K3];
    s->v[VR_DY + 0] = -k1 * y[0] + k3 * y[1] * y[2];
    s->v[VR_DY + 1] = k1 * y[0] - k3 * y[1] * y[2] - k2 * y[1] * y[1];
    s->v[VR_DY + 2] = k2 * y[1] * y[1];
}

static void reset(Instance *s)
{
    memset(s, 0, sizeof *s);
    s->v[VR_Y] = 1.0;
    s->v[VR_K1] = 0.04; s->v[VR_K2] = 3e7; s->v[VR_K3] = 1e4;
    derivatives(s);
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
        if (vr[i] >= N_VR || (vr[i] >= VR_DY && vr[i] < VR_K1)) return fmi2Error;
        s->v[vr[i]] = v[i];
    }
    return fmi2OK;
}
/* d(dy)/dy times the seed: the unknowns are derivatives, the knowns states */
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference k[], size_t nk,
                                        const fmi2Real dk[], fmi2Real du[]) {
    Instance *s = c;
    const double *y = s->v + VR_Y, k1 = s->v[VR_K1], k2 = s->v[VR_K2], k3 = s->v[VR_K3];
    double J[NX][NX] = {
        {-k1, k3 * y[2], k3 * y[1]},
        {k1, -k3 * y[2] - 2 * k2 * y[1], -k3 * y[1]},
        {0, 2 * k2 * y[1], 0}};
    for (size_t i = 0; i < nu; i++) {
        if (u[i] < VR_DY || u[i] >= VR_DY + NX) return fmi2Error;
        du[i] = 0;
        for (size_t j = 0; j < nk; j++) {
            if (k[j] >= VR_Y + NX) return fmi2Error;
            du[i] += J[u[i] - VR_DY][k[j]] * dk[j];
        }
    }
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) { ((Instance *)c)->time = t; return fmi2OK; }
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    Instance *s = c;
    if (nx != NX) return fmi2Error;
    memcpy(s->v + VR_Y, x, sizeof(double) * NX);
    return fmi2OK;
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t nx) {
    Instance *s = c;
    if (nx != NX) return fmi2Error;
    derivatives(s);
    memcpy(dx, s->v + VR_DY, sizeof(double) * NX);
    return fmi2OK;
}
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    Instance *s = c;
    if (nx != NX) return fmi2Error;
    memcpy(x, s->v + VR_Y, sizeof(double) * NX);
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
