// Wavefront OBJ line elements (`l v1 v2 ...`) through tinyobjloader (Debian 12's 2.0.0rc10
// parses them into shape_t::lines).  Each `l` element is a strand, and a two-or-more-vertex
// element that starts at the vertex where the previous one ended continues it (exporters that
// write one `l a b` per segment, as glTF LINES does); `v` positions only: OBJ stores no radius,
// so LoadOptions::default_radius, else radius_from_extent.  Faces, points, normals, texture
// coordinates and materials (mtllib is not opened) are ignored, faces with a counted warning.
// Before tinyobjloader allocates anything, one pass over the text counts the `v` lines and the
// `l` indices, checks them against LoadOptions::max_bytes, and keeps only the lines it needs.
#include <fstream>
#include <sstream>

#include <tiny_obj_loader.h>

#include "scene/binary_file.h"
#include "scene/hygiene.h"
#include "scene/scene_error.h"

namespace ht {

namespace {

struct ObjLines {
    std::string text;  // the `v`, `l`, `o` and `g` lines: all tinyobjloader is given
    uint64_t vertices = 0, line_elements = 0, line_indices = 0, faces = 0;
};

// One pass over the text: counts what the strands will need, and keeps only the lines that make
// them.  tinyobjloader never sees the others: besides being unused, some of them reach undefined
// behaviour in it (a `vw` skin weight line with a non-finite joint id is converted to int;
// found by fuzzing, tests/fuzz/regressions/fuzz_obj_file/).
ObjLines hair_lines(const std::string& text) {
    ObjLines c;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        const size_t start = line.find_first_not_of(" \t");
        if (start == std::string::npos || start + 1 >= line.size()) continue;
        const char kind = line[start], next = line[start + 1];
        if (next != ' ' && next != '\t') continue;
        if (kind == 'v') {
            ++c.vertices;
        } else if (kind == 'l') {
            ++c.line_elements;
            std::istringstream words(line.substr(start + 1));
            std::string w;
            while (words >> w) ++c.line_indices;
        } else if (kind == 'f') {
            ++c.faces;
            continue;
        } else if (kind != 'o' && kind != 'g') {
            continue;
        }
        c.text += line;
        c.text += '\n';
    }
    return c;
}

}  // namespace

Scene load_obj_file(const std::string& path, const LoadOptions& opt) {
    require_regular_file(path);
    std::ifstream in(path, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof()) scene_fail(path, "read error");
    const ObjLines counts = hair_lines(text);
    check_scene_size(path, str_cat("the file has ", counts.vertices, " vertices and ", counts.line_indices,
                                   " line element indices"),
                     counts.line_elements, counts.vertices + counts.line_indices, opt);
    if (counts.line_elements == 0) scene_fail(path, "no line elements ('l'): the file holds no hair strands");

    tinyobj::ObjReader reader;
    tinyobj::ObjReaderConfig config;
    config.triangulate = false;
    if (!reader.ParseFromString(counts.text, "", config))
        scene_fail(path, "OBJ parse error: ", reader.Error().empty() ? std::string("unknown") : reader.Error());
    const std::vector<tinyobj::real_t>& v = reader.GetAttrib().vertices;
    const uint64_t vertex_count = v.size() / 3;

    Scene scene;
    scene.source = path;
    Strands& s = scene.strands;
    std::vector<uint64_t> file_element;  // the file's line element (0-based, over all `l`) of each strand
    uint64_t element = 0;
    s.first_point.push_back(0);
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        const std::vector<tinyobj::index_t>& idx = shape.lines.indices;
        size_t next = 0;
        int64_t previous_end = -1;
        for (const int n : shape.lines.num_line_vertices) {
            if (n < 0 || static_cast<size_t>(n) > idx.size() - next)
                scene_fail(path, "line element ", element, ": inconsistent vertex list from the parser");
            for (int k = 0; k < n; ++k) {
                const int64_t i = idx[next + k].vertex_index;
                if (i < 0 || static_cast<uint64_t>(i) >= vertex_count)
                    scene_fail(path, "line element ", element, " vertex ", k, ": index ", i + 1, " is not in [1, ",
                               vertex_count, "]");
            }
            const bool continues = n >= 2 && !file_element.empty() && idx[next].vertex_index == previous_end;
            if (!continues && n > 0) {
                if (!file_element.empty()) s.first_point.push_back(uint32_t(s.points.size())), s.material.push_back(0);
                file_element.push_back(element);
            }
            for (int k = continues ? 1 : 0; k < n; ++k) {
                const size_t i = static_cast<size_t>(idx[next + k].vertex_index);
                s.points.push_back({v[3 * i], v[3 * i + 1], v[3 * i + 2]});
            }
            if (n > 0) previous_end = idx[next + n - 1].vertex_index;
            next += static_cast<size_t>(n);
            ++element;
        }
    }
    if (file_element.empty()) scene_fail(path, "no line elements ('l'): the file holds no hair strands");
    s.first_point.push_back(uint32_t(s.points.size()));
    s.material.push_back(0);
    if (counts.faces > 0)
        scene.warnings.push_back(str_cat(path, ": ignored ", counts.faces, " faces (only line elements are hair)"));

    float radius = opt.default_radius;
    if (!(radius > 0.0f)) {
        radius = radius_from_extent(s.points);
        scene.warnings.push_back(str_cat(path, ": OBJ stores no radius: using ", radius,
                                         " (1/1000 of the hair's extent; set a default radius to override)"));
    }
    s.radius.assign(s.points.size(), radius);
    scene.materials.push_back(blond_hair_material());
    auto namer = [&file_element](size_t strand) { return str_cat("line element ", file_element[strand]); };
    add_hygiene_warnings(scene, path, sanitize_strands(s, path, namer));
    return scene;
}

}  // namespace ht
