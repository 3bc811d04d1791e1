/* term_decay: x' = -x + sin(t), x(0) = x0, FMI 2 Co-Simulation, each doStep exact
   (x(t + h) = (x(t) - p(t)) e^-h + p(t + h), p(t) = (sin t - cos t) / 2, on the FMU's
   own clock), that declares canGetAndSetFMUstate and restores its state as the
   parameter `restore` says: 0 exactly, 1 not at all (fmi2SetFMUstate does nothing and
   says OK), 2 in part (x, not the clock): the state restores some exporters ship.
   With t_stop > 0 it ends the run there the FMI 2 way (the step reaching t_stop stops
   at it and answers fmi2Discard; fmi2Terminated is then true). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"
#define HANDMADE_CS
#define OWN_fmi2GetInteger
#define OWN_fmi2SetInteger
#define OWN_fmi2GetFMUstate
#define OWN_fmi2SetFMUstate
#define OWN_fmi2FreeFMUstate
#define OWN_fmi2SerializedFMUstateSize
#define OWN_fmi2SerializeFMUstate
#define OWN_fmi2DeSerializeFMUstate
#include "../fmi2_defaults.h"

typedef struct {
    double time, x;
    int terminated;
} State;

typedef struct {
    State s;
    double x0, t_stop;
    int restore;
    char name[64];
    fmi2CallbackFunctions cb;
} Instance;

static double p(double t) { return 0.5 * (sin(t) - cos(t)); }

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                              fmi2String location, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean logging) {
    (void)guid; (void)location; (void)visible; (void)logging;
    if (type != fmi2CoSimulation) return NULL;
    Instance *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    if (functions) s->cb = *functions;
    snprintf(s->name, sizeof s->name, "%s", name ? name : "term_decay");
    s->x0 = 1.0;
    s->s.x = 1.0;
    return s;
}
fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDef, fmi2Real tol, fmi2Real t0,
                               fmi2Boolean stopDef, fmi2Real t1) {
    (void)tolDef; (void)tol; (void)stopDef; (void)t1;
    ((Instance *)c)->s.time = t0; return fmi2OK;
}
fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    Instance *s = c; s->s.x = s->x0; return fmi2OK;
}
fmi2Status fmi2Reset(fmi2Component c) {
    Instance *s = c;
    memset(&s->s, 0, sizeof s->s);
    s->x0 = s->s.x = 1.0; s->t_stop = 0; s->restore = 0; return fmi2OK;
}
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] == 1) v[i] = s->s.x;
        else if (vr[i] == 2) v[i] = s->x0;
        else if (vr[i] == 4) v[i] = s->t_stop;
        else return fmi2Error;
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] == 2) s->x0 = v[i];
        else if (vr[i] == 4) s->t_stop = v[i];
        else return fmi2Error;
    }
    return fmi2OK;
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != 3) return fmi2Error;
        v[i] = s->restore;
    }
    return fmi2OK;
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != 3 || v[i] < 0 || v[i] > 2) return fmi2Error;
        s->restore = v[i];
    }
    return fmi2OK;
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *st) {
    Instance *s = c;
    State *copy = *st ? (State *)*st : malloc(sizeof *copy);
    if (!copy) return fmi2Error;
    *copy = s->s;
    *st = copy;
    return fmi2OK;
}
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate st) {
    Instance *s = c;
    const State *saved = st;
    if (!saved) return fmi2Error;
    if (s->restore == 0) s->s = *saved;
    else if (s->restore == 2) s->s.x = saved->x; /* the clock (and its end) stay */
    return fmi2OK;
}
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *st) {
    (void)c; free(*st); *st = NULL; return fmi2OK;
}
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate st, size_t *n) {
    (void)c; (void)st; *n = sizeof(State); return fmi2OK;
}
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate st, fmi2Byte b[], size_t n) {
    (void)c;
    if (n != sizeof(State)) return fmi2Error;
    memcpy(b, st, sizeof(State)); return fmi2OK;
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t n, fmi2FMUstate *st) {
    (void)c;
    if (n != sizeof(State)) return fmi2Error;
    State *copy = malloc(sizeof *copy);
    if (!copy) return fmi2Error;
    memcpy(copy, b, sizeof *copy);
    *st = copy;
    return fmi2OK;
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetPrior) {
    Instance *s = c;
    double t0 = s->s.time, t1 = t0 + h; /* its own clock, not the communication point */
    int stop = s->t_stop > 0 && t1 >= s->t_stop - 1e-12;
    (void)t; (void)noSetPrior;
    if (s->s.terminated) return fmi2Error;
    if (stop) t1 = s->t_stop;
    s->s.x = (s->s.x - p(t0)) * exp(-(t1 - t0)) + p(t1);
    s->s.time = t1;
    if (!stop) return fmi2OK;
    s->s.terminated = 1;
    if (s->cb.logger)
        s->cb.logger(s->cb.componentEnvironment, s->name, fmi2Discard, "logStatusDiscard",
                     "the run ends at t_stop");
    return fmi2Discard;
}
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind k, fmi2Real *v) {
    Instance *s = c;
    if (k != fmi2LastSuccessfulTime) return fmi2Discard;
    *v = s->s.time; return fmi2OK;
}
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind k, fmi2Boolean *v) {
    Instance *s = c;
    if (k != fmi2Terminated) return fmi2Discard;
    *v = s->s.terminated; return fmi2OK;
}
