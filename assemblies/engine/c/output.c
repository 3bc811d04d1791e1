/*
 * output.c: event tables and the progress throttle.
 */
#define _POSIX_C_SOURCE 200809L
#include "output.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#define PROGRESS_INTERVAL_S 0.25

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
    p->next_wall = wall_now() + PROGRESS_INTERVAL_S;
}

int eng_progress_check(eng_progress *p, double t)
{
    double now;
    if (p->fn == NULL) return 0;
    now = wall_now();
    if (now < p->next_wall) return 0;
    p->next_wall = now + PROGRESS_INTERVAL_S;
    return p->fn(p->ctx, t) != 0;
}
