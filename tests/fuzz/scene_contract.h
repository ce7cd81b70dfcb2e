// What every successfully loaded Scene must satisfy: the guarantees host/scene documents
// (scene.h, hygiene.cpp) and that the BVH, the renderer and the kernels rely on without
// re-checking.  Shared by the libFuzzer targets (tests/fuzz/) and the regression replay test
// (tests/unit/fuzz_regressions_test.cpp), so that "loads" always means "loads a usable scene": a
// loader that returns garbage instead of throwing SceneError is as much a bug as a crash.
#pragma once

#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

#include "scene/hygiene.h"
#include "scene/scene.h"

namespace ht_fuzz {

inline bool finite3(const ht::Vec3f& v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

// Loader options used for fuzzing: defaults, except that the strand-memory budget is lowered from
// 16 GiB to 64 MiB.  The loaders promise to check this budget before allocating, so with
// -malloc_limit_mb=2048 any allocation libFuzzer flags is a broken promise rather than a
// legitimately big scene; 64 MiB also keeps the largest legal builtin (4M points) under the
// per-input timeout.
inline ht::LoadOptions fuzz_load_options() {
    ht::LoadOptions opt;
    opt.max_bytes = uint64_t(64) << 20;
    return opt;
}

// Empty when `s` honours the contract, otherwise the first violation found: one line starting
// with its category, "strands: ", "camera: " or "light: " (the fuzz harness can be told to
// tolerate a category that is already reported; see HT_FUZZ_IGNORE in fuzz_common.h).
inline std::string scene_contract_violation(const ht::Scene& s) {
    std::ostringstream why;
    const ht::Strands& st = s.strands;
    const size_t strands = st.strand_count();
    if (strands == 0) return "strands: the scene has no strands (load_scene must refuse it)";
    if (st.first_point.front() != 0) return "strands: first_point[0] != 0";
    if (st.first_point.back() != st.points.size())
        return "strands: first_point.back() != points.size()";
    if (st.radius.size() != st.points.size()) return "strands: radius.size() != points.size()";
    if (st.material.size() != strands) return "strands: material.size() != strand_count()";
    if (s.materials.empty()) return "strands: no materials";
    if (st.points.size() > ht::kMaxScenePoints) return "strands: more than kMaxScenePoints points";
    for (size_t k = 0; k < strands; ++k) {
        const size_t b = st.first_point[k], e = st.first_point[k + 1];
        if (e < b + 2) {
            why << "strands: strand " << k << " has " << (e >= b ? e - b : 0)
                << " points (hygiene keeps >= 2)";
            return why.str();
        }
        if (st.material[k] >= s.materials.size()) {
            why << "strands: strand " << k << " refers to material " << st.material[k] << " of "
                << s.materials.size();
            return why.str();
        }
        for (size_t i = b; i < e; ++i) {
            if (!finite3(st.points[i])) {
                why << "strands: strand " << k << " point " << i - b << " is not finite";
                return why.str();
            }
            if (!std::isfinite(st.radius[i]) || !(st.radius[i] > 0.0f)) {
                why << "strands: strand " << k << " point " << i - b << " radius " << st.radius[i]
                    << " is not positive finite";
                return why.str();
            }
            if (i > b && ht::is_zero_length_segment(st.points[i - 1], st.points[i])) {
                why << "strands: strand " << k << " keeps a zero-length segment at point " << i - b;
                return why.str();
            }
        }
    }
    // The camera and lights feed straight into ray generation and light sampling: a non-finite
    // value there turns the whole image into NaN, so a loader must refuse rather than pass it on.
    if (s.has_camera) {
        const ht::Camera& c = s.camera;
        if (!finite3(c.eye) || !finite3(c.target) || !finite3(c.up)) {
            why << "camera: eye (" << c.eye[0] << ", " << c.eye[1] << ", " << c.eye[2]
                << "), target or up is not finite";
            return why.str();
        }
        if (!(c.yfov_deg > 0.0f && c.yfov_deg < 180.0f)) {
            why << "camera: yfov " << c.yfov_deg << " deg is not in (0, 180)";
            return why.str();
        }
        if (c.has_aspect && !(std::isfinite(c.aspect) && c.aspect > 0.0f))
            return "camera: aspect is not positive finite";
    }
    // Textures: the shade kernel indexes texels by these sizes and coordinates without checks.
    for (size_t i = 0; i < s.textures.size(); ++i) {
        const ht::Texture& t = s.textures[i];
        if (t.width == 0 || t.height == 0 || t.texels.size() != uint64_t(t.width) * t.height) {
            why << "textures: texture " << i << " is " << t.width << " x " << t.height << " with "
                << t.texels.size() << " texels";
            return why.str();
        }
    }
    for (size_t i = 0; i < s.surface_materials.size(); ++i)
        if (s.surface_materials[i].texture >= 0 && size_t(s.surface_materials[i].texture) >= s.textures.size()) {
            why << "textures: surface material " << i << " refers to texture " << s.surface_materials[i].texture
                << " of " << s.textures.size();
            return why.str();
        }
    for (size_t i = 0; i < s.meshes.size(); ++i) {
        const ht::Mesh& m = s.meshes[i];
        if (!m.uvs.empty() && m.uvs.size() != m.positions.size()) {
            why << "textures: mesh " << i << " has " << m.uvs.size() << " uvs for " << m.positions.size()
                << " positions";
            return why.str();
        }
        for (const auto& uv : m.uvs)
            if (!std::isfinite(uv[0]) || !std::isfinite(uv[1])) {
                why << "textures: mesh " << i << " keeps a non-finite texture coordinate";
                return why.str();
            }
    }
    for (size_t i = 0; i < s.lights.size(); ++i) {
        const ht::Light& l = s.lights[i];
        if (!finite3(l.position) || !finite3(l.direction) || !finite3(l.color) ||
            !std::isfinite(l.intensity) || l.intensity < 0.0f || !std::isfinite(l.radius)) {
            why << "light: light " << i << " has a non-finite position, direction, colour or "
                << "intensity (colour " << l.color[0] << ", " << l.color[1] << ", " << l.color[2]
                << "; intensity " << l.intensity << ")";
            return why.str();
        }
    }
    return {};
}

}  // namespace ht_fuzz
