#include "render/pixel_footprint.h"

#include <algorithm>

namespace ht {

PixelFootprint pixel_footprint(const ProjectedPrimitives& projected) {
    const size_t w = size_t(projected.width), h = size_t(projected.height);
    PixelFootprint f;
    if (!projected.bounded) {
        f.seen.resize(w * h);
        for (size_t i = 0; i < w * h; ++i) f.seen[i] = uint32_t(i);
        return f;
    }
    std::vector<uint8_t> seen(w * h, 0);
    int r[4];
    for (const PrimitiveImage& im : projected.images)
        if (im.pixel_rect(kFootprintMarginPixels, int(w), int(h), r))
            for (int y = r[2]; y <= r[3]; ++y)
                std::fill(seen.begin() + size_t(y) * w + size_t(r[0]), seen.begin() + size_t(y) * w + size_t(r[1]) + 1, 1);
    for (size_t i = 0; i < seen.size(); ++i) (seen[i] ? f.seen : f.empty).push_back(uint32_t(i));
    return f;
}

PixelFootprint pixel_footprint(const PixelCandidates& lists) {
    PixelFootprint f;
    for (size_t i = 0; i < lists.count.size(); ++i) (lists.count[i] != 0 ? f.seen : f.empty).push_back(uint32_t(i));
    return f;
}

PixelFootprint pixel_footprint(const HtCamera& camera, const SceneGeometry& geometry) {
    return pixel_footprint(project_primitives(camera, geometry));
}

}  // namespace ht
