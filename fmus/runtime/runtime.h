/*
 * The FMI-version-independent core of every mechfmu FMU.
 *
 * All behaviour lives here: the state machine, value access rules, event
 * iteration, Model-Exchange primitives, the Co-Simulation step with its
 * embedded solver, and FMU-state snapshots. A version adapter (fmi2.c or
 * fmi3.c) only translates arguments and passes its own function name, used as
 * the prefix of every log message ("fmi3DoStep: ...").
 *
 * Every function is NULL-safe in the instance (returns MF_ERROR, logs nothing
 * since there is nowhere to log to).
 */
#ifndef MECHFMU_RUNTIME_H
#define MECHFMU_RUNTIME_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "model.h"

/* Same numbering as fmi3Status and the first five of fmi2Status. */
typedef enum { MF_OK = 0, MF_WARNING = 1, MF_DISCARD = 2, MF_ERROR = 3, MF_FATAL = 4 } mf_status;

typedef enum { MF_MODEL_EXCHANGE, MF_CO_SIMULATION } mf_interface;

/* The importer's logger, type-erased: each FMI version has its own callback
   signature, so the adapter supplies `dispatch` which casts `callback` back. */
typedef void (*mf_generic_fn)(void);
typedef void (*mf_log_dispatch)(mf_generic_fn callback, void *environment,
                                const char *instance_name, mf_status status,
                                const char *category, const char *message);

/* Tells the importer, from inside a Co-Simulation step, that an event was handled
   at time t and that outputs may be read now (FMI 3 intermediate update). */
typedef void (*mf_event_dispatch)(mf_generic_fn callback, void *environment, double t);

typedef struct {
    const char *float_type;  /* "Float64" / "Real", for messages */
    const char *int_type;    /* "Int32" / "Integer" */
    const char *token_name;  /* "instantiationToken" / "GUID", for messages */
    const char *reset_hint;  /* what to call to recover, e.g. "fmi3Reset or fmi3SetFMUState" */
    mf_log_dispatch dispatch;
    mf_generic_fn callback;  /* may be NULL: then nothing is logged */
    void *environment;
    mf_event_dispatch event_dispatch;  /* may be NULL (FMI 2 has no such callback) */
    mf_generic_fn event_callback;      /* may be NULL: then events are not reported */
    int early_return_allowed;          /* Co-Simulation may stop a step at its first event */
} mf_host;

typedef struct mf_instance mf_instance;

/* Log categories understood by mf_set_debug_logging. */
#define MF_N_LOG_CATEGORIES 4
extern const char *const mf_log_categories[MF_N_LOG_CATEGORIES];

/* --- life cycle -------------------------------------------------------- */

/* NULL (after logging why) if the token does not match the model or memory runs out.
   resource_location: as the importer gave it (an FMI 2 URI, an FMI 3 path, or NULL);
   a component's FMU has no resources, an assembly FMU's members live there. */
mf_instance *mf_create(const mf_model *model, const char *fn, const char *instance_name,
                       const char *token, const char *resource_location, mf_interface iface,
                       int logging_on, int event_mode_used, const mf_host *host);
void mf_free(mf_instance *inst);
mf_status mf_set_debug_logging(mf_instance *inst, const char *fn, int logging_on,
                               size_t n_categories, const char *const categories[]);
/* The experiment (relative tolerance of the embedded solver, start time, stop time) is
   set in the Instantiated state, before Initialization Mode: FMI 2 has its own call for
   it (fmi2SetupExperiment), FMI 3 passes it to fmi3EnterInitializationMode, whose
   adapter calls both. Not calling it keeps the defaults (1e-8, the start of time, no
   stop time). A defined stop time is the end of the simulation: both standards say
   an FMU returns an error when the importer tries to compute past it (fmi2SetupExperiment,
   fmi3EnterInitializationMode), so a doStep ending after it is refused. */
mf_status mf_setup_experiment(mf_instance *inst, const char *fn, int tolerance_defined,
                              double tolerance, double start_time, int stop_time_defined,
                              double stop_time);

/* The relative tolerances an FMU accepts: below about 50 ulp (1e-14) the embedded
   solvers' error test is failed by rounding alone and the step size collapses; above 1
   a relative tolerance bounds nothing. An assembly FMU checks the importer's the same,
   with the same message (printf arguments: the function's name, the tolerance). */
static inline int mf_tolerance_ok(double tolerance)
{
    return tolerance >= 1e-14 && tolerance <= 1.0;
}
#define MF_TOLERANCE_REFUSED                                                              \
    "%s: tolerance %g is outside the allowed range [1e-14, 1] (a relative tolerance below " \
    "1e-14 asks for more digits than double precision carries)"
/* Whether a step ending at t_end goes past a defined stop time: beyond 1e-9 of it
   (relative, absolute below 1). An importer's t + h rounds (t + (stop - t) need not be
   stop exactly), and fmpy takes a communication point within math.isclose's 1e-9 of
   the stop time for the stop time itself. */
static inline int mf_past_stop(double t_end, double stop)
{
    return t_end > stop + 1e-9 * fmax(1.0, fabs(stop));
}
/* Its message (printf arguments: the function's name, t, h, t + h, the stop time). */
#define MF_PAST_STOP                                                                       \
    "%s: the step from t = %.17g by %g ends at %.17g, past the stop time %.17g the "        \
    "importer defined at initialization; the FMU does not compute past it"
mf_status mf_enter_initialization_mode(mf_instance *inst, const char *fn);
mf_status mf_exit_initialization_mode(mf_instance *inst, const char *fn);
mf_status mf_terminate(mf_instance *inst, const char *fn);
mf_status mf_reset(mf_instance *inst, const char *fn);
/* Logs "<fn>: not supported by this FMU (<why>)" and returns MF_ERROR. */
mf_status mf_unsupported(mf_instance *inst, const char *fn, const char *why);

/* --- variables --------------------------------------------------------- */

mf_status mf_get_float(mf_instance *inst, const char *fn, const uint32_t vr[], size_t n_vr,
                       double values[], size_t n_values);
mf_status mf_set_float(mf_instance *inst, const char *fn, const uint32_t vr[], size_t n_vr,
                       const double values[], size_t n_values);
mf_status mf_get_int(mf_instance *inst, const char *fn, const uint32_t vr[], size_t n_vr,
                     int32_t values[], size_t n_values);
mf_status mf_set_int(mf_instance *inst, const char *fn, const uint32_t vr[], size_t n_vr,
                     const int32_t values[], size_t n_values);

/* --- events (Model Exchange, and Co-Simulation with event mode) ---------- */

mf_status mf_enter_event_mode(mf_instance *inst, const char *fn);
/* Runs event iteration to its fixed point; *states_changed: x was changed. */
mf_status mf_update_discrete_states(mf_instance *inst, const char *fn, int *states_changed,
                                    int *terminate);

/* --- Model Exchange ------------------------------------------------------ */

mf_status mf_enter_continuous_time_mode(mf_instance *inst, const char *fn);
mf_status mf_completed_integrator_step(mf_instance *inst, const char *fn);
mf_status mf_set_time(mf_instance *inst, const char *fn, double time);
mf_status mf_set_continuous_states(mf_instance *inst, const char *fn, const double x[], size_t n);
mf_status mf_get_continuous_states(mf_instance *inst, const char *fn, double x[], size_t n);
mf_status mf_get_derivatives(mf_instance *inst, const char *fn, double dx[], size_t n);
mf_status mf_get_event_indicators(mf_instance *inst, const char *fn, double z[], size_t n);
/* mf_set_time, mf_set_continuous_states, then mf_get_derivatives (dx != NULL) and
   mf_get_event_indicators (z != NULL) in one call, in the ordinary case only: MF_OK, or
   MF_DISCARD with nothing logged wherever one of them would refuse or fail (time and
   states may be set by then, as those calls would have set them), and always where a
   runtime has no such shortcut: the caller makes the four calls, which say why
   (fmi3.c's mfEvaluateAt). */
mf_status mf_evaluate_at(mf_instance *inst, double t, const double x[], size_t n, double dx[],
                         double z[], size_t nz);
/* The derivatives (dx != NULL) and indicators (z != NULL, as mf_get_event_indicators
   gives them) at (t, x) without moving the instance there: its time, states and what it
   computed at them are left as they were (fmi3.c's mfEvaluateOff). Model Exchange only,
   inputs as set. MF_OK, or MF_DISCARD with nothing logged wherever mf_evaluate_at would
   decline (then the caller takes the separate calls, which say why). */
mf_status mf_evaluate_off(mf_instance *inst, double t, const double x[], double dx[], double z[]);
mf_status mf_get_nominals(mf_instance *inst, const char *fn, double nominals[], size_t n);
mf_status mf_get_number_of_states(mf_instance *inst, const char *fn, size_t *n);
mf_status mf_get_number_of_event_indicators(mf_instance *inst, const char *fn, size_t *n);

/* --- Co-Simulation ------------------------------------------------------- */

mf_status mf_enter_step_mode(mf_instance *inst, const char *fn);
/* *last_time: the time actually reached (t + h on success, earlier when the model
   asked to terminate, which *terminate reports, or when the importer allowed early
   return and an event happened, which *early_return reports). */
mf_status mf_do_step(mf_instance *inst, const char *fn, double t, double h, double *last_time,
                     int *terminate, int *early_return);

/* Where the simulation stands: the time reached (after a step the model ended
   early, the time it ended at), and whether the model has ended the simulation.
   For FMI 2's status queries after fmi2DoStep returned fmi2Discard. */
mf_status mf_get_time(mf_instance *inst, const char *fn, double *time);
mf_status mf_get_terminated(mf_instance *inst, const char *fn, int *terminated);

/* --- partial derivatives ------------------------------------------------- */

/* Seed-weighted products of the Jacobian d unknowns / d knowns at the current point.
   Unknowns: state derivatives, computed variables (outputs, event indicators) and
   states; knowns: continuous states and inputs (anything else is refused with a log).
   adjoint = 0: sensitivity = J seed (nSeed = nKnowns, nSensitivity = nUnknowns);
   adjoint = 1: sensitivity = J^T seed (nSeed = nUnknowns, nSensitivity = nKnowns). */
mf_status mf_partial_derivatives(mf_instance *inst, const char *fn, int adjoint,
                                 const uint32_t unknowns[], size_t n_unknowns,
                                 const uint32_t knowns[], size_t n_knowns, const double seed[],
                                 size_t n_seed, double sensitivity[], size_t n_sensitivity);

/* --- FMU state ----------------------------------------------------------- */

mf_status mf_get_state(mf_instance *inst, const char *fn, void **state);
mf_status mf_set_state(mf_instance *inst, const char *fn, const void *state);
mf_status mf_free_state(mf_instance *inst, const char *fn, void **state);
mf_status mf_serialized_state_size(mf_instance *inst, const char *fn, const void *state,
                                   size_t *size);
mf_status mf_serialize_state(mf_instance *inst, const char *fn, const void *state,
                             unsigned char bytes[], size_t size);
mf_status mf_deserialize_state(mf_instance *inst, const char *fn, const unsigned char bytes[],
                               size_t size, void **state);

#endif
