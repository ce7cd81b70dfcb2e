/* Arbitrary output values (render --aovs): what each path records besides its radiance, laid
 * out once for the kernels and the host (host/render/aovs.h names the output channels).
 *
 * Per path, HT_AOV_STRIDE floats (the path buffer "aovs"); the first HT_AOV_OUT are summed into
 * the film per pixel, the rest is the path's working state:
 *   alpha      1 when the camera ray met geometry, else 0
 *   depth      the camera ray's hit distance (0 on a miss; the host divides by alpha)
 *   tangent    the first hit's unit fibre tangent (a surface's geometric normal)
 *   albedo     the first vertex's BCSDF sample weight f cos / pdf: its mean over samples is the
 *              directional albedo for the camera direction
 *   direct     light that scattered at most once on its way to the camera (the environment seen
 *              directly included); indirect: the rest, so direct + indirect = beauty
 *   R, TT, TRT, residual: the light whose first scattering was at hair, split by that vertex's
 *              lobes in proportion f_p / f at the direction taken (next-event: the light's
 *              direction; continuation: the sampled one), so they sum to the hair's share of
 *              the beauty; residual is chiang's TRRT+ (0 for the other models)
 * The next-event contribution queued at shadow slot k carries HT_SHADOW_AOV_STRIDE floats: the
 * four lobe fractions and whether it is direct light (kernels/stages/resolve_shadows.cl). */
#ifndef HT_AOVS_H
#define HT_AOVS_H

#define HT_AOV_ALPHA 0
#define HT_AOV_DEPTH 1
#define HT_AOV_TANGENT 2
#define HT_AOV_ALBEDO 5
#define HT_AOV_DIRECT 8
#define HT_AOV_INDIRECT 11
#define HT_AOV_LOBES 14 /* 4 x rgb: R, TT, TRT, residual */
#define HT_AOV_OUT 26
#define HT_AOV_FRACTIONS 26 /* state: lobe fractions of the path's first (hair) vertex */
#define HT_AOV_STRIDE 32
#define HT_SHADOW_AOV_STRIDE 8 /* fractions[4], direct, pad[3] */

#endif /* HT_AOVS_H */
