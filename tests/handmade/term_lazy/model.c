/* term_lazy: x' = -x, x(0) = 1, FMI 2 Co-Simulation, each doStep exact, that buffers
   a step until it is told that no earlier state can be set again: a doStep with
   noSetFMUStatePriorToCurrentPoint = false is kept pending (the outputs stay), and
   one with true first commits the pending step that ends where it starts. A master
   that always passes false never sees it advance (an exporter's FMU does this). */
#include <math.h>
#include <stdlib.h>
#include "fmi2Functions.h"
#define HANDMADE_CS
#include "../fmi2_defaults.h"

typedef struct {
    double time, x;
    int pending;           /* a step [pending_from, pending_to] not yet committed */
    double pending_from, pending_to;
} Instance;

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                              fmi2String location, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean logging) {
    (void)name; (void)guid; (void)location; (void)functions; (void)visible; (void)logging;
    if (type != fmi2CoSimulation) return NULL;
    Instance *s = calloc(1, sizeof *s);
    if (s) s->x = 1.0;
    return s;
}
fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDef, fmi2Real tol, fmi2Real t0,
                               fmi2Boolean stopDef, fmi2Real t1) {
    (void)tolDef; (void)tol; (void)stopDef; (void)t1;
    ((Instance *)c)->time = t0; return fmi2OK;
}
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) {
    Instance *s = c; s->time = 0; s->x = 1.0; s->pending = 0; return fmi2OK;
}
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != 1) return fmi2Error;
        v[i] = s->x;
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    (void)c; (void)vr; (void)v; return n ? fmi2Error : fmi2OK;
}

static void commit(Instance *s, double from, double to) {
    s->x *= exp(-(to - from));
    s->time = to;
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetPrior) {
    Instance *s = c;
    if (!noSetPrior) { /* the master may set an earlier state: wait to know the step stands */
        s->pending = 1;
        s->pending_from = t;
        s->pending_to = t + h;
        return fmi2OK;
    }
    if (s->pending && fabs(s->pending_to - t) <= 1e-12 * fmax(1.0, fabs(t)))
        commit(s, s->pending_from, s->pending_to);
    s->pending = 0;
    commit(s, t, t + h);
    return fmi2OK;
}
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind k, fmi2Real *v) {
    Instance *s = c;
    if (k != fmi2LastSuccessfulTime) return fmi2Discard;
    *v = s->time; return fmi2OK;
}
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind k, fmi2Boolean *v) {
    (void)c; (void)k; (void)v; return fmi2Discard;
}
