/*
 * Dense LU factorisation with partial pivoting, for the small Newton-type
 * matrices (I / (h gamma) - J) of the implicit solver. Column-major storage, as
 * CasADi writes the Jacobian. No allocation: the caller owns every array.
 */
#ifndef MECHFMU_DENSE_LU_H
#define MECHFMU_DENSE_LU_H

/* Factors the n x n matrix a in place (L below the diagonal with unit diagonal,
   U on and above it); piv[k] is the row swapped with row k at step k.
   Returns 0, or k + 1 if the pivot of column k is zero or not finite (singular). */
int mf_lu_factor(double *a, int n, int *piv);

/* Solves A x = b with the factors of mf_lu_factor; b is overwritten by x. */
void mf_lu_solve(const double *lu, int n, const int *piv, double *b);

/* The same for a banded a: a(i, j) = 0 where i > j + kl or j > i + ku. Rows and
   columns outside the band are neither read nor written except within kl + ku above
   the diagonal (the fill of row swaps), which the caller must have set (to zero where
   a has nothing). Returns as mf_lu_factor. */
int mf_lu_factor_band(double *a, int n, int kl, int ku, int *piv);

/* Solves A x = b with the factors of mf_lu_factor_band (same kl, ku). */
void mf_lu_solve_band(const double *lu, int n, int kl, int ku, const int *piv, double *b);

#endif
