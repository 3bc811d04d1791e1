/*
 * assembly_config.c: reads resources/assembly.txt (see assembly_config.h).
 */
#include "assembly_config.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    char *at;             /* next unread character */
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
    s->instance_name = word(r);
    s->model_identifier = word(r);
    s->instantiation_token = word(r);
    s->fmi_version = (int)integer(r, 2, 3);
    s->n_states = (int)integer(r, 0, 1L << 30);
    s->n_event_indicators = (int)integer(r, 0, 1L << 30);
    s->can_get_set_state = (int)integer(r, 0, 1);
    s->provides_directional_derivative = (int)integer(r, 0, 1);
    if (r->failed) return;
    /* the members are carried extracted, each in resources/<instance name>/ */
    len = strlen(resources_dir) + strlen(s->instance_name) + 2;
    cfg->unzip_dirs[i] = (char *)table(r, len, 1);
    if (r->failed) return;
    snprintf(cfg->unzip_dirs[i], len, "%s/%s", resources_dir, s->instance_name);
    s->unzip_dir = cfg->unzip_dirs[i];
    s->n_float_starts = (int)integer(r, 0, 1L << 30);
    vr = (uint32_t *)table(r, (size_t)s->n_float_starts, sizeof *vr);
    fv = (double *)table(r, (size_t)s->n_float_starts, sizeof *fv);
    s->float_start_vr = vr;
    s->float_start_values = fv;
    for (k = 0; k < s->n_float_starts && !r->failed; k++) {
        vr[k] = (uint32_t)integer(r, 0, 0xffffffffL);
        fv[k] = number(r);
    }
    s->n_int_starts = (int)integer(r, 0, 1L << 30);
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
    if (fseek(f, 0, SEEK_END) || (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET)) {
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
    int i, k, n;
    memset(cfg, 0, sizeof *cfg);
    snprintf(path, sizeof path, "%s/assembly.txt", resources_dir);
    if (read_all(path, &cfg->text)) {
        snprintf(err, err_len, "cannot read %s (is the resource location right?)", path);
        asm_config_free(cfg);
        return -1;
    }
    r.at = cfg->text;
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
    expect(&r, "settings");
    g->stop_time = number(&r);
    g->tolerance = number(&r);
    g->step = number(&r);
    g->scheme = (int)integer(&r, ENG_JACOBI, ENG_GAUSS_SEIDEL);
    g->extrapolation = (int)integer(&r, 0, 2);
    g->adaptive = (int)integer(&r, 0, 1);
    g->tol = number(&r);
    g->loop_tolerance = number(&r);
    g->max_loop_iterations = (int)integer(&r, 1, 1L << 20);
    g->newton = (int)integer(&r, 0, 1);
    g->event_sync = (int)integer(&r, 0, 1);
    g->event_tol = number(&r);
    cfg->me_spec.method = (int)integer(&r, ENG_DOPRI5, ENG_AUTO);
    cfg->me_spec.event_subsamples = (int)integer(&r, 0, 1000);
    cfg->me_spec.max_step = number(&r);

    expect(&r, "instances");
    g->n_instances = n = (int)integer(&r, 1, 1L << 20);
    cfg->instances = (eng_instance_spec *)table(&r, (size_t)n, sizeof *cfg->instances);
    cfg->unzip_dirs = (char **)table(&r, (size_t)n, sizeof *cfg->unzip_dirs);
    g->instances = cfg->instances;
    for (i = 0; i < n && !r.failed; i++) instance(&r, cfg, i, resources_dir);

    expect(&r, "couplings");
    g->n_couplings = n = (int)integer(&r, 0, 1L << 20);
    cfg->couplings = (eng_coupling *)table(&r, (size_t)n, sizeof *cfg->couplings);
    cfg->held = (int *)table(&r, (size_t)n, sizeof(int));
    cfg->derivative = (int *)table(&r, (size_t)n, sizeof(int));
    g->couplings = cfg->couplings;
    g->held = cfg->held;
    g->derivative = cfg->derivative;
    for (k = 0; k < n && !r.failed; k++) {
        expect(&r, "coupling");
        variable(&r, &cfg->couplings[k].source, g->n_instances);
        variable(&r, &cfg->couplings[k].target, g->n_instances);
        cfg->couplings[k].gain = number(&r);
        cfg->held[k] = (int)integer(&r, 0, 1);
        cfg->derivative[k] = (int)integer(&r, -1, n - 1);
    }

    expect(&r, "groups");
    g->n_groups = n = (int)integer(&r, 0, 1L << 20);
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
    for (i = 0; i < g->n_instances && !r.failed; i++)
        cfg->sweep_order[i] = (int)integer(&r, 0, g->n_instances - 1);

    expect(&r, "states");
    g->n_states = n = (int)integer(&r, 0, 1L << 24);
    cfg->states = (eng_variable *)table(&r, (size_t)n, sizeof *cfg->states);
    g->states = cfg->states;
    for (k = 0; k < n && !r.failed; k++) variable(&r, &cfg->states[k], g->n_instances);

    expect(&r, "ports");
    cfg->n_ports = n = (int)integer(&r, 0, 1L << 24);
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
    }
    expect(&r, "end");
    cfg->me_spec.n_instances = g->n_instances;
    cfg->me_spec.instances = g->instances;
    cfg->me_spec.n_couplings = g->n_couplings; /* written in the order the mode evaluates */
    cfg->me_spec.couplings = g->couplings;
    cfg->me_spec.stop_time = g->stop_time;
    cfg->me_spec.tolerance = g->tolerance;

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
    free(cfg->group_start);
    free(cfg->group_members);
    free(cfg->group_is_loop);
    free(cfg->sweep_order);
    free(cfg->states);
    free(cfg->ports);
    free(cfg->text);
    memset(cfg, 0, sizeof *cfg);
}
