/* hpy_hidden: x' = v, v' = -x (x(0) = 0, v(0) = 1: x = sin t), FMI 2 Model Exchange, whose
   modelDescription.xml declares both states (der(x) and der(v) carry derivative=) but
   lists only der(x) in ModelStructure/Derivatives. An importer that counts the states
   from that list gives the FMU nx = 1: the binary, which honours nx as the standard
   says, integrates x and leaves v at 1, so x = t, silently. */
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"
#define HANDMADE_ME
#include "../fmi2_defaults.h"

typedef struct { double time, x[2]; } Instance;

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                              fmi2String location, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean logging) {
    (void)name; (void)guid; (void)location; (void)functions; (void)visible; (void)logging;
    if (type != fmi2ModelExchange) return NULL;
    Instance *s = calloc(1, sizeof *s);
    if (s) s->x[1] = 1.0;
    return s;
}
fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDef, fmi2Real tol, fmi2Real t0,
                               fmi2Boolean stopDef, fmi2Real t1) {
    (void)tolDef; (void)tol; (void)stopDef; (void)t1;
    ((Instance *)c)->time = t0; return fmi2OK;
}
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) {
    Instance *s = c; s->time = 0; s->x[0] = 0; s->x[1] = 1; return fmi2OK;
}
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        switch (vr[i]) {
        case 0: v[i] = s->x[0]; break;
        case 1: v[i] = s->x[1]; break;
        case 2: v[i] = s->x[1]; break;
        case 3: v[i] = -s->x[0]; break;
        default: return fmi2Error;
        }
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    Instance *s = c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] == 0) s->x[0] = v[i];
        else if (vr[i] == 2) s->x[1] = v[i];
        else return fmi2Error;
    }
    return fmi2OK;
}
fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) { ((Instance *)c)->time = t; return fmi2OK; }
/* the first nx states, as the standard has the importer say how many it holds */
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    Instance *s = c;
    for (size_t i = 0; i < nx && i < 2; i++) s->x[i] = x[i];
    return fmi2OK;
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t nx) {
    Instance *s = c;
    double d[2] = {s->x[1], -s->x[0]};
    for (size_t i = 0; i < nx && i < 2; i++) dx[i] = d[i];
    return fmi2OK;
}
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    Instance *s = c;
    for (size_t i = 0; i < nx && i < 2; i++) x[i] = s->x[i];
    return fmi2OK;
}
