/* term_stair3: a counter of whole seconds, FMI 3 Co-Simulation, that ends its run the
   FMI 3 way: the doStep reaching t = 5 s sets terminateSimulation with
   lastSuccessfulTime = 5 and returns fmi3OK, or fmi3Discard where the parameter
   `discard` is 1 (the standard allows either; fmpy reads only the first). It declares
   canGetAndSetFMUState; fmi3SetFMUState restores exactly, or (parameter `restore` = 1)
   does nothing and says OK. */
#include <stdlib.h>
#include <string.h>
#include "fmi3Functions.h"

#define T_END 5.0

typedef struct {
    double time;
    int counter;
    int terminated;
} State;

typedef struct {
    State s;
    int discard, restore;
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log;
} Instance;

static fmi3Instance instantiate(fmi3InstanceEnvironment env, fmi3LogMessageCallback log) {
    Instance *s = calloc(1, sizeof *s);
    if (s) { s->env = env; s->log = log; }
    return s;
}

const char *fmi3GetVersion(void) { return fmi3Version; }
fmi3Status fmi3SetDebugLogging(fmi3Instance i, fmi3Boolean on, size_t n, const fmi3String c[]) {
    (void)i; (void)on; (void)n; (void)c; return fmi3OK;
}
fmi3Instance fmi3InstantiateModelExchange(fmi3String n, fmi3String t, fmi3String r, fmi3Boolean v,
                                          fmi3Boolean l, fmi3InstanceEnvironment e,
                                          fmi3LogMessageCallback m) {
    (void)n; (void)t; (void)r; (void)v; (void)l; (void)e; (void)m; return NULL;
}
fmi3Instance fmi3InstantiateCoSimulation(fmi3String n, fmi3String t, fmi3String r, fmi3Boolean v,
                                         fmi3Boolean l, fmi3Boolean em, fmi3Boolean er,
                                         const fmi3ValueReference req[], size_t nreq,
                                         fmi3InstanceEnvironment e, fmi3LogMessageCallback m,
                                         fmi3IntermediateUpdateCallback u) {
    (void)n; (void)t; (void)r; (void)v; (void)l; (void)em; (void)er; (void)req; (void)nreq; (void)u;
    return instantiate(e, m);
}
fmi3Instance fmi3InstantiateScheduledExecution(fmi3String n, fmi3String t, fmi3String r,
                                               fmi3Boolean v, fmi3Boolean l,
                                               fmi3InstanceEnvironment e, fmi3LogMessageCallback m,
                                               fmi3ClockUpdateCallback c,
                                               fmi3LockPreemptionCallback lp,
                                               fmi3UnlockPreemptionCallback up) {
    (void)n; (void)t; (void)r; (void)v; (void)l; (void)e; (void)m; (void)c; (void)lp; (void)up;
    return NULL;
}
void fmi3FreeInstance(fmi3Instance i) { free(i); }
fmi3Status fmi3EnterInitializationMode(fmi3Instance i, fmi3Boolean td, fmi3Float64 tol,
                                       fmi3Float64 t0, fmi3Boolean sd, fmi3Float64 t1) {
    (void)td; (void)tol; (void)sd; (void)t1; ((Instance *)i)->s.time = t0; return fmi3OK;
}
fmi3Status fmi3ExitInitializationMode(fmi3Instance i) { (void)i; return fmi3OK; }
fmi3Status fmi3EnterEventMode(fmi3Instance i) { (void)i; return fmi3Error; }
fmi3Status fmi3Terminate(fmi3Instance i) { (void)i; return fmi3OK; }
fmi3Status fmi3Reset(fmi3Instance i) {
    Instance *s = i;
    memset(&s->s, 0, sizeof s->s);
    s->discard = s->restore = 0;
    return fmi3OK;
}

fmi3Status fmi3GetFloat64(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr,
                          fmi3Float64 v[], size_t nv) {
    Instance *s = i;
    if (nv != nvr) return fmi3Error;
    for (size_t k = 0; k < nvr; k++) {
        if (vr[k] != 0 && vr[k] != 2) return fmi3Error;
        v[k] = s->s.time;
    }
    return fmi3OK;
}
fmi3Status fmi3GetInt32(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr,
                        fmi3Int32 v[], size_t nv) {
    Instance *s = i;
    if (nv != nvr) return fmi3Error;
    for (size_t k = 0; k < nvr; k++) {
        if (vr[k] == 1) v[k] = s->s.counter;
        else if (vr[k] == 3) v[k] = s->discard;
        else if (vr[k] == 4) v[k] = s->restore;
        else return fmi3Error;
    }
    return fmi3OK;
}
fmi3Status fmi3SetInt32(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr,
                        const fmi3Int32 v[], size_t nv) {
    Instance *s = i;
    if (nv != nvr) return fmi3Error;
    for (size_t k = 0; k < nvr; k++) {
        if (vr[k] == 3) s->discard = v[k] != 0;
        else if (vr[k] == 4) s->restore = v[k] != 0;
        else return fmi3Error;
    }
    return fmi3OK;
}
fmi3Status fmi3SetFloat64(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr,
                          const fmi3Float64 v[], size_t nv) {
    (void)i; (void)vr; (void)v; (void)nv; return nvr ? fmi3Error : fmi3OK;
}

/* no other variable types: any value asked for is an error */
#define NO_VARIABLES(T, Name)                                                                  \
    fmi3Status fmi3Get##Name(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, T v[], \
                             size_t nv) {                                                      \
        (void)i; (void)vr; (void)v; (void)nv; return nvr ? fmi3Error : fmi3OK;                 \
    }                                                                                          \
    fmi3Status fmi3Set##Name(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr,        \
                             const T v[], size_t nv) {                                         \
        (void)i; (void)vr; (void)v; (void)nv; return nvr ? fmi3Error : fmi3OK;                 \
    }
NO_VARIABLES(fmi3Float32, Float32)
NO_VARIABLES(fmi3Int8, Int8)
NO_VARIABLES(fmi3UInt8, UInt8)
NO_VARIABLES(fmi3Int16, Int16)
NO_VARIABLES(fmi3UInt16, UInt16)
NO_VARIABLES(fmi3UInt32, UInt32)
NO_VARIABLES(fmi3Int64, Int64)
NO_VARIABLES(fmi3UInt64, UInt64)
NO_VARIABLES(fmi3Boolean, Boolean)
NO_VARIABLES(fmi3String, String)

fmi3Status fmi3GetBinary(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr,
                         size_t sizes[], fmi3Binary v[], size_t nv) {
    (void)i; (void)vr; (void)sizes; (void)v; (void)nv; return nvr ? fmi3Error : fmi3OK;
}
fmi3Status fmi3SetBinary(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr,
                         const size_t sizes[], const fmi3Binary v[], size_t nv) {
    (void)i; (void)vr; (void)sizes; (void)v; (void)nv; return nvr ? fmi3Error : fmi3OK;
}
fmi3Status fmi3GetClock(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Clock v[]) {
    (void)i; (void)vr; (void)v; return nvr ? fmi3Error : fmi3OK;
}
fmi3Status fmi3SetClock(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr,
                        const fmi3Clock v[]) {
    (void)i; (void)vr; (void)v; return nvr ? fmi3Error : fmi3OK;
}
fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance i, fmi3ValueReference vr, size_t *n) {
    (void)i; (void)vr; (void)n; return fmi3Error;
}
fmi3Status fmi3GetVariableDependencies(fmi3Instance i, fmi3ValueReference d, size_t ed[],
                                       fmi3ValueReference ind[], size_t ei[],
                                       fmi3DependencyKind k[], size_t n) {
    (void)i; (void)d; (void)ed; (void)ind; (void)ei; (void)k; (void)n; return fmi3Error;
}
fmi3Status fmi3GetFMUState(fmi3Instance i, fmi3FMUState *st) {
    Instance *s = i;
    State *copy = *st ? (State *)*st : malloc(sizeof *copy);
    if (!copy) return fmi3Error;
    *copy = s->s;
    *st = copy;
    return fmi3OK;
}
fmi3Status fmi3SetFMUState(fmi3Instance i, fmi3FMUState st) {
    Instance *s = i;
    if (!st) return fmi3Error;
    if (!s->restore) s->s = *(const State *)st;
    return fmi3OK;
}
fmi3Status fmi3FreeFMUState(fmi3Instance i, fmi3FMUState *st) {
    (void)i; free(*st); *st = NULL; return fmi3OK;
}
fmi3Status fmi3SerializedFMUStateSize(fmi3Instance i, fmi3FMUState st, size_t *n) {
    (void)i; (void)st; (void)n; return fmi3Error;
}
fmi3Status fmi3SerializeFMUState(fmi3Instance i, fmi3FMUState st, fmi3Byte b[], size_t n) {
    (void)i; (void)st; (void)b; (void)n; return fmi3Error;
}
fmi3Status fmi3DeserializeFMUState(fmi3Instance i, const fmi3Byte b[], size_t n, fmi3FMUState *st) {
    (void)i; (void)b; (void)n; (void)st; return fmi3Error;
}
fmi3Status fmi3GetDirectionalDerivative(fmi3Instance i, const fmi3ValueReference u[], size_t nu,
                                        const fmi3ValueReference k[], size_t nk,
                                        const fmi3Float64 s[], size_t ns, fmi3Float64 d[],
                                        size_t nd) {
    (void)i; (void)u; (void)nu; (void)k; (void)nk; (void)s; (void)ns; (void)d; (void)nd;
    return fmi3Error;
}
fmi3Status fmi3GetAdjointDerivative(fmi3Instance i, const fmi3ValueReference u[], size_t nu,
                                    const fmi3ValueReference k[], size_t nk,
                                    const fmi3Float64 s[], size_t ns, fmi3Float64 d[],
                                    size_t nd) {
    (void)i; (void)u; (void)nu; (void)k; (void)nk; (void)s; (void)ns; (void)d; (void)nd;
    return fmi3Error;
}
fmi3Status fmi3EnterConfigurationMode(fmi3Instance i) { (void)i; return fmi3Error; }
fmi3Status fmi3ExitConfigurationMode(fmi3Instance i) { (void)i; return fmi3Error; }
fmi3Status fmi3GetIntervalDecimal(fmi3Instance i, const fmi3ValueReference vr[], size_t n,
                                  fmi3Float64 iv[], fmi3IntervalQualifier q[]) {
    (void)i; (void)vr; (void)n; (void)iv; (void)q; return fmi3Error;
}
fmi3Status fmi3GetIntervalFraction(fmi3Instance i, const fmi3ValueReference vr[], size_t n,
                                   fmi3UInt64 c[], fmi3UInt64 r[], fmi3IntervalQualifier q[]) {
    (void)i; (void)vr; (void)n; (void)c; (void)r; (void)q; return fmi3Error;
}
fmi3Status fmi3GetShiftDecimal(fmi3Instance i, const fmi3ValueReference vr[], size_t n,
                               fmi3Float64 s[]) {
    (void)i; (void)vr; (void)n; (void)s; return fmi3Error;
}
fmi3Status fmi3GetShiftFraction(fmi3Instance i, const fmi3ValueReference vr[], size_t n,
                                fmi3UInt64 c[], fmi3UInt64 r[]) {
    (void)i; (void)vr; (void)n; (void)c; (void)r; return fmi3Error;
}
fmi3Status fmi3SetIntervalDecimal(fmi3Instance i, const fmi3ValueReference vr[], size_t n,
                                  const fmi3Float64 iv[]) {
    (void)i; (void)vr; (void)n; (void)iv; return fmi3Error;
}
fmi3Status fmi3SetIntervalFraction(fmi3Instance i, const fmi3ValueReference vr[], size_t n,
                                   const fmi3UInt64 c[], const fmi3UInt64 r[]) {
    (void)i; (void)vr; (void)n; (void)c; (void)r; return fmi3Error;
}
fmi3Status fmi3SetShiftDecimal(fmi3Instance i, const fmi3ValueReference vr[], size_t n,
                               const fmi3Float64 s[]) {
    (void)i; (void)vr; (void)n; (void)s; return fmi3Error;
}
fmi3Status fmi3SetShiftFraction(fmi3Instance i, const fmi3ValueReference vr[], size_t n,
                                const fmi3UInt64 c[], const fmi3UInt64 r[]) {
    (void)i; (void)vr; (void)n; (void)c; (void)r; return fmi3Error;
}
fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance i) { (void)i; return fmi3Error; }
fmi3Status fmi3UpdateDiscreteStates(fmi3Instance i, fmi3Boolean *a, fmi3Boolean *b,
                                    fmi3Boolean *c, fmi3Boolean *d, fmi3Boolean *e,
                                    fmi3Float64 *f) {
    (void)i; (void)a; (void)b; (void)c; (void)d; (void)e; (void)f; return fmi3Error;
}
fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance i) { (void)i; return fmi3Error; }
fmi3Status fmi3CompletedIntegratorStep(fmi3Instance i, fmi3Boolean n, fmi3Boolean *e,
                                       fmi3Boolean *t) {
    (void)i; (void)n; (void)e; (void)t; return fmi3Error;
}
fmi3Status fmi3SetTime(fmi3Instance i, fmi3Float64 t) { (void)i; (void)t; return fmi3Error; }
fmi3Status fmi3SetContinuousStates(fmi3Instance i, const fmi3Float64 x[], size_t n) {
    (void)i; (void)x; (void)n; return fmi3Error;
}
fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance i, fmi3Float64 d[], size_t n) {
    (void)i; (void)d; (void)n; return fmi3Error;
}
fmi3Status fmi3GetEventIndicators(fmi3Instance i, fmi3Float64 z[], size_t n) {
    (void)i; (void)z; (void)n; return fmi3Error;
}
fmi3Status fmi3GetContinuousStates(fmi3Instance i, fmi3Float64 x[], size_t n) {
    (void)i; (void)x; (void)n; return fmi3Error;
}
fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance i, fmi3Float64 x[], size_t n) {
    (void)i; (void)x; (void)n; return fmi3Error;
}
fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance i, size_t *n) { (void)i; *n = 0; return fmi3OK; }
fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance i, size_t *n) { (void)i; *n = 0; return fmi3OK; }
fmi3Status fmi3EnterStepMode(fmi3Instance i) { (void)i; return fmi3OK; }
fmi3Status fmi3GetOutputDerivatives(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr,
                                    const fmi3Int32 o[], fmi3Float64 v[], size_t nv) {
    (void)i; (void)vr; (void)nvr; (void)o; (void)v; (void)nv; return fmi3Error;
}
fmi3Status fmi3ActivateModelPartition(fmi3Instance i, fmi3ValueReference c, fmi3Float64 t) {
    (void)i; (void)c; (void)t; return fmi3Error;
}

fmi3Status fmi3DoStep(fmi3Instance i, fmi3Float64 t, fmi3Float64 h, fmi3Boolean noSetPrior,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                      fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime) {
    Instance *s = i;
    double target = t + h;
    (void)noSetPrior;
    *eventHandlingNeeded = fmi3False;
    *earlyReturn = fmi3False;
    *terminateSimulation = fmi3False;
    if (s->s.terminated) return fmi3Error;
    if (target >= T_END - 1e-12) {
        s->s.time = T_END;
        s->s.counter = (int)T_END;
        s->s.terminated = 1;
        *terminateSimulation = fmi3True;
        *lastSuccessfulTime = T_END;
        if (s->log)
            s->log(s->env, s->discard ? fmi3Discard : fmi3OK, "logStatusDiscard",
                   "the staircase ends at t = 5 s");
        return s->discard ? fmi3Discard : fmi3OK;
    }
    s->s.time = target;
    s->s.counter = (int)(target + 1e-9);
    *lastSuccessfulTime = target;
    return fmi3OK;
}
