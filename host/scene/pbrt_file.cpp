// pbrt-v4 scene files (.pbrt, gzipped .pbrt.gz): the hair, i.e. every `Shape "curve"`.
//
// Read: `Shape "curve"` with "point3 P" (or "point P"), "string basis" bezier (default) or
// bspline, "integer degree" 3 (default) or 2, "float width" (default 1) or "float width0" /
// "float width1" (pbrt's widths are diameters, interpolated along the whole shape), "string
// type" cylinder / flat / ribbon (all become round fibres: the fibre models need a cylinder);
// "integer splitdepth" and ribbon normals are ignored.  The current transformation applies
// (Identity, Translate, Scale, Rotate, Transform, ConcatTransform, AttributeBegin/End; WorldBegin
// resets it, as in pbrt).  `Include` and `Import` read another file (relative to the including
// file; gzipped when its name ends in .gz), at most 16 deep.  Every other directive (cameras,
// lights, materials, other shapes) is skipped with its parameters and counted in a warning: the
// automatic view and light rig and the default hair material apply.
//
// Flattening: each Bezier segment becomes k straight capsules between points of the curve at
// uniform parameter steps, with k the smallest count for which the chord error bound
// max|B''| / (8 k^2) is at most kTolerance (a tenth) of the segment's smaller radius, at most
// kMaxPieces per segment.  An exactly linear segment (hair2pbrt writes those) stays one capsule.
// Radii are interpolated linearly in the parameter.  One Shape is one strand.
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "scene/binary_file.h"
#include "scene/hygiene.h"
#include "scene/scene_error.h"

namespace ht {

namespace {

constexpr double kTolerance = 0.1;
constexpr int kMaxPieces = 64;
constexpr int kMaxIncludeDepth = 16;

using Mat4 = std::array<double, 16>;  // row-major; points are columns (pbrt's convention)
constexpr Mat4 kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Mat4 mul(const Mat4& a, const Mat4& b) {
    Mat4 r{};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 4; ++k) r[4 * i + j] += a[4 * i + k] * b[4 * k + j];
    return r;
}

struct P3 {
    double x, y, z;
};
P3 operator+(P3 a, P3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
P3 operator-(P3 a, P3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
P3 operator*(double s, P3 a) { return {s * a.x, s * a.y, s * a.z}; }
double norm(P3 a) { return std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z); }

P3 transform(const Mat4& m, P3 p) {
    const double x = m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3];
    const double y = m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7];
    const double z = m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11];
    const double w = m[12] * p.x + m[13] * p.y + m[14] * p.z + m[15];
    return w == 1.0 || w == 0.0 ? P3{x, y, z} : P3{x / w, y / w, z / w};
}

// Reads a whole file, gunzipping it when its name ends in .gz; refuses more than `limit` bytes.
std::string read_text(const std::string& path, uint64_t limit) {
    require_regular_file(path);
    const bool gz = path.size() > 3 && path.compare(path.size() - 3, 3, ".gz") == 0;
    std::string text;
    if (!gz) {
        std::ifstream in(path, std::ios::binary);
        text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    } else {
        gzFile f = gzopen(path.c_str(), "rb");
        if (!f) scene_fail(path, "cannot open");
        char buf[1 << 16];
        int n;
        while ((n = gzread(f, buf, sizeof buf)) > 0) {
            text.append(buf, static_cast<size_t>(n));
            if (text.size() > limit) break;
        }
        int err = 0;
        const char* msg = gzerror(f, &err);
        const std::string message = n < 0 && msg ? msg : "";
        gzclose(f);
        if (n < 0) scene_fail(path, "gzip error: ", message);
    }
    if (text.size() > limit)
        scene_fail(path, "the text is more than ", limit, " bytes (LoadOptions::max_bytes)");
    return text;
}

struct Token {
    enum Kind { Word, String, Number, Open, Close } kind;
    std::string text;
    double number = 0;
};

// Splits pbrt text into tokens one at a time (a whole file's tokens at once would take many times
// the memory of its text).
class Tokenizer {
public:
    Tokenizer(const std::string& file, const std::string& text) : file_(file), s_(text) {}

    // The next token, or false at the end of the text.
    bool next(Token& out) {
        const std::string& s = s_;
        while (i_ < s.size()) {
            const char c = s[i_];
            if (std::isspace(static_cast<unsigned char>(c))) {
                ++i_;
            } else if (c == '#') {
                while (i_ < s.size() && s[i_] != '\n') ++i_;
            } else if (c == '[' || c == ']') {
                out = {c == '[' ? Token::Open : Token::Close, std::string(1, c)};
                ++i_;
                return true;
            } else if (c == '"') {
                const size_t end = s.find('"', i_ + 1);
                if (end == std::string::npos) scene_fail(file_, "a string is not closed");
                out = {Token::String, s.substr(i_ + 1, end - i_ - 1)};
                i_ = end + 1;
                return true;
            } else {
                size_t end = i_;
                while (end < s.size() && !std::isspace(static_cast<unsigned char>(s[end])) && s[end] != '[' &&
                       s[end] != ']' && s[end] != '"' && s[end] != '#')
                    ++end;
                out = {Token::Word, s.substr(i_, end - i_)};
                char* stop = nullptr;
                out.number = std::strtod(out.text.c_str(), &stop);
                if (*stop == '\0') out.kind = Token::Number;
                i_ = end;
                return true;
            }
        }
        return false;
    }

private:
    const std::string& file_;
    const std::string& s_;
    size_t i_ = 0;
};

// A parameter list: "type name" followed by one value or a bracketed list.
struct Param {
    std::string type;
    std::vector<double> numbers;
    std::vector<std::string> strings;
};
using Params = std::map<std::string, Param>;

class PbrtReader {
public:
    PbrtReader(const std::string& top, const LoadOptions& opt) : top_(top), opt_(opt) {
        scene_.source = top;
        scene_.strands.first_point.push_back(0);
    }

    Scene read() {
        read_file(top_, 0);
        Strands& s = scene_.strands;
        if (s.strand_count() == 0) scene_fail(top_, "the scene holds no Shape \"curve\"");
        if (skipped_shapes_ > 0)
            scene_.warnings.push_back(str_cat(top_, ": skipped ", skipped_shapes_, " shapes other than \"curve\""));
        if (skipped_directives_ > 0)
            scene_.warnings.push_back(str_cat(top_, ": skipped ", skipped_directives_,
                                              " directives (camera, lights, materials, ...): the automatic view, "
                                              "light rig and hair material apply"));
        scene_.materials.push_back(blond_hair_material());
        auto namer = [this](size_t strand) { return shape_names_[strand]; };
        add_hygiene_warnings(scene_, top_, sanitize_strands(s, top_, namer));
        return std::move(scene_);
    }

private:
    void read_file(const std::string& path, int depth) {
        if (depth > kMaxIncludeDepth) scene_fail(path, "Include/Import nested more than ", kMaxIncludeDepth, " deep");
        // A file that includes itself (directly or not) would be read 2^depth times.
        std::error_code ec;
        const std::string key = std::filesystem::weakly_canonical(path, ec).string();
        if (std::find(reading_.begin(), reading_.end(), key) != reading_.end())
            scene_fail(path, "includes itself");
        reading_.push_back(key);
        const std::string text = read_text(path, opt_.max_bytes);
        Tokenizer tokens(path, text);
        Token t;
        bool more = tokens.next(t);
        while (more) {
            if (t.kind != Token::Word) scene_fail(path, "expected a directive, found '", t.text.substr(0, 40), "'");
            const std::string d = t.text;
            std::vector<Token> args;  // everything up to the next directive
            while ((more = tokens.next(t)) && t.kind != Token::Word) args.push_back(std::move(t));
            directive(path, depth, d, args);
        }
        reading_.pop_back();
    }

    std::vector<double> numbers(const std::string& path, const std::string& d, const std::vector<Token>& a,
                                size_t n) {
        std::vector<double> v;
        for (const Token& t : a)
            if (t.kind == Token::Number) v.push_back(t.number);
            else if (t.kind != Token::Open && t.kind != Token::Close)
                scene_fail(path, d, ": expected numbers, found '", t.text.substr(0, 40), "'");
        if (v.size() != n) scene_fail(path, d, " takes ", n, " numbers, found ", v.size());
        return v;
    }

    void directive(const std::string& path, int depth, const std::string& d, const std::vector<Token>& a) {
        if (d == "Include" || d == "Import") {
            if (a.size() != 1 || a[0].kind != Token::String) scene_fail(path, d, " needs one file name");
            std::filesystem::path next(a[0].text);
            if (next.is_relative()) next = std::filesystem::path(path).parent_path() / next;
            read_file(next.string(), depth + 1);
        } else if (d == "AttributeBegin" || d == "TransformBegin") {
            stack_.push_back(ctm_);
        } else if (d == "AttributeEnd" || d == "TransformEnd") {
            if (stack_.empty()) scene_fail(path, d, " without a matching begin");
            ctm_ = stack_.back();
            stack_.pop_back();
        } else if (d == "WorldBegin" || d == "Identity") {
            ctm_ = kIdentity;
        } else if (d == "Translate") {
            const auto v = numbers(path, d, a, 3);
            ctm_ = mul(ctm_, {1, 0, 0, v[0], 0, 1, 0, v[1], 0, 0, 1, v[2], 0, 0, 0, 1});
        } else if (d == "Scale") {
            const auto v = numbers(path, d, a, 3);
            ctm_ = mul(ctm_, {v[0], 0, 0, 0, 0, v[1], 0, 0, 0, 0, v[2], 0, 0, 0, 0, 1});
        } else if (d == "Rotate") {
            const auto v = numbers(path, d, a, 4);
            const double len = norm({v[1], v[2], v[3]});
            if (!(len > 0)) scene_fail(path, "Rotate about a zero axis");
            const double x = v[1] / len, y = v[2] / len, z = v[3] / len;
            const double th = v[0] * 3.14159265358979323846 / 180.0, c = std::cos(th), s = std::sin(th);
            ctm_ = mul(ctm_, {x * x + (1 - x * x) * c, x * y * (1 - c) - z * s, x * z * (1 - c) + y * s, 0,
                              x * y * (1 - c) + z * s, y * y + (1 - y * y) * c, y * z * (1 - c) - x * s, 0,
                              x * z * (1 - c) - y * s, y * z * (1 - c) + x * s, z * z + (1 - z * z) * c, 0, 0, 0, 0, 1});
        } else if (d == "Transform" || d == "ConcatTransform") {
            const auto v = numbers(path, d, a, 16);
            Mat4 m;  // pbrt lists the matrix column by column
            for (int r = 0; r < 4; ++r)
                for (int c = 0; c < 4; ++c) m[4 * r + c] = v[4 * c + r];
            ctm_ = d == "Transform" ? m : mul(ctm_, m);
        } else if (d == "Shape") {
            if (a.empty() || a[0].kind != Token::String) scene_fail(path, "Shape needs a type name");
            if (a[0].text != "curve") {
                ++skipped_shapes_;
                return;
            }
            curve(path, params(path, a));
        } else {
            ++skipped_directives_;
        }
    }

    Params params(const std::string& path, const std::vector<Token>& a) {
        Params out;
        size_t i = 1;
        while (i < a.size()) {
            if (a[i].kind != Token::String) scene_fail(path, "Shape \"curve\": expected a \"type name\" string");
            const std::string decl = a[i++].text;
            const size_t space = decl.find(' ');
            const size_t name_start = space == std::string::npos ? space : decl.find_first_not_of(' ', space);
            if (name_start == std::string::npos)
                scene_fail(path, "Shape \"curve\": parameter \"", decl, "\" is not \"type name\"");
            Param p;
            p.type = decl.substr(0, space);
            const std::string name = decl.substr(name_start);
            auto take = [&](const Token& t) {
                if (t.kind == Token::Number) p.numbers.push_back(t.number);
                else if (t.kind == Token::String) p.strings.push_back(t.text);
                else scene_fail(path, "Shape \"curve\": bad value '", t.text.substr(0, 40), "' of \"", decl, "\"");
            };
            if (i < a.size() && a[i].kind == Token::Open) {
                ++i;
                while (i < a.size() && a[i].kind != Token::Close) take(a[i++]);
                if (i == a.size()) scene_fail(path, "Shape \"curve\": \"", decl, "\" has no closing ]");
                ++i;
            } else if (i < a.size()) {
                take(a[i++]);
            }
            out[name] = std::move(p);
        }
        return out;
    }

    double scalar(const Params& p, const char* name, double fallback) {
        const auto it = p.find(name);
        return it == p.end() || it->second.numbers.empty() ? fallback : it->second.numbers[0];
    }
    std::string word(const Params& p, const char* name, const char* fallback) {
        const auto it = p.find(name);
        return it == p.end() || it->second.strings.empty() ? fallback : it->second.strings[0];
    }

    void curve(const std::string& path, const Params& p) {
        const size_t shape = shapes_++;
        auto it = p.find("P");
        if (it == p.end()) scene_fail(path, "curve ", shape, ": no \"point3 P\"");
        const std::vector<double>& raw = it->second.numbers;
        if (raw.size() % 3 != 0) scene_fail(path, "curve ", shape, ": P holds ", raw.size(), " numbers, not whole points");
        std::vector<P3> cp;
        for (size_t k = 0; k < raw.size(); k += 3) cp.push_back({raw[k], raw[k + 1], raw[k + 2]});
        const std::string basis = word(p, "basis", "bezier");
        const double degree_value = scalar(p, "degree", 3);
        if (degree_value != 2 && degree_value != 3)
            scene_fail(path, "curve ", shape, ": degree ", degree_value, " is not 2 or 3");
        const int degree = int(degree_value);
        if (basis != "bezier" && basis != "bspline")
            scene_fail(path, "curve ", shape, ": basis \"", basis, "\" is not bezier or bspline");
        // Bezier control points of each segment (degree + 1 each).
        std::vector<std::array<P3, 4>> segments;
        const size_t n = cp.size();
        if (basis == "bezier") {
            if (n < size_t(degree) + 1 || (n - 1) % degree != 0)
                scene_fail(path, "curve ", shape, ": a degree ", degree, " bezier curve needs ", degree, "k + 1 points, has ", n);
            for (size_t k = 0; k + degree < n; k += degree)
                segments.push_back({cp[k], cp[k + 1], cp[k + 2], degree == 3 ? cp[k + 3] : cp[k + 2]});
        } else {
            if (n < size_t(degree) + 1)
                scene_fail(path, "curve ", shape, ": a degree ", degree, " bspline needs at least ", degree + 1, " points, has ", n);
            for (size_t k = 0; k + degree < n; ++k) {
                const P3 a = cp[k], b = cp[k + 1], c = cp[k + 2];
                if (degree == 2) {
                    segments.push_back({0.5 * (a + b), b, 0.5 * (b + c), 0.5 * (b + c)});
                } else {
                    const P3 d = cp[k + 3];
                    segments.push_back({(1.0 / 6) * (a + 4.0 * b + c), (1.0 / 3) * (2.0 * b + c),
                                        (1.0 / 3) * (b + 2.0 * c), (1.0 / 6) * (b + 4.0 * c + d)});
                }
            }
        }
        const double width = scalar(p, "width", 1.0);
        const double w0 = scalar(p, "width0", width), w1 = scalar(p, "width1", width);
        Strands& s = scene_.strands;
        const size_t count = segments.size();
        for (size_t k = 0; k < count; ++k) {
            const std::array<P3, 4>& b = segments[k];
            const double r0 = 0.5 * (w0 + (w1 - w0) * double(k) / double(count));
            const double r1 = 0.5 * (w0 + (w1 - w0) * double(k + 1) / double(count));
            // max |B''| over the segment: for a cubic, 6 x the largest second difference.
            double bend;
            if (degree == 3) bend = 6 * std::max(norm(b[0] - 2.0 * b[1] + b[2]), norm(b[1] - 2.0 * b[2] + b[3]));
            else bend = 2 * norm(b[0] - 2.0 * b[1] + b[2]);
            const double tol = kTolerance * std::min(std::abs(r0), std::abs(r1));
            int pieces = 1;
            if (bend > 0 && tol > 0 && std::isfinite(bend))
                pieces = int(std::min<double>(kMaxPieces, std::ceil(std::sqrt(bend / (8 * tol)))));
            pieces = std::max(pieces, 1);
            for (int q = k == 0 ? 0 : 1; q <= pieces; ++q) {
                const double t = double(q) / pieces, u = 1 - t;
                P3 at;
                if (degree == 3) at = (u * u * u) * b[0] + (3 * u * u * t) * b[1] + (3 * u * t * t) * b[2] + (t * t * t) * b[3];
                else at = (u * u) * b[0] + (2 * u * t) * b[1] + (t * t) * b[2];
                const P3 w = transform(ctm_, at);
                if (s.points.size() + 1 > kMaxScenePoints ||
                    strands_bytes(s.strand_count() + 1, s.points.size() + 1) > opt_.max_bytes)
                    check_scene_size(path, str_cat("the curves up to curve ", shape, " need"), s.strand_count() + 1,
                                     s.points.size() + 1, opt_);
                s.points.push_back({float(w.x), float(w.y), float(w.z)});
                s.radius.push_back(float((r0 + (r1 - r0) * t) * scale_of(ctm_)));
            }
        }
        s.first_point.push_back(uint32_t(s.points.size()));
        s.material.push_back(0);
        shape_names_.push_back(path == top_ ? str_cat("curve ", shape) : str_cat(path, " curve ", shape));
    }

    // Widths scale with the transformation's mean linear scale (cube root of |det|).
    static double scale_of(const Mat4& m) {
        const double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
                           m[2] * (m[4] * m[9] - m[5] * m[8]);
        return std::cbrt(std::abs(det));
    }

    const std::string& top_;
    const LoadOptions& opt_;
    Scene scene_;
    Mat4 ctm_ = kIdentity;
    std::vector<Mat4> stack_;
    std::vector<std::string> shape_names_;
    std::vector<std::string> reading_;  // the Include chain being read, canonical paths
    size_t shapes_ = 0, skipped_shapes_ = 0, skipped_directives_ = 0;
};

}  // namespace

Scene load_pbrt_file(const std::string& path, const LoadOptions& opt) { return PbrtReader(path, opt).read(); }

}  // namespace ht
