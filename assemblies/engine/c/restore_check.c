/*
 * restore_check.c: the one-off check of an FMU's state restore (restore_check.h).
 */
#include "restore_check.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmu.h"
#include "instances.h"

#define MAX_COMPARED 100000 /* variables compared: bounds the buffers below */

static void unchecked(eng_restore_check *r, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->message, sizeof r->message, fmt, ap);
    va_end(ap);
    r->verdict = ENG_RESTORE_UNCHECKED;
}

/* Reads the compared variables into v; with `skip`, leaves out (skip[j] = 1) those
   whose read fails, else a failed read is an error. 0 on success. */
static int read_all(fmu_t *f, int n, const eng_variable *vars, int *skip,
                    int first, double *v)
{
    int j;
    for (j = 0; j < n; j++) {
        if (skip[j]) continue;
        if (eng_get_value(f, &vars[j], &v[j]) != FMU_OK) {
            if (!first) return -1;
            skip[j] = 1;
        }
    }
    return 0;
}

/* The first compared variable whose values differ in their bits (NaN equals NaN
   with the same bits), or -1. */
static int first_difference(int n, const int *skip, const double *a, const double *b)
{
    int j;
    for (j = 0; j < n; j++)
        if (!skip[j] && memcmp(&a[j], &b[j], sizeof(double)) != 0) return j;
    return -1;
}

static int step_once(fmu_t *f, double h)
{
    fmu_step_result r;
    /* a terminating or discarded step says nothing about the restore */
    return fmu_do_step(f, 0.0, h, 0, &r) == FMU_OK && !r.terminate && !r.early_return ? 0 : -1;
}

void eng_check_restore(const eng_instance_spec *spec, double step, double tolerance, int n,
                       const eng_variable *vars, eng_restore_check *result)
{
    char err[512];
    fmu_t *f = NULL;
    void *saved = NULL;
    double *start = NULL, *first = NULL, *again = NULL;
    int *skip = NULL, j;

    memset(result, 0, sizeof *result);
    result->which = -1;
    if (n < 0 || n > MAX_COMPARED || !(step > 0.0)) {
        unchecked(result, "%d variables and a step of %g: nothing to check", n, step);
        return;
    }
    start = (double *)calloc((size_t)n + 1, sizeof(double));
    first = (double *)calloc((size_t)n + 1, sizeof(double));
    again = (double *)calloc((size_t)n + 1, sizeof(double));
    skip = (int *)calloc((size_t)n + 1, sizeof(int));
    if (!start || !first || !again || !skip) {
        unchecked(result, "out of memory");
        goto done;
    }
    f = eng_instantiate(spec, FMU_CO_SIMULATION, NULL, NULL, 0, err, sizeof err);
    if (!f) {
        unchecked(result, "%s", err);
        goto done;
    }
    if (fmu_enter_initialization(f, tolerance, 0.0, 0.0) != FMU_OK
        || fmu_exit_initialization(f) != FMU_OK) {
        unchecked(result, "initialization failed: %s", fmu_message(f));
        goto done;
    }
    if (read_all(f, n, vars, skip, 1, start)) goto read_failed;
    if (fmu_get_state(f, &saved) != FMU_OK) {
        unchecked(result, "getFMUState failed: %s", fmu_message(f));
        goto done;
    }
    if (step_once(f, step)) goto step_failed;
    if (read_all(f, n, vars, skip, 0, first)) goto read_failed;
    if (fmu_set_state(f, saved) != FMU_OK) {
        unchecked(result, "setFMUState failed: %s", fmu_message(f));
        goto done;
    }
    if (read_all(f, n, vars, skip, 0, again)) goto read_failed;
    j = first_difference(n, skip, start, again);
    if (j >= 0) {
        result->verdict = ENG_RESTORE_INEXACT;
        result->which = j;
        result->expected = start[j];
        result->got = again[j];
        goto done;
    }
    if (step_once(f, step)) goto step_failed;
    if (read_all(f, n, vars, skip, 0, again)) goto read_failed;
    j = first_difference(n, skip, first, again);
    if (j >= 0) {
        result->verdict = ENG_RESTORE_INEXACT;
        result->which = j;
        result->after_step = 1;
        result->expected = first[j];
        result->got = again[j];
        goto done;
    }
    result->verdict = ENG_RESTORE_EXACT;
    goto done;
step_failed:
    unchecked(result, "its doStep of %g s from t = 0 did not complete: %s", step, fmu_message(f));
    goto done;
read_failed:
    unchecked(result, "reading its outputs failed: %s", fmu_message(f));
done:
    if (f) {
        if (saved) fmu_free_state(f, &saved);
        fmu_free(f);
    }
    free(start);
    free(first);
    free(again);
    free(skip);
}
