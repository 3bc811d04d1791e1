/*
 * me.h: the engine's Model Exchange master one communication step at a time, for an
 * FMU that runs an assembly of Model Exchange FMUs in its doStep (assembly_runtime.c).
 * A run from Python takes the whole experiment in one call instead (engine.h,
 * eng_simulate_me); both integrate the same way.
 *
 * The spec must outlive the handle; its output fields (times, out, columns, event
 * groups) are not used. Every call returns 0 or ENG_FAILED, after which
 * eng_me_message says why in one line.
 */
#ifndef MECHFMU_ENGINE_ME_H
#define MECHFMU_ENGINE_ME_H

#include "engine.h"
#include "fmu.h"

typedef struct eng_me eng_me;

/* Loads the members with their start values. NULL only when memory runs out; a
   member that did not load: eng_me_failed. */
eng_me *eng_me_create(const eng_me_spec *spec);
int eng_me_failed(const eng_me *m);
int eng_me_enter_initialization(eng_me *m, double start_time);
int eng_me_exit_initialization(eng_me *m);
/* A member's input was set from outside: the next advance starts with an event, since
   the new value may switch a mode (a force past the static friction limit). */
void eng_me_inputs_changed(eng_me *m);
/* Integrates until `target`, or until a member ends the simulation (eng_me_terminated).
   The members are left at the point reached, so their outputs can be read. */
int eng_me_advance(eng_me *m, double target);
double eng_me_time(const eng_me *m);
int eng_me_terminated(const eng_me *m);
fmu_t *eng_me_member(eng_me *m, int i);
const char *eng_me_message(const eng_me *m);
void eng_me_free(eng_me *m);

/* The same coupled members offered as one Model Exchange FMU, the importer's
   integrator driving them: time and states are the importer's, events are handled
   when it asks (the engine's event iteration through the couplings). */
int eng_me_number_of_states(const eng_me *m);
int eng_me_number_of_indicators(const eng_me *m);
void eng_me_set_time(eng_me *m, double t);
void eng_me_set_states(eng_me *m, const double *x);
void eng_me_get_states(const eng_me *m, double *x);
void eng_me_get_nominals(const eng_me *m, double *nominals);
int eng_me_sync(eng_me *m);
int eng_me_derivatives(eng_me *m, double *dx);
int eng_me_indicators(eng_me *m, double *z);
int eng_me_event_update(eng_me *m, int *states_changed);
int eng_me_completed_step(eng_me *m, int *enter_event_mode);

#endif
