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
 * event location on the dense output.
 *
 * Sliding blocks are integrated in groups, each on its own clock: a group is a run of
 * sliding blocks with at most one stuck block between neighbours (a stuck block between
 * two sliding ones is watched by both, so they must share a clock). Groups further apart
 * cannot feel each other until a block between them breaks away, so one group's events
 * do not cut another's steps (in a big chain several slide at once: one clock for all
 * would end a step for every block at every block's switch). The loop always advances
 * the earliest clock, the closed-form break-aways included, and applies an event only
 * when its time is the earliest, so events happen in time order. When a break-away
 * brings two groups within one stuck block, the one that has stepped past that time is
 * taken back to it on its last step's dense output (its step began no later than the
 * current time, since only the earliest clock steps) and the two are joined.
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
enum { P_M, P_KC, P_KP, P_V, P_SIGMA, P_ALPHA, P_VW, P_TOL, P_TSTOP, P_BACKWARD, P_COUNT };
/* P_BACKWARD: 1, friction holds both ways (Coulomb, as the component); 0, a block never
   slides backward (Carlson & Langer: the friction for v < 0 is unbounded) */
/* totals[], what the run reports beyond the catalogue */
enum { T_TIME, T_PLATE_WORK, T_DISSIPATED, T_E_START, T_E_END, T_STEPS, T_REJECTED,
       T_RHS, T_BLOCK_RHS, T_LOCATED, T_BREAKAWAYS, T_SLIPS_DROPPED, T_STATUS, T_CREATED,
       T_SLIDES, T_SLIDING, T_COUNT };
/* T_SLIDING: block-seconds of sliding, summed over ended slides: the events' own size in
   space-time, what the work should be proportional to */
/* T_STATUS: 0 stop time reached, 1 max_events reached, 2 catalogue full, 3 every block
   stuck for good (the plate still) */


typedef struct {
    int live;
    int nm, cap;        /* sliding blocks, room */
    int *mov;           /* its sliding blocks */
    double *y, *yd;     /* [slip in the step (nm), v (nm), friction work in the step (nm),
                           plate work on its blocks in the step]: 3 cap + 1 */
    int *hit, *dir;     /* crossings located at t, applied when t is the earliest */
    int nhit;
    mf_dopri s;
    double t;           /* its clock */
    int stepped;        /* y holds a step (or its part up to an event) not yet committed */
    int pending;        /* events located at t wait in hit/dir */
    int fresh;          /* its blocks or their velocities changed: reload y, restart */
} group;

typedef struct {
    int n;
    double m, kc, kp, V, sigma, alpha, vw, tol;
    int backward;
    const double *F;
    double *x, *v, *xs; /* xs: stage positions for sliding blocks, x for stuck ones */
    int *q;             /* -1, 0, +1 */
    int *gid, *pos;     /* a sliding block's group and its index there (-1 stuck) */
    int *watch, *wmark, nw; /* the current group's stuck neighbours */
    int wstamp;
    /* segment tree of closed-form break-away times of the other stuck blocks */
    int P;
    double *tmin;
    int *targ;
    /* groups */
    group *G;
    int ng, gcap, cur;
    int *stack, sp;     /* crossings being applied (nested when groups meet) */
    int *tmp;           /* a group's blocks in order, when it splits */
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
    double t_acc; /* the stuck blocks' plate work is summed up to here */
    int oom;      /* an allocation failed */
    /* integration scratch (one group at a time) */
    double *z_ref, *z_b, *z_ev, *work;
    double W, D, D_c, W_c; /* Kahan sums */
    double block_rhs, steps, rejected, rhs_count;
    double sliding; /* block-seconds of ended slides */
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


/* ---- groups --------------------------------------------------------------------- */
static int group_reserve(bk *b, group *g, int need)
{
    int cap;
    if (need <= g->cap) return 0;
    cap = g->cap * 2 > need ? g->cap * 2 : need;
    if (cap < 4) cap = 4;
    if (cap > b->n) cap = b->n;
    {
        int *mov = realloc(g->mov, (size_t)cap * sizeof(int));
        int *hit = mov ? realloc(g->hit, 3 * (size_t)cap * sizeof(int)) : NULL;
        int *dir;
        double *y, *yd;
        if (mov) g->mov = mov;
        if (hit) g->hit = hit;
        dir = hit ? realloc(g->dir, 3 * (size_t)cap * sizeof(int)) : NULL;
        if (dir) g->dir = dir;
        y = dir ? realloc(g->y, (3 * (size_t)cap + 1) * sizeof(double)) : NULL;
        if (y) g->y = y;
        yd = y ? realloc(g->yd, (3 * (size_t)cap + 1) * sizeof(double)) : NULL;
        if (yd) g->yd = yd;
        if (!yd) { b->oom = 1; return -1; }
    }
    {   /* the solver's buffers: its history goes (a membership change restarts it) */
        double h = g->s.h_guess;
        mf_dopri_free(&g->s);
        if (mf_dopri_alloc(&g->s, 3 * cap + 1) != 0) { b->oom = 1; return -1; }
        g->s.h_guess = h;
    }
    g->cap = cap;
    return 0;
}

static int group_new(bk *b, double t)
{
    int k;
    for (k = 0; k < b->ng; k++)
        if (!b->G[k].live) break;
    if (k == b->ng) {
        if (b->ng == b->gcap) {
            int cap = b->gcap ? 2 * b->gcap : 8;
            group *G = realloc(b->G, (size_t)cap * sizeof(group));
            if (!G) { b->oom = 1; return -1; }
            memset(G + b->gcap, 0, (size_t)(cap - b->gcap) * sizeof(group));
            b->G = G;
            b->gcap = cap;
        }
        b->ng++;
    }
    b->G[k].live = 1;
    b->G[k].nm = 0;
    b->G[k].t = t;
    b->G[k].stepped = b->G[k].pending = 0;
    b->G[k].nhit = 0;
    b->G[k].fresh = 1;
    return k;
}

static int group_add(bk *b, int g, int i)
{
    group *G = &b->G[g];
    if (group_reserve(b, G, G->nm + 1) != 0) return -1;
    b->pos[i] = G->nm;
    b->gid[i] = g;
    G->mov[G->nm++] = i;
    G->fresh = 1;
    return 0;
}

static void group_remove(bk *b, int i)
{
    group *G = &b->G[b->gid[i]];
    int k = b->pos[i], last = G->mov[G->nm - 1];
    G->mov[k] = last;
    b->pos[last] = k;
    b->pos[i] = -1;
    b->gid[i] = -1;
    G->nm--;
    G->fresh = 1;
    if (G->nm == 0) G->live = 0;
}

/* fold a group's uncommitted increments (up to its clock) into the blocks and the sums */
static void commit(bk *b, group *G)
{
    const int nm = G->nm;
    int k;
    if (!G->stepped) return;
    for (k = 0; k < nm; k++) {
        int i = G->mov[k];
        double w = G->y[2 * nm + k];
        b->x[i] += G->y[k];
        b->xs[i] = b->x[i];
        b->v[i] = G->y[nm + k];
        b->ev_energy[find(b, b->label[i])] += w;
        kahan(&b->D, &b->D_c, w);
        G->y[k] = 0.0;
        G->y[2 * nm + k] = 0.0;
    }
    kahan(&b->W, &b->W_c, G->y[3 * nm]);
    G->y[3 * nm] = 0.0;
    G->stepped = 0;
}

static void load(group *G, const bk *b)
{
    const int nm = G->nm;
    int k;
    for (k = 0; k < nm; k++) {
        G->y[k] = 0.0;
        G->y[nm + k] = b->v[G->mov[k]];
        G->y[2 * nm + k] = 0.0;
    }
    G->y[3 * nm] = 0.0;
    G->s.n = 3 * nm + 1;
    mf_dopri_restart(&G->s);
    G->fresh = 0;
}

/* plate work on the stuck blocks up to t (the stuck set changes only at events, which are
   applied in time order): their total stretch is n_st V t - X_st */
static void stuck_work(bk *b, double t)
{
    double ta = b->t_acc, h = t - ta, S;
    if (!(h > 0.0)) return;
    S = b->n_st * b->V * ta - b->X_st;
    kahan(&b->W, &b->W_c, b->kp * b->V * (S * h + 0.5 * b->n_st * b->V * h * h));
    b->t_acc = t;
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

static void stick(bk *b, int i, double t)
{
    int e = find(b, b->label[i]);
    double slip = b->x[i] - b->seg_x[i];
    stuck_work(b, t);
    b->ev_moment[e] += slip;
    b->sliding += t - b->seg_t[i];
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
    group_remove(b, i);
    b->q[i] = 0;
    b->v[i] = 0.0;
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

/* a block whose velocity reached 0: stuck, or, if its force is still beyond the static
   threshold there, sliding on from rest (the other way, or the same) in the same event */
static void stopped(bk *b, int i, double t)
{
    double A = coupling(b, b->x, i) + b->kp * (b->V * t - b->x[i]);
    b->v[i] = 0.0;
    b->G[b->gid[i]].fresh = 1;
    if (A >= b->F[i]) b->q[i] = 1;
    else if (b->backward && A <= -b->F[i]) b->q[i] = -1;
    else stick(b, i, t);
}

static int apply_events(bk *b, int g, double t);

/* group h brought to time t (t no later than its clock, and its last step begun no later
   than t): its step cut back on the dense output, or its own events at t applied first.
   Returns -1 on a full catalogue or no memory. */
static int bring_to(bk *b, int h, double t)
{
    group *H = &b->G[h];
    if (H->t > t) {
        if (H->stepped) mf_dopri_dense(&H->s, t, H->y); /* its step covers t */
        H->t = t;
        H->pending = 0; /* later than t: they will be found again if they still happen */
        H->nhit = 0;
    }
    commit(b, H);
    if (H->pending) return apply_events(b, h, t);
    return 0;
}

/* block j breaks away at time t in direction dir, joining (and joining up) the groups
   within one stuck block of it; returns -1 on a full catalogue or no memory */
static int start_block(bk *b, int j, int dir, double t)
{
    int target = -1, d, e;
    for (;;) { /* groups with events of their own at t apply them first: gather again */
        int again = 0;
        for (d = -2; d <= 2 && !again; d++) {
            int i = j + d, h;
            if (d == 0 || i < 0 || i >= b->n || b->gid[i] < 0) continue;
            h = b->gid[i];
            if (b->G[h].t != t || b->G[h].stepped || b->G[h].pending) {
                if (b->G[h].pending && b->G[h].t == t) again = 1;
                if (bring_to(b, h, t) != 0) return -1;
            }
        }
        if (!again) break;
    }
    if (b->q[j] != 0) return 0; /* started by a neighbour's events meanwhile */
    for (d = -2; d <= 2; d++) { /* join every group in reach into the largest */
        int i = j + d;
        if (d == 0 || i < 0 || i >= b->n || b->gid[i] < 0) continue;
        if (target < 0 || b->G[b->gid[i]].nm > b->G[target].nm) target = b->gid[i];
    }
    for (d = -2; d <= 2 && target >= 0; d++) {
        int i = j + d, h, k;
        if (d == 0 || i < 0 || i >= b->n || b->gid[i] < 0 || b->gid[i] == target) continue;
        h = b->gid[i];
        for (k = 0; k < b->G[h].nm; k++)
            if (group_add(b, target, b->G[h].mov[k]) != 0) return -1;
        b->G[h].nm = 0;
        b->G[h].live = 0;
    }
    if (target < 0 && (target = group_new(b, t)) < 0) return -1;
    e = neighbour_event(b, j);
    if (e < 0) {
        if (b->created >= b->cap) return -1;
        e = (int)b->created++;
        b->parent[e] = e;
        b->active[e] = 0;
        b->ev_start[e] = t;
        b->ev_end[e] = NAN;
        b->ev_moment[e] = b->ev_energy[e] = 0.0;
        b->ev_blocks[e] = 0;
        b->ev_first[e] = j;
    }
    e = find(b, e);
    stuck_work(b, t);
    if (group_add(b, target, j) != 0) return -1;
    b->G[target].t = t;
    b->q[j] = dir;
    b->v[j] = 0.0;
    b->label[j] = e;
    b->active[e]++;
    if (b->last_ev[j] < 0 || find(b, b->last_ev[j]) != e) b->ev_blocks[e]++;
    b->last_ev[j] = e;
    b->seg_x[j] = b->x[j];
    b->seg_t[j] = t;
    b->slept[j] += t - b->stuck_since[j];
    b->X_st -= b->x[j];
    b->n_st--;
    tree_update(b, j - 1);
    tree_update(b, j);
    tree_update(b, j + 1);
    return 0;
}

static int by_index(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* a group whose blocks have come apart (two or more stuck blocks between neighbours: no
   block is watched from both sides) goes on as separate groups, each on its own clock
   from t; returns -1 on no memory */
static int split(bk *b, int g, double t)
{
    int nm = b->G[g].nm, k, start = 0, first = 1;
    if (nm < 2) return 0;
    memcpy(b->tmp, b->G[g].mov, (size_t)nm * sizeof(int));
    qsort(b->tmp, (size_t)nm, sizeof(int), by_index);
    for (k = 1; k < nm; k++)
        if (b->tmp[k] - b->tmp[k - 1] > 2) break;
    if (k == nm) return 0; /* still one piece */
    b->G[g].nm = 0;
    b->G[g].fresh = 1;
    for (k = 1; k <= nm; k++) {
        if (k < nm && b->tmp[k] - b->tmp[k - 1] <= 2) continue;
        {
            int h = first ? g : group_new(b, t), m;
            if (h < 0) return -1;
            for (m = start; m < k; m++)
                if (group_add(b, h, b->tmp[m]) != 0) return -1;
            b->G[h].s.h_guess = b->G[g].s.h_guess;
        }
        first = 0;
        start = k;
    }
    return 0;
}

/* the crossings group g located at t, applied (g committed at t); copied to the stack
   first: meeting groups may apply theirs in between */
static int apply_events(bk *b, int g, double t)
{
    group *G = &b->G[g];
    int base = b->sp, k, nh = G->nhit;
    for (k = 0; k < nh; k++) {
        b->stack[b->sp++] = G->hit[k];
        b->stack[b->sp++] = G->dir[k];
    }
    G->pending = 0;
    G->nhit = 0;
    G->fresh = 1;
    for (k = base; k < base + 2 * nh; k += 2) {
        int i = b->stack[k], dir = b->stack[k + 1];
        if (dir == 0) {
            if (b->q[i] != 0) stopped(b, i, t);
        } else if (b->q[i] == 0) {
            if (start_block(b, i, dir, t) != 0) { b->sp = base; return -1; }
        }
    }
    b->sp = base;
    return b->G[g].live ? split(b, g, t) : 0;
}

/* ---- one group's step -------------------------------------------------------------- */
static int rhs(void *ctx, double t, const double *y, double *dy)
{
    bk *b = (bk *)ctx;
    const group *G = &b->G[b->cur];
    const int nm = G->nm;
    double P = 0.0;
    int k;
    for (k = 0; k < nm; k++) b->xs[G->mov[k]] = b->x[G->mov[k]] + y[k];
    for (k = 0; k < nm; k++) {
        int i = G->mov[k], q = b->q[i];
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

static void build_watch(bk *b, const group *G)
{
    int k, d;
    b->nw = 0;
    b->wstamp++;
    for (k = 0; k < G->nm; k++)
        for (d = -1; d <= 1; d += 2) {
            int j = G->mov[k] + d;
            if (j < 0 || j >= b->n || b->q[j] != 0 || b->wmark[j] == b->wstamp) continue;
            b->wmark[j] = b->wstamp;
            b->watch[b->nw++] = j;
        }
}

/* indicators at state y: q v per sliding block, then F - A and F + A per watched block */
static void indicators_at(bk *b, const group *G, double t, const double *y, double *z)
{
    const int nm = G->nm;
    int k;
    for (k = 0; k < nm; k++) {
        int i = G->mov[k];
        b->xs[i] = b->x[i] + y[k];
        z[k] = b->q[i] * y[nm + k];
    }
    for (k = 0; k < b->nw; k++) {
        int j = b->watch[k];
        double A = coupling(b, b->xs, j) + b->kp * (b->V * t - b->x[j]);
        z[nm + 2 * k] = b->F[j] - A;
        z[nm + 2 * k + 1] = b->backward ? b->F[j] + A : 1.0;
    }
}

static int indicators_dense(void *ctx, double t, double *z)
{
    bk *b = (bk *)ctx;
    group *G = &b->G[b->cur];
    mf_dopri_dense(&G->s, t, G->yd);
    indicators_at(b, G, t, G->yd, z);
    return 0;
}

/* one step of group g from its clock towards t_stop; a crossing inside it ends the step
   there and waits (pending) until its time is the earliest. 0, or -1 with msg. */
static int step_group(bk *b, int g, double t_stop, char *msg, int msg_len)
{
    group *G = &b->G[g];
    const int nm = G->nm;
    int nz, found, k;
    double ta = G->t, t = G->t, te;
    mf_dopri_result r;
    long rej0 = G->s.n_rejected, rhs0 = G->s.n_rhs;
    b->cur = g;
    if (G->fresh) load(G, b);
    build_watch(b, G);
    nz = nm + 2 * b->nw;
    indicators_at(b, G, t, G->y, b->z_ref);
    r = mf_dopri_step(&G->s, rhs, b, &t, G->y, t_stop, b->tol, 1e-3);
    b->steps += 1;
    b->rejected += (double)(G->s.n_rejected - rej0);
    b->rhs_count += (double)(G->s.n_rhs - rhs0);
    if (r != MF_DOPRI_OK) {
        snprintf(msg, (size_t)msg_len, "fault: the slide could not be integrated at t = %.9g "
                 "(%s, %d blocks sliding)", ta, r == MF_DOPRI_STEP_UNDERFLOW
                 ? "step size underflow" : "friction law not finite", nm);
        return -1;
    }
    indicators_at(b, G, t, G->y, b->z_b);
    found = mf_locate_event(indicators_dense, b, nz, ta, b->z_ref, t, b->z_b, 4, &te,
                            b->z_ev, b->work);
    if (found < 0) {
        snprintf(msg, (size_t)msg_len, "fault: an indicator was not finite at t = %.9g", ta);
        return -1;
    }
    G->stepped = 1;
    if (!found) {
        G->t = t;
        return 0;
    }
    mf_dopri_dense(&G->s, te, G->y);
    G->t = te;
    G->nhit = 0;
    for (k = 0; k < nz; k++) {
        if (!mf_crossed(b->z_ref[k], b->z_ev[k])) continue;
        if (k < nm) { G->hit[G->nhit] = G->mov[k]; G->dir[G->nhit++] = 0; }
        else {
            G->hit[G->nhit] = b->watch[(k - nm) / 2];
            G->dir[G->nhit++] = (k - nm) % 2 == 0 ? 1 : -1;
        }
    }
    G->pending = 1;
    return 0;
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
    int failed = 0, i, k, status = 0, rc = 0;
    long iterations = 0;
    double t = 0.0, t_stop = par[P_TSTOP];

    memset(&b, 0, sizeof b);
    if (n < 1 || n > 10000000 || cap < 1 || sl_cap < 0) {
        snprintf(msg, (size_t)msg_len, "fault: n must be in 1..1e7 and the catalogue hold "
                 "at least one event (n = %d, capacity %ld)", n, cap);
        return -1;
    }
    b.n = n;
    b.m = par[P_M]; b.kc = par[P_KC]; b.kp = par[P_KP]; b.V = par[P_V];
    b.sigma = par[P_SIGMA]; b.alpha = par[P_ALPHA]; b.vw = par[P_VW]; b.tol = par[P_TOL];
    b.backward = par[P_BACKWARD] != 0.0;
    b.F = F; b.x = x; b.cap = cap; b.max_events = max_events;
    b.ev_start = ev_start; b.ev_end = ev_end; b.ev_moment = ev_moment;
    b.ev_energy = ev_energy; b.ev_blocks = ev_blocks; b.ev_first = ev_first;
    b.sl_cap = sl_cap; b.sl_event = sl_event; b.sl_block = sl_block; b.sl_t0 = sl_t0;
    b.sl_t1 = sl_t1; b.sl_slip = sl_slip; b.slept = slept;
    for (b.P = 1; b.P < n; b.P *= 2) {}
    b.v = grab((size_t)n, sizeof(double), &failed);
    b.xs = grab((size_t)n, sizeof(double), &failed);
    b.q = grab((size_t)n, sizeof(int), &failed);
    b.gid = grab((size_t)n, sizeof(int), &failed);
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
    /* crossings on the stack: at most one per sliding block and two per watched one */
    b.stack = grab(6 * (size_t)n + 16, sizeof(int), &failed);
    b.tmp = grab((size_t)n, sizeof(int), &failed);
    b.z_ref = grab(3 * (size_t)n, sizeof(double), &failed);
    b.z_b = grab(3 * (size_t)n, sizeof(double), &failed);
    b.z_ev = grab(3 * (size_t)n, sizeof(double), &failed);
    b.work = grab(MF_LOCATE_WORK(3 * (size_t)n, 4), sizeof(double), &failed);
    if (failed) {
        snprintf(msg, (size_t)msg_len, "fault: out of memory for %d blocks", n);
        rc = -1;
        goto done;
    }
    for (i = 0; i < 2 * b.P; i++) b.tmin[i] = INFINITY;
    for (i = 0; i < n; i++) {
        b.xs[i] = x[i];
        b.pos[i] = b.gid[i] = b.last_ev[i] = -1;
        b.X_st += x[i];
        slept[i] = 0.0;
    }
    b.n_st = n;
    for (i = 0; i < n; i++) tree_update(&b, i);
    totals[T_E_START] = stored_energy(&b, 0.0);
    /* blocks already at or past their thresholds at t = 0 start at once */
    for (i = 0; i < n; i++) {
        double A = coupling(&b, b.x, i) - b.kp * b.x[i];
        if (b.q[i] == 0 && (A >= F[i] || (b.backward && A <= -F[i])) &&
            start_block(&b, i, A > 0 ? 1 : -1, 0.0) != 0) {
            status = 2;
            goto finish;
        }
    }

    for (;;) {
        int g = -1;
        double tg = INFINITY, tt = b.tmin[1];
        if (++iterations > max_steps) {
            snprintf(msg, (size_t)msg_len, "fault: more than %ld steps before t = %g (at t = "
                     "%.9g): raise max_steps or shorten the run", max_steps, t_stop, b.t_acc);
            rc = -1;
            goto finish;
        }
        for (k = 0; k < b.ng; k++) /* the earliest clock */
            if (b.G[k].live && b.G[k].t < tg) { tg = b.G[k].t; g = k; }
        if (g < 0) {
            /* every block stuck: jump to the earliest closed-form break-away */
            if (b.completed >= max_events) { status = 1; t = b.t_acc; break; }
            if (!isfinite(tt) && !isfinite(t_stop)) { status = 3; t = b.t_acc; break; }
            if (!(tt < t_stop)) { t = t_stop; break; }
            if (tt < b.t_acc) tt = b.t_acc; /* rounding: a threshold met now */
            b.steps += 0; /* a jump, not a step */
            totals[T_BREAKAWAYS] += 1;
            if (start_block(&b, b.targ[1], 1, tt) != 0) { status = 2; t = tt; break; }
            continue;
        }
        if (tt < tg && tt < t_stop) {
            /* a stuck block far from every slide reaches its threshold first */
            if (tt < b.t_acc) tt = b.t_acc;
            totals[T_BREAKAWAYS] += 1;
            if (start_block(&b, b.targ[1], 1, tt) != 0) { status = 2; t = tt; break; }
            continue;
        }
        if (tg >= t_stop) { t = t_stop; break; } /* every group has reached the stop time */
        commit(&b, &b.G[g]);
        if (b.G[g].pending) {
            totals[T_LOCATED] += 1;
            if (apply_events(&b, g, tg) != 0) { status = 2; t = tg; break; }
            continue; /* its blocks changed: the earliest clock is chosen again */
        }
        if (step_group(&b, g, t_stop, msg, msg_len) != 0) { rc = -1; t = tg; goto finish; }
    }
finish:
    if (b.oom && rc == 0) {
        snprintf(msg, (size_t)msg_len, "fault: out of memory for the sliding groups");
        rc = -1;
    }
    for (k = 0; k < b.ng; k++) /* the groups' last steps, up to where each has got */
        if (b.G[k].live) commit(&b, &b.G[k]);
    stuck_work(&b, t);
    for (i = 0; i < n; i++)
        if (b.q[i] == 0) slept[i] += t - b.stuck_since[i];
    totals[T_TIME] = t;
    totals[T_PLATE_WORK] = b.W;
    totals[T_DISSIPATED] = b.D;
    totals[T_E_END] = stored_energy(&b, t);
    totals[T_STEPS] = b.steps;
    totals[T_REJECTED] = b.rejected;
    totals[T_RHS] = b.rhs_count;
    totals[T_BLOCK_RHS] = b.block_rhs;
    totals[T_SLIPS_DROPPED] = (double)b.sl_dropped;
    totals[T_CREATED] = (double)b.created;
    totals[T_SLIDES] = (double)b.sl_count;
    totals[T_SLIDING] = b.sliding;
done:
    totals[T_STATUS] = status;
    for (k = 0; k < b.gcap; k++) {
        mf_dopri_free(&b.G[k].s);
        free(b.G[k].mov); free(b.G[k].hit); free(b.G[k].dir);
        free(b.G[k].y); free(b.G[k].yd);
    }
    free(b.G);
    free(b.v); free(b.xs); free(b.q); free(b.gid); free(b.pos); free(b.watch);
    free(b.wmark); free(b.tmin); free(b.targ); free(b.label); free(b.last_ev);
    free(b.seg_x); free(b.seg_t); free(b.stuck_since); free(b.parent); free(b.active);
    free(b.stack); free(b.tmp); free(b.z_ref); free(b.z_b); free(b.z_ev); free(b.work);
    return rc;
}

/* the lengths of par[] and totals[], so that Python and C agree on the layout */
EXPORT int mf_fault_layout(int *p_count, int *t_count)
{
    *p_count = P_COUNT;
    *t_count = T_COUNT;
    return 0;
}
