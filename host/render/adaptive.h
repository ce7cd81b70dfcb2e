// render --target-error: where the next chunk of samples goes, decided from the film alone.
//
// The estimate.  Every film of an adaptive render carries the sums of each pixel's even-numbered
// samples beside the sums of all of them (core/film.h), so a pixel with n >= 2 samples has two
// independent half estimates A (even samples) and B (odd samples) of its mean I.  Their
// difference has the standard deviation 2 sigma / sqrt(n) when the samples have sigma, so half of
// it estimates the standard error of I, and relative to the pixel's brightness
//
//     e_p = |Y(A) - Y(B)| / (2 (Y(I) + eps)),     eps = 0.1 x the image's mean Y(I)
//
// with Y the Rec. 709 luminance.  eps keeps nearly black pixels (a stray hair in the background)
// from asking for samples that no one would see; pixels with fewer than 2 samples count as 0.
// One pixel's e_p is a single draw of a half-normal variable, so the decision is made per tile
// of kTile x kTile pixels from the root mean square of its pixels' e_p, an estimate of the tile's
// RMS relative standard error.  The image's error is the largest tile error (what the target
// bounds) and the RMS over all tiles.
//
// The decision.  After the first `min_spp` samples (every pixel), chunk j (samples
// [jK, (j+1)K), split/accumulation.h) renders exactly the tiles whose pixels hold all jK samples
// of the chunks before it and whose tile error in that film exceeds the target.  A tile left out
// once has fewer samples than jK from then on and is never rendered again, so every pixel's
// samples are a prefix 0..n_p-1 of its own sequence, and the image equals, pixel for pixel, the
// non-adaptive image rendered with n_p samples.  The film after whole chunks is the same bits for
// any thread count, device split or checkpoint, so is every decision.
#pragma once

#include "core/film.h"

#include <cstdint>
#include <vector>

namespace ht {

constexpr int kAdaptiveTile = 8;        // tile side in pixels
constexpr float kAdaptiveEpsShare = 0.1f;  // eps as a share of the image's mean luminance

struct AdaptiveState {
    // The pixels of the tiles to render next (ascending y * width + x); empty: none is left.
    std::vector<uint32_t> pixels;
    int tiles = 0, active_tiles = 0;
    int tiles_above = 0;  // tiles whose error exceeds the target, whatever their samples
    double max_error = 0, rms_error = 0;  // over every tile of the film
    int min_spp = 0, max_spp = 0;
    double mean_spp = 0;
};

// e_p of pixel i in `film` (0 without the even half or with fewer than 2 samples).
float pixel_error(const Film& film, size_t i, float eps);
// eps of the formula above for this film.
float error_floor(const Film& film);

// The state of `film` (the fold of every complete chunk before sample `samples`): the tiles
// that hold all `samples` samples and whose error exceeds `target` go on.
AdaptiveState assess_film(const Film& film, int samples, float target);

}  // namespace ht
