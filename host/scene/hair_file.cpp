// Cem Yuksel's .hair format (http://www.cemyuksel.com/research/hairmodels/), little-endian:
//
//   offset  type        field
//   0       char[4]     "HAIR"
//   4       uint32      hair_count (strands)
//   8       uint32      point_count (all strands)
//   12      uint32      arrays: 1 segments, 2 points, 4 thickness, 8 transparency, 16 color
//   16      uint32      default segment count (when bit 1 is clear)
//   20      float32     default thickness (when bit 4 is clear)
//   24      float32     default transparency
//   28      float32[3]  default color
//   40      char[88]    info
//   128     then the arrays whose bits are set, in bit order: uint16 segments[hair_count],
//           float32 points[point_count][3], float32 thickness[point_count],
//           float32 transparency[point_count], float32 color[point_count][3].
//
// Thickness is used as the fibre RADIUS (as Embree's cy_hair_loader and the project's Embree
// anchor do) unless LoadOptions::thickness_is_diameter.  Transparency and colour are skipped:
// appearance comes from the scene's hair material.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>

#include "core/hash.h"
#include "scene/binary_file.h"
#include "scene/hygiene.h"
#include "scene/scene_error.h"

namespace ht {

namespace {

constexpr uint64_t kHeaderBytes = 128;
constexpr uint32_t kSegmentsBit = 1, kPointsBit = 2, kThicknessBit = 4, kTransparencyBit = 8,
                   kColorBit = 16;
constexpr uint32_t kKnownBits = 31;

#pragma pack(push, 1)
struct HairHeader {
    char signature[4];
    uint32_t hair_count;
    uint32_t point_count;
    uint32_t arrays;
    uint32_t default_segments;
    float default_thickness;
    float default_transparency;
    float default_color[3];
    char info[88];
};
#pragma pack(pop)
static_assert(sizeof(HairHeader) == kHeaderBytes, ".hair header is 128 bytes");
static_assert(sizeof(Vec3f) == 12, "Vec3f must be three packed floats (read by memcpy)");

// One array of the file as the header states it: element count and byte length (0 bytes when
// its flag bit is clear).
struct ArrayExtent {
    const char* name;
    uint64_t count;  // elements stated by the header
    const char* unit;
    uint64_t bytes;
};

}  // namespace

Scene load_hair_file(const std::string& path, const LoadOptions& opt) {
    BinaryFile file(path);
    if (file.size() < kHeaderBytes)
        scene_fail(path, "the file holds ", file.size(), " bytes, less than the ", kHeaderBytes,
                   "-byte .hair header");
    HairHeader h;
    file.read(0, &h, sizeof h, "the header");
    if (std::memcmp(h.signature, "HAIR", 4) != 0)
        scene_fail(path, "not a .hair file (the signature is not \"HAIR\")");
    if (h.arrays & ~kKnownBits)
        scene_fail(path, "unknown array flag bits 0x", std::hex, (h.arrays & ~kKnownBits),
                   " (known: 1 segments, 2 points, 4 thickness, 8 transparency, 16 color)");
    if (!(h.arrays & kPointsBit))
        scene_fail(path, "the points array flag (2) is clear: the file holds no geometry");
    if (h.hair_count == 0) scene_fail(path, "the header says the file holds no strands");

    const uint64_t strands = h.hair_count, points = h.point_count;
    check_scene_size(path, str_cat("header says ", strands, " strands and ", points, " points"),
                     strands, points, opt);

    // Every array's extent, checked against the file length before anything is allocated.
    const ArrayExtent arrays[] = {
        {"segment counts", strands, "strands", (h.arrays & kSegmentsBit) ? 2 * strands : 0},
        {"point coordinates", points, "points", 12 * points},
        {"thickness values", points, "points", (h.arrays & kThicknessBit) ? 4 * points : 0},
        {"transparency values", points, "points", (h.arrays & kTransparencyBit) ? 4 * points : 0},
        {"colors", points, "points", (h.arrays & kColorBit) ? 12 * points : 0},
    };
    uint64_t offset = kHeaderBytes;
    uint64_t array_offset[5];
    for (int a = 0; a < 5; ++a) {
        array_offset[a] = offset;
        const uint64_t available = file.size() - offset;
        if (arrays[a].bytes > available)
            scene_fail(path, "header says ", arrays[a].count, " ", arrays[a].unit,
                       " but the file holds only ", available, " bytes of ", arrays[a].name,
                       " (needs ", arrays[a].bytes, ")");
        offset += arrays[a].bytes;
    }

    Scene scene;
    scene.source = path;
    if (offset < file.size())
        scene.warnings.push_back(str_cat(path, ": ignored ", file.size() - offset,
                                         " bytes after the last array"));

    // Strand layout: per-strand segment counts or the default, which must add up to point_count.
    Strands& s = scene.strands;
    s.first_point.resize(strands + 1);
    s.first_point[0] = 0;
    if (h.arrays & kSegmentsBit) {
        std::vector<uint16_t> segments(strands);
        file.read(array_offset[0], segments.data(), 2 * strands, "the segment counts");
        uint64_t total = 0;
        for (uint64_t i = 0; i < strands; ++i) {
            total += uint64_t(segments[i]) + 1;
            // Stop at the first overshoot so first_point never wraps around.
            if (total > points)
                scene_fail(path, "segment counts need more than the ", points,
                           " points the header states (exceeded at strand ", i, ")");
            s.first_point[i + 1] = static_cast<uint32_t>(total);
        }
        if (total != points)
            scene_fail(path, "segment counts add up to ", total, " points but the header says ",
                       points);
    } else {
        const uint64_t per_strand = uint64_t(h.default_segments) + 1;
        if (strands * per_strand != points)
            scene_fail(path, "header says ", strands, " strands of ", h.default_segments,
                       " segments (", strands * per_strand, " points) but point_count is ", points);
        for (uint64_t i = 0; i < strands; ++i)
            s.first_point[i + 1] = static_cast<uint32_t>((i + 1) * per_strand);
    }

    s.points.resize(points);
    file.read(array_offset[1], s.points.data(), 12 * points, "the point coordinates");

    const float radius_scale = opt.thickness_is_diameter ? 0.5f : 1.0f;
    if (h.arrays & kThicknessBit) {
        s.radius.resize(points);
        file.read(array_offset[2], s.radius.data(), 4 * points, "the thickness values");
        for (float& r : s.radius) r *= radius_scale;
    } else {
        const float radius =
            opt.default_radius > 0.0f ? opt.default_radius : h.default_thickness * radius_scale;
        if (!std::isfinite(radius) || !(radius > 0.0f))
            scene_fail(path, "no thickness array and the default thickness is ",
                       h.default_thickness, " (set a default radius to load this file)");
        s.radius.assign(points, radius);
    }

    s.material.assign(strands, 0);
    scene.materials.push_back(blond_hair_material());
    add_hygiene_warnings(scene, path, sanitize_strands(s, path));
    return scene;
}

namespace {
constexpr size_t kAllStrandsFit = ~size_t(0);
// The .hair segments array of `s` (segments per strand); returns the first strand the format cannot
// hold (no point, or more than 65,536), kAllStrandsFit when there is none.
size_t hair_segment_counts(const Strands& s, std::vector<uint16_t>& segments) {
    segments.resize(s.strand_count());
    for (size_t i = 0; i < segments.size(); ++i) {
        const size_t n = s.first_point[i + 1] - s.first_point[i];
        if (n < 1 || n - 1 > std::numeric_limits<uint16_t>::max()) return i;
        segments[i] = static_cast<uint16_t>(n - 1);
    }
    return kAllStrandsFit;
}
}  // namespace

uint64_t hair_file_hash(const Strands& s) {
    std::vector<uint16_t> segments;
    if (s.strand_count() > std::numeric_limits<uint32_t>::max() ||
        s.point_count() > std::numeric_limits<uint32_t>::max() || hair_segment_counts(s, segments) != kAllStrandsFit)
        return 0;
    return fnv1a(s.radius, fnv1a(s.points, fnv1a(segments)));
}

void save_hair_file(const std::string& path, const Scene& scene) {
    const Strands& s = scene.strands;
    const size_t strands = s.strand_count();
    if (strands > std::numeric_limits<uint32_t>::max() ||
        s.point_count() > std::numeric_limits<uint32_t>::max())
        scene_fail(path, "too many strands or points for the .hair format");
    std::vector<uint16_t> segments;
    const size_t bad = hair_segment_counts(s, segments);
    if (bad != kAllStrandsFit)
        scene_fail(path, "strand ", bad, " has ", s.first_point[bad + 1] - s.first_point[bad],
                   " points; the .hair format stores 1..65536 points per strand");
    HairHeader h;
    std::memset(&h, 0, sizeof h);
    std::memcpy(h.signature, "HAIR", 4);
    h.hair_count = static_cast<uint32_t>(strands);
    h.point_count = static_cast<uint32_t>(s.point_count());
    h.arrays = kSegmentsBit | kPointsBit | kThicknessBit;
    h.default_segments = strands > 0 ? segments[0] : 0;
    h.default_thickness = s.radius.empty() ? 0.1f : s.radius[0];
    h.default_transparency = 0.0f;
    h.default_color[0] = 0.9f, h.default_color[1] = 0.75f, h.default_color[2] = 0.5f;
    std::snprintf(h.info, sizeof h.info, "hairtrace; thickness=RADIUS; source %s",
                  scene.source.c_str());

    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) scene_fail(path, "cannot open for writing");
    out.write(reinterpret_cast<const char*>(&h), sizeof h);
    out.write(reinterpret_cast<const char*>(segments.data()),
              static_cast<std::streamsize>(segments.size() * sizeof(uint16_t)));
    out.write(reinterpret_cast<const char*>(s.points.data()),
              static_cast<std::streamsize>(s.points.size() * sizeof(Vec3f)));
    out.write(reinterpret_cast<const char*>(s.radius.data()),
              static_cast<std::streamsize>(s.radius.size() * sizeof(float)));
    out.close();
    if (!out) scene_fail(path, "write error");
}

}  // namespace ht
