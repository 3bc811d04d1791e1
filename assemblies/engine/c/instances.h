/*
 * instances.h: an assembly's FMU instances as the masters use them: loaded with
 * their start values, read and written across value types, coupled.
 */
#ifndef MECHFMU_ENGINE_INSTANCES_H
#define MECHFMU_ENGINE_INSTANCES_H

#include <stddef.h>

#include "engine.h"
#include "fmu.h"

/* Loads one instance and sets its parameters and start values. NULL on failure,
   the reason in err. */
fmu_t *eng_instantiate(const eng_instance_spec *spec, fmu_kind kind,
                       fmu_intermediate_fn intermediate, void *intermediate_ctx,
                       int early_return_allowed, char *err, size_t err_len);

/* One value of any type as a double (a String as its index in the thread's string
   table, an array element through its whole array). FMU_OK or the fmu.h error code. */
int eng_get_value(fmu_t *fmu, const eng_variable *v, double *value);
int eng_set_value(fmu_t *fmu, const eng_variable *v, double value);

/* Evaluates the couplings in order: target = gain * source. values[i] (may be NULL)
   receives coupling i's value. On failure *failed is the index of the instance whose
   call failed and FMU_ERROR is returned. */
int eng_propagate(fmu_t **fmus, const eng_coupling *couplings, int n_couplings, double *values,
                  int *failed);

/* "<instance>: <what> failed at t = ...: <FMU message>" into message. */
void eng_describe_failure(char *message, size_t len, fmu_t *fmu, const char *what, double t);

#endif
