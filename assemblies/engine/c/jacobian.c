#include "jacobian.h"

#include <stdlib.h>
#include <string.h>

/* One instance's part: its knowns (states, then the Float64 inputs couplings set) and
   unknowns (derivatives, then the Float64 outputs couplings read), with a seed and a
   sensitivity for each. */
typedef struct {
    int n_x, n_known, n_unknown;
    uint32_t *known_vr, *unknown_vr;
    double *seed, *sens;
    int dirty; /* its seed changed since it was last evaluated */
} part;

struct eng_jacobian {
    int n, n_x;
    const int *x_off;
    part *parts;
    int n_couplings;
    int *from, *to; /* per coupling: index among its source's unknowns, its target's knowns; -1: Int32 */
    const eng_coupling *couplings;
};

/* The index of `vr` in list[0 .. *n), appended when absent. */
static int slot(uint32_t *list, int *n, uint32_t vr)
{
    int k;
    for (k = 0; k < *n; k++)
        if (list[k] == vr) return k;
    list[*n] = vr;
    return (*n)++;
}

void eng_jacobian_free(eng_jacobian *J)
{
    int i;
    if (!J) return;
    if (J->parts)
        for (i = 0; i < J->n; i++) {
            free(J->parts[i].known_vr); free(J->parts[i].unknown_vr);
            free(J->parts[i].seed); free(J->parts[i].sens);
        }
    free(J->parts); free(J->from); free(J->to);
    free(J);
}

eng_jacobian *eng_jacobian_plan(const eng_me_spec *s, const int *x_off)
{
    const int nc = s->n_couplings;
    eng_jacobian *J = calloc(1, sizeof *J);
    int i, k, *coupled;
    if (!J) return NULL;
    J->n = s->n_instances;
    J->n_x = x_off[s->n_instances];
    J->x_off = x_off;
    J->couplings = s->couplings;
    J->n_couplings = nc;
    J->parts = calloc((size_t)J->n, sizeof *J->parts);
    J->from = calloc((size_t)nc + 1, sizeof(int));
    J->to = calloc((size_t)nc + 1, sizeof(int));
    coupled = calloc((size_t)J->n, sizeof(int));
    if (!J->parts || !J->from || !J->to || !coupled) goto refuse;
    for (k = 0; k < nc; k++)
        if (ENG_PLAIN(&s->couplings[k].source)) {
            coupled[s->couplings[k].source.instance] = 1;
            coupled[s->couplings[k].target.instance] = 1;
        }
    for (i = 0; i < J->n; i++) {
        const eng_instance_spec *in = &s->instances[i];
        part *p = &J->parts[i];
        int room = in->n_states + nc;
        p->n_x = in->n_states;
        if (p->n_x == 0 && !coupled[i]) continue; /* nothing of it enters the Jacobian */
        if (!in->provides_directional_derivative ||
            (p->n_x > 0 && (!in->state_vr || !in->derivative_vr)))
            goto refuse;
        p->known_vr = calloc((size_t)room + 1, sizeof(uint32_t));
        p->unknown_vr = calloc((size_t)room + 1, sizeof(uint32_t));
        p->seed = calloc((size_t)room + 1, sizeof(double));
        p->sens = calloc((size_t)room + 1, sizeof(double));
        if (!p->known_vr || !p->unknown_vr || !p->seed || !p->sens) goto refuse;
        if (p->n_x > 0) { /* a stateless member has no state arrays (NULL): memcpy
                             from NULL is undefined even for 0 bytes */
            memcpy(p->known_vr, in->state_vr, (size_t)p->n_x * sizeof(uint32_t));
            memcpy(p->unknown_vr, in->derivative_vr, (size_t)p->n_x * sizeof(uint32_t));
        }
        p->n_known = p->n_unknown = p->n_x;
    }
    for (k = 0; k < nc; k++) {
        const eng_coupling *c = &s->couplings[k];
        /* discrete, Float32 and array couplings carry nothing here (jacobian.h) */
        if (!ENG_PLAIN(&c->source) || !ENG_PLAIN(&c->target)) {
            J->from[k] = J->to[k] = -1;
            continue;
        }
        J->from[k] = slot(J->parts[c->source.instance].unknown_vr,
                          &J->parts[c->source.instance].n_unknown, c->source.vr);
        J->to[k] = slot(J->parts[c->target.instance].known_vr,
                        &J->parts[c->target.instance].n_known, c->target.vr);
    }
    free(coupled);
    return J;
refuse:
    free(coupled);
    eng_jacobian_free(J);
    return NULL;
}

int eng_jacobian_eval(eng_jacobian *J, fmu_t **fmus, const int *asleep, double *jac, int *bad)
{
    int i, j, k, pass;
    for (j = 0; j < J->n_x; j++) {
        int owner = 0, pending;
        while (J->x_off[owner + 1] <= j) owner++;
        for (i = 0; i < J->n; i++) {
            part *p = &J->parts[i];
            if (p->seed) {
                memset(p->seed, 0, (size_t)p->n_known * sizeof(double));
                memset(p->sens, 0, (size_t)p->n_unknown * sizeof(double));
            }
            p->dirty = 0;
        }
        if (!asleep[owner]) {
            J->parts[owner].seed[j - J->x_off[owner]] = 1.0;
            J->parts[owner].dirty = 1;
        }
        for (pass = 0, pending = !asleep[owner]; pending && pass <= J->n; pass++) {
            for (i = 0; i < J->n; i++) {
                part *p = &J->parts[i];
                if (!p->dirty) continue;
                p->dirty = 0;
                if (fmu_directional_derivative(fmus[i], p->unknown_vr, (size_t)p->n_unknown,
                                               p->known_vr, (size_t)p->n_known, p->seed,
                                               p->sens)) {
                    *bad = i;
                    return -1;
                }
            }
            pending = 0;
            for (k = 0; k < J->n_couplings; k++) {
                const eng_coupling *c = &J->couplings[k];
                part *target = &J->parts[c->target.instance];
                double v;
                if (J->from[k] < 0 || asleep[c->target.instance]) continue;
                v = asleep[c->source.instance]
                        ? 0.0 : c->gain * J->parts[c->source.instance].sens[J->from[k]];
                if (v != target->seed[J->to[k]]) {
                    target->seed[J->to[k]] = v;
                    target->dirty = pending = 1;
                }
            }
        }
        if (pending) return 1;
        for (i = 0; i < J->n; i++) {
            const part *p = &J->parts[i];
            for (k = 0; k < p->n_x; k++)
                jac[(size_t)j * (size_t)J->n_x + (size_t)(J->x_off[i] + k)] =
                    asleep[i] ? 0.0 : p->sens[k];
        }
    }
    return 0;
}
