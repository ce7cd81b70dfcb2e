/* How much of a fibre a direction sees: the fibre's foreshortening along w, the cos(theta) of
 * every fibre model (kernels/fiber/).  The lights' pick (kernels/lights.h ht_facing, floored) and
 * the light vertices' densities (kernels/integrator/light_vertices.h, as it is) weigh by it.
 * Feature-free, so a program that includes it reads no feature define through it. */
#ifndef HT_GEOMETRY_FACING_H
#define HT_GEOMETRY_FACING_H

#include "../compat.h"

/* For a fibre with unit tangent t seen along unit w: sqrt(1 - (t . w)^2), the cosine of w's
 * inclination to the fibre's normal plane. */
HT_FN real ht_fibre_facing(real3 t, real3 w) {
    const real c = dot(t, w);
    return ht_safe_sqrt(HT_R(1) - c * c);
}

#endif
