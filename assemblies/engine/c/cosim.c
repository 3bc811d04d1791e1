/*
 * cosim.c: the co-simulation master (see cosim.h for what it does and why).
 *
 * Every FMU call goes through fmu.h (instances.h for typed values). Names follow
 * the Python reference master (assemblies/masters/cosim.py): consistent(), step(),
 * held_value(), the step controller of adaptive.py and the loop solver of loops.py,
 * so that the two can be read side by side.
 */
#include "cosim.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "instances.h"
#include "linear_map.h"
#include "loop.h"
#include "output.h"
#include "solver.h" /* MF_MIN_STEP: the shortest step time can resolve */

/* Coupled steps per call that advances time (per output interval of a run, per doStep
   of an assembly FMU): each is several member doSteps, each with its own budget. */
#define MAX_COUPLED_STEPS 1000000L

/* Steps taken without an estimate after each accepted one (adaptive.py COAST_STEPS).
   Step doubling costs three doSteps to advance two half steps; on a scene whose steps
   the estimate keeps about even (a table shaken at one frequency) adaptivity then
   costs 1.5x fixed steps of the same length. A run of unjudged half steps in between
   brings that to (3 + 4) / (2 + 4) = 1.17; an event, a start event moved back, or a
   chain defect over its allowance (checked after every step, free) ends the run of
   them, and a defect rejects the step. Measured (benchmarks/cosim_fixed.py, CPU time):
   conveyor at tol 1e-2 525 -> 391 ms at the same error (1.2e-5), two_block_belt at
   tol 1e-4 327 -> 261 ms (1.5e-5). More unjudged steps, checked by nothing else, lost
   control of the error; longer runs are guarded by the coupling defect (below). */
#define COAST_STEPS 4

/* How long a run of unjudged steps may grow, and what guards it. A run that ran to its
   end, followed by an estimate that keeps the step where it was (between COAST_STEADY
   and 1 / COAST_STEADY of the step asked for: the error is steady, or the output
   interval caps the step), doubles the next run, up to COAST_MAX; any other estimate
   (the step should grow or shrink: short runs let it change fast), an event, a located
   start event or a run cut short sets it back to COAST_STEPS, except a rejection that
   shrinks the step by less than COAST_KEEP after a full run (the run stays as long).
   (A step that may grow keeping the run's length had stick_slip with the smooth law at
   eps 1e-8 take 5790 doSteps instead of 4328; now 3910.)
   Every unjudged step is judged for free by its coupling defect (chain_defect: each
   coupling's extrapolation against what its source returned at the step's end): one
   over COAST_DEFECT_GROWTH times the defect at the last estimate (its second half
   step, of the run's length), plus what the FMUs' tolerance leaves in the values,
   rejects the step and estimates again. The estimate then stays valid where the
   coupling moves as it did when it was made, which is what a long run needs: on
   moving_table (a block on a shaken table, where a step's error depends on the
   table's phase) runs of up to 32 checked only by step doubling left block.s 2.6e-2
   off the monolithic model at tol 1e-2 (4.9e-4 at 1e-3); with the check 1.7e-3
   (2.4e-5), and runs of 4 did 5.9e-4 (1.8e-4) with as many doSteps. Measured (benchmarks.cosim_fixed,
   --repeats 3, CPU at the same error, runs of 4 -> these): beam_friction_damper vs
   fixed steps 1.31 / 1.61 / 1.24 / 1.20 -> see benchmarks/RESULTS.md (issue 27). */
#define COAST_MAX 32
#define COAST_STEADY 0.8
#define COAST_KEEP 0.5
#define COAST_DEFECT_GROWTH 2.0

/* Steps fit the output grid: the steps between where a step starts and the next output
   point are equal, as many as a step of the length asked for needs (cells()), so that
   no output point cuts one short. Before, the steps ran at the length asked for and the
   last before each output point was what was left of the interval: an estimate taken on
   that remnant made the next run's steps half of it (beam_friction_damper at tol 1e-2:
   runs of 1.6 ms steps in an interval of 12.5 ms the estimate allowed 6.25 ms in), and
   the run started again at COAST_STEPS. The run's length is now the estimate's wish
   (min of the step asked for and the next one, halved), and an estimate whose two
   halves do not fit before the output point is put off to it: the run goes on by one
   step (once), the coupling defect judging it like every other. A run the coupling
   defect ended (COAST_GUARDED) is no run cut short: where the estimate then keeps the
   step, the defect grew without the error, and the next run is as long as this one
   (not doubled: the couplings move unlike before). */
#define COAST_GUARDED 2

/* The order step doubling takes the coupling to be of: the extrapolation's + 1 where
   every held input is run along its polynomial (2.00, 2.99, 4.00 on two_block_belt at
   fixed steps), but never above 3. Friction events cap what a run shows: the shaken
   table measures order 2 at fixed steps whatever the extrapolation, and taken at 4
   (Richardson's error / 15) the cubic's estimate let moving_table end 1.06 and 1.96
   tol off at tol 1e-3 and 1e-4; at 3 (error / 7), 0.64 and 0.57, for 1.1-1.2x the
   doSteps. */
#define ORDER_MAX 3
#define FIT_STRETCH 0.25      /* the steps of an interval may grow by a quarter of one in all */
#define ESTIMATE_SPAN 2.0     /* the step asked for may be this many output intervals (adaptive.py) */

#define HISTORY 4             /* points kept per held input: enough for order 3 */

typedef struct cosim cosim;

typedef struct {
    cosim *owner;
    int index;
    fmu_t *fmu;
    double step_start;        /* currentCommunicationPoint of the doStep in progress */
    int event_at_start;       /* an event handled at the start of the step (inputs moved) */
    double event_in_step;     /* earliest event located inside the step; INFINITY: none */
    eng_table *events;        /* outputs at this instance's events, time first */
} instance;

/* Everything a rollback restores: the FMUs' states and the master's own memory. */
typedef struct {
    void **fmu_state;
    double *hist_t, *hist_v;  /* n_couplings x HISTORY */
    int *hist_n;
    long *n_events;
    int terminated, terminated_instance;
    double terminated_time;
    double t;
    /* the members the master evaluates (cosim.evaluated): the inputs it keeps for them,
       where each FMU stood and which of its up-to-date points fmu_state[i] holds (its
       FMU state is got again only when it moved since) */
    double *u;
    double *fmu_time;
    long *version;
} snapshot;

/* A held input's last points and their divided differences (fit_held). */
typedef struct {
    int m;
    double pt[HISTORY], pv[HISTORY], d[HISTORY];
} poly_memo;

/* Step controller of adaptive.py: error per unit step, exponent 1/p. Its shortest step
   is MF_MIN_STEP(t), the time's resolution where it stands: one relative to the
   horizon (1e-12 x 1e4 s) refused the steps a friction onset needs late in a long run. */
typedef struct {
    double tol, horizon, h_max;
    double h_cap; /* the longest step asked for: ESTIMATE_SPAN output intervals */
    int order;
} controller;

struct cosim {
    const eng_cosim_spec *cfg;
    eng_stats *run_stats;
    eng_cosim_stats *stats;
    eng_run *run;
    instance *inst;
    fmu_t **fmus;
    double *u;                /* the value last set on each coupling's input */
    double *hist_t, *hist_v;  /* history of held inputs at communication points */
    int *hist_n;
    int *in_loop;
    int *done;                /* Gauss–Seidel: instances stepped in this sweep */
    double *asleep_since;     /* per instance: when its group fell asleep; INFINITY: awake */
    int *moving;              /* per instance, while groups are checked: a derivative is not 0 */
    int *which;               /* instances whose event is being located */
    int hold_raw;             /* this step holds the sources' values (no extrapolation) */
    int all_rated;            /* every held input takes its rates: the coupling's order is
                                 the extrapolation's + 1 (ORDER_MAX) */
    int rejected_last;        /* the step controller's last step was rejected */
    int coast;                /* unjudged steps of h_coast left before the next estimate */
    double h_coast;           /* their length: the half step the estimate found good */
    double *state, *coarse;   /* state vectors for the error estimate */
    double *predicted;        /* chained inputs: where the FMU's Taylor chain ends a step */
    double *settle_u;         /* the inputs where an event's modes began to settle */
    int unsettled;            /* settling was cut at an output point: it goes on from there */
    int *chain_order;         /* chained inputs: 1 + the chain's length below them */
    int *judged_end;          /* per coupling: a rated chain end whose target has indicators
                                 (chain_defect) */
    double *rate_v;           /* per coupling, ENG_RATES: the rates set on its target */
    poly_memo *memo;          /* per coupling: its last divided differences */
    double defect;            /* the last step's worst chain defect over its allowance */
    int defect_order;         /* ... and the order of that chain's defect in the step */
    eng_loop loop;            /* the loop solver, sized for the largest group */
    double coupling_defect;   /* the last step's worst coupling off its extrapolation */
    double defect_ref;        /* ... at the last accepted estimate's second half step
                                 (from an output interval on: the largest since the run
                                 last reset) */
    double defect_ref_h;      /* ... the length of the half step it was taken at */
    int coast_run;            /* length of the next run of unjudged steps */
    int coast_done;           /* the last run of unjudged steps ran to its end (1), or
                                 the coupling defect ended it (COAST_GUARDED) */
    int coast_extended;       /* the run went on past its end to an output point */
    snapshot snap[3];         /* current step, previous step, probe */
    int terminated, terminated_instance;
    double terminated_time;
    double *row;              /* one event row */
    /* where the stepping stands between two calls of one_step */
    controller ctl;
    double t, h;              /* the time reached; the adaptive step to try next */
    double h_prev;            /* the last accepted step, which ended at t */
    double located_at;        /* the last start-of-step event moved back to here */
    int have_prev;            /* snap[1] holds the start of that step: an event may move into it */
    /* members evaluated by the master (eng_cosim_spec.time_function / .linear_map; anchor):
       evaluated[i] EVAL_TIME or EVAL_LINEAR while they are, from the start of the run. By
       coupling out of one: ev_y0 its source value at the start (no gain), ev_rate its
       rate (EVAL_TIME) or ev_row the start of its row of d output / d input in ev_J over
       the couplings into its instance, ev_in[ev_in_start[i] .. ev_in_start[i + 1] - 1];
       by coupling into one: ev_u0 its input at the start. By state (`states`): ev_x0 and
       ev_dx where its instance is EVAL_TIME. */
    int *evaluated, any_evaluated, *recorded;
    int *ev_in_start, *ev_in, *ev_row;
    double *ev_y0, *ev_rate, *ev_u0, *ev_J, *ev_x0, *ev_dx;
    double ev_t0;             /* the start: where every constant above was read */
    double t_now;             /* where the last step() left the stepped members */
    int *stale;               /* per instance: its FMU's inputs lag the master's */
    double *fmu_time;         /* per instance: where its FMU stands (an evaluated one lags) */
    long *version, versions;  /* per instance: its FMU's up-to-date point (a counter) */
};

enum { EVAL_NONE = 0, EVAL_TIME = 1, EVAL_LINEAR = 2 };

/* ---------------------------------------------------------------------------- */
/* messages and FMU calls                                                          */

static int fail(cosim *c, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(c->run_stats->message, sizeof c->run_stats->message, fmt, ap);
    va_end(ap);
    return -1;
}

static int fmu_fail(cosim *c, int i, const char *what, double t)
{
    eng_describe_failure(c->run_stats->message, sizeof c->run_stats->message, c->fmus[i], what, t);
    return -1;
}

/* Coupled output k of an evaluated member at t, from the constants of the start. */
static double evaluated_value(const cosim *c, int k, double t)
{
    const int i = c->cfg->couplings[k].source.instance;
    double y = c->ev_y0[k];
    int a;
    if (c->evaluated[i] == EVAL_TIME) return y + c->ev_rate[k] * (t - c->ev_t0);
    for (a = c->ev_in_start[i]; a < c->ev_in_start[i + 1]; a++) {
        const int j = c->ev_in[a];
        y += c->ev_J[c->ev_row[k] + a - c->ev_in_start[i]] * (c->u[j] - c->ev_u0[j]);
    }
    return y;
}

/* Coupled output k at t: its source FMU holds it (stepped to t, or a member whose
   outputs follow its inputs), or the master evaluates it. */
static int source_value(cosim *c, int k, double t, double *value)
{
    const eng_variable *v = &c->cfg->couplings[k].source;
    double y;
    if (c->any_evaluated && c->evaluated[v->instance]) {
        *value = c->cfg->couplings[k].gain * evaluated_value(c, k, t);
        return 0;
    }
    if (eng_get_value(c->fmus[v->instance], v, &y))
        return fmu_fail(c, v->instance, "get of a coupled output", t);
    *value = c->cfg->couplings[k].gain * y;
    return 0;
}

static int set_input(cosim *c, int k, double value, double t)
{
    const eng_variable *v = &c->cfg->couplings[k].target;
    if (c->any_evaluated && c->evaluated[v->instance]) { /* kept here, set when it is read */
        c->u[k] = value;
        c->stale[v->instance] = 1;
        return 0;
    }
    if (eng_set_value(c->fmus[v->instance], v, value))
        return fmu_fail(c, v->instance, "set of a coupled input", t);
    c->u[k] = value;
    return 0;
}

/* FMI 3 intermediate update: an event inside a step. Records the instance's
   outputs and what the synchronisation needs to know; never asks to return early. */
static int on_intermediate(void *ctx, fmu_t *f, double time, int get_allowed, int step_finished,
                           int can_return_early)
{
    instance *in = (instance *)ctx;
    const eng_instance_spec *spec = &in->owner->cfg->instances[in->index];
    double *row = in->owner->row;
    int j;
    (void)can_return_early;
    if (!get_allowed || step_finished) return 0;
    if (time <= in->step_start + 1e-12 * fmax(1.0, fabs(in->step_start))) in->event_at_start = 1;
    else if (time < in->event_in_step) in->event_in_step = time;
    row[0] = time;
    for (j = 0; j < spec->n_event_outputs; j++) {
        row[1 + j] = NAN;
        eng_get_value(f, &spec->event_outputs[j], &row[1 + j]);
    }
    eng_table_append(in->events, row); /* out of memory: the row is lost, the run goes on */
    return 0;
}

/* ---------------------------------------------------------------------------- */
/* held inputs: the step mean of the extrapolating polynomial (extrapolation.py)  */

static void push_history(cosim *c, int k, double t, double value)
{
    double *ht = c->hist_t + k * HISTORY, *hv = c->hist_v + k * HISTORY;
    double eps = 1e-12 * fmax(1.0, fabs(t));
    int n = c->hist_n[k], keep = 0, j;
    for (j = 0; j < n; j++) { /* drop points at or after t (a step redone) */
        if (ht[j] < t - eps) {
            ht[keep] = ht[j];
            hv[keep] = hv[j];
            keep++;
        }
    }
    if (keep == HISTORY) {
        memmove(ht, ht + 1, (HISTORY - 1) * sizeof(double));
        memmove(hv, hv + 1, (HISTORY - 1) * sizeof(double));
        keep--;
    }
    ht[keep] = t;
    hv[keep] = value;
    c->hist_n[k] = keep + 1;
}

/* Newton's divided differences d of m points, in absolute time: they depend on the
   points alone, not on the step, so one set serves every step tried from the same
   points (fit_held). The points are distinct communication points. */
static void divided_differences(const double *pt, const double *pv, int m, double d[HISTORY])
{
    int a, b;
    for (a = 0; a < m; a++) d[a] = pv[a];
    for (a = 1; a < m; a++) /* d[b]: the divided difference over points b - a ... b */
        for (b = m - 1; b >= a; b--) d[b] = (d[b] - d[b - 1]) / (pt[b] - pt[b - a]);
}

/* The Newton form (d over the nodes pt) as coefficients in units of h from t,
   p(t + s h) = sum_k coef[k] s^k: expanded about t by Horner's scheme, then scaled by
   h^k. Only products: a held input is fitted at every step tried, and the divisions
   of a fit in units of h (the old way) were a fifth of two_block_belt's CPU time
   (perf). */
static void expand_about(const double *pt, const double d[HISTORY], int m, double t, double h,
                         double coef[HISTORY])
{
    double scale = 1.0;
    int a, b;
    for (a = 0; a < m; a++) coef[a] = d[a];
    for (a = m - 2; a >= 0; a--) /* p = d[a] + (x - pt[a]) p, from the highest down */
        for (b = a; b < m - 1; b++) coef[b] -= (pt[a] - t) * coef[b + 1];
    for (a = 1; a < m; a++) {
        scale *= h;
        coef[a] *= scale;
    }
}

/* Coefficients (in units of h from t) of the polynomial through the last order + 1 of
   held input k's n points; returns how many (at most HISTORY). The operations of the
   fmpy master's extrapolation._fit in its order (the two round alike). The divided
   differences are remembered per input and reused where the points are the same
   (set_held and held_end_value in every step, the full step and the first half of step
   doubling); keyed on the values themselves, they cannot go stale. */
static int fit_held(cosim *c, int k, const double *pt, const double *pv, int n, double t,
                    double h, double coef[HISTORY])
{
    poly_memo *memo = &c->memo[k];
    int order = c->cfg->extrapolation, m = n < order + 1 ? n : order + 1, a = 0;
    pt += n - m;
    pv += n - m;
    if (memo->m == m)
        for (a = 0; a < m && memo->pt[a] == pt[a] && memo->pv[a] == pv[a]; a++) continue;
    if (memo->m != m || a != m) {
        divided_differences(pt, pv, m, memo->d);
        memo->m = m;
        memcpy(memo->pt, pt, (size_t)m * sizeof(double));
        memcpy(memo->pv, pv, (size_t)m * sizeof(double));
    }
    expand_about(pt, memo->d, m, t, h, coef);
    return m;
}

/* Mean over [t, t + h] of the polynomial through the last order + 1 points. */
static double step_mean(cosim *c, int k, const double *pt, const double *pv, int n, double t,
                        double h)
{
    double coef[HISTORY], mean = 0.0;
    int m = fit_held(c, k, pt, pv, n, t, h, coef), j;
    for (j = 0; j < m; j++) mean += coef[j] / (j + 1);
    return mean;
}

/* Held input k's history before t_source, then `now`, its source's value at t_source
   (t, or t + h where Gauss–Seidel stepped the source already); returns how many. */
static int held_points(const cosim *c, int k, double t_source, double now, double *pt, double *pv)
{
    const double *ht = c->hist_t + k * HISTORY, *hv = c->hist_v + k * HISTORY;
    double eps = 1e-12 * fmax(1.0, fabs(t_source));
    int n = 0, j;
    for (j = 0; j < c->hist_n[k]; j++) {
        if (ht[j] < t_source - eps) {
            pt[n] = ht[j];
            pv[n] = hv[j];
            n++;
        }
    }
    pt[n] = t_source;
    pv[n] = now;
    return n + 1;
}

/* The constant for held input k over [t, t + h]. */
static double held_value(cosim *c, int k, double t, double h, double t_source, double now)
{
    double pt[HISTORY + 1], pv[HISTORY + 1];
    int n;
    if (c->cfg->extrapolation == 0 && t_source == t) return now;
    n = held_points(c, k, t_source, now, pt, pv);
    return step_mean(c, k, pt, pv, n, t, h);
}

/* Held input k's rate inputs, where its target has them (cosim.h: rates); NULL
   otherwise. */
static const eng_variable *rate_inputs(const cosim *c, int k)
{
    const eng_variable *r = c->cfg->rates ? c->cfg->rates + ENG_RATES * k : NULL;
    return r && r[0].instance >= 0 ? r : NULL;
}

/* A member the master evaluates takes its inputs at communication points only: its
   rates are kept for the chains' end values (so that the step control is the same as
   with the member stepped), not set. */
static int set_rates(cosim *c, int k, const eng_variable *r, const double rates[ENG_RATES], double t)
{
    const int stepped = !(c->any_evaluated && c->evaluated[r[0].instance]);
    int j;
    for (j = 0; j < ENG_RATES; j++) {
        double value = r[j].instance >= 0 ? rates[j] : 0.0;
        if (stepped && r[j].instance >= 0 && eng_set_value(c->fmus[r[j].instance], &r[j], value))
            return fmu_fail(c, r[j].instance, "set of a rate input", t);
        c->rate_v[ENG_RATES * k + j] = value;
    }
    return 0;
}

/* Sets held input k and its rates on its stepped target in one fmu_set_float64 where
   all are plain Float64 values of it (ours always are: four calls through every FMI
   layer cost more than the fit they set). 1: set; 0: not such a case (nothing set);
   -1: the FMU refused them. */
static int set_plain_with_rates(cosim *c, int k, const eng_variable *r, double value,
                                const double rates[ENG_RATES], double t)
{
    const eng_variable *v = &c->cfg->couplings[k].target;
    uint32_t vr[1 + ENG_RATES];
    double values[1 + ENG_RATES];
    int n = 1, j;
    if ((c->any_evaluated && c->evaluated[v->instance]) || !ENG_PLAIN(v)) return 0;
    vr[0] = v->vr;
    values[0] = value;
    for (j = 0; j < ENG_RATES; j++) {
        if (r[j].instance < 0) continue;
        if (r[j].instance != v->instance || !ENG_PLAIN(&r[j])) return 0;
        vr[n] = r[j].vr;
        values[n++] = rates[j];
    }
    if (fmu_set_float64(c->fmus[v->instance], vr, (size_t)n, values))
        return fmu_fail(c, v->instance, "set of a coupled input and its rates", t);
    c->u[k] = value;
    for (j = 0; j < ENG_RATES; j++) c->rate_v[ENG_RATES * k + j] = r[j].instance >= 0 ? rates[j] : 0.0;
    return 1;
}

/* Sets held input k for the step [t, t + h]: the extrapolating polynomial itself where
   its target takes the input's rates (its value and derivatives at t, which the FMU's
   Taylor chain turns back into the polynomial), its step mean otherwise. */
static int set_held(cosim *c, int k, double t, double h, double t_source, double now)
{
    const eng_variable *r = rate_inputs(c, k);
    double pt[HISTORY + 1], pv[HISTORY + 1], coef[HISTORY] = {0.0}, rates[ENG_RATES] = {0.0};
    double scale = 1.0;
    int m, j, batched;
    if (!r) return set_input(c, k, held_value(c, k, t, h, t_source, now), t);
    m = fit_held(c, k, pt, pv, held_points(c, k, t_source, now, pt, pv), t, h, coef);
    for (j = 0; j < ENG_RATES && j + 1 < m; j++) { /* d^j/dt^j of coef[j] (t - t0)^j / h^j */
        scale *= (double)(j + 1) / h;
        rates[j] = coef[j + 1] * scale;
    }
    batched = set_plain_with_rates(c, k, r, coef[0], rates, t);
    if (batched) return batched < 0 ? -1 : 0;
    if (set_input(c, k, coef[0], t)) return -1;
    return set_rates(c, k, r, rates, t);
}

/* Held input k's rates back to 0 (the input held constant), where any is not. */
static int clear_rates(cosim *c, int k, double t)
{
    static const double none[ENG_RATES] = {0.0};
    const eng_variable *r = c->cfg->held[k] ? rate_inputs(c, k) : NULL;
    int j;
    if (!r) return 0;
    for (j = 0; j < ENG_RATES; j++)
        if (c->rate_v[ENG_RATES * k + j] != 0.0) return set_rates(c, k, r, none, t);
    return 0;
}

/* Sets input k to its source's value, held over the step. */
static int set_raw(cosim *c, int k, double value, double t)
{
    return set_input(c, k, value, t) ? -1 : clear_rates(c, k, t);
}

/* ---------------------------------------------------------------------------- */
/* the motion an FMU extrapolates itself: its defect at the step's end             */

/* Where the target FMU's Taylor chain (s -> v -> a, runtime.c inputs_at) puts chained
   input k at the end of a step of h, from the values set for the step. */
static double chain_end_value(const cosim *c, int k, double h)
{
    double value = c->u[k], term = 1.0;
    int d = c->cfg->derivative[k], order = 1, end = k, j;
    while (d >= 0 && order <= c->cfg->n_couplings) {
        term *= h / order++;
        if (c->u[d] != 0.0) value += c->u[d] * term;
        end = d;
        d = c->cfg->derivative[d];
    }
    for (j = 0; j < ENG_RATES; j++) { /* the chain's end goes on along its rates (0: none) */
        term *= h / order++;
        if (c->rate_v[ENG_RATES * end + j] != 0.0) value += c->rate_v[ENG_RATES * end + j] * term;
    }
    return value;
}

/* Where the extrapolating polynomial through held input k's history (its last point is
   the step's start) puts the coupling at the end of a step of h. */
static double held_end_value(cosim *c, int k, double h)
{
    const double *ht = c->hist_t + k * HISTORY, *hv = c->hist_v + k * HISTORY;
    double coef[HISTORY], end = 0.0;
    int n = c->hist_n[k], m, j;
    if (n < 1) return c->u[k];
    m = fit_held(c, k, ht, hv, n, ht[n - 1], h, coef);
    for (j = 0; j < m; j++) end += coef[j]; /* at tau = 1: t + h */
    return end;
}

static void predict_chains(cosim *c, double h)
{
    int k;
    for (k = 0; k < c->cfg->n_couplings; k++) {
        if (c->cfg->derivative[k] >= 0) c->predicted[k] = chain_end_value(c, k, h);
        else if (c->cfg->held[k]) c->predicted[k] = held_end_value(c, k, h);
    }
}

/* After consistent() at the step's end: how far the motion each FMU extrapolated
   strays from its source's, over what the step may leave (tol, relative to the value
   like the FMUs' own solver tolerance). A friction block that sticks to a shaken
   table has states that do not move, so step doubling sees no error while the table's
   acceleration passes the static limit and back within one step; this bound keeps
   the table's motion as the block sees it within tol of the table's own, and so the
   communication points close enough to see such an excursion. */
/* Whether an FMU feeding chain k (the input or one of its derivatives) had an event in
   the step just taken. The chain is at most n_couplings links long (derivative[] is
   acyclic, as chain_end_value also assumes). */
static int source_had_event(const cosim *c, int k)
{
    int links;
    for (links = 0; k >= 0 && links <= c->cfg->n_couplings; links++) {
        const instance *in = &c->inst[c->cfg->couplings[k].source.instance];
        if (in->event_at_start || isfinite(in->event_in_step)) return 1;
        k = c->cfg->derivative[k];
    }
    return 0;
}

/* Whether coupling k's target FMU had an event in the step just taken. */
static int target_had_event(const cosim *c, int k)
{
    const instance *in = &c->inst[c->cfg->couplings[k].target.instance];
    return in->event_at_start || isfinite(in->event_in_step);
}

/* ... A chain whose source had an event in the step is left out: an event may make the
   source's motion jump (a mass hitting a hard stop: v := 0), which no Taylor chain
   follows, so its defect stays the jump over tol however short the step, and the
   step shrank to nothing just before the impact (translational_friction's stop2).
   Event synchronisation has already ended the step at the event, so the target takes
   the jumped value at this communication point; the motion before the event is still
   judged by step doubling on the states. */
/* Alongside, the coupling defect (c->coupling_defect): the same miss for every coupling,
   held inputs included (where the polynomial through their history, which the held
   mean comes from, ends the step), relative to the value and not to tol. It costs no
   doStep; the step controller compares it with its value when step doubling last
   vouched for the step (one_step, COAST_DEFECT_GROWTH). A coupling whose source had
   an event in the step is left out of both: its jump is the event's, and the event
   ends the run. (Counted, a friction force's jump rejected the unjudged step after
   the event and step doubling then judged steps whose held input extrapolated across
   the jump, shrinking them to nothing: moving_table, tol 1e-5, extrapolation 1.) */
/* A held input run along its polynomial into an FMU that has event indicators is judged
   as a chain of its own (judged_end) in a step where that FMU had an event: the event
   it fired from the input (a block letting go of a shaken table) is off by as far as
   the polynomial strays, which step doubling does not see while the block sticks and
   its states stand still. The short slips' break-aways at tol 1e-5: 5.5e-4 s early
   unjudged, 2.4e-4 judged so (within tol (1 + |a|) over the rate a crosses at, 4.5e-4;
   moved back by bisection from a held input they were 1e-9 off). Judged in every
   step, beam_friction_damper's pad took its beam tip's ringing acceleration to tol
   throughout, 1.4x the doSteps at tol 1e-2. Only from an FMI 3 source,
   which reports its events: a jump no event reports (an FMI 2 member's) would keep
   the defect over its allowance however short the step. */
static void chain_defect(cosim *c)
{
    const double tol = c->cfg->tol;
    int k;
    c->defect = 0.0;
    c->defect_order = 1;
    c->coupling_defect = 0.0;
    for (k = 0; k < c->cfg->n_couplings; k++) {
        double relative, ratio;
        if ((c->cfg->derivative[k] < 0 && !c->cfg->held[k]) || source_had_event(c, k)) continue;
        relative = fabs(c->u[k] - c->predicted[k]) / (1.0 + fabs(c->u[k]));
        c->coupling_defect = fmax(c->coupling_defect, relative);
        if (c->cfg->derivative[k] < 0 && !(c->judged_end[k] && target_had_event(c, k))) continue;
        ratio = fabs(c->u[k] - c->predicted[k]) / (tol * (1.0 + fabs(c->u[k])));
        if (ratio > c->defect) {
            c->defect = ratio;
            c->defect_order = c->chain_order[k];
        }
    }
}

/* ---------------------------------------------------------------------------- */
/* algebraic loops (loops.py)                                                      */

typedef struct {
    cosim *c;
    const int *cs;    /* the loop's couplings */
    double t;
} loop_ctx;

/* eng_loop_residual_fn: the loop's inputs set to u, r = u - G(u) */
static int loop_residual(void *ctx, const double *u, double *r)
{
    const loop_ctx *L = ctx;
    const int n = L->c->loop.n;
    int i;
    for (i = 0; i < n; i++) if (set_input(L->c, L->cs[i], u[i], L->t)) return -1;
    for (i = 0; i < n; i++) {
        double y;
        if (source_value(L->c, L->cs[i], L->t, &y)) return -1;
        r[i] = u[i] - y;
    }
    return 0;
}

/* eng_loop_matrix_fn: I - dG/du from the FMUs' directional derivatives */
static int loop_matrix(void *ctx, double *a)
{
    const loop_ctx *L = ctx;
    int bad = -1;
    if (eng_loop_matrix_dd(L->c->fmus, L->c->cfg->couplings, L->cs, L->c->loop.n, a, &bad))
        return fmu_fail(L->c, bad, "directional derivative", L->t);
    return 0;
}

static int solve_loop(cosim *c, int group, double t)
{
    const eng_cosim_spec *g = c->cfg;
    const int *cs = g->group_members + g->group_start[group];
    const eng_loop_options options = {g->loop_tolerance, g->max_loop_iterations, g->newton,
                                      0, 0};
    loop_ctx ctx = {c, cs, t};
    double res = 0.0;
    long before = c->loop.iterations;
    int i, rc;
    c->loop.n = g->group_start[group + 1] - g->group_start[group];
    for (i = 0; i < c->loop.n; i++) c->loop.u[i] = c->u[cs[i]];
    rc = eng_loop_solve(&c->loop, loop_residual, loop_matrix, &ctx, &options, &res);
    if (rc == ENG_LOOP_FAILED) return -1;
    if (rc == ENG_LOOP_OK) {
        c->stats->loop_iterations += c->loop.iterations - before;
        c->stats->loop_residual = fmax(c->stats->loop_residual, res);
        return 0;
    }
    c->stats->loop_failed_group = group;
    c->stats->loop_failed_time = t;
    if (rc == ENG_LOOP_SINGULAR) {
        c->stats->loop_singular = 1;
        return fail(c, "singular");
    }
    c->stats->loop_residual = res;
    return fail(c, "diverged");
}

/* ---------------------------------------------------------------------------- */
/* the master                                                                     */

/* Every input set to its source's output at t, loops solved; history updated. */
static int consistent(cosim *c, double t)
{
    const eng_cosim_spec *g = c->cfg;
    int grp, k;
    for (grp = 0; grp < g->n_groups; grp++) {
        if (g->group_is_loop[grp]) {
            if (solve_loop(c, grp, t)) return -1;
        } else {
            double y;
            k = g->group_members[g->group_start[grp]];
            if (source_value(c, k, t, &y) || set_input(c, k, y, t)) return -1;
        }
    }
    for (k = 0; k < g->n_couplings; k++)
        if (g->held[k]) push_history(c, k, t, c->u[k]);
    return 0;
}

/* FMI 2 ends a run with Discard and fmi2Terminated; FMI 3 with terminateSimulation
   (with OK or Discard): a step that ends the run is no failure, any other is. */
static int step_failed(int rc, const fmu_step_result *r)
{
    return rc != FMU_OK && !(rc == FMU_DISCARD && r->terminate);
}

static int do_step(cosim *c, int i, double t, double h)
{
    instance *in = &c->inst[i];
    fmu_step_result r;
    int rc;
    if (c->asleep_since[i] <= t) return 0; /* its group stands still for good */
    if (c->any_evaluated && c->evaluated[i]) return 0; /* the master evaluates it (bring_up) */
    memset(&r, 0, sizeof r);
    c->stats->do_steps++;
    in->step_start = t;
    /* a run that never rolls back says so: some FMUs commit a step only when told
       that no earlier state can be set again (noSetFMUStatePriorToCurrentPoint) */
    rc = fmu_do_step(in->fmu, t, h, !(c->cfg->adaptive || c->cfg->event_sync), &r);
    if (step_failed(rc, &r)) return fmu_fail(c, i, "doStep", t);
    if (r.terminate && !c->terminated) { /* the model cannot go on (why: in its log) */
        c->terminated = 1;
        c->terminated_instance = i;
        /* where it stopped, within the step (an FMU without fmi2LastSuccessfulTime
           reports the step's end) */
        c->terminated_time = fmax(t, fmin(r.last_time, t + h));
    }
    return 0;
}

/* An evaluated member's FMU brought to where the master stands at t: its inputs set to
   the master's, and a time function stepped over the time it lagged (one doStep: its
   derivatives are constants, which its runtime takes in one stride). */
static int bring_up(cosim *c, int i, double t)
{
    const eng_cosim_spec *g = c->cfg;
    int a;
    if (!c->any_evaluated || !c->evaluated[i]) return 0;
    if (c->stale[i]) {
        for (a = c->ev_in_start[i]; a < c->ev_in_start[i + 1]; a++) {
            const int k = c->ev_in[a];
            if (eng_set_value(c->fmus[i], &g->couplings[k].target, c->u[k]))
                return fmu_fail(c, i, "set of a coupled input", t);
        }
        c->stale[i] = 0;
        c->version[i] = ++c->versions;
    }
    if (c->evaluated[i] == EVAL_TIME && t > c->fmu_time[i]) {
        fmu_step_result r;
        memset(&r, 0, sizeof r);
        c->stats->do_steps++;
        c->inst[i].step_start = c->fmu_time[i];
        if (step_failed(fmu_do_step(c->inst[i].fmu, c->fmu_time[i], t - c->fmu_time[i],
                                    !(g->adaptive || g->event_sync), &r), &r))
            return fmu_fail(c, i, "doStep", c->fmu_time[i]);
        c->fmu_time[i] = t;
        c->version[i] = ++c->versions;
    }
    return 0;
}

static void clear_event_flags(cosim *c)
{
    int i;
    for (i = 0; i < c->cfg->n_instances; i++) {
        c->inst[i].event_at_start = 0;
        c->inst[i].event_in_step = INFINITY;
    }
}

/* One communication step from t (inputs consistent at t) to t + h. */
static int step(cosim *c, double t, double h)
{
    const eng_cosim_spec *g = c->cfg;
    const int extrapolate = g->extrapolation && !c->hold_raw;
    int i, k;
    clear_event_flags(c);
    if (g->scheme == ENG_JACOBI) {
        for (k = 0; k < g->n_couplings; k++) {
            double now;
            if (!g->held[k]) continue;
            now = c->hist_v[k * HISTORY + c->hist_n[k] - 1];
            /* (held raw, the input stands where consistent() set it) */
            if (extrapolate ? set_held(c, k, t, h, t, now) : clear_rates(c, k, t)) return -1;
        }
        for (i = 0; i < g->n_instances; i++)
            if (do_step(c, i, t, h)) return -1;
    } else {
        int *done = c->done, n, status = 0;
        memset(done, 0, (size_t)g->n_instances * sizeof(int));
        for (n = 0; n < g->n_instances && !status; n++) {
            int name = g->sweep_order[n];
            for (k = 0; k < g->n_couplings && !status; k++) {
                int ahead;
                double now;
                if (g->couplings[k].target.instance != name) continue;
                ahead = done[g->couplings[k].source.instance];
                if (c->in_loop[k] && !(g->held[k] && extrapolate))
                    continue; /* keeps the loop's consistent value from t */
                if (ahead || !c->in_loop[k]) { /* (a source stepped already stands at t + h) */
                    if (source_value(c, k, ahead ? t + h : t, &now)) { status = -1; break; }
                } else {
                    now = c->hist_v[k * HISTORY + c->hist_n[k] - 1];
                }
                if (g->held[k] && extrapolate ? set_held(c, k, t, h, ahead ? t + h : t, now)
                                              : set_raw(c, k, now, t))
                    status = -1;
            }
            if (!status && do_step(c, name, t, h)) status = -1;
            done[name] = 1;
        }
        if (status) return -1;
    }
    if (c->terminated) return 0;
    c->t_now = t + h;
    predict_chains(c, h);
    if (consistent(c, t + h)) return -1;
    chain_defect(c);
    return 0;
}

/* ---------------------------------------------------------------------------- */
/* rollback                                                                       */

static int snap_alloc(cosim *c, snapshot *s)
{
    int n = c->cfg->n_couplings > 0 ? c->cfg->n_couplings : 1;
    s->fmu_state = (void **)calloc((size_t)c->cfg->n_instances, sizeof(void *));
    s->hist_t = (double *)calloc((size_t)n * HISTORY, sizeof(double));
    s->hist_v = (double *)calloc((size_t)n * HISTORY, sizeof(double));
    s->hist_n = (int *)calloc((size_t)n, sizeof(int));
    s->n_events = (long *)calloc((size_t)c->cfg->n_instances, sizeof(long));
    s->u = (double *)calloc((size_t)n, sizeof(double));
    s->fmu_time = (double *)calloc((size_t)c->cfg->n_instances + 1, sizeof(double));
    s->version = (long *)calloc((size_t)c->cfg->n_instances + 1, sizeof(long));
    return s->fmu_state && s->hist_t && s->hist_v && s->hist_n && s->n_events && s->u
           && s->fmu_time && s->version ? 0 : -1;
}

static void snap_free(cosim *c, snapshot *s)
{
    int i;
    if (s->fmu_state)
        for (i = 0; i < c->cfg->n_instances; i++)
            if (s->fmu_state[i]) fmu_free_state(c->inst[i].fmu, &s->fmu_state[i]);
    free(s->fmu_state);
    free(s->hist_t);
    free(s->hist_v);
    free(s->hist_n);
    free(s->n_events);
    free(s->u);
    free(s->fmu_time);
    free(s->version);
    memset(s, 0, sizeof *s);
}

static int save(cosim *c, snapshot *s, double t)
{
    int i, n = c->cfg->n_couplings;
    for (i = 0; i < c->cfg->n_instances; i++) {
        const int evaluated = c->any_evaluated && c->evaluated[i];
        /* an evaluated member's FMU moves only where it is brought up to date: a state
           this snapshot holds already is still its state */
        if (!evaluated || !s->fmu_state[i] || s->version[i] != c->version[i]) {
            if (fmu_get_state(c->inst[i].fmu, &s->fmu_state[i]) != FMU_OK)
                return fmu_fail(c, i, "getFMUState", t);
            s->version[i] = c->version[i];
        }
        s->fmu_time[i] = c->fmu_time[i];
        s->n_events[i] = c->inst[i].events->n_rows;
    }
    if (c->any_evaluated) memcpy(s->u, c->u, (size_t)n * sizeof(double));
    memcpy(s->hist_t, c->hist_t, (size_t)n * HISTORY * sizeof(double));
    memcpy(s->hist_v, c->hist_v, (size_t)n * HISTORY * sizeof(double));
    memcpy(s->hist_n, c->hist_n, (size_t)n * sizeof(int));
    s->terminated = c->terminated;
    s->terminated_instance = c->terminated_instance;
    s->terminated_time = c->terminated_time;
    s->t = t;
    return 0;
}

static int restore_instance(cosim *c, const snapshot *s, int i)
{
    const int evaluated = c->any_evaluated && c->evaluated[i];
    if ((!evaluated || c->version[i] != s->version[i])
        && fmu_set_state(c->inst[i].fmu, s->fmu_state[i]) != FMU_OK)
        return fmu_fail(c, i, "setFMUState", s->t);
    if (evaluated) {
        c->version[i] = s->version[i];
        c->fmu_time[i] = s->fmu_time[i];
    }
    c->inst[i].events->n_rows = s->n_events[i]; /* events of a step that did not count */
    return 0;
}

static int restore(cosim *c, const snapshot *s)
{
    const eng_cosim_spec *g = c->cfg;
    int i, k, n = g->n_couplings;
    for (i = 0; i < g->n_instances; i++) {
        /* back to before a group fell asleep: it moves again from there */
        if (c->asleep_since[i] > s->t) c->asleep_since[i] = INFINITY;
        if (restore_instance(c, s, i)) return -1;
    }
    memcpy(c->hist_t, s->hist_t, (size_t)n * HISTORY * sizeof(double));
    memcpy(c->hist_v, s->hist_v, (size_t)n * HISTORY * sizeof(double));
    memcpy(c->hist_n, s->hist_n, (size_t)n * sizeof(int));
    c->terminated = s->terminated;
    c->terminated_instance = s->terminated_instance;
    c->terminated_time = s->terminated_time;
    /* the inputs are part of each FMU's state; read them back into the master's copy
       (an evaluated member's are the master's own: from the snapshot) */
    for (k = 0; k < n; k++) {
        const eng_variable *v = &g->couplings[k].target;
        if (c->any_evaluated && c->evaluated[v->instance]) {
            c->u[k] = s->u[k];
            c->stale[v->instance] = 1;
            continue;
        }
        if (eng_get_value(c->fmus[v->instance], v, &c->u[k]))
            return fmu_fail(c, v->instance, "get of a coupled input", s->t);
    }
    return 0;
}

/* The states where the last step() ended (an evaluated time function's from time). */
static int state_vector(cosim *c, double *x, double t)
{
    const eng_cosim_spec *g = c->cfg;
    int j;
    for (j = 0; j < g->n_states; j++) {
        const eng_variable *v = &g->states[j];
        if (c->any_evaluated && c->evaluated[v->instance] == EVAL_TIME) {
            x[j] = c->ev_x0[j] + c->ev_dx[j] * (c->t_now - c->ev_t0);
            continue;
        }
        if (eng_get_value(c->fmus[v->instance], v, &x[j]))
            return fmu_fail(c, v->instance, "get of a state", t);
    }
    return 0;
}

/* ---------------------------------------------------------------------------- */
/* event synchronisation                                                          */

static double earliest_event_in_step(const cosim *c)
{
    double te = INFINITY;
    int i;
    for (i = 0; i < c->cfg->n_instances; i++) te = fmin(te, c->inst[i].event_in_step);
    return te;
}

static int any_event_at_start(const cosim *c)
{
    int i;
    for (i = 0; i < c->cfg->n_instances; i++)
        if (c->inst[i].event_at_start) return 1;
    return 0;
}

/* The step a probe takes to see whether an event fires at its start: the FMU handles
   such an event before it integrates, so any length the FMU accepts will do. */
static double probe_step(double t) { return 1e-8 * fmax(1.0, fabs(t)); }

/* Would an event fire at the start of the next step from t (inputs consistent at t)?
   Each instance in `which` takes a tiny step and is put back. */
static int fires_at_start(cosim *c, const int *which, double t, double h_probe, int *fires)
{
    snapshot *p = &c->snap[2];
    int i;
    *fires = 0;
    for (i = 0; i < c->cfg->n_instances && !*fires; i++) {
        instance *in = &c->inst[i];
        /* (an evaluated member has no indicators: nothing fires in it) */
        if (!which[i] || (c->any_evaluated && c->evaluated[i])) continue;
        if (fmu_get_state(in->fmu, &p->fmu_state[i]) != FMU_OK) return fmu_fail(c, i, "getFMUState", t);
        p->n_events[i] = in->events->n_rows;
        in->event_at_start = 0;
        in->event_in_step = INFINITY;
        in->step_start = t;
        { /* (a terminate request is the real step's business) */
            fmu_step_result r;
            if (step_failed(fmu_do_step(in->fmu, t, h_probe, 0, &r), &r))
                return fmu_fail(c, i, "doStep", t);
        }
        c->stats->do_steps++;
        *fires = in->event_at_start;
        p->t = t;
        if (restore_instance(c, p, i)) return -1;
    }
    return 0;
}

/* An event fired at the start of the step from prev->t + h_prev: the inputs crossed
   an indicator's zero somewhere in the previous step. Bisect that step (rollback to
   `prev`) for the earliest point where the event fires, and leave the run there:
   returns the new time in *t_event. `which`: the instances whose event it was. */
static int locate_start_event(cosim *c, const snapshot *prev, double h_prev, const int *which,
                              double *t_event)
{
    double lo = 0.0, hi = h_prev, t0 = prev->t;
    double width = fmax(c->cfg->event_tol, 4e-16 * fmax(1.0, fabs(t0)));
    double probe = probe_step(t0);
    int held_raw = c->hold_raw, status = 0;
    /* the trial steps hold the sources' values from t0: an extrapolated input is the
       mean over the trial step, ahead of its source by an amount that grows with the
       trial's length, and could fire the event at t0 in a long trial and not in a short
       one (the bisection then converges anywhere); held at t0's values, the FMU sees
       the coupled system's crossing only at the probe, where the inputs are consistent */
    c->hold_raw = 1;
    while (hi - lo > width && !status) {
        double m = 0.5 * (lo + hi);
        int fires, i;
        if (restore(c, prev) || step(c, t0, m)) { status = -1; break; }
        for (i = 0, fires = 0; i < c->cfg->n_instances; i++)
            if (which[i] && c->inst[i].event_at_start) fires = 1; /* already at t0 */
        if (c->terminated || fires) { hi = m; continue; }
        if (fires_at_start(c, which, t0 + m, probe, &fires)) { status = -1; break; }
        if (fires) hi = m;
        else lo = m;
    }
    /* the step kept, up to the first point known to fire, takes the inputs as any step
       does: held at t0's values over it (up to the step before, a full one), their
       error was never judged; CoupledClutches' J1.w took 7e-5 rad/s from it at 0.4 s */
    c->hold_raw = held_raw;
    if (!status && (restore(c, prev) || step(c, t0, hi))) status = -1;
    c->hold_raw = held_raw;
    if (status) return -1;
    c->stats->events_located++;
    *t_event = t0 + hi;
    return 0;
}

/* Settle steps after an event at a communication point (MAX_SETTLE_STEPS): a cascade
   needs one per FMU whose mode change moves another's inputs across its condition. */
#define MAX_SETTLE_STEPS 16

/* After settling: a held input that jumped while the modes settled (by more than tol
   relative to its value; a smooth one moves by its rate times a few probes) restarts
   its history at the settled point, as a polynomial through values from before the
   jump extrapolates it across the next step. One that did not keeps its history:
   restarting a ramp held it constant over the next fixed step after a break-away
   (test_rotational_friction, w off by 1e-3). */
static void restart_moved_history(cosim *c)
{
    const eng_cosim_spec *g = c->cfg;
    int k;
    for (k = 0; k < g->n_couplings; k++) {
        if (!g->held[k] || c->hist_n[k] < 1
            || !(fabs(c->u[k] - c->settle_u[k]) > g->tol * (1.0 + fabs(c->u[k]))))
            continue;
        c->hist_t[k * HISTORY] = c->hist_t[k * HISTORY + c->hist_n[k] - 1];
        c->hist_v[k * HISTORY] = c->hist_v[k * HISTORY + c->hist_n[k] - 1];
        c->hist_n[k] = 1;
    }
}

static void restart_jumped_history(cosim *c)
{
    c->unsettled = 0;
    restart_moved_history(c);
}

/* An event fires at the start of the step from c->t: an input set there crossed a
   switching condition (a locked clutch whose normal force drops to 0). Our FMUs are Co-
   Simulation without Event Mode (FMI 2 has none; ours declare hasEventMode = false), so
   a member changes its mode only at the start of a doStep, after the master made every
   input consistent with the outputs of the old modes: the coupled step that follows
   would take the loop's values of the locked clutch (its torque on the driver, the
   driver's acceleration of the pair) over its whole length, and a row at the event the
   old modes. Instead the master lets the modes settle first, as an event iteration
   across the FMUs: steps of probe length, each followed by consistent() (the loops
   solved with the new modes), until one in which no member fires at its start. Each is
   a step of the run (snap[1] and h_prev are its start, where a later start event may
   move back to), holding the sources (no extrapolation over a probe). The settle steps
   never pass `target` (an assembly FMU's doStep ends there exactly): one cut there
   leaves c->unsettled, and the next step from there goes on settling. */
static int settle(cosim *c, double target)
{
    const eng_cosim_spec *g = c->cfg;
    int n, k, settled = 0, held_raw = c->hold_raw;
    if (!c->unsettled)
        for (k = 0; k < g->n_couplings; k++) c->settle_u[k] = c->u[k];
    c->unsettled = 1;
    c->hold_raw = 1;
    for (n = 0; n < MAX_SETTLE_STEPS; n++) {
        double h = fmin(probe_step(c->t), target - c->t);
        if (!(h > 0.0 && c->t + h > c->t)) break; /* at `target`: the next step goes on */
        if (save(c, &c->snap[1], c->t) || step(c, c->t, h)) {
            c->hold_raw = held_raw;
            return -1;
        }
        c->h_prev = h;
        c->have_prev = 1;
        c->t = c->terminated ? c->terminated_time : h == target - c->t ? target : c->t + h;
        if (c->terminated || !any_event_at_start(c)) {
            settled = 1;
            break;
        }
    }
    c->hold_raw = held_raw;
    if (settled || n == MAX_SETTLE_STEPS) restart_jumped_history(c);
    return 0;
}

/* ---------------------------------------------------------------------------- */
/* the run                                                                        */

static int sample(cosim *c, double t, double *row)
{
    const eng_cosim_spec *g = c->cfg;
    int i, j;
    row[0] = t;
    for (i = 0; i < g->n_instances && c->any_evaluated; i++)
        if (c->recorded[i] && bring_up(c, i, t)) return -1;
    for (j = 0; j < g->n_columns; j++) {
        const eng_variable *v = &g->columns[j];
        if (eng_get_value(c->fmus[v->instance], v, &row[1 + j]))
            return fmu_fail(c, v->instance, "get of a recorded output", t);
    }
    return 0;
}

/* The members the master may evaluate (eng_cosim_spec.time_function / .linear_map),
   which their FMUs' structure allows: no indicators, and for a linear map no states,
   every coupled end a Float64 scalar, no algebraic loop, and under Gauss–Seidel no input
   it extrapolates itself. Their couplings in (ev_in) and the rows of ev_J, bounded. */
static int plan_evaluated(cosim *c)
{
    const eng_cosim_spec *g = c->cfg;
    const int n = g->n_instances, nc = g->n_couplings;
    int i, k;
    size_t total;
    for (i = 0; i < n; i++) {
        const eng_instance_spec *in = &g->instances[i];
        c->evaluated[i] = in->n_event_indicators != 0 ? EVAL_NONE
                          : g->time_function && g->time_function[i]
                                && (in->n_states == 0 || (in->state_vr && in->derivative_vr))
                              ? EVAL_TIME
                          : g->linear_map && g->linear_map[i] && in->n_states == 0 ? EVAL_LINEAR
                                                                                   : EVAL_NONE;
    }
    for (k = 0; k < nc; k++) {
        const eng_coupling *cp = &g->couplings[k];
        if (!ENG_PLAIN(&cp->source)) c->evaluated[cp->source.instance] = EVAL_NONE;
        if (!ENG_PLAIN(&cp->target) && c->evaluated[cp->target.instance] == EVAL_LINEAR)
            c->evaluated[cp->target.instance] = EVAL_NONE;
        if (c->in_loop[k]) c->evaluated[cp->source.instance] = c->evaluated[cp->target.instance] = 0;
        if (g->scheme == ENG_GAUSS_SEIDEL && g->derivative[k] >= 0
            && c->evaluated[cp->target.instance] == EVAL_LINEAR)
            c->evaluated[cp->target.instance] = EVAL_NONE;
    }
    eng_inputs_by_target(g->couplings, nc, n, NULL, c->ev_in_start, c->ev_in);
    total = eng_linear_rows(g->couplings, nc, c->ev_in_start, c->evaluated, EVAL_LINEAR,
                            c->ev_row);
    c->ev_J = (double *)calloc(total + 1, sizeof(double));
    if (!c->ev_J) return fail(c, "out of memory");
    for (k = 0; k < g->n_columns; k++) c->recorded[g->columns[k].instance] = 1;
    return 0;
}

/* The constants of each evaluated member at the start t0 (inputs consistent there): its
   coupled outputs, their rates along its derivatives (a time function) or their
   derivatives along its coupled inputs (a linear map), its states and derivatives. A
   member whose reads fail is stepped as any other: this saves calls, it decides nothing. */
static void anchor(cosim *c, double t0)
{
    const eng_cosim_spec *g = c->cfg;
    const double one = 1.0;
    int i, j, k, a;
    c->ev_t0 = c->t_now = t0;
    for (i = 0; i < g->n_instances; i++) {
        const eng_instance_spec *in = &g->instances[i];
        const int nx = in->n_states, first = c->ev_in_start[i];
        double *dx = NULL;
        fmu_t *f = c->fmus[i];
        int ok = 1, x = 0;
        c->fmu_time[i] = t0;
        if (!c->evaluated[i]) continue;
        for (j = 0; j < g->n_states; j++) /* its states, contiguous in `states` */
            if (g->states[j].instance == i) { x = j; break; }
        if (c->evaluated[i] == EVAL_TIME && nx) {
            dx = c->ev_dx + x;
            ok = x + nx <= g->n_states && fmu_get_float64(f, in->derivative_vr, (size_t)nx, dx) == 0
                 && fmu_get_float64(f, in->state_vr, (size_t)nx, c->ev_x0 + x) == 0;
            for (j = 0; j < nx && ok; j++)
                ok = g->states[x + j].instance == i && g->states[x + j].vr == in->state_vr[j]
                     && isfinite(dx[j]);
        }
        for (k = 0; k < g->n_couplings && ok; k++) {
            const eng_variable *v = &g->couplings[k].source;
            if (v->instance != i) continue;
            ok = fmu_get_float64(f, &v->vr, 1, &c->ev_y0[k]) == 0;
            c->ev_rate[k] = 0.0;
            if (ok && c->evaluated[i] == EVAL_TIME && nx)
                ok = fmu_directional_derivative(f, &v->vr, 1, in->state_vr, (size_t)nx, dx,
                                                &c->ev_rate[k]) == 0 && isfinite(c->ev_rate[k]);
            for (a = first; a < c->ev_in_start[i + 1] && ok && c->evaluated[i] == EVAL_LINEAR; a++) {
                double *entry = c->ev_J + c->ev_row[k] + a - first;
                ok = fmu_directional_derivative(f, &v->vr, 1, &g->couplings[c->ev_in[a]].target.vr,
                                                1, &one, entry) == 0 && isfinite(*entry);
            }
        }
        for (a = first; a < c->ev_in_start[i + 1]; a++) c->ev_u0[c->ev_in[a]] = c->u[c->ev_in[a]];
        if (!ok) c->evaluated[i] = EVAL_NONE;
        c->any_evaluated = c->any_evaluated || c->evaluated[i];
    }
}

/* Everything allocated, every FMU loaded with its start values; -1: message set. */
static int create(cosim *c, const eng_cosim_spec *g)
{
    int i, k, grp, n_c = g->n_couplings > 0 ? g->n_couplings : 1, width_max = 1, largest_loop = 1;
    int *widths = (int *)calloc((size_t)g->n_instances + 1, sizeof(int));
    if (!widths) return fail(c, "out of memory");
    for (i = 0; i < g->n_instances; i++) {
        widths[i] = 1 + g->instances[i].n_event_outputs;
        if (widths[i] > width_max) width_max = widths[i];
    }
    c->run = eng_run_new(g->n_instances, widths);
    free(widths);
    c->inst = (instance *)calloc((size_t)g->n_instances + 1, sizeof(instance));
    c->fmus = (fmu_t **)calloc((size_t)g->n_instances + 1, sizeof(fmu_t *));
    c->u = (double *)calloc((size_t)n_c, sizeof(double));
    c->hist_t = (double *)calloc((size_t)n_c * HISTORY, sizeof(double));
    c->hist_v = (double *)calloc((size_t)n_c * HISTORY, sizeof(double));
    c->hist_n = (int *)calloc((size_t)n_c, sizeof(int));
    c->in_loop = (int *)calloc((size_t)n_c, sizeof(int));
    c->done = (int *)calloc((size_t)g->n_instances + 1, sizeof(int));
    c->moving = (int *)calloc((size_t)g->n_instances + 1, sizeof(int));
    c->asleep_since = (double *)calloc((size_t)g->n_instances + 1, sizeof(double));
    if (c->asleep_since)
        for (i = 0; i < g->n_instances; i++) c->asleep_since[i] = INFINITY;
    c->which = (int *)calloc((size_t)g->n_instances + 1, sizeof(int));
    c->state = (double *)calloc((size_t)g->n_states + 1, sizeof(double));
    c->coarse = (double *)calloc((size_t)g->n_states + 1, sizeof(double));
    c->predicted = (double *)calloc((size_t)n_c, sizeof(double));
    c->settle_u = (double *)calloc((size_t)n_c, sizeof(double));
    c->chain_order = (int *)calloc((size_t)n_c, sizeof(int));
    c->rate_v = (double *)calloc(ENG_RATES * (size_t)n_c, sizeof(double));
    c->judged_end = (int *)calloc((size_t)n_c, sizeof(int));
    c->memo = (poly_memo *)calloc((size_t)n_c + 1, sizeof(poly_memo));
    c->row = (double *)calloc((size_t)width_max, sizeof(double));
    c->evaluated = (int *)calloc((size_t)g->n_instances + 1, sizeof(int));
    c->recorded = (int *)calloc((size_t)g->n_instances + 1, sizeof(int));
    c->stale = (int *)calloc((size_t)g->n_instances + 1, sizeof(int));
    c->fmu_time = (double *)calloc((size_t)g->n_instances + 1, sizeof(double));
    c->version = (long *)calloc((size_t)g->n_instances + 1, sizeof(long));
    c->ev_in_start = (int *)calloc((size_t)g->n_instances + 1, sizeof(int));
    c->ev_in = (int *)calloc((size_t)n_c, sizeof(int));
    c->ev_row = (int *)calloc((size_t)n_c, sizeof(int));
    c->ev_y0 = (double *)calloc((size_t)n_c, sizeof(double));
    c->ev_rate = (double *)calloc((size_t)n_c, sizeof(double));
    c->ev_u0 = (double *)calloc((size_t)n_c, sizeof(double));
    c->ev_x0 = (double *)calloc((size_t)g->n_states + 1, sizeof(double));
    c->ev_dx = (double *)calloc((size_t)g->n_states + 1, sizeof(double));
    if (!c->evaluated || !c->recorded || !c->stale || !c->fmu_time || !c->version
        || !c->ev_in_start || !c->ev_in || !c->ev_row || !c->ev_y0 || !c->ev_rate || !c->ev_u0
        || !c->ev_x0 || !c->ev_dx)
        return fail(c, "out of memory");
    for (k = 0; k < g->n_groups; k++)
        if (g->group_is_loop[k] && g->group_start[k + 1] - g->group_start[k] > largest_loop)
            largest_loop = g->group_start[k + 1] - g->group_start[k];
    if (!c->run || !c->inst || !c->fmus || !c->u || !c->hist_t || !c->hist_v || !c->hist_n
        || !c->in_loop || !c->done || !c->moving || !c->asleep_since || !c->which || !c->state
        || !c->coarse || !c->row || !c->predicted || !c->settle_u || !c->chain_order || !c->rate_v
        || !c->judged_end || !c->memo
        || eng_loop_alloc(&c->loop, largest_loop))
        return fail(c, "out of memory");
    c->all_rated = 1;
    for (k = 0; k < g->n_couplings; k++) {
        int d = g->derivative[k], end = k;
        c->chain_order[k] = 1;
        while (d >= 0 && c->chain_order[k] <= g->n_couplings) {
            c->chain_order[k]++;
            end = d;
            d = g->derivative[d];
        }
        /* rates at a chain's end extrapolate it to the polynomial's order */
        if (rate_inputs(c, end)) c->chain_order[k] += g->extrapolation;
        if (g->held[k] && !rate_inputs(c, k)) c->all_rated = 0;
        c->judged_end[k] = end == k && rate_inputs(c, k)
                           && g->instances[g->couplings[k].target.instance].n_event_indicators > 0
                           && g->instances[g->couplings[k].source.instance].fmi_version >= 3;
    }
    for (i = 0; i < 3; i++)
        if (snap_alloc(c, &c->snap[i])) return fail(c, "out of memory");
    for (grp = 0; grp < g->n_groups; grp++)
        if (g->group_is_loop[grp])
            for (k = g->group_start[grp]; k < g->group_start[grp + 1]; k++)
                c->in_loop[g->group_members[k]] = 1;
    if (plan_evaluated(c)) return -1;
    for (i = 0; i < g->n_instances; i++) {
        instance *in = &c->inst[i];
        char err[512];
        in->owner = c;
        in->index = i;
        in->events = &c->run->tables[i];
        in->event_in_step = INFINITY;
        in->fmu = c->fmus[i] = eng_instantiate(&g->instances[i], FMU_CO_SIMULATION, on_intermediate,
                                               in, 0, err, sizeof err);
        if (!in->fmu) return fail(c, "%s: %s", g->instances[i].instance_name, err);
    }
    return 0;
}

static int enter_initialization(cosim *c, double t0)
{
    const eng_cosim_spec *g = c->cfg;
    int i;
    /* no stop time for the members (stop = start: none given): event location probes a
       member with a tiny doStep past where it stands (fires_at_start), also at the end of
       the run, and a member must refuse to compute past a stop time it was given */
    for (i = 0; i < g->n_instances; i++)
        if (fmu_enter_initialization(c->fmus[i], g->tolerance, t0, t0) != FMU_OK)
            return fmu_fail(c, i, "enter initialization", t0);
    return 0;
}

static int exit_initialization(cosim *c, double t0)
{
    const eng_cosim_spec *g = c->cfg;
    int i;
    if (consistent(c, t0)) return -1;
    for (i = 0; i < g->n_instances; i++)
        if (fmu_exit_initialization(c->fmus[i]) != FMU_OK)
            return fmu_fail(c, i, "exit initialization", t0);
    if (consistent(c, t0)) return -1;
    anchor(c, t0);
    return 0;
}

/* The share of the FMUs' tolerance a step of h may leave as noise (adaptive.py
   NOISE_SHARE_MIN, StepController.noise): h / h_max of it, the step's part of an output
   interval, never less than NOISE_SHARE_MIN. The whole tolerance in every step, as it
   was, let the allowed error grow with the number of steps: on conveyor (|x| up to 40 m,
   tolerance 1e-8) 4e-7 per step against tol 1e-3's 1.3e-8, so every tol <= 1e-3 took
   the same steps and stayed 6.6e-6 off (now 5.2e-7, 1.9e-7, 1.5e-7 at 1e-3, 1e-4, 1e-5).
   The least share stands for what no step length removes: round-off and the FMUs' event
   location left 1e-13 in x = 30 m; without it the step fell to 3e-13 s there. */
#define NOISE_SHARE_MIN 1e-4

static double noise_share(const controller *k, double h)
{
    return fmax(NOISE_SHARE_MIN, fmin(1.0, h / k->h_max));
}

/* `noise`: what the FMUs' own solvers leave in the step (noise_share), a floor below
   which the two runs of step doubling cannot agree (without it the step would shrink
   without end where the coupling error is smaller than that). */
static int judge(cosim *c, const controller *k, double error, double noise, double defect,
                 int defect_order, double h, double *h_next)
{
    double allowed = k->tol * h / k->horizon + noise, factor;
    int ok = error <= allowed && defect <= 1.0;
    if (ok) {
        c->run_stats->steps++;
        c->stats->error_ratio_max = fmax(c->stats->error_ratio_max, fmax(error / allowed, defect));
    } else {
        c->run_stats->rejected++;
    }
    factor = error == 0.0 ? 4.0
                          : fmin(4.0, fmax(0.2, 0.9 * pow(allowed / error, 1.0 / k->order)));
    /* the chains' defect is local (each communication point sets the motion afresh):
       its allowance does not grow with h, and it shrinks as h^defect_order */
    if (defect > 0.0)
        factor = fmin(factor, fmax(0.2, 0.9 * pow(1.0 / defect, 1.0 / defect_order)));
    /* a rejected step shrinks, by what the estimate says (halving regardless wastes
       steps where the error is close to the noise floor); the step after a rejection
       does not grow (Hairer's rule against reject/accept cycles) */
    if (!ok) factor = fmin(factor, 0.9);
    else if (c->rejected_last) factor = fmin(factor, 1.0);
    c->rejected_last = !ok;
    *h_next = fmin(k->h_cap, h * factor);
    return ok;
}

static void swap_snapshots(cosim *c)
{
    snapshot s = c->snap[0];
    c->snap[0] = c->snap[1];
    c->snap[1] = s;
}

static int needs_rollback_capability(cosim *c)
{
    const eng_cosim_spec *g = c->cfg;
    int i;
    if (!g->adaptive && !g->event_sync) return 0;
    for (i = 0; i < g->n_instances; i++)
        if (!fmu_can_get_set_state(c->fmus[i]))
            return fail(c, "%s co-simulation rolls steps back, but FMU instance '%s' cannot get "
                        "and set its state (canGetAndSetFMUState is false); use a fixed step "
                        "without event synchronisation",
                        g->adaptive ? "adaptive" : "event-synchronised", g->instances[i].instance_name);
    return 0;
}

static void start_stepping(cosim *c, double t0, double horizon)
{
    const eng_cosim_spec *g = c->cfg;
    c->t = t0;
    c->h_prev = 0.0;
    c->located_at = -INFINITY;
    c->unsettled = 0;
    c->have_prev = 0;
    c->ctl.tol = g->tol;
    c->ctl.horizon = horizon;
    c->ctl.h_max = g->step;
    c->ctl.h_cap = ESTIMATE_SPAN * g->step;
    c->ctl.order = g->extrapolation == 0 ? 1
                   : c->all_rated ? (int)fmin(g->extrapolation + 1, ORDER_MAX) : 2;
    c->h = g->adaptive ? g->step / 4 : g->step;
    c->coast = 0;
    c->coast_run = COAST_STEPS;
    c->coast_done = 0;
    c->coast_extended = 0;
    c->defect_ref = 0.0;
    c->defect_ref_h = INFINITY;
}

/* How far a run's unjudged step of h may take the coupling defect (adaptive.py
   defect_allowance): COAST_DEFECT_GROWTH times the estimate's, grown as the
   extrapolation's error, (h / h_ref)^(p + 1), where the step is longer than the half step
   it was taken at (a run's steps may be a whole output interval, ESTIMATE_SPAN), plus
   ten times the FMUs' tolerance. */
static double defect_allowance(const cosim *c, double h)
{
    double growth = h > c->defect_ref_h ? pow(h / c->defect_ref_h, c->cfg->extrapolation + 1) : 1.0;
    return COAST_DEFECT_GROWTH * c->defect_ref * growth + 10.0 * c->cfg->tolerance;
}

/* How many equal steps of about h fill r: at most h each, or together a quarter of one
   longer (`stretch`; the old rule for the one step before an output point, now spread
   over them all), never fewer than one. (A ratio that is a whole number to round-off
   stays that number.) */
static double cells(double r, double h, int stretch)
{
    double n = ceil(r / h - (stretch ? FIT_STRETCH : 1e-9));
    return n < 1.0 ? 1.0 : n;
}

/* One step from c->t towards `target` (never past it): accepted, rejected (c->t stays),
   or ended at an event. Returns 1 when an event handled at the start of the step was
   moved back into the previous one (c->t went back), 0 otherwise, -1 on failure. */
static int one_step(cosim *c, double target)
{
    const eng_cosim_spec *g = c->cfg;
    const int rollback = g->adaptive || g->event_sync;
    const double t = c->t, eps_t = eng_time_slack(t, target), left = target - t;
    /* (no stretch right after a rejection at that length) */
    const int stretch = !c->rejected_last;
    int coasting = g->adaptive && c->coast > 0;
    double h_try = left, h_wanted = left; /* h_wanted: before the output grid fits it */
    int at_event = 0, ok = 1, i;

    if (g->adaptive && !coasting && c->coast_done == 1 && !c->coast_extended
        && cells(left, c->h / 2, stretch) < 2.0) {
        /* the estimate's two halves do not fit before the output point: the run goes on
           to it, and the estimate is taken from there (COAST_GUARDED says why) */
        coasting = 1;
        c->coast = 1;
        c->coast_extended = 1;
    }
    if (g->adaptive && coasting) {
        h_wanted = c->h_coast;
        h_try = left / cells(left, h_wanted, stretch);
    } else if (g->adaptive) { /* two of the steps that fill the interval, or all that is left */
        double n;
        h_wanted = c->h;
        n = cells(left, h_wanted / 2, stretch);
        h_try = n >= 2.0 ? 2.0 * left / n : left;
    }
    /* no adaptive step shorter than time resolves where it stands (at 1e15 s a double
       moves in 0.125 s steps) */
    if (g->adaptive && h_try < MF_MIN_STEP(t)) h_try = fmin(MF_MIN_STEP(t), target - t);
    if (!(t + h_try > t)) /* a step that does not move time would be taken forever */
        return fail(c, "a step of %g s cannot move time from t = %.17g (below its resolution "
                    "there)", h_try, t);

    if (c->unsettled) { /* settling was cut at an output point: it goes on from here */
        if (settle(c, target)) return -1;
        if (c->t > t) {
            c->coast = 0;
            c->coast_run = COAST_STEPS;
            c->coast_done = 0;
            return 1;
        }
        restart_jumped_history(c); /* no room for a settle step before `target`: step on */
    }
    if (rollback && save(c, &c->snap[0], t)) return -1;
    for (;;) { /* the (coarse) step, shortened to end at the first event inside it */
        double te;
        if (step(c, t, h_try)) return -1;
        if (!g->event_sync) break;
        if (any_event_at_start(c) && t > c->located_at) {
            double t_event;
            for (i = 0; i < g->n_instances; i++) c->which[i] = c->inst[i].event_at_start;
            if (g->extrapolation && !c->hold_raw) {
                /* an extrapolated held input runs ahead of its source (it is the mean
                   over the coming step): if the sources' own values at t do not fire
                   the event, it is premature, and the step is redone holding them */
                int fires;
                if (restore(c, &c->snap[0])
                    || fires_at_start(c, c->which, t, probe_step(t), &fires))
                    return -1;
                if (!fires) {
                    c->hold_raw = 1;
                    continue;
                }
            }
            if (!c->have_prev) { /* nothing to go back into: the event stays at t */
                if (restore(c, &c->snap[0])) return -1;
                t_event = t;
            } else {
                if (locate_start_event(c, &c->snap[1], c->h_prev, c->which, &t_event)) return -1;
                c->h_prev = t_event - c->snap[1].t;
            }
            c->located_at = c->t = t_event;
            if (settle(c, target)) return -1; /* the modes change there, before the next step */
            c->hold_raw = 0;
            c->coast = 0;
            c->coast_run = COAST_STEPS;
            c->coast_done = 0;
            return 1; /* the next step starts where the event settled */
        }
        te = earliest_event_in_step(c);
        if (!at_event && te - t > g->event_tol && te < t + h_try) {
            double margin = fmin(g->event_tol, 0.5 * (t + h_try - te));
            if (restore(c, &c->snap[0])) return -1;
            h_try = te - t + margin;
            at_event = 1;
            c->stats->events_synchronised++;
            continue;
        }
        break;
    }

    if (coasting) {
        /* the motion strayed, or the couplings move unlike when the estimate was made */
        if (c->defect > 1.0
            || c->coupling_defect > defect_allowance(c, h_try)) {
            if (restore(c, &c->snap[0])) return -1;
            c->run_stats->rejected++;
            /* (also after the coupling's defect: without, the estimate that follows
               may grow the step, and moving_table at tol 1e-2 ended 6.7e-4 off instead
               of 1.6e-4, conveyor 4.8e-5 instead of 8.0e-6, at the same cost) */
            c->rejected_last = 1;
            /* a chain's defect says the step is too long; the coupling's only that the
               estimate is due (its halves are this step) */
            c->h = c->defect > 1.0 ? h_try : 2.0 * h_try;
            ok = 0;
        } else {
            c->run_stats->steps++;
        }
        c->coast = at_event || !ok ? 0 : c->coast - 1;
        c->coast_done = c->coast > 0 || at_event ? 0
                        : ok ? 1 : c->defect <= 1.0 ? COAST_GUARDED : 0;
        if (!c->coast_done && c->coast == 0) c->coast_run = COAST_STEPS;
    } else if (g->adaptive) {
        double error = 0.0, noise = 0.0, h_next, defect = c->defect;
        int j, defect_order = c->defect_order;
        c->coast_extended = 0;
        if (state_vector(c, c->coarse, t) || restore(c, &c->snap[0])) return -1;
        if (step(c, t, h_try / 2)) return -1;
        if (!c->terminated && step(c, t + h_try / 2, h_try / 2)) return -1;
        if (c->terminated) { /* the model ended the run: keep what it did */
            c->t = c->terminated_time;
            return 0;
        }
        if (g->event_sync && any_event_at_start(c) && t + h_try / 2 > c->located_at) {
            /* an event fired where the two half steps meet: the coupled system
               crossed inside the first half, and the whole step's error is the
               event's, not the coupling's. The first half is tried again as a step
               of its own, judged like any other (kept unjudged, a first step of
               0.03 s left axle_motor 5e-3 off whatever the tolerance); the step
               after it fires the event at its start and moves it back there. Only
               a half within the event tolerance is kept as it is: its coupling
               error is nil, and an event that fires at every point would
               otherwise halve the step without end. */
            if (restore(c, &c->snap[0])) return -1;
            h_try /= 2;
            c->h = h_try;
            if (h_try > g->event_tol) {
                c->run_stats->rejected++;
                c->rejected_last = 1;
                ok = 0;
            } else {
                if (step(c, t, h_try)) return -1;
                c->run_stats->steps++;
            }
        } else {
            if (state_vector(c, c->state, t)) return -1;
            for (j = 0; j < g->n_states; j++) {
                error = fmax(error, fabs(c->state[j] - c->coarse[j]));
                noise = fmax(noise, g->tolerance * (1.0 + fabs(c->state[j])) * noise_share(&c->ctl, h_try));
            }
            error /= (double)((1 << c->ctl.order) - 1);
            ok = judge(c, &c->ctl, error, noise, defect, defect_order, h_try, &h_next);
            if (ok && !at_event) {
                /* (the second half step's coupling defect is the reference: it has the
                   unjudged steps' length) */
                double ratio = h_next / h_wanted;
                /* (a step the grid left shorter is judged as any: the run's steps come
                   from the step asked for, not from its halves, COAST_GUARDED) */
                int steady = c->coast_done && ratio >= COAST_STEADY && COAST_STEADY * ratio <= 1.0;
                c->coast_run = !steady ? COAST_STEPS
                               : c->coast_done == COAST_GUARDED ? c->coast_run
                               : c->coast_run < COAST_MAX / 2 ? 2 * c->coast_run : COAST_MAX;
                /* below an output interval the defect when the estimate was made: an
                   estimate taken where the error is small (a phase of an oscillation)
                   would otherwise let a longer step run on where it is large. From a
                   step asked for of an output interval on, the grid sets the run's
                   steps (the interval's halves, or the whole interval, ESTIMATE_SPAN),
                   and the reference keeps the largest
                   defect of the runs the estimates vouched for: beam_friction_damper's
                   stuck pad rings at 34.9 rad/s, whose phase made half of its unjudged
                   steps at the output interval estimate again (tol 1e-2: 22546 -> 17946
                   doSteps, error 2.2e-5 -> 3.3e-5; moving_table never gets there) */
                c->defect_ref = steady && h_next >= c->ctl.h_max
                                    ? fmax(c->coupling_defect, c->defect_ref) : c->coupling_defect;
                c->defect_ref_h = h_try / 2;
                c->coast = c->coast_run;
                /* (fitted to the grid as taken; longer than the estimate's halves only
                   once the estimates are steady, ESTIMATE_SPAN) */
                c->h_coast = fmin(fmin(h_wanted, h_next), steady ? c->ctl.h_cap : c->ctl.h_max) / 2;
                c->coast_done = 0;
            } else if (ok || !c->coast_done || h_next < COAST_KEEP * h_wanted) {
                c->coast_run = COAST_STEPS;
                c->coast_done = 0;
            } /* else a mild rejection after a run: the step shrinks, the run stays as long */
            if (!ok && h_try <= MF_MIN_STEP(t)) /* rejected at the shortest step there is */
                return fail(c, "adaptive step fell below %.3g s at t = %g (tol %g cannot be met)",
                            MF_MIN_STEP(t), t, g->tol);
            if (!ok && restore(c, &c->snap[0])) return -1;
            c->h = fmax(h_next, MF_MIN_STEP(t));
        }
    } else {
        c->run_stats->steps++;
    }
    c->hold_raw = 0;
    if (c->terminated) { /* the last row is where the model stopped */
        c->t = c->terminated_time;
        return 0;
    }
    if (ok) {
        c->stats->h_min = fmin(c->stats->h_min, h_try);
        c->stats->h_max = fmax(c->stats->h_max, h_try);
        c->t = fabs(target - (t + h_try)) < eps_t ? target : t + h_try;
        if (rollback) {
            swap_snapshots(c); /* the step's start becomes the previous step's */
            c->h_prev = h_try;
            c->have_prev = 1;
        }
    }
    return 0;
}

/* Puts to sleep each group of instances (eng_cosim_spec.rest_group) whose state
   derivatives are all exactly zero now. 1 when every instance sleeps (the whole
   assembly rests), 0 when not, -1 on failure. */
static int fall_asleep(cosim *c)
{
    const eng_cosim_spec *g = c->cfg;
    int i, j, all = 1;
    for (i = 0; i < g->n_instances; i++) c->moving[i] = 0;
    for (j = 0; j < g->n_states; j++) {
        const eng_variable *v = &g->derivatives[j];
        double d;
        if (c->asleep_since[v->instance] < INFINITY || g->rest_group[v->instance] < 0) continue;
        if (eng_get_value(c->fmus[v->instance], v, &d))
            return fmu_fail(c, v->instance, "get of a state derivative", c->t);
        if (d != 0.0) c->moving[v->instance] = 1;
    }
    for (i = 0; i < g->n_instances; i++) { /* a group sleeps when none of it moves */
        int group = g->rest_group[i], k, still = group >= 0;
        if (c->asleep_since[i] < INFINITY) continue;
        for (k = 0; k < g->n_instances && still; k++)
            if (g->rest_group[k] == group && c->moving[k]) still = 0;
        if (still) c->asleep_since[i] = c->t;
        else all = 0;
    }
    return all;
}

/* The run after initialisation: steps, rows at the output times. */
static int run(cosim *c, eng_progress *progress)
{
    const eng_cosim_spec *g = c->cfg;
    const int width = 1 + g->n_columns;
    const double *out_times = g->times + 1;
    const long n_out = g->n_times - 1;
    long k = 0, k_budget = -1;
    eng_budget budget;
    char why[256];

    const double t0 = g->times[0];

    if (sample(c, t0, g->out)) return -1;
    c->run_stats->n_rows = 1;
    if (n_out < 1) return 0;
    start_stepping(c, t0, out_times[n_out - 1] - t0);

    while (k < n_out) {
        double target = out_times[k];
        int moved;
        if (c->t >= target - 1e-12 * fmax(1.0, fabs(target)) || c->terminated) {
            if (sample(c, c->terminated ? c->t : target,
                       g->out + (size_t)(k + 1) * (size_t)width))
                return -1;
            k++;
            c->run_stats->n_rows = k + 1;
            c->run_stats->t_end = c->t;
            if (c->terminated) break;
            if (eng_progress_check(progress, c->t)) {
                c->run_stats->status = ENG_STOPPED;
                break;
            }
            continue;
        }
        if (k != k_budget) { /* a new output interval: a fresh budget */
            eng_budget_start(&budget, MAX_COUPLED_STEPS, c->t);
            k_budget = k;
        }
        if (eng_budget_spend(&budget, c->t, target, why, sizeof why))
            return fail(c, "co-simulation: %s", why);
        moved = one_step(c, target);
        if (moved < 0) return -1;
        if (moved) { /* rows sampled at or after the event's new time are sampled again,
                        from where it settled (past them, or at them to round-off): a
                        row at or after an event shows the modes after it */
            while (k > 0 && out_times[k - 1] >= c->located_at) k--;
            c->run_stats->n_rows = k + 1;
        } else if (g->derivatives && g->rest_group && !c->terminated) {
            int rest = fall_asleep(c);
            if (rest < 0) return -1;
            if (rest) { /* nothing moves any more: every remaining row is this point */
                double *first = g->out + (size_t)(k + 1) * (size_t)width;
                long j;
                if (sample(c, out_times[k], first)) return -1;
                for (j = k + 1; j < n_out; j++) {
                    double *row = g->out + (size_t)(j + 1) * (size_t)width;
                    memcpy(row, first, (size_t)width * sizeof(double));
                    row[0] = out_times[j];
                }
                c->stats->at_rest_from = c->t;
                c->run_stats->n_rows = n_out + 1;
                c->run_stats->t_end = out_times[n_out - 1];
                c->t = out_times[n_out - 1];
                break;
            }
        }
    }
    return 0;
}

static void destroy(cosim *c)
{
    int i;
    for (i = 0; i < 3; i++) snap_free(c, &c->snap[i]);
    if (c->inst)
        for (i = 0; i < c->cfg->n_instances; i++) fmu_free(c->inst[i].fmu);
    free(c->inst);
    free(c->fmus);
    free(c->u);
    free(c->hist_t);
    free(c->hist_v);
    free(c->hist_n);
    free(c->in_loop);
    free(c->done);
    free(c->moving);
    free(c->asleep_since);
    free(c->which);
    free(c->state);
    free(c->coarse);
    free(c->predicted);
    free(c->settle_u);
    free(c->chain_order);
    free(c->rate_v);
    free(c->memo);
    free(c->judged_end);
    eng_loop_free(&c->loop);
    free(c->row);
    free(c->evaluated);
    free(c->recorded);
    free(c->stale);
    free(c->fmu_time);
    free(c->version);
    free(c->ev_in_start);
    free(c->ev_in);
    free(c->ev_row);
    free(c->ev_y0);
    free(c->ev_rate);
    free(c->ev_u0);
    free(c->ev_J);
    free(c->ev_x0);
    free(c->ev_dx);
}

ENG_API eng_run *eng_cosimulate(const eng_cosim_spec *spec, eng_stats *stats,
                                eng_cosim_stats *cosim_stats)
{
    cosim c;
    eng_progress progress;
    int i;
    memset(&c, 0, sizeof c);
    memset(stats, 0, sizeof *stats);
    memset(cosim_stats, 0, sizeof *cosim_stats);
    stats->terminated_by = -1;
    cosim_stats->loop_failed_group = -1;
    cosim_stats->h_min = INFINITY;
    cosim_stats->at_rest_from = INFINITY;
    c.cfg = spec;
    c.run_stats = stats;
    c.stats = cosim_stats;
    eng_progress_start(&progress, spec->progress, spec->progress_ctx);
    stats->status = ENG_DONE;
    if (spec->n_times < 1) {
        fail(&c, "no output times");
        stats->status = ENG_FAILED;
    } else if (create(&c, spec) || needs_rollback_capability(&c)
               || enter_initialization(&c, spec->times[0])
               || exit_initialization(&c, spec->times[0])
               || run(&c, &progress)) {
        stats->status = ENG_FAILED;
    } else if (c.terminated) {
        stats->status = ENG_TERMINATED;
        stats->terminated_by = c.terminated_instance;
        stats->t_end = c.terminated_time;
        snprintf(stats->message, sizeof stats->message, "%s", fmu_message(c.fmus[c.terminated_instance]));
    }
    if (cosim_stats->h_max == 0.0) cosim_stats->h_min = NAN, cosim_stats->h_max = NAN;
    if (spec->asleep_since && c.asleep_since)
        memcpy(spec->asleep_since, c.asleep_since, (size_t)spec->n_instances * sizeof(double));
    if (spec->evaluated && c.evaluated)
        for (i = 0; i < spec->n_instances; i++)
            spec->evaluated[i] = c.any_evaluated ? c.evaluated[i] : EVAL_NONE;
    destroy(&c);
    return c.run;
}

/* ---------------------------------------------------------------------------- */
/* the master one communication step at a time: an assembly FMU's doStep          */

struct eng_cosim {
    cosim c;
    eng_stats stats;
    eng_cosim_stats cosim_stats;
    double t0;
    int inputs_changed;  /* a member's input was set from outside (eng_cosim_inputs_changed) */
};

void eng_cosim_inputs_changed(eng_cosim *m) { m->inputs_changed = 1; }

eng_cosim *eng_cosim_create(const eng_cosim_spec *spec)
{
    eng_cosim *m = (eng_cosim *)calloc(1, sizeof *m);
    if (!m) return NULL;
    m->stats.terminated_by = -1;
    m->cosim_stats.loop_failed_group = -1;
    m->cosim_stats.h_min = INFINITY;
    m->cosim_stats.at_rest_from = INFINITY;
    m->c.cfg = spec;
    m->c.run_stats = &m->stats;
    m->c.stats = &m->cosim_stats;
    if (create(&m->c, spec) || needs_rollback_capability(&m->c)) m->stats.status = ENG_FAILED;
    return m;
}

int eng_cosim_enter_initialization(eng_cosim *m, double start_time)
{
    if (m->stats.status == ENG_FAILED) return ENG_FAILED;
    m->t0 = start_time;
    if (enter_initialization(&m->c, start_time)) return m->stats.status = ENG_FAILED;
    return 0;
}

int eng_cosim_exit_initialization(eng_cosim *m)
{
    if (m->stats.status == ENG_FAILED) return ENG_FAILED;
    if (exit_initialization(&m->c, m->t0)) return m->stats.status = ENG_FAILED;
    /* the step controller spreads its error budget over the experiment's length */
    start_stepping(&m->c, m->t0, fmax(m->c.cfg->stop_time - m->t0, m->c.cfg->step));
    return 0;
}

/* Events are moved back only within the call: what the importer read at earlier
   communication points stays as it was. An event whose coupled crossing lies in the
   last step before `target` is found by a probe at `target` and moved back before
   the call returns, so that a step boundary does not delay it. */
int eng_cosim_advance(eng_cosim *m, double target)
{
    cosim *c = &m->c;
    const double eps_t = eng_time_slack(c->t, target);
    int probes = 0;
    eng_budget budget;
    char why[256];
    if (m->stats.status == ENG_FAILED) return ENG_FAILED;
    /* refused at once when even the longest steps (the export's step) are too many */
    if (c->cfg->adaptive && (target - c->t) / c->ctl.h_max > (double)MAX_COUPLED_STEPS) {
        fail(c, "t = %.17g is %.3g steps of at most %g s (the exported communication step) "
             "from t = %.17g, more than the %ld allowed per doStep; ask for shorter steps",
             target, (target - c->t) / c->ctl.h_max, c->ctl.h_max, c->t, MAX_COUPLED_STEPS);
        return m->stats.status = ENG_FAILED;
    }
    eng_budget_start(&budget, MAX_COUPLED_STEPS, c->t);
    c->have_prev = 0;
    if (m->inputs_changed) {
        /* an input set from outside since the last doStep moves the couplings at c->t:
           they are made consistent there, and a held input that jumped restarts its
           history, as after an event (a polynomial through the values from before the
           jump would run the target along it; a judged one shrank the step to nothing) */
        int k;
        m->inputs_changed = 0;
        /* (while settling goes on, settle_u holds where it began: the settled end
           compares against that and restarts a history that jumped, this jump too) */
        if (!c->unsettled)
            for (k = 0; k < c->cfg->n_couplings; k++) c->settle_u[k] = c->u[k];
        if (consistent(c, c->t)) return m->stats.status = ENG_FAILED;
        if (!c->unsettled) restart_moved_history(c);
    }
    while (!c->terminated) {
        if (c->t < target - eps_t) {
            if (eng_budget_spend(&budget, c->t, target, why, sizeof why)) {
                fail(c, "%s", why);
                return m->stats.status = ENG_FAILED;
            }
            if (one_step(c, target) < 0) return m->stats.status = ENG_FAILED;
            continue;
        }
        /* (a bounded number of times: modes that fire again at every point would
           otherwise bisect without end; the step after this call handles them) */
        if (c->cfg->event_sync && c->have_prev && c->t > c->located_at && probes++ < 100) {
            int i, fires;
            double t_event;
            for (i = 0; i < c->cfg->n_instances; i++) c->which[i] = 1;
            if (fires_at_start(c, c->which, c->t, probe_step(c->t), &fires))
                return m->stats.status = ENG_FAILED;
            if (fires) {
                if (locate_start_event(c, &c->snap[1], c->h_prev, c->which, &t_event))
                    return m->stats.status = ENG_FAILED;
                c->located_at = c->t = t_event;
                c->h_prev = t_event - c->snap[1].t;
                /* the modes change there (up to `target`; the next call goes on) */
                if (settle(c, target)) return m->stats.status = ENG_FAILED;
                continue;
            }
        }
        break;
    }
    return 0;
}

int eng_cosim_failed(const eng_cosim *m) { return m->stats.status == ENG_FAILED; }

double eng_cosim_time(const eng_cosim *m) { return m->c.t; }

int eng_cosim_terminated(const eng_cosim *m) { return m->c.terminated; }

fmu_t *eng_cosim_member(eng_cosim *m, int i) { return m->c.fmus ? m->c.fmus[i] : NULL; }

const char *eng_cosim_message(const eng_cosim *m) { return m->stats.message; }

void eng_cosim_free(eng_cosim *m)
{
    if (!m) return;
    destroy(&m->c);
    eng_run_free(m->c.run);
    free(m);
}
