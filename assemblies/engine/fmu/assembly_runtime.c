/*
 * assembly_runtime.c: the core behind the shared FMI adapters (fmus/runtime/fmi2.c,
 * fmi3.c) for an FMU that is a whole assembly. Where a component's FMU integrates its
 * generated model, this one runs one of the engine's masters over the
 * member FMUs it carries in resources/, one communication step per doStep.
 *
 * Members that are Co-Simulation FMUs are co-simulated (cosim.c); members that are all
 * Model Exchange FMUs join the engine's one integrator (me.c), which then runs from one
 * communication point to the next; resources/assembly.txt says which.
 *
 * Its inputs are the members' unconnected inputs, its outputs the members' outputs
 * chosen at export (value reference 0 is time); both are forwarded to the member, which
 * checks values and units itself, and whose messages come back through this FMU's
 * logger. An assembly of Model Exchange members is also a Model Exchange FMU: the
 * importer integrates the members' stacked states, and an event it signals runs the
 * engine's event iteration through the couplings. FMU state and derivatives are refused
 * with a message saying why, as the modelDescription's capability flags promise.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "assembly_config.h"
#include "instances.h"
#include "runtime.h"

/* The adapters hand &MF_MODEL to mf_create. An assembly has no generated model: its
   description is read from resources/ at instantiation, so this one only names it. */
const mf_model MF_MODEL = {"assembly", "", 0, 0, 0, 0, 0, 0, 0, 0, NULL, NULL, NULL,
                           {NULL, NULL}, {NULL, NULL}, {NULL, NULL}, {NULL, NULL},
                           {NULL, NULL}, {NULL, NULL}, -1, NULL, {NULL, NULL}, 0, NULL, 0};

const char *const mf_log_categories[MF_N_LOG_CATEGORIES] = {
    "logEvents", "logStatusWarning", "logStatusError", "logSolver"};

enum { INSTANTIATED, INITIALIZATION, STEPPING, EVENT_MODE, CONTINUOUS, TERMINATED, FAILED };

static const char *const phase_names[] = {"Instantiated state", "Initialization Mode",
                                          "Step Mode", "Event Mode", "Continuous-Time Mode",
                                          "Terminated state",
                                          "error state (after a failed call)"};

struct mf_instance {
    char *name;
    mf_host host;
    int logging_on;
    int phase;
    mf_interface iface;   /* Model Exchange: the importer integrates the members' states */
    int event_pending;    /* Event Mode entered: the next update runs the event iteration */
    double *z;            /* event indicators, for reading them as variables (FMI 3) */
    double start_time;
    int stop_defined;     /* the importer's stop time, past which no doStep goes */
    double stop_time;
    char resources[4096];
    asm_config cfg;
    eng_cosim *cosim;     /* the master, by cfg.mode */
    eng_me *me;
};

/* --- the master, whichever mode it runs ------------------------------------------- */

static int create_master(mf_instance *A)
{
    if (A->cfg.mode == ASM_ME) return (A->me = eng_me_create(&A->cfg.me_spec)) ? 0 : -1;
    return (A->cosim = eng_cosim_create(&A->cfg.spec)) ? 0 : -1;
}

static void free_master(mf_instance *A)
{
    eng_me_free(A->me);
    eng_cosim_free(A->cosim); /* both terminate the members that still run */
    A->me = NULL;
    A->cosim = NULL;
}

static int master_failed(const mf_instance *A)
{
    return A->me ? eng_me_failed(A->me) : eng_cosim_failed(A->cosim);
}

static const char *master_message(const mf_instance *A)
{
    return A->me ? eng_me_message(A->me) : eng_cosim_message(A->cosim);
}

static int enter_initialization(mf_instance *A, double t0)
{
    return A->me ? eng_me_enter_initialization(A->me, t0)
                 : eng_cosim_enter_initialization(A->cosim, t0);
}

static int exit_initialization(mf_instance *A)
{
    return A->me ? eng_me_exit_initialization(A->me) : eng_cosim_exit_initialization(A->cosim);
}

static int advance(mf_instance *A, double target)
{
    return A->me ? eng_me_advance(A->me, target) : eng_cosim_advance(A->cosim, target);
}

static double master_time(const mf_instance *A)
{
    return A->me ? eng_me_time(A->me) : eng_cosim_time(A->cosim);
}

static int has_terminated(const mf_instance *A)
{
    return A->me ? eng_me_terminated(A->me) : eng_cosim_terminated(A->cosim);
}

static fmu_t *member_of(mf_instance *A, int i)
{
    return A->me ? eng_me_member(A->me, i) : eng_cosim_member(A->cosim, i);
}

static void say(mf_instance *A, mf_status status, const char *category, const char *fmt, ...)
{
    char message[2048];
    va_list ap;
    if (!A->host.callback) return;
    if (status == MF_OK && !A->logging_on) return;
    va_start(ap, fmt);
    vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
    A->host.dispatch(A->host.callback, A->host.environment, A->name, status, category, message);
}

#define ERROR(A, ...) (say((A), MF_ERROR, "logStatusError", __VA_ARGS__), MF_ERROR)

static int allowed(mf_instance *A, const char *fn, int phase_a, int phase_b)
{
    if (A->phase == phase_a || A->phase == phase_b) return 1;
    say(A, MF_ERROR, "logStatusError", "%s: not allowed in the %s", fn, phase_names[A->phase]);
    return 0;
}

/* The engine failed: its one-line message (naming the member) goes to the importer,
   and the FMU accepts nothing but freeing (or reset) from now on. */
static mf_status engine_failed(mf_instance *A, const char *fn)
{
    A->phase = FAILED;
    return ERROR(A, "%s: %s", fn, master_message(A));
}

/* "file:///a/b%20c/resources/" or "/a/b c/resources/" -> "/a/b c/resources" */
static int resource_folder(const char *location, char *out, size_t len)
{
    size_t n = 0;
    if (!location || !*location) return -1;
    if (strncmp(location, "file://", 7) == 0) {
        location += 7;
        if (strncmp(location, "localhost/", 10) == 0) location += 9;
    } else if (strncmp(location, "file:", 5) == 0) {
        location += 5;
    }
    for (; *location && n + 1 < len; location++) {
        unsigned int code;
        if (*location == '%' && sscanf(location + 1, "%2x", &code) == 1) {
            out[n++] = (char)code;
            location += 2;
        } else {
            out[n++] = *location;
        }
    }
    out[n] = '\0';
    while (n > 1 && out[n - 1] == '/') out[--n] = '\0';
    return 0;
}

static const asm_port *port(mf_instance *A, const char *fn, uint32_t vr)
{
    int k;
    for (k = 0; k < A->cfg.n_ports; k++)
        if (A->cfg.ports[k].vr == vr) return &A->cfg.ports[k];
    say(A, MF_ERROR, "logStatusError", "%s: no variable has value reference %u (time is 0, "
        "the assembly's inputs and outputs 1 to %d)", fn, vr, A->cfg.n_ports);
    return NULL;
}

/* --- life cycle -------------------------------------------------------------- */

mf_instance *mf_create(const mf_model *model, const char *fn, const char *instance_name,
                       const char *token, const char *resource_location, mf_interface iface,
                       int logging_on, int event_mode_used, const mf_host *host)
{
    mf_instance *A = (mf_instance *)calloc(1, sizeof *A);
    char err[1024];
    (void)model;
    if (!A) return NULL;
    A->host = *host;
    A->logging_on = logging_on;
    A->name = (char *)malloc(strlen(instance_name ? instance_name : "") + 1);
    if (!A->name) {
        free(A);
        return NULL;
    }
    strcpy(A->name, instance_name ? instance_name : "");
    A->iface = iface;
    if (iface == MF_CO_SIMULATION && event_mode_used) {
        say(A, MF_ERROR, "logStatusError", "%s: this FMU's Co-Simulation has no event mode (its "
            "members' events are handled inside doStep)", fn);
        mf_free(A);
        return NULL;
    }
    if (resource_folder(resource_location, A->resources, sizeof A->resources)) {
        say(A, MF_ERROR, "logStatusError", "%s: no resource location given: the assembly's "
            "members are in the FMU's resources/ folder", fn);
        mf_free(A);
        return NULL;
    }
    if (asm_config_read(&A->cfg, A->resources, err, sizeof err)) {
        say(A, MF_ERROR, "logStatusError", "%s: %s", fn, err);
        mf_free(A);
        return NULL;
    }
    if (iface == MF_MODEL_EXCHANGE && A->cfg.mode != ASM_ME) {
        say(A, MF_ERROR, "logStatusError", "%s: this assembly FMU is Co-Simulation only: its "
            "members are co-simulated", fn);
        mf_free(A);
        return NULL;
    }
    if (!token || strcmp(token, A->cfg.token) != 0) {
        say(A, MF_ERROR, "logStatusError", "%s: instantiation token '%s' does not match this "
            "FMU's '%s'", fn, token ? token : "(null)", A->cfg.token);
        mf_free(A);
        return NULL;
    }
    if (create_master(A) || master_failed(A)) { /* out of memory, or a member did not load */
        say(A, MF_ERROR, "logStatusError", "%s: %s", fn,
            A->me || A->cosim ? master_message(A) : "out of memory");
        mf_free(A);
        return NULL;
    }
    if (A->me && !(A->z = (double *)calloc((size_t)eng_me_number_of_indicators(A->me) + 1,
                                            sizeof(double)))) {
        mf_free(A);
        return NULL;
    }
    A->phase = INSTANTIATED;
    return A;
}

void mf_free(mf_instance *A)
{
    if (!A) return;
    free_master(A);
    asm_config_free(&A->cfg);
    free(A->z);
    free(A->name);
    free(A);
}

mf_status mf_set_debug_logging(mf_instance *A, const char *fn, int logging_on,
                               size_t n_categories, const char *const categories[])
{
    (void)fn; (void)n_categories; (void)categories;
    if (!A) return MF_ERROR;
    A->logging_on = logging_on;
    return MF_OK;
}

mf_status mf_setup_experiment(mf_instance *A, const char *fn, int tolerance_defined,
                              double tolerance, double start_time, int stop_time_defined,
                              double stop_time)
{
    if (!A || !allowed(A, fn, INSTANTIATED, INSTANTIATED)) return MF_ERROR;
    /* the members' tolerances were chosen at export, so a valid one is not used; an
       invalid one is refused as a component FMU refuses it (runtime.c) */
    if (tolerance_defined && !mf_tolerance_ok(tolerance))
        return ERROR(A, MF_TOLERANCE_REFUSED, fn, tolerance);
    if (!isfinite(start_time))
        return ERROR(A, "%s: start time %g is not finite", fn, start_time);
    if (stop_time_defined && !(isfinite(stop_time) && stop_time >= start_time))
        return ERROR(A, "%s: stop time %g must be finite and not before the start time %g", fn,
                     stop_time, start_time);
    A->start_time = start_time;
    A->stop_defined = stop_time_defined != 0;
    A->stop_time = stop_time_defined ? stop_time : 0.0;
    return MF_OK;
}

mf_status mf_enter_initialization_mode(mf_instance *A, const char *fn)
{
    if (!A || !allowed(A, fn, INSTANTIATED, INSTANTIATED)) return MF_ERROR;
    if (enter_initialization(A, A->start_time)) return engine_failed(A, fn);
    A->phase = INITIALIZATION;
    return MF_OK;
}

mf_status mf_exit_initialization_mode(mf_instance *A, const char *fn)
{
    if (!A || !allowed(A, fn, INITIALIZATION, INITIALIZATION)) return MF_ERROR;
    if (exit_initialization(A)) return engine_failed(A, fn);
    /* Model Exchange leaves initialization in Event Mode (both FMI versions); the
       engine has already settled the members' initial event */
    A->phase = A->iface == MF_MODEL_EXCHANGE ? EVENT_MODE : STEPPING;
    return MF_OK;
}

mf_status mf_terminate(mf_instance *A, const char *fn)
{
    if (!A || A->phase == INSTANTIATED || A->phase == TERMINATED)
        return A ? ERROR(A, "%s: not allowed in the %s", fn, phase_names[A->phase]) : MF_ERROR;
    A->phase = TERMINATED; /* the members terminate when they are freed */
    return MF_OK;
}

mf_status mf_reset(mf_instance *A, const char *fn)
{
    if (!A) return MF_ERROR;
    free_master(A);
    if (create_master(A) || master_failed(A)) {
        A->phase = FAILED;
        return ERROR(A, "%s: %s", fn, A->me || A->cosim ? master_message(A) : "out of memory");
    }
    A->start_time = 0.0;
    A->stop_defined = 0;
    A->event_pending = 0;
    A->phase = INSTANTIATED;
    return MF_OK;
}

mf_status mf_unsupported(mf_instance *A, const char *fn, const char *why)
{
    if (!A) return MF_ERROR;
    return ERROR(A, "%s: not supported by this FMU (%s)", fn, why);
}

/* --- variables ----------------------------------------------------------------- */

/* Reads or writes n variables, each through its member; `ints`: the values are int32_t
   (Int32 / Integer), else double. */
static mf_status access(mf_instance *A, const char *fn, const uint32_t vr[], size_t n_vr,
                        void *values, size_t n_values, int writing, int ints)
{
    size_t k;
    if (!A) return MF_ERROR;
    if (A->phase == FAILED || (writing && A->phase == TERMINATED))
        return ERROR(A, "%s: not allowed in the %s", fn, phase_names[A->phase]);
    if (n_values != n_vr) return ERROR(A, "%s: %zu values for %zu variables", fn, n_values, n_vr);
    if (n_vr > 0 && (!vr || !values)) return ERROR(A, "%s: NULL array for %zu values", fn, n_vr);
    for (k = 0; k < n_vr; k++) {
        double *f = ints ? NULL : (double *)values + k;
        int32_t *i = ints ? (int32_t *)values + k : NULL;
        const asm_port *p;
        fmu_t *member;
        double v;
        int rc, integrating;
        if (vr[k] == 0) {
            if (writing) return ERROR(A, "%s: time (value reference 0) is not settable", fn);
            if (ints) return ERROR(A, "%s: time is a %s, not an %s", fn, A->host.float_type,
                                   A->host.int_type);
            *f = master_time(A);
            continue;
        }
        if (!(p = port(A, fn, vr[k]))) return MF_ERROR;
        if ((p->member.type == ENG_INT32) != ints)
            return ERROR(A, "%s: value reference %u is not of type %s", fn, vr[k],
                         ints ? A->host.int_type : A->host.float_type);
        if (writing && p->kind != ASM_INPUT)
            return ERROR(A, "%s: value reference %u is not an input, not settable (states are "
                         "set through SetContinuousStates)", fn, vr[k]);
        /* once the importer integrates (Event and Continuous-Time Mode), what is read is
           computed at its time and states; before that, the members' own values */
        integrating = A->iface == MF_MODEL_EXCHANGE &&
                      (A->phase == EVENT_MODE || A->phase == CONTINUOUS);
        if (p->kind == ASM_INDICATOR) {
            /* FMI 3 lets fmi3Get{VariableType} read every variable in Step Mode (the
               Co-Simulation state machine, state Step Mode), indicators too: there they
               are the members' at the point the engine reached */
            if (!A->me || A->phase == INSTANTIATED || A->phase == INITIALIZATION)
                return ERROR(A, "%s: event indicators are read once initialization is done "
                             "(of an assembly of Model Exchange members), not in the %s", fn,
                             phase_names[A->phase]);
            /* the parser bounds it too; an index into z is checked where it is used */
            if (p->member.vr >= (uint32_t)eng_me_number_of_indicators(A->me))
                return ERROR(A, "%s: value reference %u names event indicator %u of %d", fn,
                             vr[k], p->member.vr, eng_me_number_of_indicators(A->me));
            if (eng_me_indicators(A->me, A->z)) return engine_failed(A, fn);
            *f = A->z[p->member.vr];
            continue;
        }
        if (!writing && integrating && eng_me_sync(A->me)) return engine_failed(A, fn);
        member = member_of(A, p->member.instance);
        if (writing) {
            v = ints ? (double)*i : *f;
            rc = eng_set_value(member, &p->member, v);
            /* the integrator must not carry a switched mode across the new value */
            if (rc == FMU_OK && A->me && A->phase == STEPPING) eng_me_inputs_changed(A->me);
            if (rc == FMU_OK && A->cosim && A->phase == STEPPING) eng_cosim_inputs_changed(A->cosim);
        } else {
            rc = eng_get_value(member, &p->member, &v);
            if (rc == FMU_OK) {
                if (ints) *i = (int32_t)v;
                else *f = v;
            }
        }
        if (rc != FMU_OK)
            return ERROR(A, "%s: member '%s': %s", fn,
                         A->cfg.instances[p->member.instance].instance_name, fmu_message(member));
    }
    return MF_OK;
}

mf_status mf_get_float(mf_instance *A, const char *fn, const uint32_t vr[], size_t n_vr,
                       double values[], size_t n_values)
{
    return access(A, fn, vr, n_vr, values, n_values, 0, 0);
}

mf_status mf_set_float(mf_instance *A, const char *fn, const uint32_t vr[], size_t n_vr,
                       const double values[], size_t n_values)
{
    return access(A, fn, vr, n_vr, (void *)values, n_values, 1, 0);
}

mf_status mf_get_int(mf_instance *A, const char *fn, const uint32_t vr[], size_t n_vr,
                     int32_t values[], size_t n_values)
{
    return access(A, fn, vr, n_vr, values, n_values, 0, 1);
}

mf_status mf_set_int(mf_instance *A, const char *fn, const uint32_t vr[], size_t n_vr,
                     const int32_t values[], size_t n_values)
{
    return access(A, fn, vr, n_vr, (void *)values, n_values, 1, 1);
}

/* --- Co-Simulation ---------------------------------------------------------------- */

mf_status mf_do_step(mf_instance *A, const char *fn, double t, double h, double *last_time,
                     int *terminate, int *early_return)
{
    double now;
    if (!A || !allowed(A, fn, STEPPING, STEPPING)) return MF_ERROR;
    now = master_time(A);
    if (early_return) *early_return = 0;
    if (terminate) *terminate = 0;
    if (last_time) *last_time = now;
    if (!(isfinite(h) && h > 0.0))
        return ERROR(A, "%s: communication step size %g must be finite and > 0", fn, h);
    if (!isfinite(t) || fabs(t - now) > 1e-9 * fmax(1.0, fabs(now)))
        return ERROR(A, "%s: currentCommunicationPoint %.17g is not the time reached, %.17g "
                     "(the assembly cannot go back: canGetAndSetFMUState is false)", fn, t, now);
    if (A->stop_defined && mf_past_stop(t + h, A->stop_time))
        return ERROR(A, MF_PAST_STOP, fn, t, h, t + h, A->stop_time);
    if (has_terminated(A)) {
        if (terminate) *terminate = 1;
        return ERROR(A, "%s: a member ended the simulation at t = %g", fn, now);
    }
    if (advance(A, t + h)) return engine_failed(A, fn);
    if (last_time) *last_time = master_time(A);
    if (has_terminated(A)) {
        if (terminate) *terminate = 1;
        say(A, MF_WARNING, "logStatusWarning", "%s: %s", fn, master_message(A));
    }
    return MF_OK;
}

mf_status mf_get_time(mf_instance *A, const char *fn, double *time)
{
    (void)fn;
    if (!A || !time) return MF_ERROR;
    *time = master_time(A);
    return MF_OK;
}

mf_status mf_get_terminated(mf_instance *A, const char *fn, int *terminated)
{
    (void)fn;
    if (!A || !terminated) return MF_ERROR;
    *terminated = has_terminated(A);
    return MF_OK;
}

/* --- what an assembly FMU does not offer ------------------------------------------ */

#define NO_STATE(A, fn) mf_unsupported((A), (fn), "canGetAndSetFMUState is false")

/* --- Model Exchange: the importer integrates the members' states ------------------ */

static int me_allowed(mf_instance *A, const char *fn, int phase_a, int phase_b)
{
    if (A->iface != MF_MODEL_EXCHANGE) {
        mf_unsupported(A, fn, "instantiated for Co-Simulation");
        return 0;
    }
    return allowed(A, fn, phase_a, phase_b);
}

static mf_status wrong_size(mf_instance *A, const char *fn, size_t n, int expected)
{
    return ERROR(A, "%s: %zu values for %d (the assembly's continuous states / event "
                 "indicators)", fn, n, expected);
}

mf_status mf_enter_event_mode(mf_instance *A, const char *fn)
{
    if (!A || !me_allowed(A, fn, CONTINUOUS, EVENT_MODE)) return MF_ERROR;
    A->event_pending = 1;
    A->phase = EVENT_MODE;
    return MF_OK;
}

mf_status mf_update_discrete_states(mf_instance *A, const char *fn, int *states_changed,
                                    int *terminate)
{
    int changed = 0;
    if (!A || !me_allowed(A, fn, EVENT_MODE, EVENT_MODE)) return MF_ERROR;
    if (A->event_pending) { /* the event iteration runs to its fixed point at once */
        if (eng_me_event_update(A->me, &changed)) return engine_failed(A, fn);
        A->event_pending = 0;
    }
    if (states_changed) *states_changed = changed;
    if (terminate) *terminate = eng_me_terminated(A->me);
    return MF_OK;
}

mf_status mf_enter_continuous_time_mode(mf_instance *A, const char *fn)
{
    if (!A || !me_allowed(A, fn, EVENT_MODE, EVENT_MODE)) return MF_ERROR;
    A->phase = CONTINUOUS;
    return MF_OK;
}

mf_status mf_completed_integrator_step(mf_instance *A, const char *fn)
{
    int enter = 0;
    if (!A || !me_allowed(A, fn, CONTINUOUS, CONTINUOUS)) return MF_ERROR;
    if (eng_me_completed_step(A->me, &enter)) return engine_failed(A, fn);
    return MF_OK;
}

mf_status mf_set_time(mf_instance *A, const char *fn, double time)
{
    if (!A || !me_allowed(A, fn, CONTINUOUS, EVENT_MODE)) return MF_ERROR;
    if (!isfinite(time)) return ERROR(A, "%s: time %g is not finite", fn, time);
    eng_me_set_time(A->me, time);
    return MF_OK;
}

mf_status mf_set_continuous_states(mf_instance *A, const char *fn, const double x[], size_t n)
{
    size_t i;
    if (!A || !me_allowed(A, fn, CONTINUOUS, CONTINUOUS)) return MF_ERROR;
    if (n != (size_t)eng_me_number_of_states(A->me))
        return wrong_size(A, fn, n, eng_me_number_of_states(A->me));
    for (i = 0; i < n; i++)
        if (!isfinite(x[i])) return ERROR(A, "%s: state %zu is %g, not finite", fn, i, x[i]);
    eng_me_set_states(A->me, x);
    return MF_OK;
}

mf_status mf_get_continuous_states(mf_instance *A, const char *fn, double x[], size_t n)
{
    if (!A || !me_allowed(A, fn, CONTINUOUS, EVENT_MODE)) return MF_ERROR;
    if (n != (size_t)eng_me_number_of_states(A->me))
        return wrong_size(A, fn, n, eng_me_number_of_states(A->me));
    eng_me_get_states(A->me, x);
    return MF_OK;
}

mf_status mf_get_derivatives(mf_instance *A, const char *fn, double dx[], size_t n)
{
    if (!A || !me_allowed(A, fn, CONTINUOUS, EVENT_MODE)) return MF_ERROR;
    if (n != (size_t)eng_me_number_of_states(A->me))
        return wrong_size(A, fn, n, eng_me_number_of_states(A->me));
    return eng_me_derivatives(A->me, dx) ? engine_failed(A, fn) : MF_OK;
}

mf_status mf_get_event_indicators(mf_instance *A, const char *fn, double z[], size_t n)
{
    if (!A || !me_allowed(A, fn, CONTINUOUS, EVENT_MODE)) return MF_ERROR;
    if (n != (size_t)eng_me_number_of_indicators(A->me))
        return wrong_size(A, fn, n, eng_me_number_of_indicators(A->me));
    return eng_me_indicators(A->me, z) ? engine_failed(A, fn) : MF_OK;
}

/* No shortcut through an assembly (runtime.h): fmi3.c's mfEvaluateAt makes the four calls,
   and mfEvaluateOff declines (its caller makes them) */
mf_status mf_evaluate_at(mf_instance *A, double t, const double x[], size_t n, double dx[],
                         double z[], size_t nz)
{
    (void)A, (void)t, (void)x, (void)n, (void)dx, (void)z, (void)nz;
    return MF_DISCARD;
}

mf_status mf_evaluate_off(mf_instance *A, double t, const double x[], double dx[], double z[])
{
    (void)A, (void)t, (void)x, (void)dx, (void)z;
    return MF_DISCARD;
}

mf_status mf_get_nominals(mf_instance *A, const char *fn, double nominals[], size_t n)
{
    if (!A || !me_allowed(A, fn, CONTINUOUS, EVENT_MODE)) return MF_ERROR;
    if (n != (size_t)eng_me_number_of_states(A->me))
        return wrong_size(A, fn, n, eng_me_number_of_states(A->me));
    eng_me_get_nominals(A->me, nominals);
    return MF_OK;
}

mf_status mf_get_number_of_states(mf_instance *A, const char *fn, size_t *n)
{
    (void)fn;
    if (!A || !n) return MF_ERROR;
    *n = A->me ? (size_t)eng_me_number_of_states(A->me) : 0;
    return MF_OK;
}

mf_status mf_get_number_of_event_indicators(mf_instance *A, const char *fn, size_t *n)
{
    (void)fn;
    if (!A || !n) return MF_ERROR;
    *n = A->me ? (size_t)eng_me_number_of_indicators(A->me) : 0;
    return MF_OK;
}

mf_status mf_enter_step_mode(mf_instance *A, const char *fn)
{
    return mf_unsupported(A, fn, "the FMU has no event mode");
}

mf_status mf_partial_derivatives(mf_instance *A, const char *fn, int adjoint,
                                 const uint32_t unknowns[], size_t n_unknowns,
                                 const uint32_t knowns[], size_t n_knowns, const double seed[],
                                 size_t n_seed, double sensitivity[], size_t n_sensitivity)
{
    (void)adjoint; (void)unknowns; (void)n_unknowns; (void)knowns; (void)n_knowns;
    (void)seed; (void)n_seed; (void)sensitivity; (void)n_sensitivity;
    return mf_unsupported(A, fn, "providesDirectionalDerivative is false");
}

mf_status mf_get_state(mf_instance *A, const char *fn, void **state)
{
    (void)state;
    return NO_STATE(A, fn);
}
mf_status mf_set_state(mf_instance *A, const char *fn, const void *state)
{
    (void)state;
    return NO_STATE(A, fn);
}
mf_status mf_free_state(mf_instance *A, const char *fn, void **state)
{
    (void)state;
    return NO_STATE(A, fn);
}
mf_status mf_serialized_state_size(mf_instance *A, const char *fn, const void *state,
                                   size_t *size)
{
    (void)state; (void)size;
    return NO_STATE(A, fn);
}
mf_status mf_serialize_state(mf_instance *A, const char *fn, const void *state,
                             unsigned char bytes[], size_t size)
{
    (void)state; (void)bytes; (void)size;
    return NO_STATE(A, fn);
}
mf_status mf_deserialize_state(mf_instance *A, const char *fn, const unsigned char bytes[],
                               size_t size, void **state)
{
    (void)bytes; (void)size; (void)state;
    return NO_STATE(A, fn);
}
