/*
 * Dormand–Prince 8(5,3) with its 7th-order continuous extension (Hairer, Nørsett &
 * Wanner, DOP853), the engine's explicit method at tight tolerances.
 *
 * At tight tolerances an 8th-order method reaches an error with far fewer evaluations
 * than DOPRI5's 5th order (at tolerance 1e-9 for DOPRI5's error: the axle pendulum 2.1x
 * fewer, the rolling coin 2.5x, the continuous extension's three extra stages counted;
 * engine.h, ENG_HIGH_ORDER_TOLERANCE, says where the engine takes it). It has
 * the shape of mf_dopri (fmus/runtime/solver.h) so that the engine can take either:
 * one accepted step at a time, FSAL, the stiffness estimate h |lambda| from two stages
 * at t + h, and a continuous extension of the last accepted step. Its extension needs
 * three more evaluations, so it is made only when asked (eng_dop853_dense_prepare): a
 * step with no row and no event indicator inside it never pays for them.
 */
#ifndef MECHFMU_DOP853_H
#define MECHFMU_DOP853_H

#include "solver.h" /* mf_rhs_fn, mf_dopri_result, MF_MIN_STEP */

/* DOPRI5's stability interval on the negative real axis (about 3.3) over DOP853's
   (about 6.0, Hairer's stiffness threshold 6.1 against DOPRI5's 3.25): a DOP853 step's
   h |lambda| times this is where it stands in DOPRI5's terms, which the automatic
   choice (stiffness.h) is written in. */
#define ENG_DOP853_EDGE_RATIO (3.3 / 6.0)

typedef struct {
    int n;
    /* stage slopes: k[0] is f(t, x) at the current point (FSAL); after an accepted step
       k[12] holds the previous point's, until the continuous extension is made; k[13..15]
       are the extension's own stages */
    double *k[16];
    double *xs;          /* stage argument */
    double *xn;          /* candidate 8th-order solution */
    double *r[8];        /* continuous extension: r[0] the step's start, r[1..7] its terms */
    int dense_ready;     /* r[] holds the whole extension of the last accepted step */
    double t_old, h_old; /* last accepted step covers [t_old, t_old + h_old] */
    double h_guess;      /* controller's proposal for the next step; 0 = none yet */
    int fsal_valid;      /* k[0] belongs to the current (t, x) */
    double h_lambda;     /* the last accepted step's h |lambda| (DOP853's own scale) */
    long n_rejected;
    long n_rhs;
} eng_dop853;

/* 0 on success, -1 if memory could not be allocated (then nothing is held). */
int eng_dop853_alloc(eng_dop853 *s, int n);
void eng_dop853_free(eng_dop853 *s);
/* as mf_dopri_restart and mf_dopri_reset */
void eng_dop853_restart(eng_dop853 *s);
void eng_dop853_reset(eng_dop853 *s);

/* One accepted step, as mf_dopri_step (atol = rtol). The continuous extension is then
   valid at the step's ends only, until eng_dop853_dense_prepare makes the rest. */
mf_dopri_result eng_dop853_step(eng_dop853 *s, mf_rhs_fn f, void *ctx, double *t, double *x,
                                double t_end, double rtol, double h_initial);

/* The last accepted step's whole continuous extension (three evaluations of f inside
   it); 0 on success, -1 where f failed there (the extension is then not valid). */
int eng_dop853_dense_prepare(eng_dop853 *s, mf_rhs_fn f, void *ctx);

/* The 7th-order continuous extension at time t in the last accepted step, all of x or
   component i alone. */
void eng_dop853_dense(const eng_dop853 *s, double t, double *x);
double eng_dop853_dense_one(const eng_dop853 *s, double t, int i);

#endif
