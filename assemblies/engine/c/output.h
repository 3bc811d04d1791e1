/*
 * output.h: what a run hands back besides the output table: growable tables of
 * event rows, one per instance, the wall-clock throttle of the progress callback,
 * and the guards every time loop runs under (a step budget, a progress check, the
 * round-off slack of a target time).
 */
#ifndef MECHFMU_ENGINE_OUTPUT_H
#define MECHFMU_ENGINE_OUTPUT_H

#include <stddef.h>

#include "engine.h"

typedef struct {
    double *rows;
    long n_rows, capacity;
    int width;
} eng_table;

/* 0 on success, -1 when memory runs out (the table keeps what it had). */
int eng_table_append(eng_table *table, const double *row);

/* A run handle: one event table per event group. */
struct eng_run {
    int n_tables;
    eng_table *tables;
};

eng_run *eng_run_new(int n_tables, const int *widths);

typedef struct {
    eng_progress_fn fn;
    void *ctx;
    double next_wall; /* seconds on the monotonic clock */
    double last_read; /* when the clock was last read */
    int stride, skipped; /* the clock is read on every stride-th check */
} eng_progress;

void eng_progress_start(eng_progress *p, eng_progress_fn fn, void *ctx);
/* Calls the callback when 0.25 s have passed since the last call; nonzero: stop. */
int eng_progress_check(eng_progress *p, double t);

/* The step budget of one call that advances time: at most max_steps steps, and every
   ENG_BUDGET_WINDOW steps a pace check that refuses at once when the last window's
   pace projects more than ENG_BUDGET_SLACK times the steps the budget has left (a
   request that cannot be finished fails in bounded time, not after max_steps; the
   slack spares a run whose first steps are short and whose later ones grow). */
#define ENG_BUDGET_WINDOW 1000L
#define ENG_BUDGET_SLACK 100.0
typedef struct {
    long steps, max_steps;
    double t_window;  /* the time reached at the start of the current window */
} eng_budget;

void eng_budget_start(eng_budget *b, long max_steps, double t);
/* Counts one step that reached t on the way to `target`: 0 to go on, -1 with the reason
   in why (one line) when the budget is spent or the pace cannot reach the target. */
int eng_budget_spend(eng_budget *b, double t, double target, char *why, size_t len);
/* The round-off an importer's communication points carry (0.5 + 0.1 against 6 * 0.1):
   a time within this of `target` is the target. Relative to the target, but never more
   than a small part of the interval from `from`, so that a short step late in time
   (1 s at t = 1e15) is taken rather than mistaken for round-off. */
double eng_time_slack(double from, double target);

#endif
