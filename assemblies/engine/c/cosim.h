/*
 * cosim.h: the engine's co-simulation master for Co-Simulation FMUs (FMI 2 and 3).
 *
 * The Python side works out everything structural (couplings, their dependency
 * groups and algebraic loops, the Gauss–Seidel order, which inputs the FMUs hold
 * constant over a step) and hands it here in one configuration; the master then
 * loads the FMUs (fmu.h), initialises them and runs the whole experiment in C:
 *
 *   - Jacobi or Gauss–Seidel sweeps; inputs made consistent with outputs at every
 *     communication point, algebraic loops by Newton with the FMUs' directional
 *     derivatives (or plain fixed-point iteration);
 *   - on inputs the FMU holds constant over a step, the step mean of the polynomial
 *     of order 0/1/2 through the source's last values (FMI 3 has no input
 *     derivatives; inputs the FMU extrapolates itself are set as plain values);
 *   - fixed communication steps, or adaptive ones: step doubling on the FMUs'
 *     continuous states, rollback through FMU state when a step is rejected, and a
 *     few steps without an estimate after each accepted one (COAST_STEPS);
 *   - event synchronisation (optional; on by default with adaptive steps): a step in
 *     which an FMU locates an event is redone to end at the event, and an event an
 *     FMU handles at the start of a step (its inputs moved across an indicator's
 *     zero at the communication point) is moved back to where the coupled system
 *     crossed, by bisection of the previous step through rollback;
 *   - outputs at events recorded through FMI 3 intermediate update, terminate
 *     requests honoured, a progress callback about every 0.25 s of wall time that
 *     may stop the run (what was computed is kept).
 *
 * The step mean, the sweeps and the loop solver follow the Python reference master
 * (assemblies/masters/) statement by statement, so that at a fixed step without
 * event synchronisation both give the same numbers. The adaptive step is its step
 * doubling with three changes measured on the friction scenes: the FMUs' own solver
 * error is a floor under the allowed error (below it the two runs cannot agree and
 * the step would shrink without end), a rejected step shrinks by what the estimate
 * says with no growth on the next step (halving regardless made reject/accept
 * cycles), and an event where the half steps meet sends the first half back to be
 * judged as a step of its own.
 */
#ifndef MECHFMU_ENGINE_COSIM_H
#define MECHFMU_ENGINE_COSIM_H

#include "engine.h"
#include "fmu.h"

enum { ENG_JACOBI = 0, ENG_GAUSS_SEIDEL = 1 };

/* rate inputs per coupling (eng_cosim_spec.rates): enough for the cubic of extrapolation 3 */
#define ENG_RATES 3

typedef struct {
    int n_instances;
    const eng_instance_spec *instances;
    int n_couplings;
    const eng_coupling *couplings;  /* target = gain * source, any order */
    const int *held;                /* per coupling: 1 if the FMU holds the input constant
                                       over a step (no derivative input extrapolates it) */
    const int *derivative;          /* per coupling: the coupling that sets its target's
                                       derivative input (the FMU extrapolates the input
                                       along that chain over a step), or -1 */
    const eng_variable *rates;      /* per coupling, ENG_RATES: its target's rate inputs (a
                                       force flange's f_rate, f_rate2, f_rate3), which carry
                                       a held input's extrapolating polynomial into the
                                       step; instance -1 where it has none. NULL: none */
    int n_groups;                   /* coupling groups in dependency order (sources first) */
    const int *group_start;         /* n_groups + 1 offsets into group_members */
    const int *group_members;       /* coupling indices */
    const int *group_is_loop;
    const int *sweep_order;         /* instance indices, Gauss–Seidel order */
    int n_states;                   /* the FMUs' continuous states (error estimate) */
    const eng_variable *states;
    int n_columns;
    const eng_variable *columns;
    long n_times;
    const double *times;            /* output times, increasing to the stop time; the run
                                       starts at times[0] */
    double *out;                    /* n_times x (1 + n_columns), row-major, time first */
    double stop_time, tolerance;    /* tolerance: the FMUs' own solver tolerance */
    double step;                    /* fixed: the step; adaptive: the largest step */
    int scheme;                     /* ENG_JACOBI or ENG_GAUSS_SEIDEL */
    int extrapolation;              /* 0, 1, 2 */
    int adaptive;
    double tol;                     /* adaptive: global error tolerance on the states */
    double loop_tolerance;
    int max_loop_iterations;
    int newton;
    int event_sync;
    double event_tol;               /* event synchronisation: final bracket width [s] */
    eng_progress_fn progress;       /* may be NULL */
    void *progress_ctx;
    /* At rest: the derivative of each of `states`, in their order, when every instance
       is autonomous (no explicit time in its derivatives, outputs and indicators). A
       communication point where all are exactly zero, inputs consistent, is a fixed
       point of the coupled system, which stays there: the remaining rows repeat it and
       no more steps are taken. NULL: never (an instance may move with time). */
    const eng_variable *derivatives;
    /* Sleep: each instance's group of instances coupled to one another (-1: it never
       sleeps, not autonomous or without derivatives). A group whose derivatives are all
       exactly zero at a communication point stands still for good, whatever the rest
       of the assembly does, since nothing reaches it: its FMUs are not stepped again
       (their outputs keep their values). NULL: no group sleeps. */
    const int *rest_group;
    double *asleep_since;           /* out, n_instances (or NULL): when each fell asleep;
                                       INFINITY: never */
    /* Members the master evaluates itself, as the engine's me does (engine.h,
       eng_me_spec.time_function / .linear_map), per instance (NULL: none). time_function:
       no event indicators, constant state derivatives, outputs affine in the states and
       free of time and inputs (ConstantSpeed): each coupled output is its value at the
       start plus its rate (the directional derivative along the derivatives) times the
       time since, and it is not stepped. linear_map: no states, indicators or time,
       outputs affine in its inputs with constant coefficients (a spring): each coupled
       output is its value at the start plus its directional derivatives there times the
       change of the coupled inputs since, and its inputs are kept by the master. Either
       FMU is brought up to date (inputs set, one doStep over the time it lagged) where a
       row records it, and rolled back with the rest; one whose reads fail at the start,
       one in an algebraic loop, and under Gauss–Seidel a linear one with an input it
       extrapolates itself (its FMU reads the chain's end after its doStep) is stepped as
       any other. Only the coupled Float64 scalars are evaluated. */
    const int *time_function;
    const int *linear_map;
    int *evaluated;                 /* out, n_instances (or NULL): 1 where the run took the
                                       member as a time function, 2 as a linear map, else 0 */
} eng_cosim_spec;

typedef struct {
    long do_steps, loop_iterations;
    double loop_residual;
    double h_min, h_max, error_ratio_max;
    long events_synchronised;       /* steps redone to end at an event */
    long events_located;            /* start-of-step events moved back by bisection */
    int loop_failed_group;          /* after a failure in an algebraic loop: its group ... */
    int loop_singular;              /* ... 1: singular Newton matrix, 0: no convergence ... */
    double loop_failed_time;        /* ... at this time (Python words the message) */
    double at_rest_from;            /* where the run found the system at rest; INFINITY: never */
} eng_cosim_stats;

/* Co-simulation of Co-Simulation FMUs, one call per run. stats->status is ENG_DONE,
   ENG_STOPPED (progress callback), ENG_TERMINATED or ENG_FAILED (stats->message);
   stats->n_rows rows of `out` are valid in every case. Returns the event tables
   (eng_run_events, eng_run_free); NULL only when memory for them runs out. */
ENG_API eng_run *eng_cosimulate(const eng_cosim_spec *spec, eng_stats *stats,
                                eng_cosim_stats *cosim_stats);

/* The same master one communication step at a time, for an FMU that runs an assembly
   in its doStep (assembly_runtime.c). The spec must outlive the handle; its output
   fields (times, out) are not used. Every call returns 0 or ENG_FAILED, after which
   eng_cosim_message says why in one line. */
typedef struct eng_cosim eng_cosim;

/* Loads the members with their start values. NULL only when memory runs out; a
   failure to load is reported by the first call that follows. */
eng_cosim *eng_cosim_create(const eng_cosim_spec *spec);
int eng_cosim_enter_initialization(eng_cosim *m, double start_time);
int eng_cosim_exit_initialization(eng_cosim *m);
/* A member's input was set from outside (the assembly FMU's own input): the next
   eng_cosim_advance starts from couplings made consistent with it. */
void eng_cosim_inputs_changed(eng_cosim *m);
/* Steps until `target`, or until a member ends the simulation (eng_cosim_terminated). */
int eng_cosim_advance(eng_cosim *m, double target);
int eng_cosim_failed(const eng_cosim *m);
double eng_cosim_time(const eng_cosim *m);
int eng_cosim_terminated(const eng_cosim *m);
fmu_t *eng_cosim_member(eng_cosim *m, int i);
const char *eng_cosim_message(const eng_cosim *m);
void eng_cosim_free(eng_cosim *m);

#endif
