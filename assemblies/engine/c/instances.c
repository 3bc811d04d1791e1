/*
 * instances.c: loading an instance with its start values, value access across
 * types, and the evaluation of couplings.
 */
#include "instances.h"

#include <math.h>
#include <stdio.h>

fmu_t *eng_instantiate(const eng_instance_spec *s, fmu_kind kind,
                       fmu_intermediate_fn intermediate, void *intermediate_ctx,
                       int early_return_allowed, char *err, size_t err_len)
{
    fmu_options o = {0};
    fmu_t *f;
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
        fmu_set_int32(f, s->int_start_vr, (size_t)s->n_int_starts, s->int_start_values)) {
        snprintf(err, err_len, "%s (setting parameters and start values)", fmu_message(f));
        fmu_free(f);
        return NULL;
    }
    return f;
}

int eng_get_value(fmu_t *f, uint32_t vr, int is_int, double *value)
{
    if (is_int) {
        int32_t i = 0;
        int rc = fmu_get_int32(f, &vr, 1, &i);
        *value = i;
        return rc;
    }
    return fmu_get_float64(f, &vr, 1, value);
}

int eng_set_value(fmu_t *f, uint32_t vr, int is_int, double value)
{
    if (is_int) {
        /* an Int32 input takes the nearest integer: couplings of mode-like signals */
        int32_t i = (int32_t)lround(value);
        return fmu_set_int32(f, &vr, 1, &i);
    }
    return fmu_set_float64(f, &vr, 1, &value);
}

int eng_propagate(fmu_t **fmus, const eng_coupling *c, int n, double *values, int *failed)
{
    int k;
    for (k = 0; k < n; k++) {
        double v;
        if (eng_get_value(fmus[c[k].source.instance], c[k].source.vr, c[k].source.is_int, &v)) {
            *failed = c[k].source.instance;
            return FMU_ERROR;
        }
        v *= c[k].gain;
        if (eng_set_value(fmus[c[k].target.instance], c[k].target.vr, c[k].target.is_int, v)) {
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
