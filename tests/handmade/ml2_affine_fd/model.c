/* ml2_affine_fd: ml2_affine's equations, its description offering no directional
   derivatives (an algebraic loop through it takes its matrix from differences). */
#include "../ml2_affine/model.c"
