/* The layout contract between the host and the kernels, declared once: every struct they share,
 * its size and the byte offset of each field.  host/core/kernel_layouts.cpp turns the list into
 * static_asserts against the C++ compiler's layout, and tests/kernel/layout_test.cpp compiles it
 * into a kernel that reports the OpenCL compiler's sizeof and offsetof for the same entries, so
 * a struct that the two compilers lay out differently fails a build or a test, not a render.
 *
 * HT_SHARED_LAYOUTS(S, F): S(type, bytes) opens a struct, F(type, field, offset) follows for each
 * of its fields, in declaration order.  A new shared struct or field is added here. */
#ifndef HT_LAYOUTS_H
#define HT_LAYOUTS_H

#include "types.h"
#include "fiber/query.h"

#define HT_SHARED_LAYOUTS(S, F)                                                                    \
    S(HtPoint, 16) F(HtPoint, x, 0) F(HtPoint, y, 4) F(HtPoint, z, 8) F(HtPoint, r, 12)           \
    S(HtSegment, 8) F(HtSegment, point, 0) F(HtSegment, strand_flags, 4)                          \
    S(HtBvhNode, 256) F(HtBvhNode, x, 0) F(HtBvhNode, y, 64) F(HtBvhNode, z, 128)               \
        F(HtBvhNode, child, 192) F(HtBvhNode, count, 224)                                     \
    S(HtPathGrid, 32) F(HtPathGrid, lo, 0) F(HtPathGrid, cell, 12) F(HtPathGrid, dims, 16)        \
        F(HtPathGrid, inv_cell, 28)                                                                \
    S(HtTriangleShading, 128) F(HtTriangleShading, n0, 0) F(HtTriangleShading, n1, 16)            \
        F(HtTriangleShading, n2, 32) F(HtTriangleShading, albedo, 48) F(HtTriangleShading, uv, 64) \
        F(HtTriangleShading, texture, 88) F(HtTriangleShading, pad1, 96)                           \
    S(HtTexture, 32) F(HtTexture, offset, 0) F(HtTexture, width, 4) F(HtTexture, height, 8)       \
        F(HtTexture, wrap_s, 16) F(HtTexture, wrap_t, 20)                                          \
    S(HtRay, 32) F(HtRay, ox, 0) F(HtRay, oy, 4) F(HtRay, oz, 8) F(HtRay, tmin, 12)               \
        F(HtRay, dx, 16) F(HtRay, dy, 20) F(HtRay, dz, 24) F(HtRay, tmax, 28)                      \
    S(HtHit, 32) F(HtHit, t, 0) F(HtHit, u, 4) F(HtHit, h, 8) F(HtHit, segment, 12)               \
        F(HtHit, tx, 16) F(HtHit, ty, 20) F(HtHit, tz, 24) F(HtHit, radius, 28)                    \
    S(HtPathState, 48) F(HtPathState, throughput, 0) F(HtPathState, pixel, 12)                    \
        F(HtPathState, radiance, 16) F(HtPathState, flags, 28) F(HtPathState, last_pdf, 32)        \
        F(HtPathState, split, 36) F(HtPathState, sample, 40) F(HtPathState, node, 44)              \
    S(HtShadowContrib, 16) F(HtShadowContrib, contrib, 0) F(HtShadowContrib, path, 12)            \
    S(HtDualRecord, 32) F(HtDualRecord, weight, 0) F(HtDualRecord, material, 12)                  \
        F(HtDualRecord, theta_i, 16) F(HtDualRecord, theta_o, 20) F(HtDualRecord, phi, 24)        \
    S(HtBounce, 32) F(HtBounce, seed, 0) F(HtBounce, pad0, 4) F(HtBounce, bounce, 8)              \
        F(HtBounce, max_depth, 12) F(HtBounce, field_mode, 16) F(HtBounce, pixel_angle, 20)        \
        F(HtBounce, splits, 24) F(HtBounce, light_samples, 28)                                     \
    S(HtLightVertices, 32) F(HtLightVertices, disc, 0) F(HtLightVertices, count, 16)              \
        F(HtLightVertices, first_sample, 20)                                                       \
    S(HtCamera, 80) F(HtCamera, eye, 0) F(HtCamera, right, 16) F(HtCamera, up, 32)                \
        F(HtCamera, forward, 48) F(HtCamera, width, 64) F(HtCamera, height, 68)                    \
    S(HtShadowGrid, 96) F(HtShadowGrid, dir, 0) F(HtShadowGrid, u, 16) F(HtShadowGrid, v, 32)     \
        F(HtShadowGrid, w, 48) F(HtShadowGrid, inv_cell, 64) F(HtShadowGrid, nx, 68)               \
        F(HtShadowGrid, ny, 72) F(HtShadowGrid, cell_offset, 76) F(HtShadowGrid, kind, 80)         \
    S(HtLight, 80) F(HtLight, type, 0) F(HtLight, position, 16) F(HtLight, direction, 32)         \
        F(HtLight, radiance, 48) F(HtLight, cos_outer, 64) F(HtLight, cos_inner, 68)               \
    S(HtEnvironment, 32) F(HtEnvironment, width, 0) F(HtEnvironment, height, 4)                   \
        F(HtEnvironment, has_map, 8) F(HtEnvironment, enabled, 12) F(HtEnvironment, scale, 16)     \
    S(HtMaterial, 272) F(HtMaterial, model, 0) F(HtMaterial, flags, 4) F(HtMaterial, sigma_a, 16) \
        F(HtMaterial, eta, 32) F(HtMaterial, beta_m, 36) F(HtMaterial, beta_n, 40)                 \
        F(HtMaterial, alpha, 44) F(HtMaterial, v, 48) F(HtMaterial, mp_c, 64) F(HtMaterial, s, 80) \
        F(HtMaterial, azim_sigma, 84) F(HtMaterial, ks_norm, 88) F(HtMaterial, ks_exponent, 92)    \
        F(HtMaterial, sin_tilt, 96) F(HtMaterial, cos_tilt, 112) F(HtMaterial, alpha_r, 128)       \
        F(HtMaterial, alpha_tt, 132) F(HtMaterial, alpha_trt, 136) F(HtMaterial, beta_r, 144)      \
        F(HtMaterial, beta_tt, 148) F(HtMaterial, beta_trt, 152) F(HtMaterial, caustic_wc, 160)    \
        F(HtMaterial, caustic_kg, 164) F(HtMaterial, caustic_deta, 168)                            \
        F(HtMaterial, caustic_dhm, 172) F(HtMaterial, eccentricity, 176) F(HtMaterial, kd, 192)    \
        F(HtMaterial, ks, 208) F(HtMaterial, mz_sin_tilt, 224) F(HtMaterial, mz_cos_tilt, 240)     \
        F(HtMaterial, mz_log_norm, 256)                                                            \
    S(HtFiberQuery, 64) F(HtFiberQuery, wo, 0) F(HtFiberQuery, wi, 16) F(HtFiberQuery, h, 32)     \
        F(HtFiberQuery, u0, 36) F(HtFiberQuery, u1, 40) F(HtFiberQuery, u2, 44)                    \
        F(HtFiberQuery, u3, 48) F(HtFiberQuery, lobe_weight, 52)                                   \
    S(HtFiberResult, 112) F(HtFiberResult, value, 0) F(HtFiberResult, lobes, 16)                  \
        F(HtFiberResult, wi, 80) F(HtFiberResult, pdf, 96) F(HtFiberResult, ok, 100)

#endif /* HT_LAYOUTS_H */
