/*
 * A C importer for valgrind memcheck: loads one FMU binary with dlopen and drives
 * Co-Simulation with both embedded solvers (events inside doStep), FMU-state save,
 * restore, serialize and deserialize, Model Exchange with event handling, and a
 * set of misuse calls, then frees everything. Built twice by memcheck.py, with
 * -DFMI_VERSION=2 or 3 against the FMI headers that fmpy ships.
 *
 * usage: memcheck_harness LIBRARY TOKEN VR_SOLVER VR_STATE STATE_START
 *   VR_STATE/STATE_START: a state set away from rest so that something happens.
 */
#include <dlfcn.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if FMI_VERSION == 3
#include "fmi3Functions.h"
#else
#include "fmi2Functions.h"
#endif

static void *lib;
static int failures;

static void *sym(const char *name)
{
    void *f = dlsym(lib, name);
    if (!f) {
        fprintf(stderr, "missing symbol %s\n", name);
        exit(2);
    }
    return f;
}
#define LOAD(T, name) T name = (T)sym(#name)

/* a misuse call must answer Error (or Discard), a proper one OK/Warning */
static void expect(const char *what, int status, int ok)
{
    int good = ok ? status <= 1 : (status == 2 || status == 3);
    if (!good) {
        fprintf(stderr, "%s: unexpected status %d\n", what, status);
        failures++;
    }
}

#if FMI_VERSION == 3
static void logger(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category,
                   fmi3String message)
{
    (void)env; (void)status; (void)category;
    (void)strlen(message); /* touch every byte, so that valgrind checks the buffer */
}

static void run(const char *token, unsigned vr_solver, unsigned vr_state, double x0)
{
    LOAD(fmi3InstantiateCoSimulationTYPE *, fmi3InstantiateCoSimulation);
    LOAD(fmi3InstantiateModelExchangeTYPE *, fmi3InstantiateModelExchange);
    LOAD(fmi3FreeInstanceTYPE *, fmi3FreeInstance);
    LOAD(fmi3EnterInitializationModeTYPE *, fmi3EnterInitializationMode);
    LOAD(fmi3ExitInitializationModeTYPE *, fmi3ExitInitializationMode);
    LOAD(fmi3SetInt32TYPE *, fmi3SetInt32);
    LOAD(fmi3SetFloat64TYPE *, fmi3SetFloat64);
    LOAD(fmi3GetFloat64TYPE *, fmi3GetFloat64);
    LOAD(fmi3DoStepTYPE *, fmi3DoStep);
    LOAD(fmi3GetFMUStateTYPE *, fmi3GetFMUState);
    LOAD(fmi3SetFMUStateTYPE *, fmi3SetFMUState);
    LOAD(fmi3FreeFMUStateTYPE *, fmi3FreeFMUState);
    LOAD(fmi3SerializedFMUStateSizeTYPE *, fmi3SerializedFMUStateSize);
    LOAD(fmi3SerializeFMUStateTYPE *, fmi3SerializeFMUState);
    LOAD(fmi3DeserializeFMUStateTYPE *, fmi3DeserializeFMUState);
    LOAD(fmi3TerminateTYPE *, fmi3Terminate);
    LOAD(fmi3ResetTYPE *, fmi3Reset);
    LOAD(fmi3EnterContinuousTimeModeTYPE *, fmi3EnterContinuousTimeMode);
    LOAD(fmi3EnterEventModeTYPE *, fmi3EnterEventMode);
    LOAD(fmi3UpdateDiscreteStatesTYPE *, fmi3UpdateDiscreteStates);
    LOAD(fmi3GetNumberOfContinuousStatesTYPE *, fmi3GetNumberOfContinuousStates);
    LOAD(fmi3GetNumberOfEventIndicatorsTYPE *, fmi3GetNumberOfEventIndicators);
    LOAD(fmi3GetContinuousStatesTYPE *, fmi3GetContinuousStates);
    LOAD(fmi3SetContinuousStatesTYPE *, fmi3SetContinuousStates);
    LOAD(fmi3GetContinuousStateDerivativesTYPE *, fmi3GetContinuousStateDerivatives);
    LOAD(fmi3GetEventIndicatorsTYPE *, fmi3GetEventIndicators);
    LOAD(fmi3SetTimeTYPE *, fmi3SetTime);
    LOAD(fmi3CompletedIntegratorStepTYPE *, fmi3CompletedIntegratorStep);
    int solver;
    for (solver = 0; solver <= 1; solver++) {
        fmi3Instance c = fmi3InstantiateCoSimulation("cs", token, NULL, fmi3False, fmi3True,
                                                     fmi3False, fmi3False, NULL, 0, NULL,
                                                     logger, NULL);
        fmi3FMUState s1 = NULL, s2 = NULL;
        fmi3Boolean ev, term, early;
        fmi3Float64 last, val, nan = NAN;
        fmi3Byte *bytes;
        size_t size;
        fmi3ValueReference bad = 999999;
        int i;
        if (!c) { fprintf(stderr, "instantiate failed\n"); exit(2); }
        expect("set solver", fmi3SetInt32(c, &vr_solver, 1, &solver, 1), 1);
        expect("set state", fmi3SetFloat64(c, &vr_state, 1, &x0, 1), 1);
        expect("init", fmi3EnterInitializationMode(c, fmi3True, 1e-8, 0.0, fmi3False, 0.0), 1);
        expect("exit init", fmi3ExitInitializationMode(c), 1);
        for (i = 0; i < 5; i++)
            expect("doStep", fmi3DoStep(c, i * 1.0, 1.0, fmi3True, &ev, &term, &early, &last), 1);
        expect("get state", fmi3GetFMUState(c, &s1), 1);
        expect("doStep", fmi3DoStep(c, 5.0, 2.5, fmi3True, &ev, &term, &early, &last), 1);
        expect("set state", fmi3SetFMUState(c, s1), 1);
        expect("size", fmi3SerializedFMUStateSize(c, s1, &size), 1);
        bytes = (fmi3Byte *)malloc(size);
        expect("serialize", fmi3SerializeFMUState(c, s1, bytes, size), 1);
        expect("deserialize", fmi3DeserializeFMUState(c, bytes, size, &s2), 1);
        expect("short bytes", fmi3DeserializeFMUState(c, bytes, size / 2, &s2), 0);
        free(bytes);
        expect("set state 2", fmi3SetFMUState(c, s2), 1);
        expect("doStep", fmi3DoStep(c, 5.0, 2.5, fmi3True, &ev, &term, &early, &last), 1);
        /* misuse */
        expect("unknown vr", fmi3GetFloat64(c, &bad, 1, &val, 1), 0);
        expect("NaN state", fmi3SetFloat64(c, &vr_state, 1, &nan, 1), 0);
        expect("negative h", fmi3DoStep(c, last, -1.0, fmi3True, &ev, &term, &early, &last), 0);
        expect("wrong t", fmi3DoStep(c, last + 3.0, 1.0, fmi3True, &ev, &term, &early, &last), 0);
        expect("free s1", fmi3FreeFMUState(c, &s1), 1);
        expect("free s2", fmi3FreeFMUState(c, &s2), 1);
        expect("terminate", fmi3Terminate(c), 1);
        expect("doStep after terminate", fmi3DoStep(c, last, 1.0, fmi3True, &ev, &term, &early,
                                                    &last), 0);
        expect("reset", fmi3Reset(c), 1);
        fmi3FreeInstance(c);
    }
    {
        fmi3Instance m = fmi3InstantiateModelExchange("me", token, NULL, fmi3False, fmi3True,
                                                      NULL, logger);
        size_t nx, nz, k;
        double *x, *dx, *z, t = 0.0, h = 1e-3;
        fmi3Boolean a, b, c2, d, e;
        fmi3Float64 next;
        int i;
        if (!m) { fprintf(stderr, "instantiate failed\n"); exit(2); }
        expect("set state", fmi3SetFloat64(m, &vr_state, 1, &x0, 1), 1);
        expect("init", fmi3EnterInitializationMode(m, fmi3False, 0.0, 0.0, fmi3False, 0.0), 1);
        expect("exit init", fmi3ExitInitializationMode(m), 1);
        expect("update", fmi3UpdateDiscreteStates(m, &a, &b, &c2, &d, &e, &next), 1);
        expect("ct mode", fmi3EnterContinuousTimeMode(m), 1);
        fmi3GetNumberOfContinuousStates(m, &nx);
        fmi3GetNumberOfEventIndicators(m, &nz);
        x = (double *)calloc(nx + 1, sizeof(double));
        dx = (double *)calloc(nx + 1, sizeof(double));
        z = (double *)calloc(nz + 1, sizeof(double));
        for (i = 0; i < 200; i++) { /* explicit Euler, as the simplest importer */
            expect("get x", fmi3GetContinuousStates(m, x, nx), 1);
            expect("get dx", fmi3GetContinuousStateDerivatives(m, dx, nx), 1);
            for (k = 0; k < nx; k++) x[k] += h * dx[k];
            t += h;
            expect("set t", fmi3SetTime(m, t), 1);
            expect("set x", fmi3SetContinuousStates(m, x, nx), 1);
            expect("get z", fmi3GetEventIndicators(m, z, nz), 1);
            expect("step done", fmi3CompletedIntegratorStep(m, fmi3True, &a, &b), 1);
            if (i % 50 == 49) { /* an event round trip */
                expect("event", fmi3EnterEventMode(m), 1);
                expect("update", fmi3UpdateDiscreteStates(m, &a, &b, &c2, &d, &e, &next), 1);
                expect("ct mode", fmi3EnterContinuousTimeMode(m), 1);
            }
        }
        expect("wrong nx", fmi3GetContinuousStates(m, x, nx + 1), 0);
        free(x); free(dx); free(z);
        expect("terminate", fmi3Terminate(m), 1);
        fmi3FreeInstance(m);
    }
}
#else
static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status,
                   fmi2String category, fmi2String message, ...)
{
    char buf[2048];
    va_list ap;
    (void)env; (void)name; (void)status; (void)category;
    va_start(ap, message);
    vsnprintf(buf, sizeof buf, message, ap); /* formats, so valgrind checks the arguments */
    va_end(ap);
}

static void run(const char *token, unsigned vr_solver, unsigned vr_state, double x0)
{
    LOAD(fmi2InstantiateTYPE *, fmi2Instantiate);
    LOAD(fmi2FreeInstanceTYPE *, fmi2FreeInstance);
    LOAD(fmi2SetupExperimentTYPE *, fmi2SetupExperiment);
    LOAD(fmi2EnterInitializationModeTYPE *, fmi2EnterInitializationMode);
    LOAD(fmi2ExitInitializationModeTYPE *, fmi2ExitInitializationMode);
    LOAD(fmi2SetIntegerTYPE *, fmi2SetInteger);
    LOAD(fmi2SetRealTYPE *, fmi2SetReal);
    LOAD(fmi2GetRealTYPE *, fmi2GetReal);
    LOAD(fmi2DoStepTYPE *, fmi2DoStep);
    LOAD(fmi2GetFMUstateTYPE *, fmi2GetFMUstate);
    LOAD(fmi2SetFMUstateTYPE *, fmi2SetFMUstate);
    LOAD(fmi2FreeFMUstateTYPE *, fmi2FreeFMUstate);
    LOAD(fmi2SerializedFMUstateSizeTYPE *, fmi2SerializedFMUstateSize);
    LOAD(fmi2SerializeFMUstateTYPE *, fmi2SerializeFMUstate);
    LOAD(fmi2DeSerializeFMUstateTYPE *, fmi2DeSerializeFMUstate);
    LOAD(fmi2TerminateTYPE *, fmi2Terminate);
    LOAD(fmi2ResetTYPE *, fmi2Reset);
    LOAD(fmi2EnterContinuousTimeModeTYPE *, fmi2EnterContinuousTimeMode);
    LOAD(fmi2EnterEventModeTYPE *, fmi2EnterEventMode);
    LOAD(fmi2NewDiscreteStatesTYPE *, fmi2NewDiscreteStates);
    LOAD(fmi2GetContinuousStatesTYPE *, fmi2GetContinuousStates);
    LOAD(fmi2SetContinuousStatesTYPE *, fmi2SetContinuousStates);
    LOAD(fmi2GetDerivativesTYPE *, fmi2GetDerivatives);
    LOAD(fmi2GetEventIndicatorsTYPE *, fmi2GetEventIndicators);
    LOAD(fmi2SetTimeTYPE *, fmi2SetTime);
    LOAD(fmi2CompletedIntegratorStepTYPE *, fmi2CompletedIntegratorStep);
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    int solver;
    for (solver = 0; solver <= 1; solver++) {
        fmi2Component c = fmi2Instantiate("cs", fmi2CoSimulation, token, "", &cb, fmi2False,
                                          fmi2True);
        fmi2FMUstate s1 = NULL, s2 = NULL;
        fmi2Real val, nan = NAN;
        fmi2Byte *bytes;
        size_t size;
        fmi2ValueReference bad = 999999;
        int i;
        if (!c) { fprintf(stderr, "instantiate failed\n"); exit(2); }
        expect("set solver", fmi2SetInteger(c, &vr_solver, 1, &solver), 1);
        expect("set state", fmi2SetReal(c, &vr_state, 1, &x0), 1);
        expect("setup", fmi2SetupExperiment(c, fmi2True, 1e-8, 0.0, fmi2False, 0.0), 1);
        expect("init", fmi2EnterInitializationMode(c), 1);
        expect("exit init", fmi2ExitInitializationMode(c), 1);
        for (i = 0; i < 5; i++) expect("doStep", fmi2DoStep(c, i * 1.0, 1.0, fmi2True), 1);
        expect("get state", fmi2GetFMUstate(c, &s1), 1);
        expect("doStep", fmi2DoStep(c, 5.0, 2.5, fmi2True), 1);
        expect("set state", fmi2SetFMUstate(c, s1), 1);
        expect("size", fmi2SerializedFMUstateSize(c, s1, &size), 1);
        bytes = (fmi2Byte *)malloc(size);
        expect("serialize", fmi2SerializeFMUstate(c, s1, bytes, size), 1);
        expect("deserialize", fmi2DeSerializeFMUstate(c, bytes, size, &s2), 1);
        expect("short bytes", fmi2DeSerializeFMUstate(c, bytes, size / 2, &s2), 0);
        free(bytes);
        expect("set state 2", fmi2SetFMUstate(c, s2), 1);
        expect("doStep", fmi2DoStep(c, 5.0, 2.5, fmi2True), 1);
        expect("unknown vr", fmi2GetReal(c, &bad, 1, &val), 0);
        expect("NaN state", fmi2SetReal(c, &vr_state, 1, &nan), 0);
        expect("negative h", fmi2DoStep(c, 7.5, -1.0, fmi2True), 0);
        expect("wrong t", fmi2DoStep(c, 10.5, 1.0, fmi2True), 0);
        expect("free s1", fmi2FreeFMUstate(c, &s1), 1);
        expect("free s2", fmi2FreeFMUstate(c, &s2), 1);
        expect("terminate", fmi2Terminate(c), 1);
        expect("doStep after terminate", fmi2DoStep(c, 7.5, 1.0, fmi2True), 0);
        expect("reset", fmi2Reset(c), 1);
        fmi2FreeInstance(c);
    }
    {
        fmi2Component m = fmi2Instantiate("me", fmi2ModelExchange, token, "", &cb, fmi2False,
                                          fmi2True);
        fmi2EventInfo info;
        size_t nx = 64, nz = 64, k; /* generous buffers; the sizes passed are queried below */
        double x[64], dx[64], z[64], t = 0.0, h = 1e-3;
        fmi2Boolean a, b;
        int i;
        if (!m) { fprintf(stderr, "instantiate failed\n"); exit(2); }
        expect("set state", fmi2SetReal(m, &vr_state, 1, &x0), 1);
        expect("setup", fmi2SetupExperiment(m, fmi2False, 0.0, 0.0, fmi2False, 0.0), 1);
        expect("init", fmi2EnterInitializationMode(m), 1);
        expect("exit init", fmi2ExitInitializationMode(m), 1);
        expect("update", fmi2NewDiscreteStates(m, &info), 1);
        expect("ct mode", fmi2EnterContinuousTimeMode(m), 1);
        /* FMI 2 has no size query: find the sizes the FMU accepts */
        for (nx = 0; nx < 64 && fmi2GetContinuousStates(m, x, nx) != fmi2OK; nx++) {}
        for (nz = 0; nz < 64 && fmi2GetEventIndicators(m, z, nz) != fmi2OK; nz++) {}
        for (i = 0; i < 200; i++) {
            expect("get x", fmi2GetContinuousStates(m, x, nx), 1);
            expect("get dx", fmi2GetDerivatives(m, dx, nx), 1);
            for (k = 0; k < nx; k++) x[k] += h * dx[k];
            t += h;
            expect("set t", fmi2SetTime(m, t), 1);
            expect("set x", fmi2SetContinuousStates(m, x, nx), 1);
            expect("get z", fmi2GetEventIndicators(m, z, nz), 1);
            expect("step done", fmi2CompletedIntegratorStep(m, fmi2True, &a, &b), 1);
            if (i % 50 == 49) {
                expect("event", fmi2EnterEventMode(m), 1);
                expect("update", fmi2NewDiscreteStates(m, &info), 1);
                expect("ct mode", fmi2EnterContinuousTimeMode(m), 1);
            }
        }
        expect("terminate", fmi2Terminate(m), 1);
        fmi2FreeInstance(m);
    }
}
#endif

int main(int argc, char **argv)
{
    if (argc != 6) {
        fprintf(stderr, "usage: %s LIBRARY TOKEN VR_SOLVER VR_STATE STATE_START\n", argv[0]);
        return 2;
    }
    lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "dlopen: %s\n", dlerror());
        return 2;
    }
    run(argv[2], (unsigned)atoi(argv[3]), (unsigned)atoi(argv[4]), atof(argv[5]));
    dlclose(lib);
    if (failures) fprintf(stderr, "%d unexpected statuses\n", failures);
    return failures ? 1 : 0;
}
