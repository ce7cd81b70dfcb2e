// RenderSettings::samples_per_pass: a pass renders several consecutive samples of each traced
// pixel (kernels/stages/generate_camera_rays.cl), and accumulate adds them in sample order, so the
// film must hold the same bits for any count -- sums, sample counts, the --target-error half film
// and the AOV sums -- with first-hit splits and light samples, skipped empty pixels, several
// bounces, listed pixels and sample ranges that do not divide by the count.
#include <gtest/gtest.h>

#include "render_test_util.h"

#include <vector>

namespace {

using namespace rendertest;

struct Rendered {
    ht::Film film;
    ht::RenderStats stats;
    int per_pass = 0;
};

Rendered render_with(const ht::Scene& s, ht::RenderSettings rs, int samples_per_pass) {
    rs.samples_per_pass = samples_per_pass;
    Rendered out;
    ht::Renderer r(context(), s, rs);
    r.render(out.film);
    out.stats = r.stats();
    out.per_pass = r.samples_per_pass();
    return out;
}

void expect_same_film(const ht::Film& a, const ht::Film& b) {
    EXPECT_EQ(a.rgba, b.rgba);
    EXPECT_EQ(a.even, b.even);
    EXPECT_EQ(a.aov, b.aov);
}

}  // namespace

TEST(SamplesPerPass, SameFilmBitsForAnyCount) {
    struct Case {
        const char* name;
        bool aovs;
        int depth, splits, light_samples;
    };
    // --aovs keeps every pixel traced (no skipped empty pixels); the others skip them
    for (const Case& c : {Case{"empty pixels skipped, splits, half films", false, 3, 2, 1},
                          Case{"aovs, two light samples", true, 2, 1, 2}}) {
        SCOPED_TRACE(c.name);
        const ht::Scene s = sparse_strand();
        ht::RenderSettings rs = small_settings(7, 5, c.depth);
        rs.first_hit_splits = c.splits;
        rs.first_hit_light_samples = c.light_samples;
        rs.target_error = 0.01f;  // the even half film is filled too
        rs.aovs = c.aovs;
        const Rendered one = render_with(s, rs, 1);
        ASSERT_EQ(one.per_pass, 1);
        if (!c.aovs) {
            ASSERT_GT(one.stats.empty_pixels, 0u) << "the strand leaves pixels empty";
        }
        for (const int n : {3, 8}) {
            SCOPED_TRACE(n);
            const Rendered many = render_with(s, rs, n);
            EXPECT_EQ(many.per_pass, n) << "a 48x48 image fits n samples in one pass";
            expect_same_film(one.film, many.film);
            EXPECT_EQ(one.stats.camera_rays, many.stats.camera_rays);
            EXPECT_EQ(one.stats.background_samples, many.stats.background_samples);
            EXPECT_EQ(one.stats.extension_rays, many.stats.extension_rays);
        }
    }
}

// A pass that cannot hold every pixel N times holds as many whole samples as fit, or one sample
// spread over several passes as before: the same film either way.
TEST(SamplesPerPass, FewerWhenThePassIsSmall) {
    const ht::Scene s = thick_strand();
    ht::RenderSettings rs = small_settings(5, 9, 2);
    rs.width = rs.height = 16;
    rs.first_hit_splits = 1;
    rs.skip_empty_pixels = false;  // all 256 pixels traced
    const Rendered one = render_with(s, rs, 1);
    rs.max_paths_per_pass = 2 * 256 + 100;  // two samples of every pixel
    const Rendered two = render_with(s, rs, 8);
    EXPECT_EQ(two.per_pass, 2);
    expect_same_film(one.film, two.film);
    rs.max_paths_per_pass = 100;  // a sample takes three passes
    const Rendered split = render_with(s, rs, 8);
    EXPECT_EQ(split.per_pass, 1);
    expect_same_film(one.film, split.film);
}

// render_samples over ranges that do not divide by the count, and over listed pixels (render
// --target-error), adds up to the film of one sample at a time.
TEST(SamplesPerPass, RangesAndListedPixels) {
    const ht::Scene s = sparse_strand();
    ht::RenderSettings rs = small_settings(1, 3, 2);
    rs.first_hit_splits = 2;
    const std::vector<uint32_t> listed = {0, 5, 47, 48 * 20 + 24, 48 * 24 + 20, 48 * 24 + 30, 48 * 48 - 1};
    for (const bool with_list : {false, true}) {
        SCOPED_TRACE(with_list ? "listed pixels" : "every pixel");
        ht::Film a, b;
        a.width = b.width = rs.width, a.height = b.height = rs.height;
        a.rgba.assign(4 * size_t(rs.width) * rs.height, 0.0f);
        b.rgba = a.rgba;
        rs.samples_per_pass = 1;
        {
            ht::Renderer r(context(), s, rs);
            if (with_list) r.set_pixels(listed);
            r.upload_film(a);
            for (uint32_t i = 0; i < 11; ++i) r.render_sample(i);
            r.download_film(a);
        }
        rs.samples_per_pass = 4;
        {
            ht::Renderer r(context(), s, rs);
            if (with_list) r.set_pixels(listed);
            EXPECT_EQ(r.samples_per_pass(), 4);
            r.upload_film(b);
            r.render_samples(0, 5);  // 4 + 1
            r.render_samples(5, 6);  // 4 + 2
            r.download_film(b);
        }
        EXPECT_EQ(a.rgba, b.rgba);
    }
}

// --first-hit-splits auto's pilot renders its samples several to a pass too
// (kernels/stages/split_pilot.cl pilot_accumulate): the same moments, the same choice.
TEST(SamplesPerPass, ThePilotMeasuresTheSame) {
    const ht::Scene s = thick_strand();
    ht::RenderSettings rs = small_settings(2, 4, 3);
    rs.first_hit_splits = ht::kAutoFirstHitSplits;
    ht::SplitChoice choice[2];
    for (const int n : {1, 8}) {
        rs.samples_per_pass = n;
        ht::Renderer r(context(), s, rs);
        choice[n == 8] = r.choose_first_hit_splits();
    }
    EXPECT_GT(choice[0].variance.total, 0.0) << "the pilot saw light";
    EXPECT_EQ(choice[0].variance.total, choice[1].variance.total);
    EXPECT_EQ(choice[0].variance.split, choice[1].variance.split);
    EXPECT_EQ(choice[0].variance.stratification, choice[1].variance.stratification);
    EXPECT_EQ(choice[0].cost.c0, choice[1].cost.c0);
    EXPECT_EQ(choice[0].cost.c1, choice[1].cost.c1);
    EXPECT_EQ(choice[0].splits, choice[1].splits);
}
