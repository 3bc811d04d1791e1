/*
 * The mechfmu runtime core; see runtime.h for the division of labour.
 */
#include "runtime.h"
#include "events.h"
#include "solver.h"
#include "solver_implicit.h"
#include "stiffness.h"

#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_EVENT_ITERATIONS 100
#define MAX_STEPS_PER_DO_STEP 10000000L
/* internal steps between two projections of how many more a doStep needs */
#define PROGRESS_WINDOW 10000L
#define DEFAULT_TOLERANCE 1e-8
/* interior points of each internal step at which the event indicators are sampled, so
   that an indicator crossing twice inside one step (a slip shorter than the step)
   is still seen */
#define EVENT_SUBSAMPLES 4

/* Phases as bits so that each function states where it is allowed with one mask. */
enum {
    PH_INSTANTIATED = 1 << 0,
    PH_INIT = 1 << 1,
    PH_EVENT = 1 << 2,
    PH_CONT = 1 << 3,
    PH_STEP = 1 << 4,
    PH_TERMINATED = 1 << 5,
    PH_ANY = 0x3f
};

enum { LOG_EVENTS = 1 << 0, LOG_WARNING = 1 << 1, LOG_ERROR = 1 << 2, LOG_SOLVER = 1 << 3 };

const char *const mf_log_categories[MF_N_LOG_CATEGORIES] = {
    "logEvents", "logStatusWarning", "logStatusError", "logSolver"};

struct mf_instance {
    const mf_model *m;
    char *name;
    mf_host host;
    mf_interface iface;
    unsigned log_mask;

    int phase;
    /* an event iteration or the solver failed: the model state is not one the
       simulation can go on from, so only inspection and recovery are allowed */
    int failed;
    int terminate_reported; /* the model's terminate message was logged */
    /* the FMU states this instance made that the importer has not freed: freeing the
       instance frees them ("all the allocated memory", FMI 2 and 3 FreeInstance) */
    struct snapshot *states;

    double t;
    double t_start;
    double rtol;
    int stop_defined;
    double t_stop;

    double *x, *q, *p;
    double *u;      /* inputs as the importer set them, valid at t_u */
    double t_u;     /* base time of the Co-Simulation input extrapolation */
    int inputs_changed;

    /* cached model results at the current point, invalid after any change */
    double *y, *xdot, *z;
    int y_valid, xdot_valid, z_valid;

    double *z_prev; /* indicators just after the last accepted point / event */
    double *z_shift; /* what an importer reads for an indicator that is exactly 0: set
                        at each event restart, 0 for those not at zero there */
    int event_changed; /* the last event iteration changed a state or a mode */

    /* the Taylor chains of the inputs (plan_chains): chains_len ints, the first
       chains_read of them for the inputs the model reads; and 1 / k for k = 0 ... n_u */
    int *chains, chains_len, chains_read;
    double *inv_order;
    /* ue holds the inputs at ue_t from the base ue_tu while ue_gen is u_gen, which every
       write to u moves on (inputs_moved) */
    unsigned long u_gen, ue_gen;
    double ue_t, ue_tu;

    /* scratch */
    double *ue, *x_new, *q_new, *x_tmp, *z_hit, *z_work, *g;
    double *dd; /* the (n_x + n_y) x (n_x + n_u) Jacobian of mf_dd, dense; its structural
                   zeros stay as calloc left them */
    double *dd_nz; /* what mf_dd returns: the nonzeros, by the model's dd_sparsity */
    /* the point dd was evaluated at (t, x, q, u, p) and whether it was: an importer that
       builds a Jacobian column by column (one seed per call, as FMI asks) gets all its
       columns from one evaluation of dd, not one each (n evaluations of an n x n matrix
       per Jacobian: 9,798 Jacobians of the beam at N = 64 in the engine took most of a
       minute). A comparison of the point, not invalidation by every setter: the point
       is all dd reads, so the cache cannot go stale. */
    double *dd_at;
    int dd_fresh;
    const double **arg;
    double **res;
    mf_int *iw;
    double *w;

    mf_dopri solver;  /* DOPRI5, explicit */
    mf_ros ros;       /* RODAS3, implicit */
    int method;       /* the `solver` parameter: which of them Co-Simulation uses */
    mf_stiffness stiff; /* the automatic choice (method MF_METHOD_AUTO) */
    int dense_implicit; /* the last accepted step, whose dense output is valid, was RODAS3's */
};

/* ------------------------------------------------------------------------ */
/* logging                                                                   */

static void emit(const mf_host *host, const char *name, mf_status status, const char *category,
                 const char *fmt, va_list ap)
{
    char buf[1024];
    if (!host || !host->callback || !host->dispatch) return;
    vsnprintf(buf, sizeof buf, fmt, ap);
    host->dispatch(host->callback, host->environment, name ? name : "", status, category, buf);
}

#if defined(__GNUC__)
#define PRINTF_LIKE(a, b) __attribute__((format(printf, a, b)))
/* an error path: out of line, so that the checks before it inline into their callers */
#define MF_COLD __attribute__((cold, noinline))
#else
#define PRINTF_LIKE(a, b)
#define MF_COLD
#endif

static void log_error(const mf_instance *I, const char *fmt, ...) PRINTF_LIKE(2, 3);
static void log_info(const mf_instance *I, unsigned cat, const char *fmt, ...) PRINTF_LIKE(3, 4);
static void log_always(const mf_instance *I, const char *fmt, ...) PRINTF_LIKE(2, 3);

/* a warning the importer must see whatever the logging settings (why a run ends) */
static void log_always(const mf_instance *I, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    emit(&I->host, I->name, MF_WARNING, "logStatusWarning", fmt, ap);
    va_end(ap);
}

/* errors are always reported, whatever the logging settings */
static void log_error(const mf_instance *I, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    emit(&I->host, I->name, MF_ERROR, "logStatusError", fmt, ap);
    va_end(ap);
}

static void log_info(const mf_instance *I, unsigned cat, const char *fmt, ...)
{
    va_list ap;
    int i;
    if (!(I->log_mask & cat)) return;
    for (i = 0; i < MF_N_LOG_CATEGORIES; i++)
        if (cat == (1u << i)) break;
    va_start(ap, fmt);
    emit(&I->host, I->name, MF_OK, mf_log_categories[i < MF_N_LOG_CATEGORIES ? i : 0], fmt, ap);
    va_end(ap);
}

static const char *phase_name(int phase)
{
    switch (phase) {
    case PH_INSTANTIATED: return "Instantiated state";
    case PH_INIT: return "Initialization Mode";
    case PH_EVENT: return "Event Mode";
    case PH_CONT: return "Continuous-Time Mode";
    case PH_STEP: return "Step Mode";
    case PH_TERMINATED: return "Terminated state";
    default: return "unknown state";
    }
}

/* progress: the call advances the simulation, which a failed instance must not */
static int allowed(const mf_instance *I, const char *fn, int mask, int progress)
{
    if (!(I->phase & mask)) {
        log_error(I, "%s: not allowed in %s", fn, phase_name(I->phase));
        return 0;
    }
    if (progress && I->failed) {
        log_error(I, "%s: not allowed after an earlier failure of the simulation; call %s", fn,
                  I->host.reset_hint ? I->host.reset_hint : "Reset");
        return 0;
    }
    return 1;
}

static MF_COLD int null_array(const mf_instance *I, const char *fn, const char *what)
{
    log_error(I, "%s: argument '%s' is NULL", fn, what);
    return 0;
}

static int array_ok(const mf_instance *I, const char *fn, const void *a, size_t n,
                    const char *what)
{
    return n == 0 || a ? 1 : null_array(I, fn, what);
}

static int size_ok(const mf_instance *I, const char *fn, size_t got, int expected,
                   const char *what)
{
    if (got != (size_t)expected) {
        log_error(I, "%s: %s is %lu but this model has %d", fn, what, (unsigned long)got,
                  expected);
        return 0;
    }
    return 1;
}

/* name of the variable of a kind and index, for messages */
static const char *name_of(const mf_instance *I, mf_kind kind, int index)
{
    int i;
    for (i = 0; i < I->m->n_variables; i++)
        if (I->m->variables[i].kind == kind && I->m->variables[i].index == index)
            return I->m->variables[i].name;
    return "?";
}

/* ------------------------------------------------------------------------ */
/* model evaluation                                                          */

static void invalidate(mf_instance *I) { I->y_valid = I->xdot_valid = I->z_valid = 0; }

/* x or the right-hand side jumped: each solver's stored f(t, x) is stale (both,
   so that a later change of method never starts from a stale slope) */
static void solvers_restart(mf_instance *I)
{
    mf_dopri_restart(&I->solver);
    mf_ros_restart(&I->ros);
}

static void solvers_reset(mf_instance *I)
{
    mf_dopri_reset(&I->solver);
    mf_ros_reset(&I->ros);
    mf_stiffness_reset(&I->stiff, I->method == MF_METHOD_IMPLICIT);
    I->dense_implicit = I->method == MF_METHOD_IMPLICIT;
}

/* How many links input i's Taylor chain has (i -> d1 -> ... -> d_links); -1 for a
   chain that comes back on itself. */
static int chain_links(const mf_model *m, int i)
{
    int links = 0, d = m->input_derivative[i];
    for (; d >= 0; d = m->input_derivative[d])
        if (++links >= m->n_u) return -1;
    return links;
}

/* u was written: what inputs_at extrapolated from it is stale. */
static void inputs_moved(mf_instance *I) { I->u_gen++; }

/* ue = u run along the chains of the plan from c to end (plan_chains) to t, each in
   Horner's form; the inputs outside them as they are. */
static void extrapolate(const mf_instance *I, double t, const int *c, const int *end)
{
    const double *u = I->u, *inv = I->inv_order;
    const double tau = t - I->t_u;
    memcpy(I->ue, u, (size_t)I->m->n_u * sizeof(double));
    while (c < end) {
        const int i = c[0], *d = c + 2; /* d[0 .. links - 1]: the chain after i */
        int links = c[1], k;
        double acc;
        c += 2 + links;
        /* a zero tail adds nothing, also where a huge step makes tau^n / n! infinite
           (0 * inf would be NaN) */
        while (links > 0 && u[d[links - 1]] == 0.0) links--;
        if (links == 0) continue;
        acc = u[d[links - 1]]; /* sum_k u_dk tau^k / k!, from the highest term down */
        for (k = links - 1; k >= 1; k--) acc = u[d[k - 1]] + acc * tau * inv[k + 1];
        I->ue[i] = u[i] + acc * tau;
    }
}

/* Inputs at time t. Co-Simulation extrapolates each input by its Taylor chain
   (s -> v -> a) from the base time t_u, into ue; Model Exchange uses them as set, with
   no copy (the masters of joined models read and set values tens of times per
   right-hand side). Only the chains of the inputs the model reads are run: this runs
   at every right-hand side of every step, and a friction block's 20 inputs with their
   rate chains, term by term, made it a sixth of a co-simulation's time. */
static const double *inputs_at(mf_instance *I, double t)
{
    if (I->iface != MF_CO_SIMULATION || t == I->t_u || I->chains_read == 0) return I->u;
    /* the solver's last stage, the outputs and the indicators all ask at a step's end */
    if (I->ue_gen == I->u_gen && I->ue_t == t && I->ue_tu == I->t_u) return I->ue;
    extrapolate(I, t, I->chains, I->chains + I->chains_read);
    I->ue_gen = I->u_gen;
    I->ue_t = t;
    I->ue_tu = I->t_u;
    return I->ue;
}

/* Every input, read or not, moved along its chain to now, the new base of the
   extrapolation: a rate input no equation reads still carries its own chain on (f_rate
   by f_rate2) for the steps that follow. */
static void rebase_inputs(mf_instance *I)
{
    if (I->chains_len > 0) {
        extrapolate(I, I->t, I->chains, I->chains + I->chains_len);
        memcpy(I->u, I->ue, (size_t)I->m->n_u * sizeof(double));
    }
    I->t_u = I->t;
    inputs_moved(I);
}

/* The chains extrapolate runs: [i, links, d1 ... d_links] for each input that has a
   derivative input (model_defect has ruled out cycles), those the model reads first
   (chains_read ints of chains_len), and 1 / k for the Taylor terms. 0, or -1 out of
   memory. */
static int plan_chains(mf_instance *I)
{
    const mf_model *m = I->m;
    size_t len = 0;
    int i, k, pass, *c;
    if (!m->input_derivative || m->n_u == 0) return 0;
    for (i = 0; i < m->n_u; i++)
        if (m->input_derivative[i] >= 0) len += 2 + (size_t)chain_links(m, i);
    if (len == 0) return 0;
    if (len > (size_t)INT_MAX) return -1; /* (chains of a million inputs each) */
    I->chains = c = (int *)malloc(len * sizeof(int));
    I->inv_order = (double *)malloc((size_t)(m->n_u + 1) * sizeof(double));
    if (!c || !I->inv_order) return -1;
    for (k = 1; k <= m->n_u; k++) I->inv_order[k] = 1.0 / k;
    I->inv_order[0] = 0.0;
    for (pass = 1; pass >= 0; pass--) { /* the read ones, then the others */
        for (i = 0; i < m->n_u; i++) {
            int d;
            if (m->input_derivative[i] < 0 || (!m->input_read || m->input_read[i]) != pass)
                continue;
            *c++ = i;
            *c++ = chain_links(m, i);
            for (d = m->input_derivative[i]; d >= 0; d = m->input_derivative[d]) *c++ = d;
        }
        if (pass == 1) I->chains_read = (int)(c - I->chains);
    }
    I->chains_len = (int)len;
    return 0;
}

static int call(mf_instance *I, const mf_function *f, double t, const double *x, const double *q,
                const double *u, double *r0, double *r1)
{
    double tt = t;
    if (!f->eval) return 0; /* only for functions without outputs (checked at create) */
    I->arg[0] = &tt;
    I->arg[1] = x;
    I->arg[2] = q;
    I->arg[3] = u;
    I->arg[4] = I->p;
    I->res[0] = r0;
    I->res[1] = r1;
    return f->eval(I->arg, I->res, I->iw, I->w, 0);
}

static int all_finite(const double *v, int n)
{
    int i;
    for (i = 0; i < n; i++) if (!isfinite(v[i])) return 0;
    return 1;
}

/* The derivatives at the current point, unless known: 1, or 0 (nothing logged) where
   the evaluation fails */
static int eval_xdot(mf_instance *I)
{
    if (I->xdot_valid) return 1;
    if (call(I, &I->m->ode, I->t, I->x, I->q, inputs_at(I, I->t), I->xdot, NULL)) return 0;
    I->xdot_valid = 1;
    return 1;
}

static int update_xdot(mf_instance *I, const char *fn)
{
    if (eval_xdot(I)) return 1;
    log_error(I, "%s: evaluation of the state derivatives failed at t = %.17g", fn, I->t);
    return 0;
}

static int update_y(mf_instance *I, const char *fn)
{
    if (I->y_valid) return 1;
    if (call(I, &I->m->out, I->t, I->x, I->q, inputs_at(I, I->t), I->y, NULL)) {
        log_error(I, "%s: evaluation of the outputs failed at t = %.17g", fn, I->t);
        return 0;
    }
    /* a non-finite output is refused where it is read (mf_get_float) or produced
       (mf_do_step), with its name */
    I->y_valid = 1;
    return 1;
}

/* The indicators at the current point, unless known: 0, else 1 where the evaluation
   fails and 2 where an indicator is not finite (nothing logged) */
static int eval_z(mf_instance *I)
{
    if (I->z_valid) return 0;
    if (call(I, &I->m->zc, I->t, I->x, I->q, inputs_at(I, I->t), I->z, NULL)) return 1;
    if (!all_finite(I->z, I->m->n_z)) return 2;
    I->z_valid = 1;
    return 0;
}

static int update_z(mf_instance *I, const char *fn)
{
    int i, why = eval_z(I);
    if (why == 0) return 1;
    if (why == 1) {
        log_error(I, "%s: evaluation of the event indicators failed at t = %.17g", fn, I->t);
        return 0;
    }
    /* no crossing can be decided from a NaN, and a read must not report one as OK */
    for (i = 0; i < I->m->n_z && isfinite(I->z[i]); i++) {}
    log_error(I, "%s: event indicator %d is not finite (%g) at t = %.17g", fn, i + 1, I->z[i],
              I->t);
    return 0;
}

static int crossed(double before, double after) { return mf_crossed(before, after); }

/* The indicators a first-order step ahead of the current point, along the derivatives,
   into z_work: 1, or 0 where the model cannot be evaluated there. */
static int look_ahead(mf_instance *I)
{
    const mf_model *m = I->m;
    const double dt = 1.4901161193847656e-08 * fmax(1.0, fabs(I->t)); /* sqrt(eps) */
    int j;
    if (!I->xdot_valid) {
        if (call(I, &m->ode, I->t, I->x, I->q, inputs_at(I, I->t), I->xdot, NULL) ||
            !all_finite(I->xdot, m->n_x))
            return 0;
        I->xdot_valid = 1;
    }
    for (j = 0; j < m->n_x; j++) I->x_tmp[j] = I->x[j] + dt * I->xdot[j];
    if (call(I, &m->zc, I->t + dt, I->x_tmp, I->q, inputs_at(I, I->t + dt), I->z_work, NULL))
        return 0;
    return all_finite(I->z_work, m->n_z);
}

/* The side on which an importer reads each indicator that is exactly 0 at an event
   restart (MF_INDICATOR_SHIFT, events.h). After an event that changed nothing it has
   only touched zero: the side it came from, its kept reference, so that the importer
   still sees it go across later, as this runtime does. After a change it starts afresh
   from zero (a slide starting from rest): the side it leaves to, as this runtime's own
   crossing test takes it (mf_locate_event), here from a look ahead along the
   derivatives; the positive side where that look ahead stays at zero too. Our engine
   knows the shift and takes it for the zero it stands for (mf_at_zero). */
static void restart_shifts(mf_instance *I, int changed)
{
    const mf_model *m = I->m;
    int i, probed = -1;
    for (i = 0; i < m->n_z; i++) {
        double side = 0.0;
        I->z_shift[i] = 0.0;
        if (I->z[i] != 0.0) continue;
        if (!changed && I->z_prev[i] != 0.0) {
            side = I->z_prev[i];
        } else {
            if (probed < 0) probed = look_ahead(I);
            if (probed) side = I->z_work[i];
        }
        I->z_shift[i] = side < 0.0 ? -MF_INDICATOR_SHIFT : MF_INDICATOR_SHIFT;
    }
}

/* The indicators as an importer reads them: an exact 0 on the side of its restart. */
static void shifted(const mf_instance *I, double *z)
{
    int i;
    for (i = 0; i < I->m->n_z; i++)
        if (z[i] == 0.0) z[i] = I->z_shift[i];
}

/* Applies `jump` until nothing changes, then takes the indicators at the new
   state as the reference for crossing detection (they may jump at events). */
static mf_status event_iteration(mf_instance *I, const char *fn, int *x_changed)
{
    const mf_model *m = I->m;
    int it, i, changed_x = 0, changed_q = 0;

    for (it = 0; it < MAX_EVENT_ITERATIONS; it++) {
        int same = 1;
        if (call(I, &m->jump, I->t, I->x, I->q, inputs_at(I, I->t), I->x_new, I->q_new)) {
            log_error(I, "%s: evaluation of the event function failed at t = %.17g", fn, I->t);
            return MF_ERROR;
        }
        for (i = 0; i < m->n_x; i++) {
            if (!isfinite(I->x_new[i])) {
                log_error(I, "%s: the event at t = %.17g set state '%s' to a non-finite value",
                          fn, I->t, name_of(I, MF_STATE, i));
                return MF_ERROR;
            }
            if (I->x_new[i] != I->x[i]) { same = 0; changed_x = 1; }
        }
        for (i = 0; i < m->n_q; i++) {
            if (!isfinite(I->q_new[i])) {
                log_error(I, "%s: the event at t = %.17g set '%s' to a non-finite value", fn,
                          I->t, name_of(I, MF_DISCRETE, i));
                return MF_ERROR;
            }
            if (I->q_new[i] != I->q[i]) { same = 0; changed_q = 1; }
        }
        if (same) break;
        if (m->n_x) memcpy(I->x, I->x_new, (size_t)m->n_x * sizeof(double));
        if (m->n_q) memcpy(I->q, I->q_new, (size_t)m->n_q * sizeof(double));
        invalidate(I);
    }
    if (it == MAX_EVENT_ITERATIONS) {
        log_error(I, "%s: event iteration did not converge at t = %.17g (still changing after %d "
                     "iterations)", fn, I->t, MAX_EVENT_ITERATIONS);
        return MF_ERROR;
    }
    if (changed_x || changed_q) {
        log_info(I, LOG_EVENTS, "%s: event at t = %.17g (%d iteration%s; %s%s%s changed)", fn,
                 I->t, it, it == 1 ? "" : "s", changed_q ? "discrete states" : "",
                 changed_q && changed_x ? " and " : "", changed_x ? "continuous states" : "");
        for (i = 0; i < m->n_q && (I->log_mask & LOG_EVENTS); i++)
            log_info(I, LOG_EVENTS, "%s:   %s = %.17g", fn, name_of(I, MF_DISCRETE, i), I->q[i]);
    }
    if (x_changed) *x_changed = changed_x;
    I->event_changed = changed_x || changed_q;
    if (!update_z(I, fn)) return MF_ERROR;
    for (i = 0; i < m->n_z; i++) {
        /* An indicator sitting exactly on zero after an event that changed
           nothing has touched zero without going across (the model's mode
           conditions are typically strict): keep its old sign, so that it still
           triggers once it really goes across. After a real state change a
           zero is a fresh start (e.g. a velocity reset to 0) and must not. */
        if (I->z[i] == 0.0 && !changed_x && !changed_q) continue;
        I->z_prev[i] = I->z[i];
    }
    restart_shifts(I, changed_x || changed_q);
    return MF_OK;
}

/* ------------------------------------------------------------------------ */
/* life cycle                                                                */

static void set_start_values(mf_instance *I)
{
    const mf_model *m = I->m;
    int i;
    for (i = 0; i < m->n_variables; i++) {
        const mf_variable *v = &m->variables[i];
        switch (v->kind) {
        case MF_TIME: I->t = v->start; break;
        case MF_PARAMETER: I->p[v->index] = v->start; break;
        case MF_STATE: I->x[v->index] = v->start; break;
        case MF_INPUT: I->u[v->index] = v->start; inputs_moved(I); break;
        case MF_DISCRETE: I->q[v->index] = v->start; break;
        case MF_RUNTIME: I->method = (int)v->start; break;
        default: break;
        }
    }
    I->t_start = I->t;
    I->t_u = I->t;
    I->rtol = DEFAULT_TOLERANCE;
    I->inputs_changed = 0;
    I->failed = 0;
    I->terminate_reported = 0;
    I->phase = PH_INSTANTIATED;
    I->stop_defined = 0;
    I->t_stop = 0.0;
    if (m->n_z) memset(I->z_prev, 0, (size_t)m->n_z * sizeof(double));
    if (m->n_z) memset(I->z_shift, 0, (size_t)m->n_z * sizeof(double));
    invalidate(I);
    solvers_reset(I);
}

static int kind_size(const mf_model *m, mf_kind kind)
{
    switch (kind) {
    case MF_TIME: return 1;
    case MF_PARAMETER: return m->n_p;
    case MF_STATE: case MF_DERIVATIVE: return m->n_x;
    case MF_INPUT: return m->n_u;
    case MF_COMPUTED: return m->n_y;
    case MF_DISCRETE: return m->n_q;
    case MF_RUNTIME: return 1; /* index 0: solver */
    default: return -1;
    }
}

/* Catches generator bugs once, so that no later access can go out of bounds. */
static const char *model_defect(const mf_model *m)
{
    int i;
    const mf_function *fs[7];
    int n_out[7];
    if (m->n_x < 0 || m->n_q < 0 || m->n_u < 0 || m->n_p < 0 || m->n_y < 0 || m->n_z < 0 ||
        m->n_c < 0)
        return "negative size";
    if (m->n_variables < 1 || !m->variables || m->variables[0].kind != MF_TIME)
        return "the variable table must start with time (value reference 0)";
    for (i = 0; i < m->n_variables; i++) {
        const mf_variable *v = &m->variables[i];
        int n = kind_size(m, v->kind);
        if (!v->name || n < 0 || v->index < 0 || v->index >= n)
            return "a variable's kind or index is out of range";
    }
    if (m->n_u > 0 && m->input_derivative) {
        for (i = 0; i < m->n_u; i++)
            if (m->input_derivative[i] < -1 || m->input_derivative[i] >= m->n_u)
                return "input_derivative out of range";
        for (i = 0; i < m->n_u; i++) /* a chain visits each input at most once */
            if (chain_links(m, i) < 0) return "input_derivative has a cycle";
    }
    if (m->n_c > 0 && !m->constraints) return "constraints missing";
    fs[0] = &m->ode; n_out[0] = m->n_x;
    fs[1] = &m->out; n_out[1] = m->n_y;
    fs[2] = &m->zc; n_out[2] = m->n_z;
    fs[3] = &m->jump; n_out[3] = m->n_x + m->n_q;
    fs[4] = &m->check; n_out[4] = m->n_c;
    fs[5] = &m->jac; n_out[5] = m->n_x;
    fs[6] = &m->dd; n_out[6] = (m->n_x + m->n_y) * (m->n_x + m->n_u);
    if (m->dd.eval) {
        const mf_int *sp = m->dd_sparsity ? m->dd_sparsity(0) : NULL;
        if (!sp || sp[0] != m->n_x + m->n_y || sp[1] != m->n_x + m->n_u)
            return "the directional-derivative Jacobian's pattern is missing or of another size";
    }
    for (i = 0; i < 7; i++) {
        if (n_out[i] > 0 && !fs[i]->eval) return "a model function with outputs is missing";
        if (fs[i]->eval && !fs[i]->work) return "a model function has no work-size function";
    }
    return NULL;
}

static double *dvec(int n) { return (double *)calloc((size_t)(n > 0 ? n : 1), sizeof(double)); }

/* dd's pattern (model.h dd_sparsity): CasADi writes a dense one as (rows, cols, 1), and
   a sparse one's column starts begin with 0 */
static int dd_dense(const mf_int *sp) { return sp[2] == 1; }

static int dd_nonzeros(const mf_model *m)
{
    const mf_int *sp;
    if (!m->dd_sparsity) return 0;
    sp = m->dd_sparsity(0);
    return (int)(dd_dense(sp) ? sp[0] * sp[1] : sp[2 + sp[1]]);
}

/* dd's nonzeros into the dense matrix, at their places by the pattern */
static void dd_scatter(mf_instance *I)
{
    const mf_int *sp = I->m->dd_sparsity(0), *colind = sp + 2, *row = sp + 3 + sp[1];
    const size_t rows = (size_t)sp[0];
    mf_int c, k;
    if (dd_dense(sp)) {
        memcpy(I->dd, I->dd_nz, rows * (size_t)sp[1] * sizeof(double));
        return;
    }
    for (c = 0; c < sp[1]; c++)
        for (k = colind[c]; k < colind[c + 1]; k++)
            I->dd[(size_t)row[k] + (size_t)c * rows] = I->dd_nz[k];
}

mf_instance *mf_create(const mf_model *model, const char *fn, const char *instance_name,
                       const char *token, const char *resource_location, mf_interface iface,
                       int logging_on, int event_mode_used, const mf_host *host)
{
    mf_instance tmp, *I;
    const char *defect;
    const mf_function *fs[7];
    mf_int sz_arg = 5, sz_res = 2, sz_iw = 0, sz_w = 0;
    int i;

    (void)resource_location; /* a component's FMU carries no resources */
    /* a stack stand-in, so that failures before allocation can be logged alike */
    memset(&tmp, 0, sizeof tmp);
    if (host) tmp.host = *host;
    tmp.name = (char *)(instance_name ? instance_name : "");

    if (!model) {
        log_error(&tmp, "%s: no model", fn);
        return NULL;
    }
    if (!token || strcmp(token, model->instantiation_token) != 0) {
        log_error(&tmp, "%s: %s '%s' does not match this FMU's '%s' (the "
                        "modelDescription.xml and the binary come from different builds)",
                  fn, tmp.host.token_name ? tmp.host.token_name : "instantiation token",
                  token ? token : "(null)", model->instantiation_token);
        return NULL;
    }
    if (iface == MF_CO_SIMULATION && event_mode_used) {
        log_error(&tmp, "%s: eventModeUsed = true is refused: this FMU declares hasEventMode = "
                        "false in its modelDescription.xml (its doStep handles every event "
                        "itself); instantiate it with eventModeUsed = false", fn);
        return NULL;
    }
    defect = model_defect(model);
    if (defect) {
        log_error(&tmp, "%s: the compiled model '%s' is inconsistent: %s", fn, model->model_name,
                  defect);
        return NULL;
    }

    I = (mf_instance *)calloc(1, sizeof *I);
    if (!I) goto oom;
    I->m = model;
    if (host) I->host = *host;
    I->iface = iface;
    I->log_mask = logging_on ? ~0u : 0u;
    I->name = (char *)malloc(strlen(tmp.name) + 1);
    if (!I->name) goto oom;
    strcpy(I->name, tmp.name);

    I->x = dvec(model->n_x);
    I->q = dvec(model->n_q);
    I->p = dvec(model->n_p);
    I->u = dvec(model->n_u);
    I->y = dvec(model->n_y);
    I->xdot = dvec(model->n_x);
    I->z = dvec(model->n_z);
    I->z_prev = dvec(model->n_z);
    I->z_shift = dvec(model->n_z);
    I->ue = dvec(model->n_u);
    I->x_new = dvec(model->n_x);
    I->q_new = dvec(model->n_q);
    I->x_tmp = dvec(model->n_x);
    I->z_work = dvec((int)MF_LOCATE_WORK(model->n_z, EVENT_SUBSAMPLES));
    I->z_hit = dvec(model->n_z);
    I->g = dvec(model->n_c);
    I->dd = dvec((model->n_x + model->n_y) * (model->n_x + model->n_u));
    I->dd_nz = dvec(dd_nonzeros(model));
    I->dd_at = dvec(1 + model->n_x + model->n_q + model->n_u + model->n_p);
    if (!I->x || !I->q || !I->p || !I->u || !I->y || !I->xdot || !I->z || !I->z_prev ||
        !I->z_shift || !I->ue ||
        !I->x_new || !I->q_new || !I->x_tmp || !I->z_work || !I->z_hit || !I->g || !I->dd ||
        !I->dd_nz || !I->dd_at)
        goto oom;

    /* one set of work buffers, large enough for every model function */
    fs[0] = &model->ode; fs[1] = &model->out; fs[2] = &model->zc;
    fs[3] = &model->jump; fs[4] = &model->check; fs[5] = &model->jac;
    fs[6] = &model->dd;
    for (i = 0; i < 7; i++) {
        mf_int a = 0, r = 0, iw = 0, w = 0;
        if (!fs[i]->eval) continue;
        if (fs[i]->work(&a, &r, &iw, &w)) {
            log_error(&tmp, "%s: the model's work-size query failed", fn);
            mf_free(I);
            return NULL;
        }
        if (a > sz_arg) sz_arg = a;
        if (r > sz_res) sz_res = r;
        if (iw > sz_iw) sz_iw = iw;
        if (w > sz_w) sz_w = w;
    }
    I->arg = (const double **)calloc((size_t)sz_arg, sizeof(double *));
    I->res = (double **)calloc((size_t)sz_res, sizeof(double *));
    I->iw = (mf_int *)calloc((size_t)(sz_iw > 0 ? sz_iw : 1), sizeof(mf_int));
    I->w = (double *)calloc((size_t)(sz_w > 0 ? sz_w : 1), sizeof(double));
    if (!I->arg || !I->res || !I->iw || !I->w) goto oom;
    if (mf_dopri_alloc(&I->solver, model->n_x)) goto oom;
    if (mf_ros_alloc(&I->ros, model->n_x)) goto oom;
    if (plan_chains(I)) goto oom;
    I->ue_t = NAN; /* nothing extrapolated yet */

    set_start_values(I);
    return I;

oom:
    log_error(&tmp, "%s: out of memory", fn);
    mf_free(I);
    return NULL;
}

static void snap_release(struct snapshot *s);

void mf_free(mf_instance *I)
{
    if (!I) return;
    while (I->states) snap_release(I->states);
    mf_dopri_free(&I->solver);
    mf_ros_free(&I->ros);
    free(I->name);
    free(I->x); free(I->q); free(I->p); free(I->u); free(I->y); free(I->xdot); free(I->z);
    free(I->chains); free(I->inv_order);
    free(I->z_prev); free(I->z_shift); free(I->ue); free(I->x_new); free(I->q_new); free(I->x_tmp);
    free(I->z_work); free(I->z_hit); free(I->g); free(I->dd); free(I->dd_nz); free(I->dd_at);
    free((void *)I->arg); free(I->res); free(I->iw); free(I->w);
    free(I);
}

mf_status mf_set_debug_logging(mf_instance *I, const char *fn, int logging_on,
                               size_t n_categories, const char *const categories[])
{
    size_t k;
    unsigned mask = 0;
    if (!I) return MF_ERROR;
    if (!array_ok(I, fn, categories, n_categories, "categories")) return MF_ERROR;
    if (n_categories == 0) {
        I->log_mask = logging_on ? ~0u : 0u;
        return MF_OK;
    }
    for (k = 0; k < n_categories; k++) {
        int i;
        for (i = 0; i < MF_N_LOG_CATEGORIES; i++)
            if (categories[k] && strcmp(categories[k], mf_log_categories[i]) == 0) break;
        if (i == MF_N_LOG_CATEGORIES) {
            log_error(I, "%s: unknown log category '%s' (known: logEvents, logStatusWarning, "
                         "logStatusError, logSolver)", fn, categories[k] ? categories[k] : "(null)");
            return MF_ERROR;
        }
        mask |= 1u << i;
    }
    if (logging_on) I->log_mask |= mask;
    else I->log_mask &= ~mask;
    return MF_OK;
}

mf_status mf_unsupported(mf_instance *I, const char *fn, const char *what)
{
    if (!I) return MF_ERROR;
    log_error(I, "%s: not supported by this FMU (%s)", fn, what);
    return MF_ERROR;
}

mf_status mf_setup_experiment(mf_instance *I, const char *fn, int tolerance_defined,
                              double tolerance, double start_time, int stop_time_defined,
                              double stop_time)
{
    if (!I) return MF_ERROR;
    if (!allowed(I, fn, PH_INSTANTIATED, 0)) return MF_ERROR;
    /* all checked before any is stored, so a refused call changes nothing */
    if (tolerance_defined && !mf_tolerance_ok(tolerance)) {
        log_error(I, MF_TOLERANCE_REFUSED, fn, tolerance);
        return MF_ERROR;
    }
    if (!isfinite(start_time)) {
        log_error(I, "%s: startTime must be finite, got %g", fn, start_time);
        return MF_ERROR;
    }
    if (stop_time_defined && !(isfinite(stop_time) && stop_time >= start_time)) {
        log_error(I, "%s: stopTime %g must be finite and not before startTime %g", fn,
                  stop_time, start_time);
        return MF_ERROR;
    }
    I->stop_defined = stop_time_defined != 0;
    I->t_stop = stop_time_defined ? stop_time : 0.0;
    I->rtol = tolerance_defined ? tolerance : DEFAULT_TOLERANCE;
    I->t = I->t_start = I->t_u = start_time;
    invalidate(I);
    return MF_OK;
}

mf_status mf_enter_initialization_mode(mf_instance *I, const char *fn)
{
    if (!I) return MF_ERROR;
    if (!allowed(I, fn, PH_INSTANTIATED, 0)) return MF_ERROR;
    I->phase = PH_INIT;
    log_info(I, LOG_EVENTS, "%s: Initialization Mode at t = %.17g, relative tolerance %g", fn,
             I->t, I->rtol);
    return MF_OK;
}

static int constraints_hold(mf_instance *I, const char *fn)
{
    const mf_model *m = I->m;
    int i, ok = 1;
    if (m->n_c == 0) return 1;
    if (call(I, &m->check, I->t, I->x, I->q, I->u, I->g, NULL)) {
        log_error(I, "%s: evaluation of the parameter constraints failed", fn);
        return 0;
    }
    for (i = 0; i < m->n_c; i++) {
        double g = I->g[i];
        int holds = m->constraints[i].strict ? (g > 0.0) : (g >= 0.0);
        if (!holds) {
            log_error(I, "%s: %s", fn,
                      m->constraints[i].message ? m->constraints[i].message : "constraint violated");
            ok = 0;
        }
    }
    return ok;
}

mf_status mf_exit_initialization_mode(mf_instance *I, const char *fn)
{
    mf_status st;
    if (!I) return MF_ERROR;
    if (!allowed(I, fn, PH_INIT, 1)) return MF_ERROR;
    if (!constraints_hold(I, fn)) return MF_ERROR;
    st = event_iteration(I, fn, NULL);
    if (st != MF_OK) {
        I->failed = 1;
        return st;
    }
    I->inputs_changed = 0;
    solvers_reset(I);
    I->phase = I->iface == MF_CO_SIMULATION ? PH_STEP : PH_EVENT;
    log_info(I, LOG_EVENTS, "%s: initialised at t = %.17g; now in %s", fn, I->t,
             phase_name(I->phase));
    return MF_OK;
}

mf_status mf_terminate(mf_instance *I, const char *fn)
{
    if (!I) return MF_ERROR;
    if (!allowed(I, fn, PH_INIT | PH_EVENT | PH_CONT | PH_STEP, 0)) return MF_ERROR;
    I->phase = PH_TERMINATED;
    log_info(I, LOG_EVENTS, "%s: terminated at t = %.17g", fn, I->t);
    return MF_OK;
}

mf_status mf_reset(mf_instance *I, const char *fn)
{
    if (!I) return MF_ERROR;
    (void)fn;
    set_start_values(I);
    return MF_OK;
}

/* ------------------------------------------------------------------------ */
/* variables                                                                 */

/* The error path of lookup, kept out of line: the look-up itself is on the path of
   every get and set, which the masters of joined models make tens of times per
   right-hand side. */
static MF_COLD const mf_variable *bad_reference(const mf_instance *I, const char *fn,
                                                 uint32_t vr, int want_int)
{
    const mf_variable *v;
    const char *has, *asked;
    if (vr >= (uint32_t)I->m->n_variables) {
        log_error(I, "%s: unknown value reference %lu (this model has 0 to %d)", fn,
                  (unsigned long)vr, I->m->n_variables - 1);
        return NULL;
    }
    v = &I->m->variables[vr];
    has = v->is_integer ? I->host.int_type : I->host.float_type;
    asked = want_int ? I->host.int_type : I->host.float_type;
    log_error(I, "%s: variable '%s' (value reference %lu) has type %s, not %s", fn, v->name,
              (unsigned long)vr, has ? has : "?", asked ? asked : "?");
    return NULL;
}

static const mf_variable *lookup(const mf_instance *I, const char *fn, uint32_t vr, int want_int)
{
    const mf_variable *v;
    if (vr < (uint32_t)I->m->n_variables) {
        v = &I->m->variables[vr];
        if ((v->is_integer != 0) == (want_int != 0)) return v;
    }
    return bad_reference(I, fn, vr, want_int);
}

static int get_value(mf_instance *I, const char *fn, const mf_variable *v, double *out)
{
    switch (v->kind) {
    case MF_TIME: *out = I->t; return 1;
    case MF_PARAMETER: *out = I->p[v->index]; return 1;
    case MF_STATE: *out = I->x[v->index]; return 1;
    case MF_INPUT: *out = I->u[v->index]; return 1;
    case MF_DISCRETE: *out = I->q[v->index]; return 1;
    case MF_RUNTIME: *out = I->method; return 1;
    case MF_DERIVATIVE:
        if (!I->xdot_valid && !update_xdot(I, fn)) return 0;
        *out = I->xdot[v->index];
        return 1;
    case MF_COMPUTED:
        if (!I->y_valid && !update_y(I, fn)) return 0;
        *out = I->y[v->index];
        /* the last n_z are the event indicators (FMI 3 variables), read as by
           GetEventIndicators */
        if (*out == 0.0 && v->index >= I->m->n_y - I->m->n_z)
            *out = I->z_shift[v->index - (I->m->n_y - I->m->n_z)];
        return 1;
    }
    return 0;
}

/* The phases in which a variable of this kind may be set; 0: never (computed). */
static int settable_phases(int kind)
{
    switch (kind) {
    case MF_PARAMETER:
    case MF_STATE:
    case MF_DISCRETE:
    case MF_RUNTIME: return PH_INSTANTIATED | PH_INIT;
    case MF_INPUT: return PH_ANY & ~PH_TERMINATED;
    default: return 0;
    }
}

static int valid_method(double val)
{
    return val == MF_METHOD_EXPLICIT || val == MF_METHOD_IMPLICIT || val == MF_METHOD_AUTO;
}

/* Why a value cannot be set (settable said no). */
static MF_COLD int not_settable(mf_instance *I, const char *fn, const mf_variable *v,
                                uint32_t vr, double val)
{
    int mask = settable_phases(v->kind);
    if (!mask) {
        log_error(I, "%s: variable '%s' (value reference %lu) is computed by the model and "
                     "cannot be set", fn, v->name, (unsigned long)vr);
    } else if (!(I->phase & mask)) {
        log_error(I, "%s: variable '%s' can be set %s, not in %s", fn, v->name,
                  v->kind == MF_INPUT
                      ? "at any time before termination"
                      : "only before initialisation ends (Instantiated state or "
                        "Initialization Mode)",
                  phase_name(I->phase));
    } else if (!isfinite(val)) {
        log_error(I, "%s: value %g for variable '%s' is not finite; not set", fn, val, v->name);
    } else {
        log_error(I, "%s: '%s' must be 0 (DOPRI5, explicit), 1 (RODAS3, implicit) or 2 "
                     "(automatic: switches between them on stiffness), got %g", fn, v->name, val);
    }
    return 0;
}

static int settable(mf_instance *I, const char *fn, const mf_variable *v, uint32_t vr, double val)
{
    if ((I->phase & settable_phases(v->kind)) && isfinite(val) &&
        (v->kind != MF_RUNTIME || valid_method(val)))
        return 1;
    return not_settable(I, fn, v, vr, val);
}

static void store_value(mf_instance *I, const mf_variable *v, double val)
{
    switch (v->kind) {
    case MF_PARAMETER: I->p[v->index] = val; break;
    case MF_STATE:
        I->x[v->index] = val;
        solvers_restart(I);
        break;
    case MF_DISCRETE: I->q[v->index] = val; break;
    case MF_RUNTIME:
        I->method = (int)val;
        solvers_reset(I);
        break;
    case MF_INPUT:
        if (I->iface == MF_CO_SIMULATION && I->t != I->t_u) {
            /* move the extrapolation base to now, so that inputs not set again
               continue from where their extrapolation has brought them */
            rebase_inputs(I);
        }
        /* an input set to the value it has leaves every cached result valid; masters
           set all inputs at every point, and most of them have not moved */
        if (I->u[v->index] == val) return;
        I->inputs_changed = 1;
        I->u[v->index] = val;
        inputs_moved(I);
        break;
    default: break;
    }
    invalidate(I);
}

static MF_COLD int bad_vr_args(const mf_instance *I, const char *fn, const uint32_t vr[],
                               size_t n_vr, const void *values, size_t n_values)
{
    if (!array_ok(I, fn, vr, n_vr, "valueReferences")) return 0;
    if (!array_ok(I, fn, values, n_values, "values")) return 0;
    log_error(I, "%s: nValueReferences (%lu) and nValues (%lu) differ; every variable "
                 "here is a scalar", fn, (unsigned long)n_vr, (unsigned long)n_values);
    return 0;
}

static int vr_args_ok(const mf_instance *I, const char *fn, const uint32_t vr[], size_t n_vr,
                      const void *values, size_t n_values)
{
    if (n_vr == n_values && (n_vr == 0 || (vr && values))) return 1;
    return bad_vr_args(I, fn, vr, n_vr, values, n_values);
}

static MF_COLD mf_status not_finite_read(const mf_instance *I, const char *fn,
                                         const mf_variable *v, double value)
{
    log_error(I, "%s: '%s' is not finite (%g) at t = %.17g; the model cannot be evaluated "
                 "here", fn, v->name, value, I->t);
    return MF_ERROR;
}

mf_status mf_get_float(mf_instance *I, const char *fn, const uint32_t vr[], size_t n_vr,
                       double values[], size_t n_values)
{
    size_t k;
    if (!I) return MF_ERROR;
    if (!vr_args_ok(I, fn, vr, n_vr, values, n_values)) return MF_ERROR;
    for (k = 0; k < n_vr; k++) {
        const mf_variable *v = lookup(I, fn, vr[k], 0);
        if (!v || !get_value(I, fn, v, &values[k])) return MF_ERROR;
        /* a value read with status OK is a number the importer can use */
        if (!isfinite(values[k])) return not_finite_read(I, fn, v, values[k]);
    }
    return MF_OK;
}

mf_status mf_get_int(mf_instance *I, const char *fn, const uint32_t vr[], size_t n_vr,
                     int32_t values[], size_t n_values)
{
    size_t k;
    if (!I) return MF_ERROR;
    if (!vr_args_ok(I, fn, vr, n_vr, values, n_values)) return MF_ERROR;
    for (k = 0; k < n_vr; k++) {
        double d;
        const mf_variable *v = lookup(I, fn, vr[k], 1);
        if (!v || !get_value(I, fn, v, &d)) return MF_ERROR;
        d = floor(d + 0.5);
        if (!(d >= -2147483648.0 && d <= 2147483647.0)) {
            log_error(I, "%s: value of '%s' does not fit an %s", fn, v->name, I->host.int_type);
            return MF_ERROR;
        }
        values[k] = (int32_t)d;
    }
    return MF_OK;
}

/* all values are checked before any is stored, so a rejected call changes nothing */
static mf_status set_doubles(mf_instance *I, const char *fn, const uint32_t vr[], size_t n_vr,
                             const double *dv, const int32_t *iv, size_t n_values)
{
    size_t k;
    int want_int = iv != NULL;
    if (!vr_args_ok(I, fn, vr, n_vr, want_int ? (const void *)iv : (const void *)dv, n_values))
        return MF_ERROR;
    for (k = 0; k < n_vr; k++) {
        const mf_variable *v = lookup(I, fn, vr[k], want_int);
        if (!v || !settable(I, fn, v, vr[k], want_int ? (double)iv[k] : dv[k])) return MF_ERROR;
    }
    for (k = 0; k < n_vr; k++)
        store_value(I, &I->m->variables[vr[k]], want_int ? (double)iv[k] : dv[k]);
    return MF_OK;
}

mf_status mf_set_float(mf_instance *I, const char *fn, const uint32_t vr[], size_t n_vr,
                       const double values[], size_t n_values)
{
    if (!I) return MF_ERROR;
    return set_doubles(I, fn, vr, n_vr, values, NULL, n_values);
}

mf_status mf_set_int(mf_instance *I, const char *fn, const uint32_t vr[], size_t n_vr,
                     const int32_t values[], size_t n_values)
{
    static const double dummy = 0.0;
    if (!I) return MF_ERROR;
    if (!values && n_values == 0) values = (const int32_t *)(const void *)&dummy;
    return set_doubles(I, fn, vr, n_vr, NULL, values, n_values);
}

/* ------------------------------------------------------------------------ */
/* events and Model Exchange                                                 */

/* The first of the model's terminate flags that is set, or -1 (no logging: status
   queries use it too). */
static int terminate_flag(const mf_instance *I)
{
    const mf_model *m = I->m;
    int k;
    for (k = 0; k < m->n_terminate; k++) {
        int q = m->terminate_q[k];
        if (q >= 0 && q < m->n_q && I->q[q] != 0.0) return k;
    }
    return -1;
}

/* Why flag k ends the simulation. */
static const char *terminate_reason(const mf_instance *I, int k)
{
    const char *why = k >= 0 ? I->m->terminate_message[k] : 0;
    return why ? why : "the model ended the simulation";
}

/* Whether a terminate flag of the model is set; says so (always, with the time and the
   flag's reason) the first time, since the importer must learn why the simulation ends. */
static int model_terminates(mf_instance *I, const char *fn)
{
    int k = terminate_flag(I);
    if (k < 0) return 0;
    if (!I->terminate_reported) {
        I->terminate_reported = 1;
        log_always(I, "%s: %s at t = %.17g", fn, terminate_reason(I, k), I->t);
    }
    return 1;
}

mf_status mf_enter_event_mode(mf_instance *I, const char *fn)
{
    if (!I) return MF_ERROR;
    if (I->iface != MF_MODEL_EXCHANGE) {
        log_error(I, "%s: not allowed; this Co-Simulation FMU has no Event Mode "
                     "(hasEventMode = false): its doStep handles its events itself", fn);
        return MF_ERROR;
    }
    if (!allowed(I, fn, PH_CONT, 1)) return MF_ERROR;
    I->phase = PH_EVENT;
    log_info(I, LOG_EVENTS, "%s: Event Mode at t = %.17g", fn, I->t);
    return MF_OK;
}

mf_status mf_update_discrete_states(mf_instance *I, const char *fn, int *states_changed,
                                    int *terminate)
{
    mf_status st;
    int changed = 0;
    if (terminate) *terminate = 0;
    if (!I) return MF_ERROR;
    if (!allowed(I, fn, PH_EVENT, 1)) return MF_ERROR;
    st = event_iteration(I, fn, &changed);
    if (st != MF_OK) {
        I->failed = 1;
        return st;
    }
    solvers_restart(I);
    if (states_changed) *states_changed = changed;
    if (terminate) *terminate = model_terminates(I, fn);
    return MF_OK;
}

mf_status mf_enter_continuous_time_mode(mf_instance *I, const char *fn)
{
    if (!I) return MF_ERROR;
    if (I->iface != MF_MODEL_EXCHANGE) {
        log_error(I, "%s: only for Model Exchange; this is a Co-Simulation instance", fn);
        return MF_ERROR;
    }
    if (!allowed(I, fn, PH_EVENT, 1)) return MF_ERROR;
    I->phase = PH_CONT;
    log_info(I, LOG_EVENTS, "%s: Continuous-Time Mode at t = %.17g", fn, I->t);
    return MF_OK;
}

static int me_only(const mf_instance *I, const char *fn)
{
    if (I->iface != MF_MODEL_EXCHANGE) {
        log_error(I, "%s: only for Model Exchange; this is a Co-Simulation instance", fn);
        return 0;
    }
    return 1;
}

mf_status mf_completed_integrator_step(mf_instance *I, const char *fn)
{
    if (!I) return MF_ERROR;
    if (!me_only(I, fn) || !allowed(I, fn, PH_CONT, 1)) return MF_ERROR;
    return MF_OK;
}

mf_status mf_set_time(mf_instance *I, const char *fn, double time)
{
    if (!I) return MF_ERROR;
    if (!me_only(I, fn) || !allowed(I, fn, PH_CONT | PH_EVENT, 1)) return MF_ERROR;
    if (!isfinite(time)) {
        log_error(I, "%s: time must be finite, got %g", fn, time);
        return MF_ERROR;
    }
    if (I->t == time && I->t_u == time) return MF_OK; /* cached results stay valid */
    I->t = time;
    I->t_u = time;
    if (!I->m->time_invariant) invalidate(I);
    return MF_OK;
}

mf_status mf_set_continuous_states(mf_instance *I, const char *fn, const double x[], size_t n)
{
    int i;
    if (!I) return MF_ERROR;
    if (!me_only(I, fn) || !allowed(I, fn, PH_CONT | PH_EVENT, 1)) return MF_ERROR;
    if (!size_ok(I, fn, n, I->m->n_x, "nContinuousStates") ||
        !array_ok(I, fn, x, n, "continuousStates"))
        return MF_ERROR;
    for (i = 0; i < I->m->n_x; i++)
        if (!isfinite(x[i])) {
            log_error(I, "%s: value %g for state '%s' is not finite; no state set", fn, x[i],
                      name_of(I, MF_STATE, i));
            return MF_ERROR;
        }
    if (n == 0 || memcmp(I->x, x, n * sizeof(double)) == 0) return MF_OK; /* nothing moved */
    memcpy(I->x, x, n * sizeof(double));
    invalidate(I);
    return MF_OK;
}

mf_status mf_get_continuous_states(mf_instance *I, const char *fn, double x[], size_t n)
{
    if (!I) return MF_ERROR;
    if (!size_ok(I, fn, n, I->m->n_x, "nContinuousStates") ||
        !array_ok(I, fn, x, n, "continuousStates"))
        return MF_ERROR;
    if (!all_finite(I->x, I->m->n_x)) {
        int i;
        for (i = 0; i < I->m->n_x && isfinite(I->x[i]); i++) {}
        log_error(I, "%s: state '%s' is not finite at t = %.17g", fn, name_of(I, MF_STATE, i),
                  I->t);
        return MF_ERROR;
    }
    if (n) memcpy(x, I->x, n * sizeof(double));
    return MF_OK;
}

mf_status mf_get_derivatives(mf_instance *I, const char *fn, double dx[], size_t n)
{
    if (!I) return MF_ERROR;
    if (!size_ok(I, fn, n, I->m->n_x, "nContinuousStates") ||
        !array_ok(I, fn, dx, n, "derivatives"))
        return MF_ERROR;
    if (!update_xdot(I, fn)) return MF_ERROR;
    if (!all_finite(I->xdot, I->m->n_x)) {
        int i;
        for (i = 0; i < I->m->n_x && isfinite(I->xdot[i]); i++) {}
        log_error(I, "%s: derivative of state '%s' is not finite at t = %.17g", fn,
                  name_of(I, MF_STATE, i), I->t);
        return MF_ERROR;
    }
    if (n) memcpy(dx, I->xdot, n * sizeof(double));
    return MF_OK;
}

mf_status mf_get_event_indicators(mf_instance *I, const char *fn, double z[], size_t n)
{
    if (!I) return MF_ERROR;
    if (!size_ok(I, fn, n, I->m->n_z, "nEventIndicators") ||
        !array_ok(I, fn, z, n, "eventIndicators"))
        return MF_ERROR;
    if (!update_z(I, fn)) return MF_ERROR;
    if (n) memcpy(z, I->z, n * sizeof(double));
    shifted(I, z);
    return MF_OK;
}

/* bitwise, as memcmp (a state going from 0.0 to -0.0 is a change), inlined for the few
   states of a small model */
static int same_states(const double *a, const double *b, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (memcmp(a + i, b + i, sizeof(double)) != 0) return 0;
    return 1;
}

mf_status mf_evaluate_at(mf_instance *I, double t, const double x[], size_t n, double dx[],
                         double z[], size_t nz)
{
    const mf_model *m;
    int i;
    if (!I || I->iface != MF_MODEL_EXCHANGE || !(I->phase & (PH_CONT | PH_EVENT)) || I->failed
        || !isfinite(t))
        return MF_DISCARD;
    m = I->m;
    if (n != (size_t)m->n_x || (n && !x) || (z && nz != (size_t)m->n_z)) return MF_DISCARD;
    for (i = 0; i < m->n_x; i++)
        if (!isfinite(x[i])) return MF_DISCARD;
    if (!(I->t == t && I->t_u == t)) { /* as mf_set_time */
        I->t = t;
        I->t_u = t;
        if (!m->time_invariant) invalidate(I);
    }
    if (!same_states(I->x, x, m->n_x)) { /* as mf_set_continuous_states */
        for (i = 0; i < m->n_x; i++) I->x[i] = x[i];
        invalidate(I);
    }
    if (dx) { /* as mf_get_derivatives */
        if (!eval_xdot(I) || !all_finite(I->xdot, m->n_x)) return MF_DISCARD;
        for (i = 0; i < m->n_x; i++) dx[i] = I->xdot[i];
    }
    if (z) { /* as mf_get_event_indicators */
        if (eval_z(I)) return MF_DISCARD;
        for (i = 0; i < m->n_z; i++) z[i] = I->z[i];
        shifted(I, z);
    }
    return MF_OK;
}

mf_status mf_evaluate_off(mf_instance *I, double t, const double x[], double dx[], double z[])
{
    const mf_model *m;
    if (!I || I->iface != MF_MODEL_EXCHANGE || !(I->phase & (PH_CONT | PH_EVENT)) || I->failed
        || !isfinite(t))
        return MF_DISCARD;
    m = I->m;
    if (!all_finite(x, m->n_x)) return MF_DISCARD;
    /* straight into the caller's arrays: the instance's own point and what it has
       computed there stay as they are */
    if (dx && (call(I, &m->ode, t, x, I->q, I->u, dx, NULL) || !all_finite(dx, m->n_x)))
        return MF_DISCARD;
    if (z) {
        if (call(I, &m->zc, t, x, I->q, I->u, z, NULL) || !all_finite(z, m->n_z))
            return MF_DISCARD;
        shifted(I, z);
    }
    return MF_OK;
}

mf_status mf_get_nominals(mf_instance *I, const char *fn, double nominals[], size_t n)
{
    size_t i;
    if (!I) return MF_ERROR;
    if (!size_ok(I, fn, n, I->m->n_x, "nContinuousStates") ||
        !array_ok(I, fn, nominals, n, "nominals"))
        return MF_ERROR;
    for (i = 0; i < n; i++) nominals[i] = 1.0;
    for (i = 0; i < (size_t)I->m->n_variables; i++) {
        const mf_variable *v = &I->m->variables[i];
        if (v->kind == MF_STATE && v->index >= 0 && (size_t)v->index < n) nominals[v->index] = v->nominal;
    }
    return MF_OK;
}

mf_status mf_get_number_of_states(mf_instance *I, const char *fn, size_t *n)
{
    if (!I) return MF_ERROR;
    if (!array_ok(I, fn, n, 1, "nContinuousStates")) return MF_ERROR;
    *n = (size_t)I->m->n_x;
    return MF_OK;
}

mf_status mf_get_number_of_event_indicators(mf_instance *I, const char *fn, size_t *n)
{
    if (!I) return MF_ERROR;
    if (!array_ok(I, fn, n, 1, "nEventIndicators")) return MF_ERROR;
    *n = (size_t)I->m->n_z;
    return MF_OK;
}

/* ------------------------------------------------------------------------ */
/* Co-Simulation                                                             */

mf_status mf_enter_step_mode(mf_instance *I, const char *fn)
{
    if (!I) return MF_ERROR;
    if (I->iface != MF_CO_SIMULATION) {
        log_error(I, "%s: only for Co-Simulation; this is a Model Exchange instance", fn);
        return MF_ERROR;
    }
    /* Initialization Mode leads straight to Step Mode: there is no Event Mode to leave */
    log_error(I, "%s: not allowed; this Co-Simulation FMU has no Event Mode (hasEventMode = "
                 "false), it is in Step Mode from fmi3ExitInitializationMode on", fn);
    return MF_ERROR;
}

static int rhs(void *ctx, double t, const double *x, double *xdot)
{
    mf_instance *I = (mf_instance *)ctx;
    return call(I, &I->m->ode, t, x, I->q, inputs_at(I, t), xdot, NULL);
}

static int jacobian(void *ctx, double t, const double *x, double *jac)
{
    mf_instance *I = (mf_instance *)ctx;
    return call(I, &I->m->jac, t, x, I->q, inputs_at(I, t), jac, NULL);
}

/* The selected method's step, in the explicit solver's result codes (the two
   enums share their meaning). Both leave (t, x) unchanged on failure. With the
   automatic choice, the step's own stiffness evidence picks the next step's method,
   which starts from the step size the other one reached. */
static mf_dopri_result solver_step(mf_instance *I, double t_end, double h_initial)
{
    const double t0 = I->t;
    /* a sliver shorter than the controllers' smallest step is one Euler step, which
       says nothing about stiffness */
    const int automatic = I->method == MF_METHOD_AUTO && t_end - t0 >= MF_MIN_STEP(t0);
    mf_dopri_result r;
    if (I->method == MF_METHOD_IMPLICIT || (I->method == MF_METHOD_AUTO && I->stiff.implicit)) {
        switch (mf_ros_step(&I->ros, rhs, jacobian, I, &I->t, I->x, t_end, I->rtol, h_initial)) {
        case MF_ROS_OK: break;
        case MF_ROS_RHS_FAILED: return MF_DOPRI_RHS_FAILED;
        default: return MF_DOPRI_STEP_UNDERFLOW;
        }
        I->dense_implicit = 1;
        /* the Jacobian of the step's start, as RODAS3 factored it */
        if (automatic && mf_stiffness_after_implicit(&I->stiff, I->t - t0, I->ros.jac,
                                                     I->m->n_x)) {
            mf_dopri_restart(&I->solver);
            I->solver.h_guess = I->ros.h_guess;
        }
        return MF_DOPRI_OK;
    }
    r = mf_dopri_step(&I->solver, rhs, I, &I->t, I->x, t_end, I->rtol, h_initial);
    if (r != MF_DOPRI_OK) return r;
    I->dense_implicit = 0;
    if (automatic && (mf_stiffness_after_explicit(&I->stiff, I->t - t0, I->solver.h_lambda)
                      || (mf_stiffness_wants_jacobian(&I->stiff)
                          && jacobian(I, I->t, I->x, I->ros.jac) == 0
                          && mf_stiffness_explicit_check(&I->stiff, I->solver.h_guess,
                                                         I->ros.jac, I->m->n_x)))) {
        mf_ros_restart(&I->ros);
        I->ros.h_guess = I->solver.h_guess;
    }
    return MF_DOPRI_OK;
}

static const char *method_name(const mf_instance *I)
{
    if (I->method == MF_METHOD_AUTO)
        return I->stiff.implicit ? "automatic, now RODAS3" : "automatic, now DOPRI5";
    return I->method == MF_METHOD_IMPLICIT ? "RODAS3" : "DOPRI5";
}

/* the dense output over the last accepted step, of the method that took it */
static void solver_dense(const mf_instance *I, double t, double *x)
{
    if (I->dense_implicit) mf_ros_dense(&I->ros, t, x);
    else mf_dopri_dense(&I->solver, t, x);
}

/* work counters of both methods, summed: only the selected one moves in a step */
static void solver_work(const mf_instance *I, long *n_rhs, long *n_rejected, long *n_jac)
{
    *n_rhs = I->solver.n_rhs + I->ros.n_rhs;
    *n_rejected = I->solver.n_rejected + I->ros.n_rejected;
    /* RODAS3's and the stiffness checks' alike: each evaluates the whole matrix */
    *n_jac = I->ros.n_jac + I->stiff.jacobians_checked;
}

/* indicators at time t inside the last accepted step (mf_indicator_fn) */
static int z_inside(void *ctx, double t, double *z)
{
    mf_instance *I = (mf_instance *)ctx;
    solver_dense(I, t, I->x_tmp);
    return call(I, &I->m->zc, t, I->x_tmp, I->q, inputs_at(I, t), z, NULL);
}

/* The solver gave up because the state derivatives were not finite: say whether they
   already are at the current point (then it is the model there: parameters, inputs,
   states) or only at every trial point of the step ahead (the step runs the model out
   of its domain, e.g. a huge step whose trial states overflow). */
static void explain_rhs_failure(mf_instance *I, const char *fn, double t_end)
{
    int i;
    I->xdot_valid = 0;
    if (!update_xdot(I, fn)) return;
    for (i = 0; i < I->m->n_x; i++)
        if (!isfinite(I->xdot[i])) {
            log_error(I, "%s: the derivative of state '%s' is not finite (%g) at t = %.17g; the "
                         "model cannot be evaluated at this point (check its parameters, "
                         "inputs and states)", fn, name_of(I, MF_STATE, i), I->xdot[i], I->t);
            return;
        }
    log_error(I, "%s: from t = %.17g towards %.17g every trial step down to %g s led to state "
                 "derivatives that are not finite (the states left the model's domain or "
                 "overflowed); shorter communication steps may help", fn, I->t, t_end,
              MF_MIN_STEP(I->t));
}

/* After a step: the outputs and indicators the importer may read now are finite, or
   the step fails here, naming the first that is not (no NaN is reported with OK). */
static int outputs_finite(mf_instance *I, const char *fn)
{
    int i;
    if (!update_y(I, fn)) return 0;
    for (i = 0; i < I->m->n_y; i++)
        if (!isfinite(I->y[i])) {
            log_error(I, "%s: output '%s' is not finite (%g) at t = %.17g", fn,
                      name_of(I, MF_COMPUTED, i), I->y[i], I->t);
            return 0;
        }
    for (i = 0; i < I->m->n_x; i++)
        if (!isfinite(I->x[i])) {
            log_error(I, "%s: state '%s' is not finite at t = %.17g", fn,
                      name_of(I, MF_STATE, i), I->t);
            return 0;
        }
    return I->m->n_z == 0 || update_z(I, fn);
}

/* A step with no solver, where the model is a function of time: no event indicator
   can fire, and there are no states (a kinematic source such as s = U sin(omega t))
   or their derivatives are constants of the parameters (ConstantSpeed's travel' = v;
   model.h constant_derivatives), so x(t_end) = x + (t_end - t) xdot exactly. The step
   is then one evaluation, not a solver's steps. 1: done (I->t not yet moved); 0: the
   solver must take it; -1: the derivatives could not be evaluated. */
static int step_without_solver(mf_instance *I, const char *fn, double t_end)
{
    const mf_model *m = I->m;
    double h = t_end - I->t;
    int i;
    if (m->n_z != 0 || (m->n_x != 0 && !m->constant_derivatives)) return 0;
    if (m->n_x == 0) return 1;
    if (!update_xdot(I, fn)) return -1;
    for (i = 0; i < m->n_x; i++) I->x[i] += h * I->xdot[i];
    solvers_restart(I); /* their memory of the last step no longer holds */
    return 1;
}

mf_status mf_do_step(mf_instance *I, const char *fn, double t, double h, double *last_time,
                     int *terminate, int *early_return)
{
    const mf_model *m;
    double t_end, t_window;
    long steps = 0, events = 0, rhs0, rej0, jac0, rhs1, rej1, jac1, switches0;
    int i;

    if (terminate) *terminate = 0;
    if (early_return) *early_return = 0;
    if (!I) return MF_ERROR;
    m = I->m;
    switches0 = I->stiff.switches;
    if (last_time) *last_time = I->t;
    if (I->iface != MF_CO_SIMULATION) {
        log_error(I, "%s: only for Co-Simulation; this is a Model Exchange instance", fn);
        return MF_ERROR;
    }
    if (!allowed(I, fn, PH_STEP, 1)) return MF_ERROR;
    if (!isfinite(t) || fabs(t - I->t) > 1e-10 * fmax(1.0, fabs(I->t))) {
        log_error(I, "%s: currentCommunicationPoint %.17g differs from the FMU's time %.17g", fn,
                  t, I->t);
        return MF_ERROR;
    }
    if (!(h > 0.0) || !isfinite(h)) {
        log_error(I, "%s: communicationStepSize must be finite and > 0, got %g", fn, h);
        return MF_ERROR;
    }
    if (I->terminate_reported && model_terminates(I, fn)) {
        /* the importer has been told (FMI 2: Discard with fmi2Terminated true; FMI 3:
           terminateSimulation): both standards allow no step after that, and a silent
           repeat of the first answer leaves a master looping without a reason */
        log_error(I, "%s: the model ended the simulation at t = %.17g (%s); no step can "
                     "follow: terminate, reset or free the instance", fn, I->t,
                  terminate_reason(I, terminate_flag(I)));
        if (terminate) *terminate = 1;
        return MF_ERROR;
    }
    if (model_terminates(I, fn)) {
        if (terminate) *terminate = 1;
        return MF_OK; /* stays where the model ended it */
    }
    t_end = I->t + h;
    if (!isfinite(t_end)) {
        log_error(I, "%s: t + communicationStepSize = %.17g + %g is not a finite time", fn,
                  I->t, h);
        return MF_ERROR;
    }
    if (I->stop_defined && mf_past_stop(t_end, I->t_stop)) {
        log_error(I, MF_PAST_STOP, fn, I->t, h, t_end, I->t_stop);
        return MF_ERROR;
    }
    t_window = I->t;
    solver_work(I, &rhs0, &rej0, &jac0);

    if (I->inputs_changed) {
        /* the importer may have moved an input discontinuously across an
           indicator's zero: that is an event at the communication point */
        int cross = 0;
        I->inputs_changed = 0;
        solvers_restart(I);
        if (!update_z(I, fn)) goto fail;
        for (i = 0; i < m->n_z; i++)
            if (crossed(I->z_prev[i], I->z[i])) cross = 1;
        if (cross) {
            if (event_iteration(I, fn, NULL) != MF_OK) goto fail;
            if (I->event_changed) {
                /* an event like those inside the step, so an importer that records
                   events (FMI 3 intermediate update) sees it too; one that changed
                   nothing (an input grazing a zero) is no event */
                events++;
                if (I->host.event_dispatch && I->host.event_callback)
                    I->host.event_dispatch(I->host.event_callback, I->host.environment, I->t);
                if (model_terminates(I, fn)) {
                    if (terminate) *terminate = 1;
                    return MF_OK;
                }
            }
        } else if (m->n_z) {
            memcpy(I->z_prev, I->z, (size_t)m->n_z * sizeof(double));
        }
    }

    switch (step_without_solver(I, fn, t_end)) {
    case 1: I->t = t_end; break;
    case 0: break;
    default: goto fail;
    }
    while (I->t < t_end) {
        double t_old = I->t, t_event;
        int found;
        mf_dopri_result r;

        if (++steps > MAX_STEPS_PER_DO_STEP) {
            log_error(I, "%s: more than %ld internal steps between t = %.17g and %.17g "
                         "(reached t = %.17g); the model may be chattering between modes",
                      fn, MAX_STEPS_PER_DO_STEP, t, t_end, I->t);
            goto fail;
        }
        if (steps % PROGRESS_WINDOW == 0) {
            /* A step the model cannot finish (1e300 s of a rolling coin) must not run for
               minutes before MAX_STEPS_PER_DO_STEP says so: project the remaining steps
               from the recent pace and refuse at once when they are too many. */
            double pace = (I->t - t_window) / (double)PROGRESS_WINDOW;
            double needed = pace > 0.0 ? (t_end - I->t) / pace : HUGE_VAL;
            if ((double)steps + needed > (double)MAX_STEPS_PER_DO_STEP) {
                log_error(I, "%s: communicationStepSize %g from t = %.17g is too long for "
                             "this model: its last %ld internal steps advanced %g s (to t = "
                             "%.17g), so the rest needs about %.3g steps, more than the %ld "
                             "allowed per step; use shorter communication steps", fn, h, t,
                          PROGRESS_WINDOW, I->t - t_window, I->t, needed,
                          MAX_STEPS_PER_DO_STEP);
                goto fail;
            }
            t_window = I->t;
        }
        r = solver_step(I, t_end, h);
        if (r != MF_DOPRI_OK) {
            if (r == MF_DOPRI_RHS_FAILED)
                explain_rhs_failure(I, fn, t_end);
            else
                log_error(I, "%s: the solver's step size fell below %g s at t = %.17g "
                             "(relative tolerance %g): the model is too stiff or "
                             "discontinuous here for %s%s", fn, MF_MIN_STEP(I->t), I->t,
                          I->rtol, I->method == 1 ? "RODAS3" : "DOPRI5",
                          I->method == 1 ? "" : "; the implicit solver (solver = 1) may manage");
            goto fail;
        }
        invalidate(I);
        if (m->n_z == 0) continue;
        if (!update_z(I, fn)) goto fail;
        found = mf_locate_event(z_inside, I, m->n_z, t_old, I->z_prev, I->t, I->z,
                                EVENT_SUBSAMPLES, &t_event, I->z_hit, I->z_work);
        if (found < 0) {
            log_error(I, "%s: the event indicators could not be evaluated while locating an "
                         "event between t = %.17g and %.17g", fn, t_old, I->t);
            goto fail;
        }
        if (!found) {
            memcpy(I->z_prev, I->z, (size_t)m->n_z * sizeof(double));
            continue;
        }
        solver_dense(I, t_event, I->x);
        I->t = t_event;
        invalidate(I);
        if (event_iteration(I, fn, NULL) != MF_OK) goto fail;
        solvers_restart(I);
        events++;
        if (I->host.event_dispatch && I->host.event_callback)
            I->host.event_dispatch(I->host.event_callback, I->host.environment, I->t);
        if (model_terminates(I, fn)) {
            if (!outputs_finite(I, fn)) goto fail;
            if (terminate) *terminate = 1;
            if (last_time) *last_time = I->t;
            return MF_OK;
        }
        if (I->host.early_return_allowed && early_return && I->t < t_end) {
            if (!outputs_finite(I, fn)) goto fail;
            /* the importer wants to see every event as a communication point */
            *early_return = 1;
            if (last_time) *last_time = I->t;
            return MF_OK;
        }
    }
    I->t = t_end;
    invalidate(I);
    if (!outputs_finite(I, fn)) goto fail;
    solver_work(I, &rhs1, &rej1, &jac1);
    log_info(I, LOG_SOLVER, "%s: [%.17g, %.17g]: %s: %ld steps, %ld rejected, %ld derivative "
                            "evaluations, %ld Jacobians, %ld events, %ld method switches", fn, t,
             t_end, method_name(I), steps, rej1 - rej0, rhs1 - rhs0, jac1 - jac0, events,
             I->stiff.switches - switches0);
    if (last_time) *last_time = t_end;
    return MF_OK;

fail:
    I->failed = 1;
    invalidate(I);
    if (last_time) *last_time = I->t;
    return MF_ERROR;
}

mf_status mf_get_time(mf_instance *I, const char *fn, double *time)
{
    if (!I) return MF_ERROR;
    if (!array_ok(I, fn, time, 1, "value")) return MF_ERROR;
    *time = I->t;
    return MF_OK;
}

mf_status mf_get_terminated(mf_instance *I, const char *fn, int *terminated)
{
    if (!I) return MF_ERROR;
    if (!array_ok(I, fn, terminated, 1, "value")) return MF_ERROR;
    /* the flags themselves, not model_terminates(): a status query must not log */
    *terminated = terminate_flag(I) >= 0;
    return MF_OK;
}

/* ------------------------------------------------------------------------ */
/* partial derivatives                                                       */

/* The row of an unknown in the mf_dd Jacobian [xdot; y] x [x; u]; a state output is
   not a row there (d x_i / d [x; u] is a unit row), so state i is coded -1 - i. */
static int dd_row(const mf_instance *I, const char *fn, uint32_t vr, int *row)
{
    const mf_variable *v = lookup(I, fn, vr, 0);
    if (!v) return 0;
    switch (v->kind) {
    case MF_DERIVATIVE: *row = v->index; return 1;
    case MF_COMPUTED: *row = I->m->n_x + v->index; return 1;
    case MF_STATE: *row = -1 - v->index; return 1;
    default:
        log_error(I, "%s: unknown '%s' (value reference %lu) is not a state derivative, an "
                     "output or a state; only those have partial derivatives here", fn, v->name,
                  (unsigned long)vr);
        return 0;
    }
}

/* The column of a known: states, then inputs. Parameters are not knowns here: they
   are fixed after initialisation and the Jacobian is not generated for them. */
static int dd_col(const mf_instance *I, const char *fn, uint32_t vr, int *col)
{
    const mf_variable *v = lookup(I, fn, vr, 0);
    if (!v) return 0;
    switch (v->kind) {
    case MF_STATE: *col = v->index; return 1;
    case MF_INPUT: *col = I->m->n_x + v->index; return 1;
    default:
        log_error(I, "%s: known '%s' (value reference %lu) is not a continuous state or an "
                     "input; derivatives are provided with respect to those only", fn, v->name,
                  (unsigned long)vr);
        return 0;
    }
}

static double dd_entry(const mf_instance *I, int row, int col)
{
    if (row < 0) return col == -1 - row ? 1.0 : 0.0;
    return I->dd[row + (size_t)col * (size_t)(I->m->n_x + I->m->n_y)];
}

/* 1 when dd holds the Jacobian at the instance's present point; else records that
   point, for the evaluation that follows */
static int dd_current(mf_instance *I)
{
    const mf_model *m = I->m;
    const double *u = inputs_at(I, I->t);
    const double *parts[5];
    int sizes[5], k, same = I->dd_fresh;
    double *at = I->dd_at;
    parts[0] = &I->t; sizes[0] = 1;
    parts[1] = I->x; sizes[1] = m->n_x;
    parts[2] = I->q; sizes[2] = m->n_q;
    parts[3] = u; sizes[3] = m->n_u;
    parts[4] = I->p; sizes[4] = m->n_p;
    for (k = 0; k < 5; k++) {
        size_t bytes = (size_t)sizes[k] * sizeof(double);
        if (sizes[k] > 0) {
            if (same && memcmp(at, parts[k], bytes) != 0) same = 0;
            if (!same) memcpy(at, parts[k], bytes);
        }
        at += sizes[k];
    }
    if (!same) I->dd_fresh = 0;
    return same;
}

mf_status mf_partial_derivatives(mf_instance *I, const char *fn, int adjoint,
                                 const uint32_t unknowns[], size_t n_unknowns,
                                 const uint32_t knowns[], size_t n_knowns, const double seed[],
                                 size_t n_seed, double sensitivity[], size_t n_sensitivity)
{
    const mf_model *m;
    size_t i, j, rows_needed, cols_needed;
    int r, c;
    if (!I) return MF_ERROR;
    m = I->m;
    if (!allowed(I, fn, PH_INIT | PH_EVENT | PH_CONT | PH_STEP | PH_TERMINATED, 0)) return MF_ERROR;
    if (!array_ok(I, fn, unknowns, n_unknowns, "unknowns") ||
        !array_ok(I, fn, knowns, n_knowns, "knowns") || !array_ok(I, fn, seed, n_seed, "seed") ||
        !array_ok(I, fn, sensitivity, n_sensitivity, "sensitivity"))
        return MF_ERROR;
    /* every variable is a scalar: a seed per known (directional) or per unknown (adjoint) */
    rows_needed = adjoint ? n_knowns : n_unknowns;
    cols_needed = adjoint ? n_unknowns : n_knowns;
    if (n_seed != cols_needed || n_sensitivity != rows_needed) {
        log_error(I, "%s: nSeed (%lu) must equal the number of %s (%lu) and nSensitivity (%lu) "
                     "that of the %s (%lu); every variable here is a scalar", fn,
                  (unsigned long)n_seed, adjoint ? "unknowns" : "knowns",
                  (unsigned long)cols_needed, (unsigned long)n_sensitivity,
                  adjoint ? "knowns" : "unknowns", (unsigned long)rows_needed);
        return MF_ERROR;
    }
    for (i = 0; i < n_unknowns; i++) if (!dd_row(I, fn, unknowns[i], &r)) return MF_ERROR;
    for (j = 0; j < n_knowns; j++) if (!dd_col(I, fn, knowns[j], &c)) return MF_ERROR;
    for (j = 0; j < n_seed; j++)
        if (!isfinite(seed[j])) {
            log_error(I, "%s: seed[%lu] = %g is not finite", fn, (unsigned long)j, seed[j]);
            return MF_ERROR;
        }
    if ((m->n_x + m->n_y) * (m->n_x + m->n_u) > 0 && !dd_current(I)) {
        if (call(I, &m->dd, I->t, I->x, I->q, inputs_at(I, I->t), I->dd_nz, NULL)) {
            log_error(I, "%s: evaluation of the Jacobian failed at t = %.17g", fn, I->t);
            return MF_ERROR;
        }
        dd_scatter(I);
        I->dd_fresh = 1;
    }
    for (i = 0; i < n_sensitivity; i++) sensitivity[i] = 0.0;
    /* only the nonzero seeds: an importer's Jacobian column seeds one known in n, and
       the whole product would make each of its n calls O(n^2) */
    if (adjoint) {
        for (i = 0; i < n_unknowns; i++) {
            if (seed[i] == 0.0) continue;
            dd_row(I, fn, unknowns[i], &r);
            for (j = 0; j < n_knowns; j++) {
                dd_col(I, fn, knowns[j], &c);
                sensitivity[j] += seed[i] * dd_entry(I, r, c);
            }
        }
    } else {
        for (j = 0; j < n_knowns; j++) {
            if (seed[j] == 0.0) continue;
            dd_col(I, fn, knowns[j], &c);
            for (i = 0; i < n_unknowns; i++) {
                dd_row(I, fn, unknowns[i], &r);
                sensitivity[i] += dd_entry(I, r, c) * seed[j];
            }
        }
    }
    for (i = 0; i < n_sensitivity; i++)
        if (!isfinite(sensitivity[i])) {
            log_error(I, "%s: sensitivity[%lu] is not finite at t = %.17g (the model's partial "
                         "derivatives are undefined here)", fn, (unsigned long)i, I->t);
            return MF_ERROR;
        }
    return MF_OK;
}

/* ------------------------------------------------------------------------ */
/* FMU state                                                                 */

/* A snapshot is everything dynamic, as one flat array of doubles. */
#define SNAP_MAGIC 0x4d465331u /* "MFS1" */
enum { S_T, S_TSTART, S_RTOL, S_TU, S_HGUESS, S_FACOLD, S_PHASE, S_INCHANGED, S_FAILED,
       S_METHOD, S_HGUESS_ROS, S_STIFF_IMPLICIT, S_STIFF_VOTES, S_STIFF_AGAINST, S_STIFF_SWITCHES,
       S_STIFF_CHECK, S_STIFF_DWELL, S_STIFF_PENALTY, S_STIFF_HEXPLICIT, S_STIFF_HSUM,
       S_STIFF_CHECKED, S_STIFF_FRUITLESS, S_DENSE_IMPLICIT, S_STOP_DEFINED, S_TSTOP, S_HEADER };

typedef struct snapshot {
    unsigned magic;
    const mf_model *model;
    mf_instance *owner;             /* the instance whose list holds it */
    struct snapshot *prev, *next;
    size_t n;
    double d[1];
} snapshot;

static size_t snap_len(const mf_model *m)
{
    return (size_t)S_HEADER + (size_t)m->n_x + (size_t)m->n_q + (size_t)m->n_u + (size_t)m->n_p +
           2 * (size_t)m->n_z;
}

static snapshot *snap_alloc(mf_instance *I)
{
    size_t n = snap_len(I->m);
    snapshot *s = (snapshot *)calloc(1, sizeof(snapshot) + n * sizeof(double));
    if (!s) return NULL;
    s->magic = SNAP_MAGIC;
    s->model = I->m;
    s->n = n;
    s->owner = I;
    s->next = I->states;
    if (I->states) I->states->prev = s;
    I->states = s;
    return s;
}

static void snap_release(snapshot *s)
{
    if (s->prev) s->prev->next = s->next;
    else s->owner->states = s->next;
    if (s->next) s->next->prev = s->prev;
    s->magic = 0;
    free(s);
}

static const snapshot *snap_check(const mf_instance *I, const char *fn, const void *state)
{
    const snapshot *s = (const snapshot *)state;
    if (!s) {
        log_error(I, "%s: FMUState is NULL", fn);
        return NULL;
    }
    if (s->magic != SNAP_MAGIC || s->model != I->m || s->n != snap_len(I->m)) {
        log_error(I, "%s: FMUState was not created by an instance of this model", fn);
        return NULL;
    }
    return s;
}

static void copy_block(double *dst, const double *src, int n)
{
    if (n > 0) memcpy(dst, src, (size_t)n * sizeof(double));
}

mf_status mf_get_state(mf_instance *I, const char *fn, void **state)
{
    const mf_model *m;
    snapshot *s;
    double *d;
    if (!I) return MF_ERROR;
    m = I->m;
    if (!array_ok(I, fn, state, 1, "FMUState")) return MF_ERROR;
    if (*state) {
        /* overwrite in place, as the standard allows reuse of a previous state */
        if (!snap_check(I, fn, *state)) return MF_ERROR;
        s = (snapshot *)*state;
    } else {
        s = snap_alloc(I);
        if (!s) {
            log_error(I, "%s: out of memory", fn);
            return MF_ERROR;
        }
    }
    d = s->d;
    d[S_T] = I->t;
    d[S_TSTART] = I->t_start;
    d[S_RTOL] = I->rtol;
    d[S_TU] = I->t_u;
    d[S_HGUESS] = I->solver.h_guess;
    d[S_FACOLD] = I->solver.facold;
    d[S_PHASE] = I->phase;
    d[S_INCHANGED] = I->inputs_changed;
    d[S_FAILED] = I->failed;
    d[S_METHOD] = I->method;
    d[S_HGUESS_ROS] = I->ros.h_guess;
    d[S_STIFF_IMPLICIT] = I->stiff.implicit;
    d[S_STIFF_VOTES] = I->stiff.votes;
    d[S_STIFF_AGAINST] = I->stiff.against;
    d[S_STIFF_SWITCHES] = (double)I->stiff.switches;
    d[S_STIFF_CHECK] = (double)I->stiff.explicit_steps;
    d[S_STIFF_DWELL] = (double)I->stiff.dwell;
    d[S_STIFF_PENALTY] = I->stiff.penalty;
    d[S_STIFF_HEXPLICIT] = I->stiff.h_explicit;
    d[S_STIFF_HSUM] = I->stiff.implicit_h_sum;
    d[S_STIFF_CHECKED] = (double)I->stiff.jacobians_checked;
    d[S_STIFF_FRUITLESS] = I->stiff.fruitless;
    d[S_DENSE_IMPLICIT] = I->dense_implicit;
    d[S_STOP_DEFINED] = I->stop_defined;
    d[S_TSTOP] = I->t_stop;
    d += S_HEADER;
    copy_block(d, I->x, m->n_x); d += m->n_x;
    copy_block(d, I->q, m->n_q); d += m->n_q;
    copy_block(d, I->u, m->n_u); d += m->n_u;
    copy_block(d, I->p, m->n_p); d += m->n_p;
    copy_block(d, I->z_prev, m->n_z); d += m->n_z;
    copy_block(d, I->z_shift, m->n_z);
    *state = s;
    return MF_OK;
}

mf_status mf_set_state(mf_instance *I, const char *fn, const void *state)
{
    const mf_model *m;
    const snapshot *s;
    const double *d;
    if (!I) return MF_ERROR;
    m = I->m;
    s = snap_check(I, fn, state);
    if (!s) return MF_ERROR;
    d = s->d;
    I->t = d[S_T];
    I->t_start = d[S_TSTART];
    I->rtol = d[S_RTOL];
    I->t_u = d[S_TU];
    I->stop_defined = d[S_STOP_DEFINED] != 0.0;
    I->t_stop = d[S_TSTOP];
    I->phase = (int)d[S_PHASE];
    I->inputs_changed = (int)d[S_INCHANGED];
    I->failed = (int)d[S_FAILED];
    I->method = d[S_METHOD] == MF_METHOD_IMPLICIT ? MF_METHOD_IMPLICIT
                : d[S_METHOD] == MF_METHOD_AUTO ? MF_METHOD_AUTO : MF_METHOD_EXPLICIT;
    d += S_HEADER;
    copy_block(I->x, d, m->n_x); d += m->n_x;
    copy_block(I->q, d, m->n_q); d += m->n_q;
    copy_block(I->u, d, m->n_u); d += m->n_u;
    inputs_moved(I);
    copy_block(I->p, d, m->n_p); d += m->n_p;
    copy_block(I->z_prev, d, m->n_z); d += m->n_z;
    copy_block(I->z_shift, d, m->n_z);
    solvers_reset(I);
    /* the controller history too, so that a restored run repeats bit for bit */
    I->solver.h_guess = s->d[S_HGUESS];
    I->solver.facold = s->d[S_FACOLD];
    I->ros.h_guess = s->d[S_HGUESS_ROS];
    I->stiff.implicit = s->d[S_STIFF_IMPLICIT] != 0.0;
    I->stiff.votes = (int)s->d[S_STIFF_VOTES];
    I->stiff.against = (int)s->d[S_STIFF_AGAINST];
    I->stiff.switches = (long)s->d[S_STIFF_SWITCHES];
    I->stiff.explicit_steps = (long)s->d[S_STIFF_CHECK];
    I->stiff.dwell = (long)s->d[S_STIFF_DWELL];
    I->stiff.penalty = (int)s->d[S_STIFF_PENALTY];
    I->stiff.h_explicit = s->d[S_STIFF_HEXPLICIT];
    I->stiff.implicit_h_sum = s->d[S_STIFF_HSUM];
    I->stiff.jacobians_checked = (long)s->d[S_STIFF_CHECKED];
    I->stiff.fruitless = (int)s->d[S_STIFF_FRUITLESS];
    I->dense_implicit = s->d[S_DENSE_IMPLICIT] != 0.0;
    invalidate(I);
    return MF_OK;
}

mf_status mf_free_state(mf_instance *I, const char *fn, void **state)
{
    if (!I) return MF_ERROR;
    if (!state || !*state) return MF_OK;
    if (!snap_check(I, fn, *state)) return MF_ERROR;
    snap_release((snapshot *)*state);
    *state = NULL;
    return MF_OK;
}

/* serialized: "MFS1" | u64 total size | u64 token length | token | u64 n | n doubles */
static size_t serial_size(const mf_instance *I)
{
    return 4 + 8 + 8 + strlen(I->m->instantiation_token) + 8 + snap_len(I->m) * sizeof(double);
}

static void put_u64(unsigned char **p, uint64_t v)
{
    memcpy(*p, &v, 8);
    *p += 8;
}

static uint64_t get_u64(const unsigned char **p)
{
    uint64_t v;
    memcpy(&v, *p, 8);
    *p += 8;
    return v;
}

mf_status mf_serialized_state_size(mf_instance *I, const char *fn, const void *state,
                                   size_t *size)
{
    if (!I) return MF_ERROR;
    if (!snap_check(I, fn, state) || !array_ok(I, fn, size, 1, "size")) return MF_ERROR;
    *size = serial_size(I);
    return MF_OK;
}

mf_status mf_serialize_state(mf_instance *I, const char *fn, const void *state,
                             unsigned char bytes[], size_t size)
{
    const snapshot *s;
    size_t tl;
    unsigned char *p = bytes;
    if (!I) return MF_ERROR;
    s = snap_check(I, fn, state);
    if (!s) return MF_ERROR;
    if (size != serial_size(I)) {
        log_error(I, "%s: size %lu differs from the serialized size %lu", fn,
                  (unsigned long)size, (unsigned long)serial_size(I));
        return MF_ERROR;
    }
    if (!array_ok(I, fn, bytes, size, "serializedState")) return MF_ERROR;
    tl = strlen(I->m->instantiation_token);
    memcpy(p, "MFS1", 4);
    p += 4;
    put_u64(&p, (uint64_t)size);
    put_u64(&p, (uint64_t)tl);
    memcpy(p, I->m->instantiation_token, tl);
    p += tl;
    put_u64(&p, (uint64_t)s->n);
    memcpy(p, s->d, s->n * sizeof(double));
    return MF_OK;
}

mf_status mf_deserialize_state(mf_instance *I, const char *fn, const unsigned char bytes[],
                               size_t size, void **state)
{
    const unsigned char *p = bytes;
    size_t tl;
    snapshot *s;
    if (!I) return MF_ERROR;
    if (!array_ok(I, fn, bytes, size, "serializedState") || !array_ok(I, fn, state, 1, "FMUState"))
        return MF_ERROR;
    tl = strlen(I->m->instantiation_token);
    if (size != serial_size(I) || memcmp(p, "MFS1", 4) != 0) {
        log_error(I, "%s: not a serialized state of this model (wrong size or header)", fn);
        return MF_ERROR;
    }
    p += 4;
    if (get_u64(&p) != (uint64_t)size || get_u64(&p) != (uint64_t)tl ||
        memcmp(p, I->m->instantiation_token, tl) != 0) {
        log_error(I, "%s: the serialized state belongs to a different model or build "
                     "(instantiation token mismatch)", fn);
        return MF_ERROR;
    }
    p += tl;
    if (get_u64(&p) != (uint64_t)snap_len(I->m)) {
        log_error(I, "%s: the serialized state has the wrong length", fn);
        return MF_ERROR;
    }
    s = snap_alloc(I);
    if (!s) {
        log_error(I, "%s: out of memory", fn);
        return MF_ERROR;
    }
    memcpy(s->d, p, s->n * sizeof(double));
    /* every value of a snapshot is finite (set and step refuse anything else), so a
       NaN or infinity here is corruption that would otherwise be read back as OK */
    if (!all_finite(s->d, (int)s->n) ||
        !(s->d[S_PHASE] >= 1 && s->d[S_PHASE] <= PH_TERMINATED) ||
        ((int)s->d[S_PHASE] & ((int)s->d[S_PHASE] - 1))) {
        snap_release(s); /* out of the instance's list too, or FreeInstance frees it again */
        log_error(I, "%s: the serialized state is corrupt", fn);
        return MF_ERROR;
    }
    if (*state) mf_free_state(I, fn, state);
    *state = s;
    return MF_OK;
}
