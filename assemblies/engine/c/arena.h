/*
 * arena.h: the zeroed arrays of one engine run taken from a few large blocks instead
 * of a calloc each, and given back all at once. A short run of the Model Exchange
 * master allocates some sixty arrays that live exactly as long as the run; their
 * callocs and frees cost it more than its integration (issue 27).
 *
 * Under AddressSanitizer each array is followed by a poisoned gap, so that an overrun
 * from one array into the next is still reported as it would be between callocs.
 */
#ifndef MECHFMU_ENGINE_ARENA_H
#define MECHFMU_ENGINE_ARENA_H

#include <stddef.h>

typedef struct eng_arena_block eng_arena_block;

typedef struct {
    eng_arena_block *blocks; /* the newest first; NULL: nothing taken yet */
} eng_arena;

/* n zeroed elements of `size` bytes, aligned for any type; NULL when out of memory or
   when n * size does not fit in a size_t. n = 0 gives a valid (empty) array. */
void *eng_arena_take(eng_arena *a, size_t n, size_t size);
/* Gives back every array taken; the arena is empty and usable again. */
void eng_arena_free(eng_arena *a);

#endif
