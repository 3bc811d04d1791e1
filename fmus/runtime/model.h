/*
 * The contract between one generated model and the shared mechfmu runtime.
 *
 * The Python builder (fmus/codegen.py) writes, per model, CasADi-generated C for
 * the functions below plus one `MF_MODEL` description. Everything else — the FMI
 * state machine, the embedded solver, event iteration, input extrapolation — lives
 * once in the runtime, so every component and every FMI version shares it.
 *
 * Every model function has the same five dense inputs, in this order:
 *     t (1), x (n_x), q (n_q), u (n_u), p (n_p)
 * where x are continuous states, q discrete states (modes, stored as doubles),
 * u inputs and p parameters. Outputs are dense, column-major.
 */
#ifndef MECHFMU_MODEL_H
#define MECHFMU_MODEL_H

typedef long long mf_int; /* CasADi's casadi_int */

typedef struct {
    /* CasADi's generated calling convention */
    int (*eval)(const double **arg, double **res, mf_int *iw, double *w, int mem);
    int (*work)(mf_int *sz_arg, mf_int *sz_res, mf_int *sz_iw, mf_int *sz_w);
} mf_function;

typedef enum {
    MF_TIME = 0,   /* the independent variable; value reference 0 */
    MF_PARAMETER,  /* p[index]; fixed after initialisation */
    MF_STATE,      /* x[index] */
    MF_DERIVATIVE, /* der(x[index]); computed */
    MF_INPUT,      /* u[index] */
    MF_COMPUTED,   /* y[index]; outputs and locals computed by `out` */
    MF_DISCRETE,   /* q[index]; changed only at events */
    MF_RUNTIME     /* a setting of the runtime, not of the model; index 0: the
                      Co-Simulation solver (0 DOPRI5, 1 RODAS3). After every model
                      variable, so the model's value references do not move */
} mf_kind;

typedef struct {
    const char *name;     /* FMI name, for log messages */
    mf_kind kind;
    int index;            /* into the array of its kind */
    int is_integer;       /* exposed as Int32 (FMI 3) / Integer (FMI 2) */
    double start;
    double nominal;       /* states: the scale an importer's error control may use; else 1 */
} mf_variable;

typedef struct {
    const char *message;  /* says which parameter and what is allowed */
    int strict;           /* 1: g > 0 required; 0: g >= 0 required */
} mf_constraint;

typedef struct {
    const char *model_name;
    const char *instantiation_token;
    int n_x, n_q, n_u, n_p, n_y, n_z, n_c;
    int n_variables;                 /* value reference == position in `variables` */
    const mf_variable *variables;
    /* for each input: the input that is its time derivative (s -> v -> a), or -1.
       Co-Simulation extrapolates inputs over a step by this Taylor chain. */
    const int *input_derivative;
    const mf_constraint *constraints;
    mf_function ode;   /* -> xdot (n_x) */
    mf_function out;   /* -> y (n_y) */
    mf_function zc;    /* -> event indicators (n_z); a sign change is an event */
    mf_function jump;  /* -> x_new (n_x), q_new (n_q): one event-iteration step */
    mf_function check; /* -> g (n_c); constraint i holds when g[i] >= 0 (> 0 if strict) */
    mf_function jac;   /* -> d xdot / d x (n_x * n_x, column-major) */
    /* the discrete states that, once nonzero, end the simulation (a coin that fell
       flat; a joined model has one per member that can end a run), n_terminate of them,
       and why each does (the runtime adds the time) */
    int n_terminate;
    const int *terminate_q;
    const char *const *terminate_message;
    /* d [xdot; y] / d [x; u]: the dense (n_x + n_y) x (n_x + n_u) Jacobian, column-major,
       for fmi2/3GetDirectionalDerivative and fmi3GetAdjointDerivative */
    mf_function dd;
    /* 1: time appears in none of ode, out and zc, so setting the time alone leaves
       what they computed valid (an importer sets it at every evaluation) */
    int time_invariant;
    /* the pattern of dd's result, which holds only its structural nonzeros: CasADi's
       compressed column form (n_rows, n_cols, then colind[n_cols + 1] and row[nnz];
       or n_rows, n_cols, 1 for a dense one). A dense dd of a joined model of 32 blocks
       would be 100,000 mostly zero entries, written one by one in its C */
    const mf_int *(*dd_sparsity)(mf_int i);
    /* 1: every state derivative is a constant of the parameters (no t, x, q or u in
       ode) and there is no event indicator: a Co-Simulation step adds h xdot, exactly,
       without the solver (runtime.c step_without_solver) */
    int constant_derivatives;
    /* for each input: 1 where a model function reads it, 0 for one that only carries
       another input along its Taylor chain (a rate input); NULL: every input is read */
    const int *input_read;
} mf_model;

extern const mf_model MF_MODEL;

#endif
