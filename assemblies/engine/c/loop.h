/*
 * loop.h: an algebraic loop between direct-feedthrough outputs, solved by Newton's
 * method for the coupled inputs u of its couplings (assemblies/masters/loops.py):
 *
 *     r(u) = u - G(u) = 0,   G_i(u) = gain_i * y_source(i)(u),
 *
 * the matrix I - dG/du from the FMUs' directional derivatives dy/du (or from
 * differences of r where an FMU has none). Both masters use it: co-simulation at each
 * communication point (cosim.c), Model Exchange at every evaluation of the coupled
 * system (me.c), where the factors are kept from one solve to the next while they
 * still converge (a loop linear in u, locked clutches, then takes one step per
 * evaluation and no new matrix until the FMUs' feedthrough changes).
 */
#ifndef MECHFMU_ENGINE_LOOP_H
#define MECHFMU_ENGINE_LOOP_H

#include "engine.h"
#include "fmu.h"

/* Sets the loop's inputs to u and gives r = u - G(u): 0, or nonzero when a call failed
   (the caller has said why). */
typedef int (*eng_loop_residual_fn)(void *ctx, const double *u, double *r);
/* a = I - dG/du at the point the inputs were last set to (column-major, n x n): 0, or
   nonzero when a call failed. NULL: by forward differences of the residual. */
typedef int (*eng_loop_matrix_fn)(void *ctx, double *a);

typedef struct {
    int capacity, n;      /* allocated for `capacity` couplings; this loop has n */
    double *u, *r, *du, *a, *u2, *r2;
    int *pivot;
    int factored;         /* a holds the LU factors of a matrix that may be reused */
    long iterations;      /* Newton (or fixed-point) steps over every solve */
    long matrices;        /* matrices evaluated and factored */
} eng_loop;

typedef struct {
    double tolerance;     /* converged: max |r| <= tolerance (1 + max |u|) */
    int max_iterations;
    int newton;           /* 0: plain fixed-point iteration u <- G(u) */
    /* keep the factors across solves; a new matrix after this many steps on a matrix
       of an earlier solve that did not converge (0: a new matrix for every step) */
    int reuse;
    int min_steps;        /* steps taken even when u already converges */
} eng_loop_options;

enum { ENG_LOOP_OK = 0, ENG_LOOP_FAILED = -1, ENG_LOOP_SINGULAR = 1, ENG_LOOP_DIVERGED = 2 };

int eng_loop_alloc(eng_loop *L, int capacity);
void eng_loop_free(eng_loop *L);

/* Solves the loop from L->u (its n entries the starting point, the solution after) for
   L->n couplings. The inputs hold L->u on return where it converged. ENG_LOOP_OK,
   _FAILED (a callback failed), _SINGULAR (I - dG/du cannot be factored), or
   _DIVERGED (no convergence within max_iterations, or u left the finite numbers);
   *residual: max |r| at the end. */
int eng_loop_solve(eng_loop *L, eng_loop_residual_fn residual, eng_loop_matrix_fn matrix,
                   void *ctx, const eng_loop_options *options, double *residual_out);

/* I - dG/du from directional derivatives for the couplings members[0 .. n-1] of
   `couplings` into a (column-major): entry (i, j) is -gain_i d y_i / d u_j where
   coupling j sets an input of coupling i's source instance. 0, or -1 with *bad the
   instance whose call failed. */
int eng_loop_matrix_dd(fmu_t **fmus, const eng_coupling *couplings, const int *members, int n,
                       double *a, int *bad);

#endif
