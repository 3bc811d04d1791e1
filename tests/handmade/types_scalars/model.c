/* types_scalars: FMI 3 Co-Simulation and Model Exchange (no continuous states) with a
   variable of every type the engine carries,
   each got and set only through its own FMI call (a call of another type, or a value
   reference of another type, is an fmi3Error with a message naming it).

   With n = floor(t) (a discrete state: Co-Simulation updates it at the end of each step,
   Model Exchange at the time event it announces for every whole second), the outputs are
     n8 (Int8) = k * n, on (Boolean) = flag XOR (n odd), tag (String) = label "-" n,
     y32 (Float32) = gain * t, big (UInt64) = base + n, m (Enumeration) = mode,
     i16 (Int16) = offset16 + n, u8 (UInt8) = 20 * n, u16 (UInt16) = 1000 * n,
     i64 (Int64) = n - 2^53,
   and each *_echo output is the value of its input (direct feedthrough). A local Binary
   `blob` is there to show that a variable the user never reaches does not refuse the FMU.
   Unused FMI functions exist (importers look every one up) and return fmi3Error. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fmi3FunctionTypes.h"

#define TEXT 256

typedef struct {
    double time;
    /* parameters */
    fmi3Int8 k; fmi3Boolean flag; char label[TEXT]; fmi3Float32 gain; fmi3UInt64 base;
    fmi3Int64 mode; fmi3Int16 offset16;
    /* inputs */
    fmi3Int8 n8_in; fmi3Boolean on_in; char tag_in[TEXT]; fmi3Float32 y32_in;
    fmi3UInt64 big_in; fmi3Int64 m_in; fmi3Int32 i32_in; fmi3Float64 x_in;
    fmi3UInt32 u32_in; fmi3Int64 i64_in;
    long n;         /* whole seconds: the discrete state */
    char tag[TEXT]; /* the String output's storage: valid until the next call */
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log;
} Instance;

static fmi3Status refuse(Instance *s, const char *fn, fmi3ValueReference vr) {
    char text[128];
    snprintf(text, sizeof text, "%s: value reference %u is not a variable of this type", fn, vr);
    if (s->log) s->log(s->env, fmi3Error, "logStatusError", text);
    return fmi3Error;
}

static long whole_seconds(const Instance *s) { return s->n; }

static Instance *instantiate(fmi3InstanceEnvironment env, fmi3LogMessageCallback log) {
    Instance *s = calloc(1, sizeof *s);
    if (s == NULL) return NULL;
    s->k = 3; s->flag = false; strcpy(s->label, "tick"); s->gain = 0.5f;
    s->base = 4503599627370496ULL; s->mode = 2; s->offset16 = -300;
    s->m_in = 1;
    s->env = env; s->log = log;
    return s;
}
fmi3Instance fmi3InstantiateCoSimulation(fmi3String name, fmi3String token, fmi3String resources,
    fmi3Boolean visible, fmi3Boolean logging, fmi3Boolean event_mode, fmi3Boolean early,
    const fmi3ValueReference required[], size_t n_required, fmi3InstanceEnvironment env,
    fmi3LogMessageCallback log, fmi3IntermediateUpdateCallback update) {
    (void)name; (void)token; (void)resources; (void)visible; (void)logging; (void)event_mode;
    (void)early; (void)required; (void)n_required; (void)update;
    return instantiate(env, log);
}
fmi3Instance fmi3InstantiateModelExchange(fmi3String name, fmi3String token, fmi3String resources,
    fmi3Boolean visible, fmi3Boolean logging, fmi3InstanceEnvironment env,
    fmi3LogMessageCallback log) {
    (void)name; (void)token; (void)resources; (void)visible; (void)logging;
    return instantiate(env, log);
}
static void update_n(Instance *s) { s->n = (long)floor(s->time + 1e-9); }

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
fmi3Status fmi3ExitInitializationMode(fmi3Instance c) { update_n(c); return fmi3OK; }
fmi3Status fmi3EnterEventMode(fmi3Instance c) { (void)c; return fmi3OK; }
fmi3Status fmi3UpdateDiscreteStates(fmi3Instance c, fmi3Boolean *more, fmi3Boolean *terminate,
                                    fmi3Boolean *nominals, fmi3Boolean *values,
                                    fmi3Boolean *next_defined, fmi3Float64 *next) {
    Instance *s = c;
    update_n(s);
    *more = *terminate = *nominals = *values = false;
    *next_defined = true;
    *next = (double)(s->n + 1);
    return fmi3OK;
}
fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance c) { (void)c; return fmi3OK; }
fmi3Status fmi3CompletedIntegratorStep(fmi3Instance c, fmi3Boolean no_set_prior,
                                       fmi3Boolean *enter_event, fmi3Boolean *terminate) {
    (void)c; (void)no_set_prior; *enter_event = *terminate = false; return fmi3OK;
}
fmi3Status fmi3SetTime(fmi3Instance c, fmi3Float64 t) { ((Instance *)c)->time = t; return fmi3OK; }
fmi3Status fmi3SetContinuousStates(fmi3Instance c, const fmi3Float64 x[], size_t n) {
    (void)c; (void)x; return n ? fmi3Error : fmi3OK;
}
fmi3Status fmi3GetContinuousStates(fmi3Instance c, fmi3Float64 x[], size_t n) {
    (void)c; (void)x; return n ? fmi3Error : fmi3OK;
}
fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance c, fmi3Float64 dx[], size_t n) {
    (void)c; (void)dx; return n ? fmi3Error : fmi3OK;
}
fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance c, fmi3Float64 v[], size_t n) {
    (void)c; (void)v; return n ? fmi3Error : fmi3OK;
}
fmi3Status fmi3GetEventIndicators(fmi3Instance c, fmi3Float64 z[], size_t n) {
    (void)c; (void)z; return n ? fmi3Error : fmi3OK;
}
fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance c, size_t *n) { (void)c; *n = 0; return fmi3OK; }
fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance c, size_t *n) { (void)c; *n = 0; return fmi3OK; }
fmi3Status fmi3EnterStepMode(fmi3Instance c) { (void)c; return fmi3OK; }
fmi3Status fmi3Terminate(fmi3Instance c) { (void)c; return fmi3OK; }
fmi3Status fmi3Reset(fmi3Instance c) { (void)c; return fmi3Error; }

fmi3Status fmi3DoStep(fmi3Instance c, fmi3Float64 t, fmi3Float64 h, fmi3Boolean no_set_prior,
                      fmi3Boolean *event_needed, fmi3Boolean *terminate, fmi3Boolean *early,
                      fmi3Float64 *last) {
    Instance *s = c;
    (void)no_set_prior;
    s->time = t + h;
    update_n(s);
    *event_needed = false; *terminate = false; *early = false; *last = s->time;
    return fmi3OK;
}

/* One typed getter/setter per type: `CASE(vr, expression)` lines, anything else refused. */
#define GETTER(fn, ctype, body)                                                           \
    fmi3Status fn(fmi3Instance c, const fmi3ValueReference vr[], size_t n_vr, ctype v[],   \
                  size_t n_values) {                                                       \
        Instance *s = c; size_t i; long n = whole_seconds(s); (void)n;                     \
        if (n_values != n_vr) return refuse(s, #fn " (nValues)", n_vr ? vr[0] : 0);        \
        for (i = 0; i < n_vr; i++) switch (vr[i]) { body default: return refuse(s, #fn, vr[i]); } \
        return fmi3OK;                                                                     \
    }
#define SETTER(fn, ctype, body)                                                           \
    fmi3Status fn(fmi3Instance c, const fmi3ValueReference vr[], size_t n_vr, const ctype v[], \
                  size_t n_values) {                                                       \
        Instance *s = c; size_t i;                                                         \
        if (n_values != n_vr) return refuse(s, #fn " (nValues)", n_vr ? vr[0] : 0);        \
        for (i = 0; i < n_vr; i++) switch (vr[i]) { body default: return refuse(s, #fn, vr[i]); } \
        return fmi3OK;                                                                     \
    }
#define CASE(ref, stmt) case ref: stmt; break;

GETTER(fmi3GetFloat64, fmi3Float64, CASE(0, v[i] = s->time) CASE(27, v[i] = s->x_in)
                                    CASE(37, v[i] = s->x_in))
SETTER(fmi3SetFloat64, fmi3Float64, CASE(27, s->x_in = v[i]))
GETTER(fmi3GetFloat32, fmi3Float32, CASE(4, v[i] = s->gain) CASE(13, v[i] = (fmi3Float32)(s->gain * s->time))
                                    CASE(23, v[i] = s->y32_in) CASE(33, v[i] = s->y32_in))
SETTER(fmi3SetFloat32, fmi3Float32, CASE(4, s->gain = v[i]) CASE(23, s->y32_in = v[i]))
GETTER(fmi3GetInt8, fmi3Int8, CASE(1, v[i] = s->k) CASE(10, v[i] = (fmi3Int8)(s->k * n))
                              CASE(20, v[i] = s->n8_in) CASE(30, v[i] = s->n8_in))
SETTER(fmi3SetInt8, fmi3Int8, CASE(1, s->k = v[i]) CASE(20, s->n8_in = v[i]))
GETTER(fmi3GetUInt8, fmi3UInt8, CASE(17, v[i] = (fmi3UInt8)(20 * n)))
SETTER(fmi3SetUInt8, fmi3UInt8, )
GETTER(fmi3GetInt16, fmi3Int16, CASE(7, v[i] = s->offset16) CASE(16, v[i] = (fmi3Int16)(s->offset16 + n)))
SETTER(fmi3SetInt16, fmi3Int16, CASE(7, s->offset16 = v[i]))
GETTER(fmi3GetUInt16, fmi3UInt16, CASE(18, v[i] = (fmi3UInt16)(1000 * n)))
SETTER(fmi3SetUInt16, fmi3UInt16, )
GETTER(fmi3GetInt32, fmi3Int32, CASE(26, v[i] = s->i32_in) CASE(36, v[i] = s->i32_in))
SETTER(fmi3SetInt32, fmi3Int32, CASE(26, s->i32_in = v[i]))
GETTER(fmi3GetUInt32, fmi3UInt32, CASE(28, v[i] = s->u32_in) CASE(38, v[i] = s->u32_in))
SETTER(fmi3SetUInt32, fmi3UInt32, CASE(28, s->u32_in = v[i]))
/* Enumerations are got and set as Int64 */
GETTER(fmi3GetInt64, fmi3Int64, CASE(6, v[i] = s->mode) CASE(15, v[i] = s->mode)
                                CASE(25, v[i] = s->m_in) CASE(35, v[i] = s->m_in)
                                CASE(19, v[i] = n - (1LL << 53))
                                CASE(29, v[i] = s->i64_in) CASE(39, v[i] = s->i64_in))
SETTER(fmi3SetInt64, fmi3Int64, CASE(6, s->mode = v[i]) CASE(25, s->m_in = v[i])
                                CASE(29, s->i64_in = v[i]))
GETTER(fmi3GetUInt64, fmi3UInt64, CASE(5, v[i] = s->base) CASE(14, v[i] = s->base + (fmi3UInt64)n)
                                  CASE(24, v[i] = s->big_in) CASE(34, v[i] = s->big_in))
SETTER(fmi3SetUInt64, fmi3UInt64, CASE(5, s->base = v[i]) CASE(24, s->big_in = v[i]))
GETTER(fmi3GetBoolean, fmi3Boolean, CASE(2, v[i] = s->flag) CASE(11, v[i] = s->flag != (n % 2 != 0))
                                    CASE(21, v[i] = s->on_in) CASE(31, v[i] = s->on_in))
SETTER(fmi3SetBoolean, fmi3Boolean, CASE(2, s->flag = v[i]) CASE(21, s->on_in = v[i]))

static fmi3Status copy_text(Instance *s, char *to, const char *from, fmi3ValueReference vr) {
    if (from == NULL || strlen(from) >= TEXT) return refuse(s, "fmi3SetString (too long)", vr);
    strcpy(to, from);
    return fmi3OK;
}
GETTER(fmi3GetString, fmi3String, CASE(3, v[i] = s->label)
       CASE(12, (snprintf(s->tag, TEXT, "%s-%ld", s->label, n), v[i] = s->tag))
       CASE(22, v[i] = s->tag_in) CASE(32, v[i] = s->tag_in))
fmi3Status fmi3SetString(fmi3Instance c, const fmi3ValueReference vr[], size_t n_vr,
                         const fmi3String v[], size_t n_values) {
    Instance *s = c; size_t i;
    if (n_values != n_vr) return refuse(s, "fmi3SetString (nValues)", n_vr ? vr[0] : 0);
    for (i = 0; i < n_vr; i++) {
        fmi3Status st;
        if (vr[i] == 3) st = copy_text(s, s->label, v[i], vr[i]);
        else if (vr[i] == 22) st = copy_text(s, s->tag_in, v[i], vr[i]);
        else st = refuse(s, "fmi3SetString", vr[i]);
        if (st != fmi3OK) return st;
    }
    return fmi3OK;
}

/* never called by an importer of this FMU (no FMU state, no clocks) */
#define STUB(name) fmi3Status name(void) { return fmi3Error; }
STUB(fmi3InstantiateScheduledExecution) STUB(fmi3GetBinary) STUB(fmi3SetBinary) STUB(fmi3GetClock)
STUB(fmi3SetClock) STUB(fmi3GetNumberOfVariableDependencies) STUB(fmi3GetVariableDependencies)
STUB(fmi3GetFMUState) STUB(fmi3SetFMUState) STUB(fmi3FreeFMUState)
STUB(fmi3SerializedFMUStateSize) STUB(fmi3SerializeFMUState) STUB(fmi3DeserializeFMUState)
STUB(fmi3GetDirectionalDerivative) STUB(fmi3GetAdjointDerivative)
STUB(fmi3EnterConfigurationMode) STUB(fmi3ExitConfigurationMode)
STUB(fmi3GetIntervalDecimal) STUB(fmi3GetIntervalFraction) STUB(fmi3GetShiftDecimal)
STUB(fmi3GetShiftFraction) STUB(fmi3SetIntervalDecimal) STUB(fmi3SetIntervalFraction)
STUB(fmi3SetShiftDecimal) STUB(fmi3SetShiftFraction) STUB(fmi3EvaluateDiscreteStates)
STUB(fmi3GetOutputDerivatives) STUB(fmi3ActivateModelPartition)
