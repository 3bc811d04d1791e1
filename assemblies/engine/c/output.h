/*
 * output.h: what a run hands back besides the output table: growable tables of
 * event rows, one per instance, and the wall-clock throttle of the progress
 * callback.
 */
#ifndef MECHFMU_ENGINE_OUTPUT_H
#define MECHFMU_ENGINE_OUTPUT_H

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
} eng_progress;

void eng_progress_start(eng_progress *p, eng_progress_fn fn, void *ctx);
/* Calls the callback when 0.25 s have passed since the last call; nonzero: stop. */
int eng_progress_check(eng_progress *p, double t);

#endif
