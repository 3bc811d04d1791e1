/*
 * assembly_config.c: reads resources/assembly.txt (see assembly_config.h).
 *
 * The file is input, not code: whoever made the FMU may have written anything into it.
 * Every count is bounded by what the rest of the file can hold before anything is
 * allocated, every number by the range its master can run, every value reference that
 * indexes an array of this FMU by that array's size, and every name that becomes a
 * path or a symbol is a plain name whose folder lies inside the FMU's resources/.
 */
#define _XOPEN_SOURCE 700 /* realpath */
#include "assembly_config.h"

#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_NAME 200          /* an instance name or model identifier */
#define MAX_TOKEN 1000        /* an instantiation token */
#define MAX_TOTAL (1L << 24)  /* states or indicators of all members together */

typedef struct {
    char *at;             /* next unread character */
    const char *end;      /* the terminating '\0' of the text */
    const char *section;  /* for messages */
    int failed;
    char *err;
    size_t err_len;
} reader;

static void complain(reader *r, const char *fmt, ...)
{
    va_list ap;
    int n;
    if (r->failed) return;
    r->failed = 1;
    n = snprintf(r->err, r->err_len, "resources/assembly.txt, section '%s': ", r->section);
    va_start(ap, fmt);
    if (n >= 0 && (size_t)n < r->err_len) vsnprintf(r->err + n, r->err_len - (size_t)n, fmt, ap);
    va_end(ap);
}

/* The next whitespace-separated token, terminated in place; "" at the end. */
static const char *word(reader *r)
{
    char *start;
    if (r->failed) return "";
    while (*r->at == ' ' || *r->at == '\n' || *r->at == '\t' || *r->at == '\r') r->at++;
    start = r->at;
    while (*r->at && *r->at != ' ' && *r->at != '\n' && *r->at != '\t' && *r->at != '\r') r->at++;
    if (*r->at) *r->at++ = '\0';
    if (!*start) complain(r, "the file ends early");
    return start;
}

static void expect(reader *r, const char *keyword)
{
    const char *w = word(r);
    r->section = keyword;
    if (!r->failed && strcmp(w, keyword) != 0) complain(r, "expected '%s', found '%s'", keyword, w);
}

static double number(reader *r)
{
    const char *w = word(r);
    char *end;
    double v = strtod(w, &end);
    if (!r->failed && (*end || end == w)) complain(r, "'%s' is not a number", w);
    return v;
}

static long integer(reader *r, long lo, long hi)
{
    const char *w = word(r);
    char *end;
    long v = strtol(w, &end, 10);
    if (!r->failed && (*end || end == w || v < lo || v > hi))
        complain(r, "'%s' is not an integer in [%ld, %ld]", w, lo, hi);
    return r->failed ? lo : v;
}

/* A count of entries that take at least `tokens` tokens each: no more than the rest of
   the file can hold (each token is a character and a separator), so that a count of
   1e9 is refused before it is allocated. */
static int count(reader *r, long lo, long tokens)
{
    long room = r->failed ? 0 : (long)((r->end - r->at) / (2 * tokens));
    return (int)integer(r, lo, room < lo ? lo : (room < (1L << 30) ? room : (1L << 30)));
}

/* A finite number in [lo, hi]: `what` names the setting in the message. */
static double bounded(reader *r, const char *what, double lo, double hi)
{
    double v = number(r);
    if (!r->failed && !(isfinite(v) && v >= lo && v <= hi))
        complain(r, "%s %g is not a finite number in [%g, %g]", what, v, lo, hi);
    return v;
}

/* A name that becomes part of a path or a symbol: 1 to MAX_NAME characters of
   letters, digits and '_' (and, for an instance, '-' and '.' but not first), so that
   it cannot name a folder above resources/ or a library outside the member. */
static const char *plain_name(reader *r, const char *what, int identifier)
{
    const char *w = word(r), *c;
    size_t n = strlen(w);
    int ok = n > 0 && n <= MAX_NAME && w[0] != '.' && w[0] != '-'
             && !(identifier && w[0] >= '0' && w[0] <= '9');
    for (c = w; ok && *c; c++)
        ok = (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9')
             || *c == '_' || (!identifier && (*c == '-' || *c == '.'));
    if (!r->failed && !ok)
        complain(r, "%s '%.200s' is not a plain name (%s, at most %d characters)", what, w,
                 identifier ? "a C identifier: letters, digits and '_'"
                            : "letters, digits, '_', '-' and '.', not starting with '.' or '-'",
                 MAX_NAME);
    return w;
}

/* The member's folder, resolved (links too), must lie inside resources/. */
static void confined(reader *r, const char *resources_dir, const char *folder, const char *name)
{
    char *root, *real;
    size_t n;
    if (r->failed) return;
    root = realpath(resources_dir, NULL);
    real = realpath(folder, NULL);
    if (!root || !real)
        complain(r, "instance '%s': its folder resources/%s is missing", name, name);
    else if (n = strlen(root), strncmp(real, root, n) != 0 || real[n] != '/')
        complain(r, "instance '%s': resources/%s leads outside the FMU's resources (to %.300s)",
                 name, name, real);
    free(root);
    free(real);
}

static void *table(reader *r, size_t n, size_t size)
{
    void *p = calloc(n > 0 ? n : 1, size);
    if (!p) complain(r, "out of memory");
    return p;
}

static void variable(reader *r, eng_variable *v, int n_instances)
{
    v->instance = (int)integer(r, 0, n_instances - 1);
    v->vr = (uint32_t)integer(r, 0, 0xffffffffL);
    v->type = (int)integer(r, ENG_FLOAT64, ENG_INT32); /* what an assembly FMU passes on */
}

static void instance(reader *r, asm_config *cfg, int i, const char *resources_dir)
{
    eng_instance_spec *s = &cfg->instances[i];
    uint32_t *vr;
    double *fv;
    int32_t *iv;
    int k;
    size_t len;
    expect(r, "instance");
    s->instance_name = plain_name(r, "instance name", 0);
    s->model_identifier = plain_name(r, "model identifier", 1);
    s->instantiation_token = word(r);
    if (!r->failed && strlen(s->instantiation_token) > MAX_TOKEN)
        complain(r, "instance '%s': instantiation token longer than %d characters",
                 s->instance_name, MAX_TOKEN);
    s->fmi_version = (int)integer(r, 2, 3);
    s->n_states = (int)integer(r, 0, MAX_TOTAL);
    s->n_event_indicators = (int)integer(r, 0, MAX_TOTAL);
    s->can_get_set_state = (int)integer(r, 0, 1);
    s->provides_directional_derivative = (int)integer(r, 0, 1);
    if (r->failed) return;
    /* the members are carried extracted, each in resources/<instance name>/ */
    len = strlen(resources_dir) + strlen(s->instance_name) + 2;
    cfg->unzip_dirs[i] = (char *)table(r, len, 1);
    if (r->failed) return;
    snprintf(cfg->unzip_dirs[i], len, "%s/%s", resources_dir, s->instance_name);
    s->unzip_dir = cfg->unzip_dirs[i];
    confined(r, resources_dir, s->unzip_dir, s->instance_name);
    s->n_float_starts = count(r, 0, 2);
    vr = (uint32_t *)table(r, (size_t)s->n_float_starts, sizeof *vr);
    fv = (double *)table(r, (size_t)s->n_float_starts, sizeof *fv);
    s->float_start_vr = vr;
    s->float_start_values = fv;
    for (k = 0; k < s->n_float_starts && !r->failed; k++) {
        vr[k] = (uint32_t)integer(r, 0, 0xffffffffL);
        fv[k] = number(r);
    }
    s->n_int_starts = count(r, 0, 2);
    vr = (uint32_t *)table(r, (size_t)s->n_int_starts, sizeof *vr);
    iv = (int32_t *)table(r, (size_t)s->n_int_starts, sizeof *iv);
    s->int_start_vr = vr;
    s->int_start_values = iv;
    for (k = 0; k < s->n_int_starts && !r->failed; k++) {
        vr[k] = (uint32_t)integer(r, 0, 0xffffffffL);
        iv[k] = (int32_t)integer(r, -2147483647L - 1, 2147483647L);
    }
}

static int read_all(const char *path, char **text)
{
    FILE *f = fopen(path, "rb");
    long n;
    if (!f) return -1;
    /* a description is kilobytes: 64 MiB is far beyond any, and bounds the allocation */
    if (fseek(f, 0, SEEK_END) || (n = ftell(f)) < 0 || n > (64L << 20)
        || fseek(f, 0, SEEK_SET)) {
        fclose(f);
        return -1;
    }
    *text = (char *)malloc((size_t)n + 1);
    if (!*text || fread(*text, 1, (size_t)n, f) != (size_t)n) {
        fclose(f);
        return -1;
    }
    (*text)[n] = '\0';
    fclose(f);
    return 0;
}

int asm_config_read(asm_config *cfg, const char *resources_dir, char *err, size_t err_len)
{
    eng_cosim_spec *g = &cfg->spec;
    reader r = {0};
    char path[4096];
    int i, j, k, n, rated;
    memset(cfg, 0, sizeof *cfg);
    snprintf(path, sizeof path, "%s/assembly.txt", resources_dir);
    if (read_all(path, &cfg->text)) {
        snprintf(err, err_len, "cannot read %s (is the resource location right?)", path);
        asm_config_free(cfg);
        return -1;
    }
    r.at = cfg->text;
    r.end = cfg->text + strlen(cfg->text);
    r.section = "mechfmu-assembly";
    r.err = err;
    r.err_len = err_len;

    expect(&r, "mechfmu-assembly");
    if (integer(&r, 1, 1) != 1) complain(&r, "unknown format version");
    expect(&r, "token");
    cfg->token = word(&r);
    expect(&r, "mode");
    {
        const char *mode = word(&r);
        cfg->mode = strcmp(mode, "me") == 0 ? ASM_ME : ASM_COSIM;
        if (!r.failed && cfg->mode == ASM_COSIM && strcmp(mode, "cosim") != 0)
            complain(&r, "mode '%s' is neither cosim nor me", mode);
    }
    /* the ranges the Python side checks before it writes them (check_experiment,
       check_tolerance, check_cosim_settings) */
    expect(&r, "settings");
    g->stop_time = bounded(&r, "stop time", 1e-300, 1e300);
    g->tolerance = bounded(&r, "tolerance", 1e-14, 0.5);
    g->step = bounded(&r, "communication step", 1e-300, 1e300);
    g->scheme = (int)integer(&r, ENG_JACOBI, ENG_GAUSS_SEIDEL);
    g->extrapolation = (int)integer(&r, 0, 3);
    g->adaptive = (int)integer(&r, 0, 1);
    g->tol = bounded(&r, "adaptive tolerance tol", 1e-300, 0.5);
    g->loop_tolerance = bounded(&r, "loop tolerance", 1e-300, 1e300);
    g->max_loop_iterations = (int)integer(&r, 1, 1000);
    g->newton = (int)integer(&r, 0, 1);
    g->event_sync = (int)integer(&r, 0, 1);
    g->event_tol = bounded(&r, "event tolerance", 1e-300, 1e300);
    cfg->me_spec.method = (int)integer(&r, ENG_DOPRI5, ENG_AUTO);
    cfg->me_spec.event_subsamples = (int)integer(&r, 0, 1000);
    /* 0: none; else no shorter than a millionth of the step, which the export writes
       (1e-300 would make every doStep a budget's worth of steps that go nowhere) */
    cfg->me_spec.max_step = number(&r);
    if (!r.failed && cfg->me_spec.max_step != 0.0
        && !(isfinite(cfg->me_spec.max_step) && cfg->me_spec.max_step >= 1e-6 * g->step))
        complain(&r, "max_step %g is neither 0 (no limit) nor a finite step of at least 1e-6 "
                 "x the communication step %g", cfg->me_spec.max_step, g->step);

    expect(&r, "instances");
    g->n_instances = n = count(&r, 1, 11);
    cfg->instances = (eng_instance_spec *)table(&r, (size_t)n, sizeof *cfg->instances);
    cfg->unzip_dirs = (char **)table(&r, (size_t)n, sizeof *cfg->unzip_dirs);
    g->instances = cfg->instances;
    for (i = 0; i < n && !r.failed; i++) instance(&r, cfg, i, resources_dir);
    {
        long states = 0, indicators = 0;
        for (i = 0; i < n && !r.failed; i++) {
            states += cfg->instances[i].n_states;
            indicators += cfg->instances[i].n_event_indicators;
        }
        if (!r.failed && (states > MAX_TOTAL || indicators > MAX_TOTAL))
            complain(&r, "%ld states and %ld event indicators in all, more than %ld", states,
                     indicators, MAX_TOTAL);
        cfg->n_indicators = (int)indicators;
    }

    expect(&r, "couplings");
    g->n_couplings = n = count(&r, 0, 9);
    cfg->couplings = (eng_coupling *)table(&r, (size_t)n, sizeof *cfg->couplings);
    cfg->held = (int *)table(&r, (size_t)n, sizeof(int));
    cfg->derivative = (int *)table(&r, (size_t)n, sizeof(int));
    cfg->rates = (eng_variable *)table(&r, ENG_RATES * (size_t)n, sizeof(eng_variable));
    g->couplings = cfg->couplings;
    g->held = cfg->held;
    g->derivative = cfg->derivative;
    g->rates = cfg->rates;
    for (k = 0; k < n && !r.failed; k++) {
        expect(&r, "coupling");
        variable(&r, &cfg->couplings[k].source, g->n_instances);
        variable(&r, &cfg->couplings[k].target, g->n_instances);
        cfg->couplings[k].gain = number(&r);
        cfg->held[k] = (int)integer(&r, 0, 1);
        cfg->derivative[k] = (int)integer(&r, -1, n - 1);
        rated = (int)integer(&r, 0, ENG_RATES); /* its target's rate inputs (then -1) */
        for (j = 0; j < ENG_RATES && cfg->rates; j++) {
            if (j < rated) variable(&r, &cfg->rates[ENG_RATES * k + j], g->n_instances);
            else cfg->rates[ENG_RATES * k + j].instance = -1;
        }
    }

    expect(&r, "groups");
    g->n_groups = n = count(&r, 0, 3);
    cfg->group_start = (int *)table(&r, (size_t)n + 1, sizeof(int));
    cfg->group_is_loop = (int *)table(&r, (size_t)n, sizeof(int));
    cfg->group_members = (int *)table(&r, (size_t)g->n_couplings, sizeof(int));
    g->group_start = cfg->group_start;
    g->group_is_loop = cfg->group_is_loop;
    g->group_members = cfg->group_members;
    for (k = 0, i = 0; k < n && !r.failed; k++) {
        int m, size;
        expect(&r, "group");
        cfg->group_is_loop[k] = (int)integer(&r, 0, 1);
        size = (int)integer(&r, 1, g->n_couplings - i);
        cfg->group_start[k] = i;
        for (m = 0; m < size && !r.failed; m++)
            cfg->group_members[i++] = (int)integer(&r, 0, g->n_couplings - 1);
    }
    cfg->group_start[n] = i;

    expect(&r, "sweep");
    cfg->sweep_order = (int *)table(&r, (size_t)g->n_instances, sizeof(int));
    g->sweep_order = cfg->sweep_order;
    {   /* each instance once: a repeated one would be stepped twice in a sweep */
        char *seen = (char *)table(&r, (size_t)g->n_instances, 1);
        for (i = 0; i < g->n_instances && !r.failed; i++) {
            int j = cfg->sweep_order[i] = (int)integer(&r, 0, g->n_instances - 1);
            if (!r.failed && seen[j]++) complain(&r, "instance %d comes twice", j);
        }
        free(seen);
    }

    expect(&r, "states");
    g->n_states = n = count(&r, 0, 3);
    cfg->states = (eng_variable *)table(&r, (size_t)n, sizeof *cfg->states);
    g->states = cfg->states;
    for (k = 0; k < n && !r.failed; k++) variable(&r, &cfg->states[k], g->n_instances);

    expect(&r, "ports");
    cfg->n_ports = n = count(&r, 0, 6);
    cfg->ports = (asm_port *)table(&r, (size_t)n, sizeof *cfg->ports);
    for (k = 0; k < n && !r.failed; k++) {
        const char *causality;
        expect(&r, "port");
        cfg->ports[k].vr = (uint32_t)integer(&r, 1, 0xffffffffL);
        causality = word(&r);
        if (strcmp(causality, "input") == 0) cfg->ports[k].kind = ASM_INPUT;
        else if (strcmp(causality, "output") == 0) cfg->ports[k].kind = ASM_OUTPUT;
        else if (strcmp(causality, "local") == 0) cfg->ports[k].kind = ASM_LOCAL;
        else if (strcmp(causality, "indicator") == 0) cfg->ports[k].kind = ASM_INDICATOR;
        else complain(&r, "port kind '%s' is not input, output, local or indicator", causality);
        variable(&r, &cfg->ports[k].member, g->n_instances);
        /* an indicator's vr indexes the coupled system's indicator array */
        if (!r.failed && cfg->ports[k].kind == ASM_INDICATOR
            && (cfg->mode != ASM_ME || cfg->ports[k].member.type != ENG_FLOAT64
                || cfg->ports[k].member.vr >= (uint32_t)cfg->n_indicators))
            complain(&r, "port %u: event indicator %u is not one of the %d indicators of a "
                     "Model Exchange assembly", cfg->ports[k].vr, cfg->ports[k].member.vr,
                     cfg->mode == ASM_ME ? cfg->n_indicators : 0);
    }
    expect(&r, "end");
    cfg->me_spec.n_instances = g->n_instances;
    cfg->me_spec.instances = g->instances;
    cfg->me_spec.n_couplings = g->n_couplings; /* written in the order the mode evaluates */
    cfg->me_spec.couplings = g->couplings;
    cfg->me_spec.stop_time = g->stop_time;
    cfg->me_spec.tolerance = g->tolerance;
    if (cfg->mode == ASM_ME && !r.failed) {
        /* the groups of a Model Exchange assembly are its algebraic loops, each a run of
           consecutive couplings in the order written (eng_me_spec.n_loops) */
        int n_loops = 0;
        cfg->loop_first = (int *)table(&r, (size_t)g->n_groups, sizeof(int));
        cfg->loop_count = (int *)table(&r, (size_t)g->n_groups, sizeof(int));
        for (k = 0; k < g->n_groups && !r.failed; k++) {
            const int start = cfg->group_start[k], size = cfg->group_start[k + 1] - start;
            int m;
            if (!cfg->group_is_loop[k]) continue;
            for (m = 0; m < size; m++)
                if (cfg->group_members[start + m] != cfg->group_members[start] + m)
                    complain(&r, "group %d: a Model Exchange loop's couplings must be "
                                 "consecutive", k);
            cfg->loop_first[n_loops] = cfg->group_members[start];
            cfg->loop_count[n_loops++] = size;
        }
        cfg->me_spec.n_loops = n_loops;
        cfg->me_spec.loop_first = cfg->loop_first;
        cfg->me_spec.loop_count = cfg->loop_count;
    }

    if (r.failed) {
        asm_config_free(cfg);
        return -1;
    }
    return 0;
}

void asm_config_free(asm_config *cfg)
{
    int i;
    if (cfg->instances) {
        for (i = 0; i < cfg->spec.n_instances; i++) {
            free((void *)cfg->instances[i].float_start_vr);
            free((void *)cfg->instances[i].float_start_values);
            free((void *)cfg->instances[i].int_start_vr);
            free((void *)cfg->instances[i].int_start_values);
            if (cfg->unzip_dirs) free(cfg->unzip_dirs[i]);
        }
    }
    free(cfg->instances);
    free(cfg->unzip_dirs);
    free(cfg->couplings);
    free(cfg->held);
    free(cfg->derivative);
    free(cfg->rates);
    free(cfg->group_start);
    free(cfg->group_members);
    free(cfg->group_is_loop);
    free(cfg->sweep_order);
    free(cfg->states);
    free(cfg->loop_first);
    free(cfg->loop_count);
    free(cfg->ports);
    free(cfg->text);
    memset(cfg, 0, sizeof *cfg);
}
