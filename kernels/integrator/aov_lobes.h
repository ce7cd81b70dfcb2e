/* The lobe split of render --aovs at a shading point: what shade records, through
 * aov_record.h, for the R, TT, TRT and residual outputs. */
#ifndef HT_AOV_LOBES_H
#define HT_AOV_LOBES_H

#include "shading_point.h"

#if HT_FEATURE_AOVS

/* The fractions f_p / f of the fibre's four lobes towards wi (zero for a surface, or where the
 * fibre sends nothing). */
HT_FN float4 ht_aov_lobe_fractions(const HtShadingPoint* sp, float3 wi) {
#if HT_FEATURE_MESHES
    if (sp->is_surface) return (float4)(0.0f);
#endif
    float3 lobes[4], value;
    ht_bcsdf_eval_lobes_o(&sp->mat, &sp->wo_prep, sp->wo_l, ht_to_fiber_local(wi, sp->fx, sp->fy, sp->fz), sp->h,
                          lobes, &value, 0);
    float4 e = (float4)(lobes[0].x + lobes[0].y + lobes[0].z, lobes[1].x + lobes[1].y + lobes[1].z,
                        lobes[2].x + lobes[2].y + lobes[2].z, lobes[3].x + lobes[3].y + lobes[3].z);
    e = max(e, (float4)(0.0f));
    float sum = e.x + e.y + e.z + e.w;
    return sum > 0.0f && ht_isfinite(sum) ? e / sum : (float4)(0.0f);
}

#endif
#endif
