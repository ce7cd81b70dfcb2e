/* --light-vertices: the pass's light rays (kernels/integrator/light_vertices.h ht_light_ray), one
 * set of lv.count per camera sample of the pass; intersect_closest then finds their first hits,
 * the light vertices that shade connects to. */
#include "../types.h"
#include "../integrator/light_vertices.h"

__kernel void generate_light_rays(HtLightVertices lv, __global const HtLight* lights, uint light_count, uint seed,
                                  uint count, __global HtRay* light_rays) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const HtLight light = lights[ht_light_vertex_light(i % lv.count, light_count)];
    light_rays[i] = ht_light_ray(&lv, &light, seed, i);
}
