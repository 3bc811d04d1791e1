/*
 * Doolittle LU with partial pivoting (Golub & Van Loan, Alg. 3.4.1), column-major:
 * element (i, j) is a[i + j * n]. The state dimension of our components is small
 * (2 to a few dozen), so a dense, unblocked factorisation is the right tool.
 */
#include "dense_lu.h"

#include <math.h>
#include <stddef.h>

#define A(i, j) a[(i) + (size_t)(j) * (size_t)n]

int mf_lu_factor(double *a, int n, int *piv)
{
    int i, j, k;
    for (k = 0; k < n; k++) {
        int p = k;
        double big = fabs(A(k, k));
        for (i = k + 1; i < n; i++)
            if (fabs(A(i, k)) > big) {
                big = fabs(A(i, k));
                p = i;
            }
        piv[k] = p;
        if (!(big > 0.0) || !isfinite(big)) return k + 1;
        if (p != k)
            for (j = 0; j < n; j++) {
                double tmp = A(k, j);
                A(k, j) = A(p, j);
                A(p, j) = tmp;
            }
        for (i = k + 1; i < n; i++) A(i, k) /= A(k, k);
        /* rank-one update of the trailing block, column by column (contiguous) */
        for (j = k + 1; j < n; j++) {
            double akj = A(k, j);
            if (akj == 0.0) continue;
            for (i = k + 1; i < n; i++) A(i, j) -= A(i, k) * akj;
        }
    }
    return 0;
}

#define LU(i, j) lu[(i) + (size_t)(j) * (size_t)n]

void mf_lu_solve(const double *lu, int n, const int *piv, double *b)
{
    int i, j;
    for (i = 0; i < n; i++)
        if (piv[i] != i) {
            double tmp = b[i];
            b[i] = b[piv[i]];
            b[piv[i]] = tmp;
        }
    /* forward substitution with the unit lower triangle, column-oriented */
    for (j = 0; j < n; j++) {
        double bj = b[j];
        if (bj == 0.0) continue;
        for (i = j + 1; i < n; i++) b[i] -= LU(i, j) * bj;
    }
    /* back substitution with the upper triangle */
    for (j = n - 1; j >= 0; j--) {
        double bj;
        b[j] /= LU(j, j);
        bj = b[j];
        if (bj == 0.0) continue;
        for (i = 0; i < j; i++) b[i] -= LU(i, j) * bj;
    }
}

/* The banded variant (LAPACK's dgbtf2 on full storage): nonzeros of a lie within kl
   rows below and ku columns above the diagonal, so column k's pivot is among rows
   k .. k + kl and a row swap fills U up to kl + ku above the diagonal. A row swap at
   step k moves the columns from k on only, so the multipliers stay where they were
   computed and mf_lu_solve_band applies the swaps one step at a time. O(n kl (kl + ku))
   instead of O(n^3): a chain of n blocks costs n, not n^3. */
int mf_lu_factor_band(double *a, int n, int kl, int ku, int *piv)
{
    int i, j, k;
    for (k = 0; k < n; k++) {
        const int last = k + kl < n - 1 ? k + kl : n - 1;
        const int right = k + kl + ku < n - 1 ? k + kl + ku : n - 1;
        int p = k;
        double big = fabs(A(k, k));
        for (i = k + 1; i <= last; i++)
            if (fabs(A(i, k)) > big) {
                big = fabs(A(i, k));
                p = i;
            }
        piv[k] = p;
        if (!(big > 0.0) || !isfinite(big)) return k + 1;
        if (p != k)
            for (j = k; j <= right; j++) {
                double tmp = A(k, j);
                A(k, j) = A(p, j);
                A(p, j) = tmp;
            }
        for (i = k + 1; i <= last; i++) A(i, k) /= A(k, k);
        for (j = k + 1; j <= right; j++) {
            double akj = A(k, j);
            if (akj == 0.0) continue;
            for (i = k + 1; i <= last; i++) A(i, j) -= A(i, k) * akj;
        }
    }
    return 0;
}

void mf_lu_solve_band(const double *lu, int n, int kl, int ku, const int *piv, double *b)
{
    int i, j;
    for (j = 0; j < n; j++) {
        const int last = j + kl < n - 1 ? j + kl : n - 1;
        double bj;
        if (piv[j] != j) {
            double tmp = b[j];
            b[j] = b[piv[j]];
            b[piv[j]] = tmp;
        }
        bj = b[j];
        if (bj == 0.0) continue;
        for (i = j + 1; i <= last; i++) b[i] -= LU(i, j) * bj;
    }
    for (j = n - 1; j >= 0; j--) {
        const int first = j - kl - ku > 0 ? j - kl - ku : 0;
        double bj;
        b[j] /= LU(j, j);
        bj = b[j];
        if (bj == 0.0) continue;
        for (i = first; i < j; i++) b[i] -= LU(i, j) * bj;
    }
}
