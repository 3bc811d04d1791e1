/*
 * output.c: event tables, the progress throttle and the time loops' guards.
 */
#define _POSIX_C_SOURCE 200809L
#include "output.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define PROGRESS_INTERVAL_S 0.25
#define PROGRESS_FAST_S 1e-3
#define PROGRESS_MAX_STRIDE 16

int eng_table_append(eng_table *t, const double *row)
{
    if (t->n_rows == t->capacity) {
        long capacity = t->capacity ? 2 * t->capacity : 16;
        double *rows = realloc(t->rows, (size_t)capacity * (size_t)t->width * sizeof(double));
        if (rows == NULL) return -1;
        t->rows = rows;
        t->capacity = capacity;
    }
    memcpy(t->rows + (size_t)t->n_rows * (size_t)t->width, row, (size_t)t->width * sizeof(double));
    t->n_rows++;
    return 0;
}

eng_run *eng_run_new(int n, const int *widths)
{
    int i;
    eng_run *run = calloc(1, sizeof *run);
    if (run == NULL) return NULL;
    run->tables = calloc((size_t)(n > 0 ? n : 1), sizeof *run->tables);
    if (run->tables == NULL) {
        free(run);
        return NULL;
    }
    run->n_tables = n;
    for (i = 0; i < n; i++) run->tables[i].width = widths[i];
    return run;
}

ENG_API int eng_run_events(const eng_run *run, int group, const double **rows, long *n_rows,
                           int *width)
{
    if (run == NULL || group < 0 || group >= run->n_tables) return -1;
    *rows = run->tables[group].rows;
    *n_rows = run->tables[group].n_rows;
    *width = run->tables[group].width;
    return 0;
}

ENG_API void eng_run_free(eng_run *run)
{
    int i;
    if (run == NULL) return;
    for (i = 0; i < run->n_tables; i++) free(run->tables[i].rows);
    free(run->tables);
    free(run);
}

static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void eng_progress_start(eng_progress *p, eng_progress_fn fn, void *ctx)
{
    p->fn = fn;
    p->ctx = ctx;
    p->last_read = wall_now();
    p->next_wall = p->last_read + PROGRESS_INTERVAL_S;
    p->stride = 1;
    p->skipped = 0;
}

int eng_progress_check(eng_progress *p, double t)
{
    double now;
    if (p->fn == NULL) return 0;
    /* Reading the clock costs as much as a small model's step (stick_slip: 3 % of a
       run); while checks come fast, it is read on every stride-th one only, the stride
       doubling up to PROGRESS_MAX_STRIDE while a stride's checks take under
       PROGRESS_FAST_S, back to 1 when they take longer (so a run of slow steps is
       never kept from its callback longer than PROGRESS_MAX_STRIDE of them) */
    if (++p->skipped < p->stride) return 0;
    p->skipped = 0;
    now = wall_now();
    if (now - p->last_read < PROGRESS_FAST_S) {
        if (p->stride < PROGRESS_MAX_STRIDE) p->stride *= 2;
    } else {
        p->stride = 1;
    }
    p->last_read = now;
    if (now < p->next_wall) return 0;
    p->next_wall = now + PROGRESS_INTERVAL_S;
    return p->fn(p->ctx, t) != 0;
}

void eng_budget_start(eng_budget *b, long max_steps, double t)
{
    b->steps = 0;
    b->max_steps = max_steps;
    b->t_window = t;
}

int eng_budget_spend(eng_budget *b, double t, double target, char *why, size_t len)
{
    double pace, needed;
    if (++b->steps > b->max_steps) {
        snprintf(why, len, "more than %ld steps without reaching t = %.17g (reached t = %.17g)",
                 b->max_steps, target, t);
        return -1;
    }
    if (b->steps % ENG_BUDGET_WINDOW) return 0;
    pace = (t - b->t_window) / (double)ENG_BUDGET_WINDOW;
    needed = pace > 0.0 ? (target - t) / pace : HUGE_VAL;
    if (needed > ENG_BUDGET_SLACK * (double)(b->max_steps - b->steps)) {
        snprintf(why, len, "t = %.17g cannot be reached from t = %.17g within %ld steps: the "
                 "last %ld advanced %g s, so the rest needs about %.3g; ask for a shorter "
                 "interval", target, t, b->max_steps, ENG_BUDGET_WINDOW, t - b->t_window, needed);
        return -1;
    }
    b->t_window = t;
    return 0;
}

double eng_time_slack(double from, double target)
{
    return fmin(1e-12 * fmax(1.0, fabs(target)), 1e-3 * fabs(target - from));
}
