/* lm_gain: a stateless gain, FMI 2 Model Exchange: y = k u. Its only use is to be taken
   by the engine's me as a linear map between events (eng_me_spec.linear_map), where
   the coefficient comes from fmi2GetDirectionalDerivative: dy/du = k with dd_mode 0, an
   Error with dd_mode 1, as an exporter that declares the capability and fails it. */
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"
#define HANDMADE_ME
#define OWN_fmi2GetDirectionalDerivative
#include "../fmi2_defaults.h"

enum { VR_U = 0, VR_Y = 1, VR_K = 2, VR_DD = 3, N_VR = 4 };

typedef struct {
    double v[N_VR];
} Instance;

static void reset(Instance *s)
{
    memset(s, 0, sizeof *s);
    s->v[VR_K] = 2.0;
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
    (void)c; (void)tolDef; (void)tol; (void)t0; (void)stopDef; (void)t1; return fmi2OK;
}
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) { reset(c); return fmi2OK; }
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *s = c;
    s->v[VR_Y] = s->v[VR_K] * s->v[VR_U];
    for (size_t i = 0; i < n; i++) {
        if (vr[i] >= N_VR) return fmi2Error;
        v[i] = s->v[vr[i]];
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] >= N_VR || vr[i] == VR_Y) return fmi2Error;
        s->v[vr[i]] = v[i];
    }
    return fmi2OK;
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference unknown[],
                                        size_t n_unknown, const fmi2ValueReference known[],
                                        size_t n_known, const fmi2Real seed[],
                                        fmi2Real value[]) {
    Instance *s = c;
    if (s->v[VR_DD] != 0.0) return fmi2Error;
    for (size_t i = 0; i < n_unknown; i++) {
        if (unknown[i] != VR_Y) return fmi2Error;
        value[i] = 0.0;
        for (size_t j = 0; j < n_known; j++) {
            if (known[j] != VR_U) return fmi2Error;
            value[i] += s->v[VR_K] * seed[j];
        }
    }
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) { (void)c; (void)t; return fmi2OK; }
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    (void)c; (void)x; return nx ? fmi2Error : fmi2OK;
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t nx) {
    (void)c; (void)dx; return nx ? fmi2Error : fmi2OK;
}
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    (void)c; (void)x; return nx ? fmi2Error : fmi2OK;
}
