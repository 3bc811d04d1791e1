/* band_lu: solves random banded systems n x n (band kl below, ku above the diagonal;
   every other one with a small diagonal, so that row swaps happen) with the banded LU
   and with the dense one, and prints the largest difference of the solutions relative
   to their size, and the residual |A x - b| of the banded solution relative to
   |A| |x| + |b| (max norms). Arguments: n kl ku. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "dense_lu.h"

#define MAX_N 200

int main(int argc, char **argv)
{
    static double a[MAX_N * MAX_N], band[MAX_N * MAX_N], orig[MAX_N * MAX_N];
    double x[MAX_N], y[MAX_N], rhs[MAX_N], diff = 0.0, residual = 0.0;
    int piv[MAX_N], piv_band[MAX_N], n, kl, ku, i, j, t;
    if (argc != 4) return 2;
    n = atoi(argv[1]); kl = atoi(argv[2]); ku = atoi(argv[3]);
    if (n < 1 || n > MAX_N || kl < 0 || ku < 0) return 2;
    srand(1);
    for (t = 0; t < 100; t++) {
        for (j = 0; j < n; j++)
            for (i = 0; i < n; i++) {
                double v = (i - j > kl || j - i > ku) ? 0.0 : rand() / (double)RAND_MAX - 0.5;
                if (i == j && t % 2) v *= 1e-3;
                a[i + j * n] = band[i + j * n] = orig[i + j * n] = v;
            }
        for (i = 0; i < n; i++) x[i] = y[i] = rhs[i] = sin(i + t);
        if (mf_lu_factor(a, n, piv) || mf_lu_factor_band(band, n, kl, ku, piv_band)) continue;
        mf_lu_solve(a, n, piv, x);
        mf_lu_solve_band(band, n, kl, ku, piv_band, y);
        double scale = 0.0, norm_a = 0.0, norm_y = 0.0;
        for (i = 0; i < n; i++) {
            double row = 0.0;
            for (j = 0; j < n; j++) row += fabs(orig[i + j * n]);
            if (row > norm_a) norm_a = row;
            if (fabs(y[i]) > norm_y) norm_y = fabs(y[i]);
        }
        scale = norm_a * norm_y + 1.0;
        for (i = 0; i < n; i++) {
            double r = -rhs[i];
            if (fabs(x[i] - y[i]) / (1.0 + fabs(x[i])) > diff) diff = fabs(x[i] - y[i]) / (1.0 + fabs(x[i]));
            for (j = 0; j < n; j++) r += orig[i + j * n] * y[j];
            if (fabs(r) / scale > residual) residual = fabs(r) / scale;
        }
    }
    printf("%.17g %.17g\n", diff, residual);
    return 0;
}
