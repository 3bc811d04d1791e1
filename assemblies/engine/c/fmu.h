/*
 * fmu.h: the engine's one way to talk to an FMU, whatever its FMI version
 * (2.0 or 3.0) and interface (Model Exchange or Co-Simulation).
 *
 * The FMU must already be extracted (the Python side does that once); its
 * library binaries/<platform>/<modelIdentifier>.so is opened with dlopen and
 * the FMI functions are looked up by name, so any FMU works, not only ours.
 *
 * How to use it (every call returns FMU_OK = 0 or a negative code; never aborts):
 *
 *     char err[512];
 *     fmu_options o = {0};
 *     o.unzip_dir = "/tmp/x"; o.model_identifier = "SpringBlock";
 *     o.instantiation_token = "{...}"; o.instance_name = "block";
 *     o.fmi_version = 3; o.kind = FMU_CO_SIMULATION;
 *     o.can_get_set_state = 1;           // from modelDescription
 *     o.intermediate = my_cb; o.intermediate_ctx = me;   // FMI 3 CS only, optional
 *     fmu_t *f = fmu_load(&o, err, sizeof err);   // NULL: err says why
 *     fmu_set_float64(f, vr, n, values);          // parameters, start values
 *     fmu_enter_initialization(f, 1e-8, 0.0, 10.0);
 *     fmu_exit_initialization(f);
 *     fmu_step_result r;
 *     if (fmu_do_step(f, t, h, 1, &r) != FMU_OK) puts(fmu_message(f));
 *     fmu_free(f);                                // terminates if needed
 *
 * After any failure fmu_message(f) holds one line: the FMU's last logged message
 * (an error if there was one) or the loader's own reason ("fmi3DoStep returned
 * fmi3Error"). FMU_DISCARD is not an error: a CS step or a state/time the FMU
 * refuses; the caller decides (e.g. retry with a smaller step).
 *
 * Value references are uint32 for both versions (fmi2ValueReference is unsigned
 * int). Int32 maps to fmi2Integer in FMI 2. Model Exchange FMUs of both versions
 * are in event mode after fmu_exit_initialization (FMI 3's initial event mode,
 * FMI 2's event mode): the caller runs fmu_update_discrete_states until
 * needs_more is 0 and then fmu_enter_continuous_time_mode.
 */
#ifndef MECHFMU_ENGINE_FMU_H
#define MECHFMU_ENGINE_FMU_H

#include <stddef.h>
#include <stdint.h>

enum { FMU_OK = 0, FMU_DISCARD = -1, FMU_ERROR = -2 };

typedef enum { FMU_MODEL_EXCHANGE = 0, FMU_CO_SIMULATION = 1 } fmu_kind;

typedef struct fmu_t fmu_t;

/* FMI 3 Co-Simulation: called from inside fmu_do_step when the FMU reaches an
   intermediate point (ours: after each handled event). get_allowed: outputs may be
   read now with fmu_get_float64/int32 (this is how the engine records outputs at
   events inside a step). Return nonzero to ask the FMU to return early at `time`
   (honoured only if can_return_early and the FMU was loaded with
   early_return_allowed). */
typedef int (*fmu_intermediate_fn)(void *ctx, fmu_t *fmu, double time, int get_allowed,
                                   int step_finished, int can_return_early);

typedef struct {
    const char *unzip_dir;           /* folder the FMU was extracted into */
    const char *model_identifier;    /* modelIdentifier of the interface used */
    const char *instantiation_token; /* FMI 3 instantiationToken / FMI 2 guid */
    const char *instance_name;
    int fmi_version;                 /* 2 or 3 */
    fmu_kind kind;
    int n_states;                    /* Model Exchange: continuous states, event indicators */
    int n_event_indicators;
    int can_get_set_state;           /* capability flags from the model description */
    int provides_directional_derivative;
    int early_return_allowed;        /* FMI 3 CS: the FMU may end a step at an event */
    int logging_on;                  /* FMU debug logging (all categories) */
    fmu_intermediate_fn intermediate; /* FMI 3 CS, may be NULL */
    void *intermediate_ctx;
} fmu_options;

/* --- life cycle -------------------------------------------------------------- */

/* Opens the library and instantiates. NULL on failure, the reason in err. */
fmu_t *fmu_load(const fmu_options *options, char *err, size_t err_len);
/* Terminates (when initialized and not yet terminated), frees the instance, closes
   the library. NULL-safe. */
void fmu_free(fmu_t *fmu);
/* tolerance <= 0: none given; stop_time <= start_time: none given. */
int fmu_enter_initialization(fmu_t *fmu, double tolerance, double start_time, double stop_time);
/* Leaves initialization. Model Exchange (both versions): the FMU is then in event
   mode (see the header comment). */
int fmu_exit_initialization(fmu_t *fmu);
int fmu_terminate(fmu_t *fmu);

/* The last message: the FMU's last log line (preferring errors) or the loader's own. */
const char *fmu_message(const fmu_t *fmu);
const char *fmu_instance_name(const fmu_t *fmu);
int fmu_fmi_version(const fmu_t *fmu);
fmu_kind fmu_interface(const fmu_t *fmu);
int fmu_number_of_states(const fmu_t *fmu);
int fmu_number_of_event_indicators(const fmu_t *fmu);

/* --- variables (batched) ------------------------------------------------------ */

int fmu_get_float64(fmu_t *fmu, const uint32_t *vr, size_t n, double *values);
int fmu_set_float64(fmu_t *fmu, const uint32_t *vr, size_t n, const double *values);
int fmu_get_int32(fmu_t *fmu, const uint32_t *vr, size_t n, int32_t *values);
int fmu_set_int32(fmu_t *fmu, const uint32_t *vr, size_t n, const int32_t *values);

/* Values of any numeric type of engine.h (ENG_FLOAT64 ... ENG_ENUMERATION: `type`),
   through that type's FMI call, as doubles: n_vr value references holding n_values
   values (an FMI 3 array counts all its elements, row-major). A set rounds to the
   nearest integer for an integer type and fails for a value outside the type's range;
   a get of an Int64/UInt64/Enumeration beyond 2^53 fails (engine.h). */
int fmu_get_typed(fmu_t *fmu, int type, const uint32_t *vr, size_t n_vr, double *values,
                  size_t n_values);
int fmu_set_typed(fmu_t *fmu, int type, const uint32_t *vr, size_t n_vr, const double *values,
                  size_t n_values);
/* Element `element` of the array `vr` of `size` elements: the whole array is set, its
   other elements at the values this instance last set (0 before any). */
int fmu_set_element(fmu_t *fmu, int type, uint32_t vr, size_t size, size_t element,
                    double value);
/* One String; *value is the FMU's, valid until its next call. */
int fmu_get_string(fmu_t *fmu, uint32_t vr, const char **value);
int fmu_set_strings(fmu_t *fmu, const uint32_t *vr, size_t n, const char *const *values);
/* "Float64", "Int8"...: engine.h's type codes by their FMI names */
const char *fmu_type_name(int type);
/* Makes `format` the instance's message (fmu_message), unless an error of the FMU's own
   is kept: for failures the caller finds in values the FMU accepted. */
void fmu_complain(fmu_t *fmu, const char *format, ...);

/* --- Model Exchange -------------------------------------------------------------- */

typedef struct {
    int needs_more;        /* call fmu_update_discrete_states again (FMI 2: newDiscreteStatesNeeded) */
    int terminate;         /* the model asks to end the simulation */
    int nominals_changed;
    int values_changed;    /* continuous states were changed: re-read them */
    int next_time_defined; /* a time event is due at next_time */
    double next_time;
} fmu_event_info;

int fmu_set_time(fmu_t *fmu, double time);
int fmu_set_continuous_states(fmu_t *fmu, const double *x, size_t n);
int fmu_get_continuous_states(fmu_t *fmu, double *x, size_t n);
int fmu_get_derivatives(fmu_t *fmu, double *dx, size_t n);
int fmu_get_event_indicators(fmu_t *fmu, double *z, size_t n);
/* Whether fmu_evaluate_at can be called: an FMI 3 Model Exchange FMU built from our
   runtime (it exports mfEvaluateAt). */
int fmu_can_evaluate_at(const fmu_t *fmu);
/* Time and states set, then the derivatives (dx != NULL) and the indicators (z != NULL)
   read, in one call; FMU_OK, or nonzero where one of the separate calls would refuse or
   fail (the caller makes them: they say what failed, as without this call). */
int fmu_evaluate_at(fmu_t *fmu, double t, const double *x, size_t n, double *dx, double *z,
                    size_t nz);
/* mfEvaluateOff of an FMU built from our runtime (fmus/runtime/fmi3.c), for the
   integrator's trial points: the derivatives (dx != NULL) and indicators (z != NULL) at
   (t, x) without moving the instance there, straight into the FMU with nothing between.
   0, or nonzero where fmu_evaluate_at would decline (the caller takes that path, which
   says why). */
typedef int fmu_off_fn(void *instance, double t, const double *x, double *dx, double *z);
typedef struct {
    fmu_off_fn *fn;
    void *instance;
} fmu_off;
/* The instance's fmu_off; 0 where it has none (not ours, FMI 2, Co-Simulation) */
int fmu_evaluate_off(const fmu_t *fmu, fmu_off *off);
int fmu_get_nominals(fmu_t *fmu, double *nominals, size_t n);
int fmu_enter_event_mode(fmu_t *fmu);
int fmu_update_discrete_states(fmu_t *fmu, fmu_event_info *info);
int fmu_enter_continuous_time_mode(fmu_t *fmu);
int fmu_completed_integrator_step(fmu_t *fmu, int no_set_state_prior, int *enter_event_mode,
                                  int *terminate);

/* --- Co-Simulation ------------------------------------------------------------ */

typedef struct {
    int terminate;       /* the FMU asks to end the simulation */
    int early_return;    /* FMI 3: the step ended before t + h (at an event) */
    double last_time;    /* the time actually reached */
} fmu_step_result;

/* FMU_DISCARD: the FMU refused or cut the step (result->last_time says where it is,
   when the FMU can tell). */
int fmu_do_step(fmu_t *fmu, double t, double h, int no_set_state_prior,
                fmu_step_result *result);

/* --- FMU state and derivatives ------------------------------------------------- */

int fmu_can_get_set_state(const fmu_t *fmu);
/* *state NULL: a new snapshot is allocated; otherwise it is overwritten (FMI rules). */
int fmu_get_state(fmu_t *fmu, void **state);
int fmu_set_state(fmu_t *fmu, void *state);
int fmu_free_state(fmu_t *fmu, void **state);

int fmu_provides_directional_derivative(const fmu_t *fmu);
/* sensitivity[n_unknowns] = d unknowns / d knowns * seed[n_knowns] */
int fmu_directional_derivative(fmu_t *fmu, const uint32_t *unknowns, size_t n_unknowns,
                               const uint32_t *knowns, size_t n_knowns, const double *seed,
                               double *sensitivity);

#endif
