/*
 * restore_check.h: whether an FMU's state restore can be trusted, checked once.
 *
 * Several exporters declare canGetAndSetFMUState while their fmiSetFMUState restores
 * part of the state, or nothing; a master that rolls back through such a restore is
 * silently wrong (1-23 % off on foreign FMUs, no warning). Before a run rolls back
 * through an FMU it did not build, the caller (assemblies/engine/restore.py) asks here
 * once: on an instance of its own (a restore that does nothing would leave the run's
 * instance ahead), initialised as the run's would be, the check saves the state at
 * the start, takes one doStep, reads the compared variables, restores, reads them
 * again, takes the same doStep again and reads them a third time. The restore is
 * exact when the values after the restore are the start's and the second step's the
 * first's, bit for bit: from a state really restored, an FMU computes the same.
 */
#ifndef MECHFMU_ENGINE_RESTORE_CHECK_H
#define MECHFMU_ENGINE_RESTORE_CHECK_H

#include <stdint.h>

#include "engine.h"

enum { ENG_RESTORE_EXACT = 1, ENG_RESTORE_INEXACT = 0, ENG_RESTORE_UNCHECKED = -1 };

typedef struct {
    int verdict;       /* ENG_RESTORE_EXACT, _INEXACT, or _UNCHECKED (message says why) */
    int which;         /* inexact: the index of the first variable that differed */
    int after_step;    /* ... 0: right after the restore, 1: after the repeated doStep */
    double expected;   /* its value before (at the start, or after the first doStep) */
    double got;        /* ... and after the restore */
    char message[1024];
} eng_restore_check;

/* Checks `spec`'s Co-Simulation restore over one doStep of `step` from 0 (the solver
   tolerance `tolerance`, 0: the FMU's own), comparing the n variables (any type; their
   `instance` is not read);
   a variable whose first read fails is left out (a type the engine does not read). */
ENG_API void eng_check_restore(const eng_instance_spec *spec, double step, double tolerance,
                               int n, const eng_variable *vars, eng_restore_check *result);

#endif
