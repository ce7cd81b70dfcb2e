#include "render/render_identity.h"

#include "core/hash.h"
#include "render/aovs.h"

#include <algorithm>
#include <stdexcept>
#include <type_traits>

namespace ht {

namespace {

const char* const kPartNames[RenderIdentity::kPartCount] = {"geometry", "materials", "lights",
                                                            "camera",   "settings",  "aovs"};
// What each part covers, in the words of the options and scene contents a user changes.
const char* const kPartMessages[RenderIdentity::kPartCount] = {
    "different geometry (strand points, radii or materials per strand; meshes)",
    "different materials (--model, --sigma-a, material extras of the scene; surface colours and textures)",
    "different lights (the scene's lights or the default key light; --background, --environment, "
    "--environment-intensity, the environment map's contents)",
    "a different camera (the scene's camera or the default framing, image aspect)",
    "different settings (--width, --height, --seed, --max-depth, --chunk, --indirect, --fiber-field, "
    "--features, --clamp-indirect, --regularize, --spawn-offset, --sampler, --first-hit-splits, "
    "--first-hit-light-samples, --light-threshold, --light-guiding, --target-error, --min-spp; or a "
    "hairtrace whose estimator differs wrote it)",
    "different AOVs (--aovs: which output values are recorded, if any)",
};

// Hashes values one after another: plain values by their bytes, vectors by their elements'.
struct Digest {
    uint64_t h = kFnv1aSeed;
    template <typename T>
    Digest& add(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>, "hash only plain bytes");
        h = fnv1a(&v, sizeof v, h);
        return *this;
    }
    template <typename T>
    Digest& add(const std::vector<T>& v) {
        add(uint64_t(v.size()));  // so that [a][bc] and [ab][c] differ
        h = fnv1a(v, h);
        return *this;
    }
    Digest& add(const std::string& s) {
        add(uint64_t(s.size()));
        h = fnv1a(s, h);
        return *this;
    }
    // Records of several fields: the count, then `fields(digest, record)` for each.
    template <typename T, typename Fields>
    Digest& add_each(const std::vector<T>& records, Fields fields) {
        add(uint64_t(records.size()));
        for (const T& r : records) fields(*this, r);
        return *this;
    }
};

uint64_t geometry_digest(const Scene& scene) {
    return Digest()
        .add(strands_content_hash(scene.strands))
        .add_each(scene.meshes, [](Digest& d, const Mesh& m) {
            d.add(m.positions).add(m.indices).add(m.normals).add(m.uvs).add(m.material);
        })
        .h;
}

// Hair materials as the kernels get them (overrides applied, melanin and colour converted).
uint64_t materials_digest(const Scene& scene, const PreparedScene& p) {
    return Digest()
        .add(p.materials)
        .add_each(scene.surface_materials,
                  [](Digest& d, const SurfaceMaterialDesc& m) { d.add(m.albedo).add(m.texture); })
        .add_each(scene.textures, [](Digest& d, const Texture& t) {
            d.add(t.width).add(t.height).add(t.wrap_s).add(t.wrap_t).add(t.texels);
        })
        .h;
}

// The environment as its tables hold it: the map's texels as loaded (not its file name), the
// intensity and colour in the header.
uint64_t lights_digest(const PreparedScene& p) {
    return Digest().add(p.lights).add(p.environment.header).add(p.environment.texels).h;
}

uint64_t camera_digest(const PreparedScene& p) { return Digest().add(p.camera).h; }

// The kernel build options are left out: they follow from the scene and these settings (and
// from the device's geometry paging, which never changes a bit).
// The estimator's revision: the same settings give other samples once the kernels' rules change,
// so a checkpoint or a render-farm part written by a build with other rules must not be merged
// with this one's samples.  Builds before revision 1 digested no revision.
//   1: roulette from the rays of bounce 4 (was 3), and --light-guiding (kernels/stages/shade.cl).
//   2: guided continuations of chiang fibres weigh each lobe against the guide on its own
//      (kernels/integrator/light_guide.h).
constexpr uint32_t kEstimatorRevision = 2;

uint64_t settings_digest(const RenderSettings& s, int chunk) {
    Digest d;
    d.add(kEstimatorRevision);
    d.add(s.width).add(s.height).add(s.seed).add(s.max_depth).add(chunk);
    d.add(s.indirect).add(s.fiber_field).add(s.features).add(s.clamp_indirect).add(s.regularize_deg);
    d.add(s.spawn_offset).add(s.sampler);
    // only when splitting, so that checkpoints and parts of renders from before keep their identity
    if (s.first_hit_splits != 1 || s.first_hit_light_samples != 1)
        d.add(s.first_hit_splits).add(s.first_hit_light_samples);
    // only when adaptive: which pixels get which samples depends on both
    if (s.target_error > 0) d.add(s.target_error).add(s.adaptive_min_spp);
    if (s.light_threshold > 0) d.add(s.light_threshold);
    if (s.light_guiding != 0) d.add(s.light_guiding).add(std::string("light_guiding"));
    if (s.light_pick != RenderSettings::LightPick::Uniform) d.add(s.light_pick);
    if (s.light_vertices > 0) d.add(s.light_vertices).add(std::string("light_vertices"));
    return d.h;
}

// Which of aov_names() are asked for: the same set in another order is the same render.
uint64_t aovs_digest(const std::vector<std::string>& aovs) {
    Digest d;
    for (const std::string& name : aov_names())
        d.add(uint8_t(std::find(aovs.begin(), aovs.end(), name) != aovs.end()));
    return d.h;
}

}  // namespace

uint64_t RenderIdentity::key() const { return fnv1a(digests.data(), sizeof digests); }

std::string RenderIdentity::differences(const RenderIdentity& other) const {
    std::string out;
    for (int p = 0; p < kPartCount; ++p)
        if (digests[p] != other.digests[p]) out += (out.empty() ? "" : " and ") + std::string(kPartMessages[p]);
    return out;
}

std::string RenderIdentity::to_text() const {
    std::string out;
    for (int p = 0; p < kPartCount; ++p) out += (p ? "," : "") + std::string(kPartNames[p]) + "=" + hex64(digests[p]);
    return out;
}

RenderIdentity RenderIdentity::from_text(const std::string& text) {
    RenderIdentity id;
    size_t pos = 0;
    for (int p = 0; p < kPartCount; ++p) {
        const std::string name = std::string(p ? "," : "") + kPartNames[p] + "=";
        if (text.compare(pos, name.size(), name) != 0 || pos + name.size() + 16 > text.size())
            throw std::invalid_argument("render identity '" + text + "' lacks " + kPartNames[p]);
        const std::string digit = text.substr(pos + name.size(), 16);
        if (digit.find_first_not_of("0123456789abcdef") != std::string::npos)
            throw std::invalid_argument("render identity '" + text + "' has a malformed " + kPartNames[p]);
        id.digests[p] = std::stoull(digit, nullptr, 16);
        pos += name.size() + 16;
    }
    if (pos != text.size()) throw std::invalid_argument("render identity '" + text + "' has trailing text");
    return id;
}

RenderIdentity render_identity(const Scene& scene, const PreparedScene& prepared, int chunk,
                               const std::vector<std::string>& aovs) {
    RenderIdentity id;
    id.digests[RenderIdentity::Geometry] = geometry_digest(scene);
    id.digests[RenderIdentity::Materials] = materials_digest(scene, prepared);
    id.digests[RenderIdentity::Lights] = lights_digest(prepared);
    id.digests[RenderIdentity::Camera] = camera_digest(prepared);
    id.digests[RenderIdentity::Settings] = settings_digest(prepared.settings, chunk);
    id.digests[RenderIdentity::Aovs] = aovs_digest(aovs);
    return id;
}

RenderIdentity render_identity(const Scene& scene, const RenderSettings& settings, int chunk,
                               const std::vector<std::string>& aovs) {
    return render_identity(scene, prepare_scene(scene, settings), chunk, aovs);
}

}  // namespace ht
