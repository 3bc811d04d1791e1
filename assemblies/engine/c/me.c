/*
 * me.c: the Model Exchange master. The continuous states of every instance form
 * one vector integrated by one solver (the FMU runtime's DOPRI5 or RODAS3);
 * couplings are evaluated in the given order at every right-hand-side call, so
 * inputs are exact at every stage and the error is the solver's alone. Every
 * instance's event indicators are scanned inside each accepted step
 * (mf_locate_event, with interior samples for double crossings); at an event the
 * instances it touches (those whose indicators crossed, whose time event is due or
 * that asked for one, and those whose coupled inputs the updates change) go through
 * event mode together until neither they nor the inputs they see change; the others
 * see no call (event_local). Outputs come from the dense output: no step ends at an
 * output time.
 */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "arena.h"
#include "dop853.h"
#include "engine.h"
#include "events.h"
#include "instances.h"
#include "me.h"
#include "output.h"
#include "solver.h"
#include "solver_implicit.h"
#include "stiffness.h"
#include "jacobian.h"
#include "linear_map.h"
#include "loop.h"

#define MAX_EVENT_ITERATIONS 100
#define MAX_EVENTS 1000000L
/* integrator steps (and time events) per call that advances time: a whole run, or one
   doStep of an assembly FMU; as many as a component FMU's doStep may take */
#define MAX_STEPS 10000000L
/* An algebraic loop's inputs are made consistent to this fraction of the solver's
   tolerance (relative, as the fmpy master's LOOP_TOLERANCE): far below what the
   integration resolves. Newton from the last solution takes one step where the loop is
   linear in its inputs (locked clutches); a matrix of an earlier evaluation is kept
   while it converges within LOOP_REUSE steps. */
#define LOOP_TOLERANCE 1e-3
#define MAX_LOOP_ITERATIONS 20
#define LOOP_REUSE 2

/* Per-instance event location (locate): the distinct times one step's location asks
   for, followed in the order they are first asked (SHARED_RANKS of them), and the
   whole-assembly evaluations kept for the times many instances ask for (SHARED_SLOTS:
   the two ends of the quiet test and the interior samples, events.h) */
#define SHARED_RANKS 8
#define SHARED_SLOTS 4

/* The couplings one kind of evaluation sets, in order (plan_couplings): live[p],
   p < n_live; the arrays below are by p. */
typedef struct {
    int *live, n_live;
    int *segment_end;     /* couplings p .. segment_end[p] are read before any is set */
    int *run_end;         /* couplings p .. run_end[p] read Float64 outputs of one source */
    int *write_order;     /* a segment's couplings by target, so one call sets a target's inputs */
    uint32_t *source_vr;  /* source value references */
    int *loop;            /* the algebraic loop (eng_me_spec.n_loops) a segment solves, -1 */
} coupling_plan;

typedef struct {
    const eng_me_spec *spec;
    eng_stats *stats;
    eng_run *run;
    int n;                /* instances */
    fmu_t **fmus;
    int *x_off, *z_off;   /* each instance's slice of the state and indicator vectors */
    int n_x, n_z;
    double *x, *x_tmp, *x_set, *nominals;
    double *z_prev, *z_now, *z_hit, *z_work;
    double *values, *values_new; /* coupling values, to see the event iteration settle */
    double *sent;         /* the value each coupling last set on its target... */
    int sent_valid;       /* ...valid while nothing else set the inputs */
    /* what the evaluation between events needs (eng_me_spec.continuous), and what the
       recorded columns alone need (eng_me_spec.row_coupling): a row sets only the
       row_instance[i] and the couplings of `rows`, when rows_partial */
    coupling_plan between, rows;
    coupling_plan all;    /* every coupling: the event iteration's propagation through loops */
    eng_loop *loops;      /* per algebraic loop: its Newton solver and last solution */
    int n_loops;
    int *loop_of;         /* per coupling: its loop, -1 */
    int *loop_dd;         /* per loop: its sources give directional derivatives */
    int *members;         /* 0 .. n_couplings - 1: a loop's couplings for eng_loop_matrix_dd */
    int loop_min_steps;   /* Newton steps a loop takes even when it already converges */
    /* event location per instance (eng_me_spec.indicator_start): instance i's plan and
       the instances it moves, local_instance[local_start[i] .. local_start[i + 1] - 1];
       local NULL: the indicators are located on the whole assembly */
    coupling_plan *local;
    int *local_start, *local_instance;
    /* the times of one step's per-instance location that every instance asks for (the
       quiet test's two, events.h) cost one whole-assembly evaluation less than each
       instance's own (shared_point): ask_t[r], the r-th distinct time asked in this step,
       asked by ask_count[r] instances (ask_last[r]: the last of them); prev_count[r], by
       how many in the step before, which predicts it; a time asked by shared_from or
       more is evaluated once for all, into shared_z (shared_t: its times) */
    double ask_t[SHARED_RANKS], shared_t[SHARED_SLOTS];
    int ask_count[SHARED_RANKS], ask_last[SHARED_RANKS], prev_count[SHARED_RANKS];
    int n_ask, n_shared, shared_from;
    double *shared_z;
    int *row_instance, rows_partial;
    int *set_again, any_set_again; /* foreign row instances: set again before a row */
    double *read;         /* source values read in one call per run, by plan index */
    uint32_t *pending_vr; /* inputs of one target waiting to be set in one call */
    double *pending_value;
    double *row;                 /* an event row */
    double *fd, *fd2;            /* finite-difference columns */
    eng_jacobian *exact;         /* the Jacobian from directional derivatives; NULL: by
                                    finite differences, or not planned yet */
    int exact_wanted;            /* directional derivatives it is: exact is planned at the
                                    first Jacobian the run needs (plan_exact) */
    int *group_changed;          /* event groups with an indicator that crossed at this event */
    /* An event that costs what it touches (event_local): per instance, whether it takes
       part (event mode, discrete updates, states re-read), part_list its n_part members;
       prepared[i]: moved to the event and given its inputs already, in this event
       (prepared_list); touched[i]: an input of it changed in the current pass; asked[i]:
       it asked for a step event at the last completed step; next_def/next_t: its own
       next time event; passive[i]: nothing to update when only its continuous inputs
       change (eng_me_spec.event_free) */
    int *part, *part_list, n_part, *prepared, *prepared_list, n_prepared, *touched;
    int *asked, *next_def, *passive;
    double *next_t;
    int events_local;     /* the spec allows it: no algebraic loops */
    int event_was_local;  /* the last event_iteration took part of the assembly only */
    int z_now_valid;      /* z_now holds the indicators at (M->t, M->x) */
    mf_dopri dopri;
    eng_dop853 dop853;
    int high_order;       /* the explicit steps are DOP853's, not DOPRI5's */
    int left_high_order;  /* "auto" left DOP853 for DOPRI5 (events came too often) */
    mf_ros ros;
    mf_stiffness stiff;   /* which of the two takes the next step */
    int dense_implicit;   /* the last accepted step was RODAS3's */
    double t_set;         /* the point the instances were last set to */
    int set_valid;
    int thin;             /* one instance, no couplings, mfEvaluateAt: the thin path (thin_point) */
    fmu_off off;          /* on the thin path, mfEvaluateOff where the FMU has it (off.fn) */
    int *evaluate_at;     /* per instance: its FMU has mfEvaluateAt (move_one) */
    /* instances evaluated from time between events (eng_me_spec.time_function; read_timed):
       timed[i] while they are, timed_t[i] the event their constants come from, timed_dx
       their derivatives then (by state), timed_y and timed_rate each coupling's source
       value then and its rate (by coupling, for couplings out of a timed instance) */
    int *timed, any_timed;
    double *timed_t, *timed_dx, *timed_y, *timed_rate;
    /* per instance: not moved between events, as timed or time-free (eng_me_spec.time_free),
       but at each event and where the run stops (move_unmoved) */
    int *unmoved, any_unmoved;
    int *needed;          /* by coupling: in the plan between events (plan_between) */
    /* instances that are fixed linear maps between events (eng_me_spec.linear_map;
       read_linear): linear[i] while they are. By coupling into one: lin_u its input now,
       lin_u0 at the last event; by coupling out of one: lin_y0 its source value then and
       lin_row the start of its row in lin_J of d output / d input over the couplings
       into its instance, lin_in[lin_in_start[i] .. lin_in_start[i + 1] - 1] */
    int *linear, any_linear, *lin_in_start, *lin_in, *lin_row;
    int *lin_recorded, any_lin_recorded; /* linear with a recorded column: set before a row */
    int *lin_ready;       /* its lin_J is read (once: the coefficients are constants) */
    /* the couplings out of each instance, out_list[out_start[i] .. out_start[i + 1] - 1],
       and their source value references in that order (out_vr) */
    int *out_start, *out_list;
    uint32_t *out_vr;
    double *lin_u, *lin_u0, *lin_y0, *lin_J;
    long k_out;           /* next output row */
    int rows_from_states; /* every column is a state (eng_me_spec.column_state) */
    int rows_by_state;    /* and so few that interpolating only those costs less */
    int next_defined;     /* a time event is due at t_next */
    double t_next;
    int terminate;        /* an instance asked to end the run */
    double *x_before;     /* the states before an event's jumps */
    double *x_start;      /* the states at the start of the step (runs that may rest) */
    int *asleep;          /* per instance: its group rests for good (eng_me_spec.rest_group) */
    double t;             /* the time reached */
    double h_initial;     /* the first step the solver tries */
    int inputs_changed;   /* an importer set a member's input since the last step */
    /* why the last call failed; the run's error if it cannot go on (inside a step the
       solver may still recover by trying a shorter one) */
    char message[sizeof(((eng_stats *)0)->message)];
    eng_arena arena;      /* the arrays allocate takes, given back together by release */
} me_master;

/* --- failures --------------------------------------------------------------- */

static int failed(me_master *M, int instance, const char *what, double t)
{
    eng_describe_failure(M->message, sizeof M->message, M->fmus[instance], what, t);
    return -1;
}

static int fail(me_master *M, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    vsnprintf(M->message, sizeof M->message, format, args);
    va_end(args);
    return -1;
}

/* --- the coupled system at one point ----------------------------------------------- */

/* Sets the Float64 inputs gathered for one target in one call. */
static int flush(me_master *M, int target, int *n_pending, double t)
{
    if (*n_pending && fmu_set_float64(M->fmus[target], M->pending_vr, (size_t)*n_pending,
                                      M->pending_value))
        return failed(M, target, "setting coupled inputs", t);
    *n_pending = 0;
    return 0;
}

/* --- algebraic loops (eng_me_spec.n_loops) ----------------------------------------- */

static int couple(me_master *M, const coupling_plan *P, double t);

typedef struct {
    me_master *M;
    int loop;
    double t;
} loop_ctx;

/* eng_loop_residual_fn: the loop's inputs set to u, r = u - G(u) */
static int loop_residual(void *ctx, const double *u, double *r)
{
    const loop_ctx *L = ctx;
    me_master *M = L->M;
    const eng_coupling *c = M->spec->couplings + M->spec->loop_first[L->loop];
    const int n = M->spec->loop_count[L->loop];
    int i;
    for (i = 0; i < n; i++)
        if (fmu_set_float64(M->fmus[c[i].target.instance], &c[i].target.vr, 1, &u[i]))
            return failed(M, c[i].target.instance, "setting an input of an algebraic loop", L->t);
    for (i = 0; i < n; i++) {
        double y;
        if (fmu_get_float64(M->fmus[c[i].source.instance], &c[i].source.vr, 1, &y))
            return failed(M, c[i].source.instance, "reading an output of an algebraic loop",
                          L->t);
        r[i] = u[i] - c[i].gain * y;
    }
    return 0;
}

/* eng_loop_matrix_fn: I - dG/du from the sources' directional derivatives */
static int loop_matrix(void *ctx, double *a)
{
    const loop_ctx *L = ctx;
    me_master *M = L->M;
    int bad = -1;
    if (eng_loop_matrix_dd(M->fmus, M->spec->couplings,
                           M->members + M->spec->loop_first[L->loop],
                           M->spec->loop_count[L->loop], a, &bad))
        return failed(M, bad, "getting the directional derivatives of an algebraic loop", L->t);
    return 0;
}

/* Loop k's inputs consistent with its outputs at the point the instances stand at,
   Newton from the last solution; M->sent holds what it set. */
static int solve_loop(me_master *M, int k, double t)
{
    const eng_me_spec *s = M->spec;
    const eng_loop_options options = {LOOP_TOLERANCE * s->tolerance, MAX_LOOP_ITERATIONS, 1,
                                      LOOP_REUSE, M->loop_min_steps};
    const char *name = s->loop_name ? s->loop_name[k] : NULL;
    char between[512];
    eng_loop *L = &M->loops[k];
    loop_ctx ctx = {M, k, t};
    double res = 0.0;
    int rc = eng_loop_solve(L, loop_residual, M->loop_dd[k] ? loop_matrix : NULL, &ctx, &options,
                            &res);
    if (rc == ENG_LOOP_FAILED) return -1;
    if (rc != ENG_LOOP_OK && !name) { /* no name given (an assembly FMU's): its instances */
        size_t used = (size_t)snprintf(between, sizeof between, "through");
        int j;
        for (j = s->loop_first[k]; j < s->loop_first[k] + s->loop_count[k]; j++)
            if (used < sizeof between)
                used += (size_t)snprintf(between + used, sizeof between - used, " %.100s",
                                         fmu_instance_name(M->fmus[s->couplings[j].source.instance]));
        name = between;
    }
    if (rc == ENG_LOOP_SINGULAR)
        return fail(M, "algebraic loop %.700s: the matrix I - dy/du is singular at t = %.10g "
                       "(no unique consistent input)", name, t);
    if (rc != ENG_LOOP_OK)
        return fail(M, "algebraic loop %.700s: Newton did not converge in %d iterations at "
                       "t = %.10g (residual %.3g)", name, MAX_LOOP_ITERATIONS, t, res);
    memcpy(M->sent + s->loop_first[k], L->u, (size_t)L->n * sizeof(double));
    return 0;
}

/* The loops' matrices are evaluated anew at their next solve: an event may have changed
   which outputs feed through (a clutch that locks). */
static void forget_loop_matrices(me_master *M)
{
    int k;
    for (k = 0; k < M->n_loops; k++) M->loops[k].factored = 0;
}

/* Every coupling in order, into values[]: eng_propagate, or where there are loops, a
   pass of the plan of every coupling with each loop solved (it stays where it
   converges, so that an event iteration that changes nothing sees the same values). */
static int propagate(me_master *M, double *values, double t)
{
    const int nc = M->spec->n_couplings;
    int bad, rc;
    if (M->n_loops == 0)
        return eng_propagate(M->fmus, M->spec->couplings, nc, values, &bad)
                   ? failed(M, bad, "evaluating the couplings", t) : 0;
    forget_loop_matrices(M);
    /* as eng_propagate: every FMU read and set (couple() takes none of the plan `all`
       from time or a linear map: their values at the last event are what this
       refreshes) */
    M->loop_min_steps = 0;
    M->sent_valid = 0;
    rc = couple(M, &M->all, t);
    M->loop_min_steps = 1;
    if (rc) return -1;
    if (nc) memcpy(values, M->sent, (size_t)nc * sizeof(double));
    return 0;
}

/* The source values of the run of couplings from p (plan P) out of a timed instance at
   t: each is its value at the last event plus its rate times the time since, as exact
   as the source's own evaluation (its outputs are affine in states that move at a
   constant rate), and no call. */
static void timed_values(me_master *M, const coupling_plan *P, int p, double t)
{
    const int end = P->run_end[p];
    const double dt = t - M->timed_t[M->spec->couplings[P->live[p]].source.instance];
    for (; p <= end; p++) {
        const int j = P->live[p];
        M->read[p] = M->timed_y[j] + M->timed_rate[j] * dt;
    }
}

/* The source values of the run of couplings from p (plan P) out of a linear instance:
   each its value at the last event plus d output / d input times each coupled input's
   change since, exact for a map with constant coefficients, and no call. */
static void linear_values(me_master *M, const coupling_plan *P, int p)
{
    const int end = P->run_end[p];
    const int i = M->spec->couplings[P->live[p]].source.instance;
    const int first = M->lin_in_start[i], n_in = M->lin_in_start[i + 1] - first;
    for (; p <= end; p++) {
        const int k = P->live[p];
        const double *row = M->lin_J + M->lin_row[k];
        double y = M->lin_y0[k];
        int a;
        for (a = 0; a < n_in; a++) {
            const int j = M->lin_in[first + a];
            y += row[a] * (M->lin_u[j] - M->lin_u0[j]);
        }
        M->read[p] = y;
    }
}

/* The couplings of plan P in continuous time, cheaply. They come in segments
   (plan_couplings):
   within one, no coupling reads an instance that another one in it sets, so all of a
   segment's outputs are read first and its inputs set afterwards. Each FMU thus
   evaluates its outputs once per segment instead of once per read after a set (an FMU
   drops what it computed whenever an input changes). The outputs of one source are
   read in one call, the changed inputs of one target are set in one call, and an input
   whose value did not change since it was last set is not set again (an FMU keeps a
   value until it is set: exact, and the FMU keeps what it computed from it). A plan
   holds only the couplings some evaluation between events needs; the event iteration
   propagates them all. */
static int couple(me_master *M, const coupling_plan *P, double t)
{
    const eng_coupling *c = M->spec->couplings;
    const int direct = P == &M->all; /* propagate(): every FMU read and set */
    int k, p, j, w, n = P->n_live;
    for (k = 0; k < n; k = P->segment_end[k] + 1) {
        int end = P->segment_end[k], target = -1, n_pending = 0;
        if (P->loop[k] >= 0) { /* a segment of its own (plan_couplings) */
            if (solve_loop(M, P->loop[k], t)) return -1;
            continue;
        }
        for (p = k; p <= end; p = P->run_end[p] + 1) {
            const eng_variable *source = &c[P->live[p]].source;
            int rc;
            if (M->timed[source->instance] && !direct) {
                timed_values(M, P, p, t);
                continue;
            }
            if (M->linear[source->instance] && !direct) {
                linear_values(M, P, p);
                continue;
            }
            rc = !ENG_PLAIN(source)
                         ? eng_get_value(M->fmus[source->instance], source, &M->read[p])
                         : fmu_get_float64(M->fmus[source->instance], P->source_vr + p,
                                           (size_t)(P->run_end[p] - p + 1), M->read + p);
            if (rc) return failed(M, source->instance, "reading a coupled output", t);
        }
        for (w = k; w <= end; w++) {
            double v;
            p = P->write_order[w];
            j = P->live[p];
            v = c[j].gain * M->read[p];
            if (M->linear[c[j].target.instance] && !direct) { /* set at events only */
                M->lin_u[j] = v;
                continue;
            }
            if (M->sent_valid && v == M->sent[j]) continue;
            if (c[j].target.instance != target && flush(M, target, &n_pending, t)) return -1;
            target = c[j].target.instance;
            if (!ENG_PLAIN(&c[j].target)) {
                if (eng_set_value(M->fmus[target], &c[j].target, v))
                    return failed(M, target, "setting a coupled input", t);
            } else {
                M->pending_vr[n_pending] = c[j].target.vr;
                M->pending_value[n_pending++] = v;
            }
            M->sent[j] = v;
        }
        if (flush(M, target, &n_pending, t)) return -1;
    }
    M->sent_valid = 1;
    return 0;
}

/* Whether the instances already stand at (t, x), coupled. */
static int at_point(const me_master *M, double t, const double *x)
{
    return M->set_valid && t == M->t_set &&
           (M->n_x == 0 || memcmp(x, M->x_set, (size_t)M->n_x * sizeof(double)) == 0);
}

/* Time and instance i's states (xi, its slice) on instance i: one call where its FMU
   is ours (mfEvaluateAt with nothing to read), since the two FMI calls through both
   sides' wrappers cost more than a small member's equations and an assembly makes them
   for every instance at every right-hand side (two_block_belt: 9 instances). Where it
   declines, the FMI calls follow and say why. */
static int move_one(me_master *M, int i, double t, const double *xi)
{
    const int nx = M->x_off[i + 1] - M->x_off[i];
    if (M->evaluate_at[i] && fmu_evaluate_at(M->fmus[i], t, xi, (size_t)nx, NULL, NULL, 0) == 0)
        return 0;
    if (fmu_set_time(M->fmus[i], t)) return failed(M, i, "setting the time", t);
    if (nx && fmu_set_continuous_states(M->fmus[i], xi, (size_t)nx))
        return failed(M, i, "setting the continuous states", t);
    return 0;
}

/* Time and states on every instance, or on those with only[i]. */
static int move_instances(me_master *M, double t, const double *x, const int *only)
{
    int i;
    for (i = 0; i < M->n; i++) {
        if (M->asleep[i]) continue; /* it stands where it fell asleep, for good */
        if (M->unmoved[i]) continue; /* moved at events only (move_unmoved) */
        if (only && !only[i]) continue;
        if (move_one(M, i, t, x + M->x_off[i])) return -1;
    }
    return 0;
}

/* Sets time and states on every instance and the couplings; skipped when the
   instances already stand at (t, x). */
static int set_point(me_master *M, double t, const double *x)
{
    if (at_point(M, t, x)) return 0;
    M->set_valid = 0;
    if (move_instances(M, t, x, NULL) || couple(M, &M->between, t)) return -1;
    M->t_set = t;
    if (M->n_x) memcpy(M->x_set, x, (size_t)M->n_x * sizeof(double));
    M->set_valid = 1;
    return 0;
}

/* What an output row needs at (t, x): where rows_partial, only the instances the
   recorded columns read and the couplings into them. The others stay where they
   were, so the next set_point moves everything. An output point costs a right-hand
   side's worth of FMI calls otherwise, for columns that often sit on a few instances. */
static int set_row_point(me_master *M, double t, const double *x)
{
    if (!M->rows_partial || at_point(M, t, x)) return set_point(M, t, x);
    M->set_valid = 0;
    return move_instances(M, t, x, M->row_instance) || couple(M, &M->rows, t) ? -1 : 0;
}

/* The one instance at (t, x) and its derivatives (dx) or indicators (z), in one call
   through mfEvaluateAt (fmu_evaluate_at): an FMU alone with nothing coupled needs no
   more, and the separate FMI calls cost more than a small model's right-hand side
   (stick_slip: 2 states, 5,028 right-hand sides at tolerance 1e-10). 0 on success;
   nonzero: the caller takes the separate calls, which say what failed. */
static int thin_point(me_master *M, double t, const double *x, double *dx, double *z)
{
    M->set_valid = 0;
    if (fmu_evaluate_at(M->fmus[0], t, x, (size_t)M->n_x, dx, z, (size_t)M->n_z)) return -1;
    M->t_set = t;
    if (M->n_x) memcpy(M->x_set, x, (size_t)M->n_x * sizeof(double));
    M->set_valid = 1;
    return 0;
}

static int rhs(void *ctx, double t, const double *x, double *dx)
{
    me_master *M = ctx;
    int i;
    M->stats->rhs_calls++;
    /* a trial point: evaluated off the instance, which stays where it stands (set_point's
       cache stays true); where that declines, the instance is moved there */
    if (M->thin && !M->asleep[0] &&
        ((M->off.fn && M->off.fn(M->off.instance, t, x, dx, NULL) == 0) ||
         thin_point(M, t, x, dx, NULL) == 0))
        return 0;
    if (set_point(M, t, x)) return -1;
    for (i = 0; i < M->n; i++) {
        int j;
        if (M->asleep[i]) {
            for (j = M->x_off[i]; j < M->x_off[i + 1]; j++) dx[j] = 0.0;
            continue;
        }
        if (M->timed[i]) {
            for (j = M->x_off[i]; j < M->x_off[i + 1]; j++) dx[j] = M->timed_dx[j];
            continue;
        }
        if (M->x_off[i + 1] > M->x_off[i] &&
            fmu_get_derivatives(M->fmus[i], dx + M->x_off[i],
                                (size_t)(M->x_off[i + 1] - M->x_off[i])))
            return failed(M, i, "getting the state derivatives", t);
    }
    return 0;
}

/* The run leaves the directional derivatives for finite differences, for good; with a
   format, eng_stats.jacobian_note says why, naming the instance. */
static void drop_exact(me_master *M, int instance, const char *format, ...)
{
    char *note = M->stats->jacobian_note;
    const size_t size = sizeof M->stats->jacobian_note;
    eng_jacobian_free(M->exact);
    M->exact = NULL;
    M->exact_wanted = 0;
    M->ros.banded = 0; /* differences know no structure: dense from here on */
    M->stats->exact_jacobian = 0;
    if (format && instance >= 0) {
        va_list args;
        int k = snprintf(note, size, "%s: ", fmu_instance_name(M->fmus[instance]));
        if (k < 0 || (size_t)k >= size) return;
        va_start(args, format);
        vsnprintf(note + k, size - (size_t)k, format, args);
        va_end(args);
    }
}

/* The directional derivatives see a timed instance's outputs move with its states; the
   right-hand side takes them from time (read_timed), so its columns are zero there and
   the time dependence is RODAS3's df/dt: the matrix of the function integrated. */
static void drop_timed_columns(const me_master *M, double *jac)
{
    int i;
    if (!M->any_timed) return;
    for (i = 0; i < M->n; i++)
        if (M->timed[i] && M->x_off[i + 1] > M->x_off[i])
            memset(jac + (size_t)M->x_off[i] * (size_t)M->n_x, 0,
                   (size_t)(M->x_off[i + 1] - M->x_off[i]) * (size_t)M->n_x * sizeof(double));
}

/* The directional derivatives' plan, at the first Jacobian a run needs: it follows
   every state's reach through the couplings, quadratic in the states of a composite
   FMU (every derivative on every state: a 256-block chain's took a tenth of a run that
   never asked for a Jacobian). A banded pattern (a chain) is factored in O(n_x) where
   that beats the dense O(n_x^3): a band of b diagonals costs about n_x b^2 against
   n_x^3 / 3. 0: planned or not wanted; -1: out of memory under jacobian='exact'
   (otherwise the run takes differences). */
static int plan_exact(me_master *M)
{
    int kl, ku;
    if (M->exact || !M->exact_wanted) return 0;
    M->exact = eng_jacobian_plan(M->spec, M->x_off);
    if (!M->exact) {
        drop_exact(M, -1, NULL);
        return M->spec->jacobian == ENG_JACOBIAN_EXACT
                   ? fail(M, "out of memory planning the Jacobian (jacobian='exact')") : 0;
    }
    eng_jacobian_bandwidth(M->exact, &kl, &ku);
    if ((double)(2 * kl + ku + 1) * (double)(kl + 1) * 3.0 < (double)M->n_x * (double)M->n_x) {
        M->ros.banded = 1;
        M->ros.kl = kl;
        M->ros.ku = ku;
    }
    return 0;
}

/* Column j of d f / d x at (t, x) by central differences with the step delta against
   exact[], the directional derivatives' column: 1 when they disagree (*worst: the row
   that disagrees most), 0 when they agree, -1 when the model fails. Central
   differences are exact for a quadratic; what else they carry is delta^2 f''' / 6 and
   the round-off of f, eps |f| / delta, so an entry off by more than 1e-3 of the
   column's largest and than 1000 times that round-off is the derivatives' error
   (*worst_cd: the differences' value there). */
static int column_disagrees(me_master *M, double t, const double *x, int j, double delta,
                            const double *exact, int *worst, double *worst_cd)
{
    const int n = M->n_x;
    double span, largest = 0.0, most = 0.0;
    int i, disagree = 0;
    memcpy(M->x_tmp, x, (size_t)n * sizeof(double));
    M->x_tmp[j] = x[j] + delta;
    span = M->x_tmp[j];
    if (rhs(M, t, M->x_tmp, M->fd)) return -1;
    M->x_tmp[j] = x[j] - delta;
    span -= M->x_tmp[j]; /* the steps actually taken */
    if (!(span > 0.0)) return 0; /* x_j too large for the step to tell */
    if (rhs(M, t, M->x_tmp, M->fd2)) return -1;
    for (i = 0; i < n; i++) {
        double cd = (M->fd[i] - M->fd2[i]) / span;
        largest = fmax(largest, fmax(fabs(cd), fabs(exact[i])));
    }
    for (i = 0; i < n; i++) {
        double cd = (M->fd[i] - M->fd2[i]) / span;
        double noise = 1e3 * DBL_EPSILON * fmax(fabs(M->fd[i]), fabs(M->fd2[i])) / span;
        double off = fabs(cd - exact[i]);
        if (off > 1e-3 * largest + noise && off - noise > most) {
            most = off - noise;
            *worst = i;
            *worst_cd = cd;
            disagree = 1;
        }
    }
    return disagree;
}

/* A foreign FMU's directional derivatives against central differences of the coupled
   right-hand side at the run's first point (ENG_JACOBIAN_AUTO): one exporter's are
   plainly wrong, and RODAS3 on a wrong Jacobian crawls, fails or drifts. A column that
   disagrees at the step cbrt(eps) scale and again at 1e-3 of it is wrong, not a steep
   feature the wider secant missed. Dropped for finite differences where they disagree or
   a call fails. 0: checked, -1: the model failed. */
static int probe_jacobian(me_master *M, double t)
{
    const int n = M->n_x;
    double *exact = M->ros.jac;
    int bad = -1, j, rc;
    if (plan_exact(M)) return -1;
    if (!M->exact) return 0;
    if (set_point(M, t, M->x)) return -1;
    rc = eng_jacobian_eval(M->exact, M->fmus, M->asleep, exact, &bad);
    if (rc < 0) {
        drop_exact(M, bad, "its directional derivatives failed at t = %.10g (%.300s)", t,
                   fmu_message(M->fmus[bad]));
        return 0;
    }
    if (rc > 0) return 0; /* a loop: the solver's first Jacobian finds it and falls back */
    drop_timed_columns(M, exact);
    for (j = 0; j < n; j++) {
        const double *column = exact + (size_t)j * (size_t)n;
        const double delta = cbrt(DBL_EPSILON) * fmax(fabs(M->x[j]), M->nominals[j]);
        int worst = -1, owner = 0, state = 0, wide, narrow;
        double cd = 0.0;
        wide = column_disagrees(M, t, M->x, j, delta, column, &worst, &cd);
        if (wide <= 0) {
            if (wide < 0) return -1;
            continue;
        }
        narrow = column_disagrees(M, t, M->x, j, 1e-3 * delta, column, &worst, &cd);
        if (narrow < 0) return -1;
        if (!narrow) continue;
        while (M->x_off[owner + 1] <= worst) owner++;
        while (M->x_off[state + 1] <= j) state++;
        /* the row's instance, unless it is ours and the seed came from a foreign one
           through a coupling */
        drop_exact(M, M->spec->instances[owner].foreign ? owner : state,
                   "its directional derivatives disagree with differences at t = %.10g: "
                   "d(derivative %d of %s)/d(state %d of %s) = %.6g, central differences "
                   "give %.6g", t, worst - M->x_off[owner], fmu_instance_name(M->fmus[owner]),
                   j - M->x_off[state], fmu_instance_name(M->fmus[state]), column[worst], cd);
        return 0;
    }
    return 0;
}

/* d f / d x: from the instances' directional derivatives carried through the
   couplings where every instance has them (jacobian.h says why), else by forward
   differences, column by column, which any FMU allows. An FMU that fails to give its
   derivatives, or couplings that do not settle, hand the run to finite differences
   for good (the failure noted), or fail it under ENG_JACOBIAN_EXACT. f(t, x) is the
   solver's own. */
static int jacobian(void *ctx, double t, const double *x, double *jac)
{
    me_master *M = ctx;
    const double *f0 = M->ros.f0;
    int i, j, n = M->n_x;
    if (plan_exact(M)) return -1;
    if (M->exact) {
        int bad = -1, rc;
        if (set_point(M, t, x)) return -1;
        rc = eng_jacobian_eval(M->exact, M->fmus, M->asleep, jac, &bad);
        if (rc == 0) {
            drop_timed_columns(M, jac);
            return 0;
        }
        if (M->spec->jacobian == ENG_JACOBIAN_EXACT)
            return rc < 0 ? failed(M, bad, "getting the directional derivatives "
                                           "(jacobian='exact')", t)
                          : fail(M, "jacobian='exact': the directional derivatives do not "
                                    "settle through the couplings at t = %.10g (an algebraic "
                                    "loop); 'fd' or 'auto' take differences", t);
        if (rc < 0)
            drop_exact(M, bad, "its directional derivatives failed at t = %.10g (%.300s)", t,
                       fmu_message(M->fmus[bad]));
        else
            drop_exact(M, -1, NULL);
    }
    if (M->n_loops) {
        /* the loops solved afresh at x too: f0 came from a solve to the loop tolerance,
           and a column of differences would carry that error over sqrt(eps) */
        forget_loop_matrices(M);
        M->set_valid = 0;
        if (rhs(M, t, x, M->fd2)) return -1;
        f0 = M->fd2;
    }
    memcpy(M->x_tmp, x, (size_t)n * sizeof(double));
    for (j = 0; j < n; j++) {
        double delta = sqrt(DBL_EPSILON) * fmax(fabs(x[j]), M->nominals[j]);
        M->x_tmp[j] = x[j] + delta;
        delta = M->x_tmp[j] - x[j]; /* the step actually taken */
        if (rhs(M, t, M->x_tmp, M->fd)) return -1;
        for (i = 0; i < n; i++) jac[(size_t)j * n + i] = (M->fd[i] - f0[i]) / delta;
        M->x_tmp[j] = x[j];
    }
    return 0;
}

static int indicators_at(me_master *M, double t, const double *x, double *z)
{
    int i;
    if (M->thin && !M->asleep[0] && M->n_z &&
        ((M->off.fn && M->off.fn(M->off.instance, t, x, NULL, z) == 0) ||
         thin_point(M, t, x, NULL, z) == 0))
        return 0;
    if (set_point(M, t, x)) return -1;
    for (i = 0; i < M->n; i++)
        if (M->z_off[i + 1] > M->z_off[i] &&
            fmu_get_event_indicators(M->fmus[i], z + M->z_off[i],
                                     (size_t)(M->z_off[i + 1] - M->z_off[i])))
            return failed(M, i, "getting the event indicators", t);
    return 0;
}

/* --- the solver ---------------------------------------------------------------- */

/* Whether output row k is due before `limit` (or at it, when inclusive). */
static int row_due(const eng_me_spec *s, long k, double limit, int inclusive)
{
    return k < s->n_times && (s->times[k] < limit || (inclusive && s->times[k] <= limit));
}

/* No step longer than spec->max_step (Python gives the output interval where an
   indicator can move while the states stand still: through another FMU's outputs, or
   with time). While a contact sticks the states are constant and the steps grow without
   limit, but a shaken table's acceleration still moves the static margin: a 0.1 s
   excursion inside a 3 s step slips between the interior samples. Output points still
   come from the dense output; no step is made to end on one. Without indicators there
   is nothing to miss, and the solver steps freely: INFINITY. */
static double step_cap(const me_master *M)
{
    return M->spec->max_step > 0 && M->n_z > 0 ? M->spec->max_step : INFINITY;
}

static void dense(const me_master *M, double t, double *x)
{
    if (M->dense_implicit) mf_ros_dense(&M->ros, t, x);
    else if (M->high_order) eng_dop853_dense(&M->dop853, t, x);
    else mf_dopri_dense(&M->dopri, t, x);
}

/* State j of the dense output alone (emit_states_until) */
static double dense_one(const me_master *M, double t, int j)
{
    if (M->dense_implicit) return mf_ros_dense_one(&M->ros, t, j);
    if (M->high_order) return eng_dop853_dense_one(&M->dop853, t, j);
    return mf_dopri_dense_one(&M->dopri, t, j);
}

/* mf_indicator_fn: the indicators inside the last accepted step */
static int indicators_inside(void *ctx, double t, double *z)
{
    me_master *M = ctx;
    dense(M, t, M->x_tmp);
    return indicators_at(M, t, M->x_tmp, z);
}

/* Instance k's part of the dense output of the last accepted step, into x: the
   solvers' own interpolation on the slice (a shallow copy whose coefficient rows start
   at k's states), so that a local evaluation costs what k has, not the assembly. */
static void dense_part(const me_master *M, double t, double *x, int k)
{
    int lo = M->x_off[k], n = M->x_off[k + 1] - lo, j;
    if (n == 0) return;
    if (M->dense_implicit) {
        mf_ros part = M->ros;
        part.n = n;
        part.dx0 += lo; part.dx1 += lo; part.dc0 += lo; part.dc1 += lo;
        mf_ros_dense(&part, t, x + lo);
    } else if (M->high_order) {
        eng_dop853 part = M->dop853;
        part.n = n;
        for (j = 0; j < 8; j++) part.r[j] += lo;
        eng_dop853_dense(&part, t, x + lo);
    } else {
        mf_dopri part = M->dopri;
        part.n = n;
        for (j = 0; j < 5; j++) part.r[j] += lo;
        mf_dopri_dense(&part, t, x + lo);
    }
}

typedef struct {
    me_master *M;
    int instance;
} local_ctx;

/* Instance i asks for its indicators at t inside the step: k > 0 when they are (or are
   now put) in the whole-assembly evaluation shared_z row k - 1, 0 when i evaluates its
   own, -1 on failure. Every instance's location of one step asks for the same two
   times (the quiet test's, events.h) and those inside a step that is not quiet for
   the same samples; an instance's own evaluation moves it and its sources (a chain's
   block: six instances), so where the step before had shared_from or more instances
   asking at the same rank, this time is evaluated once on the whole assembly instead.
   The values are the same either way: the dense output is the same per state, and an
   instance's indicators read only the couplings of its own plan. */
static int shared_point(me_master *M, int i, double t)
{
    int r, k;
    for (k = 0; k < M->n_shared; k++)
        if (M->shared_t[k] == t) break;
    for (r = 0; r < M->n_ask && M->ask_t[r] != t; r++) {}
    if (r == M->n_ask && r < SHARED_RANKS) {
        M->ask_t[r] = t;
        M->ask_count[r] = 0;
        M->ask_last[r] = -1;
        M->n_ask++;
    }
    if (r < M->n_ask && M->ask_last[r] != i) {
        M->ask_count[r]++;
        M->ask_last[r] = i;
    }
    if (k < M->n_shared) return k + 1;
    if (r >= M->n_ask || M->prev_count[r] < M->shared_from || k >= SHARED_SLOTS) return 0;
    dense(M, t, M->x_tmp);
    if (indicators_at(M, t, M->x_tmp, M->shared_z + (size_t)k * (size_t)M->n_z)) return -1;
    M->shared_t[k] = t;
    M->n_shared++;
    return k + 1;
}

/* mf_indicator_fn: one instance's indicators inside the last accepted step, with only
   it and the instances its indicators read moved there (the others stay where they
   were: the next set_point moves everything). */
static int local_indicators(void *ctx, double t, double *z)
{
    const local_ctx *L = ctx;
    me_master *M = L->M;
    const int i = L->instance;
    int a, shared = shared_point(M, i, t);
    if (shared < 0) return -1;
    if (shared) {
        memcpy(z, M->shared_z + (size_t)(shared - 1) * (size_t)M->n_z + M->z_off[i],
               (size_t)(M->z_off[i + 1] - M->z_off[i]) * sizeof(double));
        return 0;
    }
    M->set_valid = 0;
    for (a = M->local_start[i]; a < M->local_start[i + 1]; a++) {
        const int k = M->local_instance[a];
        if (M->asleep[k] || M->unmoved[k]) continue;
        dense_part(M, t, M->x_tmp, k);
        if (move_one(M, k, t, M->x_tmp + M->x_off[k])) return -1;
    }
    if (couple(M, &M->local[i], t)) return -1;
    if (fmu_get_event_indicators(M->fmus[i], z, (size_t)(M->z_off[i + 1] - M->z_off[i])))
        return failed(M, i, "getting the event indicators", t);
    return 0;
}

/* The earliest crossing in (t_old, t] (mf_locate_event's result; M->z_hit: every
   indicator there). Per instance where the spec allows it: a step in which block 7
   slips then costs block 7's and its neighbours' evaluations, not the chain's, and an
   instance whose indicators stay clear of zero costs two of its own. */
static int locate(me_master *M, double t_old, double t, double *t_event)
{
    const eng_me_spec *s = M->spec;
    int i, r, found = 0;
    if (!M->local)
        return mf_locate_event(indicators_inside, M, M->n_z, t_old, M->z_prev, t, M->z_now,
                               s->event_subsamples, t_event, M->z_hit, M->z_work);
    /* this step's asks predict the next's (shared_point) */
    for (r = 0; r < SHARED_RANKS; r++) M->prev_count[r] = r < M->n_ask ? M->ask_count[r] : 0;
    M->n_ask = M->n_shared = 0;
    for (i = 0; i < M->n; i++) {
        const int off = M->z_off[i], nz = M->z_off[i + 1] - off;
        local_ctx L = {M, i};
        double te;
        int r;
        if (nz == 0) continue;
        r = mf_locate_event(local_indicators, &L, nz, t_old, M->z_prev + off, t, M->z_now + off,
                            s->event_subsamples, &te, M->z_hit + off, M->z_work);
        if (r < 0) return -1;
        if (r && (!found || te < *t_event)) {
            *t_event = te;
            found = 1;
        }
    }
    if (found) { /* every indicator at the earliest crossing: the ones that crossed by then */
        dense(M, *t_event, M->x_tmp);
        if (indicators_at(M, *t_event, M->x_tmp, M->z_hit)) return -1;
    }
    return found;
}

/* The explicit method's restart, step and step-size proposal: DOP853's where
   M->high_order, else DOPRI5's. */
static void explicit_restart(me_master *M)
{
    if (M->high_order) eng_dop853_restart(&M->dop853);
    else mf_dopri_restart(&M->dopri);
}

/* f at the current point, evaluated by someone else, as the explicit method's first
   stage of the next step (which it then does not evaluate); a non-finite one is left
   for the solver to find and report */
static void explicit_take_first_stage(me_master *M, const double *f)
{
    int i;
    if (M->stiff.implicit) return;
    for (i = 0; i < M->n_x; i++)
        if (!isfinite(f[i])) return;
    if (M->high_order) {
        memcpy(M->dop853.k[0], f, (size_t)M->n_x * sizeof(double));
        M->dop853.fsal_valid = 1;
    } else {
        memcpy(M->dopri.k[0], f, (size_t)M->n_x * sizeof(double));
        M->dopri.fsal_valid = 1;
    }
}

static double *explicit_h_guess(me_master *M)
{
    return M->high_order ? &M->dop853.h_guess : &M->dopri.h_guess;
}

static void restart(me_master *M)
{
    explicit_restart(M);
    mf_ros_restart(&M->ros);
}

/* One accepted explicit step, as mf_dopri_step. DOP853's continuous extension is made
   where something reads inside the step: a row before its end, or event location. */
static int explicit_step(me_master *M, double *t, double t_end, double h_initial)
{
    const double t0 = *t;
    int r;
    if (!M->high_order)
        return mf_dopri_step(&M->dopri, rhs, M, t, M->x, t_end, M->spec->tolerance, h_initial);
    r = eng_dop853_step(&M->dop853, rhs, M, t, M->x, t_end, M->spec->tolerance, h_initial);
    if (r == MF_DOPRI_OK && (M->n_z > 0 || row_due(M->spec, M->k_out, *t, 0)) &&
        eng_dop853_dense_prepare(&M->dop853, rhs, M)) {
        /* the step stands; f failed at a point of its continuous extension. The member's
           reason is copied first: fail() writes M->message */
        char why[sizeof M->message];
        snprintf(why, sizeof why, "%s", M->message[0] ? M->message : "not finite");
        fail(M, "the model could not be evaluated inside the step from t = %.10g to %.10g "
                "(DOP853's continuous extension): %.800s", t0, *t, why);
        return -1;
    }
    return r;
}

/* The Jacobian at the point an explicit step reached, into the implicit solver's
   matrix (the periodic stiffness check): the forward differences need f there, which
   the explicit method holds as the next step's first stage. */
static int explicit_jacobian(me_master *M, double t)
{
    memcpy(M->ros.f0, M->high_order ? M->dop853.k[0] : M->dopri.k[0],
           (size_t)M->n_x * sizeof(double));
    return jacobian(M, t, M->x, M->ros.jac);
}

/* "auto" at a tight tolerance starts with DOP853 and leaves it for DOPRI5 for good once
   events come every few steps: each event restarts the method, a step between two close
   events is short whatever its order, and DOP853's costs 12 evaluations (15 with the
   dense output event location reads) against DOPRI5's 6. Fewer than EVENT_DENSE_STEPS
   accepted steps per event, counted from EVENT_DENSE_AFTER events on: the
   Burridge-Knopoff chain (n = 250, 1e-10) has 1.1 and took 79,928 evaluations with
   DOP853 against 34,757; stick_slip at 1e-9 has 4.7 and gains (0.62 of DOPRI5's). */
enum { EVENT_DENSE_STEPS = 3, EVENT_DENSE_AFTER = 8 };

static void leave_high_order_where_events_are_dense(me_master *M)
{
    const eng_stats *st = M->stats;
    if (!M->high_order || M->spec->method != ENG_AUTO || st->events < EVENT_DENSE_AFTER ||
        st->steps >= EVENT_DENSE_STEPS * st->events)
        return;
    M->high_order = 0;
    M->left_high_order = 1;
    M->dopri.h_guess = M->dop853.h_guess;
    mf_dopri_restart(&M->dopri);
    if (M->dop853.fsal_valid) explicit_take_first_stage(M, M->dop853.k[0]);
}

/* One accepted step from (*t, x) towards t_end; 0 on success. */
static int step(me_master *M, double *t, double t_end, double h_initial)
{
    const double t0 = *t;
    /* a sliver shorter than the solvers' smallest step is one Euler step, which says
       nothing about stiffness */
    const int automatic = M->spec->method == ENG_AUTO && t_end - t0 >= MF_MIN_STEP(t0);
    int r;
    M->message[0] = '\0';
    leave_high_order_where_events_are_dense(M);
    if (M->stiff.implicit) {
        r = mf_ros_step(&M->ros, rhs, jacobian, M, t, M->x, t_end, M->spec->tolerance, h_initial);
        if (r == MF_ROS_OK) {
            M->dense_implicit = 1;
            if (automatic && mf_stiffness_after_implicit(&M->stiff, *t - t0, M->ros.jac,
                                                         M->n_x)) {
                explicit_restart(M);
                *explicit_h_guess(M) = M->ros.h_guess;
            }
            return 0;
        }
        r = r == MF_ROS_RHS_FAILED ? MF_DOPRI_RHS_FAILED : MF_DOPRI_STEP_UNDERFLOW;
    } else {
        r = explicit_step(M, t, t_end, h_initial);
        if (r < 0) return -1;
        if (r == MF_DOPRI_OK) {
            /* stiffness.h judges by DOPRI5's stability interval: DOP853's, wider, gives
               its h |lambda| and its proposal in DOPRI5's terms */
            const double scale = M->high_order ? ENG_DOP853_EDGE_RATIO : 1.0;
            const double h_lambda =
                scale * (M->high_order ? M->dop853.h_lambda : M->dopri.h_lambda);
            const double h_check = scale * *explicit_h_guess(M);
            M->dense_implicit = 0;
            if (automatic && (mf_stiffness_after_explicit(&M->stiff, *t - t0, h_lambda)
                              || (mf_stiffness_wants_jacobian(&M->stiff)
                                  && explicit_jacobian(M, *t) == 0
                                  && mf_stiffness_explicit_check(&M->stiff, h_check,
                                                                 M->ros.jac, M->n_x)))) {
                mf_ros_restart(&M->ros);
                M->ros.h_guess = *explicit_h_guess(M);
            }
            return 0;
        }
    }
    if (r == MF_DOPRI_RHS_FAILED && M->message[0]) {
        /* the member's reason is in M->message, which fail() writes: copied first, as
           vsnprintf from a buffer into itself is undefined (and garbled the line) */
        char why[sizeof M->message];
        snprintf(why, sizeof why, "%s", M->message);
        return fail(M, "the solver cannot go on from t = %.10g: %.900s", *t, why);
    }
    /* a non-finite derivative inside a step is mostly a trial step that overshot: an
       explicit method on a stiff coupling; say that before blaming the user's values */
    if (r == MF_DOPRI_RHS_FAILED)
        return fail(M, "the state derivatives are not finite at or just after t = %.10g "
                       "(tolerance %g): a trial step left the model's range, as an explicit "
                       "method's does on a stiff model%s, or a parameter or input drives the "
                       "model out of its range", *t, M->spec->tolerance,
                    M->stiff.implicit ? ""
                        : " (method RODAS3, implicit, takes stiff models)");
    return fail(M, "the step size fell below %g at t = %.10g (tolerance %g): the model is "
                   "too stiff or discontinuous here", MF_MIN_STEP(*t), *t,
                M->spec->tolerance);
}

/* --- outputs ------------------------------------------------------------------- */

static int settle_linear(me_master *M, double t, int recorded);

/* Where column c's value is among the states (rows_from_states). */
static int recorded_state(const me_master *M, int c)
{
    return M->x_off[M->spec->columns[c].instance] + M->spec->column_state[c];
}

static int write_row(me_master *M, double t, const double *x)
{
    const eng_me_spec *s = M->spec;
    double *row = s->out + (size_t)M->k_out * (size_t)s->n_columns;
    int c;
    /* standing at (t, x) is not enough for an FMU that computes its outputs in
       fmiSetTime from the states it holds then: set once more, now that they are x */
    if (!M->rows_from_states &&
        (set_row_point(M, t, x) || (M->any_set_again && move_instances(M, t, x, M->set_again))
         || (M->any_lin_recorded && settle_linear(M, t, 1))))
        return -1;
    for (c = 0; c < s->n_columns; c++) {
        const eng_variable *v = &s->columns[c];
        if (M->rows_from_states)
            row[c] = x[recorded_state(M, c)];
        else if (eng_get_value(M->fmus[v->instance], v, &row[c]))
            return failed(M, v->instance, "reading the recorded outputs", t);
    }
    M->k_out++;
    M->stats->n_rows = M->k_out;
    return 0;
}

/* Rows whose columns are a few of many states (rows_by_state), interpolated straight
   into the table: each the value the whole dense output gives, without its other states
   and write_row's general path (a short run's rows cost it more than its steps). */
static void emit_states_until(me_master *M, double limit, int inclusive)
{
    const eng_me_spec *s = M->spec;
    long k = M->k_out;
    int c;
    while (row_due(s, k, limit, inclusive)) {
        const double t = s->times[k];
        double *row = s->out + (size_t)k * (size_t)s->n_columns;
        for (c = 0; c < s->n_columns; c++) {
            const int j = recorded_state(M, c);
            row[c] = dense_one(M, t, j);
        }
        k++;
    }
    M->k_out = k;
    M->stats->n_rows = k;
}

/* Output rows at the times before `limit` (and at it when inclusive), from the dense
   output of the last step, or from x itself when dense_output is 0. */
static int emit_until(me_master *M, double limit, int inclusive, int dense_output)
{
    const eng_me_spec *s = M->spec;
    if (dense_output && M->rows_by_state) {
        emit_states_until(M, limit, inclusive);
        return 0;
    }
    while (row_due(s, M->k_out, limit, inclusive)) {
        double t = s->times[M->k_out];
        const double *x = M->x;
        if (dense_output) {
            dense(M, t, M->x_tmp);
            x = M->x_tmp;
        }
        if (write_row(M, t, x)) return -1;
    }
    return 0;
}

/* Whether instance i's states are as the step found them (and, with `f`, their
   derivatives exactly zero). */
static int still(const me_master *M, int i, const double *f)
{
    int j;
    for (j = M->x_off[i]; j < M->x_off[i + 1]; j++)
        if (M->x_start[j] != M->x[j] || (f && f[j] != 0.0)) return 0;
    return 1;
}

static int group_still(const me_master *M, int group, const double *f)
{
    int i;
    for (i = 0; i < M->n; i++)
        if (M->spec->rest_group[i] == group && !M->asleep[i] && !still(M, i, f)) return 0;
    return 1;
}

/* After a step without events from `x_start`, or an event (x_start its point): puts to
   sleep each group whose states the step left as they were with every derivative exactly
   zero (eng_me_spec.rest_group). 1 when every instance sleeps, 0 when not, -1 on failure.
   The derivatives are only evaluated where some group's states stood still; then
   M->fd holds f(t, x) and *evaluated (where given) is 1. */
static int fall_asleep(me_master *M, double t, int *evaluated)
{
    const int *group = M->spec->rest_group;
    int i, all = 1, candidate = 0, slept = 0;
    if (evaluated) *evaluated = 0;
    if (!group || M->n_x == 0 || M->next_defined) return 0;
    for (i = 0; i < M->n && !candidate; i++)
        candidate = !M->asleep[i] && group[i] >= 0 && group_still(M, group[i], NULL);
    if (!candidate) return 0;
    if (rhs(M, t, M->x, M->fd)) return -1;
    if (evaluated) *evaluated = 1;
    for (i = 0; i < M->n; i++) {
        if (!M->asleep[i] && group[i] >= 0 && group_still(M, group[i], M->fd)) {
            M->asleep[i] = slept = 1;
            if (M->spec->asleep_since) M->spec->asleep_since[i] = t;
        }
        all = all && M->asleep[i];
    }
    if (!all) M->set_valid = 0; /* the sleepers are skipped from now on */
    /* and their rows of the Jacobian are zero, not those RODAS3 evaluated ahead */
    if (!all && slept) mf_ros_restart(&M->ros);
    return all;
}

/* The rows left, all equal to the point (t, x) the system rests at for good. */
static int rest_rows(me_master *M)
{
    const eng_me_spec *s = M->spec;
    const size_t width = (size_t)s->n_columns;
    const double *first;
    if (M->k_out >= s->n_times) return 0;
    /* an autonomous instance's outputs do not depend on the time it is given */
    if (write_row(M, s->times[M->k_out], M->x)) return -1;
    first = s->out + (size_t)(M->k_out - 1) * width;
    for (; M->k_out < s->n_times; M->k_out++)
        memcpy(s->out + (size_t)M->k_out * width, first, width * sizeof(double));
    M->stats->n_rows = M->k_out;
    return 0;
}

/* Reads each run of Float64 scalars in one call, any other value by itself: an event's
   row is a dozen outputs, and a call each cost about as much as locating the event
   (stick_slip's composite: 12 calls per event, now 2: its Float64s and its mode). */
#define EVENT_ROW_BATCH 64
static int record_event(me_master *M, int g, double t)
{
    const eng_event_group *group = &M->spec->event_groups[g];
    fmu_t *f = M->fmus[group->instance];
    uint32_t vr[EVENT_ROW_BATCH];
    int k = 0, j;
    M->row[0] = t;
    while (k < group->n_outputs) {
        for (j = 0; j < EVENT_ROW_BATCH && k + j < group->n_outputs &&
                    ENG_PLAIN(&group->outputs[k + j]); j++)
            vr[j] = group->outputs[k + j].vr;
        if (j > 0 ? fmu_get_float64(f, vr, (size_t)j, &M->row[1 + k])
                  : eng_get_value(f, &group->outputs[k], &M->row[1 + k]))
            return failed(M, group->instance, "reading the outputs at an event", t);
        k += j > 0 ? j : 1;
    }
    if (eng_table_append(&M->run->tables[g], M->row))
        return fail(M, "out of memory recording events");
    return 0;
}

/* --- events -------------------------------------------------------------------- */

/* The instances not moved between events, at (t, x): where an event or the caller
   reads them. */
static int move_unmoved(me_master *M, double t, const double *x)
{
    int i;
    for (i = 0; i < M->n && M->any_unmoved; i++)
        if (M->unmoved[i] && !M->asleep[i] && move_one(M, i, t, x + M->x_off[i])) return -1;
    return 0;
}

static int plan_couplings(me_master *M, coupling_plan *P, const int *needed);

/* The plans between events without the couplings out of timed instances whose value
   stands still until the next event (rate 0: a wall's position, a belt's speed): the
   event iteration has set them, nothing else sets their inputs, and evaluating them at
   every point only finds them unchanged (two_block_belt: 10 of its 22). */
static int needed_between(const me_master *M, int j)
{
    const eng_me_spec *s = M->spec;
    return (!s->continuous || s->continuous[j]) &&
           !(M->timed[s->couplings[j].source.instance] && M->timed_rate[j] == 0.0);
}

static int plan_between(me_master *M)
{
    const eng_me_spec *s = M->spec;
    int j, changed = 0;
    for (j = 0; j < s->n_couplings; j++) {
        const int needed = needed_between(M, j);
        changed = changed || needed != M->needed[j];
        M->needed[j] = needed;
    }
    if (!changed) return 0;
    if (plan_couplings(M, &M->between, M->needed)) return -1;
    if (!M->rows_partial || !s->row_coupling) return 0;
    for (j = 0; j < s->n_couplings; j++) M->needed[j] = M->needed[j] && s->row_coupling[j];
    if (plan_couplings(M, &M->rows, M->needed)) return -1;
    for (j = 0; j < s->n_couplings; j++) M->needed[j] = needed_between(M, j); /* for the next */
    return 0;
}

/* Each linear instance's FMU (recorded: those with a recorded column) given the inputs
   the couplings have brought it to since the last event: where an event, an output row
   or the caller reads it. */
static int settle_linear(me_master *M, double t, int recorded)
{
    const eng_coupling *c = M->spec->couplings;
    int i, a;
    for (i = 0; i < M->n && M->any_linear; i++) {
        const int first = M->lin_in_start[i], n_in = M->lin_in_start[i + 1] - first;
        if (!M->linear[i] || n_in == 0 || (recorded && !M->lin_recorded[i])) continue;
        for (a = 0; a < n_in; a++) {
            const int j = M->lin_in[first + a];
            M->pending_vr[a] = c[j].target.vr;
            M->pending_value[a] = M->sent[j] = M->lin_u[j];
        }
        if (fmu_set_float64(M->fmus[i], M->pending_vr, (size_t)n_in, M->pending_value))
            return failed(M, i, "setting coupled inputs", t);
    }
    return 0;
}

/* A linear instance's coefficients at the event just settled (t): each coupled input as
   the event iteration set it, each coupled output's value, and its directional
   derivative along each coupled input. An instance whose reads fail is evaluated as any
   other from here on: this saves calls, it decides nothing. */
static void read_linear(me_master *M, double t)
{
    const eng_coupling *c = M->spec->couplings;
    const double one = 1.0;
    int i, a, b;
    for (i = 0; i < M->n && M->any_linear; i++) {
        const int first = M->lin_in_start[i], n_in = M->lin_in_start[i + 1] - first;
        const int out = M->out_start[i], n_out = M->out_start[i + 1] - out;
        fmu_t *f = M->fmus[i];
        const int was_ready = M->lin_ready[i];
        int ok;
        if (!M->linear[i]) continue;
        for (a = 0; a < n_in; a++) {
            const int j = M->lin_in[first + a];
            M->lin_u[j] = M->lin_u0[j] = M->sent[j]; /* what the last propagation set */
        }
        ok = fmu_get_float64(f, M->out_vr + out, (size_t)n_out, M->pending_value) == 0;
        for (b = 0; b < n_out && ok; b++) {
            const int k = M->out_list[out + b];
            M->lin_y0[k] = M->pending_value[b];
            for (a = 0; a < n_in && ok && !M->lin_ready[i]; a++) {
                double *entry = M->lin_J + M->lin_row[k] + a;
                ok = fmu_directional_derivative(f, &c[k].source.vr, 1,
                                                &c[M->lin_in[first + a]].target.vr, 1, &one,
                                                entry) == 0 && isfinite(*entry);
            }
        }
        M->lin_ready[i] = ok;
        if (!ok) { /* its inputs are as sent[] says: set from here on */
            M->linear[i] = 0;
            if (M->spec->taken_until) M->spec->taken_until[i] = was_ready ? t : NAN;
        }
    }
}

/* A timed instance's constants at the event just settled (t): its derivatives, and for
   each coupling out of it the source's value and rate (the directional derivative of the
   output along the derivatives: exact, as the output is affine in the states and free
   of time). An instance whose reads fail, or with a coupled value of another kind, is
   evaluated as any other from here on: this saves calls, it decides nothing. */
static int read_timed(me_master *M, double t, int only_part)
{
    const eng_me_spec *s = M->spec;
    int i, j, b;
    for (i = 0; i < M->n && M->any_timed; i++) {
        const int lo = M->x_off[i], nx = M->x_off[i + 1] - lo;
        fmu_t *f = M->fmus[i];
        const int was_read = !isnan(M->timed_t[i]);
        int ok;
        if (!M->timed[i] || (only_part && !M->part[i])) continue;
        M->timed_t[i] = t;
        ok = !nx || fmu_get_derivatives(f, M->timed_dx + lo, (size_t)nx) == 0;
        for (b = M->out_start[i]; b < M->out_start[i + 1] && ok; b++) {
            const eng_variable *v = &s->couplings[j = M->out_list[b]].source;
            M->timed_rate[j] = 0.0;
            ok = ENG_PLAIN(v) && fmu_get_float64(f, &v->vr, 1, &M->timed_y[j]) == 0 &&
                 (!nx || fmu_directional_derivative(f, &v->vr, 1, s->instances[i].state_vr,
                                                    (size_t)nx, M->timed_dx + lo,
                                                    &M->timed_rate[j]) == 0) &&
                 isfinite(M->timed_rate[j]);
        }
        if (!ok) { /* moved with the others from the next set_point on */
            M->timed[i] = 0;
            M->unmoved[i] = M->spec->time_free && M->spec->time_free[i] && nx == 0;
            if (s->taken_until) s->taken_until[i] = was_read ? t : NAN;
        }
    }
    return M->any_timed && plan_between(M) ? fail(M, "out of memory") : 0;
}

static int unsettled(me_master *M, double t)
{
    return fail(M, "the event iteration at t = %.10g does not settle between the connected "
                   "FMUs", t);
}

/* Instance i's discrete updates at t until it needs no more; its own next time event
   is the earliest any of them asks for in this event (next_def[i] is reset when it
   joins the event). */
static int update_one(me_master *M, int i, double t)
{
    fmu_event_info info;
    int k;
    for (k = 0; k < MAX_EVENT_ITERATIONS; k++) {
        if (fmu_update_discrete_states(M->fmus[i], &info))
            return failed(M, i, "updating the discrete states", t);
        if (info.terminate && !M->terminate) {
            M->terminate = 1;
            M->stats->terminated_by = i;
            snprintf(M->stats->message, sizeof M->stats->message, "%s", fmu_message(M->fmus[i]));
        }
        if (info.next_time_defined && (!M->next_def[i] || info.next_time < M->next_t[i])) {
            M->next_def[i] = 1;
            M->next_t[i] = info.next_time;
        }
        if (!info.needs_more) return 0;
    }
    return fail(M, "%s: discrete states do not settle at t = %.10g",
                fmu_instance_name(M->fmus[i]), t);
}

/* The earliest time event any instance asked for. */
static void next_time(me_master *M)
{
    int i;
    M->next_defined = 0;
    for (i = 0; i < M->n; i++)
        if (M->next_def[i] && (!M->next_defined || M->next_t[i] < M->t_next)) {
            M->next_defined = 1;
            M->t_next = M->next_t[i];
        }
}

/* Back to continuous time with the states re-read into M->x, each instance that took
   part; the event groups flagged in group_changed record their outputs. */
static int leave_event(me_master *M, double t)
{
    int a, i;
    for (i = 0; i < M->spec->n_event_groups; i++)
        if (M->group_changed[i] && record_event(M, i, t)) return -1;
    for (a = 0; a < M->n_part; a++) {
        i = M->part_list[a];
        if (fmu_enter_continuous_time_mode(M->fmus[i]))
            return failed(M, i, "entering continuous time mode", t);
        if (fmu_get_continuous_states(M->fmus[i], M->x + M->x_off[i],
                                      (size_t)(M->x_off[i + 1] - M->x_off[i])))
            return failed(M, i, "getting the continuous states", t);
    }
    M->stats->event_instances += M->n_part;
    next_time(M);
    return 0;
}

/* Instance k ready to be read or given inputs in a local event: moved to (t, x) where
   it is moved at events only, and a linear map's FMU given the inputs the couplings
   brought it to since the last event (both skipped for the instances no event touches:
   move_unmoved and settle_linear cost a call per instance). */
static int prepare(me_master *M, int k, double t)
{
    const eng_coupling *c = M->spec->couplings;
    int a;
    if (M->prepared[k]) return 0;
    M->prepared[k] = 1;
    M->prepared_list[M->n_prepared++] = k;
    if (M->unmoved[k] && !M->asleep[k] && move_one(M, k, t, M->x + M->x_off[k])) return -1;
    if (M->linear[k]) {
        const int first = M->lin_in_start[k], n_in = M->lin_in_start[k + 1] - first;
        for (a = 0; a < n_in; a++) {
            const int j = M->lin_in[first + a];
            M->pending_vr[a] = c[j].target.vr;
            M->pending_value[a] = M->sent[j] = M->lin_u[j];
        }
        if (n_in && fmu_set_float64(M->fmus[k], M->pending_vr, (size_t)n_in, M->pending_value))
            return failed(M, k, "setting coupled inputs", t);
    }
    return 0;
}

/* Instance k joins the event: event mode, from continuous time (FMI 2 and 3 ME). */
static int take_part(me_master *M, int k, double t)
{
    if (M->part[k]) return 0;
    if (prepare(M, k, t)) return -1;
    if (fmu_enter_event_mode(M->fmus[k])) return failed(M, k, "entering event mode", t);
    M->part[k] = 1;
    M->part_list[M->n_part++] = k;
    M->next_def[k] = 0;
    return 0;
}

/* One pass of the couplings in order (a source's inputs are set before it is read: no
   loops here), reading only the sources whose outputs can have changed: those that
   take part, those whose inputs this pass changed, and the couplings the evaluation
   between events leaves to the events (eng_me_spec.continuous). Every other coupled
   value is what its target holds (sent[], or lin_u[] for a linear map's inputs, which
   its FMU gets when prepared). A changed value is set; its target takes part first
   unless it is passive and the input is a continuous one, which FMI lets an instance
   take in continuous time. *changed: some value changed. */
static int local_pass(me_master *M, double t, int *changed)
{
    const eng_me_spec *s = M->spec;
    const eng_coupling *c = s->couplings;
    int j, a;
    *changed = 0;
    for (j = 0; j < s->n_couplings; j++) {
        const int src = c[j].source.instance, k = c[j].target.instance;
        double v, held;
        if (!(M->part[src] || M->touched[src] || (s->continuous && !s->continuous[j])))
            continue;
        if (prepare(M, src, t)) return -1;
        if (eng_get_value(M->fmus[src], &c[j].source, &v))
            return failed(M, src, "reading a coupled output", t);
        v *= c[j].gain;
        held = M->linear[k] ? M->lin_u[j] : M->sent[j];
        if (memcmp(&v, &held, sizeof v) == 0) continue; /* as the whole iteration compares */
        if (!M->passive[k] || !ENG_CONTINUOUS_TYPE(c[j].target.type)) {
            if (take_part(M, k, t)) return -1;
        } else if (prepare(M, k, t)) return -1;
        if (eng_set_value(M->fmus[k], &c[j].target, v))
            return failed(M, k, "setting a coupled input", t);
        M->sent[j] = v;
        if (M->linear[k]) M->lin_u[j] = v;
        M->touched[k] = 1;
        *changed = 1;
    }
    for (a = 0; a < M->n_prepared; a++) M->touched[M->prepared_list[a]] = 0;
    return 0;
}

/* An event that costs what it touches: the instances whose indicators crossed or sit
   at zero (z_at: every indicator at (t, M->x) before the event), whose time event is
   due or that asked for a step event take part, and then, pass by pass, every instance
   whose coupled inputs the updates change, unless it is passive (it has nothing to
   update and takes continuous inputs in continuous time). The others see no call: their
   states, modes and outputs stand as they were, which is what a whole-assembly
   iteration would find for them too. */
static int event_local(me_master *M, double t, const double *z_at)
{
    int i, j, a, it, rc, changed = 1;
    M->n_part = M->n_prepared = 0;
    for (i = 0; i < M->n; i++) {
        int take = M->asked[i] || (M->next_def[i] && M->next_t[i] <= t);
        for (j = M->z_off[i]; j < M->z_off[i + 1] && !take; j++)
            take = mf_crossed(M->z_prev[j], z_at[j]) || mf_at_zero(z_at[j]);
        if (take && take_part(M, i, t)) return -1;
    }
    /* what the evaluation between events leaves to the events, before any update */
    if (local_pass(M, t, &changed)) return -1;
    for (it = 0; it < MAX_EVENT_ITERATIONS; it++) {
        for (a = 0; a < M->n_part; a++)
            if (update_one(M, M->part_list[a], t)) return -1;
        if (local_pass(M, t, &changed)) return -1;
        if (!changed) break;
    }
    M->sent_valid = 1;
    if (it == MAX_EVENT_ITERATIONS)
        return unsettled(M, t);
    /* a timed instance that took no part keeps its constants: its derivatives are
       constants of its parameters and modes, and value + rate (t - t_read) stays exact */
    rc = leave_event(M, t) || read_timed(M, t, 1) ? -1 : 0;
    for (a = 0; a < M->n_prepared; a++) M->prepared[M->prepared_list[a]] = 0;
    for (a = 0; a < M->n_part; a++) M->part[M->part_list[a]] = 0;
    return rc;
}

/* Every instance in event mode (already there when `initial`), discrete updates until
   the instances and the inputs they see settle, then back to continuous time with
   the states re-read into M->x. Event groups flagged in group_changed record their
   outputs. With z_at (the indicators at (t, M->x) before the event), where the spec
   allows it, only the instances the event touches (event_local). */
static int event_iteration(me_master *M, double t, int initial, const double *z_at)
{
    int i, it, nc = M->spec->n_couplings;
    M->event_was_local = 0;
    if (!initial) {
        if (set_point(M, t, M->x)) return -1;
        if (z_at && M->events_local && M->sent_valid) {
            M->set_valid = 0; /* the updates change the instances behind the cache */
            M->event_was_local = 1;
            return event_local(M, t, z_at);
        }
        if (move_unmoved(M, t, M->x) || settle_linear(M, t, 0)) return -1;
        for (i = 0; i < M->n; i++)
            if (fmu_enter_event_mode(M->fmus[i]))
                return failed(M, i, "entering event mode", t);
    }
    M->set_valid = 0; /* the updates change the instances behind the cache */
    for (i = 0; i < M->n; i++) {
        M->next_def[i] = 0;
        M->part_list[i] = i;
    }
    M->n_part = M->n;
    if (propagate(M, M->values, t)) return -1;
    for (it = 0; it < MAX_EVENT_ITERATIONS; it++) {
        for (i = 0; i < M->n; i++)
            if (update_one(M, i, t)) return -1;
        if (propagate(M, M->values_new, t)) return -1;
        if (nc == 0 || memcmp(M->values, M->values_new, (size_t)nc * sizeof(double)) == 0) break;
        memcpy(M->values, M->values_new, (size_t)nc * sizeof(double));
    }
    /* every input now holds what the last propagation set */
    if (nc) memcpy(M->sent, M->values_new, (size_t)nc * sizeof(double));
    M->sent_valid = 1;
    if (it == MAX_EVENT_ITERATIONS)
        return unsettled(M, t);
    if (leave_event(M, t)) return -1;
    read_linear(M, t);
    return read_timed(M, t, 0);
}

/* After an event: the indicators at the new point become the crossing reference.
   One sitting exactly on zero while its instance's states did not move has touched
   zero without going across (mode conditions are strict): it keeps its old sign so
   that it still triggers once it really goes across; after a state jump a zero is
   a fresh start (a velocity reset to 0) and must not. After a local event the
   instances that took part are read at (t, M->x), time and states set once more as
   set_point would (an exporter may compute in its set calls; the last pass left their
   inputs consistent); the others' indicators are z_at, as neither their states nor
   their inputs moved. */
static int new_reference(me_master *M, double t, const double *x_before, const double *z_at)
{
    int i, j, a;
    if (!M->event_was_local) {
        if (indicators_at(M, t, M->x, M->z_now)) return -1;
    } else {
        if (z_at != M->z_now && M->n_z)
            memcpy(M->z_now, z_at, (size_t)M->n_z * sizeof(double));
        for (a = 0; a < M->n_part; a++) {
            i = M->part_list[a];
            if (M->z_off[i + 1] == M->z_off[i]) continue;
            if (!M->asleep[i] && move_one(M, i, t, M->x + M->x_off[i])) return -1;
            if (fmu_get_event_indicators(M->fmus[i], M->z_now + M->z_off[i],
                                         (size_t)(M->z_off[i + 1] - M->z_off[i])))
                return failed(M, i, "getting the event indicators", t);
        }
    }
    M->z_now_valid = 1;
    for (i = 0; i < M->n; i++) {
        int moved = 0;
        for (j = M->x_off[i]; j < M->x_off[i + 1]; j++)
            if (x_before[j] != M->x[j]) moved = 1;
        for (j = M->z_off[i]; j < M->z_off[i + 1]; j++)
            if (!mf_at_zero(M->z_now[j]) || moved) M->z_prev[j] = M->z_now[j];
    }
    return 0;
}

/* Which event groups own an indicator that crossed between the reference and z. */
static void mark_groups(me_master *M, const double *z)
{
    int g, j;
    for (g = 0; g < M->spec->n_event_groups; g++) {
        const eng_event_group *group = &M->spec->event_groups[g];
        int first = M->z_off[group->instance] + group->first_indicator;
        M->group_changed[g] = 0;
        for (j = first; j < first + group->n_indicators; j++)
            if (mf_crossed(M->z_prev[j], z[j])) M->group_changed[g] = 1;
    }
}

static void clear_groups(me_master *M)
{
    memset(M->group_changed, 0, (size_t)(M->spec->n_event_groups + 1) * sizeof(int));
}

/* An event at (t, M->x): iteration, bookkeeping, output rows at t. 0: go on. */
static int handle_event(me_master *M, double t, const double *z_at)
{
    if (M->n_x) memcpy(M->x_before, M->x, (size_t)M->n_x * sizeof(double));
    if (event_iteration(M, t, 0, z_at)) return -1;
    memset(M->asked, 0, (size_t)M->n * sizeof(int)); /* answered */
    if (++M->stats->events > MAX_EVENTS)
        return fail(M, "more than %ld events before t = %.10g: the modes chatter (Zeno "
                       "behaviour?)", MAX_EVENTS, t);
    restart(M);
    if (new_reference(M, t, M->x_before, z_at)) return -1;
    /* output points at the event time show the state after the jumps */
    return emit_until(M, t, 1, 0);
}

/* --- the run ------------------------------------------------------------------- */

static int completed_step(me_master *M, double t, int *step_event)
{
    int i, moved = 0;
    *step_event = 0;
    for (i = 0; i < M->n; i++) {
        int enter = 0, terminate = 0;
        /* An FMU that needs no fmiCompletedIntegratorStep is not told, nor are the
           instances moved back to the step's end for it: event location and the output
           rows have left them elsewhere, and that move costs a right-hand side. */
        M->asked[i] = 0;
        if (M->spec->instances[i].completed_step_not_needed) continue;
        if (!moved && set_point(M, t, M->x)) return -1;
        moved = 1;
        if (fmu_completed_integrator_step(M->fmus[i], 1, &enter, &terminate))
            return failed(M, i, "completing the integrator step", t);
        if (enter) *step_event = M->asked[i] = 1;
        if (terminate && !M->terminate) {
            M->terminate = 1;
            M->stats->terminated_by = i;
            snprintf(M->stats->message, sizeof M->stats->message, "%s", fmu_message(M->fmus[i]));
        }
    }
    return 0;
}

static int instantiate(me_master *M)
{
    const eng_me_spec *s = M->spec;
    int i;
    for (i = 0; i < M->n; i++) {
        M->fmus[i] = eng_instantiate(&s->instances[i], FMU_MODEL_EXCHANGE, NULL, NULL, 0,
                                     M->message, sizeof M->message);
        if (M->fmus[i] == NULL) return -1;
        M->evaluate_at[i] = fmu_can_evaluate_at(M->fmus[i]);
    }
    M->thin = M->n == 1 && s->n_couplings == 0 && M->evaluate_at[0];
    if (!M->thin || !fmu_evaluate_off(M->fmus[0], &M->off)) M->off.fn = NULL;
    return 0;
}

static int enter_initialization(me_master *M, double t0)
{
    int i;
    M->t = t0;
    for (i = 0; i < M->n; i++)
        if (fmu_enter_initialization(M->fmus[i], M->spec->tolerance, t0, M->spec->stop_time))
            return failed(M, i, "entering initialization", t0);
    return 0;
}

static int exit_initialization(me_master *M)
{
    const eng_me_spec *s = M->spec;
    const double t0 = M->t;
    const int nc = s->n_couplings;
    int i, k;
    /* A loop-free chain of outputs settles within as many passes as there are instances,
       but a pass that changes no coupled value is a fixed point: the passes after it
       would set the same values again. Stopping there keeps the initialization linear in
       the size of an assembly whose couplings come in (or near) causal order, where n
       passes of every coupling cost n^2 FMU calls (769 instances of a 256-block chain:
       half of its 10 s run). */
    for (k = 0; k < M->n && nc > 0; k++) {
        double *now = k % 2 ? M->values_new : M->values;
        const double *before = k % 2 ? M->values : M->values_new;
        if (propagate(M, now, t0)) return -1;
        if (k > 0 && memcmp(now, before, (size_t)nc * sizeof(double)) == 0) break;
    }
    for (i = 0; i < M->n; i++) {
        if (fmu_exit_initialization(M->fmus[i]))
            return failed(M, i, "leaving initialization", t0);
        if (fmu_get_nominals(M->fmus[i], M->nominals + M->x_off[i],
                             (size_t)(M->x_off[i + 1] - M->x_off[i])))
            return failed(M, i, "getting the nominal values of the states", t0);
    }
    /* both FMI versions: an ME FMU is in event mode now; settle it like any event */
    clear_groups(M);
    if (event_iteration(M, t0, 1, NULL)) return -1;
    if (indicators_at(M, t0, M->x, M->z_prev)) return -1;
    memcpy(M->z_now, M->z_prev, (size_t)M->n_z * sizeof(double));
    M->z_now_valid = 1;
    if (M->exact_wanted && s->jacobian == ENG_JACOBIAN_AUTO &&
        s->method != ENG_DOPRI5 && s->method != ENG_DOP853) {
        int foreign = 0;
        for (i = 0; i < M->n; i++) foreign = foreign || s->instances[i].foreign;
        if (foreign && probe_jacobian(M, t0)) return -1;
    }
    return 0;
}

/* The run starts at its first output time (a run from Python; eng_me_create's users
   give theirs to eng_me_enter_initialization). */
static double start_time(const eng_me_spec *s)
{
    return s->n_times > 0 && s->times ? s->times[0] : 0.0;
}

static int initialize(me_master *M)
{
    if (M->spec->jacobian == ENG_JACOBIAN_EXACT && M->n_loops && M->n_x)
        return fail(M, "jacobian='exact': the couplings form an algebraic loop (%.600s), whose "
                       "inputs no directional derivative carries ('fd' or 'auto' take "
                       "differences)", M->spec->loop_name && M->spec->loop_name[0]
                                           ? M->spec->loop_name[0] : "unnamed");
    if (M->spec->jacobian == ENG_JACOBIAN_EXACT && !M->exact_wanted && M->n_x)
        return fail(M, "jacobian='exact': an instance with states or coupled Real "
                       "variables gives no directional derivatives ('fd' or 'auto' take "
                       "differences)");
    return instantiate(M) || enter_initialization(M, start_time(M->spec))
           || exit_initialization(M);
}

/* Integrates from M->t to `target` (or until an instance ends the run). 1: the progress
   callback stopped it, 0: done, -1: failed. */
static int advance(me_master *M, double target, eng_progress *progress)
{
    const eng_me_spec *s = M->spec;
    const double h_max = step_cap(M);
    double t = M->t;

    if (M->inputs_changed) { /* an input set from outside may switch a mode: an event now */
        M->inputs_changed = 0;
        clear_groups(M);
        if (handle_event(M, t, NULL)) return -1;
    }
    /* an importer's communication points carry round-off (0.5 + 0.1 against 6 * 0.1):
       a sliver short of the target is the target, not a step of 1e-16 s */
    const double eps_t = eng_time_slack(t, target);
    eng_budget budget;
    char why[256];

    eng_budget_start(&budget, MAX_STEPS, t);
    while (t < target - eps_t && !M->terminate) {
        double bound = M->next_defined && M->t_next < target ? M->t_next : target;
        double t_old = t, t_event;
        int found, step_event, rest = 0;
        /* time events count too: a member whose next time event stays at t would
           otherwise hold the loop here */
        if (eng_budget_spend(&budget, t, target, why, sizeof why))
            return fail(M, "the integrator: %s", why);
        if (t >= bound) { /* a time event is due now */
            clear_groups(M);
            /* z_now: the indicators at (t, x), from the step or the event that ended here */
            if (handle_event(M, t, M->z_now_valid ? M->z_now : NULL)) return -1;
            continue;
        }
        if (M->n_x == 0) /* nothing to integrate: still look at the indicators often */
            bound = fmin(bound, t + fmax(1e-3, (bound - t) / 100.0));
        /* a cap a round-off short of the target ends on it: steps of h_max summed from 0
           end 4e-16 short of 2.9, a point the loop takes for the target, and the
           target's row was lost with that sliver */
        if (t + h_max < bound)
            bound = bound == target && t + h_max >= target - eps_t ? target : t + h_max;
        if (!(bound > t))
            return fail(M, "the step to t = %.17g cannot move time from t = %.17g (the step "
                           "limit %g s is below its resolution there)", bound, t, h_max);
        if (s->rest_group) memcpy(M->x_start, M->x, (size_t)M->n_x * sizeof(double));
        if (step(M, &t, bound, M->h_initial)) return -1;
        M->t = t;
        M->stats->steps++;
        M->z_now_valid = 0;
        if (indicators_at(M, t, M->x, M->z_now)) return -1;
        found = locate(M, t_old, t, &t_event);
        if (found < 0) {
            char why[sizeof M->message];
            snprintf(why, sizeof why, "%s", M->message[0] ? M->message : "not finite");
            return fail(M, "the event indicators could not be evaluated between t = %.10g and "
                           "%.10g: %.800s", t_old, t, why);
        }
        if (found) {
            if (emit_until(M, t_event, 0, 1)) return -1;
            dense(M, t_event, M->x);
            M->t = t = t_event;
            mark_groups(M, M->z_hit);
            if (completed_step(M, t, &step_event)) return -1;
            if (handle_event(M, t, M->z_hit)) return -1;
            if (!M->terminate && target >= s->stop_time && s->rest_group) {
                /* what the event left, as a step would find it: where every derivative
                   of an autonomous group is exactly zero, each stage of a step is the
                   same point, and so are its indicators (the block that sticks for good
                   rests from the event, not from the end of a step after it) */
                int evaluated;
                memcpy(M->x_start, M->x, (size_t)M->n_x * sizeof(double));
                rest = fall_asleep(M, t, &evaluated);
                /* the next step starts from f(t, x) (a sleeper's part is zero either
                   way): the look costs no evaluation where nothing rests */
                if (rest == 0 && evaluated) explicit_take_first_stage(M, M->fd);
            }
        } else {
            if (emit_until(M, t, 1, 1)) return -1;
            memcpy(M->z_prev, M->z_now, (size_t)M->n_z * sizeof(double));
            M->z_now_valid = 1;
            if (completed_step(M, t, &step_event)) return -1;
            if (step_event && !M->terminate) {
                clear_groups(M);
                if (handle_event(M, t, M->z_now)) return -1;
            } else if (!M->terminate && target >= s->stop_time) {
                rest = fall_asleep(M, t, NULL);
            }
        }
        if (rest < 0) return -1;
        if (rest) { /* nothing moves any more: no more steps */
            M->stats->at_rest_from = t;
            if (rest_rows(M)) return -1;
            t = target;
            break;
        }
        M->stats->t_end = t;
        if (!M->terminate && eng_progress_check(progress, t)) return 1;
    }
    if (!M->terminate && t < target) {
        /* a sliver short (an event within eps_t of it): the target's rows from the
           states reached, which the sliver cannot change beyond round-off */
        M->t = t = target;
        if (emit_until(M, t, 1, 0)) return -1;
    }
    M->stats->t_end = t;
    /* the instances stand at the point reached: their outputs are read from there */
    return set_point(M, t, M->x) || move_unmoved(M, t, M->x) || settle_linear(M, t, 0) ? -1 : 0;
}

static int integrate(me_master *M)
{
    const eng_me_spec *s = M->spec;
    eng_progress progress;
    int r;

    M->h_initial = s->n_times > 1 ? s->times[1] - s->times[0]
                                  : (s->stop_time - start_time(s)) / 100.0;
    eng_progress_start(&progress, s->progress, s->progress_ctx);
    if (emit_until(M, start_time(s), 1, 0)) return -1;
    if (!M->terminate) {
        r = advance(M, s->stop_time, &progress);
        if (r < 0) return -1;
        if (r == 1) {
            M->stats->status = ENG_STOPPED;
            return 0;
        }
    }
    if (M->terminate) M->stats->status = ENG_TERMINATED;
    return 0;
}

/* n zeroed elements for the run (me_master.arena), freed by release */
static void *zeroed(me_master *M, size_t n, size_t size)
{
    return eng_arena_take(&M->arena, n, size);
}

static double *zeros(me_master *M, int n)
{
    return zeroed(M, (size_t)(n > 0 ? n : 1), sizeof(double));
}

static const eng_coupling *live(const me_master *M, const coupling_plan *P, int p)
{
    return &M->spec->couplings[P->live[p]];
}

static int plan_allocate(me_master *M, coupling_plan *P, int n_couplings)
{
    size_t n = (size_t)n_couplings + 1;
    P->live = zeroed(M, n, sizeof(int));
    P->segment_end = zeroed(M, n, sizeof(int));
    P->run_end = zeroed(M, n, sizeof(int));
    P->write_order = zeroed(M, n, sizeof(int));
    P->source_vr = zeroed(M, n, sizeof(uint32_t));
    P->loop = zeroed(M, n, sizeof(int));
    return P->live && P->segment_end && P->run_end && P->write_order && P->source_vr && P->loop
               ? 0 : -1;
}

/* Segments, runs and write order (see couple) of the couplings with needed[i] (every
   one where needed is NULL). The couplings come in dependency order (a coupling after
   those that set the inputs its source output depends on); a segment ends before a
   coupling whose source instance a coupling of the segment sets, so reading a whole
   segment before setting it reads the same values as going one by one. Python orders
   them by dependency level, which makes segments long. An algebraic loop is a segment
   of its own, solved whole (solve_loop): needed when any of its couplings is. */
static int plan_couplings(me_master *M, coupling_plan *P, const int *needed)
{
    const eng_me_spec *s = M->spec;
    int nc = s->n_couplings, n, i, j, q, start = 0;
    char *targeted = calloc((size_t)M->n + 1, 1), *take = calloc((size_t)nc + 1, 1);
    if (!targeted || !take) {
        free(targeted);
        free(take);
        return -1;
    }
    for (i = 0; i < nc; i++) take[i] = !needed || needed[i];
    for (q = 0; q < M->n_loops; q++) {
        int any = 0;
        for (i = s->loop_first[q]; i < s->loop_first[q] + s->loop_count[q]; i++) any |= take[i];
        for (i = s->loop_first[q]; i < s->loop_first[q] + s->loop_count[q]; i++) take[i] = any;
    }
    for (n = i = 0; i < nc; i++)
        if (take[i]) P->live[n++] = i;
    free(take);
    P->n_live = n;
    for (i = 0; i <= n; i++) {
        const int loop = i < n ? M->loop_of[P->live[i]] : -1;
        const int before = i > start ? M->loop_of[P->live[i - 1]] : -1;
        int close;
        /* close the segment start .. i-1: before a coupling whose source it sets, and
           around a loop */
        if (i == n) close = 1;
        else if (loop >= 0 && loop == before) close = 0;
        else close = targeted[live(M, P, i)->source.instance] || loop >= 0 || before >= 0;
        if (i < n) P->loop[i] = loop;
        if (close) {
            int w = start;
            for (j = start; j < i; j++) P->segment_end[j] = i - 1;
            /* stable by target instance: an insertion per coupling, not a pass over every
               instance per segment (an assembly's per-instance indicator plans made that
               quadratic in its size) */
            for (j = start; j < i; j++) {
                const int target = live(M, P, j)->target.instance;
                int k = w++;
                while (k > start && live(M, P, P->write_order[k - 1])->target.instance > target) {
                    P->write_order[k] = P->write_order[k - 1];
                    k--;
                }
                P->write_order[k] = j;
                targeted[target] = 0;
            }
            start = i;
        }
        if (i < n) targeted[live(M, P, i)->target.instance] = 1;
    }
    free(targeted);
    for (i = n - 1; i >= 0; i--) {
        const eng_variable *source = &live(M, P, i)->source, *next;
        P->source_vr[i] = source->vr;
        P->run_end[i] = i;
        if (i + 1 == n) continue;
        /* one read for a run of one source's Float64 outputs within one segment */
        next = &live(M, P, i + 1)->source;
        if (P->segment_end[i + 1] == P->segment_end[i] && ENG_PLAIN(source) && ENG_PLAIN(next) &&
            next->instance == source->instance)
            P->run_end[i] = P->run_end[i + 1];
    }
    return 0;
}

/* The rows' own plan (eng_me_spec.row_coupling) and the instances it moves: those
   with a recorded column and the sources of its couplings. Partial only where that
   leaves something out of the evaluation between events. */
static int plan_rows(me_master *M)
{
    const eng_me_spec *s = M->spec;
    int i, p;
    M->row_instance = zeroed(M, (size_t)M->n + 1, sizeof(int));
    if (!M->row_instance || plan_allocate(M, &M->rows, s->n_couplings)) return -1;
    if (!s->row_coupling) return 0;
    if (plan_couplings(M, &M->rows, s->row_coupling)) return -1;
    for (i = 0; i < s->n_columns; i++) M->row_instance[s->columns[i].instance] = 1;
    for (p = 0; p < M->rows.n_live; p++) M->row_instance[live(M, &M->rows, p)->source.instance] = 1;
    M->rows_partial = M->rows.n_live < M->between.n_live;
    for (i = 0; i < M->n; i++) M->rows_partial = M->rows_partial || !M->row_instance[i];
    return 0;
}

/* Each instance's indicator plan (eng_me_spec.indicator_start): its couplings, and the
   instances to move, itself and every source those couplings read. */
static int plan_local(me_master *M)
{
    const eng_me_spec *s = M->spec;
    int i, a, p, total = 0, located = 0, *mask, *mark;
    double own = 0.0, whole;
    if (!s->indicator_start) return 0;
    M->local = zeroed(M, (size_t)M->n, sizeof(coupling_plan));
    M->local_start = zeroed(M, (size_t)M->n + 1, sizeof(int));
    mask = calloc((size_t)s->n_couplings + 1, sizeof(int));
    mark = calloc((size_t)M->n + 1, sizeof(int));
    if (!M->local || !M->local_start || !mask || !mark) goto fail;
    for (i = 0; i < M->n; i++)
        total += 1 + s->indicator_start[i + 1] - s->indicator_start[i];
    M->local_instance = zeroed(M, (size_t)total + 1, sizeof(int));
    if (!M->local_instance) goto fail;
    for (i = 0; i < M->n; i++) {
        const int first = s->indicator_start[i], count = s->indicator_start[i + 1] - first;
        int n_inst = M->local_start[i];
        if (plan_allocate(M, &M->local[i], count)) goto fail;
        for (a = first; a < first + count; a++) mask[s->indicator_coupling[a]] = 1;
        /* planning scans every coupling: only for the instances whose indicators read
           some (a chain's links and belts read none: two thirds of n x couplings) */
        if (count > 0 && plan_couplings(M, &M->local[i], mask)) goto fail;
        for (a = first; a < first + count; a++) mask[s->indicator_coupling[a]] = 0;
        mark[i] = 1;
        M->local_instance[n_inst++] = i;
        for (p = 0; p < M->local[i].n_live; p++) {
            int k = live(M, &M->local[i], p)->source.instance;
            if (!mark[k]) {
                mark[k] = 1;
                M->local_instance[n_inst++] = k;
            }
        }
        for (a = M->local_start[i]; a < n_inst; a++) mark[M->local_instance[a]] = 0;
        M->local_start[i + 1] = n_inst;
        if (M->z_off[i + 1] > M->z_off[i]) {
            located++;
            own += (double)(n_inst - M->local_start[i]) + M->local[i].n_live + 1.0;
        }
    }
    free(mask);
    free(mark);
    /* where a whole-assembly evaluation (every instance moved, the couplings between
       events set, every instance's indicators read) costs less than this many
       instances' own (their instances moved, their plans' couplings, their indicators) */
    whole = (double)M->n + M->between.n_live + located;
    M->shared_from = located > 0 ? (int)fmax(2.0, ceil(whole / (own / located))) : INT_MAX;
    M->shared_z = zeroed(M, (size_t)SHARED_SLOTS * (size_t)M->n_z + 1, sizeof(double));
    return M->shared_z ? 0 : -1;
fail:
    free(mask);
    free(mark);
    return -1;
}

static int plan_set_again(me_master *M)
{
    int i;
    M->set_again = zeroed(M, (size_t)M->n + 1, sizeof(int));
    if (!M->set_again) return -1;
    for (i = 0; i < M->n; i++) {
        M->set_again[i] = M->spec->instances[i].foreign &&
                          (!M->rows_partial || M->row_instance[i]);
        M->any_set_again = M->any_set_again || M->set_again[i];
    }
    return 0;
}

/* Each loop's solver, the loop of each coupling, and whether the loop's sources give
   directional derivatives (else its matrix is by differences of its residual). */
static int allocate_loops(me_master *M)
{
    const eng_me_spec *s = M->spec;
    int i, k;
    M->loop_min_steps = 1;
    M->loop_of = zeroed(M, (size_t)s->n_couplings + 1, sizeof(int));
    M->members = zeroed(M, (size_t)s->n_couplings + 1, sizeof(int));
    M->loops = zeroed(M, (size_t)s->n_loops + 1, sizeof(eng_loop));
    M->loop_dd = zeroed(M, (size_t)s->n_loops + 1, sizeof(int));
    if (!M->loop_of || !M->members || !M->loops || !M->loop_dd) return -1;
    for (i = 0; i < s->n_couplings; i++) {
        M->loop_of[i] = -1;
        M->members[i] = i;
    }
    for (k = 0; k < s->n_loops; k++) {
        const int first = s->loop_first[k], count = s->loop_count[k];
        M->n_loops = k + 1; /* release frees these, this one too if it fails halfway */
        if (eng_loop_alloc(&M->loops[k], count)) return -1;
        M->loops[k].n = count;
        M->loop_dd[k] = 1;
        for (i = first; i < first + count; i++) {
            M->loop_of[i] = k;
            M->loop_dd[k] = M->loop_dd[k] &&
                            s->instances[s->couplings[i].source.instance].provides_directional_derivative;
        }
    }
    return 0;
}

/* The linear instances (eng_me_spec.linear_map) that qualify (no states, indicators,
   and only Float64 scalars coupled to them), and where their coefficients go. */
static int allocate_linear(me_master *M)
{
    const eng_me_spec *s = M->spec;
    const int n = M->n, nc = s->n_couplings;
    int i, k, a;
    size_t total = 0;
    M->linear = zeroed(M, (size_t)n + 1, sizeof(int));
    M->lin_in_start = zeroed(M, (size_t)n + 1, sizeof(int));
    M->lin_in = zeroed(M, (size_t)nc + 1, sizeof(int));
    M->lin_row = zeroed(M, (size_t)nc + 1, sizeof(int));
    M->lin_u = zeros(M, nc);
    M->lin_u0 = zeros(M, nc);
    M->lin_y0 = zeros(M, nc);
    M->lin_recorded = zeroed(M, (size_t)n + 1, sizeof(int));
    M->lin_ready = zeroed(M, (size_t)n + 1, sizeof(int));
    M->out_start = zeroed(M, (size_t)n + 1, sizeof(int));
    M->out_list = zeroed(M, (size_t)nc + 1, sizeof(int));
    M->out_vr = zeroed(M, (size_t)nc + 1, sizeof(uint32_t));
    if (!M->linear || !M->lin_recorded || !M->lin_ready || !M->lin_in_start || !M->lin_in ||
        !M->lin_row || !M->lin_u || !M->lin_u0 || !M->lin_y0 || !M->out_start || !M->out_list ||
        !M->out_vr)
        return -1;
    for (k = 0; k < nc; k++) M->out_start[s->couplings[k].source.instance + 1]++;
    for (i = 0; i < n; i++) M->out_start[i + 1] += M->out_start[i];
    for (k = 0; k < nc; k++) { /* by source instance, in coupling order (lin_ready: a cursor) */
        i = s->couplings[k].source.instance;
        a = M->out_start[i] + M->lin_ready[i]++;
        M->out_list[a] = k;
        M->out_vr[a] = s->couplings[k].source.vr;
    }
    memset(M->lin_ready, 0, (size_t)(n + 1) * sizeof(int));
    for (i = 0; i < n && s->linear_map; i++) {
        const eng_instance_spec *in = &s->instances[i];
        M->linear[i] = s->linear_map[i] && in->n_states == 0 && in->n_event_indicators == 0;
    }
    for (k = 0; k < nc; k++) { /* scalars of Float64 only */
        const eng_coupling *c = &s->couplings[k];
        if (!ENG_PLAIN(&c->source)) M->linear[c->source.instance] = 0;
        if (!ENG_PLAIN(&c->target)) M->linear[c->target.instance] = 0;
    }
    /* a loop's members are set and read by its Newton solve itself (solve_loop), so
       their FMUs always hold what a linear map would have to track */
    for (k = 0; k < s->n_loops; k++)
        for (a = s->loop_first[k]; a < s->loop_first[k] + s->loop_count[k]; a++) {
            M->linear[s->couplings[a].source.instance] = 0;
            M->linear[s->couplings[a].target.instance] = 0;
        }
    eng_inputs_by_target(s->couplings, nc, n, M->linear, M->lin_in_start, M->lin_in);
    /* an instance dropped here keeps rows that are never read */
    total = eng_linear_rows(s->couplings, nc, M->lin_in_start, M->linear, 1, M->lin_row);
    M->lin_J = zeroed(M, total + 1, sizeof(double));
    if (!M->lin_J) return -1;
    for (i = 0; i < n; i++) M->any_linear = M->any_linear || M->linear[i];
    for (k = 0; k < s->n_columns; k++) {
        i = s->columns[k].instance;
        M->lin_recorded[i] = M->linear[i];
        M->any_lin_recorded = M->any_lin_recorded || M->linear[i];
    }
    return 0;
}

/* What event_local needs; events_local: no algebraic loop (a loop's members are solved
   together, through every coupling: one that takes part takes its loop along, which
   the whole iteration does). */
static int allocate_local_events(me_master *M)
{
    const eng_me_spec *s = M->spec;
    const size_t n1 = (size_t)M->n + 1;
    int i;
    M->part = zeroed(M, n1, sizeof(int));
    M->part_list = zeroed(M, n1, sizeof(int));
    M->prepared = zeroed(M, n1, sizeof(int));
    M->prepared_list = zeroed(M, n1, sizeof(int));
    M->touched = zeroed(M, n1, sizeof(int));
    M->asked = zeroed(M, n1, sizeof(int));
    M->next_def = zeroed(M, n1, sizeof(int));
    M->passive = zeroed(M, n1, sizeof(int));
    M->next_t = zeros(M, M->n);
    if (!M->part || !M->part_list || !M->prepared || !M->prepared_list || !M->touched ||
        !M->asked || !M->next_def || !M->passive || !M->next_t)
        return -1;
    M->events_local = s->n_loops == 0;
    for (i = 0; i < M->n; i++) {
        const eng_instance_spec *in = &s->instances[i];
        M->passive[i] = s->event_free && s->event_free[i] && in->n_event_indicators == 0;
    }
    return 0;
}

static int allocate(me_master *M)
{
    const eng_me_spec *s = M->spec;
    int i, width = 1, n = s->n_instances;
    M->n = n;
    M->fmus = zeroed(M, (size_t)(n > 0 ? n : 1), sizeof *M->fmus);
    M->x_off = zeroed(M, (size_t)n + 1, sizeof(int));
    M->z_off = zeroed(M, (size_t)n + 1, sizeof(int));
    M->group_changed = zeroed(M, (size_t)s->n_event_groups + 1, sizeof(int));
    if (!M->fmus || !M->x_off || !M->z_off || !M->group_changed) return -1;
    for (i = 0; i < n; i++) {
        M->x_off[i + 1] = M->x_off[i] + s->instances[i].n_states;
        M->z_off[i + 1] = M->z_off[i] + s->instances[i].n_event_indicators;
    }
    for (i = 0; i < s->n_event_groups; i++)
        if (1 + s->event_groups[i].n_outputs > width) width = 1 + s->event_groups[i].n_outputs;
    M->n_x = M->x_off[n];
    M->n_z = M->z_off[n];
    M->rows_from_states = s->column_state != NULL;
    for (i = 0; i < s->n_columns && M->rows_from_states; i++) {
        const eng_variable *v = &s->columns[i];
        int k = s->column_state[i];
        M->rows_from_states = k >= 0 && k < M->x_off[v->instance + 1] - M->x_off[v->instance];
    }
    /* an interpolation per column, where that is at most half the states' (coin_rolling
       records 1 of its 8) */
    M->rows_by_state = M->rows_from_states && 2 * s->n_columns <= M->n_x;
    M->x = zeros(M, M->n_x);
    M->x_tmp = zeros(M, M->n_x);
    M->x_set = zeros(M, M->n_x);
    M->nominals = zeros(M, M->n_x);
    M->fd = zeros(M, M->n_x);
    M->fd2 = zeros(M, M->n_x);
    M->x_before = zeros(M, M->n_x);
    M->x_start = zeros(M, M->n_x);
    M->asleep = zeroed(M, (size_t)M->n + 1, sizeof(int));
    M->evaluate_at = zeroed(M, (size_t)M->n + 1, sizeof(int));
    M->timed = zeroed(M, (size_t)M->n + 1, sizeof(int));
    M->unmoved = zeroed(M, (size_t)M->n + 1, sizeof(int));
    M->needed = zeroed(M, (size_t)s->n_couplings + 1, sizeof(int));
    M->timed_t = zeros(M, M->n);
    M->timed_dx = zeros(M, M->n_x);
    M->timed_y = zeros(M, s->n_couplings);
    M->timed_rate = zeros(M, s->n_couplings);
    if (!M->timed || !M->unmoved || !M->needed || !M->timed_t || !M->timed_dx || !M->timed_y ||
        !M->timed_rate)
        return -1;
    for (i = 0; i < n && s->time_function; i++) {
        /* what read_timed needs, and what no step end asks of it */
        const eng_instance_spec *in = &s->instances[i];
        M->timed[i] = s->time_function[i] && in->n_event_indicators == 0 &&
                      in->completed_step_not_needed && (in->n_states == 0 || in->state_vr);
        M->any_timed = M->any_timed || M->timed[i];
        M->timed_t[i] = NAN; /* not read yet: a first read that fails took it never */
    }
    if (allocate_linear(M)) return -1;
    for (i = 0; i < n && s->taken_until; i++)
        s->taken_until[i] = M->timed[i] || M->linear[i] ? INFINITY : NAN;
    for (i = 0; i < n; i++) {
        M->unmoved[i] = M->timed[i] || M->linear[i] ||
                        (s->time_free && s->time_free[i] && s->instances[i].n_states == 0);
        M->any_unmoved = M->any_unmoved || M->unmoved[i];
    }
    if (allocate_local_events(M)) return -1;
    M->z_prev = zeros(M, M->n_z);
    M->z_now = zeros(M, M->n_z);
    M->z_hit = zeros(M, M->n_z);
    M->z_work = zeros(M, (int)MF_LOCATE_WORK(M->n_z, s->event_subsamples));
    M->values = zeros(M, s->n_couplings);
    M->values_new = zeros(M, s->n_couplings);
    M->sent = zeros(M, s->n_couplings);
    M->read = zeros(M, s->n_couplings);
    M->pending_vr = zeroed(M, (size_t)s->n_couplings + 1, sizeof(uint32_t));
    M->pending_value = zeros(M, s->n_couplings);
    if (!M->sent || !M->read || !M->pending_vr || !M->pending_value) return -1;
    if (allocate_loops(M) || plan_allocate(M, &M->all, s->n_couplings) ||
        plan_couplings(M, &M->all, NULL) || plan_allocate(M, &M->between, s->n_couplings) ||
        plan_couplings(M, &M->between, s->continuous) || plan_rows(M) || plan_set_again(M) ||
        plan_local(M))
        return -1;
    M->row = zeros(M, width);
    if (!M->x || !M->x_tmp || !M->x_set || !M->nominals || !M->fd || !M->fd2 || !M->x_before
        || !M->x_start || !M->asleep || !M->evaluate_at || !M->z_prev || !M->z_now ||
        !M->z_hit || !M->z_work || !M->values || !M->values_new || !M->row)
        return -1;
    /* a loop's inputs are no plain function the seeds pass through: differences */
    M->exact_wanted = s->jacobian != ENG_JACOBIAN_FD && !M->n_loops && eng_jacobian_possible(s);
    M->stats->exact_jacobian = M->exact_wanted;
    /* DOPRI5 and RODAS3 whichever the run starts with: the automatic choice may take
       either, and leaves DOP853 for DOPRI5 where events are dense. "auto" takes DOP853
       only where its long steps are possible: under a step cap every step is at most an
       output interval, and an 8th-order one is accuracy wasted (moving_table at 1e-8:
       1,088 steps with either, DOP853's 16,449 evaluations against DOPRI5's 9,639) */
    M->high_order = s->method == ENG_DOP853 ||
                    (s->method == ENG_AUTO && s->tolerance <= ENG_HIGH_ORDER_TOLERANCE &&
                     isinf(step_cap(M)));
    if (mf_ros_alloc(&M->ros, M->n_x) || mf_dopri_alloc(&M->dopri, M->n_x) ||
        (M->high_order && eng_dop853_alloc(&M->dop853, M->n_x)))
        return -1;
    mf_stiffness_reset(&M->stiff, s->method == ENG_RODAS3);
    M->dense_implicit = M->stiff.implicit;
    return 0;
}

static void release(me_master *M)
{
    int i;
    if (M->fmus)
        for (i = 0; i < M->n; i++) fmu_free(M->fmus[i]);
    mf_ros_free(&M->ros);
    mf_dopri_free(&M->dopri);
    eng_dop853_free(&M->dop853);
    eng_jacobian_free(M->exact);
    if (M->loops)
        for (i = 0; i < M->n_loops; i++) eng_loop_free(&M->loops[i]);
    eng_arena_free(&M->arena); /* every other array allocate took */
}

/* The spec's own mistakes, before anything is loaded. */
static const char *spec_defect(const eng_me_spec *s)
{
    int k;
    if (s->n_instances < 1) return "no instances";
    if (!(s->stop_time > 0.0) || !isfinite(s->stop_time)) return "stop time must be finite and > 0";
    if (s->n_times > 0 && (!isfinite(s->times[0]) || !(s->times[0] < s->stop_time)))
        return "start time (the first output time) must be finite and before the stop time";
    if (!(s->tolerance > 0.0) || !(s->tolerance < 1.0)) return "tolerance must be in (0, 1)";
    if (s->method != ENG_DOPRI5 && s->method != ENG_RODAS3 && s->method != ENG_AUTO &&
        s->method != ENG_DOP853)
        return "unknown method";
    if (s->event_subsamples < 0) return "event_subsamples must be >= 0";
    if (s->jacobian != ENG_JACOBIAN_AUTO && s->jacobian != ENG_JACOBIAN_FD &&
        s->jacobian != ENG_JACOBIAN_EXACT)
        return "unknown jacobian";
    for (k = 0; k < s->n_couplings; k++)
        if (s->couplings[k].source.instance < 0 || s->couplings[k].source.instance >= s->n_instances ||
            s->couplings[k].target.instance < 0 || s->couplings[k].target.instance >= s->n_instances)
            return "a coupling names an instance out of range";
    for (k = 0; k < s->n_columns; k++)
        if (s->columns[k].instance < 0 || s->columns[k].instance >= s->n_instances)
            return "a column names an instance out of range";
    for (k = 0; k < s->n_event_groups; k++) {
        const eng_event_group *g = &s->event_groups[k];
        if (g->instance < 0 || g->instance >= s->n_instances || g->first_indicator < 0 ||
            g->n_indicators < 0 ||
            g->first_indicator + g->n_indicators > s->instances[g->instance].n_event_indicators)
            return "an event group names an instance or indicators out of range";
    }
    if (s->n_loops < 0 || s->n_loops > s->n_couplings ||
        (s->n_loops > 0 && (!s->loop_first || !s->loop_count)))
        return "n_loops must be in 0 .. n_couplings, with loop_first and loop_count";
    for (k = 0; k < s->n_loops; k++) {
        int i, end = k > 0 ? s->loop_first[k - 1] + s->loop_count[k - 1] : 0;
        if (s->loop_first[k] < end || s->loop_count[k] < 1 ||
            s->loop_count[k] > s->n_couplings - s->loop_first[k])
            return "loops must be in range, not overlap and come in increasing order";
        for (i = s->loop_first[k]; i < s->loop_first[k] + s->loop_count[k]; i++)
            if (!ENG_PLAIN(&s->couplings[i].source) || !ENG_PLAIN(&s->couplings[i].target))
                return "an algebraic loop's couplings must be Float64 scalars";
    }
    if (s->indicator_start) {
        if (!s->indicator_coupling || s->indicator_start[0] != 0)
            return "indicator_start must start at 0, with indicator_coupling";
        for (k = 0; k < s->n_instances; k++) {
            int a, first = s->indicator_start[k], end = s->indicator_start[k + 1];
            /* at most every coupling once per instance, in order: plan_local sizes by it */
            if (end < first || end - first > s->n_couplings)
                return "indicator_start must not decrease, nor list more than every coupling";
            for (a = first; a < end; a++)
                if (s->indicator_coupling[a] < 0 || s->indicator_coupling[a] >= s->n_couplings ||
                    (a > first && s->indicator_coupling[a] <= s->indicator_coupling[a - 1]))
                    return "indicator_coupling: couplings out of range or not increasing";
        }
    }
    return NULL;
}

ENG_API eng_run *eng_simulate_me(const eng_me_spec *spec, eng_stats *stats)
{
    me_master M;
    const char *defect;
    int *widths, i;

    memset(stats, 0, sizeof *stats);
    stats->terminated_by = -1;
    stats->at_rest_from = INFINITY;
    memset(&M, 0, sizeof M);
    M.spec = spec;
    M.stats = stats;
    defect = spec_defect(spec);
    if (defect) {
        stats->status = ENG_FAILED;
        snprintf(stats->message, sizeof stats->message, "eng_simulate_me: %s", defect);
        return eng_run_new(0, NULL);
    }
    widths = calloc((size_t)spec->n_event_groups + 1, sizeof(int));
    if (widths == NULL) goto oom;
    for (i = 0; i < spec->n_event_groups; i++) widths[i] = 1 + spec->event_groups[i].n_outputs;
    M.run = eng_run_new(spec->n_event_groups, widths);
    free(widths);
    if (M.run == NULL) goto oom;
    if (allocate(&M)) {
        release(&M);
        stats->status = ENG_FAILED;
        snprintf(stats->message, sizeof stats->message, "out of memory");
        return M.run;
    }
    if (initialize(&M) || integrate(&M)) {
        stats->status = ENG_FAILED;
        snprintf(stats->message, sizeof stats->message, "%s", M.message);
    }
    stats->rejected = M.dopri.n_rejected + M.dop853.n_rejected + M.ros.n_rejected;
    stats->explicit_order = spec->method == ENG_RODAS3 ? 0 : M.left_high_order ? 85
                            : M.high_order ? 8 : 5;
    /* RODAS3's and the stiffness checks' alike: each is an evaluation of the whole matrix */
    stats->jacobians = M.ros.n_jac + M.stiff.jacobians_checked;
    stats->method_switches = M.stiff.switches;
    if (M.exact) {
        stats->jacobian_groups = eng_jacobian_groups(M.exact);
        stats->jacobian_evaluations = eng_jacobian_evaluations(M.exact);
    }
    stats->jacobian_band = M.ros.banded ? M.ros.kl + M.ros.ku + 1 : 0;
    for (i = 0; i < M.n_loops; i++) {
        stats->loop_iterations += M.loops[i].iterations;
        stats->loop_matrices += M.loops[i].matrices;
    }
    release(&M);
    return M.run;

oom:
    stats->status = ENG_FAILED;
    snprintf(stats->message, sizeof stats->message, "out of memory");
    return NULL;
}

/* ---------------------------------------------------------------------------- */
/* the master one communication step at a time: an assembly FMU's doStep          */

struct eng_me {
    me_master M;
    eng_stats stats;
    eng_progress progress; /* no callback: never stops a step */
    int failed;
};

static int me_failed(eng_me *m)
{
    m->failed = 1;
    snprintf(m->stats.message, sizeof m->stats.message, "%s", m->M.message);
    return ENG_FAILED;
}

eng_me *eng_me_create(const eng_me_spec *spec)
{
    eng_me *m = (eng_me *)calloc(1, sizeof *m);
    const char *defect;
    if (!m) return NULL;
    m->stats.terminated_by = -1;
    m->stats.at_rest_from = INFINITY;
    m->M.spec = spec;
    m->M.stats = &m->stats;
    eng_progress_start(&m->progress, NULL, NULL);
    m->M.run = eng_run_new(0, NULL);
    defect = spec_defect(spec);
    if (defect) {
        snprintf(m->M.message, sizeof m->M.message, "%s", defect);
        me_failed(m);
    } else if (!m->M.run || allocate(&m->M)) {
        snprintf(m->M.message, sizeof m->M.message, "out of memory");
        me_failed(m);
    } else if (instantiate(&m->M)) {
        me_failed(m);
    }
    m->M.h_initial = spec->stop_time / 100.0;
    return m;
}

int eng_me_failed(const eng_me *m) { return m->failed; }

int eng_me_enter_initialization(eng_me *m, double start_time)
{
    if (m->failed) return ENG_FAILED;
    return enter_initialization(&m->M, start_time) ? me_failed(m) : 0;
}

int eng_me_exit_initialization(eng_me *m)
{
    if (m->failed) return ENG_FAILED;
    return exit_initialization(&m->M) ? me_failed(m) : 0;
}

void eng_me_inputs_changed(eng_me *m) { m->M.inputs_changed = 1; }

int eng_me_advance(eng_me *m, double target)
{
    if (m->failed) return ENG_FAILED;
    /* the first step tried: about the communication step (the solver adapts from there) */
    if (target > m->M.t) m->M.h_initial = target - m->M.t;
    return advance(&m->M, target, &m->progress) < 0 ? me_failed(m) : 0;
}

double eng_me_time(const eng_me *m) { return m->M.t; }

int eng_me_terminated(const eng_me *m) { return m->M.terminate; }

fmu_t *eng_me_member(eng_me *m, int i) { return m->M.fmus ? m->M.fmus[i] : NULL; }

const char *eng_me_message(const eng_me *m) { return m->stats.message; }

void eng_me_free(eng_me *m)
{
    if (!m) return;
    release(&m->M); /* what allocate got: every pointer starts NULL */
    eng_run_free(m->M.run);
    free(m);
}

/* --- the coupled members as one Model Exchange FMU: the importer integrates ------- */

int eng_me_number_of_states(const eng_me *m) { return m->M.n_x; }

int eng_me_number_of_indicators(const eng_me *m) { return m->M.n_z; }

void eng_me_set_time(eng_me *m, double t)
{
    m->M.t = t;
    m->M.z_now_valid = 0;
}

void eng_me_set_states(eng_me *m, const double *x)
{
    m->M.z_now_valid = 0;
    if (m->M.n_x) memcpy(m->M.x, x, (size_t)m->M.n_x * sizeof(double));
}

void eng_me_get_states(const eng_me *m, double *x)
{
    if (m->M.n_x) memcpy(x, m->M.x, (size_t)m->M.n_x * sizeof(double));
}

void eng_me_get_nominals(const eng_me *m, double *nominals)
{
    if (m->M.n_x) memcpy(nominals, m->M.nominals, (size_t)m->M.n_x * sizeof(double));
}

/* The members at the importer's (t, x), couplings evaluated: their outputs are current. */
int eng_me_sync(eng_me *m)
{
    if (m->failed) return ENG_FAILED;
    return set_point(&m->M, m->M.t, m->M.x) ? me_failed(m) : 0;
}

int eng_me_derivatives(eng_me *m, double *dx)
{
    if (m->failed) return ENG_FAILED;
    return rhs(&m->M, m->M.t, m->M.x, dx) ? me_failed(m) : 0;
}

int eng_me_indicators(eng_me *m, double *z)
{
    if (m->failed) return ENG_FAILED;
    return indicators_at(&m->M, m->M.t, m->M.x, z) ? me_failed(m) : 0;
}

/* An event at the importer's (t, x): the members' event iteration through the
   couplings, as the engine's own integrator runs it. *states_changed: x jumped. */
int eng_me_event_update(eng_me *m, int *states_changed)
{
    me_master *M = &m->M;
    if (m->failed) return ENG_FAILED;
    if (M->n_x) memcpy(M->x_before, M->x, (size_t)M->n_x * sizeof(double));
    clear_groups(M);
    M->z_now_valid = 0; /* the importer moves the states: the reference is its own */
    if (event_iteration(M, M->t, 0, NULL)) return me_failed(m);
    *states_changed = M->n_x && memcmp(M->x_before, M->x, (size_t)M->n_x * sizeof(double)) != 0;
    return 0;
}

int eng_me_completed_step(eng_me *m, int *enter_event_mode)
{
    if (m->failed) return ENG_FAILED;
    return completed_step(&m->M, m->M.t, enter_event_mode) ? me_failed(m) : 0;
}
