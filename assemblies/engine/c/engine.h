/*
 * engine.h: the compiled engine's public entry points and the description of a
 * run that Python (assemblies/engine/binding.py) fills in through ctypes.
 *
 * One call per run: the caller describes the instances (extracted FMUs, start
 * values), the couplings (in evaluation order), the recorded columns and the
 * output times, and gives an output buffer of n_times x n_columns doubles
 * (row-major). The call fills the buffer and returns an eng_run handle holding
 * what has no fixed size (the outputs at each event, one table per event group);
 * the caller reads it with eng_run_events and frees it with eng_run_free.
 *
 * Nothing here aborts: failures end the run with status ENG_FAILED and a one-line
 * message naming the instance; every output row computed before stays valid.
 */
#ifndef MECHFMU_ENGINE_H
#define MECHFMU_ENGINE_H

#include <stdint.h>

/* The entry points Python calls; an assembly FMU, which links the engine for its own
   use, builds with -DENG_API= so that it exports its FMI functions alone. */
#ifndef ENG_API
#define ENG_API __attribute__((visibility("default")))
#endif

/* The FMI type a variable is got and set with (eng_variable.type). Every value travels
   as a double in the engine's buffers (columns, couplings, event rows): exact for
   Float32, the 8/16/32-bit integers, Boolean (0/1) and Int64/UInt64 up to 2^53; a
   larger Int64/UInt64 value fails the run with a message naming the instance and the
   value, it is never rounded. A value set into an integer type is rounded to the
   nearest integer and must lie within the type's range (else the run fails, naming
   it). Enumeration is FMI 2's Integer call and FMI 3's Int64 call. A String travels
   as its index in the calling thread's string table (eng_string); 0 and 1 keep the
   meaning of the former is_int flag (Float64, Int32/FMI 2 Integer). */
enum {
    ENG_FLOAT64 = 0, ENG_INT32 = 1, ENG_FLOAT32, ENG_INT8, ENG_UINT8, ENG_INT16, ENG_UINT16,
    ENG_UINT32, ENG_INT64, ENG_UINT64, ENG_BOOLEAN, ENG_ENUMERATION, ENG_STRING, ENG_N_TYPES
};

/* A variable of an instance: a recorded column, an output kept at events, a coupled
   input or output. An element of an FMI 3 array is one variable: the array's value
   reference, its number of elements (`size`) and the element's index in the array's
   row-major order; an array is got and set whole (FMI 3 has no element access), so
   the engine keeps the last values it set of an array input (fmu.c). */
typedef struct {
    int instance;
    uint32_t vr;
    int type;     /* ENG_FLOAT64 ... ENG_STRING */
    int element;  /* index in the array, 0 for a scalar */
    int size;     /* elements of the array; 0 or 1: a scalar */
} eng_variable;

/* Got or set in one batched fmu_get_float64/fmu_set_float64 with other such variables */
#define ENG_PLAIN(v) ((v)->type == ENG_FLOAT64 && (v)->size <= 1)
/* A value that moves between events (extrapolated, in the Jacobian), not a discrete one */
#define ENG_CONTINUOUS_TYPE(type) ((type) == ENG_FLOAT64 || (type) == ENG_FLOAT32)

typedef struct {
    const char *unzip_dir;           /* the extracted FMU */
    const char *model_identifier;    /* of the interface the run uses */
    const char *instantiation_token;
    const char *instance_name;
    int fmi_version;                 /* 2 or 3 */
    int n_states, n_event_indicators;
    int can_get_set_state;
    int provides_directional_derivative; /* for the interface this run uses */
    /* parameters and start values, set before initialization */
    int n_float_starts;
    const uint32_t *float_start_vr;
    const double *float_start_values;
    int n_int_starts;
    const uint32_t *int_start_vr;
    const int32_t *int_start_values;
    /* outputs recorded at this instance's events (time first, then these), by the
       co-simulation master; the ME master takes them from eng_event_group (their
       `instance` is not read) */
    int n_event_outputs;
    const eng_variable *event_outputs;
    /* its continuous states and their derivatives (n_states each, in the FMU's order of
       states), for the Jacobian from directional derivatives; NULL: not known */
    const uint32_t *state_vr;
    const uint32_t *derivative_vr;
    /* Model Exchange: the FMU says it needs no fmiCompletedIntegratorStep (FMI 2's
       completedIntegratorStepNotNeeded, FMI 3's needsCompletedIntegratorStep = false);
       0 (the safe default): it is called after every step */
    int completed_step_not_needed;
    /* Model Exchange: an FMU not built by this project, held to less than FMI promises:
       time and states are set once more before an output row reads it (some exporters
       compute their outputs in fmiSetTime alone, from the states they hold then), and
       under ENG_JACOBIAN_AUTO its directional derivatives are compared with differences
       before the run trusts them */
    int foreign;
    /* parameters and start values of the other types and of array elements (their
       `instance` is not read), set after the float and int ones, in this order; an
       array's elements are set together as each one is (see eng_variable) */
    int n_typed_starts;
    const eng_variable *typed_starts;
    const double *typed_start_values;
    /* String parameters and start values */
    int n_string_starts;
    const uint32_t *string_start_vr;
    const char *const *string_start_values;
    /* Model Exchange: which inputs each derivative and output depends on (the FMU's
       ModelStructure), for the sparsity of the Jacobian (jacobian.c). With
       feedthrough_listed, unknown feedthrough_unknown[p] depends on input
       feedthrough_known[p], p < n_feedthrough, and on no other input; 0 (the safe
       default): every derivative and output may depend on every input. Every unknown
       may depend on every state of its own instance either way. */
    int feedthrough_listed;
    int n_feedthrough;
    const uint32_t *feedthrough_unknown;
    const uint32_t *feedthrough_known;
} eng_instance_spec;

/* Outputs recorded at the events of some indicators of one instance: one event table
   (time first, then these outputs). An ordinary instance has one group covering all
   its indicators; a composite FMU (a joined model) has one per member, so that each
   member's events are told apart as they are in separate FMUs. */
typedef struct {
    int instance;
    int first_indicator, n_indicators; /* the instance's indicators [first, first + n) */
    int n_outputs;
    const eng_variable *outputs; /* their `instance` is not read */
} eng_event_group;

/* target input = gain * source output */
typedef struct {
    eng_variable source, target;
    double gain;
} eng_coupling;

/* Called about every 0.25 s of wall time with the simulated time; nonzero stops the
   run cleanly at the last completed step. */
typedef int (*eng_progress_fn)(void *ctx, double t);

enum { ENG_DONE = 0, ENG_STOPPED = 1, ENG_TERMINATED = 2, ENG_FAILED = -1 };
/* ENG_AUTO: the explicit method until stiffness shows, then RODAS3 until it is gone
   (stiffness.h); the explicit method is DOPRI5, or DOP853 at tolerances up to
   ENG_HIGH_ORDER_TOLERANCE. ENG_DOP853: DOP853 throughout, as ENG_DOPRI5 is DOPRI5. */
enum { ENG_DOPRI5 = 0, ENG_RODAS3 = 1, ENG_AUTO = 2, ENG_DOP853 = 3 };
/* Where the 8th order pays on every scene measured (2026-11-28; evaluations for the
   error DOPRI5 reaches, its continuous extension's three extra stages counted, on the
   scenes of benchmarks/single_limit.py: python -m benchmarks.high_order): at 1e-9 the axle pendulum, the rolling coin
   and stick_slip take 0.48, 0.40 and 0.62 of DOPRI5's. At 1e-7 the axle (0.70) and the
   coin (0.57) still gain, but stick_slip ties (1.01: after each of its 23 events a step
   restarts with 12 stages) and the assumed-modes beam at N = 16 costs 1.2x DOPRI5's
   CPU (benchmarks/beam_scaling.py --methods); at 1e-6 stick_slip loses (1.25). */
#define ENG_HIGH_ORDER_TOLERANCE 1e-8
/* Model Exchange's Jacobian. AUTO: from directional derivatives where every instance
   has them, unless a foreign instance's disagree with central differences at the first
   point (or a call fails): then by finite differences. FD: always by differences.
   EXACT: from directional derivatives, and a failing call fails the run. */
enum { ENG_JACOBIAN_AUTO = 0, ENG_JACOBIAN_FD = 1, ENG_JACOBIAN_EXACT = 2 };

typedef struct {
    int status;           /* ENG_DONE, ENG_STOPPED, ENG_TERMINATED or ENG_FAILED */
    long n_rows;          /* output rows written (all of them when ENG_DONE) */
    double t_end;         /* the time the run reached */
    long steps, rejected, rhs_calls, jacobians, events;
    long method_switches; /* between DOPRI5 and RODAS3, with ENG_AUTO */
    double at_rest_from;  /* where the run found the system at rest for good; INFINITY: never */
    int terminated_by;    /* the instance that ended the run (ENG_TERMINATED), else -1 */
    int exact_jacobian;   /* Model Exchange: the Jacobian came from directional derivatives */
    char message[1024];   /* the error (ENG_FAILED) or the terminating FMU's last message */
    /* why the run left the directional derivatives for finite differences (ENG_JACOBIAN_AUTO),
       naming the instance; empty where it did not */
    char jacobian_note[512];
    /* Model Exchange, Jacobian from directional derivatives: column groups per Jacobian
       (jacobian.h) and directional-derivative calls over the run; 0 otherwise */
    long jacobian_groups, jacobian_evaluations;
    /* RODAS3's matrix factored as a band of this many diagonals (jacobian.h, solver_implicit.h);
       0: dense */
    long jacobian_band;
    /* Model Exchange, algebraic loops (eng_me_spec.n_loops): Newton steps and matrices
       evaluated over the run, all loops together */
    long loop_iterations, loop_matrices;
    /* Model Exchange: instances that took part in an event (event mode, discrete updates),
       summed over the events: n_instances per event where every instance does */
    long event_instances;
    /* the explicit method's order: 5 (DOPRI5) or 8 (DOP853); 85: DOP853, then DOPRI5
       (ENG_AUTO where events came every few steps); 0 for RODAS3 */
    int explicit_order;
} eng_stats;

typedef struct {
    int n_instances;
    const eng_instance_spec *instances;
    int n_couplings;
    const eng_coupling *couplings; /* in evaluation order: a source's inputs are set first */
    int n_columns;
    const eng_variable *columns;
    int n_event_groups;
    const eng_event_group *event_groups;
    long n_times;
    const double *times;           /* increasing; the run starts at times[0] */
    double *out;                   /* n_times x n_columns, row-major */
    double stop_time, tolerance;   /* tolerance: relative = absolute error of the solver */
    int method;                    /* ENG_DOPRI5, ENG_RODAS3 or ENG_AUTO */
    int event_subsamples;          /* interior points scanned per step for double crossings */
    double max_step;               /* the longest step; 0: no limit */
    eng_progress_fn progress;      /* may be NULL */
    void *progress_ctx;
    /* Rest: each instance's group of instances coupled to one another, -1 where it can
       never be seen to rest (explicit time in its derivatives, outputs or indicators).
       A step that leaves a group's states as they were, with each of their derivatives
       exactly zero, shows a fixed point the group keeps whatever the others do: it
       sleeps (its instances are no longer evaluated, their derivatives are zero), and
       once every instance sleeps the remaining rows repeat the point with no more
       steps. NULL: nothing rests. */
    const int *rest_group;
    double *asleep_since;          /* out, n_instances (or NULL): when each fell asleep */
    /* Per coupling, 1 where the evaluation between events needs it: an input that the
       state derivatives, the event indicators or the recorded columns depend on; 0 for
       one that can wait for the next event, where every coupling is propagated
       (assemblies/engine/liveness.py). NULL: every coupling, always. */
    const int *continuous;
    /* Per column, the index of the variable in its instance's continuous states where
       it is one (an FMU's state variable holds the value set by SetContinuousStates),
       else -1. Rows of states alone are written from the solution, without setting
       the instances to each output point. NULL: every column is read from its FMU. */
    const int *column_state;
    /* Per coupling, 1 where the recorded columns depend on it (a subset of
       `continuous`): an output row sets only these and the instances they and the
       columns read. NULL: a row sets every instance and the couplings of `continuous`. */
    const int *row_coupling;
    int jacobian;                  /* ENG_JACOBIAN_AUTO, _FD or _EXACT */
    /* Per instance i with event indicators, the couplings its indicators depend on
       (through other instances' outputs too): indicator_coupling[indicator_start[i] ..
       indicator_start[i + 1] - 1], in `couplings` order (n_instances + 1 starts). Event
       location then looks at each instance alone, moving only it and the instances those
       couplings read, so that its cost per step does not grow with the assembly. NULL:
       every indicator is evaluated on the whole assembly. */
    const int *indicator_start;
    const int *indicator_coupling;
    /* Algebraic loops between direct-feedthrough outputs (assemblies/masters/loops.py):
       loop k is the couplings loop_first[k] .. loop_first[k] + loop_count[k] - 1, one
       strongly connected group of Float64 scalar couplings, contiguous in `couplings`
       after every coupling it needs; loops do not overlap and come in increasing order.
       They are solved by Newton's method (loop.h) at every evaluation, to 1e-3 of the
       tolerance. loop_name[k] (may be NULL) names the loop's instances and couplings in
       messages. The Jacobian is taken by differences while there are loops. */
    int n_loops;
    const int *loop_first, *loop_count;
    const char *const *loop_name;
    /* Per instance, 1 where its states and coupled outputs are exact functions of time
       between events: constant state derivatives, outputs affine in the states and free
       of time and inputs, no event indicators, no recorded column (a kinematic source:
       ConstantSpeed). Between events such an instance is not called: its derivatives are
       the constants read at the last event and each coupled output is its value there
       plus its rate (the directional derivative along those derivatives) times the time
       since. Where a read fails, the instance is evaluated as any other. NULL: none. */
    const int *time_function;
    /* Per instance, 1 where it has no states and time appears nowhere in it (a spring
       between two masses): its outputs follow its inputs alone, so between events it is
       not moved to each point, only its inputs are set. NULL: every instance is moved. */
    const int *time_free;
    /* Per instance, 1 where it is a fixed linear map between events: no states, modes,
       indicators or time, outputs affine in its inputs with constant coefficients, and no
       recorded column (a spring between two masses). Between events it is not called:
       each coupled output is its value at the last event plus its directional
       derivatives there times the change of the coupled inputs since. Where a read fails,
       the instance is evaluated as any other. NULL: none. */
    const int *linear_map;
    /* out, n_instances (or NULL): for each instance taken from time or as a linear map,
       INFINITY where it was to the end of the run and the time of the event where a read
       failed and it was evaluated from there on; NAN for one never taken (not asked, or
       refused: states or indicators, a coupling not a Float64 scalar, a loop's member). */
    double *taken_until;
    /* Per instance, 1 where an event has nothing to update in it when only its inputs
       change: no event indicators, no modes or other discrete states (a spring, a mass,
       a kinematic source). At an event it takes part only where its own time event is
       due, it asks for one, or a coupled input of a discrete type changes; a continuous
       input it takes in continuous-time mode, as FMI allows. NULL: every instance whose
       coupled inputs the event changes takes part. */
    const int *event_free;
} eng_me_spec;

typedef struct eng_run eng_run;

/* Model Exchange: all continuous states of all instances in one integrator (a single
   FMU, e.g. a composite one, is the case n_instances = 1). NULL only when memory for
   the handle itself runs out (then stats->message says so). */
ENG_API eng_run *eng_simulate_me(const eng_me_spec *spec, eng_stats *stats);

/* The rows recorded for event group `group`: n_rows x width doubles, row-major,
   width = 1 + the group's n_outputs (time first). 0 on success. */
ENG_API int eng_run_events(const eng_run *run, int group, const double **rows, long *n_rows,
                           int *width);
ENG_API void eng_run_free(eng_run *run);

/* String values travel through the engine as indices into a table of the calling
   thread (instances.c): eng_string(i) is the text of index i (NULL: no such index),
   valid until eng_strings_clear, which a caller recording String values calls before a
   run. The table holds at most ENG_MAX_STRINGS distinct texts of a total of
   ENG_MAX_STRING_BYTES bytes; a run that would need more fails, naming the variable. */
#define ENG_MAX_STRINGS 65536
#define ENG_MAX_STRING_BYTES (64L << 20)
ENG_API const char *eng_string(long index);
ENG_API void eng_strings_clear(void);

#endif
