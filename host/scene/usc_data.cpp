// USC-HairSalon .data strands (Hu et al. 2015), little-endian:
//
//   int32 strand_count
//   strand_count times: int32 vertex_count, then vertex_count x float32 (x, y, z)
//
// A strand with 1 (or 0) vertices is how the database marks a scalp root without hair: skipped
// and counted in a warning.  The format stores no radius: LoadOptions::default_radius when > 0,
// otherwise 1/1000 of the largest extent of the points' bounding box, the same fibre-to-scene
// ratio as the built-in scenes.  Real hair is thinner than that relative to a hairstyle (a ~40 um
// radius on a ~0.5 m hairstyle is 1/10000), but such fibres need far more samples per pixel.
#include <algorithm>
#include <cmath>
#include <limits>

#include "scene/binary_file.h"
#include "scene/hygiene.h"
#include "scene/scene_error.h"

namespace ht {

Scene load_usc_data(const std::string& path, const LoadOptions& opt) {
    BinaryFile file(path);
    if (file.size() < 4)
        scene_fail(path, "the file holds ", file.size(), " bytes, too few for the strand count");
    const int32_t stated = file.read_value<int32_t>(0, "the strand count");
    if (stated < 0) scene_fail(path, "the strand count is negative (", stated, ")");
    const uint64_t strands = static_cast<uint64_t>(stated);
    if (strands * 4 > file.size() - 4)
        scene_fail(path, "header says ", strands, " strands but the file holds only ",
                   file.size() - 4, " bytes after it (each strand needs at least 4)");

    // Pass 1: walk the vertex counts (no allocation beyond the per-strand table) so that every
    // count is checked against the file length and the total is known before points are read.
    struct Run {
        uint64_t offset;  // of the first coordinate
        uint32_t count;   // vertices
        uint32_t file_index;
    };
    std::vector<Run> runs;
    uint64_t offset = 4, total_points = 0, empty_roots = 0;
    for (uint64_t i = 0; i < strands; ++i) {
        if (file.size() - offset < 4)
            scene_fail(path, "the file ends before the vertex count of strand ", i, " (of ",
                       strands, ")");
        const int32_t n = file.read_value<int32_t>(offset, "a vertex count");
        offset += 4;
        if (n < 0) scene_fail(path, "strand ", i, " has a negative vertex count (", n, ")");
        const uint64_t bytes = 12 * uint64_t(n);
        if (bytes > file.size() - offset)
            scene_fail(path, "strand ", i, " says ", n, " vertices (", bytes,
                       " bytes) but only ", file.size() - offset, " bytes remain");
        if (n < 2) {
            ++empty_roots;
        } else {
            runs.push_back({offset, static_cast<uint32_t>(n), static_cast<uint32_t>(i)});
            total_points += uint64_t(n);
            check_scene_size(path, str_cat("the vertex counts up to strand ", i, " say"),
                             runs.size(), total_points, opt);
        }
        offset += bytes;
    }

    Scene scene;
    scene.source = path;
    if (empty_roots > 0)
        scene.warnings.push_back(str_cat(path, ": skipped ", empty_roots,
                                         " empty roots (strands with fewer than 2 vertices)"));
    if (offset < file.size())
        scene.warnings.push_back(str_cat(path, ": ignored ", file.size() - offset,
                                         " bytes after the last strand"));
    if (runs.empty()) scene_fail(path, "the file holds no strand with 2 or more vertices");

    // Pass 2: read the coordinates straight into place.
    Strands& s = scene.strands;
    s.points.resize(total_points);
    s.first_point.resize(runs.size() + 1);
    s.first_point[0] = 0;
    uint64_t next = 0;
    for (size_t r = 0; r < runs.size(); ++r) {
        file.read(runs[r].offset, &s.points[next], 12 * uint64_t(runs[r].count), "the coordinates");
        next += runs[r].count;
        s.first_point[r + 1] = static_cast<uint32_t>(next);
    }

    float radius = opt.default_radius;
    if (!(radius > 0.0f)) {
        radius = radius_from_extent(s.points);
        scene.warnings.push_back(str_cat(path, ": the format stores no radius: using ", radius,
                                         " (1/1000 of the hair's extent; set a default radius "
                                         "to override)"));
    }
    s.radius.assign(total_points, radius);
    s.material.assign(runs.size(), 0);
    scene.materials.push_back(blond_hair_material());

    // Name strands by their index in the file, which differs from ours after skipped roots.
    auto namer = [&runs](size_t strand) { return str_cat("strand ", runs[strand].file_index); };
    add_hygiene_warnings(scene, path, sanitize_strands(s, path, namer));
    return scene;
}

}  // namespace ht
