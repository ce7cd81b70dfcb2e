#include "bench/ray_sources.h"

#include "render/shadow_lists.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>

#include <glm/glm.hpp>

namespace ht {

std::vector<HtLight> lights_the_rays_run_to(const std::vector<HtRay>& rays) {
    std::vector<HtLight> lights;
    std::map<std::array<uint32_t, 3>, size_t> directions;
    const auto key = [](const HtRay& r) {
        std::array<uint32_t, 3> k;
        std::memcpy(k.data(), &r.dx, sizeof k);
        return k;
    };
    for (const HtRay& r : rays) ++directions[key(r)];
    const auto shared = [&](size_t n) { return n >= 2 && n * 100 >= rays.size(); };
    std::vector<std::pair<size_t, std::array<uint32_t, 3>>> common;
    for (const auto& [k, n] : directions)
        if (shared(n)) common.push_back({n, k});
    std::sort(common.rbegin(), common.rend());
    for (const auto& [n, k] : common) {
        if (lights.size() == kMaxShadowGrids) break;
        HtLight l{};
        l.type = HT_LIGHT_DIRECTIONAL;
        float d[3];
        std::memcpy(d, k.data(), sizeof d);
        for (int i = 0; i < 3; ++i) l.direction[i] = -d[i];  // the shade stage's rays run against it
        lights.push_back(l);
    }
    // the rays along no shared direction that end somewhere
    std::vector<const HtRay*> others;
    for (const HtRay& r : rays)
        if (!shared(directions[key(r)]) && r.tmax < 1e30f) others.push_back(&r);
    if (others.empty() || lights.size() == kMaxShadowGrids) return lights;
    // the point nearest the lines of the first ray and of the first one across it
    const HtRay* a = others.front();
    const glm::dvec3 oa(a->ox, a->oy, a->oz), da(a->dx, a->dy, a->dz);
    const HtRay* b = nullptr;
    for (const HtRay* r : others)
        if (glm::length(glm::cross(da, glm::dvec3(r->dx, r->dy, r->dz))) > 1e-3) {
            b = r;
            break;
        }
    if (!b) return lights;
    const glm::dvec3 ob(b->ox, b->oy, b->oz), db(b->dx, b->dy, b->dz), w0 = oa - ob;
    const double A = glm::dot(da, da), B = glm::dot(da, db), C = glm::dot(db, db), D = glm::dot(da, w0), E = glm::dot(db, w0);
    const double denom = A * C - B * B, sa = (B * E - C * D) / denom, sb = (A * E - B * D) / denom;
    if (!(sa > 0 && sb > 0)) return lights;
    const glm::dvec3 light = 0.5 * (oa + sa * da + ob + sb * db);
    // a point light when more than half of these rays run to it
    size_t near = 0;
    for (const HtRay* r : others) {
        const glm::dvec3 to = light - glm::dvec3(r->ox, r->oy, r->oz), d(r->dx, r->dy, r->dz);
        near += glm::dot(to, d) > 0 && glm::length(glm::cross(to, d)) <= 1e-4 * std::max(1.0, glm::length(to));
    }
    if (near * 2 > others.size()) {
        HtLight l{};
        l.type = HT_LIGHT_POINT;
        for (int i = 0; i < 3; ++i) l.position[i] = float(light[i]);
        lights.push_back(l);
    }
    return lights;
}

FittedCamera camera_of_the_rays(const std::vector<HtRay>& rays) {
    FittedCamera fc;
    if (rays.size() < 64) return fc;
    glm::dvec3 sum(0.0);
    for (const HtRay& r : rays) {
        if (r.ox != rays[0].ox || r.oy != rays[0].oy || r.oz != rays[0].oz) return fc;
        sum += glm::normalize(glm::dvec3(r.dx, r.dy, r.dz));
    }
    const glm::dvec3 f = glm::normalize(sum);
    const glm::dvec3 other = std::fabs(f.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 right = glm::normalize(glm::cross(f, other)), up = glm::cross(right, f);
    double tx = 0, ty = 0;
    for (const HtRay& r : rays) {
        const glm::dvec3 d(r.dx, r.dy, r.dz);
        const double z = glm::dot(d, f);
        if (!(z > 0.45 * glm::length(d))) return fc;
        tx = std::max(tx, std::fabs(glm::dot(d, right) / z)), ty = std::max(ty, std::fabs(glm::dot(d, up) / z));
    }
    const uint32_t side = uint32_t(std::clamp(std::sqrt(double(rays.size())), 16.0, 4096.0));
    tx = std::max(tx, 1e-6) * (1 + 2.0 / side), ty = std::max(ty, 1e-6) * (1 + 2.0 / side);
    const float eye[3] = {rays[0].ox, rays[0].oy, rays[0].oz};
    for (int i = 0; i < 3; ++i) {
        fc.camera.eye[i] = eye[i];
        fc.camera.forward[i] = float(f[i]);
        fc.camera.right[i] = float(right[i] * tx);
        fc.camera.up[i] = float(up[i] * ty);
    }
    fc.camera.width = fc.camera.height = side;
    // each ray's pixel, as kernels/camera.h maps pixels to directions (y downwards), in the float
    // camera's own frame
    const glm::dvec3 cf(fc.camera.forward[0], fc.camera.forward[1], fc.camera.forward[2]);
    const glm::dvec3 cr(fc.camera.right[0], fc.camera.right[1], fc.camera.right[2]), cu(fc.camera.up[0], fc.camera.up[1], fc.camera.up[2]);
    const glm::dmat3 inv = glm::inverse(glm::dmat3(cf, cr, cu));
    fc.pixels.reserve(rays.size());
    for (const HtRay& r : rays) {
        const glm::dvec3 x = inv * glm::dvec3(r.dx, r.dy, r.dz);
        const double px = (x[1] / x[0] + 1) * 0.5 * side, py = (1 - x[2] / x[0]) * 0.5 * side;
        fc.pixels.push_back(uint32_t(std::clamp(std::floor(py), 0.0, side - 1.0)) * side +
                            uint32_t(std::clamp(std::floor(px), 0.0, side - 1.0)));
    }
    fc.ok = true;
    return fc;
}

}  // namespace ht
