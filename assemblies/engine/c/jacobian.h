/*
 * The Jacobian of the coupled state derivatives from the instances' directional
 * derivatives (FMI GetDirectionalDerivative), for the implicit solver and the
 * stiffness test of the Model Exchange master.
 *
 * Why not finite differences alone: an increment of sqrt(eps) |x| can be wider than
 * the feature that makes a model stiff. A smooth friction law 1e-8 m/s wide, with a
 * velocity near 1, gets a secant across the whole law instead of its slope, RODAS3
 * rejects step after step, and a 40 s stick-slip run takes hours instead of
 * milliseconds. Directional derivatives are exact, and every FMU of ours has them.
 *
 * A seed on state j of instance k moves k's derivatives and its coupled outputs; a
 * coupling passes an output's change on, times its gain, to the input it sets, which
 * moves that instance's derivatives and outputs in turn. Passes repeat until no coupled
 * input changes (a loop-free chain settles within as many passes as there are
 * instances); Int32 couplings are piecewise constant and carry nothing; nor do
 * the other non-Float64 and array couplings (an FMU with such couplings should not
 * offer directional derivatives to this run: assemblies/engine/binding.py).
 */
/*
 * Sparsity: the instances' ModelStructure (eng_instance_spec.feedthrough_listed) says
 * which outputs and derivatives a coupled input reaches, so the plan follows each state
 * through the couplings once, structurally, to the derivatives it can move: the
 * Jacobian's pattern. Columns that share no row are seeded together (Curtis, Powell
 * and Reid), and one propagation gives them all: a chain of n blocks takes a few
 * propagations per Jacobian instead of 2n, each touching only the instances it reaches.
 * Where the structure couples nearly everything, a group is one column, as before.
 */
#ifndef MECHFMU_ENGINE_JACOBIAN_H
#define MECHFMU_ENGINE_JACOBIAN_H

#include "engine.h"
#include "fmu.h"

typedef struct eng_jacobian eng_jacobian;

/* The plan for `spec`'s instances (x_off: each instance's slice of the states). NULL
   when an instance with states or coupled Float64 variables lacks directional
   derivatives or the value references of its states and derivatives (then finite
   differences it is), or when memory runs out. */
eng_jacobian *eng_jacobian_plan(const eng_me_spec *spec, const int *x_off);

/* Whether eng_jacobian_plan can plan `spec` (memory aside), in time linear in its
   instances and couplings: the plan itself follows every state's reach, which for a
   composite FMU (every derivative on every state) is quadratic in its states, so a
   run builds it only when it first needs a Jacobian. */
int eng_jacobian_possible(const eng_me_spec *spec);

/* jac[j * n_x + i] = d xdot_i / d x_j at the point every instance stands at (time,
   states and coupled inputs set). Instances with asleep[i] nonzero have zero rows and
   are not called. 0: done; -1: instance *bad failed; 1: the couplings did not settle
   (an algebraic loop), so the caller should fall back to finite differences. */
int eng_jacobian_eval(eng_jacobian *J, fmu_t **fmus, const int *asleep, double *jac, int *bad);

/* How many column groups one Jacobian takes (one propagation of seeds each): the
   states' count where the structure couples nearly all of them, a few for a chain. */
int eng_jacobian_groups(const eng_jacobian *J);

/* The pattern's bandwidth in the states' order: no entry lies more than *kl rows
   below or *ku columns above the diagonal (a chain's are a few states wide). */
void eng_jacobian_bandwidth(const eng_jacobian *J, int *kl, int *ku);

/* Directional-derivative calls made so far, over all instances. */
long eng_jacobian_evaluations(const eng_jacobian *J);

/* Dependencies the plan looked at to find the pattern: what its cost grows with (each
   column's reached knowns times their part's unknowns). */
long eng_jacobian_plan_checks(const eng_jacobian *J);

void eng_jacobian_free(eng_jacobian *J);

#endif
