/*
 * fmu.c: the FMI 2.0 / 3.0 loader behind fmu.h.
 *
 * Each public call dispatches on the FMI version to the function pointers looked
 * up at load time. Optional functions (FMU state, directional derivatives, the
 * interface the FMU does not implement) may be missing from the library: they are
 * looked up without failing, and calling one that is missing returns FMU_ERROR
 * with a message instead of crashing.
 */
#define _POSIX_C_SOURCE 200809L
#include "fmu.h"

#include <dlfcn.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine.h"
#include "fmi2Functions.h"
#include "fmi3Functions.h"

#define MESSAGE_LEN 1024

typedef struct {
    fmi2InstantiateTYPE *instantiate;
    fmi2FreeInstanceTYPE *free_instance;
    fmi2SetDebugLoggingTYPE *set_debug_logging;
    fmi2SetupExperimentTYPE *setup_experiment;
    fmi2EnterInitializationModeTYPE *enter_initialization_mode;
    fmi2ExitInitializationModeTYPE *exit_initialization_mode;
    fmi2TerminateTYPE *terminate;
    fmi2GetRealTYPE *get_real;
    fmi2SetRealTYPE *set_real;
    fmi2GetIntegerTYPE *get_integer;
    fmi2SetIntegerTYPE *set_integer;
    fmi2GetBooleanTYPE *get_boolean;
    fmi2SetBooleanTYPE *set_boolean;
    fmi2GetStringTYPE *get_string;
    fmi2SetStringTYPE *set_string;
    fmi2GetFMUstateTYPE *get_state;
    fmi2SetFMUstateTYPE *set_state;
    fmi2FreeFMUstateTYPE *free_state;
    fmi2GetDirectionalDerivativeTYPE *directional_derivative;
    fmi2SetTimeTYPE *set_time;
    fmi2SetContinuousStatesTYPE *set_continuous_states;
    fmi2GetContinuousStatesTYPE *get_continuous_states;
    fmi2GetDerivativesTYPE *get_derivatives;
    fmi2GetEventIndicatorsTYPE *get_event_indicators;
    fmi2GetNominalsOfContinuousStatesTYPE *get_nominals;
    fmi2EnterEventModeTYPE *enter_event_mode;
    fmi2NewDiscreteStatesTYPE *new_discrete_states;
    fmi2EnterContinuousTimeModeTYPE *enter_continuous_time_mode;
    fmi2CompletedIntegratorStepTYPE *completed_integrator_step;
    fmi2DoStepTYPE *do_step;
    fmi2GetRealStatusTYPE *get_real_status;
    fmi2GetBooleanStatusTYPE *get_boolean_status;
} fmi2_api;

/* mfEvaluateAt of FMUs built from our runtime (fmus/runtime/fmi3.c): fmi3SetTime,
   fmi3SetContinuousStates, then the derivatives and event indicators read, in one call */
typedef fmi3Status mf_evaluate_at_fn(fmi3Instance, fmi3Float64, const fmi3Float64[], size_t,
                                     fmi3Float64[], fmi3Float64[], size_t);

typedef struct {
    fmi3InstantiateModelExchangeTYPE *instantiate_me;
    fmi3InstantiateCoSimulationTYPE *instantiate_cs;
    fmi3FreeInstanceTYPE *free_instance;
    fmi3EnterInitializationModeTYPE *enter_initialization_mode;
    fmi3ExitInitializationModeTYPE *exit_initialization_mode;
    fmi3TerminateTYPE *terminate;
    fmi3GetFloat64TYPE *get_float64;
    fmi3SetFloat64TYPE *set_float64;
    fmi3GetInt32TYPE *get_int32;
    fmi3SetInt32TYPE *set_int32;
    fmi3GetFloat32TYPE *get_float32;
    fmi3SetFloat32TYPE *set_float32;
    fmi3GetInt8TYPE *get_int8;
    fmi3SetInt8TYPE *set_int8;
    fmi3GetUInt8TYPE *get_uint8;
    fmi3SetUInt8TYPE *set_uint8;
    fmi3GetInt16TYPE *get_int16;
    fmi3SetInt16TYPE *set_int16;
    fmi3GetUInt16TYPE *get_uint16;
    fmi3SetUInt16TYPE *set_uint16;
    fmi3GetUInt32TYPE *get_uint32;
    fmi3SetUInt32TYPE *set_uint32;
    fmi3GetInt64TYPE *get_int64;
    fmi3SetInt64TYPE *set_int64;
    fmi3GetUInt64TYPE *get_uint64;
    fmi3SetUInt64TYPE *set_uint64;
    fmi3GetBooleanTYPE *get_boolean;
    fmi3SetBooleanTYPE *set_boolean;
    fmi3GetStringTYPE *get_string;
    fmi3SetStringTYPE *set_string;
    fmi3GetFMUStateTYPE *get_state;
    fmi3SetFMUStateTYPE *set_state;
    fmi3FreeFMUStateTYPE *free_state;
    fmi3GetDirectionalDerivativeTYPE *directional_derivative;
    fmi3SetTimeTYPE *set_time;
    fmi3SetContinuousStatesTYPE *set_continuous_states;
    fmi3GetContinuousStatesTYPE *get_continuous_states;
    fmi3GetContinuousStateDerivativesTYPE *get_derivatives;
    fmi3GetEventIndicatorsTYPE *get_event_indicators;
    fmi3GetNominalsOfContinuousStatesTYPE *get_nominals;
    fmi3EnterEventModeTYPE *enter_event_mode;
    fmi3UpdateDiscreteStatesTYPE *update_discrete_states;
    fmi3EnterContinuousTimeModeTYPE *enter_continuous_time_mode;
    fmi3CompletedIntegratorStepTYPE *completed_integrator_step;
    fmi3EnterStepModeTYPE *enter_step_mode;
    fmi3DoStepTYPE *do_step;
    mf_evaluate_at_fn *evaluate_at; /* not FMI: our runtime's mfEvaluateAt (fmi3.c) */
    fmu_off_fn *evaluate_off;       /* not FMI: our runtime's mfEvaluateOff (fmi3.c) */
} fmi3_api;

/* The values this instance last set of one array variable: FMI 3 sets an array whole,
   the engine's couplings set it element by element (fmu_set_element). */
typedef struct array_shadow {
    struct array_shadow *next;
    uint32_t vr;
    size_t size;
    double values[];
} array_shadow;

struct fmu_t {
    void *library;
    void *instance;  /* fmi2Component / fmi3Instance */
    int fmi_version;
    fmu_kind kind;
    int n_states, n_event_indicators;
    int can_get_set_state, provides_directional_derivative;
    int initialized, terminated;
    int message_is_error;  /* an error message is kept until the next failing call */
    fmu_intermediate_fn intermediate;
    void *intermediate_ctx;
    fmi2CallbackFunctions callbacks2;  /* FMI 2 keeps a pointer to it */
    fmi2_api v2;
    fmi3_api v3;
    array_shadow *shadows;
    char name[128];
    char message[MESSAGE_LEN];
};

/* --- messages -------------------------------------------------------------------- */

/* The FMU's log: keep the latest line, but never let a later info line hide an error. */
static void keep_log(fmu_t *f, int is_error, const char *category, const char *text) {
    if (f == NULL || (f->message_is_error && !is_error)) return;
    snprintf(f->message, sizeof f->message, "%.100s: %.200s%s%.700s", f->name, category ? category : "",
             category && *category ? ": " : "", text ? text : "");
    f->message_is_error = is_error;
}

static void fail(fmu_t *f, const char *format, ...) {
    char text[MESSAGE_LEN];
    va_list args;
    va_start(args, format);
    vsnprintf(text, sizeof text, format, args);
    va_end(args);
    if (f->message_is_error) return;  /* the FMU's own error says more than ours */
    snprintf(f->message, sizeof f->message, "%.100s: %.900s", f->name, text);
    f->message_is_error = 1;
}

static void log_fmi2(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                 fmi2String category, fmi2String message, ...) {
    char text[MESSAGE_LEN];
    va_list args;
    (void)instance;
    va_start(args, message);
    vsnprintf(text, sizeof text, message ? message : "", args);
    va_end(args);
    keep_log((fmu_t *)env, status >= fmi2Error, category, text);
}

static void log_fmi3(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category,
                 fmi3String message) {
    keep_log((fmu_t *)env, status >= fmi3Error, category, message);
}

static void intermediate3(fmi3InstanceEnvironment env, fmi3Float64 time,
                          fmi3Boolean set_requested, fmi3Boolean get_allowed,
                          fmi3Boolean step_finished, fmi3Boolean can_return_early,
                          fmi3Boolean *early_return_requested, fmi3Float64 *early_return_time) {
    fmu_t *f = (fmu_t *)env;
    int stop = 0;
    (void)set_requested;
    if (f->intermediate)
        stop = f->intermediate(f->intermediate_ctx, f, time, get_allowed, step_finished,
                               can_return_early);
    *early_return_requested = stop && can_return_early;
    *early_return_time = time;
}

/* Status of an FMI call -> fmu.h code. Warnings are success. fn names the call. */
static int check(fmu_t *f, int status, const char *fn) {
    /* fmi2Status and fmi3Status number OK, Warning, Discard, Error, Fatal alike */
    if (status <= fmi3Warning) {
        f->message_is_error = 0;
        return FMU_OK;
    }
    if (status == fmi3Discard) return FMU_DISCARD;
    fail(f, "fmi%d%s failed", f->fmi_version, fn);
    return FMU_ERROR;
}

#define REQUIRE(f, ptr, fn)                                                      \
    do {                                                                         \
        if ((ptr) == NULL) {                                                     \
            fail((f), "fmi%d%s is not available in this FMU", (f)->fmi_version, (fn)); \
            return FMU_ERROR;                                                    \
        }                                                                        \
    } while (0)

/* --- loading ----------------------------------------------------------------- */

static void *symbol(void *library, const char *name) { return dlsym(library, name); }

/* Libraries loaded in this process, with their functions: a short run (0.1 ms) would
   otherwise spend a tenth of its time in dlopen and 26 dlsym per FMU. Never unloaded
   (as with RTLD_NODELETE before): an entry is valid for the life of the process. */
typedef struct loaded_library {
    struct loaded_library *next;
    void *library;
    int fmi_version;
    fmi2_api v2;
    fmi3_api v3;
    char path[4096];
} loaded_library;

static loaded_library *loaded;
static pthread_mutex_t loaded_lock = PTHREAD_MUTEX_INITIALIZER;

/* The table dies with the binary that holds it: an importer unloads an assembly FMU's
   binary at FreeInstance (fmpy does) and loads it again for the next instance, and a
   table left behind leaked an entry per member per load (LeakSanitizer, make asan).
   The members' libraries themselves stay mapped (RTLD_NODELETE). */
__attribute__((destructor)) static void forget_libraries(void)
{
    while (loaded) {
        loaded_library *next = loaded->next;
        free(loaded);
        loaded = next;
    }
}

#define LOOKUP2(field, name) (f->v2.field = (void *)symbol(f->library, "fmi2" name))
#define LOOKUP3(field, name) (f->v3.field = (void *)symbol(f->library, "fmi3" name))

static void lookup2(fmu_t *f) {
    LOOKUP2(instantiate, "Instantiate");
    LOOKUP2(free_instance, "FreeInstance");
    LOOKUP2(set_debug_logging, "SetDebugLogging");
    LOOKUP2(setup_experiment, "SetupExperiment");
    LOOKUP2(enter_initialization_mode, "EnterInitializationMode");
    LOOKUP2(exit_initialization_mode, "ExitInitializationMode");
    LOOKUP2(terminate, "Terminate");
    LOOKUP2(get_real, "GetReal");
    LOOKUP2(set_real, "SetReal");
    LOOKUP2(get_integer, "GetInteger");
    LOOKUP2(set_integer, "SetInteger");
    LOOKUP2(get_boolean, "GetBoolean");
    LOOKUP2(set_boolean, "SetBoolean");
    LOOKUP2(get_string, "GetString");
    LOOKUP2(set_string, "SetString");
    LOOKUP2(get_state, "GetFMUstate");
    LOOKUP2(set_state, "SetFMUstate");
    LOOKUP2(free_state, "FreeFMUstate");
    LOOKUP2(directional_derivative, "GetDirectionalDerivative");
    LOOKUP2(set_time, "SetTime");
    LOOKUP2(set_continuous_states, "SetContinuousStates");
    LOOKUP2(get_continuous_states, "GetContinuousStates");
    LOOKUP2(get_derivatives, "GetDerivatives");
    LOOKUP2(get_event_indicators, "GetEventIndicators");
    LOOKUP2(get_nominals, "GetNominalsOfContinuousStates");
    LOOKUP2(enter_event_mode, "EnterEventMode");
    LOOKUP2(new_discrete_states, "NewDiscreteStates");
    LOOKUP2(enter_continuous_time_mode, "EnterContinuousTimeMode");
    LOOKUP2(completed_integrator_step, "CompletedIntegratorStep");
    LOOKUP2(do_step, "DoStep");
    LOOKUP2(get_real_status, "GetRealStatus");
    LOOKUP2(get_boolean_status, "GetBooleanStatus");
}

static void lookup3(fmu_t *f) {
    LOOKUP3(instantiate_me, "InstantiateModelExchange");
    LOOKUP3(instantiate_cs, "InstantiateCoSimulation");
    LOOKUP3(free_instance, "FreeInstance");
    LOOKUP3(enter_initialization_mode, "EnterInitializationMode");
    LOOKUP3(exit_initialization_mode, "ExitInitializationMode");
    LOOKUP3(terminate, "Terminate");
    LOOKUP3(get_float64, "GetFloat64");
    LOOKUP3(set_float64, "SetFloat64");
    LOOKUP3(get_int32, "GetInt32");
    LOOKUP3(set_int32, "SetInt32");
    LOOKUP3(get_float32, "GetFloat32");
    LOOKUP3(set_float32, "SetFloat32");
    LOOKUP3(get_int8, "GetInt8");
    LOOKUP3(set_int8, "SetInt8");
    LOOKUP3(get_uint8, "GetUInt8");
    LOOKUP3(set_uint8, "SetUInt8");
    LOOKUP3(get_int16, "GetInt16");
    LOOKUP3(set_int16, "SetInt16");
    LOOKUP3(get_uint16, "GetUInt16");
    LOOKUP3(set_uint16, "SetUInt16");
    LOOKUP3(get_uint32, "GetUInt32");
    LOOKUP3(set_uint32, "SetUInt32");
    LOOKUP3(get_int64, "GetInt64");
    LOOKUP3(set_int64, "SetInt64");
    LOOKUP3(get_uint64, "GetUInt64");
    LOOKUP3(set_uint64, "SetUInt64");
    LOOKUP3(get_boolean, "GetBoolean");
    LOOKUP3(set_boolean, "SetBoolean");
    LOOKUP3(get_string, "GetString");
    LOOKUP3(set_string, "SetString");
    LOOKUP3(get_state, "GetFMUState");
    LOOKUP3(set_state, "SetFMUState");
    LOOKUP3(free_state, "FreeFMUState");
    LOOKUP3(directional_derivative, "GetDirectionalDerivative");
    LOOKUP3(set_time, "SetTime");
    LOOKUP3(set_continuous_states, "SetContinuousStates");
    LOOKUP3(get_continuous_states, "GetContinuousStates");
    LOOKUP3(get_derivatives, "GetContinuousStateDerivatives");
    LOOKUP3(get_event_indicators, "GetEventIndicators");
    LOOKUP3(get_nominals, "GetNominalsOfContinuousStates");
    LOOKUP3(enter_event_mode, "EnterEventMode");
    LOOKUP3(update_discrete_states, "UpdateDiscreteStates");
    LOOKUP3(enter_continuous_time_mode, "EnterContinuousTimeMode");
    LOOKUP3(completed_integrator_step, "CompletedIntegratorStep");
    LOOKUP3(enter_step_mode, "EnterStepMode");
    LOOKUP3(do_step, "DoStep");
    f->v3.evaluate_at = (mf_evaluate_at_fn *)symbol(f->library, "mfEvaluateAt");
    f->v3.evaluate_off = (fmu_off_fn *)symbol(f->library, "mfEvaluateOff");
}

/* The functions every FMU of this version and interface must have. */
static const char *missing_required(const fmu_t *f) {
    if (f->fmi_version == 2) {
        const fmi2_api *a = &f->v2;
        if (!a->instantiate) return "fmi2Instantiate";
        if (!a->free_instance) return "fmi2FreeInstance";
        if (!a->enter_initialization_mode || !a->exit_initialization_mode)
            return "fmi2EnterInitializationMode";
        if (!a->get_real || !a->set_real) return "fmi2GetReal";
        if (f->kind == FMU_CO_SIMULATION) return a->do_step ? NULL : "fmi2DoStep";
        if (!a->set_time || !a->set_continuous_states || !a->get_derivatives ||
            !a->get_event_indicators || !a->enter_event_mode || !a->new_discrete_states ||
            !a->enter_continuous_time_mode || !a->completed_integrator_step ||
            !a->get_continuous_states)
            return "the Model Exchange functions";
        return NULL;
    }
    const fmi3_api *a = &f->v3;
    if (f->kind == FMU_CO_SIMULATION ? !a->instantiate_cs : !a->instantiate_me)
        return f->kind == FMU_CO_SIMULATION ? "fmi3InstantiateCoSimulation"
                                            : "fmi3InstantiateModelExchange";
    if (!a->free_instance) return "fmi3FreeInstance";
    if (!a->enter_initialization_mode || !a->exit_initialization_mode)
        return "fmi3EnterInitializationMode";
    if (!a->get_float64 || !a->set_float64) return "fmi3GetFloat64";
    if (f->kind == FMU_CO_SIMULATION) return a->do_step ? NULL : "fmi3DoStep";
    if (!a->set_time || !a->set_continuous_states || !a->get_derivatives ||
        !a->get_event_indicators || !a->enter_event_mode || !a->update_discrete_states ||
        !a->enter_continuous_time_mode || !a->completed_integrator_step ||
        !a->get_continuous_states)
        return "the Model Exchange functions";
    return NULL;
}

static const char *platform_folder(int fmi_version) {
#if defined(__x86_64__)
    return fmi_version == 2 ? "linux64" : "x86_64-linux";
#elif defined(__aarch64__)
    return fmi_version == 2 ? "linux64" : "aarch64-linux";
#else
    return fmi_version == 2 ? "linux32" : "x86-linux";
#endif
}

static int instantiate(fmu_t *f, const fmu_options *o) {
    char resources[4096];
    if (f->fmi_version == 2) {
        /* FMI 2 wants a URI, FMI 3 a plain path with a trailing separator */
        snprintf(resources, sizeof resources, "file://%s/resources", o->unzip_dir);
        f->callbacks2.logger = log_fmi2;
        f->callbacks2.allocateMemory = calloc;
        f->callbacks2.freeMemory = free;
        f->callbacks2.stepFinished = NULL;
        f->callbacks2.componentEnvironment = f;
        f->instance = f->v2.instantiate(
            f->name, f->kind == FMU_CO_SIMULATION ? fmi2CoSimulation : fmi2ModelExchange,
            o->instantiation_token, resources, &f->callbacks2, fmi2False,
            o->logging_on ? fmi2True : fmi2False);
        if (f->instance && o->logging_on && f->v2.set_debug_logging)
            f->v2.set_debug_logging(f->instance, fmi2True, 0, NULL);
    } else {
        snprintf(resources, sizeof resources, "%s/resources/", o->unzip_dir);
        if (f->kind == FMU_CO_SIMULATION)
            f->instance = f->v3.instantiate_cs(
                f->name, o->instantiation_token, resources, fmi3False,
                o->logging_on ? fmi3True : fmi3False, fmi3False,
                o->early_return_allowed ? fmi3True : fmi3False, NULL, 0, f, log_fmi3,
                o->intermediate ? intermediate3 : NULL);
        else
            f->instance = f->v3.instantiate_me(f->name, o->instantiation_token, resources,
                                               fmi3False, o->logging_on ? fmi3True : fmi3False,
                                               f, log_fmi3);
    }
    return f->instance != NULL;
}

/* f's library and functions, loaded once per path and FMI version (loaded_library);
   0 on success, else dlerror()'s message in err. */
static int load_library(fmu_t *f, const char *path, char *err, size_t err_len) {
    loaded_library *l;
    pthread_mutex_lock(&loaded_lock);
    for (l = loaded; l; l = l->next)
        if (l->fmi_version == f->fmi_version && strcmp(l->path, path) == 0) break;
    if (l == NULL && (l = calloc(1, sizeof *l)) != NULL) {
        l->library = dlopen(path, RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
        if (l->library == NULL) {
            snprintf(err, err_len, "%s: cannot load %s: %s", f->name, path, dlerror());
            free(l);
            pthread_mutex_unlock(&loaded_lock);
            return -1;
        }
        f->library = l->library;
        if (f->fmi_version == 2) lookup2(f); else lookup3(f);
        l->fmi_version = f->fmi_version;
        l->v2 = f->v2;
        l->v3 = f->v3;
        snprintf(l->path, sizeof l->path, "%s", path);
        l->next = loaded;
        loaded = l;
    }
    pthread_mutex_unlock(&loaded_lock);
    if (l == NULL) {
        snprintf(err, err_len, "%s: out of memory loading %s", f->name, path);
        return -1;
    }
    f->library = l->library;
    f->v2 = l->v2;
    f->v3 = l->v3;
    return 0;
}

fmu_t *fmu_load(const fmu_options *o, char *err, size_t err_len) {
    char path[4096];
    const char *missing;
    fmu_t *f;
    if (o == NULL || o->unzip_dir == NULL || o->model_identifier == NULL ||
        o->instantiation_token == NULL || (o->fmi_version != 2 && o->fmi_version != 3)) {
        snprintf(err, err_len, "fmu_load: incomplete options (folder, modelIdentifier, token, "
                               "FMI version 2 or 3 are required)");
        return NULL;
    }
    f = calloc(1, sizeof *f);
    if (f == NULL) {
        snprintf(err, err_len, "fmu_load: out of memory");
        return NULL;
    }
    snprintf(f->name, sizeof f->name, "%s", o->instance_name ? o->instance_name : "fmu");
    f->fmi_version = o->fmi_version;
    f->kind = o->kind;
    f->n_states = o->n_states;
    f->n_event_indicators = o->n_event_indicators;
    f->can_get_set_state = o->can_get_set_state;
    f->provides_directional_derivative = o->provides_directional_derivative;
    f->intermediate = o->intermediate;
    f->intermediate_ctx = o->intermediate_ctx;
    snprintf(path, sizeof path, "%s/binaries/%s/%s.so", o->unzip_dir,
             platform_folder(o->fmi_version), o->model_identifier);
    if (load_library(f, path, err, err_len)) {
        free(f);
        return NULL;
    }
    missing = missing_required(f);
    if (missing) {
        snprintf(err, err_len, "%s: %s does not export %s", f->name, path, missing);
        free(f);
        return NULL;
    }
    if (!instantiate(f, o)) {
        snprintf(err, err_len, "%s: instantiation failed%s%s", f->name,
                 f->message[0] ? ": " : "", f->message);
        free(f);
        return NULL;
    }
    return f;
}

void fmu_free(fmu_t *f) {
    if (f == NULL) return;
    if (f->initialized && !f->terminated) fmu_terminate(f);
    while (f->shadows) {
        array_shadow *next = f->shadows->next;
        free(f->shadows);
        f->shadows = next;
    }
    if (f->fmi_version == 2) f->v2.free_instance(f->instance);
    else f->v3.free_instance(f->instance);
    free(f); /* the library stays loaded (load_library) */
}

int fmu_enter_initialization(fmu_t *f, double tolerance, double start_time, double stop_time) {
    int has_tol = tolerance > 0, has_stop = stop_time > start_time;
    if (f->fmi_version == 2) {
        if (f->v2.setup_experiment &&
            check(f, f->v2.setup_experiment(f->instance, has_tol, tolerance, start_time,
                                            has_stop, stop_time),
                  "SetupExperiment") != FMU_OK)
            return FMU_ERROR;
        return check(f, f->v2.enter_initialization_mode(f->instance), "EnterInitializationMode");
    }
    return check(f, f->v3.enter_initialization_mode(f->instance, has_tol, tolerance, start_time,
                                                     has_stop, stop_time),
                 "EnterInitializationMode");
}

int fmu_exit_initialization(fmu_t *f) {
    int rc;
    if (f->fmi_version == 2) {
        rc = check(f, f->v2.exit_initialization_mode(f->instance), "ExitInitializationMode");
    } else {
        rc = check(f, f->v3.exit_initialization_mode(f->instance), "ExitInitializationMode");
        /* FMI 3 CS without event mode goes straight to step mode */
    }
    if (rc == FMU_OK) f->initialized = 1;
    return rc;
}

int fmu_terminate(fmu_t *f) {
    int rc;
    if (f->terminated) return FMU_OK;
    if (f->fmi_version == 2)
        rc = f->v2.terminate ? check(f, f->v2.terminate(f->instance), "Terminate") : FMU_OK;
    else
        rc = f->v3.terminate ? check(f, f->v3.terminate(f->instance), "Terminate") : FMU_OK;
    f->terminated = 1;
    return rc;
}

const char *fmu_message(const fmu_t *f) { return f ? f->message : ""; }
const char *fmu_instance_name(const fmu_t *f) { return f->name; }
int fmu_fmi_version(const fmu_t *f) { return f->fmi_version; }
fmu_kind fmu_interface(const fmu_t *f) { return f->kind; }
int fmu_number_of_states(const fmu_t *f) { return f->n_states; }
int fmu_number_of_event_indicators(const fmu_t *f) { return f->n_event_indicators; }

/* --- variables ---------------------------------------------------------------- */

int fmu_get_float64(fmu_t *f, const uint32_t *vr, size_t n, double *values) {
    if (n == 0) return FMU_OK;
    if (f->fmi_version == 2) return check(f, f->v2.get_real(f->instance, vr, n, values), "GetReal");
    return check(f, f->v3.get_float64(f->instance, vr, n, values, n), "GetFloat64");
}

int fmu_set_float64(fmu_t *f, const uint32_t *vr, size_t n, const double *values) {
    if (n == 0) return FMU_OK;
    if (f->fmi_version == 2) return check(f, f->v2.set_real(f->instance, vr, n, values), "SetReal");
    return check(f, f->v3.set_float64(f->instance, vr, n, values, n), "SetFloat64");
}

int fmu_get_int32(fmu_t *f, const uint32_t *vr, size_t n, int32_t *values) {
    if (n == 0) return FMU_OK;
    if (f->fmi_version == 2) {
        int buffer[64];
        size_t i, done;
        REQUIRE(f, f->v2.get_integer, "GetInteger");
        for (done = 0; done < n; done += 64) {  /* fmi2Integer is int: same size, but be exact */
            size_t m = n - done < 64 ? n - done : 64;
            if (check(f, f->v2.get_integer(f->instance, vr + done, m, buffer), "GetInteger"))
                return FMU_ERROR;
            for (i = 0; i < m; i++) values[done + i] = buffer[i];
        }
        return FMU_OK;
    }
    REQUIRE(f, f->v3.get_int32, "GetInt32");
    return check(f, f->v3.get_int32(f->instance, vr, n, values, n), "GetInt32");
}

int fmu_set_int32(fmu_t *f, const uint32_t *vr, size_t n, const int32_t *values) {
    if (n == 0) return FMU_OK;
    if (f->fmi_version == 2) {
        int buffer[64];
        size_t i, done;
        REQUIRE(f, f->v2.set_integer, "SetInteger");
        for (done = 0; done < n; done += 64) {
            size_t m = n - done < 64 ? n - done : 64;
            for (i = 0; i < m; i++) buffer[i] = values[done + i];
            if (check(f, f->v2.set_integer(f->instance, vr + done, m, buffer), "SetInteger"))
                return FMU_ERROR;
        }
        return FMU_OK;
    }
    REQUIRE(f, f->v3.set_int32, "SetInt32");
    return check(f, f->v3.set_int32(f->instance, vr, n, values, n), "SetInt32");
}

/* --- variables of every type, as doubles ----------------------------------------- */

static const char *const type_names[ENG_N_TYPES] = {
    "Float64", "Int32", "Float32", "Int8", "UInt8", "Int16", "UInt16", "UInt32", "Int64",
    "UInt64", "Boolean", "Enumeration", "String"};

const char *fmu_type_name(int type) {
    return type >= 0 && type < ENG_N_TYPES ? type_names[type] : "an unknown type";
}

/* The whole numbers a double carries exactly: an Int64/UInt64 beyond is refused. */
#define EXACT_LIMIT 9007199254740992.0 /* 2^53 */

/* One FMI 3 get of any numeric type into a buffer of its C type, converted to double. */
#define GET3(ctype, fn, name)                                                               \
    do {                                                                                    \
        ctype small[64], *buf;                                                              \
        REQUIRE(f, f->v3.fn, name);                                                         \
        buf = n_values <= 64 ? small : malloc(n_values * sizeof(ctype));                    \
        if (buf == NULL) { fail(f, "out of memory reading %zu values", n_values); return FMU_ERROR; } \
        rc = check(f, f->v3.fn(f->instance, vr, n_vr, buf, n_values), name);                \
        for (i = 0; rc == FMU_OK && i < n_values; i++) values[i] = (double)buf[i];          \
        if (buf != small) free(buf);                                                        \
    } while (0)

/* Each value as the integer type [lo, hi] (rounded to the nearest integer), or a message. */
static int to_integer(fmu_t *f, int type, uint32_t vr, double v, double lo, double hi, double *out) {
    double r = round(v);
    if (!(r >= lo && r <= hi)) {
        fail(f, "value %.17g for variable (value reference %u) is outside the range of %s "
                "[%.17g, %.17g]", v, vr, fmu_type_name(type), lo, hi);
        return FMU_ERROR;
    }
    *out = r;
    return FMU_OK;
}

/* One FMI 3 set of any numeric type: each value checked against the type's range. */
#define SET3(ctype, fn, name, lo, hi)                                                       \
    do {                                                                                    \
        ctype small[64], *buf;                                                              \
        REQUIRE(f, f->v3.fn, name);                                                         \
        buf = n_values <= 64 ? small : malloc(n_values * sizeof(ctype));                    \
        if (buf == NULL) { fail(f, "out of memory setting %zu values", n_values); return FMU_ERROR; } \
        for (i = 0; rc == FMU_OK && i < n_values; i++) {                                    \
            double w = 0.0;                                                                 \
            rc = to_integer(f, type, vr[n_vr == n_values ? i : 0], values[i], lo, hi, &w);  \
            buf[i] = (ctype)w;                                                              \
        }                                                                                   \
        if (rc == FMU_OK) rc = check(f, f->v3.fn(f->instance, vr, n_vr, buf, n_values), name); \
        if (buf != small) free(buf);                                                        \
    } while (0)

/* An Int64/UInt64 beyond 2^53 does not travel as a double: refused, never rounded (the
   check is on the integer, before a conversion that would round it). */
#define EXACT_BITS 53
static int inexact(fmu_t *f, int type, uint32_t vr, const char *shown) {
    fail(f, "%s variable (value reference %u) has the value %s, beyond 2^53: the engine "
            "carries values as doubles and cannot pass it on exactly", fmu_type_name(type), vr,
         shown);
    return FMU_ERROR;
}

/* One FMI 3 get of a 64-bit integer type, each value checked to be exact as a double. */
#define GET3_64(ctype, fn, name, beyond, format, cast)                                      \
    do {                                                                                    \
        ctype small[64], *buf;                                                              \
        REQUIRE(f, f->v3.fn, name);                                                         \
        buf = n_values <= 64 ? small : malloc(n_values * sizeof(ctype));                    \
        if (buf == NULL) { fail(f, "out of memory reading %zu values", n_values); return FMU_ERROR; } \
        rc = check(f, f->v3.fn(f->instance, vr, n_vr, buf, n_values), name);                \
        for (i = 0; rc == FMU_OK && i < n_values; i++) {                                    \
            if (beyond) {                                                                   \
                char shown[32];                                                             \
                snprintf(shown, sizeof shown, format, cast buf[i]);                         \
                rc = inexact(f, type, vr[n_vr == n_values ? i : 0], shown);                 \
            }                                                                               \
            values[i] = (double)buf[i];                                                     \
        }                                                                                   \
        if (buf != small) free(buf);                                                        \
    } while (0)

/* FMI 2's numbers are Real, Integer (Int32 and Enumeration) and Boolean, all scalars. */
static int fmi2_can(fmu_t *f, int type, size_t n_vr, size_t n_values) {
    if (n_vr != n_values) {
        fail(f, "FMI 2 has no array variables");
        return FMU_ERROR;
    }
    if (type == ENG_FLOAT64 || type == ENG_INT32 || type == ENG_BOOLEAN || type == ENG_ENUMERATION)
        return FMU_OK;
    fail(f, "FMI 2 has no %s variables", fmu_type_name(type));
    return FMU_ERROR;
}

int fmu_get_typed(fmu_t *f, int type, const uint32_t *vr, size_t n_vr, double *values,
                  size_t n_values) {
    int rc = FMU_OK;
    size_t i;
    if (n_values == 0) return FMU_OK;
    if (type == ENG_FLOAT64 && n_vr == n_values) return fmu_get_float64(f, vr, n_vr, values);
    if (f->fmi_version == 2) {
        int small[64], *buf;
        if (fmi2_can(f, type, n_vr, n_values)) return FMU_ERROR;
        if (type == ENG_BOOLEAN) REQUIRE(f, f->v2.get_boolean, "GetBoolean");
        else REQUIRE(f, f->v2.get_integer, "GetInteger");
        buf = n_values <= 64 ? small : malloc(n_values * sizeof(int));
        if (buf == NULL) { fail(f, "out of memory reading %zu values", n_values); return FMU_ERROR; }
        rc = type == ENG_BOOLEAN
                 ? check(f, f->v2.get_boolean(f->instance, vr, n_vr, buf), "GetBoolean")
                 : check(f, f->v2.get_integer(f->instance, vr, n_vr, buf), "GetInteger");
        for (i = 0; rc == FMU_OK && i < n_values; i++)
            values[i] = type == ENG_BOOLEAN ? (buf[i] != 0) : (double)buf[i];
        if (buf != small) free(buf);
        return rc;
    }
    switch (type) {
    case ENG_FLOAT64:
        return check(f, f->v3.get_float64(f->instance, vr, n_vr, values, n_values), "GetFloat64");
    case ENG_FLOAT32: GET3(fmi3Float32, get_float32, "GetFloat32"); break;
    case ENG_INT8: GET3(fmi3Int8, get_int8, "GetInt8"); break;
    case ENG_UINT8: GET3(fmi3UInt8, get_uint8, "GetUInt8"); break;
    case ENG_INT16: GET3(fmi3Int16, get_int16, "GetInt16"); break;
    case ENG_UINT16: GET3(fmi3UInt16, get_uint16, "GetUInt16"); break;
    case ENG_INT32: GET3(fmi3Int32, get_int32, "GetInt32"); break;
    case ENG_UINT32: GET3(fmi3UInt32, get_uint32, "GetUInt32"); break;
    case ENG_INT64: case ENG_ENUMERATION:
        GET3_64(fmi3Int64, get_int64, "GetInt64",
                buf[i] > (1LL << EXACT_BITS) || buf[i] < -(1LL << EXACT_BITS), "%lld", (long long));
        break;
    case ENG_UINT64:
        GET3_64(fmi3UInt64, get_uint64, "GetUInt64", buf[i] > (1ULL << EXACT_BITS), "%llu",
                (unsigned long long));
        break;
    case ENG_BOOLEAN: GET3(fmi3Boolean, get_boolean, "GetBoolean"); break;
    default:
        fail(f, "cannot get %s values as numbers", fmu_type_name(type));
        return FMU_ERROR;
    }
    return rc;
}

int fmu_set_typed(fmu_t *f, int type, const uint32_t *vr, size_t n_vr, const double *values,
                  size_t n_values) {
    int rc = FMU_OK;
    size_t i;
    if (n_values == 0) return FMU_OK;
    if (type == ENG_FLOAT64 && n_vr == n_values) return fmu_set_float64(f, vr, n_vr, values);
    if (f->fmi_version == 2) {
        int small[64], *buf;
        if (fmi2_can(f, type, n_vr, n_values)) return FMU_ERROR;
        if (type == ENG_BOOLEAN) REQUIRE(f, f->v2.set_boolean, "SetBoolean");
        else REQUIRE(f, f->v2.set_integer, "SetInteger");
        buf = n_values <= 64 ? small : malloc(n_values * sizeof(int));
        if (buf == NULL) { fail(f, "out of memory setting %zu values", n_values); return FMU_ERROR; }
        for (i = 0; rc == FMU_OK && i < n_values; i++) {
            double w = values[i] != 0;
            if (type != ENG_BOOLEAN)
                rc = to_integer(f, type, vr[i], values[i], -2147483648.0, 2147483647.0, &w);
            buf[i] = (int)w;
        }
        if (rc == FMU_OK)
            rc = type == ENG_BOOLEAN
                     ? check(f, f->v2.set_boolean(f->instance, vr, n_vr, buf), "SetBoolean")
                     : check(f, f->v2.set_integer(f->instance, vr, n_vr, buf), "SetInteger");
        if (buf != small) free(buf);
        return rc;
    }
    switch (type) {
    case ENG_FLOAT64:
        return check(f, f->v3.set_float64(f->instance, vr, n_vr, values, n_values), "SetFloat64");
    case ENG_FLOAT32: {
        fmi3Float32 small[64], *buf;
        REQUIRE(f, f->v3.set_float32, "SetFloat32");
        buf = n_values <= 64 ? small : malloc(n_values * sizeof *buf);
        if (buf == NULL) { fail(f, "out of memory setting %zu values", n_values); return FMU_ERROR; }
        for (i = 0; i < n_values; i++) buf[i] = (fmi3Float32)values[i];
        rc = check(f, f->v3.set_float32(f->instance, vr, n_vr, buf, n_values), "SetFloat32");
        if (buf != small) free(buf);
        return rc;
    }
    case ENG_INT8: SET3(fmi3Int8, set_int8, "SetInt8", -128.0, 127.0); break;
    case ENG_UINT8: SET3(fmi3UInt8, set_uint8, "SetUInt8", 0.0, 255.0); break;
    case ENG_INT16: SET3(fmi3Int16, set_int16, "SetInt16", -32768.0, 32767.0); break;
    case ENG_UINT16: SET3(fmi3UInt16, set_uint16, "SetUInt16", 0.0, 65535.0); break;
    case ENG_INT32: SET3(fmi3Int32, set_int32, "SetInt32", -2147483648.0, 2147483647.0); break;
    case ENG_UINT32: SET3(fmi3UInt32, set_uint32, "SetUInt32", 0.0, 4294967295.0); break;
    case ENG_INT64: case ENG_ENUMERATION:
        SET3(fmi3Int64, set_int64, "SetInt64", -EXACT_LIMIT, EXACT_LIMIT); break;
    case ENG_UINT64: SET3(fmi3UInt64, set_uint64, "SetUInt64", 0.0, EXACT_LIMIT); break;
    case ENG_BOOLEAN: {
        fmi3Boolean small[64], *buf;
        REQUIRE(f, f->v3.set_boolean, "SetBoolean");
        buf = n_values <= 64 ? small : malloc(n_values * sizeof *buf);
        if (buf == NULL) { fail(f, "out of memory setting %zu values", n_values); return FMU_ERROR; }
        for (i = 0; i < n_values; i++) buf[i] = values[i] != 0;
        rc = check(f, f->v3.set_boolean(f->instance, vr, n_vr, buf, n_values), "SetBoolean");
        if (buf != small) free(buf);
        return rc;
    }
    default:
        fail(f, "cannot set %s values from numbers", fmu_type_name(type));
        return FMU_ERROR;
    }
    return rc;
}

int fmu_set_element(fmu_t *f, int type, uint32_t vr, size_t size, size_t element, double value) {
    array_shadow *a;
    if (element >= size) {
        fail(f, "element %zu of an array of %zu (value reference %u) does not exist", element + 1,
             size, vr);
        return FMU_ERROR;
    }
    for (a = f->shadows; a && !(a->vr == vr && a->size == size); a = a->next) {}
    if (a == NULL) {
        /* the other elements start at 0 until set: the engine sets every element of an
           array it sets (start values or couplings of the whole array) */
        a = calloc(1, sizeof *a + size * sizeof(double));
        if (a == NULL) { fail(f, "out of memory for an array of %zu", size); return FMU_ERROR; }
        a->vr = vr;
        a->size = size;
        a->next = f->shadows;
        f->shadows = a;
    }
    a->values[element] = value;
    return fmu_set_typed(f, type, &vr, 1, a->values, size);
}

int fmu_get_string(fmu_t *f, uint32_t vr, const char **value) {
    *value = NULL;
    if (f->fmi_version == 2) {
        fmi2String s = NULL;
        REQUIRE(f, f->v2.get_string, "GetString");
        if (check(f, f->v2.get_string(f->instance, &vr, 1, &s), "GetString")) return FMU_ERROR;
        *value = s ? s : "";
        return FMU_OK;
    } else {
        fmi3String s = NULL;
        REQUIRE(f, f->v3.get_string, "GetString");
        if (check(f, f->v3.get_string(f->instance, &vr, 1, &s, 1), "GetString")) return FMU_ERROR;
        *value = s ? s : "";
        return FMU_OK;
    }
}

int fmu_set_strings(fmu_t *f, const uint32_t *vr, size_t n, const char *const *values) {
    if (n == 0) return FMU_OK;
    if (f->fmi_version == 2) {
        REQUIRE(f, f->v2.set_string, "SetString");
        return check(f, f->v2.set_string(f->instance, vr, n, (const fmi2String *)values),
                     "SetString");
    }
    REQUIRE(f, f->v3.set_string, "SetString");
    return check(f, f->v3.set_string(f->instance, vr, n, (const fmi3String *)values, n),
                 "SetString");
}

void fmu_complain(fmu_t *f, const char *format, ...) {
    char text[MESSAGE_LEN];
    va_list args;
    va_start(args, format);
    vsnprintf(text, sizeof text, format, args);
    va_end(args);
    fail(f, "%s", text);
}

/* --- Model Exchange ---------------------------------------------------------------- */

int fmu_set_time(fmu_t *f, double time) {
    if (f->fmi_version == 2) return check(f, f->v2.set_time(f->instance, time), "SetTime");
    return check(f, f->v3.set_time(f->instance, time), "SetTime");
}

int fmu_set_continuous_states(fmu_t *f, const double *x, size_t n) {
    if (n == 0) return FMU_OK;
    if (f->fmi_version == 2)
        return check(f, f->v2.set_continuous_states(f->instance, x, n), "SetContinuousStates");
    return check(f, f->v3.set_continuous_states(f->instance, x, n), "SetContinuousStates");
}

int fmu_get_continuous_states(fmu_t *f, double *x, size_t n) {
    if (n == 0) return FMU_OK;
    if (f->fmi_version == 2)
        return check(f, f->v2.get_continuous_states(f->instance, x, n), "GetContinuousStates");
    return check(f, f->v3.get_continuous_states(f->instance, x, n), "GetContinuousStates");
}

int fmu_get_derivatives(fmu_t *f, double *dx, size_t n) {
    if (n == 0) return FMU_OK;
    if (f->fmi_version == 2)
        return check(f, f->v2.get_derivatives(f->instance, dx, n), "GetDerivatives");
    return check(f, f->v3.get_derivatives(f->instance, dx, n), "GetContinuousStateDerivatives");
}

int fmu_get_event_indicators(fmu_t *f, double *z, size_t n) {
    if (n == 0) return FMU_OK;
    if (f->fmi_version == 2)
        return check(f, f->v2.get_event_indicators(f->instance, z, n), "GetEventIndicators");
    return check(f, f->v3.get_event_indicators(f->instance, z, n), "GetEventIndicators");
}

int fmu_can_evaluate_at(const fmu_t *f) {
    return f->fmi_version == 3 && f->kind == FMU_MODEL_EXCHANGE && f->v3.evaluate_at != NULL;
}

int fmu_evaluate_at(fmu_t *f, double t, const double *x, size_t n, double *dx, double *z,
                    size_t nz) {
    /* where it fails, the FMU has said why; the caller makes the separate calls, so the
       failure is reported where the engine reports each of them */
    if (f->v3.evaluate_at(f->instance, t, x, n, dx, z, nz) > fmi3Warning) return FMU_ERROR;
    f->message_is_error = 0; /* as check() after a call that succeeded */
    return FMU_OK;
}

int fmu_evaluate_off(const fmu_t *f, fmu_off *off) {
    if (!fmu_can_evaluate_at(f) || f->v3.evaluate_off == NULL) return 0;
    off->fn = f->v3.evaluate_off;
    off->instance = f->instance;
    return 1;
}

int fmu_get_nominals(fmu_t *f, double *nominals, size_t n) {
    size_t i;
    if (n == 0) return FMU_OK;
    if (f->fmi_version == 2 ? f->v2.get_nominals == NULL : f->v3.get_nominals == NULL) {
        for (i = 0; i < n; i++) nominals[i] = 1.0;  /* the FMI default */
        return FMU_OK;
    }
    if (f->fmi_version == 2)
        return check(f, f->v2.get_nominals(f->instance, nominals, n),
                     "GetNominalsOfContinuousStates");
    return check(f, f->v3.get_nominals(f->instance, nominals, n), "GetNominalsOfContinuousStates");
}

int fmu_enter_event_mode(fmu_t *f) {
    if (f->fmi_version == 2) return check(f, f->v2.enter_event_mode(f->instance), "EnterEventMode");
    return check(f, f->v3.enter_event_mode(f->instance), "EnterEventMode");
}

int fmu_update_discrete_states(fmu_t *f, fmu_event_info *info) {
    memset(info, 0, sizeof *info);
    if (f->fmi_version == 2) {
        fmi2EventInfo e;
        memset(&e, 0, sizeof e);
        if (check(f, f->v2.new_discrete_states(f->instance, &e), "NewDiscreteStates"))
            return FMU_ERROR;
        info->needs_more = e.newDiscreteStatesNeeded;
        info->terminate = e.terminateSimulation;
        info->nominals_changed = e.nominalsOfContinuousStatesChanged;
        info->values_changed = e.valuesOfContinuousStatesChanged;
        info->next_time_defined = e.nextEventTimeDefined;
        info->next_time = e.nextEventTime;
        return FMU_OK;
    } else {
        fmi3Boolean more = 0, term = 0, nom = 0, val = 0, next = 0;
        fmi3Float64 t_next = 0;
        if (check(f, f->v3.update_discrete_states(f->instance, &more, &term, &nom, &val, &next,
                                                  &t_next),
                  "UpdateDiscreteStates"))
            return FMU_ERROR;
        info->needs_more = more;
        info->terminate = term;
        info->nominals_changed = nom;
        info->values_changed = val;
        info->next_time_defined = next;
        info->next_time = t_next;
        return FMU_OK;
    }
}

int fmu_enter_continuous_time_mode(fmu_t *f) {
    if (f->fmi_version == 2)
        return check(f, f->v2.enter_continuous_time_mode(f->instance), "EnterContinuousTimeMode");
    return check(f, f->v3.enter_continuous_time_mode(f->instance), "EnterContinuousTimeMode");
}

int fmu_completed_integrator_step(fmu_t *f, int no_set_state_prior, int *enter_event_mode,
                                  int *terminate) {
    if (f->fmi_version == 2) {
        fmi2Boolean event = 0, term = 0;
        int rc = check(f, f->v2.completed_integrator_step(f->instance, no_set_state_prior, &event,
                                                          &term),
                       "CompletedIntegratorStep");
        *enter_event_mode = event;
        *terminate = term;
        return rc;
    } else {
        fmi3Boolean event = 0, term = 0;
        int rc = check(f, f->v3.completed_integrator_step(f->instance, no_set_state_prior, &event,
                                                          &term),
                       "CompletedIntegratorStep");
        *enter_event_mode = event;
        *terminate = term;
        return rc;
    }
}

/* --- Co-Simulation ------------------------------------------------------------ */

/* FMI 2 reports a cut step through status queries, not through doStep's arguments. */
static void fmi2_step_status(fmu_t *f, double t, double h, fmu_step_result *r) {
    fmi2Boolean terminated = fmi2False;
    fmi2Real last = t + h;
    if (f->v2.get_boolean_status &&
        f->v2.get_boolean_status(f->instance, fmi2Terminated, &terminated) <= fmi2Warning)
        r->terminate = terminated;
    if (f->v2.get_real_status &&
        f->v2.get_real_status(f->instance, fmi2LastSuccessfulTime, &last) <= fmi2Warning)
        r->last_time = last;
}

int fmu_do_step(fmu_t *f, double t, double h, int no_set_state_prior, fmu_step_result *r) {
    int rc;
    memset(r, 0, sizeof *r);
    r->last_time = t + h;
    if (f->fmi_version == 2) {
        rc = check(f, f->v2.do_step(f->instance, t, h, no_set_state_prior), "DoStep");
        if (rc == FMU_DISCARD) fmi2_step_status(f, t, h, r);
        return rc;
    } else {
        fmi3Boolean event_needed = 0, term = 0, early = 0;
        fmi3Float64 last = t + h;
        rc = check(f, f->v3.do_step(f->instance, t, h, no_set_state_prior, &event_needed, &term,
                                    &early, &last),
                   "DoStep");
        r->terminate = term;
        r->early_return = early;
        r->last_time = last;
        return rc;
    }
}

/* --- FMU state and derivatives ------------------------------------------------- */

int fmu_can_get_set_state(const fmu_t *f) { return f->can_get_set_state; }
int fmu_provides_directional_derivative(const fmu_t *f) {
    return f->provides_directional_derivative;
}

int fmu_get_state(fmu_t *f, void **state) {
    if (f->fmi_version == 2) {
        REQUIRE(f, f->v2.get_state, "GetFMUstate");
        return check(f, f->v2.get_state(f->instance, (fmi2FMUstate *)state), "GetFMUstate");
    }
    REQUIRE(f, f->v3.get_state, "GetFMUState");
    return check(f, f->v3.get_state(f->instance, (fmi3FMUState *)state), "GetFMUState");
}

int fmu_set_state(fmu_t *f, void *state) {
    if (f->fmi_version == 2) {
        REQUIRE(f, f->v2.set_state, "SetFMUstate");
        return check(f, f->v2.set_state(f->instance, state), "SetFMUstate");
    }
    REQUIRE(f, f->v3.set_state, "SetFMUState");
    return check(f, f->v3.set_state(f->instance, state), "SetFMUState");
}

int fmu_free_state(fmu_t *f, void **state) {
    if (*state == NULL) return FMU_OK;
    if (f->fmi_version == 2) {
        REQUIRE(f, f->v2.free_state, "FreeFMUstate");
        return check(f, f->v2.free_state(f->instance, (fmi2FMUstate *)state), "FreeFMUstate");
    }
    REQUIRE(f, f->v3.free_state, "FreeFMUState");
    return check(f, f->v3.free_state(f->instance, (fmi3FMUState *)state), "FreeFMUState");
}

int fmu_directional_derivative(fmu_t *f, const uint32_t *unknowns, size_t n_unknowns,
                               const uint32_t *knowns, size_t n_knowns, const double *seed,
                               double *sensitivity) {
    if (f->fmi_version == 2) {
        REQUIRE(f, f->v2.directional_derivative, "GetDirectionalDerivative");
        return check(f, f->v2.directional_derivative(f->instance, unknowns, n_unknowns, knowns,
                                                     n_knowns, seed, sensitivity),
                     "GetDirectionalDerivative");
    }
    REQUIRE(f, f->v3.directional_derivative, "GetDirectionalDerivative");
    return check(f, f->v3.directional_derivative(f->instance, unknowns, n_unknowns, knowns,
                                                 n_knowns, seed, n_knowns, sensitivity,
                                                 n_unknowns),
                 "GetDirectionalDerivative");
}
