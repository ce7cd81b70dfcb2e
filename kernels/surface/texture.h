/* Base colour textures, portable (kernels: float, host tests: double).
 *
 * Texels are stored as the 8-bit sRGB values of the image (types.h, HtTexture): 4 bytes a texel
 * instead of 12-16 for linear float, and lossless for the 8-bit PNG and JPEG images glTF base
 * colour textures almost always are.  Each of the four texels of a lookup is decoded to linear
 * before filtering, so the bilinear blend happens in linear light as the glTF spec asks (it is
 * the decoded, not the encoded, colour that is interpolated).  The decode is a table lookup:
 * the texel buffer starts with HT_SRGB_TABLE_SIZE floats (as uint bits), the linear value of
 * each 8-bit code, written by the host with ht_srgb_table from the formula below.  Evaluating
 * the formula instead (12 pow() a lookup) made the shade stage of a scene half covered by a
 * textured floor 55 % slower on PoCL (docs/PERFORMANCE.md §3); the table costs 1 KiB.
 *
 * Filtering is bilinear with texel centres at ((i + 0.5) / width, (j + 0.5) / height), as OpenGL
 * and glTF samplers; there are no mip-maps, so a texture seen from far away aliases (noise that
 * the pixel's samples average out, not a bias in the mean colour of a uniform region).  Wrap
 * modes act per axis: the coordinate is first reduced to one period ([0, 1] clamp, [0, 1) repeat,
 * [0, 2) mirrored repeat) so huge coordinates never overflow the integer texel index, then the
 * two neighbouring texel indices are wrapped.
 */
#ifndef HT_SURFACE_TEXTURE_H
#define HT_SURFACE_TEXTURE_H

#include "../types.h"

/* The sRGB transfer function's inverse (IEC 61966-2-1), encoded value c in [0, 1]. */
HT_FN real ht_srgb_to_linear(real c) {
    return c <= HT_R(0.04045) ? c * HT_R(1.0 / 12.92)
                              : pow((c + HT_R(0.055)) * HT_R(1.0 / 1.055), HT_R(2.4));
}

/* Fills the decode table at the start of the texel buffer (host). */
HT_FN void ht_srgb_table(HT_GLOBAL uint* table) {
    for (uint i = 0u; i < HT_SRGB_TABLE_SIZE; ++i)
        table[i] = ht_as_uint((float)ht_srgb_to_linear((real)i * HT_R(1.0 / 255.0)));
}

/* One stored texel (r | g << 8 | b << 16, sRGB) as linear rgb, through the decode table. */
HT_FN real3 ht_texel_linear(HT_CONST_GLOBAL uint* table, uint t) {
    return make_real3(ht_as_float(table[t & 0xffu]), ht_as_float(table[(t >> 8) & 0xffu]),
                      ht_as_float(table[(t >> 16) & 0xffu]));
}

/* Texture coordinate reduced to one period of its wrap mode; a non-finite one becomes 0 (the
 * loader refuses non-finite coordinates, this only keeps arithmetic noise from indexing
 * outside the texture). */
HT_FN real ht_wrap_coord(real u, uint mode) {
    if (!ht_isfinite(u)) return HT_R(0);
    if (mode == HT_WRAP_CLAMP) return ht_clamp(u, HT_R(0), HT_R(1));
    if (mode == HT_WRAP_MIRROR) return u - HT_R(2) * floor(u * HT_R(0.5));
    return u - floor(u);
}

/* Texel index i (any int within a few periods) wrapped into [0, n). */
HT_FN int ht_wrap_texel(int i, int n, uint mode) {
    if (mode == HT_WRAP_CLAMP) return i < 0 ? 0 : (i >= n ? n - 1 : i);
    if (mode == HT_WRAP_MIRROR) {
        const int p = 2 * n;
        int m = i % p;
        if (m < 0) m += p;
        return m < n ? m : p - 1 - m;
    }
    int m = i % n;
    return m < 0 ? m + n : m;
}

/* Bilinear, linear-light rgb of texture `tex` at (u, v); texels is the shared texel buffer
 * (decode table first). */
HT_FN real3 ht_texture_sample(HtTexture tex, HT_CONST_GLOBAL uint* texels, real u, real v) {
    const int w = (int)tex.width, h = (int)tex.height;
    const real x = ht_wrap_coord(u, tex.wrap_s) * (real)w - HT_R(0.5);
    const real y = ht_wrap_coord(v, tex.wrap_t) * (real)h - HT_R(0.5);
    const real x0f = floor(x), y0f = floor(y);
    const real fx = x - x0f, fy = y - y0f;
    const int x0 = (int)x0f, y0 = (int)y0f;
    const uint xa = (uint)ht_wrap_texel(x0, w, tex.wrap_s);
    const uint xb = (uint)ht_wrap_texel(x0 + 1, w, tex.wrap_s);
    const uint ya = (uint)ht_wrap_texel(y0, h, tex.wrap_t);
    const uint yb = (uint)ht_wrap_texel(y0 + 1, h, tex.wrap_t);
    HT_CONST_GLOBAL uint* t = texels + tex.offset;
    const real3 c00 = ht_texel_linear(texels, t[ya * tex.width + xa]);
    const real3 c10 = ht_texel_linear(texels, t[ya * tex.width + xb]);
    const real3 c01 = ht_texel_linear(texels, t[yb * tex.width + xa]);
    const real3 c11 = ht_texel_linear(texels, t[yb * tex.width + xb]);
    const real gx = HT_R(1) - fx, gy = HT_R(1) - fy;
    return (c00 * gx + c10 * fx) * gy + (c01 * gx + c11 * fx) * fy;
}

#endif /* HT_SURFACE_TEXTURE_H */
