// --first-hit-splits auto: the number of continuations N per camera sample, chosen per scene from
// a short pilot render (docs/ESTIMATOR.md "First-hit splits, auto").
//
// One camera sample with N continuations estimates the pixel as Y = F + (1/N) sum_j C_j, where F
// is what its first vertex gives (its next-event estimates) and the C_j are independent given
// that vertex.  A pixel's squared error after S samples is about (V_fixed + V_split / N) / S, with
// V_split = E[Var(C | first vertex)], at a cost of S (c0 + N c1) (c0: the camera ray, its hit and
// first vertex; c1: one continuation).  The work to a given error, (c0 + N c1)(V_fixed + V_split /
// N), is least near N* = sqrt((c0 / c1)(V_split / V_fixed)).
//
// The pilot (kernels/stages/split_pilot.cl) measures both variances per sample: V_split within
// each camera sample, V_fixed as the sample's variance less V_split / N.  Per sample is not what
// an S-sample pixel shows, though: the Owen-scrambled Sobol' sampler stratifies the camera
// sample's few dimensions (pixel position, light sample), so what they add to an S-sample mean
// falls faster than their variance / S.  The pilot measures that gain on the first vertex's own
// part F, whose error it takes from two independent scramblings of the sampler (the squared
// difference of their means), and divides V_fixed by it: the stratification.  Without it N came
// out too small on every scene measured (docs/PERFORMANCE.md section 8).  The first vertex's part
// is used because it has no hair-to-hair paths in it: the rare bright ones make the error of the
// whole sample too noisy to take a small V_fixed from.
//
// The costs come from the pilot's ray counts, never from its timings, so the choice is a pure
// function of the scene and the options: checkpoints, --sample-range parts and MPI ranks all make
// the same one.
#pragma once

#include "kernels/types.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ht {

struct RenderStats;

// The pilot: kPilotSamples samples with kPilotSplits continuations, twice (two seeds of its own,
// so that its noise is not the render's), over the pixels pilot_pixels names.
constexpr int kPilotSplits = int(HT_PILOT_SPLITS);
constexpr int kPilotSamples = 8;
// At most a sixteenth of the image's pixels (a pixel in kPilotStride in each direction), and no
// more than about kPilotPixels of them: the pilot then costs at most one sample of the image with
// 2 continuations, and a quarter of one from 256^2 up.  Why 1024 and not more: the pilot's time
// is render time (pbrt's lock reaches pbrt's 64-spp error in ~8 samples), and with 4096 pixels
// it was 8 % of that time, while over eight seeds 1024 pixels chose from the same range of N on
// every scene measured (docs/PERFORMANCE.md section 8, "A smaller pilot").  Fewer samples per
// pixel instead would not do: the stratification the pilot measures grows with the sample count,
// and at 4 samples it came out too small (N too low on straight.hair blond).
constexpr int kPilotStride = 4;
constexpr int kPilotPixels = 1024;
// The stratification is taken as at least 1 and at most this (a safeguard against a first
// vertex that barely varies; over eight seeds the scenes measured show 0.7-6.9).
constexpr double kMaxStratification = 16;
// What auto chooses from: 2, which paid on every scene measured (with the Sobol' sampler the two
// continuations of a camera sample are stratified against each other, a gain the model above
// leaves out: docs/PERFORMANCE.md section 8), to 8, beyond which the work at N* and at 8 differ by
// a few per cent on the scenes measured.
constexpr int kMinAutoSplits = 2;
constexpr int kMaxAutoSplits = 8;

// Every pilot_stride-th pixel of every pilot_stride-th row (at least one pixel), spread over all
// of the image.  Ascending, as Renderer::set_pixels wants.
int pilot_stride(int width, int height);
std::vector<uint32_t> pilot_pixels(int width, int height);

// The seed of the pilot's half 0 or 1: never one a render draws with (--seed is below 2^31).
uint32_t pilot_seed(uint32_t seed, int half);

// The pilot's variances per camera sample, averaged over its pixels, summed over the channels.
struct SplitVariance {
    double total = 0;           // the sample's variance, with kPilotSplits continuations
    double split = 0;           // V_split
    double stratification = 1;  // the first vertex's variance / (S x the squared error of its S-sample mean)
    // V_fixed: (total - split / kPilotSplits, at least a thousandth of total) / stratification
    double fixed() const;
};

// From the pilot's moments (kernels/stages/split_pilot.cl: four float4 per pilot pixel).
SplitVariance split_variance(const std::vector<float>& moments);

// The cost of a camera sample in ray units.  A ray that meets a fibre costs 1 with its shading
// at the first vertex and kLaterHitCost after it (rays from inside hair, in all directions,
// traverse far more of the tree); a camera ray that misses kMissCost; a shadow ray kShadowCost.
// c0 counts the first bounce per camera ray (its hits: the continuations it started / N), c1 the
// later bounces per continuation (their rays counted as hits).  Against the time ratio c1 / c0
// measured on the four scenes of docs/PERFORMANCE.md section 8 it is 0.95x (the demo) to 1.7x
// (brown hair): mostly high, so N comes out up to 1.3x below the optimum (1.03x above on the
// demo).
constexpr double kMissCost = 0.2, kLaterHitCost = 2, kShadowCost = 0.5;
struct SplitCost {
    double c0 = 1, c1 = 0;
};
SplitCost split_cost(const RenderStats& pilot, int splits);

struct SplitChoice {
    int splits = 1;
    SplitVariance variance;
    SplitCost cost;
    double seconds = 0;            // the pilot's wall time (0: no pilot ran)
    std::string describe() const;  // one line for stderr
};

// The N in [kMinAutoSplits, kMaxAutoSplits] with the least (c0 + N c1)(V_fixed + V_split / N); the
// smaller on a tie.  Nothing to tell (no variance between continuations, no cost): kMinAutoSplits.
int best_splits(const SplitVariance& v, const SplitCost& c);

}  // namespace ht
