/*
 * Embedded Dormand–Prince 5(4) integrator used by Co-Simulation.
 *
 * It knows nothing about FMI or the model: it advances x' = f(t, x) by one
 * accepted step at a time so that the caller can look for events after each
 * step and use the dense output to locate them inside it.
 */
#ifndef MECHFMU_SOLVER_H
#define MECHFMU_SOLVER_H

#include <math.h> /* MF_MIN_STEP */

/* Returns 0 on success; nonzero means the model could not be evaluated here. */
typedef int (*mf_rhs_fn)(void *ctx, double t, const double *x, double *xdot);

/* The smallest step the controllers shrink to near time t. A step to the end of an
   interval shorter than this is still taken, as one explicit Euler step (its error,
   of order h^2, is below what double precision resolves there). */
#define MF_MIN_STEP(t) (1e-14 * fmax(1.0, fabs(t)))

typedef enum {
    MF_DOPRI_OK = 0,
    MF_DOPRI_RHS_FAILED,     /* f failed or was not finite at the current point, or at
                                every trial point down to the smallest step */
    MF_DOPRI_STEP_UNDERFLOW  /* the step size fell below MF_MIN_STEP(t) */
} mf_dopri_result;

typedef struct {
    int n;
    double *k[7];        /* stage derivatives; k[0] is f(t, x) at the current point (FSAL) */
    double *xs;          /* stage argument */
    double *xn;          /* candidate 5th-order solution */
    double *r[5];        /* continuous-extension coefficients of the last accepted step */
    double t_old, h_old; /* last accepted step covers [t_old, t_old + h_old] */
    double h_guess;      /* controller's proposal for the next step; 0 = none yet */
    double facold;       /* previous error norm, for the PI controller */
    int fsal_valid;      /* k[0] belongs to the current (t, x) */
    double h_lambda;     /* the last accepted step's stiffness estimate h |lambda| */
    long n_rejected;     /* statistics, for logging */
    long n_rhs;
} mf_dopri;

/* 0 on success, -1 if memory could not be allocated (then nothing is held). */
int mf_dopri_alloc(mf_dopri *s, int n);
void mf_dopri_free(mf_dopri *s);

/* x or the right-hand side changed discontinuously (event, reset, new inputs):
   the stored f(t, x) is stale. Keeps the step-size proposal. */
void mf_dopri_restart(mf_dopri *s);

/* Forget the step-size history too (reset, new initialisation). */
void mf_dopri_reset(mf_dopri *s);

/*
 * One accepted step from (*t, x) towards t_end, never beyond it; the step that
 * reaches t_end sets *t to exactly t_end. h_initial is used when the controller
 * has no proposal yet. atol = rtol. On MF_DOPRI_OK, *t and x hold the new point
 * and mf_dopri_dense() is valid on [t_old, *t]. On failure *t and x are unchanged.
 */
mf_dopri_result mf_dopri_step(mf_dopri *s, mf_rhs_fn f, void *ctx, double *t, double *x,
                              double t_end, double rtol, double h_initial);

/* 4th-order continuous extension of the last accepted step, at time t in it. */
void mf_dopri_dense(const mf_dopri *s, double t, double *x);
/* Its component i alone, the value mf_dopri_dense writes to x[i] (a few recorded states
   of many cost that few interpolations). */
double mf_dopri_dense_one(const mf_dopri *s, double t, int i);

#endif
