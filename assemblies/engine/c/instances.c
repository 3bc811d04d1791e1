/*
 * instances.c: loading an instance with its start values, value access across
 * types, and the evaluation of couplings.
 */
#include "instances.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

fmu_t *eng_instantiate(const eng_instance_spec *s, fmu_kind kind,
                       fmu_intermediate_fn intermediate, void *intermediate_ctx,
                       int early_return_allowed, char *err, size_t err_len)
{
    fmu_options o = {0};
    fmu_t *f;
    int k;
    o.unzip_dir = s->unzip_dir;
    o.model_identifier = s->model_identifier;
    o.instantiation_token = s->instantiation_token;
    o.instance_name = s->instance_name;
    o.fmi_version = s->fmi_version;
    o.kind = kind;
    o.n_states = s->n_states;
    o.n_event_indicators = s->n_event_indicators;
    o.can_get_set_state = s->can_get_set_state;
    o.provides_directional_derivative = s->provides_directional_derivative;
    o.early_return_allowed = early_return_allowed;
    o.intermediate = intermediate;
    o.intermediate_ctx = intermediate_ctx;
    f = fmu_load(&o, err, err_len);
    if (f == NULL) return NULL;
    if (fmu_set_float64(f, s->float_start_vr, (size_t)s->n_float_starts, s->float_start_values) ||
        fmu_set_int32(f, s->int_start_vr, (size_t)s->n_int_starts, s->int_start_values) ||
        fmu_set_strings(f, s->string_start_vr, (size_t)s->n_string_starts,
                        s->string_start_values))
        goto refused;
    for (k = 0; k < s->n_typed_starts; k++)
        if (eng_set_value(f, &s->typed_starts[k], s->typed_start_values[k])) goto refused;
    return f;
refused:
    snprintf(err, err_len, "%s (setting parameters and start values)", fmu_message(f));
    fmu_free(f);
    return NULL;
}

/* The String values of this thread's runs, each text once (engine.h: eng_string). */
static __thread struct {
    char **texts;
    long n, capacity;
    size_t bytes;
} strings;

ENG_API const char *eng_string(long index)
{
    return index >= 0 && index < strings.n ? strings.texts[index] : NULL;
}

ENG_API void eng_strings_clear(void)
{
    long i;
    for (i = 0; i < strings.n; i++) free(strings.texts[i]);
    free(strings.texts);
    memset(&strings, 0, sizeof strings);
}

/* The index of `text` in the table, added if new; -1 (a message in f) when full. */
static long intern(fmu_t *f, uint32_t vr, const char *text)
{
    long i;
    size_t len = strlen(text);
    for (i = strings.n - 1; i >= 0; i--) /* the latest first: a String output changes rarely */
        if (strcmp(strings.texts[i], text) == 0) return i;
    if (strings.n >= ENG_MAX_STRINGS || strings.bytes + len + 1 > (size_t)ENG_MAX_STRING_BYTES) {
        fmu_complain(f, "String variable (value reference %u) took more than %d distinct values "
                    "or %ld bytes in one run", vr, ENG_MAX_STRINGS, ENG_MAX_STRING_BYTES);
        return -1;
    }
    if (strings.n == strings.capacity) {
        long capacity = strings.capacity ? 2 * strings.capacity : 16;
        char **texts = realloc(strings.texts, (size_t)capacity * sizeof *texts);
        if (texts == NULL) return fmu_complain(f, "out of memory for String values"), -1;
        strings.texts = texts;
        strings.capacity = capacity;
    }
    if ((strings.texts[strings.n] = malloc(len + 1)) == NULL)
        return fmu_complain(f, "out of memory for String values"), -1;
    memcpy(strings.texts[strings.n], text, len + 1);
    strings.bytes += len + 1;
    return strings.n++;
}

int eng_get_value(fmu_t *f, const eng_variable *v, double *value)
{
    if (v->type == ENG_STRING) {
        const char *text;
        long index;
        if (fmu_get_string(f, v->vr, &text)) return FMU_ERROR;
        if ((index = intern(f, v->vr, text)) < 0) return FMU_ERROR;
        *value = (double)index;
        return FMU_OK;
    }
    if (v->size > 1) {
        double small[64], *all;
        int rc;
        if (v->element < 0 || v->element >= v->size) {
            fmu_complain(f, "element %d of an array of %d (value reference %u) does not exist",
                         v->element + 1, v->size, v->vr);
            return FMU_ERROR;
        }
        all = v->size <= 64 ? small : malloc((size_t)v->size * sizeof(double));
        if (all == NULL) return fmu_complain(f, "out of memory reading an array"), FMU_ERROR;
        rc = fmu_get_typed(f, v->type, &v->vr, 1, all, (size_t)v->size);
        if (rc == FMU_OK) *value = all[v->element];
        if (all != small) free(all);
        return rc;
    }
    return fmu_get_typed(f, v->type, &v->vr, 1, value, 1);
}

int eng_set_value(fmu_t *f, const eng_variable *v, double value)
{
    if (v->type == ENG_STRING) {
        const char *text = eng_string((long)value);
        if (text == NULL || value != floor(value)) {
            fmu_complain(f, "String variable (value reference %u): %g is no String value of this "
                        "run", v->vr, value);
            return FMU_ERROR;
        }
        return fmu_set_strings(f, &v->vr, 1, &text);
    }
    if (v->size > 1) {
        if (v->element < 0) return fmu_complain(f, "negative array element"), FMU_ERROR;
        return fmu_set_element(f, v->type, v->vr, (size_t)v->size, (size_t)v->element, value);
    }
    return fmu_set_typed(f, v->type, &v->vr, 1, &value, 1);
}

int eng_propagate(fmu_t **fmus, const eng_coupling *c, int n, double *values, int *failed)
{
    int k;
    for (k = 0; k < n; k++) {
        double v;
        if (eng_get_value(fmus[c[k].source.instance], &c[k].source, &v)) {
            *failed = c[k].source.instance;
            return FMU_ERROR;
        }
        v *= c[k].gain; /* 1 for signals: a String's index passes unchanged */
        if (eng_set_value(fmus[c[k].target.instance], &c[k].target, v)) {
            *failed = c[k].target.instance;
            return FMU_ERROR;
        }
        if (values) values[k] = v;
    }
    return FMU_OK;
}

void eng_describe_failure(char *message, size_t len, fmu_t *f, const char *what, double t)
{
    const char *logged = fmu_message(f);
    snprintf(message, len, "%.100s: %.100s failed at t = %.10g%s%.700s", fmu_instance_name(f),
             what, t, logged[0] ? ": " : "", logged);
}
