/*
 * loop.c: Newton's method on an algebraic loop's coupled inputs (loop.h), shared by
 * the co-simulation and the Model Exchange masters.
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dense_lu.h"
#include "loop.h"

int eng_loop_alloc(eng_loop *L, int capacity)
{
    size_t n = (size_t)(capacity > 0 ? capacity : 1);
    memset(L, 0, sizeof *L);
    /* the matrix is n^2: bounded by the couplings the caller has, checked here */
    if (capacity < 0 || n > 46340) return -1;
    L->capacity = (int)n;
    L->u = calloc(n, sizeof(double));
    L->r = calloc(n, sizeof(double));
    L->du = calloc(n, sizeof(double));
    L->u2 = calloc(n, sizeof(double));
    L->r2 = calloc(n, sizeof(double));
    L->a = calloc(n * n, sizeof(double));
    L->pivot = calloc(n, sizeof(int));
    return L->u && L->r && L->du && L->u2 && L->r2 && L->a && L->pivot ? 0 : -1;
}

void eng_loop_free(eng_loop *L)
{
    free(L->u); free(L->r); free(L->du); free(L->u2); free(L->r2); free(L->a); free(L->pivot);
    memset(L, 0, sizeof *L);
}

static double max_abs(const double *v, int n)
{
    double m = 0.0;
    int i;
    for (i = 0; i < n; i++) m = fmax(m, fabs(v[i]));
    return m;
}

/* I - dG/du by forward differences of r around L->u (L->r holds r(u)): a column per
   input, for FMUs without directional derivatives. */
static int matrix_by_differences(eng_loop *L, eng_loop_residual_fn residual, void *ctx)
{
    const int n = L->n;
    int i, j;
    for (j = 0; j < n; j++) {
        double h;
        memcpy(L->u2, L->u, (size_t)n * sizeof(double));
        L->u2[j] += sqrt(DBL_EPSILON) * fmax(fabs(L->u[j]), 1.0);
        h = L->u2[j] - L->u[j]; /* the step actually taken */
        if (residual(ctx, L->u2, L->r2)) return -1;
        for (i = 0; i < n; i++) L->a[(size_t)j * n + i] = (L->r2[i] - L->r[i]) / h;
    }
    return 0;
}

/* A new matrix at u, factored: 0, -1 a call failed, 1 singular. */
static int new_matrix(eng_loop *L, eng_loop_residual_fn residual, eng_loop_matrix_fn matrix,
                      void *ctx)
{
    L->factored = 0;
    if (matrix ? matrix(ctx, L->a) : matrix_by_differences(L, residual, ctx)) return -1;
    L->matrices++;
    if (mf_lu_factor(L->a, L->n, L->pivot)) return 1;
    L->factored = 1;
    return 0;
}

int eng_loop_solve(eng_loop *L, eng_loop_residual_fn residual, eng_loop_matrix_fn matrix,
                   void *ctx, const eng_loop_options *o, double *residual_out)
{
    const int n = L->n;
    int it, i, fresh = 0, old_steps = 0;
    double res = INFINITY, previous = INFINITY;
    if (residual(ctx, L->u, L->r)) return ENG_LOOP_FAILED;
    for (it = 0; it <= o->max_iterations; it++) {
        res = max_abs(L->r, n);
        *residual_out = res;
        if (it >= o->min_steps && res <= o->tolerance * (1.0 + max_abs(L->u, n))) {
            L->iterations += it;
            return ENG_LOOP_OK;
        }
        if (it == o->max_iterations) break;
        if (o->newton) {
            /* an earlier solve's factors while they bring r down: a linear loop's
               matrix holds until the FMUs' feedthrough changes */
            if (!L->factored || !o->reuse || (!fresh && (old_steps >= o->reuse || res >= previous))) {
                int rc = new_matrix(L, residual, matrix, ctx);
                if (rc) return rc < 0 ? ENG_LOOP_FAILED : ENG_LOOP_SINGULAR;
                fresh = 1;
            } else if (!fresh) {
                old_steps++;
            }
            for (i = 0; i < n; i++) L->du[i] = -L->r[i];
            mf_lu_solve(L->a, n, L->pivot, L->du);
            for (i = 0; i < n; i++) L->u[i] += L->du[i];
        } else {
            for (i = 0; i < n; i++) L->u[i] -= L->r[i];
        }
        previous = res;
        for (i = 0; i < n && isfinite(L->u[i]); i++) {}
        if (i < n) break;
        if (residual(ctx, L->u, L->r)) return ENG_LOOP_FAILED;
    }
    L->iterations += it;
    L->factored = 0;
    *residual_out = max_abs(L->r, n);
    return ENG_LOOP_DIVERGED;
}

int eng_loop_matrix_dd(fmu_t **fmus, const eng_coupling *couplings, const int *members, int n,
                       double *a, int *bad)
{
    int i, j;
    for (i = 0; i < n; i++) {
        const eng_coupling *ci = &couplings[members[i]];
        const eng_variable *y = &ci->source;
        for (j = 0; j < n; j++) {
            const eng_variable *x = &couplings[members[j]].target;
            double *entry = &a[(size_t)j * n + i];
            *entry = i == j ? 1.0 : 0.0;
            /* a discrete or array coupling: no directional derivative of it */
            if (x->instance == y->instance && ENG_PLAIN(x) && ENG_PLAIN(y)) {
                double one = 1.0, d = 0.0;
                if (fmu_directional_derivative(fmus[y->instance], &y->vr, 1, &x->vr, 1, &one,
                                               &d) != FMU_OK) {
                    *bad = y->instance;
                    return -1;
                }
                *entry -= ci->gain * d;
            }
        }
    }
    return 0;
}
