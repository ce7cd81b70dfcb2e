/* Struct layouts shared by the host and the kernels, declared once.
 *
 * Only float / uint / int fields and fixed arrays of them: no real, no float3 (whose size differs
 * between OpenCL C and C++), no pointers.  Every struct's size is a multiple of 8 bytes and is
 * declared with its field offsets in layouts.h, which both compilers check.
 */
#ifndef HT_TYPES_H
#define HT_TYPES_H

#include "compat.h"
#include "features.h"

/* ---------------------------------------------------------------- geometry */

/* A strand point: position and radius (Embree's RTC_FORMAT_FLOAT4 vertex). */
typedef struct {
    float x, y, z, r;
} HtPoint;

/* One leaf primitive = one capsule segment between points `point` and `point + 1`.
 * flags: HT_SEG_FIRST marks a strand's first segment, which owns its begin sphere; every other
 * joint sphere belongs to the segment that ends there (Embree's round linear curve rule). */
#define HT_SEG_FIRST 1u
/* A triangle, not a capsule (meshes share the BVH with the hair): `point` is the first of three
 * consecutive HtPoint vertices (r unused), `segment` its global primitive id (segment_count +
 * triangle index) and `strand` the triangle index into the HtTriangleShading array. */
#define HT_SEG_TRIANGLE 2u
/* A strand's last segment: no successor at `point + 2` (the joint rule, ht_strand_interior in
 * kernels/geometry/bvh_traverse.h, reads the neighbours of every other segment). */
#define HT_SEG_LAST 4u
/* 8 bytes per leaf record (host/bvh/NOTES.md "Eight-byte leaf records"): the strand id and the
 * flags share a word, and the global segment id (Embree's primID) is not stored: it grows with
 * `point` (strands back to back, then the triangles), which is all the kernels need of it
 * (ht_hit_precedes), and the host derives it (host/bvh/bvh.h SceneGeometry::global_id). */
typedef struct {
    uint point;         /* index of the first point */
    uint strand_flags;  /* strand id (triangles: triangle index) << HT_SEG_FLAG_BITS | HT_SEG_* flags */
} HtSegment;
#define HT_SEG_FLAG_BITS 3u
#define HT_SEG_FLAG_MASK 7u
/* the largest strand (or triangle) id a record holds */
#define HT_SEG_MAX_STRAND (0xFFFFFFFFu >> HT_SEG_FLAG_BITS)

HT_FN uint ht_seg_flags(HtSegment s) { return s.strand_flags & HT_SEG_FLAG_MASK; }
HT_FN uint ht_seg_strand(HtSegment s) { return s.strand_flags >> HT_SEG_FLAG_BITS; }
HT_FN HtSegment ht_make_segment(uint point, uint strand, uint flags) {
    HtSegment s;
    s.point = point;
    s.strand_flags = strand << HT_SEG_FLAG_BITS | flags;
    return s;
}

/* 8-wide BVH node, the children's bounds as SoA (host/bvh/NOTES.md "8-wide nodes"): per axis the
 * eight children's lower bounds, then their upper bounds, so one float16 multiply-subtract per axis
 * gives every entry and exit distance (kernels/geometry/bvh_traverse.h ht_node_slabs).  256 bytes:
 * a power of two, which pages.h pages by shift and mask.
 * count[k] == 0: child[k] is an inner node reference (index | HT_NODE_ORIENTED, below);
 * count[k] > 0: child[k] is the first index into the leaf segment array and count[k] the number
 * of segments; child 0 with count 0 = empty slot (node 0 is the root, never a child).
 *
 * Oriented nodes (host/bvh/NOTES.md "Oriented nodes"): a reference with HT_NODE_ORIENTED names a
 * node of two consecutive records (so that the node array stays one record type for paging)
 * whose children are oriented boxes: child k has an affine map p' = A_k p + b_k taking its box to
 * the unit cube [0,1]^3.  Its 12 coefficients (rows j = 0..2: A_k[j][0..2], b_k[j]) are stored
 * coefficient-major, the HT_BVH_WIDTH children side by side: coefficients 0-1 in the first record's
 * x, 2-3 in its y, 4-5 in its z, 6-7, 8-9, 10-11 in the second's x, y, z; child[] and count[] are
 * the first record's (the second's are unused).  The root (node 0) is never oriented. */
#define HT_BVH_WIDTH 8
#define HT_NODE_ORIENTED 0x80000000u
typedef struct {
    float x[2 * HT_BVH_WIDTH];
    float y[2 * HT_BVH_WIDTH];
    float z[2 * HT_BVH_WIDTH];
    uint child[HT_BVH_WIDTH];
    uint count[HT_BVH_WIDTH];
} HtBvhNode;

/* A uniform grid over the capsules for the path rays' closest hits (host/render/path_grid.h builds it,
 * kernels/geometry/path_grid.h walks it): cell (x, y, z) is the box lo + cell * [x, x+1] x ... and
 * lists every capsule that may meet a ray inside it. */
typedef struct {
    float lo[3];
    float cell;
    uint dims[3];
    float inv_cell; /* 1 / cell */
} HtPathGrid;

/* No texture: HtTriangleShading.texture of an untextured triangle. */
#define HT_NO_TEXTURE 0xFFFFFFFFu

/* Per-triangle shading data, indexed by the strand id of a triangle record (ht_seg_strand).  128
 * bytes: a power of two so that paged geometry (geometry/pages.h) finds a record by shift and mask. */
typedef struct {
    float n0[4], n1[4], n2[4]; /* vertex shading normals xyz (w = 1 when present, 0: use the
                                * geometric normal) */
    float albedo[4];           /* Lambertian albedo rgb (glTF baseColorFactor), w unused */
    float uv[6];               /* TEXCOORD_0 of vertices 0, 1, 2 (u0 v0 u1 v1 u2 v2), 0 without */
    uint texture;              /* index into the HtTexture array, or HT_NO_TEXTURE */
    uint pad0, pad1[8];
} HtTriangleShading;

/* Texture wrap modes (glTF sampler wrapS / wrapT, same meaning as OpenGL's). */
#define HT_WRAP_REPEAT 0u
#define HT_WRAP_CLAMP 1u
#define HT_WRAP_MIRROR 2u

/* One texture in the shared texel buffer: texels [offset, offset + width * height), row 0 at
 * v = 0 (the top of the image, as glTF), one uint per texel holding sRGB-encoded 8-bit r | g << 8
 * | b << 16 (alpha is not used).  Sampled bilinearly without mip-maps (kernels/surface/texture.h).
 * The buffer begins with the HT_SRGB_TABLE_SIZE-entry sRGB decode table, so offsets start there.
 * 32 bytes. */
#define HT_SRGB_TABLE_SIZE 256u
typedef struct {
    uint offset, width, height, pad0;
    uint wrap_s, wrap_t, pad1, pad2;
} HtTexture;

/* ---------------------------------------------------------------- rays and hits */

typedef struct {
    float ox, oy, oz, tmin;
    float dx, dy, dz, tmax;
} HtRay;

/* Closest hit.  segment = HT_NO_HIT for a miss.  For a hair segment: u = position along the
 * segment [0,1], h = signed offset across the fibre in units of the radius [-1,1]
 * (docs/MODEL.md §1), (tx,ty,tz) = unit tangent root->tip, radius > 0.  For a triangle
 * (segs[segment].flags & HT_SEG_TRIANGLE; radius == 0): u, h = barycentrics of vertices 1 and 2,
 * (tx,ty,tz) = unit geometric normal (counter-clockwise front, not flipped towards the ray). */
#define HT_NO_HIT 0xFFFFFFFFu
typedef struct {
    float t, u, h;
    uint segment;  /* index into the leaf segment array (not the global id) */
    float tx, ty, tz, radius;
} HtHit;

/* ---------------------------------------------------------------- wavefront path state */

/* One path of the current pass: a sample of `pixel` (kernels/stages/generate_camera_rays.cl says
 * which camera path renders which pixel and sample).  The path's radiance is summed in bounce order inside the path, so float results do not depend on the
 * order in which queues are compacted. */
typedef struct {
    float throughput[3];
    uint pixel;
    float radiance[3];
    uint flags;
    float last_pdf;  /* solid-angle pdf of the BCSDF sample that made the current ray (MIS) */
    uint split;      /* which of its camera path's continuations this is (--first-hit-splits;
                      * kernels/rng.h ht_continuation_sample): 0 for the camera path itself */
    uint sample;     /* the camera sample's index: a pass may render several samples of a pixel */
    uint node;       /* the BVH node whose leaf held the path's last hit, where the traversal of its
                      * next rays starts (kernels/geometry/bvh_traverse.h ht_traverse_from); 0: the root */
} HtPathState;
#define HT_PATH_FROM_CAMERA 1u  /* the current ray is a camera ray: no MIS on what it sees */
#define HT_PATH_FROM_FIBRE 2u   /* the current ray left a fibre (--light-vertices: the MIS partner of a connection) */

/* Unoccluded contribution of a queued shadow ray, added to path `path` if the ray is clear. */
typedef struct {
    float contrib[3];
    uint path;
} HtShadowContrib;

/* --indirect dual: what the dual-scattering terms of a queued shadow ray need besides the
 * crossings its shadow ray finds (kernels/stages/intersect_shadow_afs.cl): the light sample's
 * weight without the BCSDF (throughput x light / pdf x pick count; no MIS weight, since BCSDF
 * sampling never finds these terms), the fibre-frame angles and the material.
 * material = HT_NO_PATH: not a fibre (a surface point: opaque shadows only). */
typedef struct {
    float weight[3];
    uint material;
    float theta_i, theta_o, phi, pad;
} HtDualRecord;

/* stage_path value of a slot whose path did not continue */
#define HT_NO_PATH 0xFFFFFFFFu

/* Queue counters read back by the host after each shade: */
#define HT_COUNTER_SHADOW 0
#define HT_COUNTER_NEXT 1
#define HT_COUNTER_NAN 2   /* non-finite values caught and zeroed (reported, never written) */
#define HT_COUNTER_CUT 3   /* paths cut by --max-depth (kernels/stages/shade.cl says which) */
#define HT_COUNTER_COUNT 4

/* What one shade launch needs besides its buffers: the seed of the random sequence (each path
 * carries its sample index), the bounce and its limit, the --fiber-field choice and the first-hit
 * splits. */
typedef struct {
    uint seed, pad0, bounce, max_depth;
    uint field_mode;    /* HT_FIELD_* */
    float pixel_angle;  /* radians per pixel at the image centre (ray footprint for HT_FIELD_AUTO) */
    uint splits;        /* --first-hit-splits: continuations of each camera path after its first vertex */
    uint light_samples; /* --first-hit-light-samples: next-event estimates at that vertex */
} HtBounce;

/* --light-vertices N (kernels/integrator/light_vertices.h): each camera sample s of a pass owns
 * `count` light rays, set s - first_sample of light_rays / light_hits, the lights taking turns;
 * their first hits on fibres are the light vertices that the sample's fibre vertices connect to. */
typedef struct {
    float disc[4];     /* the scene's bounding sphere: centre (xyz) and radius (w) */
    uint count;        /* light rays per camera sample */
    uint first_sample; /* the pass's first camera sample */
    uint pad0, pad1;
} HtLightVertices;

/* --first-hit-splits auto: the continuations per camera sample of its pilot render
 * (kernels/stages/split_pilot.cl, host/render/split_choice.h) */
#define HT_PILOT_SPLITS 2u

/* ---------------------------------------------------------------- camera and lights */

typedef struct {
    float eye[4];     /* xyz, w unused */
    float right[4];   /* scaled by tan(fov/2)*aspect */
    float up[4];      /* scaled by tan(fov/2) */
    float forward[4];
    uint width, height, pad0, pad1;
} HtCamera;

/* A light's shadow lists (host/render/shadow_lists.h), of one of two kinds:
 * - HT_SHADOW_GRID_ALONG, a directional light's: every shadow ray toward it runs along `dir` (its
 *   -direction, bit for bit), so it stays in one cell of a grid across that direction, and only the
 *   primitives listed for the cell can block it.  A point p lies in cell (floor((p.u - u[3]) cells),
 *   floor((p.v - v[3]) cells)), cells = inv_cell.
 * - HT_SHADOW_GRID_FROM_POINT, a point or spot light's: a shadow ray toward it runs (within
 *   dir[3] of it) along the line from the light through its origin o, so the direction of o seen
 *   from the light picks its cell, on an image of the scene as a camera at the light would see it:
 *   depth z = u . (o - light), image coordinates v . (o - light) / z and w . (o - light) / z in
 *   [-1, 1], the nx x ny cells spanning that square; only primitives whose image covers the cell
 *   and which lie nearer the light than o can block it.
 * Either grid's nx x ny cells are cells cell_offset .. of the shared start / count arrays, row by row. */
#define HT_SHADOW_GRID_ALONG 0u
#define HT_SHADOW_GRID_FROM_POINT 1u
typedef struct {
    float dir[4];  /* along: the rays' direction xyz; from a point: the light's position xyz, and in
                      w how far from it a ray's line may pass and still take the grid */
    float u[4];    /* along: xyz the grid's first axis, w its origin's coordinate on it; from a point:
                      xyz the depth axis (unit) */
    float v[4];    /* along: the same for the second axis; from a point: xyz the image's first axis
                      over the image's half-width (a tangent) */
    float w[4];    /* from a point: the image's second axis likewise; along: unused */
    float inv_cell;
    uint nx, ny, cell_offset;
    uint kind, pad0, pad1, pad2;
} HtShadowGrid;

#define HT_LIGHT_POINT 0u
#define HT_LIGHT_SPOT 1u
#define HT_LIGHT_DIRECTIONAL 2u
#define HT_LIGHT_SPHERE 3u
/* Lights a single next-event estimate picks from by importance at most (kernels/lights.h
 * ht_pick_light reads every light's importance at the shading point); scenes with more pick
 * uniformly, and the host compiles the pick in only for 2..HT_LIGHT_PICK_MAX lights. */
#define HT_LIGHT_PICK_MAX 16u
typedef struct {
    uint type, pad0, pad1, pad2;
    float position[4];   /* xyz; w = sphere radius */
    float direction[4];  /* unit direction the light travels (spot axis / directional) */
    float radiance[4];   /* rgb intensity (W/sr) for point/spot, irradiance for directional */
    float cos_outer, cos_inner, pad3, pad4;
} HtLight;

/* Environment light: a lat-long radiance map (importance sampled through the CDF tables built
 * on the host) or, with has_map = 0, a uniform radiance `scale`.  Direction d maps to
 * u = 0.5 + atan2(d.x, -d.z) / 2pi, v = acos(d.y) / pi (+y up, row 0 at the zenith). */
typedef struct {
    uint width, height, has_map, enabled;
    float scale[4];  /* rgb multiplier (uniform radiance when has_map = 0) */
} HtEnvironment;

/* ---------------------------------------------------------------- materials */

#define HT_MODEL_KAJIYA 0u
#define HT_MODEL_MARSCHNER 1u
#define HT_MODEL_ZINKE 2u
#define HT_MODEL_CHIANG 3u
#define HT_MODEL_COUNT 4u

/* --fiber-field: which of the two Marschner-family models shades a marschner/zinke material */
#define HT_FIELD_MATERIAL 0u /* the material's own model */
#define HT_FIELD_NEAR 1u     /* zinke (near field, evaluated at the hit's h) */
#define HT_FIELD_FAR 2u      /* marschner (far field, integrated over h) */
#define HT_FIELD_AUTO 3u     /* by ray footprint, see shade.cl */
/* auto picks the near field when the fibre's diameter is at least this fraction of the camera
 * pixel's footprint at the hit */
#define HT_FIELD_AUTO_COVERAGE 0.5f

/* Hair material as the kernels see it: parameters already validated and converted on the host
 * (melanin/colour -> sigma_a, degrees -> radians) and derived quantities precomputed, all by
 * make_kernel_material (host/fiber/material.h).  Fields not used by a model are ignored by it.
 * 272 bytes (17 x 16). */
typedef struct {
    uint model, flags, pad0, pad1;
    float sigma_a[4];                 /* absorption per unit radius, rgb (all models but kajiya) */
    float eta, beta_m, beta_n, alpha; /* alpha: scale tilt in radians (chiang) */
    /* chiang: d'Eon longitudinal variances for R, TT, TRT, residual (v, v/4, 4v, 4v) */
    float v[4];
    /* chiang: -log v - log1p(-exp(-2/v)) per lobe (log normaliser of M_p; float kernels use it) */
    float mp_c[4];
    /* s: logistic scale (chiang); azim_sigma: std of the zinke azimuthal wrapped Gaussian (radians);
     * ks_norm: 1 / integral of the Kajiya-Kay specular lobe; ks_exponent: Kajiya-Kay exponent */
    float s, azim_sigma, ks_norm, ks_exponent;
    float sin_tilt[4];                /* sin(alpha), sin(2 alpha), sin(4 alpha), 0 */
    float cos_tilt[4];                /* cos of the same */
    /* Marschner / Zinke longitudinal shifts and widths (radians) */
    float alpha_r, alpha_tt, alpha_trt, pad2;
    float beta_r, beta_tt, beta_trt, pad3;
    /* Marschner caustic: w_c (radians), k_G, delta_eta', delta_h_M */
    float caustic_wc, caustic_kg, caustic_deta, caustic_dhm;
    float eccentricity, pad4, pad5, pad6; /* a <= 1: minor/major axis ratio (marschner TRT) */
    /* Kajiya-Kay */
    float kd[4];
    float ks[4];
    /* marschner/zinke, per lobe R, TT, TRT (and 0): sin and cos of the cone tilt 2 alpha_p and the
     * log normaliser of the sampling proxy's variance (2 beta_p)^2, which every shading point
     * needs (kernels/fiber/marschner.h ht_mz_prepare_material; float kernels read them) */
    float mz_sin_tilt[4];
    float mz_cos_tilt[4];
    float mz_log_norm[4];
} HtMaterial;

#endif /* HT_TYPES_H */
