/*
 * c_limit: the fastest honest run of one generated model, the floor every FMU path
 * is measured against.
 *
 * The same CasADi-generated model.c the FMU is built from, the runtime's own
 * DOPRI5 (solver.c) and event location, and nothing else: no FMI, no Python in the
 * loop, no step forced to end on an output. The solver steps freely from the first
 * to the last output time; indicator crossings are located in the dense output, the
 * jump function is applied until nothing changes (as the runtime's event iteration
 * does), and the recorded variables are sampled at the output times from the dense
 * output of the step that covers them.
 *
 * Compiled with the FMUs' flags by benchmarks/c_limit.py, called once per run.
 */
#include "events.h"
#include "model.h"
#include "solver.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define EXPORT __attribute__((visibility("default")))
#define MAX_EVENT_ITERATIONS 100 /* the runtime's bound */
#define MAX_STEPS 100000000L
/* The plain limit compares the indicators' signs at the ends of each step and samples
   no interior: none of the benchmarked scenes needs it (the runtime samples a step's
   interior only where its indicators' rates say a double crossing can hide there, and
   in these scenes they seldom do). */
#define EVENT_SCAN_POINTS 0

/* what a recorded column is: a state (x[index]) or a computed variable (y[index]) */
enum { RECORD_STATE = 0, RECORD_COMPUTED = 1 };

/* return codes of mf_c_limit_run */
enum {
    RUN_OK = 0,
    RUN_TERMINATED = 1,        /* the model ended the run; later rows are NaN */
    RUN_NO_MEMORY = -1,
    RUN_MODEL_FAILED = -2,     /* a model function failed or gave a non-finite value */
    RUN_SOLVER_FAILED = -3,    /* step underflow or too many steps */
    RUN_EVENTS_DIVERGED = -4   /* event iteration did not settle */
};

typedef struct {
    const mf_model *m;
    const double **arg;
    double **res;
    mf_int *iw;
    double *w;
    double *p, *q, *u;
    double *x_new, *q_new;    /* one jump */
    double *z_prev, *z, *z_event, *z_work; /* z_work: scratch of mf_locate_event */
    double *x_tmp, *y;
    const mf_dopri *solver;  /* whose dense output the indicators are evaluated on */
} run_ctx;

static int call(run_ctx *c, const mf_function *f, double t, const double *x, const double *q,
                double *r0, double *r1)
{
    double tt = t;
    if (!f->eval) return 0;
    c->arg[0] = &tt;
    c->arg[1] = x;
    c->arg[2] = q;
    c->arg[3] = c->u;
    c->arg[4] = c->p;
    c->res[0] = r0;
    c->res[1] = r1;
    return f->eval(c->arg, c->res, c->iw, c->w, 0);
}

static int rhs(void *ctx, double t, const double *x, double *xdot)
{
    run_ctx *c = (run_ctx *)ctx;
    return call(c, &c->m->ode, t, x, c->q, xdot, NULL);
}

/* --- event location: the runtime's own (fmus/runtime/events.c) -------------- */

/* indicators at time t inside the last accepted step */
static int z_inside(void *ctx, double t, double *z)
{
    run_ctx *c = (run_ctx *)ctx;
    mf_dopri_dense(c->solver, t, c->x_tmp);
    return call(c, &c->m->zc, t, c->x_tmp, c->q, z, NULL);
}

/* --- event iteration ---------------------------------------------------------- */

/* Applies `jump` at (t, x) until nothing changes, then takes the indicators there as
   the reference signs, keeping an old sign where an indicator merely touches zero at
   an event that changed nothing (the runtime's rule). 0 on success. */
static int event_iteration(run_ctx *c, double t, double *x)
{
    const mf_model *m = c->m;
    int it, i, changed = 0;
    for (it = 0; it < MAX_EVENT_ITERATIONS; it++) {
        int same = 1;
        if (call(c, &m->jump, t, x, c->q, c->x_new, c->q_new)) return RUN_MODEL_FAILED;
        for (i = 0; i < m->n_x; i++) {
            if (!isfinite(c->x_new[i])) return RUN_MODEL_FAILED;
            if (c->x_new[i] != x[i]) same = 0;
        }
        for (i = 0; i < m->n_q; i++) {
            if (!isfinite(c->q_new[i])) return RUN_MODEL_FAILED;
            if (c->q_new[i] != c->q[i]) same = 0;
        }
        if (same) break;
        changed = 1;
        if (m->n_x) memcpy(x, c->x_new, (size_t)m->n_x * sizeof(double));
        if (m->n_q) memcpy(c->q, c->q_new, (size_t)m->n_q * sizeof(double));
    }
    if (it == MAX_EVENT_ITERATIONS) return RUN_EVENTS_DIVERGED;
    if (call(c, &m->zc, t, x, c->q, c->z, NULL)) return RUN_MODEL_FAILED;
    for (i = 0; i < m->n_z; i++)
        if (!(c->z[i] == 0.0 && !changed)) c->z_prev[i] = c->z[i];
    return RUN_OK;
}

static int terminated(const run_ctx *c)
{
    const mf_model *m = c->m;
    int k;
    for (k = 0; k < m->n_terminate; k++)
        if (m->terminate_q[k] >= 0 && m->terminate_q[k] < m->n_q && c->q[m->terminate_q[k]] != 0.0)
            return 1;
    return 0;
}

/* the recorded columns at time t, from the state x there */
static int record(run_ctx *c, double t, const double *x, const int *kind, const int *index,
                  int n_rec, double *row)
{
    int j, have_y = 0;
    for (j = 0; j < n_rec; j++) {
        if (kind[j] == RECORD_STATE) {
            row[j] = x[index[j]];
            continue;
        }
        if (!have_y) {
            if (call(c, &c->m->out, t, x, c->q, c->y, NULL)) return RUN_MODEL_FAILED;
            have_y = 1;
        }
        row[j] = c->y[index[j]];
    }
    return RUN_OK;
}

/* --- set-up --------------------------------------------------------------------- */

static double *dvec(int n) { return (double *)calloc((size_t)(n > 0 ? n : 1), sizeof(double)); }

static void ctx_free(run_ctx *c)
{
    free((void *)c->arg); free(c->res); free(c->iw); free(c->w);
    free(c->p); free(c->q); free(c->u); free(c->x_new); free(c->q_new);
    free(c->z_prev); free(c->z); free(c->z_event); free(c->z_work); free(c->x_tmp); free(c->y);
}

static int ctx_alloc(run_ctx *c, const mf_model *m)
{
    const mf_function *fs[5];
    mf_int sz_arg = 5, sz_res = 2, sz_iw = 0, sz_w = 0;
    int i;
    memset(c, 0, sizeof *c);
    c->m = m;
    fs[0] = &m->ode; fs[1] = &m->out; fs[2] = &m->zc; fs[3] = &m->jump; fs[4] = &m->check;
    for (i = 0; i < 5; i++) {
        mf_int a = 0, r = 0, iw = 0, w = 0;
        if (!fs[i]->work) continue;
        fs[i]->work(&a, &r, &iw, &w);
        if (a > sz_arg) sz_arg = a;
        if (r > sz_res) sz_res = r;
        if (iw > sz_iw) sz_iw = iw;
        if (w > sz_w) sz_w = w;
    }
    c->arg = (const double **)calloc((size_t)sz_arg, sizeof(double *));
    c->res = (double **)calloc((size_t)sz_res, sizeof(double *));
    c->iw = (mf_int *)calloc((size_t)(sz_iw > 0 ? sz_iw : 1), sizeof(mf_int));
    c->w = dvec((int)sz_w);
    c->p = dvec(m->n_p); c->q = dvec(m->n_q); c->u = dvec(m->n_u);
    c->x_new = dvec(m->n_x); c->q_new = dvec(m->n_q);
    c->z_prev = dvec(m->n_z); c->z = dvec(m->n_z); c->z_event = dvec(m->n_z);
    c->z_work = dvec((int)MF_LOCATE_WORK(m->n_z, EVENT_SCAN_POINTS));
    c->x_tmp = dvec(m->n_x); c->y = dvec(m->n_y);
    if (!c->arg || !c->res || !c->iw || !c->w || !c->p || !c->q || !c->u || !c->x_new ||
        !c->q_new || !c->z_prev || !c->z || !c->z_event || !c->z_work || !c->x_tmp || !c->y) {
        ctx_free(c);
        return RUN_NO_MEMORY;
    }
    return RUN_OK;
}

/* parameters, inputs and modes from the variable table's start values; x likewise */
static void start_values(run_ctx *c, double *x)
{
    const mf_model *m = c->m;
    int i;
    for (i = 0; i < m->n_variables; i++) {
        const mf_variable *v = &m->variables[i];
        switch (v->kind) {
        case MF_PARAMETER: c->p[v->index] = v->start; break;
        case MF_STATE: x[v->index] = v->start; break;
        case MF_INPUT: c->u[v->index] = v->start; break;
        case MF_DISCRETE: c->q[v->index] = v->start; break;
        default: break;
        }
    }
}

/*
 * One run from times[0] to times[n_times - 1] at relative tolerance rtol (atol = rtol,
 * as the FMU's embedded solver); out[k * n_rec + j] = column j at times[k].
 * stats (4): accepted steps, derivative evaluations, rejected steps, events.
 * event_log (may be NULL): the first max_events located events, one row each of
 * 1 + n_x + n_q values: time, then x and q after the event iteration.
 * Returns RUN_OK, RUN_TERMINATED or a negative RUN_* code.
 */
EXPORT int mf_c_limit_run(double rtol, const double *times, int n_times, const int *kind,
                          const int *index, int n_rec, double *out, long *stats,
                          double *event_log, int max_events)
{
    const mf_model *m = &MF_MODEL;
    run_ctx c;
    mf_dopri s;
    double *x, t, t_stop, h_initial;
    long steps = 0, events = 0;
    int k = 0, i, rc;

    if (n_times < 1) return RUN_OK;
    if (ctx_alloc(&c, m) != RUN_OK) return RUN_NO_MEMORY;
    x = dvec(m->n_x);
    if (!x || mf_dopri_alloc(&s, m->n_x) != 0) {
        free(x);
        ctx_free(&c);
        return RUN_NO_MEMORY;
    }
    c.solver = &s;
    start_values(&c, x);
    t = times[0];
    t_stop = times[n_times - 1];
    /* the FMU's first solver step is tried at its communication step; the same here */
    h_initial = n_times > 1 ? times[1] - times[0] : 1.0;
    rc = event_iteration(&c, t, x);

    while (rc == RUN_OK && k < n_times) {
        double t_old = t, t_event;
        int event = 0;
        if (++steps > MAX_STEPS || mf_dopri_step(&s, rhs, &c, &t, x, t_stop, rtol, h_initial)
                                       != MF_DOPRI_OK) {
            rc = RUN_SOLVER_FAILED;
            break;
        }
        t_event = t;
        if (m->n_z) {
            if (call(&c, &m->zc, t, x, c.q, c.z, NULL)) { rc = RUN_MODEL_FAILED; break; }
            event = mf_locate_event(z_inside, &c, m->n_z, t_old, c.z_prev, t, c.z,
                                    EVENT_SCAN_POINTS, &t_event, c.z_event, c.z_work);
            if (event < 0) { rc = RUN_MODEL_FAILED; break; }
            if (!event) memcpy(c.z_prev, c.z, (size_t)m->n_z * sizeof(double));
        }
        /* outputs before an event come from this step; one at the event time, after it */
        while (k < n_times && (event ? times[k] < t_event : times[k] <= t)) {
            mf_dopri_dense(&s, times[k], c.x_tmp);
            if ((rc = record(&c, times[k], c.x_tmp, kind, index, n_rec, out + (long)k * n_rec)))
                break;
            k++;
        }
        if (rc != RUN_OK || !event) continue;
        mf_dopri_dense(&s, t_event, x);
        t = t_event;
        rc = event_iteration(&c, t, x);
        mf_dopri_restart(&s);
        if (event_log && events < max_events) {
            double *row = event_log + events * (1 + m->n_x + m->n_q);
            row[0] = t;
            memcpy(row + 1, x, (size_t)m->n_x * sizeof(double));
            memcpy(row + 1 + m->n_x, c.q, (size_t)m->n_q * sizeof(double));
        }
        events++;
        if (rc == RUN_OK && terminated(&c)) {
            for (; k < n_times; k++)
                for (i = 0; i < n_rec; i++) out[(long)k * n_rec + i] = NAN;
            rc = RUN_TERMINATED;
        }
        /* an event on the last output time: no step is left to take */
        for (; rc == RUN_OK && k < n_times && t >= t_stop; k++)
            rc = record(&c, t, x, kind, index, n_rec, out + (long)k * n_rec);
    }
    if (stats) {
        stats[0] = steps;
        stats[1] = s.n_rhs;
        stats[2] = s.n_rejected;
        stats[3] = events;
    }
    mf_dopri_free(&s);
    free(x);
    ctx_free(&c);
    return rc;
}
