/*
 * Embedded Rosenbrock integrator RODAS3 (order 3, embedded order 2; L-stable and
 * stiffly accurate) used by Co-Simulation for stiff models: very stiff springs,
 * steep friction laws, beams with many modes.
 *
 * Like the explicit solver (solver.h) it knows nothing about FMI: it advances
 * x' = f(t, x) by one accepted step at a time and offers a dense output over
 * that step, so the caller's event location works the same with either method.
 * Every stage solves one linear system with the matrix I / (h gamma) - J, where
 * J = df/dx comes from the model (CasADi's exact Jacobian) and is factored by
 * dense_lu.c once per step size.
 */
#ifndef MECHFMU_SOLVER_IMPLICIT_H
#define MECHFMU_SOLVER_IMPLICIT_H

#include "solver.h" /* mf_rhs_fn */

/* d f / d x at (t, x), column-major n x n. 0 on success. The solver's f0 holds
   f(t, x) during the call (a forward-difference Jacobian reads it). */
typedef int (*mf_jac_fn)(void *ctx, double t, const double *x, double *jac);

typedef enum {
    MF_ROS_OK = 0,
    MF_ROS_RHS_FAILED,      /* f or its Jacobian failed or was not finite at the current
                               point, or at every trial point down to the smallest step */
    MF_ROS_STEP_UNDERFLOW   /* the step size fell below MF_MIN_STEP(t) */
} mf_ros_result;

typedef struct {
    int n;
    double *k[4];          /* stage increments */
    double *f0;            /* f(t, x) at the current point (reused as the next stage 1) */
    double *fdt;           /* d f / d t at the current point, by a forward difference */
    double *xs, *xn, *tmp; /* stage argument, candidate solution, scratch */
    double *jac, *lu;      /* Jacobian at the current point and the factored matrix */
    double *jac_next;      /* Jacobian where the last accepted step ended (the fold
                              check's), the next step's when jac_next_valid */
    int *piv;
    double *dx0, *dx1;     /* end points of the last accepted step */
    double *dc0, *dc1;     /* its dense output's cubic part, from the stages; like the
                              rest of the dense output not part of an FMU state, as it
                              is read only before the next step */
    double t_old, h_old;   /* last accepted step covers [t_old, t_old + h_old] */
    double h_guess;        /* controller's proposal for the next step; 0 = none yet */
    int fsal_valid;        /* f0 belongs to the current (t, x) */
    int jac_next_valid;    /* so does jac_next: cleared with fsal_valid */
    /* banded: J is zero outside kl rows below and ku columns above the diagonal (the
       caller knows its structure), so the matrix is factored in O(n kl (kl + ku));
       0 (what mf_ros_alloc sets): dense */
    int banded, kl, ku;
    long n_rejected;       /* statistics, for logging */
    long n_rhs;
    long n_jac;
    long n_lu;
} mf_ros;

/* 0 on success, -1 if memory could not be allocated (then nothing is held). */
int mf_ros_alloc(mf_ros *s, int n);
void mf_ros_free(mf_ros *s);

/* x or the right-hand side changed discontinuously: the stored f(t, x) is stale. */
void mf_ros_restart(mf_ros *s);

/* Forget the step-size history too. */
void mf_ros_reset(mf_ros *s);

/*
 * One accepted step from (*t, x) towards t_end, never beyond it, with the same
 * contract as mf_dopri_step: atol = rtol; on MF_ROS_OK *t and x hold the new
 * point and mf_ros_dense() is valid on [t_old, *t]; on failure they are unchanged.
 */
mf_ros_result mf_ros_step(mf_ros *s, mf_rhs_fn f, mf_jac_fn jac, void *ctx, double *t,
                          double *x, double t_end, double rtol, double h_initial);

/* The continuous extension of the last accepted step, at time t in it: a cubic in
   the stages (3rd order; continuous, not C1, across steps). Unlike a Hermite cubic
   through the end slopes it stays bounded on stiff components: an end point within
   the tolerance delta of a slow manifold of eigenvalue -rho has the slope rho delta,
   which Hermite turns into a bulge of h rho delta / 4, while every stage carries
   (I / (h gamma) - J)^-1 and keeps it near delta. */
void mf_ros_dense(const mf_ros *s, double t, double *x);
/* Its component i alone, the value mf_ros_dense writes to x[i]. */
double mf_ros_dense_one(const mf_ros *s, double t, int i);

#endif
