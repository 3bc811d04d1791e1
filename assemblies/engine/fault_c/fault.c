/*
 * The Burridge-Knopoff chain (issue 30), event by event: work proportional to motion.
 *
 * n blocks of mass m on a fixed rough surface, each pulled by a leaf spring kp from a
 * plate at V t and coupled to its neighbours by springs kc (free ends). Friction is
 * Carlson & Langer's velocity weakening with exact Coulomb modes, as the component
 * components/translational/fault_block.py writes it: stuck (v = 0 exactly) while the
 * applied force A_i stays within +-F_i; sliding with q = sign(v), the friction is
 * -q F_i (1 - sigma) / (1 + 2 alpha q v / ((1 - sigma) v_w)); a slide ends where v
 * reaches 0 (stuck again if |A_i| <= F_i there, else it slides the other way).
 *
 * Why it is fast: a stuck block does not move, so while its neighbours are stuck too its
 * applied force is B_i + kp V t with B_i constant, and it breaks away at the closed-form
 * time (F_i - B_i) / (kp V). Those times sit in a min segment tree (O(log n) per
 * change); the earliest is the next event of the quiet chain, found, not searched for.
 * Only sliding blocks are integrated (DOPRI5 of the FMU runtime, error-controlled,
 * atol = rtol = tol on the slip within a step and on the velocity), and only the stuck
 * neighbours of sliding blocks are watched, with indicators located by the runtime's
 * event location on the dense output. A step never passes the earliest closed-form
 * break-away of the blocks outside that neighbourhood.
 *
 * Energy is kept as three independent quantities so that their balance is a check:
 * the plate's work (kp V times the integral of the leaf stretch: closed form for stuck
 * blocks, a quadrature for sliding ones), the friction dissipation (a quadrature of
 * friction power per sliding block) and the stored energy (from the state at the ends).
 *
 * A slip event is a space-time connected cluster of sliding: a block that breaks away on
 * its own (its closed-form time) opens a new event, one pushed over its threshold by a
 * sliding neighbour joins that neighbour's event (two events that meet are merged);
 * an event ends when its last block sticks.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <stdio.h>

#include "events.h"
#include "solver.h"

#define EXPORT __attribute__((visibility("default")))

/* parameters, in the order par[] carries them */
enum { P_M, P_KC, P_KP, P_V, P_SIGMA, P_ALPHA, P_VW, P_TOL, P_TSTOP, P_COUNT };
/* totals[], what the run reports beyond the catalogue */
enum { T_TIME, T_PLATE_WORK, T_DISSIPATED, T_E_START, T_E_END, T_STEPS, T_REJECTED,
       T_RHS, T_BLOCK_RHS, T_LOCATED, T_BREAKAWAYS, T_SLIPS_DROPPED, T_STATUS, T_CREATED,
       T_SLIDES, T_COUNT };
/* T_STATUS: 0 stop time reached, 1 max_events reached, 2 catalogue full, 3 every block
   stuck for good (the plate still) */

typedef struct {
    int n;
    double m, kc, kp, V, sigma, alpha, vw, tol;
    const double *F;
    double *x, *v, *xs; /* xs: stage positions for sliding blocks, x for stuck ones */
    int *q;             /* -1, 0, +1 */
    int *mov, *pos;     /* sliding blocks, and each block's index there (-1 stuck) */
    int nm;
    int *watch, *wmark, nw; /* stuck neighbours of sliding blocks */
    int wstamp;
    /* segment tree of closed-form break-away times of the other stuck blocks */
    int P;
    double *tmin;
    int *targ;
    /* events */
    int *label;          /* event of a sliding block */
    int *last_ev;        /* the event a block last joined (-1 none) */
    double *seg_x, *seg_t;
    int *parent, *active;
    double *ev_start, *ev_end, *ev_moment, *ev_energy;
    int *ev_blocks, *ev_first;
    long cap, created, completed, max_events;
    int *sl_event, *sl_block;
    double *sl_t0, *sl_t1, *sl_slip;
    long sl_cap, sl_count, sl_dropped;
    double *slept, *stuck_since;
    double X_st;  /* sum of x over stuck blocks */
    int n_st;
    /* integration */
    mf_dopri s;
    double *y, *yd, *z_ref, *z_b, *z_ev, *work;
    int *todo, *dir; /* crossings found at one event */
    double W, D, D_c, W_c; /* Kahan sums */
    double block_rhs;
} bk;

static void kahan(double *sum, double *c, double add)
{
    double yv = add - *c, t = *sum + yv;
    *c = (t - *sum) - yv;
    *sum = t;
}

static double coupling(const bk *b, const double *xs, int i)
{
    double f = 0.0;
    if (i > 0) f += xs[i - 1] - xs[i];
    if (i + 1 < b->n) f += xs[i + 1] - xs[i];
    return b->kc * f;
}

/* kinetic friction magnitude at slip speed w (q v, >= 0 while sliding; the law's smooth
   continuation a little below 0 inside a step that overshoots the stop) */
static double kinetic(const bk *b, int i, double w)
{
    double den = 1.0 + 2.0 * b->alpha * w / ((1.0 - b->sigma) * b->vw);
    return b->F[i] * (1.0 - b->sigma) / fmax(den, 0.5);
}

/* ---- segment tree: earliest closed-form break-away among quiet stuck blocks ---- */
static void tree_set(bk *b, int i, double t)
{
    int k = b->P + i;
    b->tmin[k] = t;
    b->targ[k] = i;
    for (k /= 2; k >= 1; k /= 2) {
        int l = 2 * k, r = 2 * k + 1;
        int pick = b->tmin[l] <= b->tmin[r] ? l : r;
        b->tmin[k] = b->tmin[pick];
        b->targ[k] = b->targ[pick];
    }
}

static int sliding(const bk *b, int i) { return i >= 0 && i < b->n && b->q[i] != 0; }

/* a stuck block with no sliding neighbour: A_i(t) = B_i + kp V t, so it breaks away at
   (F_i - B_i) / (kp V); any other block is watched or integrated instead */
static void tree_update(bk *b, int i)
{
    double t = INFINITY;
    if (i < 0 || i >= b->n) return;
    if (b->q[i] == 0 && !sliding(b, i - 1) && !sliding(b, i + 1) && b->kp * b->V > 0.0) {
        double B = coupling(b, b->x, i) - b->kp * b->x[i];
        t = (b->F[i] - B) / (b->kp * b->V);
    }
    tree_set(b, i, t);
}

static int find(bk *b, int e)
{
    while (b->parent[e] != e) {
        b->parent[e] = b->parent[b->parent[e]];
        e = b->parent[e];
    }
    return e;
}

static double stored_energy(const bk *b, double t)
{
    double e = 0.0;
    int i;
    for (i = 0; i < b->n; i++) {
        double leaf = b->x[i] - b->V * t;
        e += 0.5 * b->kp * leaf * leaf + 0.5 * b->m * b->v[i] * b->v[i];
        if (i + 1 < b->n) {
            double d = b->x[i + 1] - b->x[i];
            e += 0.5 * b->kc * d * d;
        }
    }
    return e;
}

/* block i starts to slide in direction dir at time t, in event e (a new one if e < 0);
   returns 0, or -1 when a new event is needed and the catalogue is full */
static int start_slide(bk *b, int i, int dir, double t, int e)
{
    if (e < 0) {
        if (b->created >= b->cap) return -1;
        e = (int)b->created++;
        b->parent[e] = e;
        b->active[e] = 0;
        b->ev_start[e] = t;
        b->ev_end[e] = NAN;
        b->ev_moment[e] = b->ev_energy[e] = 0.0;
        b->ev_blocks[e] = 0;
        b->ev_first[e] = i;
    }
    e = find(b, e);
    b->q[i] = dir;
    b->v[i] = 0.0;
    b->label[i] = e;
    b->active[e]++;
    if (b->last_ev[i] < 0 || find(b, b->last_ev[i]) != e) b->ev_blocks[e]++;
    b->last_ev[i] = e;
    b->seg_x[i] = b->x[i];
    b->seg_t[i] = t;
    b->slept[i] += t - b->stuck_since[i];
    b->pos[i] = b->nm;
    b->mov[b->nm++] = i;
    b->X_st -= b->x[i];
    b->n_st--;
    tree_update(b, i - 1);
    tree_update(b, i);
    tree_update(b, i + 1);
    return 0;
}

static void stick(bk *b, int i, double t)
{
    int e = find(b, b->label[i]), k = b->pos[i], last = b->mov[b->nm - 1];
    double slip = b->x[i] - b->seg_x[i];
    b->ev_moment[e] += slip;
    if (b->sl_count < b->sl_cap) {
        long s = b->sl_count++;
        b->sl_event[s] = e;
        b->sl_block[s] = i;
        b->sl_t0[s] = b->seg_t[i];
        b->sl_t1[s] = t;
        b->sl_slip[s] = slip;
    } else {
        b->sl_dropped++;
    }
    b->q[i] = 0;
    b->v[i] = 0.0;
    b->mov[k] = last;
    b->pos[last] = k;
    b->pos[i] = -1;
    b->nm--;
    b->stuck_since[i] = t;
    b->X_st += b->x[i];
    b->n_st++;
    if (--b->active[e] == 0) {
        b->ev_end[e] = t;
        b->completed++;
    }
    tree_update(b, i - 1);
    tree_update(b, i);
    tree_update(b, i + 1);
}

/* the event a block pushed over its threshold joins: its sliding neighbours' (merged) */
static int neighbour_event(bk *b, int j)
{
    int e = -1, k;
    for (k = -1; k <= 1; k += 2) {
        int i = j + k, f;
        if (!sliding(b, i)) continue;
        f = find(b, b->label[i]);
        if (e < 0) e = f;
        else if (f != e) { /* two events meet: the earlier absorbs the later */
            int keep = e < f ? e : f, gone = e < f ? f : e;
            b->parent[gone] = keep;
            b->active[keep] += b->active[gone];
            b->ev_moment[keep] += b->ev_moment[gone];
            b->ev_energy[keep] += b->ev_energy[gone];
            b->ev_blocks[keep] += b->ev_blocks[gone];
            b->ev_blocks[gone] = -1; /* merged: not an event of its own */
            e = keep;
        }
    }
    return e;
}

/* y = [slip within the step (nm), v (nm), friction work within the step (nm), plate work
   on sliding blocks within the step] */
static int rhs(void *ctx, double t, const double *y, double *dy)
{
    bk *b = (bk *)ctx;
    const int nm = b->nm;
    double P = 0.0;
    int k;
    for (k = 0; k < nm; k++) b->xs[b->mov[k]] = b->x[b->mov[k]] + y[k];
    for (k = 0; k < nm; k++) {
        int i = b->mov[k], q = b->q[i];
        double v = y[nm + k], stretch = b->V * t - b->xs[i];
        double fr = q * kinetic(b, i, q * v);
        dy[k] = v;
        dy[nm + k] = (coupling(b, b->xs, i) + b->kp * stretch - fr) / b->m;
        dy[2 * nm + k] = fr * v;
        P += b->kp * b->V * stretch;
    }
    dy[3 * nm] = P;
    b->block_rhs += nm;
    return 0;
}

static void build_watch(bk *b)
{
    int k, d;
    b->nw = 0;
    b->wstamp++;
    for (k = 0; k < b->nm; k++)
        for (d = -1; d <= 1; d += 2) {
            int j = b->mov[k] + d;
            if (j < 0 || j >= b->n || b->q[j] != 0 || b->wmark[j] == b->wstamp) continue;
            b->wmark[j] = b->wstamp;
            b->watch[b->nw++] = j;
        }
}

/* indicators at state y: q v per sliding block, then F - A and F + A per watched block */
static void indicators_at(bk *b, double t, const double *y, double *z)
{
    const int nm = b->nm;
    int k;
    for (k = 0; k < nm; k++) {
        int i = b->mov[k];
        b->xs[i] = b->x[i] + y[k];
        z[k] = b->q[i] * y[nm + k];
    }
    for (k = 0; k < b->nw; k++) {
        int j = b->watch[k];
        double A = coupling(b, b->xs, j) + b->kp * (b->V * t - b->x[j]);
        z[nm + 2 * k] = b->F[j] - A;
        z[nm + 2 * k + 1] = b->F[j] + A;
    }
}

static int indicators_dense(void *ctx, double t, double *z)
{
    bk *b = (bk *)ctx;
    mf_dopri_dense(&b->s, t, b->yd);
    indicators_at(b, t, b->yd, z);
    return 0;
}

/* fold a step's (or a part step's) increments into the blocks and the sums */
static void commit(bk *b, double *y)
{
    const int nm = b->nm;
    int k;
    for (k = 0; k < nm; k++) {
        int i = b->mov[k];
        double w = y[2 * nm + k];
        b->x[i] += y[k];
        b->xs[i] = b->x[i];
        b->v[i] = y[nm + k];
        b->ev_energy[find(b, b->label[i])] += w;
        kahan(&b->D, &b->D_c, w);
        y[k] = 0.0;
        y[2 * nm + k] = 0.0;
    }
    kahan(&b->W, &b->W_c, y[3 * nm]);
    y[3 * nm] = 0.0;
}

/* plate work on the stuck blocks over [ta, tb]: their stretch is n_st V t - X_st */
static void stuck_work(bk *b, double ta, double tb)
{
    double h = tb - ta, S = b->n_st * b->V * ta - b->X_st;
    kahan(&b->W, &b->W_c, b->kp * b->V * (S * h + 0.5 * b->n_st * b->V * h * h));
}

static void load_y(bk *b)
{
    const int nm = b->nm;
    int k;
    for (k = 0; k < nm; k++) {
        b->y[k] = 0.0;
        b->y[nm + k] = b->v[b->mov[k]];
        b->y[2 * nm + k] = 0.0;
    }
    b->y[3 * nm] = 0.0;
    b->s.n = 3 * nm + 1;
    mf_dopri_restart(&b->s);
}

/* a block whose velocity reached 0: stuck, or, if its force is still beyond the static
   threshold there, sliding on from rest (the other way, or the same) in the same event */
static void stopped(bk *b, int i, double t)
{
    double A = coupling(b, b->x, i) + b->kp * (b->V * t - b->x[i]);
    b->v[i] = 0.0;
    if (A >= b->F[i]) b->q[i] = 1;
    else if (A <= -b->F[i]) b->q[i] = -1;
    else stick(b, i, t);
}

static void *grab(size_t count, size_t size, int *failed)
{
    void *p = calloc(count ? count : 1, size);
    if (!p) *failed = 1;
    return p;
}

/*
 * Run the chain from x (stuck, v = 0) until par[P_TSTOP] or max_events completed events.
 * Arrays ev_* hold cap events, sl_* sl_cap slide segments; slept[n] the time each
 * block was stuck. x is updated to the final positions. Returns 0, or -1 with msg.
 */
EXPORT int mf_fault_run(int n, const double *par, const double *F, double *x,
                        long max_events, long cap, double *ev_start, double *ev_end,
                        double *ev_moment, double *ev_energy, int *ev_blocks, int *ev_first,
                        long sl_cap, int *sl_event, int *sl_block, double *sl_t0,
                        double *sl_t1, double *sl_slip, double *slept, double *totals,
                        long max_steps, char *msg, int msg_len)
{
    bk b;
    int failed = 0, i, status = 0, rc = 0;
    long steps = 0;
    double t = 0.0, t_stop = par[P_TSTOP];
    size_t dim;

    memset(&b, 0, sizeof b);
    if (n < 1 || n > 50000000 || cap < 1 || sl_cap < 0) {
        snprintf(msg, (size_t)msg_len, "fault: n must be in 1..5e7 and the catalogue hold "
                 "at least one event (n = %d, capacity %ld)", n, cap);
        return -1;
    }
    b.n = n;
    b.m = par[P_M]; b.kc = par[P_KC]; b.kp = par[P_KP]; b.V = par[P_V];
    b.sigma = par[P_SIGMA]; b.alpha = par[P_ALPHA]; b.vw = par[P_VW]; b.tol = par[P_TOL];
    b.F = F; b.x = x; b.cap = cap; b.max_events = max_events;
    b.ev_start = ev_start; b.ev_end = ev_end; b.ev_moment = ev_moment;
    b.ev_energy = ev_energy; b.ev_blocks = ev_blocks; b.ev_first = ev_first;
    b.sl_cap = sl_cap; b.sl_event = sl_event; b.sl_block = sl_block; b.sl_t0 = sl_t0;
    b.sl_t1 = sl_t1; b.sl_slip = sl_slip; b.slept = slept;
    for (b.P = 1; b.P < n; b.P *= 2) {}
    dim = 3 * (size_t)n + 1;
    b.v = grab((size_t)n, sizeof(double), &failed);
    b.xs = grab((size_t)n, sizeof(double), &failed);
    b.q = grab((size_t)n, sizeof(int), &failed);
    b.mov = grab((size_t)n, sizeof(int), &failed);
    b.pos = grab((size_t)n, sizeof(int), &failed);
    b.watch = grab((size_t)n, sizeof(int), &failed);
    b.wmark = grab((size_t)n, sizeof(int), &failed);
    b.tmin = grab(2 * (size_t)b.P, sizeof(double), &failed);
    b.targ = grab(2 * (size_t)b.P, sizeof(int), &failed);
    b.label = grab((size_t)n, sizeof(int), &failed);
    b.last_ev = grab((size_t)n, sizeof(int), &failed);
    b.seg_x = grab((size_t)n, sizeof(double), &failed);
    b.seg_t = grab((size_t)n, sizeof(double), &failed);
    b.stuck_since = grab((size_t)n, sizeof(double), &failed);
    b.parent = grab((size_t)cap, sizeof(int), &failed);
    b.active = grab((size_t)cap, sizeof(int), &failed);
    b.y = grab(dim, sizeof(double), &failed);
    b.yd = grab(dim, sizeof(double), &failed);
    /* indicators: one per sliding block, two per watched one: at most 3n */
    b.z_ref = grab(3 * (size_t)n, sizeof(double), &failed);
    b.z_b = grab(3 * (size_t)n, sizeof(double), &failed);
    b.z_ev = grab(3 * (size_t)n, sizeof(double), &failed);
    b.todo = grab(3 * (size_t)n, sizeof(int), &failed);
    b.dir = grab(3 * (size_t)n, sizeof(int), &failed);
    b.work = grab(MF_LOCATE_WORK(3 * (size_t)n, 4), sizeof(double), &failed);
    if (!failed && mf_dopri_alloc(&b.s, (int)dim) != 0) failed = 1;
    if (failed) {
        snprintf(msg, (size_t)msg_len, "fault: out of memory for %d blocks", n);
        rc = -1;
        goto done;
    }
    for (i = 0; i < 2 * b.P; i++) b.tmin[i] = INFINITY;
    for (i = 0; i < n; i++) {
        b.xs[i] = x[i];
        b.pos[i] = -1;
        b.last_ev[i] = -1;
        b.X_st += x[i];
        slept[i] = 0.0;
    }
    b.n_st = n;
    for (i = 0; i < n; i++) tree_update(&b, i);
    totals[T_E_START] = stored_energy(&b, 0.0);
    /* blocks already at or past their thresholds at t = 0 start at once */
    for (i = 0; i < n; i++) {
        double A = coupling(&b, b.x, i) - b.kp * b.x[i];
        if (fabs(A) >= F[i] && start_slide(&b, i, A > 0 ? 1 : -1, 0.0,
                                           neighbour_event(&b, i)) != 0) {
            status = 2;
            goto finish;
        }
    }
    load_y(&b);

    while (t < t_stop) {
        if (++steps > max_steps) {
            snprintf(msg, (size_t)msg_len, "fault: more than %ld steps before t = %g (at t = "
                     "%.9g, %d blocks sliding): raise max_steps or shorten the run",
                     max_steps, t_stop, t, b.nm);
            rc = -1;
            goto finish;
        }
        if (b.nm == 0) {
            /* every block stuck: jump to the earliest closed-form break-away */
            double tb = b.tmin[1];
            int j = b.targ[1];
            if (b.completed >= max_events) { status = 1; break; }
            if (!isfinite(tb) && !isfinite(t_stop)) { status = 3; break; } /* nothing moves */
            if (!(tb < t_stop)) { stuck_work(&b, t, t_stop); t = t_stop; break; }
            if (tb < t) tb = t; /* rounding: a threshold met now */
            stuck_work(&b, t, tb);
            t = tb;
            totals[T_BREAKAWAYS] += 1;
            if (start_slide(&b, j, 1, t, -1) != 0) { status = 2; break; }
            load_y(&b);
            continue;
        }
        {
            const int nm = b.nm;
            int nz, found, k;
            double ta = t, t_end = fmin(t_stop, b.tmin[1]), te;
            mf_dopri_result r;
            if (t_end < t) t_end = t;
            build_watch(&b);
            nz = nm + 2 * b.nw;
            indicators_at(&b, t, b.y, b.z_ref);
            r = mf_dopri_step(&b.s, rhs, &b, &t, b.y, t_end, b.tol, 1e-3);
            if (r != MF_DOPRI_OK) {
                snprintf(msg, (size_t)msg_len, "fault: the slide could not be integrated at "
                         "t = %.9g (%s, %d blocks sliding)", ta, r == MF_DOPRI_STEP_UNDERFLOW
                         ? "step size underflow" : "friction law not finite", nm);
                rc = -1;
                goto finish;
            }
            indicators_at(&b, t, b.y, b.z_b);
            found = mf_locate_event(indicators_dense, &b, nz, ta, b.z_ref, t, b.z_b, 4, &te,
                                    b.z_ev, b.work);
            if (found < 0) {
                snprintf(msg, (size_t)msg_len, "fault: an indicator was not finite at "
                         "t = %.9g", ta);
                rc = -1;
                goto finish;
            }
            if (found) {
                int nhit = 0, err = 0;
                mf_dopri_dense(&b.s, te, b.y);
                t = te;
                totals[T_LOCATED] += 1;
                /* collect every crossing first: the lists change as they are applied */
                for (k = 0; k < nz; k++) {
                    if (!mf_crossed(b.z_ref[k], b.z_ev[k])) continue;
                    if (k < nm) { b.todo[nhit] = b.mov[k]; b.dir[nhit++] = 0; }
                    else {
                        b.todo[nhit] = b.watch[(k - nm) / 2];
                        b.dir[nhit++] = (k - nm) % 2 == 0 ? 1 : -1;
                    }
                }
                commit(&b, b.y);
                stuck_work(&b, ta, t);
                for (k = 0; k < nhit && !err; k++) {
                    int i = b.todo[k];
                    if (b.dir[k] == 0) {
                        if (b.q[i] != 0) stopped(&b, i, t);
                    } else if (b.q[i] == 0) {
                        err = start_slide(&b, i, b.dir[k], t, neighbour_event(&b, i));
                    }
                }
                if (err) { status = 2; break; }
                load_y(&b);
            } else {
                commit(&b, b.y);
                stuck_work(&b, ta, t);
                if (t >= b.tmin[1] && t < t_stop) {
                    int j = b.targ[1];
                    totals[T_BREAKAWAYS] += 1;
                    if (start_slide(&b, j, 1, t, -1) != 0) { status = 2; break; }
                    load_y(&b);
                }
            }
            if (b.nm == 0 && b.completed >= max_events) { status = 1; break; }
        }
    }
finish:
    for (i = 0; i < n; i++)
        if (b.q[i] == 0) slept[i] += t - b.stuck_since[i];
    totals[T_TIME] = t;
    totals[T_PLATE_WORK] = b.W;
    totals[T_DISSIPATED] = b.D;
    totals[T_E_END] = stored_energy(&b, t);
    totals[T_STEPS] = (double)steps;
    totals[T_REJECTED] = (double)b.s.n_rejected;
    totals[T_RHS] = (double)b.s.n_rhs;
    totals[T_BLOCK_RHS] = b.block_rhs;
    totals[T_SLIPS_DROPPED] = (double)b.sl_dropped;
    totals[T_STATUS] = status;
    totals[T_CREATED] = (double)b.created;
    totals[T_SLIDES] = (double)b.sl_count;
done:
    totals[T_STATUS] = status;
    mf_dopri_free(&b.s);
    free(b.v); free(b.xs); free(b.q); free(b.mov); free(b.pos); free(b.watch);
    free(b.wmark); free(b.tmin); free(b.targ); free(b.label); free(b.last_ev);
    free(b.seg_x); free(b.seg_t); free(b.stuck_since); free(b.parent); free(b.active);
    free(b.y); free(b.yd); free(b.z_ref); free(b.z_b); free(b.z_ev); free(b.work);
    free(b.todo); free(b.dir);
    return rc;
}

/* the lengths of par[] and totals[], so that Python and C agree on the layout */
EXPORT int mf_fault_layout(int *p_count, int *t_count)
{
    *p_count = P_COUNT;
    *t_count = T_COUNT;
    return 0;
}
