/* jacobian_plan: the engine's Jacobian plan (assemblies/engine/c/jacobian.c) for a
   synthetic spec, no FMU loaded (the plan reads the spec alone). Arguments: kind n.
   kind "dense": one instance of n states, nothing listed (every derivative may depend
   on every state, as a composite FMU of a whole chain says of itself); kind "chain": n
   instances of 2 states, instance i's derivatives read instance i-1's output y through
   input u (listed in its feedthrough), as a chain of blocks. Prints: column groups,
   lower and upper bandwidth, dependencies the plan looked at. */
#include <stdio.h>
#include <stdlib.h>

#include "jacobian.h"

#define MAX_N 4096

/* the plan never evaluates: eng_jacobian_eval alone calls the FMU */
int fmu_directional_derivative(fmu_t *f, const uint32_t *unknowns, size_t n_unknowns,
                               const uint32_t *knowns, size_t n_knowns, const double *seed,
                               double *sensitivity)
{
    (void)f; (void)unknowns; (void)n_unknowns; (void)knowns; (void)n_knowns; (void)seed;
    (void)sensitivity;
    return -1;
}

int main(int argc, char **argv)
{
    static eng_instance_spec in[MAX_N];
    static eng_coupling couplings[MAX_N];
    static uint32_t state_vr[MAX_N], derivative_vr[MAX_N];
    static const uint32_t two_states[2] = {0, 1}, two_derivatives[2] = {2, 3};
    /* chain member: y (vr 4) depends on the states only; the derivatives on u (vr 5) */
    static const uint32_t ft_unknown[2] = {2, 3}, ft_known[2] = {5, 5};
    static int x_off[MAX_N + 1];
    eng_me_spec spec = {0};
    eng_jacobian *J;
    int n, i, kl, ku, dense;
    if (argc != 3) return 2;
    dense = argv[1][0] == 'd';
    n = atoi(argv[2]);
    if (n < 1 || n > MAX_N) return 2;
    if (dense) {
        for (i = 0; i < n; i++) {
            state_vr[i] = (uint32_t)i;
            derivative_vr[i] = (uint32_t)(n + i);
        }
        in[0].n_states = n;
        in[0].provides_directional_derivative = 1;
        in[0].state_vr = state_vr;
        in[0].derivative_vr = derivative_vr;
        spec.n_instances = 1;
        x_off[1] = n;
    } else {
        for (i = 0; i < n; i++) {
            in[i].n_states = 2;
            in[i].provides_directional_derivative = 1;
            in[i].state_vr = two_states;
            in[i].derivative_vr = two_derivatives;
            in[i].feedthrough_listed = 1;
            in[i].n_feedthrough = 2;
            in[i].feedthrough_unknown = ft_unknown;
            in[i].feedthrough_known = ft_known;
            x_off[i + 1] = 2 * (i + 1);
            if (i > 0) {
                eng_coupling *c = &couplings[i - 1];
                c->source.instance = i - 1;
                c->source.vr = 4;
                c->target.instance = i;
                c->target.vr = 5;
                c->gain = 1.0;
            }
        }
        spec.n_instances = n;
        spec.n_couplings = n - 1;
    }
    spec.instances = in;
    spec.couplings = couplings;
    J = eng_jacobian_plan(&spec, x_off);
    if (!J) return 1;
    eng_jacobian_bandwidth(J, &kl, &ku);
    printf("%d %d %d %ld\n", eng_jacobian_groups(J), kl, ku, eng_jacobian_plan_checks(J));
    eng_jacobian_free(J);
    return 0;
}
