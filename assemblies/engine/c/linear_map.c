/*
 * linear_map.c: the layout of linear maps' coefficients (see linear_map.h).
 */
#include "linear_map.h"

#include <string.h>

void eng_inputs_by_target(const eng_coupling *c, int nc, int n, const int *take, int *start,
                          int *list)
{
    int i, k;
    memset(start, 0, (size_t)(n + 1) * sizeof(int));
    for (k = 0; k < nc; k++)
        if (!take || take[c[k].target.instance]) start[c[k].target.instance + 1]++;
    for (i = 0; i < n; i++) start[i + 1] += start[i];
    /* start[i] serves as instance i's cursor, then each moves back one instance */
    for (k = 0; k < nc; k++) {
        i = c[k].target.instance;
        if (!take || take[i]) list[start[i]++] = k;
    }
    for (i = n; i > 0; i--) start[i] = start[i - 1];
    start[0] = 0;
}

size_t eng_linear_rows(const eng_coupling *c, int nc, const int *start, int *kind, int linear,
                       int *row)
{
    size_t total = 0;
    int k;
    for (k = 0; k < nc; k++) {
        const int i = c[k].source.instance;
        size_t width;
        if (kind[i] != linear) continue;
        width = (size_t)(start[i + 1] - start[i]);
        if (total + width > ENG_LINEAR_MAP_MAX_ENTRIES) { /* bounded: evaluated instead */
            kind[i] = 0;
            continue;
        }
        row[k] = (int)total;
        total += width;
    }
    return total;
}
