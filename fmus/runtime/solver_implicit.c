/*
 * RODAS3 (Sandu et al., Atmos. Environ. 31, 1997; the coefficients of KPP's
 * Rosenbrock.f90) in the formulation without matrix-vector products:
 *
 *     (I/(h gamma) - J) K_i = f(t + alpha_i h, x + sum_j a_ij K_j)
 *                             + sum_j (c_ij / h) K_j + h gamma_i df/dt
 *     x_new = x + sum_i m_i K_i,   error estimate = K_4.
 *
 * Stiffly accurate: x_new is the last stage argument plus K_4, so a very stiff
 * component lands on its slow manifold instead of ringing, and the embedded
 * 2nd-order solution is that stage argument itself. Step-size control is the
 * classical err^(-1/3) rule with the limits of the explicit solver.
 */
#include "solver_implicit.h"

#include "dense_lu.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double GAMMA = 0.5;              /* diagonal of the method */
static const double C21 = 4.0;                /* c_ij */
static const double C31 = 1.0, C32 = -1.0;
static const double C41 = 1.0, C42 = -1.0, C43 = -8.0 / 3.0;
static const double GAMMA1 = 0.5, GAMMA2 = 1.5; /* gamma_i = sum_j gamma_ij (0 for i = 3, 4) */
/* a_ij: stage 2 is evaluated at (t, x) (no new f), stage 3 at x + 2 K1, stage 4 at
   x + 2 K1 + K3, all of 3 and 4 at t + h; m = (2, 0, 1, 1) gives x_new = stage-4
   argument + K4. */
/* The dense output's extra stage K5 = lu \ (f(t + h, x_new) + h GAMMA5 df/dt) reuses
   the slope the next step needs anyway and the factored matrix: K1..K4 alone cannot
   give a 3rd-order interpolant (K3 and K4 carry the same combination of the two 3rd-
   order elementary differentials f''(f, f) and f'f'f). GAMMA5 makes the time
   component of K5 h / 2, as for an autonomous system. */
static const double GAMMA5 = 0.5;
/* x(t + theta h) = (1 - theta) x + theta x_new + theta (1 - theta) (D0 + theta D1),
   weights from the order conditions up to 3 with the weight of K3 set to theta^2:
   then in the stiff limit (h rho -> infinity for x' = -rho (x - g(t))) the interpolant
   is the quadratic through g at the step's start, slope and end, plus the end points'
   distances from g times bounded weights, never rho times them. */
static const double D01 = 7.0, D02 = -3.0, D03 = -1.0, D04 = 5.0, D05 = 2.0;
static const double D11 = -4.0, D12 = 2.0, D14 = -4.0, D15 = -2.0;

/* A step is refused when a diagonal entry of J that is stiff for it (h J_ii below
   -FOLD_STIFF) keeps less than 1 / FOLD_LOSS of its value at the step's end. An
   L-stable step damps whatever is fast at its start, so it can carry a component
   past the end of its slow manifold (a fold: the smooth friction law's peak, where
   J_ii tends to 0) and land, with a small error estimate, where the true solution
   has already run off. Refused steps approach such a point geometrically. The
   diagonal stands for the spectrum: it costs nothing more than the Jacobian the
   next step needs anyway. */
static const double FOLD_STIFF = 10.0;
static const double FOLD_LOSS = 4.0;

static const double SAFE = 0.9;
static const double FAC_MIN = 0.2;  /* h may shrink at most by 5 */
static const double FAC_MAX = 6.0;  /* and grow at most by 6 per step */

int mf_ros_alloc(mf_ros *s, int n)
{
    int i;
    size_t len = (size_t)(n > 0 ? n : 1);
    double **vec[] = {&s->f0, &s->fdt, &s->xs, &s->xn, &s->tmp,
                      &s->dx0, &s->dx1, &s->dc0, &s->dc1};
    memset(s, 0, sizeof *s);
    s->n = n;
    for (i = 0; i < 4; i++)
        if (!(s->k[i] = (double *)calloc(len, sizeof(double)))) goto fail;
    for (i = 0; i < (int)(sizeof vec / sizeof vec[0]); i++)
        if (!(*vec[i] = (double *)calloc(len, sizeof(double)))) goto fail;
    s->jac = (double *)calloc(len * len, sizeof(double));
    s->jac_next = (double *)calloc(len * len, sizeof(double));
    s->lu = (double *)calloc(len * len, sizeof(double));
    s->piv = (int *)calloc(len, sizeof(int));
    if (!s->jac || !s->jac_next || !s->lu || !s->piv) goto fail;
    mf_ros_reset(s);
    return 0;
fail:
    mf_ros_free(s);
    return -1;
}

void mf_ros_free(mf_ros *s)
{
    int i;
    for (i = 0; i < 4; i++) { free(s->k[i]); s->k[i] = NULL; }
    free(s->f0); free(s->fdt); free(s->xs); free(s->xn); free(s->tmp);
    free(s->dx0); free(s->dx1); free(s->dc0); free(s->dc1);
    free(s->jac); free(s->jac_next); free(s->lu); free(s->piv);
    s->f0 = s->fdt = s->xs = s->xn = s->tmp = NULL;
    s->dx0 = s->dx1 = s->dc0 = s->dc1 = s->jac = s->jac_next = s->lu = NULL;
    s->piv = NULL;
}

void mf_ros_restart(mf_ros *s) { s->fsal_valid = s->jac_next_valid = 0; }

void mf_ros_reset(mf_ros *s)
{
    s->fsal_valid = s->jac_next_valid = 0;
    s->h_guess = 0.0;
    s->t_old = 0.0;
    s->h_old = 0.0;
}

static int all_finite(const double *v, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) if (!isfinite(v[i])) return 0;
    return 1;
}

/* some diagonal entry of J is stiff for a step of size h: only then can the step
   cross a fold unnoticed */
static int fold_possible(const mf_ros *s, double h)
{
    int i;
    for (i = 0; i < s->n; i++)
        if (h * s->jac[i + i * s->n] < -FOLD_STIFF) return 1;
    return 0;
}

static int eval(mf_ros *s, mf_rhs_fn f, void *ctx, double t, const double *x, double *dx)
{
    s->n_rhs++;
    return f(ctx, t, x, dx) == 0 && all_finite(dx, (size_t)s->n);
}

/* lu = I / (h gamma) - J, factored; 0 if singular */
static int factor(mf_ros *s, double h)
{
    const int n = s->n;
    const double d = 1.0 / (h * GAMMA);
    int i;
    s->n_lu++;
    if (s->banded) {
        /* the band and the fill above it: kl + ku + kl diagonals */
        int j;
        for (j = 0; j < n; j++) {
            const int first = j - s->kl - s->ku > 0 ? j - s->kl - s->ku : 0;
            const int last = j + s->kl < n - 1 ? j + s->kl : n - 1;
            for (i = first; i <= last; i++)
                s->lu[i + (size_t)j * (size_t)n] = -s->jac[i + (size_t)j * (size_t)n];
            s->lu[j + (size_t)j * (size_t)n] += d;
        }
        return mf_lu_factor_band(s->lu, n, s->kl, s->ku, s->piv) == 0;
    }
    for (i = 0; i < n * n; i++) s->lu[i] = -s->jac[i];
    for (i = 0; i < n; i++) s->lu[i + i * n] += d;
    return mf_lu_factor(s->lu, n, s->piv) == 0;
}

/* the stage: K = lu \ rhs, rejected if not finite */
static int solve(mf_ros *s, double *k)
{
    if (s->banded) mf_lu_solve_band(s->lu, s->n, s->kl, s->ku, s->piv, k);
    else mf_lu_solve(s->lu, s->n, s->piv, k);
    return all_finite(k, (size_t)s->n);
}

mf_ros_result mf_ros_step(mf_ros *s, mf_rhs_fn f, mf_jac_fn jac, void *ctx, double *t,
                          double *x, double t_end, double rtol, double h_initial)
{
    const int n = s->n;
    const double t0 = *t;
    const double h_min = MF_MIN_STEP(t0);
    double h = s->h_guess > 0.0 ? s->h_guess : h_initial;
    double dt;
    int rejected = 0, failed = 0, i;

    if (n == 0) {
        s->t_old = t0;
        s->h_old = t_end - t0;
        *t = t_end;
        return MF_ROS_OK;
    }
    if (!s->fsal_valid) {
        if (!eval(s, f, ctx, t0, x, s->f0)) return MF_ROS_RHS_FAILED;
        s->fsal_valid = 1;
    }
    if (t_end - t0 < h_min) {
        /* shorter than the controller's smallest step: one explicit Euler step, as in
           mf_dopri_step (I / (h gamma) would overflow for the shortest steps); the
           dense output without its cubic part is the step's line */
        const double hh = t_end - t0;
        for (i = 0; i < n; i++)
            if (!isfinite(x[i] + hh * s->f0[i])) return MF_ROS_RHS_FAILED;
        for (i = 0; i < n; i++) {
            s->dx0[i] = x[i];
            x[i] += hh * s->f0[i];
            s->dx1[i] = x[i];
            s->dc0[i] = s->dc1[i] = 0.0;
        }
        s->t_old = t0;
        s->h_old = hh;
        *t = t_end;
        s->fsal_valid = s->jac_next_valid = 0; /* f at the new point was not evaluated */
        return MF_ROS_OK;
    }
    /* J and df/dt belong to the step's start point: computed once, kept through
       rejections. Time enters through the extrapolated inputs (and any explicit t);
       a forward difference is accurate enough for the gamma_i h df/dt term. */
    if (s->jac_next_valid) {
        /* the fold check evaluated it at this point */
        double *swap = s->jac;
        s->jac = s->jac_next;
        s->jac_next = swap;
        s->jac_next_valid = 0;
    } else {
        s->n_jac++;
        if (jac(ctx, t0, x, s->jac) != 0 || !all_finite(s->jac, (size_t)n * (size_t)n))
            return MF_ROS_RHS_FAILED;
    }
    dt = sqrt(DBL_EPSILON) * fmax(1.0, fabs(t0));
    if (eval(s, f, ctx, t0 + dt, x, s->fdt)) {
        for (i = 0; i < n; i++) s->fdt[i] = (s->fdt[i] - s->f0[i]) / dt;
    } else {
        memset(s->fdt, 0, (size_t)n * sizeof(double));
    }
    if (!(h > 0.0) || !isfinite(h)) h = t_end - t0;

    for (;;) {
        double *k1 = s->k[0], *k2 = s->k[1], *k3 = s->k[2], *k4 = s->k[3];
        double err = 0.0, fac, hnew;
        int clamped = 0, ok;

        if (h * 1.01 >= t_end - t0) {
            h = t_end - t0;
            clamped = 1;
        }
        if (h < h_min) return failed ? MF_ROS_RHS_FAILED : MF_ROS_STEP_UNDERFLOW;

        ok = factor(s, h);
        if (ok) {
            for (i = 0; i < n; i++) k1[i] = s->f0[i] + h * GAMMA1 * s->fdt[i];
            ok = solve(s, k1);
        }
        if (ok) {
            for (i = 0; i < n; i++) k2[i] = s->f0[i] + (C21 / h) * k1[i] + h * GAMMA2 * s->fdt[i];
            ok = solve(s, k2);
        }
        if (ok) {
            for (i = 0; i < n; i++) s->xs[i] = x[i] + 2.0 * k1[i];
            ok = eval(s, f, ctx, t0 + h, s->xs, k3);
        }
        if (ok) {
            for (i = 0; i < n; i++) k3[i] += (C31 * k1[i] + C32 * k2[i]) / h;
            ok = solve(s, k3);
        }
        if (ok) {
            for (i = 0; i < n; i++) s->xs[i] = x[i] + 2.0 * k1[i] + k3[i];
            ok = eval(s, f, ctx, t0 + h, s->xs, k4);
        }
        if (ok) {
            for (i = 0; i < n; i++) k4[i] += (C41 * k1[i] + C42 * k2[i] + C43 * k3[i]) / h;
            ok = solve(s, k4);
        }
        if (ok) {
            for (i = 0; i < n; i++) {
                double sc;
                s->xn[i] = s->xs[i] + k4[i];
                sc = rtol + rtol * fmax(fabs(x[i]), fabs(s->xn[i]));
                err += (k4[i] / sc) * (k4[i] / sc);
            }
            err = sqrt(err / n);
            ok = isfinite(err) && all_finite(s->xn, (size_t)n);
        }
        /* the slope at the new point, stage 1 of the next step, and through the matrix
           the dense output's K5 (in xs, free now) */
        if (ok && err <= 1.0) ok = eval(s, f, ctx, t0 + h, s->xn, s->tmp);
        if (ok && err <= 1.0) {
            for (i = 0; i < n; i++) s->xs[i] = s->tmp[i] + h * GAMMA5 * s->fdt[i];
            ok = solve(s, s->xs);
        }
        if (ok && err <= 1.0 && fold_possible(s, h)) {
            /* the Jacobian where the step ends; f there is f0 for jac's finite
               differences. One that cannot be had is left to the next step to report. */
            double *swap = s->f0;
            int fold = 0;
            s->f0 = s->tmp;
            s->tmp = swap;
            s->n_jac++;
            s->jac_next_valid = jac(ctx, t0 + h, s->xn, s->jac_next) == 0 &&
                                all_finite(s->jac_next, (size_t)n * (size_t)n);
            swap = s->f0;
            s->f0 = s->tmp;
            s->tmp = swap;
            for (i = 0; i < n && s->jac_next_valid; i++) {
                const double j0 = s->jac[i + i * n], j1 = s->jac_next[i + i * n];
                if (h * j0 < -FOLD_STIFF && j1 > j0 / FOLD_LOSS) fold = 1;
            }
            if (fold) {
                s->n_rejected++;
                s->jac_next_valid = 0;
                rejected = 1;
                failed = 0;
                h *= 0.5;
                continue;
            }
        }
        if (!ok) {
            /* a singular matrix or a trial point outside the model's domain */
            s->n_rejected++;
            rejected = failed = 1;
            h *= 0.25;
            continue;
        }

        fac = err > 0.0 ? SAFE * pow(err, -1.0 / 3.0) : FAC_MAX;
        fac = fmax(FAC_MIN, fmin(FAC_MAX, fac));
        if (err <= 1.0) {
            double *swap;
            hnew = h * fac;
            if (rejected) hnew = fmin(hnew, h);
            memcpy(s->dx0, x, (size_t)n * sizeof(double));
            memcpy(s->dx1, s->xn, (size_t)n * sizeof(double));
            for (i = 0; i < n; i++) {
                s->dc0[i] = D01 * k1[i] + D02 * k2[i] + D03 * k3[i] + D04 * k4[i] +
                            D05 * s->xs[i];
                s->dc1[i] = D11 * k1[i] + D12 * k2[i] + D14 * k4[i] + D15 * s->xs[i];
            }
            memcpy(x, s->xn, (size_t)n * sizeof(double));
            swap = s->f0;
            s->f0 = s->tmp;
            s->tmp = swap;
            s->t_old = t0;
            s->h_old = h;
            *t = clamped ? t_end : t0 + h;
            /* a step shortened to hit t_end says nothing against the longer proposal */
            s->h_guess = clamped ? fmax(hnew, s->h_guess) : hnew;
            return MF_ROS_OK;
        }
        s->n_rejected++;
        rejected = 1;
        failed = 0;
        h *= fac;
    }
}

static double ros_theta(const mf_ros *s, double t)
{
    return s->h_old > 0.0 ? (t - s->t_old) / s->h_old : 1.0;
}

static double ros_component(const mf_ros *s, double th, int i)
{
    return (1.0 - th) * s->dx0[i] + th * s->dx1[i] +
           th * (1.0 - th) * (s->dc0[i] + th * s->dc1[i]);
}

void mf_ros_dense(const mf_ros *s, double t, double *x)
{
    int i;
    double th;
    if (s->n == 0) return;
    th = ros_theta(s, t);
    for (i = 0; i < s->n; i++) x[i] = ros_component(s, th, i);
}

double mf_ros_dense_one(const mf_ros *s, double t, int i)
{
    return ros_component(s, ros_theta(s, t), i);
}
