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
    unsigned char *dep;  /* n_unknown x n_known: unknown u may depend on known k */
    unsigned char *reach_known, *reach_unknown; /* the structural propagation's marks */
    int *out, n_out;     /* the couplings that read this part's unknowns */
    int dirty;           /* its seed changed since it was last evaluated */
    int touched;         /* on the list of parts to clear */
} part;

struct eng_jacobian {
    int n, n_x;
    const int *x_off;
    part *parts;
    int n_couplings;
    int *from, *to; /* per coupling: index among its source's unknowns, its target's knowns; -1: Int32 */
    const eng_coupling *couplings;
    int *row_part;            /* the instance whose derivative each state row is */
    /* the structural pattern by columns: rows row_idx[col_start[j] .. col_start[j + 1]) */
    int *col_start, *row_idx;
    /* column groups no two columns of which share a row (Curtis, Powell and Reid): one
       propagation of a group's seeds gives every column of it */
    int n_groups, *group_start, *group_cols;
    int *list, *next, *touched; /* scratch: parts to evaluate, the next pass's, to clear */
    int *stack_part, *stack_known; /* scratch of reach: knowns newly marked, to pass on */
    int n_touched;
    long evaluations;          /* directional-derivative calls made */
    long plan_checks;          /* dependencies the plan looked at (reach) */
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
            part *p = &J->parts[i];
            free(p->known_vr); free(p->unknown_vr); free(p->seed); free(p->sens);
            free(p->dep); free(p->reach_known); free(p->reach_unknown); free(p->out);
        }
    free(J->parts); free(J->from); free(J->to);
    free(J->row_part); free(J->col_start); free(J->row_idx);
    free(J->group_start); free(J->group_cols);
    free(J->list); free(J->next); free(J->touched);
    free(J->stack_part); free(J->stack_known);
    free(J);
}

/* dep of part p from its instance's feedthrough (engine.h): states reach every unknown,
   a coupled input only the unknowns listed for it (all, when nothing is listed). */
static void feedthrough(part *p, const eng_instance_spec *in)
{
    int u, k, q;
    const size_t nk = (size_t)p->n_known;
    for (u = 0; u < p->n_unknown; u++)
        for (k = 0; k < p->n_known; k++)
            p->dep[(size_t)u * nk + (size_t)k] =
                (unsigned char)(k < p->n_x || !in->feedthrough_listed);
    if (!in->feedthrough_listed) return;
    for (q = 0; q < in->n_feedthrough; q++)
        for (u = 0; u < p->n_unknown; u++) {
            if (p->unknown_vr[u] != in->feedthrough_unknown[q]) continue;
            for (k = p->n_x; k < p->n_known; k++)
                if (p->known_vr[k] == in->feedthrough_known[q])
                    p->dep[(size_t)u * nk + (size_t)k] = 1;
        }
}

/* Clears the parts touched since the last clear. */
static void clear_touched(eng_jacobian *J)
{
    int t;
    for (t = 0; t < J->n_touched; t++) {
        part *p = &J->parts[J->touched[t]];
        if (p->seed) {
            memset(p->seed, 0, (size_t)p->n_known * sizeof(double));
            memset(p->sens, 0, (size_t)p->n_unknown * sizeof(double));
            memset(p->reach_known, 0, (size_t)p->n_known);
            memset(p->reach_unknown, 0, (size_t)p->n_unknown);
        }
        p->dirty = p->touched = 0;
    }
    J->n_touched = 0;
}

static void touch(eng_jacobian *J, int i)
{
    if (!J->parts[i].touched) {
        J->parts[i].touched = 1;
        J->touched[J->n_touched++] = i;
    }
}

/* The rows state j reaches through the instances' dependencies and the couplings,
   appended to row_idx at *nnz (room for n_x more is there). Work goes by newly marked
   knowns, each taken once (J->stack, room for every part's knowns): a known passes its
   mark to the unknowns that depend on it, and an unknown newly marked to the knowns its
   couplings set. So a column costs the unknowns of the knowns it reaches, not every
   part's unknowns times its knowns per visit: a composite FMU's 2n states, each
   reaching every derivative, cost n^2 in all instead of n^3 (a 256-block chain's plan
   took half the run). */
static void reach(eng_jacobian *J, int j, int *nnz)
{
    int owner = J->row_part[j], n_stack = 0, i, u, q;
    part *p = &J->parts[owner];
    touch(J, owner);
    p->reach_known[j - J->x_off[owner]] = 1;
    J->stack_part[n_stack] = owner;
    J->stack_known[n_stack++] = j - J->x_off[owner];
    while (n_stack > 0) {
        const int k = J->stack_known[--n_stack];
        const size_t nk = (size_t)(p = &J->parts[J->stack_part[n_stack]])->n_known;
        J->plan_checks += p->n_unknown;
        for (u = 0; u < p->n_unknown; u++) {
            if (p->reach_unknown[u] || !p->dep[(size_t)u * nk + (size_t)k]) continue;
            p->reach_unknown[u] = 1;
            for (q = 0; q < p->n_out; q++) {
                const int c = p->out[q], t = J->couplings[c].target.instance;
                part *target = &J->parts[t];
                if (J->from[c] != u || target->reach_known[J->to[c]]) continue;
                target->reach_known[J->to[c]] = 1;
                touch(J, t);
                J->stack_part[n_stack] = t;
                J->stack_known[n_stack++] = J->to[c];
            }
        }
    }
    for (q = 0; q < J->n_touched; q++) {
        i = J->touched[q];
        for (u = 0; u < J->parts[i].n_x; u++)
            if (J->parts[i].reach_unknown[u]) J->row_idx[(*nnz)++] = J->x_off[i] + u;
    }
    clear_touched(J);
}

/* The pattern column by column, then the groups: each column joins the first group
   that holds no column sharing a row with it (greedy Curtis-Powell-Reid). A chain
   needs a handful of groups whatever its length. Where half the pattern or more is
   filled, the search would cost more than it saves: one column per group, which is
   the column-by-column Jacobian. */
static int pattern_and_groups(eng_jacobian *J)
{
    const int n = J->n_x;
    int j, r, q, g, nnz = 0;
    int *colour = NULL, *count = NULL, *row_start = NULL, *col_idx = NULL, *forbid = NULL;
    size_t room, cap;
    if (n > 0 && (size_t)n > ((size_t)-1 / sizeof(int)) / (size_t)n) return -1;
    room = (size_t)n * (size_t)n; /* a column reaches at most n rows */
    cap = room < 8 * (size_t)n + 1 ? room + 1 : 8 * (size_t)n + 1; /* grows as needed */
    J->row_idx = malloc(cap * sizeof(int));
    J->col_start = calloc((size_t)n + 1, sizeof(int));
    J->group_start = calloc((size_t)n + 2, sizeof(int));
    J->group_cols = calloc((size_t)n + 1, sizeof(int));
    colour = calloc((size_t)n + 1, sizeof(int));
    count = calloc((size_t)n + 2, sizeof(int));
    forbid = calloc((size_t)n + 1, sizeof(int));
    row_start = calloc((size_t)n + 2, sizeof(int));
    if (!J->row_idx || !J->col_start || !J->group_start || !J->group_cols || !colour ||
        !count || !forbid || !row_start)
        goto refuse;
    for (j = 0; j < n; j++) {
        if ((size_t)nnz + (size_t)n > cap) { /* room for one more column's rows */
            int *grown;
            cap = 2 * cap < room + 1 ? 2 * cap : room + 1;
            if ((size_t)nnz + (size_t)n > cap) cap = (size_t)nnz + (size_t)n;
            grown = realloc(J->row_idx, cap * sizeof(int));
            if (!grown) goto refuse;
            J->row_idx = grown;
        }
        J->col_start[j] = nnz;
        reach(J, j, &nnz);
    }
    J->col_start[n] = nnz;
    if ((size_t)nnz * 2 >= room) {
        for (j = 0; j < n; j++) colour[j] = j;
        J->n_groups = n;
    } else {
        /* the pattern by rows, to find the columns sharing a row with j */
        col_idx = malloc((size_t)(nnz > 0 ? nnz : 1) * sizeof(int));
        if (!col_idx) goto refuse;
        for (q = 0; q < nnz; q++) row_start[J->row_idx[q] + 2]++;
        for (r = 0; r < n; r++) row_start[r + 2] += row_start[r + 1];
        for (j = 0; j < n; j++)
            for (q = J->col_start[j]; q < J->col_start[j + 1]; q++)
                col_idx[row_start[J->row_idx[q] + 1]++] = j;
        J->n_groups = 0;
        for (j = 0; j < n; j++) {
            for (q = J->col_start[j]; q < J->col_start[j + 1]; q++) {
                r = J->row_idx[q];
                for (g = row_start[r]; g < row_start[r + 1] && col_idx[g] < j; g++)
                    forbid[colour[col_idx[g]]] = j + 1;
            }
            for (g = 0; g < J->n_groups && forbid[g] == j + 1; g++) {}
            if (g == J->n_groups) J->n_groups++;
            colour[j] = g;
        }
    }
    for (j = 0; j < n; j++) count[colour[j] + 1]++;
    for (g = 0; g < J->n_groups; g++) J->group_start[g + 1] = J->group_start[g] + count[g + 1];
    memset(count, 0, ((size_t)n + 2) * sizeof(int));
    for (j = 0; j < n; j++) J->group_cols[J->group_start[colour[j]] + count[colour[j]]++] = j;
    free(colour); free(count); free(forbid); free(row_start); free(col_idx);
    return 0;
refuse:
    free(colour); free(count); free(forbid); free(row_start); free(col_idx);
    return -1;
}

/* Per instance, how many plain couplings may set its inputs (known) and read its
   outputs (unknown). */
static void coupled_counts(const eng_me_spec *s, int *known, int *unknown)
{
    int k;
    for (k = 0; k < s->n_couplings; k++)
        if (ENG_PLAIN(&s->couplings[k].source)) {
            unknown[s->couplings[k].source.instance]++;
            known[s->couplings[k].target.instance]++;
        }
}

/* Whether instance i enters the Jacobian without what it takes: directional
   derivatives, and the value references of its states and derivatives. */
static int lacks_derivatives(const eng_instance_spec *in, int known, int unknown)
{
    if (in->n_states == 0 && !known && !unknown) return 0; /* nothing of it enters */
    return !in->provides_directional_derivative ||
           (in->n_states > 0 && (!in->state_vr || !in->derivative_vr));
}

int eng_jacobian_possible(const eng_me_spec *s)
{
    int i, ok = 1;
    int *known = calloc((size_t)s->n_instances + 1, sizeof(int));
    int *unknown = calloc((size_t)s->n_instances + 1, sizeof(int));
    if (!known || !unknown) ok = 0;
    if (ok) coupled_counts(s, known, unknown);
    for (i = 0; ok && i < s->n_instances; i++)
        ok = !lacks_derivatives(&s->instances[i], known[i], unknown[i]);
    free(known);
    free(unknown);
    return ok;
}

eng_jacobian *eng_jacobian_plan(const eng_me_spec *s, const int *x_off)
{
    const int nc = s->n_couplings;
    eng_jacobian *J = calloc(1, sizeof *J);
    int i, k, *known = NULL, *unknown = NULL;
    size_t all_known = 0; /* every part's knowns: reach's stack holds each once at most */
    if (!J) return NULL;
    J->n = s->n_instances;
    J->n_x = x_off[s->n_instances];
    J->x_off = x_off;
    J->couplings = s->couplings;
    J->n_couplings = nc;
    J->parts = calloc((size_t)J->n + 1, sizeof *J->parts);
    J->from = calloc((size_t)nc + 1, sizeof(int));
    J->to = calloc((size_t)nc + 1, sizeof(int));
    J->row_part = calloc((size_t)J->n_x + 1, sizeof(int));
    J->list = calloc((size_t)J->n + 1, sizeof(int));
    J->next = calloc((size_t)J->n + 1, sizeof(int));
    J->touched = calloc((size_t)J->n + 1, sizeof(int));
    /* per instance, how many couplings may set its inputs and read its outputs: each
       part's arrays are sized to its own couplings (sizing every part for all of them
       costs instances x couplings) */
    known = calloc((size_t)J->n + 1, sizeof(int));
    unknown = calloc((size_t)J->n + 1, sizeof(int));
    if (!J->parts || !J->from || !J->to || !J->row_part || !J->list || !J->next ||
        !J->touched || !known || !unknown)
        goto refuse;
    for (i = 0; i < J->n; i++)
        for (k = x_off[i]; k < x_off[i + 1]; k++) J->row_part[k] = i;
    coupled_counts(s, known, unknown);
    for (i = 0; i < J->n; i++) {
        const eng_instance_spec *in = &s->instances[i];
        part *p = &J->parts[i];
        p->n_x = in->n_states;
        if (lacks_derivatives(in, known[i], unknown[i])) goto refuse;
        if (p->n_x == 0 && !known[i] && !unknown[i])
            continue; /* nothing of it enters the Jacobian */
        p->known_vr = calloc((size_t)(p->n_x + known[i]) + 1, sizeof(uint32_t));
        p->unknown_vr = calloc((size_t)(p->n_x + unknown[i]) + 1, sizeof(uint32_t));
        p->seed = calloc((size_t)(p->n_x + known[i]) + 1, sizeof(double));
        p->sens = calloc((size_t)(p->n_x + unknown[i]) + 1, sizeof(double));
        p->reach_known = calloc((size_t)(p->n_x + known[i]) + 1, 1);
        p->reach_unknown = calloc((size_t)(p->n_x + unknown[i]) + 1, 1);
        p->out = calloc((size_t)unknown[i] + 1, sizeof(int));
        if (!p->known_vr || !p->unknown_vr || !p->seed || !p->sens || !p->reach_known ||
            !p->reach_unknown || !p->out)
            goto refuse;
        if (p->n_x > 0) { /* a stateless member has no state arrays (NULL): memcpy
                             from NULL is undefined even for 0 bytes */
            memcpy(p->known_vr, in->state_vr, (size_t)p->n_x * sizeof(uint32_t));
            memcpy(p->unknown_vr, in->derivative_vr, (size_t)p->n_x * sizeof(uint32_t));
        }
        p->n_known = p->n_unknown = p->n_x;
    }
    for (k = 0; k < nc; k++) {
        const eng_coupling *c = &s->couplings[k];
        part *source;
        /* discrete, Float32 and array couplings carry nothing here (jacobian.h) */
        if (!ENG_PLAIN(&c->source) || !ENG_PLAIN(&c->target)) {
            J->from[k] = J->to[k] = -1;
            continue;
        }
        source = &J->parts[c->source.instance];
        J->from[k] = slot(source->unknown_vr, &source->n_unknown, c->source.vr);
        J->to[k] = slot(J->parts[c->target.instance].known_vr,
                        &J->parts[c->target.instance].n_known, c->target.vr);
        source->out[source->n_out++] = k;
    }
    for (i = 0; i < J->n; i++) {
        part *p = &J->parts[i];
        if (!p->seed) continue;
        p->dep = calloc((size_t)p->n_unknown * (size_t)p->n_known + 1, 1);
        if (!p->dep) goto refuse;
        feedthrough(p, &s->instances[i]);
        all_known += (size_t)p->n_known;
    }
    J->stack_part = calloc(all_known + 1, sizeof(int));
    J->stack_known = calloc(all_known + 1, sizeof(int));
    if (!J->stack_part || !J->stack_known) goto refuse;
    if (pattern_and_groups(J)) goto refuse;
    free(known); free(unknown);
    return J;
refuse:
    free(known); free(unknown);
    eng_jacobian_free(J);
    return NULL;
}

int eng_jacobian_groups(const eng_jacobian *J) { return J->n_groups; }

long eng_jacobian_evaluations(const eng_jacobian *J) { return J->evaluations; }

long eng_jacobian_plan_checks(const eng_jacobian *J) { return J->plan_checks; }

void eng_jacobian_bandwidth(const eng_jacobian *J, int *kl, int *ku)
{
    int j, q;
    *kl = *ku = 0;
    for (j = 0; j < J->n_x; j++)
        for (q = J->col_start[j]; q < J->col_start[j + 1]; q++) {
            const int d = J->row_idx[q] - j;
            if (d > *kl) *kl = d;
            if (-d > *ku) *ku = -d;
        }
}

int eng_jacobian_eval(eng_jacobian *J, fmu_t **fmus, const int *asleep, double *jac, int *bad)
{
    const size_t n_x = (size_t)J->n_x;
    int g, q, i, k, pass;
    if (n_x > 0) memset(jac, 0, n_x * n_x * sizeof(double));
    clear_touched(J);
    for (g = 0; g < J->n_groups; g++) {
        int n_list = 0;
        clear_touched(J);
        for (q = J->group_start[g]; q < J->group_start[g + 1]; q++) {
            const int j = J->group_cols[q], owner = J->row_part[j];
            part *p = &J->parts[owner];
            if (asleep[owner]) continue;
            p->seed[j - J->x_off[owner]] = 1.0;
            touch(J, owner);
            if (!p->dirty) {
                p->dirty = 1;
                J->list[n_list++] = owner;
            }
        }
        /* each pass evaluates the parts whose seeds changed, then passes their changes
           on; a loop-free chain settles within as many passes as there are instances */
        for (pass = 0; n_list > 0 && pass <= J->n; pass++) {
            int n_next = 0, *swap;
            for (q = 0; q < n_list; q++) {
                part *p = &J->parts[i = J->list[q]];
                p->dirty = 0;
                J->evaluations++;
                if (fmu_directional_derivative(fmus[i], p->unknown_vr, (size_t)p->n_unknown,
                                               p->known_vr, (size_t)p->n_known, p->seed,
                                               p->sens)) {
                    *bad = i;
                    return -1;
                }
            }
            for (q = 0; q < n_list; q++) {
                const part *p = &J->parts[J->list[q]];
                for (k = 0; k < p->n_out; k++) {
                    const eng_coupling *c = &J->couplings[p->out[k]];
                    const int t = c->target.instance;
                    part *target = &J->parts[t];
                    const double v = c->gain * p->sens[J->from[p->out[k]]];
                    if (asleep[t] || v == target->seed[J->to[p->out[k]]]) continue;
                    target->seed[J->to[p->out[k]]] = v;
                    touch(J, t);
                    if (!target->dirty) {
                        target->dirty = 1;
                        J->next[n_next++] = t;
                    }
                }
            }
            swap = J->list; J->list = J->next; J->next = swap;
            n_list = n_next;
        }
        if (n_list > 0) return 1;
        /* the group's columns apart: each row in a column's pattern is that column's
           alone within the group */
        for (q = J->group_start[g]; q < J->group_start[g + 1]; q++) {
            const int j = J->group_cols[q];
            int r;
            for (r = J->col_start[j]; r < J->col_start[j + 1]; r++) {
                const int row = J->row_idx[r], owner = J->row_part[row];
                jac[(size_t)j * n_x + (size_t)row] =
                    asleep[owner] ? 0.0 : J->parts[owner].sens[row - J->x_off[owner]];
            }
        }
    }
    clear_touched(J);
    return 0;
}
