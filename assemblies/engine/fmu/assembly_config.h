/*
 * assembly_config.h: what an assembly FMU reads from resources/assembly.txt when it
 * is instantiated: the engine's co-simulation spec (members, couplings, loops,
 * scheme) and the FMU's own interface, each variable mapped onto a member's.
 *
 * The file is written by assemblies/fmu_export.py: whitespace-separated tokens,
 * section keywords first, so that a file from another version fails with a message
 * naming the section instead of being misread.
 */
#ifndef MECHFMU_ASSEMBLY_CONFIG_H
#define MECHFMU_ASSEMBLY_CONFIG_H

#include <stddef.h>
#include <stdint.h>

#include "cosim.h"
#include "me.h"

/* what a variable of the assembly FMU is */
enum {
    ASM_INPUT,     /* a member's input, set by the importer */
    ASM_OUTPUT,    /* a member's output */
    ASM_LOCAL,     /* a member's continuous state or its derivative (Model Exchange) */
    ASM_INDICATOR  /* event indicator member.vr of the coupled system (FMI 3 ME) */
};

typedef struct {
    uint32_t vr;          /* the assembly FMU's value reference */
    int kind;             /* ASM_INPUT ... ASM_INDICATOR */
    eng_variable member;  /* the member's variable behind it */
} asm_port;

/* the master the FMU runs in its doStep */
enum { ASM_COSIM = 0, ASM_ME = 1 };

typedef struct {
    char *text;           /* the file's contents; every string below points into it */
    const char *token;    /* the instantiation token the FMU was exported with */
    int mode;             /* ASM_COSIM: members are Co-Simulation FMUs; ASM_ME: Model
                             Exchange FMUs in the engine's one integrator */
    eng_cosim_spec spec;  /* ASM_COSIM */
    eng_me_spec me_spec;  /* ASM_ME: the same instances and couplings */
    int n_ports;
    asm_port *ports;
    int n_indicators;     /* the members' event indicators together */
    /* what spec points to */
    eng_instance_spec *instances;
    char **unzip_dirs;
    eng_coupling *couplings;
    eng_variable *rates;  /* ENG_RATES per coupling (eng_cosim_spec.rates) */
    int *held, *derivative, *group_start, *group_members, *group_is_loop, *sweep_order;
    eng_variable *states;
    int *loop_first, *loop_count; /* ASM_ME: the loop groups as me_spec's loops */
} asm_config;

/* 0, or -1 with the reason in err (the config is then freed). */
int asm_config_read(asm_config *cfg, const char *resources_dir, char *err, size_t err_len);
void asm_config_free(asm_config *cfg);

#endif
