/*
 * stiffness.c: when to switch between DOPRI5 and RODAS3 (see stiffness.h).
 */
#include "stiffness.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>

/* Hairer's count (15 accepted steps) at a threshold of 3.0 rather than his 3.25: with
   this controller a stability-bound step sits at h |lambda| = 3.21 by the estimate
   (measured on the tanh friction law, stuck), below his threshold; DOPRI5's stability
   interval on the negative real axis ends at about 3.3, and a step accuracy bounds
   stays well inside it */
static const double STIFF_H_LAMBDA = 3.0;
static const int STIFF_VOTES = 15;
static const int NONSTIFF_PATIENCE = 6;
/* the periodic check: one Jacobian per this many explicit steps, a cost of well under
   1 % where the check finds nothing; it calls the model stiff where DOPRI5's proposed
   step times rho exceeds 2: a step accuracy bounds is far shorter (h rho of order
   tol^(1/5)), and a stability-bound one measured 2.84 (with a norm bound of rho) near
   a smooth law's equilibrium, where Hairer's estimate said 1.1 */
static const long EXPLICIT_CHECK_EVERY = 200;
static const double STIFF_H_RHO = 2.0;
static const int SPECTRAL_ROUNDS = 8; /* of J applied twice */
/* back to the explicit method where h rho is within a third of DOPRI5's stability
   interval on the negative real axis (about 3.3), on 6 accepted steps: a wider margin
   (1.6 was tried) hands a steep law back to DOPRI5 while it is still near the steep
   part, where a step at the stability edge rings and crosses indicators that the
   L-stable method does not (69 spurious events on the tanh law, against 5); the count
   keeps a problem at the border from switching at every step */
static const double NONSTIFF_H_RHO = 1.0;
static const int NONSTIFF_VOTES = 6;
/* An implicit episode pays where its steps are this many times the explicit step it
   replaced: a RODAS3 step (a Jacobian, an LU, four stages) costs at least two DOPRI5
   steps. An episode that did not pay doubles the explicit dwell needed before the next
   switch to the implicit method (up to MAX_PENALTY doublings, 15 * 2^12 = 61,440 steps),
   so a problem where Hairer's test calls DOPRI5 stability-bound but RODAS3's
   accuracy-bound step is no longer (an undamped beam: imaginary eigenvalues up to
   (N pi)^2, where the third-order method needs shorter steps than the fifth-order one)
   switches O(log steps) times instead of every few dozen steps (measured before: 614
   switches and 1,842 Jacobians at N = 32 in 22,005 steps, 40x DOPRI5's time). One that
   paid forgets the penalty. */
static const double PAYING_GAIN = 2.0;
static const long MIN_EXPLICIT_DWELL = 15; /* times 2^penalty, after a switch back */
static const int MAX_PENALTY = 12;
/* and an episode whose mean step, after this many, is shorter than the explicit step
   it replaced ends at once, whatever h rho says: the explicit method is cheaper per step */
static const long IMPLICIT_TRIAL = 8;

void mf_stiffness_reset(mf_stiffness *s, int start_implicit)
{
    s->implicit = start_implicit != 0;
    s->votes = s->against = 0;
    s->switches = 0;
    s->explicit_steps = 0;
    s->dwell = 0;
    s->penalty = 0;
    s->h_explicit = s->implicit_h_sum = 0.0;
    s->jacobians_checked = 0;
    s->fruitless = 0;
}

/* the method changes; the implicit episode that ends here is judged */
static void change(mf_stiffness *s, double h)
{
    if (s->implicit) {
        /* back to the explicit method: did the implicit steps beat the one they replaced? */
        int paid = s->h_explicit > 0.0 && s->dwell > 0 &&
                   s->implicit_h_sum >= PAYING_GAIN * s->h_explicit * (double)s->dwell;
        if (paid) s->penalty = 0;
        else if (s->penalty < MAX_PENALTY) s->penalty++;
    } else {
        s->h_explicit = h;
        s->implicit_h_sum = 0.0;
    }
    s->implicit = !s->implicit;
    s->votes = s->against = 0;
    s->dwell = 0;
    s->fruitless = 0;
    s->switches++;
}

/* the explicit steps needed since the last switch before the next one to implicit */
static long explicit_dwell(const mf_stiffness *s)
{
    return s->penalty == 0 ? 0 : MIN_EXPLICIT_DWELL << s->penalty;
}

/* Counts a step for the other method; `patience` steps against it in a row forget the
   count. Returns 1 when the other method takes over. */
static int vote(mf_stiffness *s, int for_the_other, int needed, int patience, double h)
{
    if (for_the_other) {
        s->votes++;
        s->against = 0;
    } else if (++s->against >= patience) {
        s->votes = 0;
    }
    if (s->votes < needed) return 0;
    if (!s->implicit && s->dwell < explicit_dwell(s)) return 0;
    change(s, h);
    return 1;
}

int mf_stiffness_after_explicit(mf_stiffness *s, double h, double h_lambda)
{
    if (s->implicit) return 0;
    s->dwell++;
    /* Hairer's patience: an event or an output point shortens a step now and then, and
       those short steps say nothing against stiffness */
    return vote(s, h_lambda > STIFF_H_LAMBDA, STIFF_VOTES, NONSTIFF_PATIENCE, h);
}

/* rho(J) by power iteration: |J^k v| grows as rho^k; the square root of two steps'
   growth copes with a complex pair, whose iterates turn while they grow. An estimate,
   not a bound: a norm of J, a bound, can exceed rho many times over (a state of size 90
   feeding one of size 1 weighs 90 in the weighted norm), and then calls a model stiff
   that DOPRI5 integrates in accuracy-bound steps. */
/* J's nonzeros by column (row index, value), in the dense order: a chain's Jacobian is
   banded, and the rounds below apply it 2 SPECTRAL_ROUNDS times, so gathering it once
   makes the estimate O(nonzeros) after one O(n^2) read instead of 16 O(n^2) products
   (22 % of a 1,500-state me run went to those products). Each row still sums its terms
   in ascending column order, the dense product's order, so rho is the same to the bit. */
typedef struct {
    int n;
    const double *dense; /* where the gathering could not allocate */
    int *start;          /* n + 1 offsets into row/value */
    int *row;
    double *value;
} columns;

static void gather(columns *c, const double *jac, int n)
{
    size_t nnz = 0, k = 0, total = (size_t)n * (size_t)n;
    int i, j;
    c->n = n;
    c->dense = jac;
    c->start = NULL;
    c->row = NULL;
    c->value = NULL;
    for (k = 0; k < total; k++) nnz += jac[k] != 0.0;
    if (nnz > total / 2 || nnz > (size_t)INT_MAX) return; /* dense enough: no gain */
    c->start = malloc(((size_t)n + 1) * sizeof *c->start);
    c->row = malloc((nnz ? nnz : 1) * sizeof *c->row);
    c->value = malloc((nnz ? nnz : 1) * sizeof *c->value);
    if (!c->start || !c->row || !c->value) {
        free(c->start);
        free(c->row);
        free(c->value);
        c->start = NULL;
        c->row = NULL;
        c->value = NULL;
        return;
    }
    k = 0;
    for (j = 0; j < n; j++) {
        c->start[j] = (int)k;
        for (i = 0; i < n; i++) {
            double a = jac[(size_t)j * n + i];
            if (a != 0.0) {
                c->row[k] = i;
                c->value[k++] = a;
            }
        }
    }
    c->start[n] = (int)k;
    c->dense = NULL;
}

static void release(columns *c)
{
    free(c->start);
    free(c->row);
    free(c->value);
}

static void apply(const columns *c, const double *v, double *out)
{
    const int n = c->n;
    int i, j, k;
    if (c->dense) {
        for (i = 0; i < n; i++) {
            out[i] = 0.0;
            for (j = 0; j < n; j++) out[i] += c->dense[(size_t)j * n + i] * v[j];
        }
        return;
    }
    /* column by column, so row i still gathers its terms in ascending j; a zero the
       dense product would add changes nothing (v is finite, x + 0 = x but for -0) */
    for (i = 0; i < n; i++) out[i] = 0.0;
    for (j = 0; j < n; j++)
        for (k = c->start[j]; k < c->start[j + 1]; k++) out[c->row[k]] += c->value[k] * v[j];
}

static double spectral_radius(const double *jac, int n)
{
    double v[n > 0 ? n : 1], w[n > 0 ? n : 1], growth = 0.0;
    int i, k;
    double start = 0.0;
    columns c;
    for (i = 0; i < n; i++) {
        v[i] = 1.0 + (double)i / n; /* not orthogonal to a mode */
        start += v[i] * v[i];
    }
    for (i = 0; i < n; i++) v[i] /= sqrt(start);
    gather(&c, jac, n);
    for (k = 0; k < SPECTRAL_ROUNDS; k++) {
        double size = 0.0;
        apply(&c, v, w);
        apply(&c, w, v);
        for (i = 0; i < n; i++) size += v[i] * v[i];
        size = sqrt(size); /* |J^2 v| for the v of size 1 before */
        if (size == 0.0) {
            growth = 0.0;
            break;
        }
        if (!isfinite(size)) {
            growth = INFINITY;
            break;
        }
        growth = sqrt(size);
        for (i = 0; i < n; i++) v[i] /= size;
    }
    release(&c);
    return growth;
}

int mf_stiffness_wants_jacobian(mf_stiffness *s)
{
    if (s->implicit) return 0;
    /* the step just voted (a vote zeroes `against`): stability may bound it, and the
       Jacobian says at once whether it does */
    if (s->dwell < explicit_dwell(s)) return 0; /* a switch could not happen now */
    /* a vote asks only once the streak reaches 2^(checks that found nothing): where
       Hairer's estimate keeps voting but rho says DOPRI5 is not stability-bound (an
       undamped beam: 692 checks in 5,612 steps at N = 16, each a whole Jacobian), the
       checks thin out to votes 1, 2, 4, 8 of a streak, then to 2, 4, 8 ... and at
       most to the 8th alone (a vote checked late lets a component below the tolerance
       ring, as said above); the streak's 15th vote switches anyway */
    if ((s->votes > 0 && s->against == 0 && (s->votes & (s->votes - 1)) == 0 &&
         s->votes >= (1 << s->fruitless)) ||
        ++s->explicit_steps >= EXPLICIT_CHECK_EVERY) {
        s->explicit_steps = 0;
        s->jacobians_checked++;
        return 1;
    }
    return 0;
}

int mf_stiffness_explicit_check(mf_stiffness *s, double h, const double *jac, int n)
{
    double rho = spectral_radius(jac, n);
    if (s->implicit || !isfinite(rho) || !(h * rho > STIFF_H_RHO)) {
        if (s->fruitless < 3) s->fruitless++;
        return 0;
    }
    if (s->dwell < explicit_dwell(s)) return 0;
    change(s, h);
    return 1;
}

int mf_stiffness_after_implicit(mf_stiffness *s, double h, const double *jac, int n)
{
    double rho;
    if (!s->implicit) return 0;
    s->dwell++;
    s->implicit_h_sum += h;
    if (s->dwell >= IMPLICIT_TRIAL && s->implicit_h_sum < s->h_explicit * (double)s->dwell) {
        change(s, h);
        return 1;
    }
    rho = spectral_radius(jac, n);
    /* no patience this way: one step that needs the implicit method keeps it */
    return vote(s, isfinite(rho) && h * rho < NONSTIFF_H_RHO, NONSTIFF_VOTES, 1, h);
}
