#include "render/scene_upload.h"

#include "core/constants.h"
#include "fiber/material.h"

#include <cmath>


namespace ht {
namespace {

void normalize3(double v[3]) {
    double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0) for (int i = 0; i < 3; ++i) v[i] /= l;
}
void cross3(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}
}  // namespace

HtCamera make_kernel_camera(const Camera& cam, int width, int height) {
    HtCamera c{};
    double f[3] = {cam.target[0] - cam.eye[0], cam.target[1] - cam.eye[1], cam.target[2] - cam.eye[2]};
    normalize3(f);
    double up[3] = {cam.up[0], cam.up[1], cam.up[2]};
    double r[3];
    cross3(f, up, r);
    if (r[0] * r[0] + r[1] * r[1] + r[2] * r[2] < 1e-12) {  // up parallel to the view direction
        double alt[3] = {1, 0, 0};
        if (std::fabs(f[0]) > 0.9) alt[0] = 0, alt[2] = 1;
        cross3(f, alt, r);
    }
    normalize3(r);
    double u[3];
    cross3(r, f, u);
    double th = std::tan(0.5 * cam.yfov_deg * kRadiansPerDegree);
    double aspect = double(width) / double(height);
    for (int i = 0; i < 3; ++i) {
        c.eye[i] = cam.eye[i];
        c.forward[i] = float(f[i]);
        c.right[i] = float(r[i] * th * aspect);
        c.up[i] = float(u[i] * th);
    }
    c.width = uint32_t(width);
    c.height = uint32_t(height);
    return c;
}

std::vector<HtLight> make_kernel_lights(const std::vector<Light>& lights) {
    std::vector<HtLight> out;
    for (const Light& l : lights) {
        HtLight k{};
        switch (l.type) {
        case LightType::Point: k.type = HT_LIGHT_POINT; break;
        case LightType::Spot: k.type = HT_LIGHT_SPOT; break;
        case LightType::Directional: k.type = HT_LIGHT_DIRECTIONAL; break;
        case LightType::Sphere: k.type = HT_LIGHT_SPHERE; break;
        }
        double d[3] = {l.direction[0], l.direction[1], l.direction[2]};
        normalize3(d);
        for (int i = 0; i < 3; ++i) {
            k.position[i] = l.position[i];
            k.direction[i] = float(d[i]);
            k.radiance[i] = l.color[i] * l.intensity;
        }
        k.position[3] = l.radius;
        k.cos_outer = float(std::cos(l.outer_cone_deg * kRadiansPerDegree));
        k.cos_inner = float(std::cos(std::min(l.inner_cone_deg, l.outer_cone_deg) * kRadiansPerDegree));
        out.push_back(k);
    }
    return out;
}

std::vector<HtMaterial> make_kernel_materials(const std::vector<HairMaterialDesc>& materials) {
    std::vector<HtMaterial> out;
    for (const auto& m : materials) out.push_back(make_kernel_material(m));
    if (out.empty()) out.push_back(make_kernel_material(HairMaterialDesc{}));
    return out;
}

std::vector<HtTexture> make_kernel_textures(const std::vector<Texture>& textures) {
    std::vector<HtTexture> out;
    uint64_t offset = HT_SRGB_TABLE_SIZE;
    auto wrap = [](TextureWrap w) {
        switch (w) {
        case TextureWrap::ClampToEdge: return HT_WRAP_CLAMP;
        case TextureWrap::MirroredRepeat: return HT_WRAP_MIRROR;
        case TextureWrap::Repeat: break;
        }
        return HT_WRAP_REPEAT;
    };
    for (const Texture& t : textures) {
        HtTexture h{};
        h.offset = uint32_t(offset);
        h.width = t.width;
        h.height = t.height;
        h.wrap_s = wrap(t.wrap_s);
        h.wrap_t = wrap(t.wrap_t);
        out.push_back(h);
        offset += t.texels.size();
    }
    return out;
}

uint64_t texel_buffer_size(const std::vector<Texture>& textures) {
    uint64_t n = HT_SRGB_TABLE_SIZE;
    for (const Texture& t : textures) n += t.texels.size();
    return n;
}

}  // namespace ht
