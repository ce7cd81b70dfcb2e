// RenderSettings::camera_lists and shadow_lists: camera rays test their pixel's candidate list
// (render/candidate_lists.h, kernels/stages/intersect_camera.cl), shadow rays toward a
// directional, point or spot light their cell's (render/shadow_lists.h, kernels/stages/intersect_shadow_lists.cl),
// instead of traversing the tree, and must find the very answers the tree finds -- so the film is
// the same bits, on sparse and dense hair, with triangles, with pixels that keep the tree beside
// pixels with lists, with splits and several bounces.  Where nothing can be proved there are no
// lists.
#include <gtest/gtest.h>

#include "render_test_util.h"

#include "cli_test_util.h"

#include <cmath>

namespace {

using namespace rendertest;

// lists against the tree: the same film; returns the lists' statistics
ht::RenderStats expect_same_film(const ht::Scene& s, ht::RenderSettings rs, const char* what) {
    ht::RenderStats lists, tree;
    rs.camera_lists = ht::RenderSettings::ListChoice::Lists;
    rs.shadow_lists = ht::RenderSettings::ShadowLists::Lists;
    const ht::Film a = render(s, rs, &lists);
    rs.camera_lists = ht::RenderSettings::ListChoice::Tree;
    rs.shadow_lists = ht::RenderSettings::ShadowLists::Tree;
    const ht::Film b = render(s, rs, &tree);
    EXPECT_EQ(a.rgba, b.rgba) << what;
    EXPECT_EQ(tree.candidate_entries, 0u) << what;
    EXPECT_EQ(tree.shadow_list_entries, 0u) << what;
    // the lists call more pixels empty (render/pixel_footprint.h): fewer traced, as many samples
    EXPECT_LE(lists.camera_rays, tree.camera_rays) << what;
    EXPECT_EQ(lists.camera_rays + lists.background_samples, tree.camera_rays + tree.background_samples) << what;
    EXPECT_EQ(lists.shadow_rays, tree.shadow_rays) << what;
    EXPECT_EQ(lists.extension_rays, tree.extension_rays) << what;
    return lists;
}

ht::Scene scene(const std::string& name) {
    ht::Scene s = ht::load_scene(name);
    ht::ensure_camera_and_light(s);
    return s;
}

// The scene lit by two directional lights besides its own: shadow rays along two grids and
// one without.
ht::Scene with_sun(ht::Scene s) {
    for (const ht::Vec3f d : {ht::Vec3f{0.3f, -1.0f, -0.4f}, ht::Vec3f{-0.8f, -0.5f, 0.2f}}) {
        ht::Light l;
        l.type = ht::LightType::Directional;
        const float n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        l.direction = {d[0] / n, d[1] / n, d[2] / n};
        l.intensity = 2.0f;
        s.lights.push_back(l);
    }
    return s;
}

// The scene lit by a point light above its hair and a spot light beside it (and nothing else):
// shadow rays to two points, each with a grid of the image a camera there would see.
ht::Scene with_lamps(ht::Scene s) {
    const ht::Bounds b = ht::scene_bounds(s);
    const ht::Vec3f c{0.5f * (b.lo[0] + b.hi[0]), 0.5f * (b.lo[1] + b.hi[1]), 0.5f * (b.lo[2] + b.hi[2])};
    float size = 0;
    for (int i = 0; i < 3; ++i) size = std::max(size, b.hi[i] - b.lo[i]);
    s.lights.clear();
    ht::Light point;
    point.type = ht::LightType::Point;
    point.position = {c[0] + 0.4f * size, c[1] + 1.5f * size, c[2] + 0.7f * size};
    point.intensity = 3.0f * size * size;
    ht::Light spot = point;
    spot.type = ht::LightType::Spot;
    spot.position = {c[0] - 1.6f * size, c[1] + 0.2f * size, c[2] + 0.9f * size};
    spot.direction = {1.6f, -0.2f, -0.9f};
    spot.outer_cone_deg = 40.0f;
    s.lights = {point, spot};
    return s;
}

}  // namespace

TEST(CandidateLists, SameFilmAsTheTree) {
    ht::Scene sparse = scene("builtin:strand?hairs=40&segments=12");
    sparse.environment.color = {0.3f, 0.45f, 0.7f};
    ht::RenderSettings rs = small_settings(4, 17, 3);
    rs.first_hit_splits = 2;
    EXPECT_GT(expect_same_film(sparse, rs, "sparse strand, splits, depth 3").candidate_entries, 0u);
    const ht::RenderStats sun = expect_same_film(with_sun(sparse), rs, "sparse strand in the sun");
    EXPECT_GT(sun.shadow_list_entries, 0u);
    const ht::RenderStats dense = expect_same_film(with_sun(scene("builtin:ball?hairs=1000&segments=16")), small_settings(3, 5, 2), "dense ball");
    EXPECT_GT(dense.candidate_entries, 48u * 48u) << "a dense ball puts several fibres under a pixel";
    const ht::RenderStats floor = expect_same_film(with_sun(scene(std::string(HT_SOURCE_DIR) + "/scenes/strand_on_floor.gltf")),
                                                   small_settings(3, 9, 3), "strand on a floor (triangles), in the sun");
    EXPECT_GT(floor.candidate_entries, 0u);
    EXPECT_GT(floor.shadow_list_entries, 0u);
    // shadow rays to a point and a spot light outside the hair: their images' lists
    EXPECT_GT(expect_same_film(with_lamps(scene("builtin:ball?hairs=1000&segments=16")), small_settings(3, 5, 3), "dense ball under lamps")
                  .shadow_list_entries,
              0u);
    EXPECT_GT(expect_same_film(with_lamps(scene(std::string(HT_SOURCE_DIR) + "/scenes/strand_on_floor.gltf")),
                               small_settings(3, 9, 3), "strand on a floor under lamps")
                  .shadow_list_entries,
              0u);
}

// Lists of 2 MiB and more go to a CPU device as the prepared scene's own pages (CL_MEM_USE_HOST_PTR,
// bvh/device_geometry.h read_only_buffer), smaller ones as copies: the large ones give the tree's
// film too.
TEST(CandidateLists, ListsInTheScenesOwnPagesGiveTheTreesFilm) {
    ht::RenderSettings rs = small_settings(2, 29, 2);
    rs.width = rs.height = 32;
    const ht::RenderStats big =
        expect_same_film(with_sun(scene("builtin:ball?hairs=2000&segments=24")), rs, "a ball with lists of megabytes");
    EXPECT_GE(big.shadow_list_entries * sizeof(float), size_t(2) << 20);
}

// A small cap: the ball's dense pixels traverse the tree beside pixels with lists, in one launch.
TEST(CandidateLists, PixelsThatKeepTheTree) {
    ht::RenderSettings rs = small_settings(3, 23, 2);
    rs.camera_list_cap = 8;
    const ht::RenderStats st = expect_same_film(scene("builtin:ball?hairs=2000&segments=16"), rs, "cap 8");
    EXPECT_GT(st.candidate_tree_pixels, 0u);
    EXPECT_GT(st.candidate_entries, 0u);
}

// The eye among the strands: no projection bounds them, so there are no lists, and the film is
// the tree's.
TEST(CandidateLists, NoListsWhenNothingCanBeProved) {
    ht::Scene s = scene("builtin:ball?hairs=300&segments=8");
    s.camera.eye = {0.0f, 0.0f, 0.0f};
    s.camera.target = {0.0f, 0.0f, -1.0f};
    const ht::RenderStats st = expect_same_film(s, small_settings(2, 3, 2), "eye inside");
    EXPECT_EQ(st.candidate_entries, 0u);
}

// On the command line: lists, tree and auto (the default) write the same image; bad values exit 2.
TEST(CandidateListsCli, ListsAndTreeWriteTheSameImage) {
    clitest::TempDir d("ht_candidate_lists_");
    clitest::expect_same_image_and_usage_errors(d, clitest::kSmallStrandRender + " --spp 3", " --camera-rays tree",
                                                " --camera-rays lists",
                                                {" --camera-rays", " --camera-rays bvh", " --camera-rays 1"});
    clitest::expect_same_image_and_usage_errors(d, clitest::kSmallStrandRender + " --spp 3", " --camera-rays auto", "", {});
    // a scene without lights gets the default view's three directional lights
    clitest::expect_same_image_and_usage_errors(
        d, std::string(HT_BINARY) + " render " + HT_SOURCE_DIR + "/tests/data/interleaved_lines.gltf --width 32 --height 24 --spp 3 --max-depth 3 --quiet",
        " --shadow-rays tree --camera-rays tree", " --shadow-rays lists", {" --shadow-rays", " --shadow-rays bvh"});
}

// --camera-rays auto: lists once spp x the image's pixels reaches kCameraListRaysPerPrimitive per
// segment, the tree below; lists and tree as asked whatever the count.
TEST(CandidateLists, AutoMakesCameraListsWhereEnoughRaysUseThem) {
    const ht::Scene s = scene("builtin:ball?hairs=300&segments=8");
    ht::RenderSettings rs = small_settings(1, 7, 1);
    const double threshold = ht::kCameraListRaysPerPrimitive * double(ht::prepare_scene(s, rs).geometry.segments.size());
    const int spp_lists = int(std::ceil(threshold / (double(rs.width) * rs.height)));
    ASSERT_GT(spp_lists, 1);
    const auto lists_at = [&](int spp, ht::RenderSettings::ListChoice choice) {
        ht::RenderSettings r = rs;
        r.spp = spp;
        r.camera_lists = choice;
        return ht::prepare_scene(s, r).candidates.enabled;
    };
    using LC = ht::RenderSettings::ListChoice;
    EXPECT_FALSE(lists_at(spp_lists - 1, LC::Auto));
    EXPECT_TRUE(lists_at(spp_lists, LC::Auto));
    EXPECT_TRUE(lists_at(1, LC::Lists));
    EXPECT_FALSE(lists_at(4 * spp_lists, LC::Tree));
}

// The shadow rays a camera path sends through the lists at its first vertex: its light samples,
// at any depth; none where AFS (at depth 1) or dual scattering takes them into its own stage.
TEST(ShadowListsAuto, CountsTheRaysThatUseTheLists) {
    ht::RenderSettings rs = small_settings(1, 7, 1);
    EXPECT_EQ(ht::list_shadow_rays_per_path(rs), 1.0);
    rs.first_hit_light_samples = 4;
    EXPECT_EQ(ht::list_shadow_rays_per_path(rs), 4.0);
    rs.max_depth = 5;
    EXPECT_EQ(ht::list_shadow_rays_per_path(rs), 4.0);
    rs.indirect = ht::RenderSettings::Indirect::Afs;
    EXPECT_EQ(ht::list_shadow_rays_per_path(rs), 4.0);
    rs.max_depth = 1;
    EXPECT_EQ(ht::list_shadow_rays_per_path(rs), 0.0);
    rs.indirect = ht::RenderSettings::Indirect::Dual;
    EXPECT_EQ(ht::list_shadow_rays_per_path(rs), 0.0);
}

// What auto weighs the rays against: the entries the lists would hold, estimated from the cells
// of each primitive's hull before any is made -- within 15 % of the entries made (2-3 % below them
// on four locks, docs/PERFORMANCE.md section 8; the estimate rounds each box's ends by one cell
// where the lists round them to the cells they touch).
TEST(ShadowListsAuto, EstimatesTheEntries) {
    for (const char* name : {"builtin:ball?hairs=300&segments=8", "builtin:strand?hairs=40&segments=12"}) {
        const ht::Scene s = with_sun(scene(name));
        const ht::PreparedScene p = ht::prepare_scene(s, small_settings(1, 7, 1));
        const double made = double(ht::build_shadow_lists(p.geometry, p.lights).primitive.size());
        const double estimate = ht::estimate_shadow_list_entries(p.geometry, p.lights);
        ASSERT_GT(made, 0) << name;
        EXPECT_NEAR(estimate / made, 1.0, 0.15) << name << ": " << estimate << " estimated, " << made << " made";
    }
}

// --shadow-rays auto: lists once spp x the pixels that see geometry x those rays per path reach
// kShadowListRaysPerEntry per estimated entry -- with three light samples at a third of one's
// samples; never with dual scattering, whose shadow stage does not read them.
TEST(ShadowListsAuto, MakesListsWhereEnoughRaysUseThem) {
    const ht::Scene s = with_sun(scene("builtin:ball?hairs=300&segments=8"));
    // the camera's lists, made at every spp, keep the pixels that see geometry the same
    const auto settings = [](int spp, int depth) {
        ht::RenderSettings r = small_settings(spp, 7, depth);
        r.camera_lists = ht::RenderSettings::ListChoice::Lists;
        return r;
    };
    const auto lists_at = [&](int spp, int depth, ht::RenderSettings::Indirect indirect) {
        ht::RenderSettings r = settings(spp, depth);
        r.indirect = indirect;
        return ht::prepare_scene(s, r).shadow_lists.enabled();
    };
    const ht::PreparedScene p = ht::prepare_scene(s, settings(1, 1));
    const double pixels = p.footprint.seen.empty() ? 48.0 * 48.0 : double(p.footprint.seen.size());
    const double threshold = ht::kShadowListRaysPerEntry * ht::estimate_shadow_list_entries(p.geometry, p.lights);
    using Indirect = ht::RenderSettings::Indirect;
    for (const int light_samples : {1, 3}) {
        ht::RenderSettings r = settings(1, 5);
        r.first_hit_light_samples = light_samples;
        const int spp_lists = int(std::ceil(threshold / (pixels * ht::list_shadow_rays_per_path(r))));
        ASSERT_GT(spp_lists, 1) << light_samples;
        for (const int spp : {spp_lists - 1, spp_lists}) {
            r.spp = spp;
            EXPECT_EQ(ht::prepare_scene(s, r).shadow_lists.enabled(), spp == spp_lists) << light_samples << " " << spp;
        }
    }
    EXPECT_FALSE(lists_at(1000, 1, Indirect::Dual));
}

// prepare_scene's lists_ready, where the render starts compiling the stages that read lists
// (kernels/stages/lists.cl), comes once exactly when it makes camera or shadow lists, before it
// makes them: a render without lists never compiles that program.
TEST(CandidateLists, ListsReadyComesOnceWhenListsAreMade) {
    int with_lists = 0, without = 0;
    for (const char* name : {"builtin:ball?hairs=300&segments=8", "builtin:strand?hairs=40&segments=12"}) {
        const ht::Scene s = with_sun(scene(name));
        for (const int spp : {1, 8, 64, 1000})
            for (const int light_samples : {1, 3}) {
                ht::RenderSettings r = small_settings(spp, 7, 5);
                r.first_hit_light_samples = light_samples;
                int calls = 0;
                bool made_before = false;
                const ht::PreparedScene p = ht::prepare_scene(s, r, {}, [&](const ht::PreparedScene& q) {
                    ++calls;
                    made_before = q.candidates.enabled || q.shadow_lists.enabled();
                });
                const bool lists = p.candidates.enabled || p.shadow_lists.enabled();
                (lists ? with_lists : without) += 1;
                EXPECT_EQ(calls, lists ? 1 : 0) << name << " spp " << spp << " light samples " << light_samples;
                EXPECT_FALSE(made_before) << name << " spp " << spp;
            }
    }
    // the sweep has renders of both kinds
    EXPECT_GE(with_lists, 4);
    EXPECT_GE(without, 2);
}

// The lists are what the rays use: emptied, every camera ray misses (the film is the background)
// and no shadow ray toward the suns is blocked (more light) -- so the tests above compare the
// lists' answers, not the tree's twice.
TEST(CandidateLists, TheRaysUseTheLists) {
    ht::Scene s = with_sun(scene("builtin:strand?hairs=40&segments=12"));
    s.lights.erase(s.lights.begin(), s.lights.end() - 2);  // the suns alone
    s.environment.color = {0.25f, 0.5f, 0.75f};
    ht::RenderSettings rs = small_settings(2, 7, 1);
    rs.camera_lists = ht::RenderSettings::ListChoice::Lists;
    rs.shadow_lists = ht::RenderSettings::ShadowLists::Lists;
    ht::PreparedScene prepared = ht::prepare_scene(s, rs);
    ASSERT_TRUE(prepared.candidates.enabled);
    ASSERT_TRUE(prepared.shadow_lists.enabled());
    const auto film_of = [&](const ht::PreparedScene& p) {
        ht::Film f;
        ht::Renderer r(context(), p);
        r.render(f);
        return f;
    };
    const ht::Film lit = film_of(prepared);
    ht::PreparedScene no_blockers = prepared;
    std::fill(no_blockers.shadow_lists.count.begin(), no_blockers.shadow_lists.count.end(), 0u);
    EXPECT_GT(image_mean(film_of(no_blockers)), image_mean(lit) * 1.001) << "shadow rays answered from the lists";
    ht::PreparedScene no_hits = prepared;
    std::fill(no_hits.candidates.count.begin(), no_hits.candidates.count.end(), 0u);
    const ht::Film blank = film_of(no_hits);
    for (size_t i = 0; i < size_t(rs.width) * rs.height; ++i)
        ASSERT_NEAR(blank.mean(i, 0), 0.25f, 1e-6f) << "camera rays answered from the lists: pixel " << i;
    EXPECT_NE(lit.rgba, blank.rgba) << "the strand is in view";
    // the same for the point and spot lights' lists
    const ht::Scene lit_by_lamps = with_lamps(scene("builtin:strand?hairs=40&segments=12"));  // outlives its prepared scene
    ht::PreparedScene lamps = ht::prepare_scene(lit_by_lamps, rs);
    ASSERT_EQ(lamps.shadow_lists.grids.size(), 2u);
    for (const HtShadowGrid& g : lamps.shadow_lists.grids) EXPECT_EQ(g.kind, HT_SHADOW_GRID_FROM_POINT);
    const ht::Film lamp_lit = film_of(lamps);
    std::fill(lamps.shadow_lists.count.begin(), lamps.shadow_lists.count.end(), 0u);
    EXPECT_GT(image_mean(film_of(lamps)), image_mean(lamp_lit) * 1.001) << "shadow rays to the lamps answered from the lists";
}

// The lists only make rays faster: a device that holds the render without them but not with them
// gets a render without them (the same film), told in the statistics, instead of a refusal; a
// device too small even without them still refuses.
TEST(CandidateLists, ListsThatDoNotFitTheDeviceAreLeftOut) {
    const ht::Scene s = with_sun(scene("builtin:ball?hairs=1000&segments=16"));
    ht::RenderSettings rs = small_settings(2, 5, 2);
    const auto fits = [&](const ht::RenderSettings& settings) {
        try {
            ht::Renderer r(context(), s, settings);
            return true;
        } catch (const ht::DeviceError&) {
            return false;
        }
    };
    // the least --max-memory that holds the render without lists
    ht::RenderSettings bare = rs;
    bare.camera_lists = ht::RenderSettings::ListChoice::Tree;
    bare.shadow_lists = ht::RenderSettings::ShadowLists::Tree;
    uint64_t lo = 1, hi = uint64_t(1) << 32;  // fits at hi, not at lo
    bare.max_device_bytes = hi;
    ASSERT_TRUE(fits(bare));
    while (hi - lo > 1) {
        bare.max_device_bytes = lo + (hi - lo) / 2;
        (fits(bare) ? hi : lo) = bare.max_device_bytes;
    }
    rs.camera_lists = ht::RenderSettings::ListChoice::Lists;
    rs.shadow_lists = ht::RenderSettings::ShadowLists::Lists;
    ht::RenderStats full, tight;
    const ht::Film with_lists = render(s, rs, &full);
    ASSERT_GT(full.candidate_entries, 0u);
    ASSERT_GT(full.shadow_list_entries, 0u);
    EXPECT_FALSE(full.camera_lists_dropped || full.shadow_lists_dropped);
    rs.max_device_bytes = hi;
    const ht::Film without = render(s, rs, &tight);
    EXPECT_TRUE(tight.shadow_lists_dropped);
    EXPECT_TRUE(tight.camera_lists_dropped);
    EXPECT_EQ(tight.candidate_entries, 0u);
    EXPECT_EQ(tight.shadow_list_entries, 0u);
    EXPECT_EQ(with_lists.rgba, without.rgba);
    rs.max_device_bytes = lo;
    EXPECT_FALSE(fits(rs)) << "too small even without the lists";
}
