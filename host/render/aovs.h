// The output values of render --aovs as named image channels (the per-path records are laid out
// in kernels/aovs.h).  Channel names follow OpenEXR's layer.channel convention: A, Z,
// tangent.X/Y/Z, albedo.R/G/B, direct.R/G/B, indirect.R/G/B, R.R/G/B, TT.*, TRT.*, residual.*.
#pragma once

#include "core/film.h"
#include "io/image_io.h"

#include <string>
#include <vector>

namespace ht {

// The --aovs names a user may give, in the order their channels are written.
const std::vector<std::string>& aov_names();

// The AOV sums per pixel in the films of a render with these --aovs names: HT_AOV_OUT (all of
// them, whichever names: the kernels record every value), or 0 without --aovs.
int aov_sums_per_pixel(const std::vector<std::string>& names);

// The names of the HT_AOV_OUT per-pixel sums of Film::aov, in record order ("A", "Z",
// "tangent.X", ...): how checkpoints and partial images label the raw sums they keep.
const std::vector<std::string>& aov_sum_names();

// The channels of `names` (each one of aov_names(), in any order; written in aov_names() order)
// from a film rendered with --aovs: means over the pixel's samples, except Z and tangent, which
// are means over the samples whose camera ray met geometry (0 where none did).  No names, no
// channels; otherwise throws std::invalid_argument for a film without AOVs or an unknown name.
std::vector<ImageChannel> aov_channels(const Film& film, const std::vector<std::string>& names);

}  // namespace ht
