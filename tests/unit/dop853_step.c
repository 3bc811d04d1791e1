/* DOP853 (assemblies/engine/c/dop853.c) on problems with known solutions.
   usage: dop853_step step PROBLEM H     one step of size h from a known point: the
                                         continuous extension's error at theta = 0.3,
                                         0.5, 0.7, then the step end's error
          dop853_step run PROBLEM TOL    t in [0.4, 10.4] at tolerance TOL with DOP853, then
                                         DOPRI5: for each, the largest error at 100
                                         points from the continuous extension, and the
                                         evaluations of f */
#include "dop853.h"
#include "solver.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int problem;

static int rhs(void *ctx, double t, const double *x, double *dx)
{
    (void)ctx;
    switch (problem) {
    case 0: dx[0] = x[1]; dx[1] = -x[0]; break;  /* oscillator */
    case 1: dx[0] = 1.0 - x[0] * x[0]; break;     /* tanh */
    default: dx[0] = cos(t) * x[0];               /* exp(sin t) */
    }
    return 0;
}

static void exact(double t0, const double *x0, double t, double *x)
{
    double s = t - t0;
    switch (problem) {
    case 0: x[0] = x0[0] * cos(s) + x0[1] * sin(s); x[1] = -x0[0] * sin(s) + x0[1] * cos(s); break;
    case 1: x[0] = tanh(atanh(x0[0]) + s); break;
    default: x[0] = x0[0] * exp(sin(t) - sin(t0));
    }
}

static double distance(int n, const double *a, const double *b)
{
    double e = 0.0;
    int i;
    for (i = 0; i < n; i++) e = fmax(e, fabs(a[i] - b[i]));
    return e;
}

int main(int argc, char **argv)
{
    const double t0 = 0.4, t_end = 10.4;
    double x0[2], xe[2], xd[2], x[2], t = t0, arg;
    int n, j;
    eng_dop853 s;
    if (argc != 4) return 2;
    problem = atoi(argv[2]);
    arg = atof(argv[3]);
    n = problem == 0 ? 2 : 1;
    x0[0] = problem == 0 ? 1.0 : problem == 1 ? 0.3 : 1.0;
    x0[1] = 0.5;
    memcpy(x, x0, sizeof x);
    if (eng_dop853_alloc(&s, n)) return 2;
    if (strcmp(argv[1], "step") == 0) {
        const double th[3] = {0.3, 0.5, 0.7};
        /* a tolerance no error reaches: the step is taken as asked */
        if (eng_dop853_step(&s, rhs, NULL, &t, x, t0 + arg, 1e6, arg) != MF_DOPRI_OK ||
            t != t0 + arg || eng_dop853_dense_prepare(&s, rhs, NULL))
            return 3;
        for (j = 0; j < 3; j++) {
            exact(t0, x0, t0 + th[j] * arg, xe);
            eng_dop853_dense(&s, t0 + th[j] * arg, xd);
            printf("%.17g ", distance(n, xd, xe));
        }
        exact(t0, x0, t, xe);
        printf("%.17g\n", distance(n, x, xe));
    } else {
        double err = 0.0, next = t0 + 0.1;
        mf_dopri d;
        while (t < t_end) {
            if (eng_dop853_step(&s, rhs, NULL, &t, x, t_end, arg, 1e-3) != MF_DOPRI_OK ||
                eng_dop853_dense_prepare(&s, rhs, NULL))
                return 3;
            for (; next <= t + 1e-12; next += 0.1) {
                exact(t0, x0, next, xe);
                eng_dop853_dense(&s, next, xd);
                err = fmax(err, distance(n, xd, xe));
            }
        }
        printf("%.17g %ld ", err, s.n_rhs);
        if (mf_dopri_alloc(&d, n)) return 2;
        memcpy(x, x0, sizeof x);
        t = t0;
        err = 0.0;
        next = t0 + 0.1;
        while (t < t_end) {
            if (mf_dopri_step(&d, rhs, NULL, &t, x, t_end, arg, 1e-3) != MF_DOPRI_OK) return 3;
            for (; next <= t + 1e-12; next += 0.1) {
                exact(t0, x0, next, xe);
                mf_dopri_dense(&d, next, xd);
                err = fmax(err, distance(n, xd, xe));
            }
        }
        printf("%.17g %ld\n", err, d.n_rhs);
        mf_dopri_free(&d);
    }
    eng_dop853_free(&s);
    return 0;
}
