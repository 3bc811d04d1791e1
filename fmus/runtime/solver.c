/*
 * Dormand–Prince 5(4) with FSAL, PI step-size control and the 4th-order
 * continuous extension, following Hairer, Nørsett & Wanner (DOPRI5, contd5).
 */
#include "solver.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Butcher tableau */
static const double C2 = 1.0 / 5.0, C3 = 3.0 / 10.0, C4 = 4.0 / 5.0, C5 = 8.0 / 9.0;
static const double A21 = 1.0 / 5.0;
static const double A31 = 3.0 / 40.0, A32 = 9.0 / 40.0;
static const double A41 = 44.0 / 45.0, A42 = -56.0 / 15.0, A43 = 32.0 / 9.0;
static const double A51 = 19372.0 / 6561.0, A52 = -25360.0 / 2187.0, A53 = 64448.0 / 6561.0,
                    A54 = -212.0 / 729.0;
static const double A61 = 9017.0 / 3168.0, A62 = -355.0 / 33.0, A63 = 46732.0 / 5247.0,
                    A64 = 49.0 / 176.0, A65 = -5103.0 / 18656.0;
static const double A71 = 35.0 / 384.0, A73 = 500.0 / 1113.0, A74 = 125.0 / 192.0,
                    A75 = -2187.0 / 6784.0, A76 = 11.0 / 84.0;
/* difference between the 5th- and 4th-order solutions */
static const double E1 = 71.0 / 57600.0, E3 = -71.0 / 16695.0, E4 = 71.0 / 1920.0,
                    E5 = -17253.0 / 339200.0, E6 = 22.0 / 525.0, E7 = -1.0 / 40.0;
/* continuous extension */
static const double D1 = -12715105075.0 / 11282082432.0, D3 = 87487479700.0 / 32700410799.0,
                    D4 = -10690763975.0 / 1880347072.0, D5 = 701980252875.0 / 199316789632.0,
                    D6 = -1453857185.0 / 822651844.0, D7 = 69997945.0 / 29380423.0;

/* step-size controller (Hairer's defaults) */
static const double SAFE = 0.9;
static const double BETA = 0.04;
static const double FAC_MIN = 0.2;   /* h may shrink at most by 5 */
static const double FAC_MAX = 10.0;  /* and grow at most by 10 per step */

int mf_dopri_alloc(mf_dopri *s, int n)
{
    int i;
    size_t len = (size_t)(n > 0 ? n : 1);
    memset(s, 0, sizeof *s);
    s->n = n;
    for (i = 0; i < 7; i++) s->k[i] = (double *)calloc(len, sizeof(double));
    for (i = 0; i < 5; i++) s->r[i] = (double *)calloc(len, sizeof(double));
    s->xs = (double *)calloc(len, sizeof(double));
    s->xn = (double *)calloc(len, sizeof(double));
    for (i = 0; i < 7; i++) if (!s->k[i]) goto fail;
    for (i = 0; i < 5; i++) if (!s->r[i]) goto fail;
    if (!s->xs || !s->xn) goto fail;
    mf_dopri_reset(s);
    return 0;
fail:
    mf_dopri_free(s);
    return -1;
}

void mf_dopri_free(mf_dopri *s)
{
    int i;
    for (i = 0; i < 7; i++) { free(s->k[i]); s->k[i] = NULL; }
    for (i = 0; i < 5; i++) { free(s->r[i]); s->r[i] = NULL; }
    free(s->xs); s->xs = NULL;
    free(s->xn); s->xn = NULL;
}

void mf_dopri_restart(mf_dopri *s) { s->fsal_valid = 0; }

void mf_dopri_reset(mf_dopri *s)
{
    s->fsal_valid = 0;
    s->h_guess = 0.0;
    s->facold = 1e-4;
    s->t_old = 0.0;
    s->h_old = 0.0;
}

static int all_finite(const double *v, int n)
{
    int i;
    for (i = 0; i < n; i++) if (!isfinite(v[i])) return 0;
    return 1;
}

static int eval(mf_dopri *s, mf_rhs_fn f, void *ctx, double t, const double *x, double *dx)
{
    s->n_rhs++;
    return f(ctx, t, x, dx) == 0 && all_finite(dx, s->n);
}

/* Hairer's stiffness test: h |lambda| from the last two stages, which share their
   time t0 + h (xs holds stage 6's argument, xn the solution; k6, k7 their slopes) */
static double stiffness_estimate(const mf_dopri *s, double h)
{
    double num = 0.0, den = 0.0;
    int i;
    for (i = 0; i < s->n; i++) {
        double df = s->k[6][i] - s->k[5][i], dx = s->xn[i] - s->xs[i];
        num += df * df;
        den += dx * dx;
    }
    return den > 0.0 ? h * sqrt(num / den) : 0.0;
}

mf_dopri_result mf_dopri_step(mf_dopri *s, mf_rhs_fn f, void *ctx, double *t, double *x,
                              double t_end, double rtol, double h_initial)
{
    const int n = s->n;
    const double t0 = *t;
    const double h_min = MF_MIN_STEP(t0);
    const double expo1 = 0.2 - BETA * 0.75;
    double h = s->h_guess > 0.0 ? s->h_guess : h_initial;
    int rejected = 0;
    int rhs_failed = 0; /* the last rejection was a failed evaluation, not the error estimate */
    int i;

    if (n == 0) {
        /* nothing to integrate; the caller still checks indicators at t_end */
        s->t_old = t0;
        s->h_old = t_end - t0;
        *t = t_end;
        return MF_DOPRI_OK;
    }
    if (!s->fsal_valid) {
        if (!eval(s, f, ctx, t0, x, s->k[0])) return MF_DOPRI_RHS_FAILED;
        s->fsal_valid = 1;
    }
    if (t_end - t0 < h_min) {
        /* a legal step shorter than the controller's smallest (a master's sliver of
           1e-16 s before its stop time): one explicit Euler step, whose error h^2 |x''|
           is below what double precision resolves; the dense output is its line */
        const double hh = t_end - t0;
        for (i = 0; i < n; i++) {
            double dx = hh * s->k[0][i];
            if (!isfinite(x[i] + dx)) return MF_DOPRI_RHS_FAILED;
        }
        for (i = 0; i < n; i++) {
            double dx = hh * s->k[0][i];
            s->r[0][i] = x[i];
            s->r[1][i] = dx;
            s->r[2][i] = s->r[3][i] = s->r[4][i] = 0.0;
            x[i] += dx;
        }
        s->t_old = t0;
        s->h_old = hh;
        *t = t_end;
        s->fsal_valid = 0; /* f at the new point was not evaluated */
        return MF_DOPRI_OK;
    }
    if (!(h > 0.0) || !isfinite(h)) h = t_end - t0;

    for (;;) {
        double *k1 = s->k[0], *k2 = s->k[1], *k3 = s->k[2], *k4 = s->k[3];
        double *k5 = s->k[4], *k6 = s->k[5], *k7 = s->k[6];
        double *xs = s->xs, *xn = s->xn;
        double err = 0.0, fac11, hnew;
        int clamped = 0, ok;

        /* land exactly on t_end rather than leave a sliver for the next step */
        if (h * 1.01 >= t_end - t0) {
            h = t_end - t0;
            clamped = 1;
        }
        if (h < h_min) return rhs_failed ? MF_DOPRI_RHS_FAILED : MF_DOPRI_STEP_UNDERFLOW;

        for (i = 0; i < n; i++) xs[i] = x[i] + h * A21 * k1[i];
        ok = eval(s, f, ctx, t0 + C2 * h, xs, k2);
        if (ok) {
            for (i = 0; i < n; i++) xs[i] = x[i] + h * (A31 * k1[i] + A32 * k2[i]);
            ok = eval(s, f, ctx, t0 + C3 * h, xs, k3);
        }
        if (ok) {
            for (i = 0; i < n; i++)
                xs[i] = x[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]);
            ok = eval(s, f, ctx, t0 + C4 * h, xs, k4);
        }
        if (ok) {
            for (i = 0; i < n; i++)
                xs[i] = x[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]);
            ok = eval(s, f, ctx, t0 + C5 * h, xs, k5);
        }
        if (ok) {
            for (i = 0; i < n; i++)
                xs[i] = x[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] +
                                    A65 * k5[i]);
            ok = eval(s, f, ctx, t0 + h, xs, k6);
        }
        if (ok) {
            for (i = 0; i < n; i++)
                xn[i] = x[i] + h * (A71 * k1[i] + A73 * k3[i] + A74 * k4[i] + A75 * k5[i] +
                                    A76 * k6[i]);
            /* a finite slope at an overflowed point would pass the error test (its
               scale is infinite too) */
            ok = all_finite(xn, n) && eval(s, f, ctx, t0 + h, xn, k7);
        }
        if (!ok) {
            /* a trial point outside the model's domain: retry closer to the valid point */
            s->n_rejected++;
            rejected = 1;
            rhs_failed = 1;
            h *= 0.25;
            continue;
        }

        for (i = 0; i < n; i++) {
            double e = h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] +
                            E7 * k7[i]);
            double sc = rtol + rtol * fmax(fabs(x[i]), fabs(xn[i]));
            err += (e / sc) * (e / sc);
        }
        err = sqrt(err / n);
        if (!isfinite(err)) {
            s->n_rejected++;
            rejected = 1;
            rhs_failed = 1;
            h *= 0.25;
            continue;
        }

        fac11 = pow(err, expo1);
        if (err <= 1.0) {
            double fac = fac11 / pow(s->facold, BETA);
            double *tmp;
            fac = fmax(1.0 / FAC_MAX, fmin(1.0 / FAC_MIN, fac / SAFE));
            hnew = h / fac;
            if (rejected) hnew = fmin(hnew, h);
            s->facold = fmax(err, 1e-4);
            s->h_lambda = stiffness_estimate(s, h);

            for (i = 0; i < n; i++) {
                double dx = xn[i] - x[i];
                double bspl = h * k1[i] - dx;
                s->r[0][i] = x[i];
                s->r[1][i] = dx;
                s->r[2][i] = bspl;
                s->r[3][i] = dx - h * k7[i] - bspl;
                s->r[4][i] = h * (D1 * k1[i] + D3 * k3[i] + D4 * k4[i] + D5 * k5[i] +
                                  D6 * k6[i] + D7 * k7[i]);
                x[i] = xn[i];
            }
            s->t_old = t0;
            s->h_old = h;
            *t = clamped ? t_end : t0 + h;
            /* FSAL: f at the new point becomes the first stage of the next step */
            tmp = s->k[0];
            s->k[0] = s->k[6];
            s->k[6] = tmp;
            /* a step shortened to hit t_end says nothing against the longer proposal */
            s->h_guess = clamped ? fmax(hnew, s->h_guess) : hnew;
            return MF_DOPRI_OK;
        }
        s->n_rejected++;
        rejected = 1;
        rhs_failed = 0;
        h = h / fmin(1.0 / FAC_MIN, fac11 / SAFE);
    }
}

static double dense_theta(const mf_dopri *s, double t)
{
    return s->h_old > 0.0 ? (t - s->t_old) / s->h_old : 1.0;
}

static double dense_component(const mf_dopri *s, double theta, int i)
{
    const double theta1 = 1.0 - theta;
    return s->r[0][i] +
           theta * (s->r[1][i] +
                    theta1 * (s->r[2][i] + theta * (s->r[3][i] + theta1 * s->r[4][i])));
}

void mf_dopri_dense(const mf_dopri *s, double t, double *x)
{
    int i;
    double theta;
    if (s->n == 0) return;
    theta = dense_theta(s, t);
    for (i = 0; i < s->n; i++) x[i] = dense_component(s, theta, i);
}

double mf_dopri_dense_one(const mf_dopri *s, double t, int i)
{
    return dense_component(s, dense_theta(s, t), i);
}
