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
 * method takes over. Near an equilibrium both of that estimate's differences are
 * round-off and it can miss a stability-bound DOPRI5 for millions of steps, so every 200
 * explicit steps the Jacobian is also evaluated: h rho beyond 2 (rho as below) means
 * stiffness too. So it is after every step that votes: 15 votes can come too late where
 * a component lies below the absolute tolerance (Robertson's kinetics at tolerance 1e-4:
 * y2 ~ 3e-5 rings negative at the stability edge within a few steps, then runs away as
 * y2' = -3e7 y2^2), and a step that does not vote costs nothing more.
 *
 * Implicit to explicit: after each accepted RODAS3 step, the Jacobian it factored
 * gives the spectral radius rho (by power iteration). Where h rho stays inside DOPRI5's stability region
 * with a margin for 6 steps in a row, the explicit method could take the
 * steps accuracy asks for, and takes over again (it is the cheaper per step, and of
 * higher order).
 *
 * Thrash: where Hairer's test calls DOPRI5 stability-bound but RODAS3's accuracy-bound
 * steps are no longer (an undamped structure: imaginary eigenvalues, a third-order
 * method against a fifth-order one), the two rules above hand the problem back and
 * forth every few dozen steps. So each implicit episode is judged when it ends: its
 * mean step against the explicit step it replaced. One that did not pay doubles the
 * explicit dwell (accepted steps since the last switch) needed before the next switch
 * to the implicit method; one that paid forgets it. The switches then number
 * O(log steps), and the implicit steps wasted are bounded by a fixed share of them.
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
    long explicit_steps; /* accepted since the last periodic check */
    long dwell;     /* accepted steps in the current method since the last switch */
    int penalty;    /* implicit episodes in a row that did not pay (the dwell doubles) */
    double h_explicit;     /* the explicit step the current implicit episode replaced */
    double implicit_h_sum; /* the episode's accepted implicit steps, summed */
    long jacobians_checked; /* Jacobians the explicit method's checks asked for */
    int fruitless;  /* checks since the last switch that found no stiffness (at most 3) */
} mf_stiffness;

void mf_stiffness_reset(mf_stiffness *s, int start_implicit);

/* After an accepted explicit step of size h with stiffness estimate h_lambda (mf_dopri's
   h_lambda): 1 when the implicit method takes the next step. */
int mf_stiffness_after_explicit(mf_stiffness *s, double h, double h_lambda);

/* After an explicit step that voted, and every EXPLICIT_CHECK_EVERY accepted explicit
   steps: 1 when the caller should also
   evaluate the Jacobian at the new point and call mf_stiffness_explicit_check, which
   catches what Hairer's estimate misses near an equilibrium (there both of its
   differences are round-off, and a stability-bound DOPRI5 can take millions of steps
   unnoticed). */
int mf_stiffness_wants_jacobian(mf_stiffness *s);

/* With the Jacobian at the current point and the step DOPRI5 proposes next: 1 when h
   rho exceeds DOPRI5's stability interval, and the implicit method takes over. */
int mf_stiffness_explicit_check(mf_stiffness *s, double h, const double *jac, int n);

/* After an accepted implicit step of size h, whose Jacobian at its start was `jac`
   (column-major n x n): 1 when the explicit method takes the next step. */
int mf_stiffness_after_implicit(mf_stiffness *s, double h, const double *jac, int n);

#endif
