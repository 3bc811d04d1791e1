/*
 * Event location inside one accepted solver step: the single copy shared by
 * the FMU runtime (runtime.c, Co-Simulation doStep) and the assembly engine.
 *
 * It knows nothing about FMI or solvers: the caller gives a function that
 * evaluates every event indicator at a time inside the step (from the solver's
 * dense output, with whatever inputs hold there).
 */
#ifndef MECHFMU_EVENTS_H
#define MECHFMU_EVENTS_H

#include <stddef.h>

/* points per step at which the sampled polynomial is searched for a dip */
#define MF_DIP_GRID 64

/* Indicators at time t inside the last accepted step; 0 on success. */
typedef int (*mf_indicator_fn)(void *ctx, double t, double *z);

/* What an importer reads for an event indicator that is exactly 0 where Event Mode left
   it, on the side it takes (runtime.c): FMI 2.0 and 3.0 (fmi2/fmi3GetEventIndicators)
   say the FMU must guarantee z_j != 0 at an event restart, "for example, by shifting z_j
   with a small value". Far below any indicator's scale, and far enough above the
   smallest double that an importer's product of two indicator values (CVODE's sign test)
   does not underflow to zero. */
#define MF_INDICATOR_SHIFT 1e-100

/* Whether z is an indicator at zero: exactly 0, or a restart's MF_INDICATOR_SHIFT, which
   the engine (an importer that knows the convention) takes for the zero it stands for. */
int mf_at_zero(double z);

/* The crossing rule: from the reference sign of `before` to zero or beyond. An
   indicator whose reference is at zero (mf_at_zero) never crosses. */
int mf_crossed(double before, double after);

/* Scratch doubles mf_locate_event needs for n indicators and n_sub interior points. */
#define MF_LOCATE_WORK(n, n_sub) ((size_t)(n) * (size_t)((n_sub) + 4))

/*
 * Earliest time in (ta, tb] at which some indicator has crossed relative to its
 * reference z_ref (mf_crossed). z_b: the indicators at tb.
 *
 * An indicator can cross twice inside one step (a slip shorter than a solver
 * step): its sign at tb is then its sign at ta. Where that cannot happen the interior
 * is not sampled: each indicator's rate at both ends (a difference over 1/1024 of the
 * step, inward: two evaluations in all) and its values there give its Hermite cubic,
 * and when the cubic's Bernstein coefficients keep every indicator that has not
 * crossed away from zero (and every one that has crossed falling monotonically) by
 * more than the cubic's bend from its chord, the signs at the ends decide. Otherwise
 * (and always when a reference is at zero) the indicators are
 * sampled at n_sub equally spaced interior points, and, from n_sub >= 2 on, the
 * polynomial through the samples and tb is searched between them for a dip across
 * zero; a dip is kept only if the indicator itself has crossed there. The dense
 * output of a step is a polynomial of low degree in time (DOPRI5: 4, RODAS3: 3), so
 * for an indicator linear in the states (a relative velocity) with n_sub >= 4 the
 * polynomial is the indicator itself and no dip wider than 1/MF_DIP_GRID of the step
 * is missed. The earliest crossing is then bracketed by the Illinois method.
 *
 * A reference at zero (mf_at_zero: an indicator restarting at zero after an event,
 * e.g. a velocity reset to 0) takes the side the indicator leaves zero to: it is
 * replaced in z_ref by the first nonzero value sampled, and a crossing is counted
 * from there on. So a slip that starts at an event and ends inside the next step
 * is found too. Otherwise z_ref is not changed.
 *
 * A step shorter than MF_MIN_STEP(tb) is a line to both solvers (one Euler step): only
 * the signs at its ends are compared, and a crossing is put at tb.
 *
 * Returns 1 with *t_event the right end of the final bracket (the far side of the
 * crossing, so the model sees the new side) and z_event[n] the indicators there;
 * 0 when nothing crossed (t_event, z_event untouched); -1 when an indicator could
 * not be evaluated or was not finite.
 * work: MF_LOCATE_WORK(n, n_sub) doubles of scratch.
 */
int mf_locate_event(mf_indicator_fn z, void *ctx, int n, double ta, double *z_ref, double tb,
                    const double *z_b, int n_sub, double *t_event, double *z_event,
                    double *work);

#endif
