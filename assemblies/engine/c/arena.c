/*
 * arena.c: one run's arrays from a few blocks (arena.h).
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "arena.h"

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/asan_interface.h>
#define GAP 32 /* bytes poisoned after each array: an overrun into it is reported */
#define POISON(p, n) ASAN_POISON_MEMORY_REGION((p), (n))
#else
#define GAP 0
#define POISON(p, n) ((void)(p), (void)(n))
#endif

/* what malloc's alignment serves (C99 has no max_align_t) */
typedef union {
    long double ld;
    double d;
    long long ll;
    void *p;
} aligned_unit;

struct eng_arena_block {
    eng_arena_block *next;
    size_t size, used;
    aligned_unit data[]; /* aligned for any type, and so is every array (ALIGN) */
};

#define ALIGN (sizeof(aligned_unit))

/* a block and its header in 1024 bytes: glibc serves a request that small from its
   per-thread cache, where a larger one first consolidates the small chunks Python
   has freed (that cost a short run more than sixty callocs) */
#define BLOCK_BYTES (1024 - sizeof(eng_arena_block))

void *eng_arena_take(eng_arena *a, size_t n, size_t size)
{
    eng_arena_block *b = a->blocks;
    size_t bytes, need;
    char *p;
    if (size != 0 && n > (SIZE_MAX - 2 * ALIGN - GAP) / size) return NULL;
    bytes = n * size;
    need = (bytes + GAP + ALIGN - 1) / ALIGN * ALIGN;
    if (need == 0) need = ALIGN;
    if (b == NULL || b->size - b->used < need) {
        size_t size_b = need > BLOCK_BYTES ? need : BLOCK_BYTES;
        if (size_b > SIZE_MAX - sizeof *b) return NULL;
        /* zeroed once: no array is taken twice from the same bytes */
        b = calloc(1, sizeof *b + size_b);
        if (b == NULL) return NULL;
        b->size = size_b;
        b->next = a->blocks;
        a->blocks = b;
        POISON(b->data, size_b);
    }
    p = (char *)b->data + b->used;
    b->used += need;
#if defined(__SANITIZE_ADDRESS__)
    ASAN_UNPOISON_MEMORY_REGION(p, bytes);
#endif
    return p;
}

void eng_arena_free(eng_arena *a)
{
    while (a->blocks) {
        eng_arena_block *next = a->blocks->next;
#if defined(__SANITIZE_ADDRESS__)
        ASAN_UNPOISON_MEMORY_REGION(a->blocks->data, a->blocks->size);
#endif
        free(a->blocks);
        a->blocks = next;
    }
}
