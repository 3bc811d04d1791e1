/*
 * Event location inside one accepted step (see events.h).
 */
#include "events.h"
#include "solver.h" /* MF_MIN_STEP: the steps the solvers take as a line */

#include <math.h>
#include <string.h>

int mf_at_zero(double z) { return z == 0.0 || fabs(z) == MF_INDICATOR_SHIFT; }

int mf_crossed(double before, double after)
{
    if (mf_at_zero(before)) return 0;
    return (before > 0.0 && after <= 0.0) || (before < 0.0 && after >= 0.0);
}

static int all_finite(int n, const double *z)
{
    int i;
    for (i = 0; i < n; i++)
        if (!isfinite(z[i])) return 0;
    return 1;
}

/* Illinois (Anderson–Björck-like) bracketing on indicator i over [ta, tb],
   whose sign at ta is that of fa != 0. Sets *t_root to the right end of the
   final bracket, the side on which the indicator has crossed. 0 on success. */
static int locate_one(mf_indicator_fn z, void *ctx, int n, int i, double ta, double fa,
                      double tb, double fb, double *t_root, double *z_tmp)
{
    /* prefer a right end strictly across zero, so that the model sees the new
       side; accept exactly zero only if that is all the bracket offers */
    const int strict = fb != 0.0;
    const int positive = fa > 0.0; /* the side the indicator starts on */
    const double tol = 1e-13 * fmax(1.0, fabs(tb));
    int side = 0, it, force_bisect = 0;
    double width_ref = tb - ta;

    for (it = 0; it < 500 && tb - ta > tol; it++) {
        double tc, fc;
        int across;
        if (!force_bisect && fb != fa) tc = tb - fb * (tb - ta) / (fb - fa);
        else tc = 0.5 * (ta + tb);
        if (!(tc > ta && tc < tb)) tc = 0.5 * (ta + tb);
        force_bisect = 0;
        if (z(ctx, tc, z_tmp) || !all_finite(n, z_tmp)) return -1;
        fc = z_tmp[i];
        across = positive ? (strict ? fc < 0.0 : fc <= 0.0) : (strict ? fc > 0.0 : fc >= 0.0);
        if (across) {
            tb = tc;
            fb = fc;
            if (side == 1) fa *= 0.5;
            side = 1;
        } else {
            ta = tc;
            fa = fc;
            if (side == -1) fb *= 0.5;
            side = -1;
        }
        /* a secant creeping in from one side: halve the bracket instead */
        if (it % 3 == 2) {
            if (tb - ta > 0.5 * width_ref) force_bisect = 1;
            width_ref = tb - ta;
        }
    }
    *t_root = tb;
    return 0;
}

/* Newton form of the polynomial through (x[k], y[k]), k < m: y becomes its divided
   differences. */
static void divided_differences(int m, const double *x, double *y)
{
    int j, k;
    for (j = 1; j < m; j++)
        for (k = m - 1; k >= j; k--) y[k] = (y[k] - y[k - 1]) / (x[k] - x[k - j]);
}

static double newton(int m, const double *x, const double *a, double at)
{
    double p = a[m - 1];
    int k;
    for (k = m - 2; k >= 0; k--) p = a[k] + (at - x[k]) * p;
    return p;
}

/* The polynomial through the samples of indicator i (and through (0, 0) too when
   `origin`: an indicator known to start at zero), at theta = at. */
static double interpolate(int m, const double *theta, const double *v, int n, int i, int origin,
                          double at)
{
    double x[65], y[65];
    int k, o = origin ? 1 : 0;
    x[0] = y[0] = 0.0;
    for (k = 0; k < m; k++) {
        x[k + o] = theta[k];
        y[k + o] = v[(size_t)k * n + i];
    }
    divided_differences(m + o, x, y);
    return newton(m + o, x, y, at);
}

/* The earliest grid theta in (0, hi] where the polynomial through the samples of
   indicator i is on or across zero from the side `sign`; 2 if nowhere. */
static double first_dip(int m, const double *theta, const double *v, int n, int i, int origin,
                        double sign, double hi)
{
    double x[65], y[65], lowest = INFINITY, highest = -INFINITY;
    int g, k, o = origin ? 1 : 0;
    x[0] = y[0] = 0.0;
    for (k = 0; k < m; k++) {
        double s = sign * v[(size_t)k * n + i];
        lowest = fmin(lowest, s);
        highest = fmax(highest, s);
        x[k + o] = theta[k];
        y[k + o] = s;
    }
    /* far from zero compared with its change over the step, the polynomial cannot
       reach zero: on [0, 1] it stays within (2^m - 1) / 2 ranges of the samples'
       middle (the Lebesgue constant of these nodes is 2^m - 1, at theta = 0) */
    if (!origin && lowest > ldexp(highest - lowest, m - 1)) return 2.0;
    divided_differences(m + o, x, y);
    for (g = 1; g <= MF_DIP_GRID; g++) {
        double at = (double)g / MF_DIP_GRID;
        if (at > hi) break;
        if (newton(m + o, x, y, at) <= 0.0) return at;
    }
    return 2.0;
}

/* Whether no indicator can cross zero and come back inside the step, so that the signs
   at its ends tell all (the interior need not be sampled). Each indicator's rate at
   both ends is taken by a difference over QUIET_DTHETA of the step, inward, on the
   caller's dense output (two evaluations, against n_sub); with the values at the ends
   they give its Hermite cubic, whose Bernstein coefficients bound it on the step. The
   step is quiet when, for every indicator (f: the indicator on its reference's side),
   - not crossed at tb: every coefficient stays above zero by more than the cubic's own
     bend away from the chord (the room left for the dense output's quartic part, which
     the step-size control keeps below the cubic's) plus the differences' error;
   - crossed at tb: the coefficients fall by more than that at each of the three
     intervals (the cubic is monotone: one root, the one the bracket finds).
   A reference at zero (an indicator restarting at zero) or a reference that is not the
   value at ta (an old side kept across an event: its difference to z(ta + d) is then
   no rate and fails the test) is never quiet. 1: quiet; 0: sample; -1: not finite. */
#define QUIET_DTHETA (1.0 / 1024.0)
static int quiet_step(mf_indicator_fn z, void *ctx, int n, double ta, const double *z_ref,
                      double tb, const double *z_b, double *z_a1, double *z_b1)
{
    const double h = tb - ta, d = QUIET_DTHETA;
    int i;
    for (i = 0; i < n; i++)
        if (mf_at_zero(z_ref[i]) || mf_at_zero(z_b[i])) return 0;
    if (z(ctx, ta + d * h, z_a1) || !all_finite(n, z_a1)) return -1;
    if (z(ctx, tb - d * h, z_b1) || !all_finite(n, z_b1)) return -1;
    for (i = 0; i < n; i++) {
        const double s = z_ref[i] > 0.0 ? 1.0 : -1.0;
        const double fa = s * z_ref[i], fb = s * z_b[i];
        const double da = s * (z_a1[i] - z_ref[i]) / d, db = s * (z_b[i] - z_b1[i]) / d;
        const double b1 = fa + da / 3.0, b2 = fb - db / 3.0; /* b0 = fa, b3 = fb */
        const double chord = fb - fa;
        /* the cubic's bend from the chord (Bernstein coefficients of their difference),
           the differences' error (d times the change of rate), a rounding floor */
        const double margin = fabs(da - chord) / 3.0 + fabs(chord - db) / 3.0 +
                              d * fabs(db - da) + 1e-12 * (fabs(fa) + fabs(fb));
        if (fb > 0.0) {
            if (!(b1 > margin && b2 > margin && s * z_a1[i] > 0.0 && s * z_b1[i] > 0.0))
                return 0;
        } else if (!(fa - b1 > margin && b1 - b2 > margin && b2 - fb > margin)) {
            return 0;
        }
    }
    return 1;
}

int mf_locate_event(mf_indicator_fn z, void *ctx, int n, double ta, double *z_ref, double tb,
                    const double *z_b, int n_sub, double *t_event, double *z_event,
                    double *work)
{
    /* samples[k] (k = 0 .. m - 1) at theta[k] = (k + 1) / m of the step; the last is tb */
    int m = (n_sub < 63 ? n_sub : 63) + 1; /* theta[] holds 64; more buy nothing */
    double *samples = work, *z_right = work + (size_t)m * n, *z_tmp = z_right + n;
    double *origin = z_tmp + n; /* 1: the indicator starts this step at exactly zero */
    double theta[64];
    const double *z_left;
    double t_left, t_right = tb, t_hit, theta_hit = 2.0;
    int k, i, first_cross = -1;

    if (n <= 0) return 0;
    if (tb - ta < MF_MIN_STEP(tb)) {
        /* A sliver (an event a rounding error before a communication point): the solvers
           take it as one Euler step, a line, and its interior times round to its ends,
           so samples there are a step function whose polynomial oscillates and "finds"
           a crossing at ta again and again. On a line the signs at the ends tell all. */
        int crossed = 0;
        for (i = 0; i < n; i++) {
            if (mf_at_zero(z_ref[i])) z_ref[i] = z_b[i];
            else if (mf_crossed(z_ref[i], z_b[i])) crossed = 1;
        }
        if (!crossed) return 0;
        *t_event = tb;
        memcpy(z_event, z_b, (size_t)n * sizeof(double));
        return 1;
    }
    if (m > 1) {
        /* the interior is sampled only where a double crossing can hide */
        int quiet = quiet_step(z, ctx, n, ta, z_ref, tb, z_b, z_tmp, z_right);
        if (quiet < 0) return -1;
        if (quiet) m = 1;
    }
    for (k = 0; k < m; k++) {
        double *zk = samples + (size_t)k * n;
        theta[k] = (double)(k + 1) / m;
        if (k == m - 1) memcpy(zk, z_b, (size_t)n * sizeof(double));
        else if (z(ctx, ta + (tb - ta) * theta[k], zk) || !all_finite(n, zk)) return -1;
    }
    /* a zero reference takes the side the indicator leaves zero to: just after ta on
       the polynomial through zero and the samples, else the first nonzero sample */
    for (i = 0; i < n; i++) {
        origin[i] = mf_at_zero(z_ref[i]);
        if (!origin[i]) continue;
        z_ref[i] = 0.0;
        if (m >= 2) z_ref[i] = interpolate(m, theta, samples, n, i, 1, 0.25 / MF_DIP_GRID);
        for (k = 0; k < m && mf_at_zero(z_ref[i]); k++) z_ref[i] = samples[(size_t)k * n + i];
    }
    for (k = 0; k < m && first_cross < 0; k++)
        for (i = 0; i < n; i++)
            if (mf_crossed(z_ref[i], samples[(size_t)k * n + i])) first_cross = k;
    /* a dip between samples, before the first sampled crossing */
    if (m >= 3) {
        double hi = first_cross < 0 ? 1.0 : (first_cross ? theta[first_cross - 1] : 0.0);
        for (i = 0; i < n; i++)
            if (!mf_at_zero(z_ref[i]))
                theta_hit = fmin(theta_hit, first_dip(m, theta, samples, n, i, origin[i] != 0.0,
                                                      z_ref[i] > 0.0 ? 1.0 : -1.0, hi));
    }
    if (theta_hit <= 1.0) {
        t_right = ta + (tb - ta) * theta_hit;
        if (z(ctx, t_right, z_right) || !all_finite(n, z_right)) return -1;
        for (i = 0; i < n; i++)
            if (mf_crossed(z_ref[i], z_right[i])) break;
        if (i == n) theta_hit = 2.0; /* the polynomial dipped, the indicator did not */
    }
    if (theta_hit <= 1.0) {
        for (k = m - 1; k >= 0 && theta[k] >= theta_hit; k--) {}
    } else if (first_cross >= 0) {
        k = first_cross - 1;
        t_right = first_cross == m - 1 ? tb : ta + (tb - ta) * theta[first_cross];
        memcpy(z_right, samples + (size_t)first_cross * n, (size_t)n * sizeof(double));
    } else {
        return 0;
    }
    /* the bracket's left end: the last sample before it, or ta (with the reference,
       on the side every indicator started from) */
    t_left = k >= 0 ? ta + (tb - ta) * theta[k] : ta;
    z_left = k >= 0 ? samples + (size_t)k * n : z_ref;
    /* the earliest root in [t_left, t_right]: shrink the right end to each crossing in
       turn; an indicator that no longer crosses at the shrunk end crosses later */
    t_hit = t_right;
    for (i = 0; i < n; i++) {
        double t_root;
        if (!mf_crossed(z_ref[i], z_right[i])) continue;
        /* a zero start still at zero at t_left: use the side it took for the secant */
        if (locate_one(z, ctx, n, i, t_left, !mf_at_zero(z_left[i]) ? z_left[i] : z_ref[i], t_hit,
                       z_right[i], &t_root, z_tmp))
            return -1;
        if (t_root < t_hit) {
            t_hit = t_root;
            if (z(ctx, t_hit, z_right) || !all_finite(n, z_right)) return -1;
        }
    }
    *t_event = t_hit;
    memcpy(z_event, z_right, (size_t)n * sizeof(double));
    return 1;
}
