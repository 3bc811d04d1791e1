/*
 * DOP853: Dormand–Prince 8(5,3), its error estimate from the embedded 5th- and
 * 3rd-order solutions, the step-size controller with Hairer's DOP853 defaults and the
 * 7th-order continuous extension (Hairer, Nørsett & Wanner, Solving ODEs I, II.5 and
 * II.10; the coefficients are Hairer's, as also published with scipy's DOP853).
 */
#include "dop853.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { STAGES = 12, FSAL = 12, STAGES_DENSE = 16 };

/* nodes c_s of the stages: 0-11 the method's, 12 the new point (FSAL), 13-15 the
   continuous extension's */
static const double C[STAGES_DENSE] = {
    0, 0.05260015195876773, 0.078900227938151601, 0.1183503419072274,
    0.28164965809277259, 0.33333333333333331, 0.25, 0.30769230769230771,
    0.6512820512820513, 0.59999999999999998, 0.8571428571428571, 1,
    1, 0.10000000000000001, 0.20000000000000001, 0.77777777777777779};
/* a_sj: stage s's argument is x + h sum_j a_sj k_j; row 12 is the 8th-order solution */
static const double A[STAGES_DENSE][STAGES_DENSE] = {
    [1] = {[0] = 0.05260015195876773},
    [2] = {[0] = 0.0197250569845379, [1] = 0.059175170953613701},
    [3] = {[0] = 0.029587585476806851, [2] = 0.088762756430420545},
    [4] = {[0] = 0.24136513415926669, [2] = -0.88454947932828609, [3] = 0.92483400326179199},
    [5] = {[0] = 0.037037037037037035, [3] = 0.17082860872947386, [4] = 0.12546768756682242},
    [6] = {[0] = 0.037109375, [3] = 0.17025221101954405, [4] = 0.060216538980455959, [5] = -0.017578125},
    [7] = {[0] = 0.037092000118504789, [3] = 0.17038392571223998, [4] = 0.10726203044637328, [5] = -0.015319437748624402, [6] = 0.0082737891638140233},
    [8] = {[0] = 0.62411095871607569, [3] = -3.3608926294469414, [4] = -0.86821934684172597, [5] = 27.59209969944671, [6] = 20.154067550477894, [7] = -43.489884181069961},
    [9] = {[0] = 0.47766253643826434, [3] = -2.4881146199716677, [4] = -0.59029082683684297, [5] = 21.230051448181193, [6] = 15.279233632882423, [7] = -33.288210968984863, [8] = -0.020331201708508627},
    [10] = {[0] = -0.9371424300859873, [3] = 5.1863724288440638, [4] = 1.0914373489967295, [5] = -8.1497870107469268, [6] = -18.520065659996959, [7] = 22.739487099350505, [8] = 2.4936055526796523, [9] = -3.0467644718982196},
    [11] = {[0] = 2.273310147516538, [3] = -10.534495466737249, [4] = -2.0008720582248625, [5] = -17.958931863118799, [6] = 27.94888452941996, [7] = -2.8589982771350235, [8] = -8.8728569335306293, [9] = 12.360567175794303, [10] = 0.64339274601576357},
    [12] = {[0] = 0.054293734116568765, [5] = 4.4503128927524092, [6] = 1.8915178993145003, [7] = -5.8012039600105849, [8] = 0.3111643669578199, [9] = -0.15216094966251609, [10] = 0.20136540080403034, [11] = 0.044710615727772587},
    [13] = {[0] = 0.056167502283047954, [6] = 0.25350021021662483, [7] = -0.2462390374708025, [8] = -0.12419142326381637, [9] = 0.15329179827876568, [10] = 0.0082010522956346907, [11] = 0.0075678976605456994, [12] = -0.0082979999999999998},
    [14] = {[0] = 0.031834648163502142, [5] = 0.028300909672366776, [6] = 0.053541988307438566, [7] = -0.054923748571390991, [10] = -0.00010834732869724932, [11] = 0.00038257109083565839, [12] = -0.00034046500868740456, [13] = 0.1413124436746325},
    [15] = {[0] = -0.42889630158379194, [5] = -4.697621415361164, [6] = 7.6834211960625991, [7] = 4.0689898183971103, [8] = 0.35672718745528109, [12] = -0.0013990241651590145, [13] = 2.9475147891527724, [14] = -9.1509584721798696},
};
/* the error estimators: the 5th-order embedded solution's and the 3rd-order one's
   differences from the 8th-order solution, per h */
static const double E5[STAGES] = {[0] = 0.01312004499419488, [5] = -1.2251564463762044, [6] = -0.4957589496572502, [7] = 1.6643771824549864, [8] = -0.35032884874997366, [9] = 0.33417911871301748, [10] = 0.08192320648511571, [11] = -0.022355307863886294};
static const double E3[STAGES] = {[0] = -0.18980075407240762, [5] = 4.4503128927524092, [6] = 1.8915178993145003, [7] = -5.8012039600105849, [8] = -0.42268232132379191, [9] = -0.15216094966251609, [10] = 0.20136540080403034, [11] = 0.022651792198360821};
/* the continuous extension's coefficients of its 4th to 7th powers */
static const double D[4][STAGES_DENSE] = {
    {[0] = -8.4289382761090135, [5] = 0.56671495351937773, [6] = -3.0689499459498917, [7] = 2.3846676565120699, [8] = 2.1170345824450281, [9] = -0.87139158377797299, [10] = 2.2404374302607883, [11] = 0.63157877876946877, [12] = -0.088990336451333307, [13] = 18.148505520854727, [14] = -9.194632392478356, [15] = -4.4360363875948936},
    {[0] = 10.427508642579134, [5] = 242.28349177525817, [6] = 165.20045171727028, [7] = -374.5467547226902, [8] = -22.113666853125306, [9] = 7.7334326684722638, [10] = -30.674084731089398, [11] = -9.3321305264302286, [12] = 15.697238121770845, [13] = -31.139403219565178, [14] = -9.3529243588444793, [15] = 35.816841486394082},
    {[0] = 19.985053242002433, [5] = -387.03730874935178, [6] = -189.17813819516758, [7] = 527.80815920542364, [8] = -11.573902539959629, [9] = 6.8812326946963003, [10] = -1.0006050966910838, [11] = 0.77771377980534429, [12] = -2.7782057523535082, [13] = -60.196695231264123, [14] = 84.320405506677162, [15] = 11.992291136182789},
    {[0] = -25.69393346270375, [5] = -154.18974869023643, [6] = -231.5293791760455, [7] = 357.63911791061412, [8] = 93.405324183624316, [9] = -37.458323136451632, [10] = 104.0996495089623, [11] = 29.840293426660502, [12] = -43.533456590011141, [13] = 96.324553959188279, [14] = -39.177261675615441, [15] = -149.72683625798564},
};

/* step-size controller: Hairer's DOP853 defaults (no PI term: beta = 0) */
static const double SAFE = 0.9;
static const double FAC_MIN = 1.0 / 3.0; /* h may shrink at most by 3 */
static const double FAC_MAX = 6.0;       /* and grow at most by 6 per step */
static const double EXPONENT = 1.0 / 8.0;

int eng_dop853_alloc(eng_dop853 *s, int n)
{
    int i;
    size_t len = (size_t)(n > 0 ? n : 1);
    memset(s, 0, sizeof *s);
    s->n = n;
    for (i = 0; i < STAGES_DENSE; i++)
        if (!(s->k[i] = calloc(len, sizeof(double)))) goto fail;
    for (i = 0; i < 8; i++)
        if (!(s->r[i] = calloc(len, sizeof(double)))) goto fail;
    if (!(s->xs = calloc(len, sizeof(double))) || !(s->xn = calloc(len, sizeof(double))))
        goto fail;
    eng_dop853_reset(s);
    return 0;
fail:
    eng_dop853_free(s);
    return -1;
}

void eng_dop853_free(eng_dop853 *s)
{
    int i;
    for (i = 0; i < STAGES_DENSE; i++) { free(s->k[i]); s->k[i] = NULL; }
    for (i = 0; i < 8; i++) { free(s->r[i]); s->r[i] = NULL; }
    free(s->xs); s->xs = NULL;
    free(s->xn); s->xn = NULL;
}

void eng_dop853_restart(eng_dop853 *s) { s->fsal_valid = 0; }

void eng_dop853_reset(eng_dop853 *s)
{
    s->fsal_valid = 0;
    s->dense_ready = 0;
    s->h_guess = 0.0;
    s->t_old = 0.0;
    s->h_old = 0.0;
}

static int all_finite(const double *v, int n)
{
    int i;
    for (i = 0; i < n; i++) if (!isfinite(v[i])) return 0;
    return 1;
}

static int eval(eng_dop853 *s, mf_rhs_fn f, void *ctx, double t, const double *x, double *dx)
{
    s->n_rhs++;
    return f(ctx, t, x, dx) == 0 && all_finite(dx, s->n);
}

/* out = x + h sum_j a[j] k[j] over the stages before `stage` (a[] mostly zeros) */
static void combine(const eng_dop853 *s, double *const *k, const double *a, int stage,
                    double h, const double *x, double *out)
{
    int i, j;
    memcpy(out, x, (size_t)s->n * sizeof(double));
    for (j = 0; j < stage; j++) {
        const double ha = h * a[j];
        if (a[j] == 0.0) continue;
        for (i = 0; i < s->n; i++) out[i] += ha * k[j][i];
    }
}

/* Hairer's stiffness test, as DOPRI5's: two slopes at t0 + h, the last stage's and the
   new point's, over their arguments' distance */
static double stiffness_estimate(const eng_dop853 *s, double h)
{
    double num = 0.0, den = 0.0;
    int i;
    for (i = 0; i < s->n; i++) {
        double df = s->k[FSAL][i] - s->k[STAGES - 1][i], dx = s->xn[i] - s->xs[i];
        num += df * df;
        den += dx * dx;
    }
    return den > 0.0 ? h * sqrt(num / den) : 0.0;
}

/* Hairer's error norm: the 5th-order estimate, damped where the 3rd-order one is much
   larger (so that the norm behaves as h^8 where both are resolved) */
static double error_norm(const eng_dop853 *s, const double *x, double h, double rtol)
{
    double err5 = 0.0, err3 = 0.0, deno;
    int i, j;
    for (i = 0; i < s->n; i++) {
        double e5 = 0.0, e3 = 0.0;
        const double sc = rtol + rtol * fmax(fabs(x[i]), fabs(s->xn[i]));
        for (j = 0; j < STAGES; j++) {
            e5 += E5[j] * s->k[j][i];
            e3 += E3[j] * s->k[j][i];
        }
        err5 += (e5 / sc) * (e5 / sc);
        err3 += (e3 / sc) * (e3 / sc);
    }
    deno = err5 + 0.01 * err3;
    if (!(deno > 0.0)) deno = 1.0;
    return fabs(h) * err5 * sqrt(1.0 / (s->n * deno));
}

mf_dopri_result eng_dop853_step(eng_dop853 *s, mf_rhs_fn f, void *ctx, double *t, double *x,
                                double t_end, double rtol, double h_initial)
{
    const int n = s->n;
    const double t0 = *t;
    const double h_min = MF_MIN_STEP(t0);
    double h = s->h_guess > 0.0 ? s->h_guess : h_initial;
    int rejected = 0;
    int rhs_failed = 0; /* the last rejection was a failed evaluation, not the error estimate */
    int i, stage;

    s->dense_ready = 0;
    if (n == 0) {
        s->t_old = t0;
        s->h_old = t_end - t0;
        s->dense_ready = 1;
        *t = t_end;
        return MF_DOPRI_OK;
    }
    if (!s->fsal_valid) {
        if (!eval(s, f, ctx, t0, x, s->k[0])) return MF_DOPRI_RHS_FAILED;
        s->fsal_valid = 1;
    }
    if (t_end - t0 < h_min) {
        /* a sliver: one explicit Euler step, as mf_dopri_step takes (its line is the
           whole continuous extension) */
        const double hh = t_end - t0;
        for (i = 0; i < n; i++)
            if (!isfinite(x[i] + hh * s->k[0][i])) return MF_DOPRI_RHS_FAILED;
        for (i = 0; i < 8; i++) memset(s->r[i], 0, (size_t)n * sizeof(double));
        for (i = 0; i < n; i++) {
            s->r[0][i] = x[i];
            s->r[1][i] = hh * s->k[0][i];
            x[i] += s->r[1][i];
        }
        s->t_old = t0;
        s->h_old = hh;
        s->dense_ready = 1;
        *t = t_end;
        s->fsal_valid = 0;
        return MF_DOPRI_OK;
    }
    if (!(h > 0.0) || !isfinite(h)) h = t_end - t0;

    for (;;) {
        double err, fac11;
        int clamped = 0, ok = 1;

        if (h * 1.01 >= t_end - t0) { /* land exactly on t_end */
            h = t_end - t0;
            clamped = 1;
        }
        if (h < h_min) return rhs_failed ? MF_DOPRI_RHS_FAILED : MF_DOPRI_STEP_UNDERFLOW;

        for (stage = 1; stage < STAGES && ok; stage++) {
            combine(s, s->k, A[stage], stage, h, x, s->xs);
            ok = eval(s, f, ctx, t0 + C[stage] * h, s->xs, s->k[stage]);
        }
        if (ok) {
            combine(s, s->k, A[FSAL], STAGES, h, x, s->xn);
            /* a finite slope at an overflowed point would pass the error test */
            ok = all_finite(s->xn, n) && eval(s, f, ctx, t0 + h, s->xn, s->k[FSAL]);
        }
        if (!ok) { /* a trial point outside the model's domain: closer to the valid one */
            s->n_rejected++;
            rejected = rhs_failed = 1;
            h *= 0.25;
            continue;
        }
        err = error_norm(s, x, h, rtol);
        if (!isfinite(err)) {
            s->n_rejected++;
            rejected = rhs_failed = 1;
            h *= 0.25;
            continue;
        }
        fac11 = pow(err, EXPONENT);
        if (err <= 1.0) {
            double fac = fmax(1.0 / FAC_MAX, fmin(1.0 / FAC_MIN, fac11 / SAFE));
            double hnew = h / fac, *tmp;
            if (rejected) hnew = fmin(hnew, h);
            s->h_lambda = stiffness_estimate(s, h);
            /* the extension's cubic Hermite part (the ends' values and slopes); the rest
               is eng_dop853_dense_prepare's, zero until then */
            for (i = 0; i < n; i++) {
                const double dx = s->xn[i] - x[i];
                s->r[0][i] = x[i];
                s->r[1][i] = dx;
                s->r[2][i] = h * s->k[0][i] - dx;
                s->r[3][i] = 2.0 * dx - h * (s->k[FSAL][i] + s->k[0][i]);
                x[i] = s->xn[i];
            }
            for (i = 4; i < 8; i++) memset(s->r[i], 0, (size_t)n * sizeof(double));
            s->t_old = t0;
            s->h_old = h;
            *t = clamped ? t_end : t0 + h;
            /* FSAL: the new point's slope is the next step's first stage; the old one
               stays in k[12] for the continuous extension */
            tmp = s->k[0];
            s->k[0] = s->k[FSAL];
            s->k[FSAL] = tmp;
            s->h_guess = clamped ? fmax(hnew, s->h_guess) : hnew;
            return MF_DOPRI_OK;
        }
        s->n_rejected++;
        rejected = 1;
        rhs_failed = 0;
        h = h / fmin(1.0 / FAC_MIN, fac11 / SAFE);
    }
}

int eng_dop853_dense_prepare(eng_dop853 *s, mf_rhs_fn f, void *ctx)
{
    const int n = s->n;
    const double h = s->h_old;
    const double *x0 = s->r[0];
    /* the stages in the tableau's order: after the FSAL swap the old point's slope is in
       k[12] and the new point's in k[0] */
    double *k[STAGES_DENSE];
    int i, j, stage;
    if (s->dense_ready) return 0;
    memcpy(k, s->k, sizeof k);
    k[0] = s->k[FSAL];
    k[FSAL] = s->k[0];
    for (stage = FSAL + 1; stage < STAGES_DENSE; stage++) {
        combine(s, k, A[stage], stage, h, x0, s->xs);
        if (!eval(s, f, ctx, s->t_old + C[stage] * h, s->xs, k[stage])) return -1;
    }
    for (j = 0; j < 4; j++) {
        double *r = s->r[4 + j];
        for (stage = 0; stage < STAGES_DENSE; stage++) {
            const double hd = h * D[j][stage];
            if (D[j][stage] == 0.0) continue;
            for (i = 0; i < n; i++) r[i] += hd * k[stage][i];
        }
    }
    s->dense_ready = 1;
    return 0;
}

static double dense_theta(const eng_dop853 *s, double t)
{
    return s->h_old > 0.0 ? (t - s->t_old) / s->h_old : 1.0;
}

static double dense_component(const eng_dop853 *s, double theta, int i)
{
    const double theta1 = 1.0 - theta;
    double y = s->r[7][i] * theta;
    y = (y + s->r[6][i]) * theta1;
    y = (y + s->r[5][i]) * theta;
    y = (y + s->r[4][i]) * theta1;
    y = (y + s->r[3][i]) * theta;
    y = (y + s->r[2][i]) * theta1;
    y = (y + s->r[1][i]) * theta;
    return s->r[0][i] + y;
}

void eng_dop853_dense(const eng_dop853 *s, double t, double *x)
{
    int i;
    double theta;
    if (s->n == 0) return;
    theta = dense_theta(s, t);
    for (i = 0; i < s->n; i++) x[i] = dense_component(s, theta, i);
}

double eng_dop853_dense_one(const eng_dop853 *s, double t, int i)
{
    return dense_component(s, dense_theta(s, t), i);
}
