/*
 * stiffness.h: the automatic choice between the explicit solver (DOPRI5) and the
 * implicit one (RODAS3), made while integrating, for the FMUs' Co-Simulation and for
 * the assembly engine alike.
 *
 * Explicit to implicit: after each accepted DOPRI5 step, Hairer's stiffness test
 * (DOPRI5's own) estimates h |lambda| from the last two stages, which share their time
 * (|f(x7) - f(x6)| / |x7 - x6|). A step limited by stability rather than by accuracy
 * sits at the edge of the stability region, h |lambda| near 3.2; 15 such steps, not
 * interrupted by 6 others in a row (Hairer's rule), mean stiffness, and the implicit
 * method takes over.
 *
 * Implicit to explicit: after each accepted RODAS3 step, the Jacobian it factored
 * gives a bound on the spectral radius (the infinity norm of D^-1 J D, D the error
 * weights, as LSODA weighs it). Where h rho stays inside DOPRI5's stability region
 * with a margin for 6 steps in a row, the explicit method could take the
 * steps accuracy asks for, and takes over again (it is the cheaper per step, and of
 * higher order).
 */
#ifndef MECHFMU_STIFFNESS_H
#define MECHFMU_STIFFNESS_H

/* the values of the runtime's `solver` setting */
enum { MF_METHOD_EXPLICIT = 0, MF_METHOD_IMPLICIT = 1, MF_METHOD_AUTO = 2 };

typedef struct {
    int implicit;   /* the method the next step takes */
    int votes;      /* steps that spoke for the other method */
    int against;    /* consecutive steps since that spoke against it */
    long switches;  /* how often the method changed, for the run's report */
} mf_stiffness;

void mf_stiffness_reset(mf_stiffness *s, int start_implicit);

/* After an accepted explicit step with stiffness estimate h_lambda (mf_dopri's
   h_lambda): 1 when the implicit method takes the next step. */
int mf_stiffness_after_explicit(mf_stiffness *s, double h_lambda);

/* After an accepted implicit step of size h, whose Jacobian at its start was `jac`
   (column-major n x n) and whose start point was x: 1 when the explicit method takes
   the next step. */
int mf_stiffness_after_implicit(mf_stiffness *s, double h, const double *jac, const double *x,
                                int n, double rtol);

#endif
