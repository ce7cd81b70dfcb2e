// PLY polylines (Stanford PLY: `format ascii 1.0`, `binary_little_endian 1.0` or
// `binary_big_endian 1.0`), read by a compact reader of our own (Debian 12 packages none).
//
// PLY has no standard for curves; hair exporters and point-cloud tools write one of three
// layouts, all read here (the first that applies):
//   1. an element named strand, strands, curve, curves, polyline or hair with a LIST property
//      (vertex_indices or vertex_index): each item is one strand, its vertices by index;
//   2. the same element with a SCALAR property (vertex_count, nverts, num_vertices or count):
//      strand i is the next vertex_count[i] vertices in file order (the counts must add up to
//      the vertex count);
//   3. an `edge` element with scalar vertex1 and vertex2 (Paul Bourke's PLY description):
//      consecutive edges that share an endpoint (end of one == start of the next) form a strand.
// Vertices: element `vertex` with x, y, z and an optional per-vertex size: `radius` (a radius),
// `thickness` (a radius, or a diameter with --thickness diameter, as for .hair) or `width` (a
// diameter, as Houdini and pbrt use it).  Without one: LoadOptions::default_radius, else
// radius_from_extent.  Every other element and property is read past and ignored (counted in a
// warning).  Counts are checked against the file length and LoadOptions::max_bytes before the
// strand arrays are allocated.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scene/binary_file.h"
#include "scene/hygiene.h"
#include "scene/scene_error.h"

namespace ht {

namespace {

enum class PlyFormat { Ascii, BinaryLittle, BinaryBig };

struct PlyProperty {
    std::string name;
    std::string type;            // scalar type, or the item type of a list
    std::string count_type;      // list length type; empty for scalars
    bool is_list() const { return !count_type.empty(); }
};

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> properties;
    int find(std::initializer_list<const char*> names, bool list) const {
        for (const char* n : names)
            for (size_t i = 0; i < properties.size(); ++i)
                if (properties[i].name == n && properties[i].is_list() == list) return int(i);
        return -1;
    }
};

// Bytes of one value of a PLY scalar type; 0 for an unknown type name.
size_t type_size(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

// Reads the values of the body one at a time, ascii or binary, with every read bounds-checked.
class PlyBody {
public:
    PlyBody(const std::string& path, PlyFormat format, uint64_t offset)
        : path_(path), format_(format), in_(path, std::ios::binary) {
        in_.seekg(static_cast<std::streamoff>(offset));
        if (!in_) scene_fail(path, "cannot read the data after the header");
    }

    double value(const std::string& type, const char* what) {
        if (format_ == PlyFormat::Ascii) {
            std::string token;
            if (!(in_ >> token)) scene_fail(path_, "the file ends inside ", what);
            char* end = nullptr;
            const double v = std::strtod(token.c_str(), &end);
            if (*end) scene_fail(path_, "'", token.substr(0, 40), "' is not a number (in ", what, ")");
            return v;
        }
        unsigned char b[8];
        const size_t n = type_size(type);
        in_.read(reinterpret_cast<char*>(b), static_cast<std::streamsize>(n));
        if (static_cast<size_t>(in_.gcount()) != n) scene_fail(path_, "the file ends inside ", what);
        if (format_ == PlyFormat::BinaryBig) std::reverse(b, b + n);
        auto as = [&b](auto v) {
            std::memcpy(&v, b, sizeof v);
            return double(v);
        };
        if (type == "char" || type == "int8") return as(int8_t());
        if (type == "uchar" || type == "uint8") return as(uint8_t());
        if (type == "short" || type == "int16") return as(int16_t());
        if (type == "ushort" || type == "uint16") return as(uint16_t());
        if (type == "int" || type == "int32") return as(int32_t());
        if (type == "uint" || type == "uint32") return as(uint32_t());
        if (type == "float" || type == "float32") return as(float());
        return as(double());
    }

    // A list's length: a whole number in [0, limit].
    uint64_t length(const PlyProperty& p, uint64_t limit, const char* what) {
        const double n = value(p.count_type, what);
        if (!(n >= 0 && n <= double(limit)) || n != std::floor(n))
            scene_fail(path_, "list length ", n, " of ", what, " is not a whole number in [0, ", limit, "]");
        return uint64_t(n);
    }

    // Reads past one item of an element.
    void skip_item(const PlyElement& e, uint64_t limit) {
        for (const PlyProperty& p : e.properties) {
            const uint64_t n = p.is_list() ? length(p, limit, e.name.c_str()) : 1;
            for (uint64_t i = 0; i < n; ++i) value(p.type, e.name.c_str());
        }
    }

private:
    std::string path_;
    PlyFormat format_;
    std::ifstream in_;
};

struct PlyHeader {
    PlyFormat format = PlyFormat::Ascii;
    std::vector<PlyElement> elements;
    uint64_t body_offset = 0;
};

PlyHeader read_header(const std::string& path, uint64_t file_size) {
    constexpr size_t kMaxHeader = 1 << 16;
    std::ifstream in(path, std::ios::binary);
    std::string line;
    if (!std::getline(in, line) || (line != "ply" && line != "ply\r")) scene_fail(path, "not a PLY file (no \"ply\" line)");
    PlyHeader h;
    bool has_format = false;
    for (;;) {
        if (!std::getline(in, line)) scene_fail(path, "the file ends inside the header (no end_header)");
        if (static_cast<uint64_t>(in.tellg()) > kMaxHeader) scene_fail(path, "the header is longer than 64 KiB");
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream words(line);
        std::string word;
        words >> word;
        if (word == "end_header") break;
        if (word == "comment" || word == "obj_info" || word.empty()) continue;
        if (word == "format") {
            std::string f, version;
            words >> f >> version;
            if (f == "ascii") h.format = PlyFormat::Ascii;
            else if (f == "binary_little_endian") h.format = PlyFormat::BinaryLittle;
            else if (f == "binary_big_endian") h.format = PlyFormat::BinaryBig;
            else scene_fail(path, "unknown PLY format '", f, "'");
            has_format = true;
        } else if (word == "element") {
            PlyElement e;
            double count = -1;
            words >> e.name >> count;
            if (e.name.empty() || !(count >= 0 && count <= double(file_size)) || count != std::floor(count))
                scene_fail(path, "element '", e.name, "': the count is missing, or more items than the file's ", file_size,
                           " bytes could hold");
            e.count = uint64_t(count);
            h.elements.push_back(e);
        } else if (word == "property") {
            if (h.elements.empty()) scene_fail(path, "a property before any element");
            PlyProperty p;
            std::string type;
            words >> type;
            if (type == "list") words >> p.count_type >> p.type >> p.name;
            else p.type = type, words >> p.name;
            if (type_size(p.type) == 0 || (p.is_list() && type_size(p.count_type) == 0) || p.name.empty())
                scene_fail(path, "element '", h.elements.back().name, "': bad property line '", line, "'");
            h.elements.back().properties.push_back(p);
        } else {
            scene_fail(path, "unknown header line '", line.substr(0, 60), "'");
        }
    }
    if (!has_format) scene_fail(path, "the header has no format line");
    h.body_offset = static_cast<uint64_t>(in.tellg());
    return h;
}

// The smallest number of bytes one item of `e` takes in the file (a lower bound for ascii: one
// digit and a separator per value), to refuse counts the file cannot hold before allocating.
uint64_t min_item_bytes(const PlyElement& e, PlyFormat format) {
    uint64_t bytes = 0;
    for (const PlyProperty& p : e.properties)
        bytes += format == PlyFormat::Ascii ? 2 : type_size(p.is_list() ? p.count_type : p.type);
    return std::max<uint64_t>(bytes, 1);
}

bool is_strand_element(const std::string& n) {
    return n == "strand" || n == "strands" || n == "curve" || n == "curves" || n == "polyline" || n == "hair";
}

}  // namespace

Scene load_ply_file(const std::string& path, const LoadOptions& opt) {
    require_regular_file(path);
    const uint64_t file_size = std::filesystem::file_size(path);
    const PlyHeader h = read_header(path, file_size);
    const uint64_t body_bytes = file_size - h.body_offset;
    const PlyElement* vertex = nullptr;
    const PlyElement* strands = nullptr;
    const PlyElement* edges = nullptr;
    for (const PlyElement& e : h.elements) {
        if (body_bytes / min_item_bytes(e, h.format) < e.count)
            scene_fail(path, "header says ", e.count, " ", e.name, " items but the file holds only ",
                       body_bytes, " bytes of data");
        if (e.name == "vertex" && !vertex) vertex = &e;
        else if (is_strand_element(e.name) && !strands) strands = &e;
        else if (e.name == "edge" && !edges) edges = &e;
    }
    if (!vertex) scene_fail(path, "no 'vertex' element");
    const int px = vertex->find({"x"}, false), py = vertex->find({"y"}, false), pz = vertex->find({"z"}, false);
    if (px < 0 || py < 0 || pz < 0) scene_fail(path, "the vertex element lacks a scalar x, y or z property");
    const int p_radius = vertex->find({"radius"}, false), p_thickness = vertex->find({"thickness"}, false),
              p_width = vertex->find({"width"}, false);
    int strand_list = -1, strand_count = -1, edge_a = -1, edge_b = -1;
    if (strands) {
        strand_list = strands->find({"vertex_indices", "vertex_index"}, true);
        if (strand_list < 0) strand_count = strands->find({"vertex_count", "nverts", "num_vertices", "count"}, false);
    }
    if (edges) edge_a = edges->find({"vertex1"}, false), edge_b = edges->find({"vertex2"}, false);
    if (strand_list < 0 && strand_count < 0 && (edge_a < 0 || edge_b < 0))
        scene_fail(path, "no strands: expected an element strand/curve/polyline with vertex_indices or "
                         "vertex_count, or an edge element with vertex1 and vertex2");
    const uint64_t vertices = vertex->count;
    check_scene_size(path, str_cat("header says ", vertices, " vertices"), 0, vertices, opt);

    Scene scene;
    scene.source = path;
    std::vector<Vec3f> at(vertices);
    std::vector<float> size(vertices, 0.0f);
    float size_scale = 1.0f;
    int p_size = p_radius;
    if (p_size < 0 && p_thickness >= 0) p_size = p_thickness, size_scale = opt.thickness_is_diameter ? 0.5f : 1.0f;
    if (p_size < 0 && p_width >= 0) p_size = p_width, size_scale = 0.5f;

    Strands& s = scene.strands;
    std::vector<uint32_t> file_strand;  // the file's strand (or first edge) index of each of ours
    uint64_t ignored_elements = 0;
    PlyBody body(path, h.format, h.body_offset);
    // Appends vertex `index` to the current strand; `what item` names the strand or edge in errors.
    auto add_point = [&](double index, const char* what, uint64_t item) {
        if (!(index >= 0 && index < double(vertices)) || index != std::floor(index))
            scene_fail(path, what, " ", item, ": vertex index ", index, " is not in [0, ", vertices, ")");
        if (s.points.size() + 1 > kMaxScenePoints || strands_bytes(s.strand_count() + 1, s.points.size() + 1) > opt.max_bytes)
            check_scene_size(path, str_cat("the strands up to ", what, " ", item, " list"), s.strand_count() + 1,
                             s.points.size() + 1, opt);
        s.points.push_back(at[uint64_t(index)]);
        s.radius.push_back(size[uint64_t(index)]);
    };
    auto end_strand = [&]() {
        s.first_point.push_back(uint32_t(s.points.size()));
        s.material.push_back(0);
    };
    s.first_point.push_back(0);
    uint64_t counted_vertices = 0;
    bool vertices_read = false;
    for (const PlyElement& e : h.elements) {
        if ((&e == strands || &e == edges) && !vertices_read)
            scene_fail(path, "the '", e.name, "' element comes before the vertex element it refers to");
        if (&e == vertex) {
            vertices_read = true;
            for (uint64_t i = 0; i < e.count; ++i)
                for (size_t k = 0; k < e.properties.size(); ++k) {
                    const PlyProperty& p = e.properties[k];
                    if (p.is_list()) {
                        const uint64_t n = body.length(p, body_bytes, "a vertex list property");
                        for (uint64_t j = 0; j < n; ++j) body.value(p.type, "a vertex list property");
                        continue;
                    }
                    const double v = body.value(p.type, "the vertices");
                    if (int(k) == px) at[i][0] = float(v);
                    else if (int(k) == py) at[i][1] = float(v);
                    else if (int(k) == pz) at[i][2] = float(v);
                    else if (int(k) == p_size) size[i] = float(v) * size_scale;
                }
        } else if (&e == strands && (strand_list >= 0 || strand_count >= 0)) {
            for (uint64_t i = 0; i < e.count; ++i) {
                file_strand.push_back(uint32_t(i));
                for (size_t k = 0; k < e.properties.size(); ++k) {
                    const PlyProperty& p = e.properties[k];
                    const uint64_t n = p.is_list() ? body.length(p, body_bytes, "a strand's vertex list") : 1;
                    for (uint64_t j = 0; j < n; ++j) {
                        const double v = body.value(p.type, "the strands");
                        if (int(k) == strand_list) {
                            add_point(v, "strand", i);
                        } else if (int(k) == strand_count) {
                            if (!(v >= 0 && v <= double(vertices - counted_vertices)) || v != std::floor(v))
                                scene_fail(path, "strand ", i, ": vertex count ", v, " is not a whole number that fits the ",
                                           vertices - counted_vertices, " vertices left");
                            for (uint64_t q = 0; q < uint64_t(v); ++q) add_point(double(counted_vertices + q), "strand", i);
                            counted_vertices += uint64_t(v);
                        }
                    }
                }
                end_strand();
            }
            if (strand_count >= 0 && counted_vertices != vertices)
                scene_fail(path, "the strands' vertex counts add up to ", counted_vertices, " but there are ", vertices,
                           " vertices");
        } else if (&e == edges && strand_list < 0 && strand_count < 0) {
            double previous_end = -1;
            for (uint64_t i = 0; i < e.count; ++i) {
                double a = -1, b = -1;
                for (size_t k = 0; k < e.properties.size(); ++k) {
                    const PlyProperty& p = e.properties[k];
                    const uint64_t n = p.is_list() ? body.length(p, body_bytes, "an edge list property") : 1;
                    for (uint64_t j = 0; j < n; ++j) {
                        const double v = body.value(p.type, "the edges");
                        if (int(k) == edge_a) a = v;
                        else if (int(k) == edge_b) b = v;
                    }
                }
                if (a != previous_end || file_strand.empty()) {
                    if (!file_strand.empty()) end_strand();
                    file_strand.push_back(uint32_t(i));
                    add_point(a, "edge", i);
                }
                add_point(b, "edge", i);
                previous_end = b;
            }
            if (!file_strand.empty()) end_strand();
        } else {
            for (uint64_t i = 0; i < e.count; ++i) body.skip_item(e, body_bytes);
            ++ignored_elements;
        }
    }
    if (ignored_elements > 0)
        scene.warnings.push_back(str_cat(path, ": ignored ", ignored_elements, " elements other than the vertices and strands"));
    if (s.strand_count() == 0) scene_fail(path, "the file holds no strands");

    if (p_size < 0) {
        float radius = opt.default_radius;
        if (!(radius > 0.0f)) {
            radius = radius_from_extent(s.points);
            scene.warnings.push_back(str_cat(path, ": the vertices have no radius, thickness or width: using ", radius,
                                             " (1/1000 of the hair's extent; set a default radius to override)"));
        }
        std::fill(s.radius.begin(), s.radius.end(), radius);
    }
    scene.materials.push_back(blond_hair_material());
    const char* unit = strand_list >= 0 || strand_count >= 0 ? "strand " : "strand starting at edge ";
    auto namer = [&file_strand, unit](size_t strand) { return str_cat(unit, file_strand[strand]); };
    add_hygiene_warnings(scene, path, sanitize_strands(s, path, namer));
    return scene;
}

}  // namespace ht
