#include "render/aovs.h"

#include "kernels/aovs.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ht {

namespace {

struct AovLayout {
    const char* name;
    int first;                          // offset in the per-pixel record (kernels/aovs.h)
    std::vector<const char*> channels;  // one name per component
    bool per_hit;                       // a mean over the samples that met geometry
};

const std::vector<AovLayout>& layouts() {
    static const std::vector<AovLayout> l = {
        {"alpha", HT_AOV_ALPHA, {"A"}, false},
        {"depth", HT_AOV_DEPTH, {"Z"}, true},
        {"tangent", HT_AOV_TANGENT, {"tangent.X", "tangent.Y", "tangent.Z"}, true},
        {"albedo", HT_AOV_ALBEDO, {"albedo.R", "albedo.G", "albedo.B"}, false},
        {"direct", HT_AOV_DIRECT, {"direct.R", "direct.G", "direct.B"}, false},
        {"indirect", HT_AOV_INDIRECT, {"indirect.R", "indirect.G", "indirect.B"}, false},
        {"R", HT_AOV_LOBES + 0, {"R.R", "R.G", "R.B"}, false},
        {"TT", HT_AOV_LOBES + 3, {"TT.R", "TT.G", "TT.B"}, false},
        {"TRT", HT_AOV_LOBES + 6, {"TRT.R", "TRT.G", "TRT.B"}, false},
        {"residual", HT_AOV_LOBES + 9, {"residual.R", "residual.G", "residual.B"}, false},
    };
    return l;
}

}  // namespace

const std::vector<std::string>& aov_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const AovLayout& l : layouts()) n.push_back(l.name);
        return n;
    }();
    return names;
}

int aov_sums_per_pixel(const std::vector<std::string>& names) { return names.empty() ? 0 : HT_AOV_OUT; }

const std::vector<std::string>& aov_sum_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n(HT_AOV_OUT);
        for (const AovLayout& l : layouts())
            for (size_t c = 0; c < l.channels.size(); ++c) n[l.first + c] = l.channels[c];
        return n;
    }();
    return names;
}

std::vector<ImageChannel> aov_channels(const Film& film, const std::vector<std::string>& names) {
    if (names.empty()) return {};
    const size_t pixels = size_t(film.width) * size_t(film.height);
    if (film.aov.size() != pixels * HT_AOV_OUT) throw std::invalid_argument("the film was rendered without --aovs");
    for (const std::string& n : names)
        if (std::find(aov_names().begin(), aov_names().end(), n) == aov_names().end())
            throw std::invalid_argument("unknown AOV '" + n + "'");
    std::vector<ImageChannel> out;
    for (const AovLayout& l : layouts()) {
        if (std::find(names.begin(), names.end(), l.name) == names.end()) continue;
        for (size_t c = 0; c < l.channels.size(); ++c) {
            ImageChannel ch{l.channels[c], std::vector<float>(pixels, 0.0f)};
            for (size_t i = 0; i < pixels; ++i) {
                const float* rec = &film.aov[i * HT_AOV_OUT];
                const float n = l.per_hit ? rec[HT_AOV_ALPHA] : film.rgba[4 * i + 3];
                const float v = n > 0 ? rec[l.first + c] / n : 0.0f;
                ch.values[i] = std::isfinite(v) ? v : 0.0f;
            }
            out.push_back(std::move(ch));
        }
    }
    return out;
}

}  // namespace ht
