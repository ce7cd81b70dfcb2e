// Partial renders (render-farm parts): an OpenEXR file that holds the raw float32 sums of a
// sample range, segment by segment, so that `hairtrace merge` can fold the parts of a render in
// the canonical chunk order (split/accumulation.h) and reproduce the single render bit for bit.
//
// Channels: R, G, B = mean radiance of the part (a preview any EXR viewer shows) and, with
// --aovs, the AOV channels of the part (render/aovs.h: A, Z, direct.R, ...; a preview too), then
// for each segment i the raw sums seg<i>.R, seg<i>.G, seg<i>.B, the per-pixel sample count
// seg<i>.N and, with --aovs, the HT_AOV_OUT raw AOV sums seg<i>.aov.A, seg<i>.aov.Z,
// seg<i>.aov.tangent.X, ... (aov_sum_names(), all of them whichever AOVs were asked for).
// Metadata: hairtrace:partial = 2 (the format: 1 had neither AOV sums nor the AOV part of the
// render identity), hairtrace:sample_first / hairtrace:sample_count (the samples held),
// hairtrace:spp_target, hairtrace:chunk, hairtrace:seed, hairtrace:max_depth,
// hairtrace:render_identity (RenderIdentity::to_text), hairtrace:render_key (its key(), 16 hex
// digits, for people), hairtrace:segments ("first+count,..." in channel order) and
// hairtrace:aovs (the --aovs names, comma-separated; empty without).
#pragma once

#include "render/render_identity.h"
#include "split/accumulation.h"
#include "io/image_io.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ht {

struct PartialImage {
    int width = 0, height = 0;
    int spp_target = 0, chunk = 0, max_depth = 0;
    uint32_t seed = 0;
    RenderIdentity identity;
    std::string scene;
    std::vector<std::string> aovs;      // --aovs names: the segments' films carry AOV sums when not empty
    std::string command_line;  // read back: the hairtrace:command_line the render wrote ("" if none)
    std::vector<FilmSegment> segments;  // sorted, disjoint
};

// Writes atomically (temporary file + rename).  Throws ImageError.
void write_partial_exr(const std::string& path, const PartialImage& part, const ImageMetadata& extra);

// Throws SceneError (exit 2) when the file is not a hairtrace partial or is inconsistent.
PartialImage read_partial_exr(const std::string& path);

}  // namespace ht
