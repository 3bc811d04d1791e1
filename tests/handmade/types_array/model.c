/* types_array: FMI 3 Model Exchange and Co-Simulation with array variables only.
     x[3]     continuous state (one array: 3 states), start 1 1 1
     der(x)   = -lam .* x + u          (lam[3]: array parameter, start 1 2 3)
     u[3]     array input, start 0 0 0
     y[3]     array output = x
     m[2,2]   array output = [[x1, x2], [x3, time]] (row-major: m[1,2] = x2)
   Co-Simulation steps exactly for an input held over the step:
     x <- x exp(-lam h) + u (1 - exp(-lam h)) / lam.
   Arrays are got and set whole: a call whose nValues is not the arrays' total size is an
   fmi3Error, as is any type but Float64. Unused FMI functions return fmi3Error. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fmi3FunctionTypes.h"

#define N 3
enum { VR_TIME = 0, VR_LAM = 1, VR_X = 2, VR_DER = 3, VR_U = 4, VR_Y = 5, VR_M = 6 };

typedef struct {
    double time, lam[N], x[N], u[N], m[4];
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log;
} Instance;

static fmi3Status refuse(Instance *s, const char *why, fmi3ValueReference vr) {
    char text[160];
    snprintf(text, sizeof text, "%s (value reference %u)", why, vr);
    if (s->log) s->log(s->env, fmi3Error, "logStatusError", text);
    return fmi3Error;
}

static Instance *instantiate(fmi3InstanceEnvironment env, fmi3LogMessageCallback log) {
    Instance *s = calloc(1, sizeof *s);
    int i;
    if (s == NULL) return NULL;
    for (i = 0; i < N; i++) { s->lam[i] = i + 1; s->x[i] = 1; }
    s->env = env; s->log = log;
    return s;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String name, fmi3String token, fmi3String resources,
    fmi3Boolean visible, fmi3Boolean logging, fmi3InstanceEnvironment env,
    fmi3LogMessageCallback log) {
    (void)name; (void)token; (void)resources; (void)visible; (void)logging;
    return instantiate(env, log);
}
fmi3Instance fmi3InstantiateCoSimulation(fmi3String name, fmi3String token, fmi3String resources,
    fmi3Boolean visible, fmi3Boolean logging, fmi3Boolean event_mode, fmi3Boolean early,
    const fmi3ValueReference required[], size_t n_required, fmi3InstanceEnvironment env,
    fmi3LogMessageCallback log, fmi3IntermediateUpdateCallback update) {
    (void)name; (void)token; (void)resources; (void)visible; (void)logging; (void)event_mode;
    (void)early; (void)required; (void)n_required; (void)update;
    return instantiate(env, log);
}
void fmi3FreeInstance(fmi3Instance c) { free(c); }
const char *fmi3GetVersion(void) { return "3.0"; }
fmi3Status fmi3SetDebugLogging(fmi3Instance c, fmi3Boolean on, size_t n, const fmi3String cat[]) {
    (void)c; (void)on; (void)n; (void)cat; return fmi3OK;
}
fmi3Status fmi3EnterInitializationMode(fmi3Instance c, fmi3Boolean tol_defined, fmi3Float64 tol,
                                       fmi3Float64 t0, fmi3Boolean stop_defined, fmi3Float64 t1) {
    (void)tol_defined; (void)tol; (void)stop_defined; (void)t1;
    ((Instance *)c)->time = t0; return fmi3OK;
}
fmi3Status fmi3ExitInitializationMode(fmi3Instance c) { (void)c; return fmi3OK; }
fmi3Status fmi3EnterEventMode(fmi3Instance c) { (void)c; return fmi3OK; }
fmi3Status fmi3EnterStepMode(fmi3Instance c) { (void)c; return fmi3OK; }
fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance c) { (void)c; return fmi3OK; }
fmi3Status fmi3Terminate(fmi3Instance c) { (void)c; return fmi3OK; }
fmi3Status fmi3Reset(fmi3Instance c) { (void)c; return fmi3Error; }
fmi3Status fmi3UpdateDiscreteStates(fmi3Instance c, fmi3Boolean *more, fmi3Boolean *terminate,
                                    fmi3Boolean *nominals, fmi3Boolean *values,
                                    fmi3Boolean *next_defined, fmi3Float64 *next) {
    (void)c;
    *more = *terminate = *nominals = *values = *next_defined = false; *next = 0;
    return fmi3OK;
}
fmi3Status fmi3CompletedIntegratorStep(fmi3Instance c, fmi3Boolean no_set_prior,
                                       fmi3Boolean *enter_event, fmi3Boolean *terminate) {
    (void)c; (void)no_set_prior; *enter_event = *terminate = false; return fmi3OK;
}
fmi3Status fmi3SetTime(fmi3Instance c, fmi3Float64 t) { ((Instance *)c)->time = t; return fmi3OK; }
fmi3Status fmi3SetContinuousStates(fmi3Instance c, const fmi3Float64 x[], size_t n) {
    Instance *s = c;
    if (n != N) return refuse(s, "fmi3SetContinuousStates: 3 states expected", 0);
    memcpy(s->x, x, sizeof s->x); return fmi3OK;
}
fmi3Status fmi3GetContinuousStates(fmi3Instance c, fmi3Float64 x[], size_t n) {
    Instance *s = c;
    if (n != N) return refuse(s, "fmi3GetContinuousStates: 3 states expected", 0);
    memcpy(x, s->x, sizeof s->x); return fmi3OK;
}
static void derivatives(const Instance *s, double *dx) {
    int i;
    for (i = 0; i < N; i++) dx[i] = -s->lam[i] * s->x[i] + s->u[i];
}
fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance c, fmi3Float64 dx[], size_t n) {
    Instance *s = c;
    if (n != N) return refuse(s, "fmi3GetContinuousStateDerivatives: 3 states expected", 0);
    derivatives(s, dx); return fmi3OK;
}
fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance c, fmi3Float64 v[], size_t n) {
    size_t i; (void)c;
    for (i = 0; i < n; i++) v[i] = 1; return fmi3OK;
}
fmi3Status fmi3GetEventIndicators(fmi3Instance c, fmi3Float64 z[], size_t n) {
    (void)c; (void)z; return n ? fmi3Error : fmi3OK;
}
fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance c, size_t *n) { (void)c; *n = 0; return fmi3OK; }
fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance c, size_t *n) { (void)c; *n = N; return fmi3OK; }

fmi3Status fmi3DoStep(fmi3Instance c, fmi3Float64 t, fmi3Float64 h, fmi3Boolean no_set_prior,
                      fmi3Boolean *event_needed, fmi3Boolean *terminate, fmi3Boolean *early,
                      fmi3Float64 *last) {
    Instance *s = c;
    int i;
    (void)no_set_prior;
    for (i = 0; i < N; i++) {
        double decay = exp(-s->lam[i] * h);
        s->x[i] = s->x[i] * decay + s->u[i] * (1 - decay) / s->lam[i];
    }
    s->time = t + h;
    *event_needed = *terminate = *early = false; *last = s->time;
    return fmi3OK;
}

/* Where each variable's values live, and how many: arrays are got and set whole. */
static double *values_of(Instance *s, fmi3ValueReference vr, size_t *n) {
    switch (vr) {
    case VR_TIME: *n = 1; return &s->time;
    case VR_LAM: *n = N; return s->lam;
    case VR_X: case VR_Y: *n = N; return s->x;
    case VR_U: *n = N; return s->u;
    case VR_M: /* row-major [[x1, x2], [x3, time]] */
        s->m[0] = s->x[0]; s->m[1] = s->x[1]; s->m[2] = s->x[2]; s->m[3] = s->time;
        *n = 4; return s->m;
    default: return NULL;
    }
}

fmi3Status fmi3GetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t n_vr,
                          fmi3Float64 v[], size_t n_values) {
    Instance *s = c;
    size_t i, used = 0, n = 0;
    double der[N];
    for (i = 0; i < n_vr; i++) {
        const double *from = values_of(s, vr[i], &n);
        if (vr[i] == VR_DER) { derivatives(s, der); from = der; n = N; }
        if (from == NULL) return refuse(s, "fmi3GetFloat64: no Float64 variable", vr[i]);
        if (used + n > n_values) return refuse(s, "fmi3GetFloat64: nValues too small", vr[i]);
        memcpy(v + used, from, n * sizeof(double));
        used += n;
    }
    return used == n_values ? fmi3OK : refuse(s, "fmi3GetFloat64: nValues too large", 0);
}

fmi3Status fmi3SetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t n_vr,
                          const fmi3Float64 v[], size_t n_values) {
    Instance *s = c;
    size_t i, used = 0, n = 0;
    for (i = 0; i < n_vr; i++) {
        double *to = vr[i] == VR_LAM || vr[i] == VR_U || vr[i] == VR_X ? values_of(s, vr[i], &n) : NULL;
        if (to == NULL) return refuse(s, "fmi3SetFloat64: not settable", vr[i]);
        if (used + n > n_values) return refuse(s, "fmi3SetFloat64: nValues too small", vr[i]);
        memcpy(to, v + used, n * sizeof(double));
        used += n;
    }
    return used == n_values ? fmi3OK : refuse(s, "fmi3SetFloat64: nValues too large", 0);
}

/* never called by an importer of this FMU (Float64 only, no FMU state, no clocks) */
#define STUB(name) fmi3Status name(void) { return fmi3Error; }
STUB(fmi3InstantiateScheduledExecution) STUB(fmi3GetFloat32) STUB(fmi3GetInt8) STUB(fmi3GetUInt8)
STUB(fmi3GetInt16) STUB(fmi3GetUInt16) STUB(fmi3GetInt32) STUB(fmi3GetUInt32) STUB(fmi3GetInt64)
STUB(fmi3GetUInt64) STUB(fmi3GetBoolean) STUB(fmi3GetString) STUB(fmi3GetBinary)
STUB(fmi3GetClock) STUB(fmi3SetFloat32) STUB(fmi3SetInt8) STUB(fmi3SetUInt8) STUB(fmi3SetInt16)
STUB(fmi3SetUInt16) STUB(fmi3SetInt32) STUB(fmi3SetUInt32) STUB(fmi3SetInt64) STUB(fmi3SetUInt64)
STUB(fmi3SetBoolean) STUB(fmi3SetString) STUB(fmi3SetBinary) STUB(fmi3SetClock)
STUB(fmi3GetNumberOfVariableDependencies) STUB(fmi3GetVariableDependencies)
STUB(fmi3GetFMUState) STUB(fmi3SetFMUState) STUB(fmi3FreeFMUState)
STUB(fmi3SerializedFMUStateSize) STUB(fmi3SerializeFMUState) STUB(fmi3DeserializeFMUState)
STUB(fmi3GetDirectionalDerivative) STUB(fmi3GetAdjointDerivative)
STUB(fmi3EnterConfigurationMode) STUB(fmi3ExitConfigurationMode)
STUB(fmi3GetIntervalDecimal) STUB(fmi3GetIntervalFraction) STUB(fmi3GetShiftDecimal)
STUB(fmi3GetShiftFraction) STUB(fmi3SetIntervalDecimal) STUB(fmi3SetIntervalFraction)
STUB(fmi3SetShiftDecimal) STUB(fmi3SetShiftFraction) STUB(fmi3EvaluateDiscreteStates)
STUB(fmi3GetOutputDerivatives) STUB(fmi3ActivateModelPartition)
