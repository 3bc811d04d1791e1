/*
 * linear_map.h: where the coefficients of members taken as linear maps between
 * events go (a spring's forces: y = y0 + J (u - u0)). Both masters take such members
 * (me.c linear_map, cosim.c evaluated), each from its own facts; the layout of their
 * coupled inputs and of the rows of J is one.
 */
#ifndef MECHFMU_ENGINE_LINEAR_MAP_H
#define MECHFMU_ENGINE_LINEAR_MAP_H

#include <stddef.h>

#include "engine.h"

/* The most coefficients all linear maps of a run keep together; a member whose rows
   would pass it is evaluated as any other. */
#define ENG_LINEAR_MAP_MAX_ENTRIES ((size_t)1 << 24)

/* The couplings into each of n instances, in coupling order: list[start[i] ..
   start[i + 1] - 1] for instance i, where take[i] (every instance with take NULL).
   start has n + 1 entries, list nc. */
void eng_inputs_by_target(const eng_coupling *c, int nc, int n, const int *take, int *start,
                          int *list);

/* For each coupling k out of an instance i with kind[i] == linear, row[k]: the offset
   of its row of d output / d input in one array, as wide as i's inputs (start, from
   eng_inputs_by_target). An instance whose rows would pass ENG_LINEAR_MAP_MAX_ENTRIES
   is refused (kind[i] = 0). Returns the entries in all. */
size_t eng_linear_rows(const eng_coupling *c, int nc, const int *start, int *kind, int linear,
                       int *row);

#endif
