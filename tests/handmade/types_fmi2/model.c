/* types_fmi2: FMI 2 Co-Simulation with Integer, Boolean, Enumeration and String variables,
   each got and set only through its FMI 2 call (Enumerations through fmi2Get/SetInteger);
   any other value reference is an fmi2Error with a message naming it.
   With n = floor(t): count (Integer) = step * n, on (Boolean) = flag XOR (n odd),
   tag (String) = label "-" n, m (Enumeration) = mode; the *_echo outputs are the inputs. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"
#define HANDMADE_CS
#define OWN_fmi2GetInteger
#define OWN_fmi2GetBoolean
#define OWN_fmi2GetString
#define OWN_fmi2SetInteger
#define OWN_fmi2SetBoolean
#define OWN_fmi2SetString
#include "../fmi2_defaults.h"

#define TEXT 256

typedef struct {
    double time;
    fmi2Integer step, mode, n_in, m_in;
    fmi2Boolean flag, on_in;
    char label[TEXT], tag_in[TEXT], tag[TEXT];
    fmi2CallbackFunctions cb;
} Instance;

static fmi2Status refuse(Instance *s, const char *fn, fmi2ValueReference vr) {
    if (s->cb.logger)
        s->cb.logger(s->cb.componentEnvironment, "types_fmi2", fmi2Error, "logStatusError",
                     "%s: value reference %u is not a variable of this type", fn, vr);
    return fmi2Error;
}
static long whole_seconds(const Instance *s) { return (long)floor(s->time + 1e-9); }

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                              fmi2String location, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean logging) {
    Instance *s;
    (void)name; (void)guid; (void)location; (void)visible; (void)logging;
    if (type != fmi2CoSimulation) return NULL;
    s = calloc(1, sizeof *s);
    if (s == NULL) return NULL;
    if (functions) s->cb = *functions;
    s->step = 7; s->mode = 2; s->m_in = 1; strcpy(s->label, "fmi2");
    return s;
}
fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDef, fmi2Real tol, fmi2Real t0,
                               fmi2Boolean stopDef, fmi2Real t1) {
    (void)tolDef; (void)tol; (void)stopDef; (void)t1;
    ((Instance *)c)->time = t0; return fmi2OK;
}
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) { (void)c; return fmi2Error; }

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *s = c; size_t i;
    for (i = 0; i < n; i++) {
        if (vr[i] != 0) return refuse(s, "fmi2GetReal", vr[i]);
        v[i] = s->time;
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    (void)v; return n ? refuse(c, "fmi2SetReal", vr[0]) : fmi2OK;
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[]) {
    Instance *s = c; size_t i; long k = whole_seconds(s);
    for (i = 0; i < n; i++) switch (vr[i]) {
        case 1: v[i] = s->step; break;
        case 3: v[i] = s->mode; break;
        case 10: v[i] = (fmi2Integer)(s->step * k); break;
        case 13: v[i] = s->mode; break;
        case 20: case 30: v[i] = s->n_in; break;
        case 23: case 33: v[i] = s->m_in; break;
        default: return refuse(s, "fmi2GetInteger", vr[i]);
    }
    return fmi2OK;
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[]) {
    Instance *s = c; size_t i;
    for (i = 0; i < n; i++) switch (vr[i]) {
        case 1: s->step = v[i]; break;
        case 3: s->mode = v[i]; break;
        case 20: s->n_in = v[i]; break;
        case 23: s->m_in = v[i]; break;
        default: return refuse(s, "fmi2SetInteger", vr[i]);
    }
    return fmi2OK;
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean v[]) {
    Instance *s = c; size_t i; long k = whole_seconds(s);
    for (i = 0; i < n; i++) switch (vr[i]) {
        case 2: v[i] = s->flag; break;
        case 11: v[i] = (s->flag != 0) != (k % 2 != 0); break;
        case 21: case 31: v[i] = s->on_in; break;
        default: return refuse(s, "fmi2GetBoolean", vr[i]);
    }
    return fmi2OK;
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[]) {
    Instance *s = c; size_t i;
    for (i = 0; i < n; i++) switch (vr[i]) {
        case 2: s->flag = v[i]; break;
        case 21: s->on_in = v[i]; break;
        default: return refuse(s, "fmi2SetBoolean", vr[i]);
    }
    return fmi2OK;
}
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2String v[]) {
    Instance *s = c; size_t i;
    for (i = 0; i < n; i++) switch (vr[i]) {
        case 4: v[i] = s->label; break;
        case 12: snprintf(s->tag, TEXT, "%s-%ld", s->label, whole_seconds(s)); v[i] = s->tag; break;
        case 22: case 32: v[i] = s->tag_in; break;
        default: return refuse(s, "fmi2GetString", vr[i]);
    }
    return fmi2OK;
}
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2String v[]) {
    Instance *s = c; size_t i;
    for (i = 0; i < n; i++) {
        char *to = vr[i] == 4 ? s->label : vr[i] == 22 ? s->tag_in : NULL;
        if (to == NULL || v[i] == NULL || strlen(v[i]) >= TEXT) return refuse(s, "fmi2SetString", vr[i]);
        strcpy(to, v[i]);
    }
    return fmi2OK;
}
fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetPrior) {
    (void)noSetPrior;
    ((Instance *)c)->time = t + h;
    return fmi2OK;
}
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind k, fmi2Real *v) {
    (void)c; (void)k; (void)v; return fmi2Discard;
}
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind k, fmi2Boolean *v) {
    (void)c; (void)k; (void)v; return fmi2Discard;
}
