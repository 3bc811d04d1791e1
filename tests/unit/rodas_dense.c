/* One RODAS3 step of size h from a known point: the dense output's error against the
   exact solution at theta = 0.3, 0.5, 0.7, then the error of the step's end.
   usage: rodas_dense PROBLEM H [RHO [DELTA]] */
#include "solver_implicit.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static double rho = 0.0;
static int problem;

static int rhs(void *ctx, double t, const double *x, double *dx)
{
    (void)ctx;
    switch (problem) {
    case 0: dx[0] = x[1]; dx[1] = -x[0]; break;          /* oscillator */
    case 1: dx[0] = 1.0 - x[0] * x[0]; break;             /* tanh */
    case 2: dx[0] = cos(t) * x[0]; break;                 /* exp(sin t) */
    default: dx[0] = -rho * (x[0] - sin(t)) + cos(t);     /* stiff, slow manifold sin t */
    }
    return 0;
}

static int jac(void *ctx, double t, const double *x, double *j)
{
    (void)ctx;
    switch (problem) {
    case 0: j[0] = 0.0; j[1] = -1.0; j[2] = 1.0; j[3] = 0.0; break;
    case 1: j[0] = -2.0 * x[0]; break;
    case 2: j[0] = cos(t); break;
    default: j[0] = -rho;
    }
    return 0;
}

static void exact(double t0, const double *x0, double t, double *x)
{
    double s = t - t0;
    switch (problem) {
    case 0: x[0] = x0[0] * cos(s) + x0[1] * sin(s); x[1] = -x0[0] * sin(s) + x0[1] * cos(s); break;
    case 1: x[0] = tanh(atanh(x0[0]) + s); break;
    case 2: x[0] = x0[0] * exp(sin(t) - sin(t0)); break;
    default: x[0] = sin(t) + (x0[0] - sin(t0)) * exp(-rho * s);
    }
}

int main(int argc, char **argv)
{
    const double th[3] = {0.3, 0.5, 0.7};
    double t0 = 0.4, x0[2], h, delta = 0.0;
    int n, i, j;
    mf_ros s;
    problem = atoi(argv[1]);
    h = atof(argv[2]);
    if (argc > 3) rho = atof(argv[3]);
    if (argc > 4) delta = atof(argv[4]);
    n = problem == 0 ? 2 : 1;
    x0[0] = problem == 0 ? 1.0 : problem == 1 ? 0.3 : problem == 2 ? 1.0 : sin(t0) + delta;
    x0[1] = 0.5;
    if (mf_ros_alloc(&s, n)) return 2;
    {
        double t = t0, x[2], xe[2], xd[2];
        memcpy(x, x0, sizeof x);
        if (mf_ros_step(&s, rhs, jac, NULL, &t, x, t0 + h, 1e6, h) != MF_ROS_OK || t != t0 + h)
            return 3;
        for (j = 0; j < 3; j++) {
            double e = 0.0;
            exact(t0, x0, t0 + th[j] * h, xe);
            mf_ros_dense(&s, t0 + th[j] * h, xd);
            for (i = 0; i < n; i++) e = fmax(e, fabs(xd[i] - xe[i]));
            printf("%.17g ", e);
        }
        exact(t0, x0, t0 + h, xe);
        printf("%.17g", fabs(x[0] - xe[0]));
        printf("\n");
    }
    mf_ros_free(&s);
    return 0;
}
