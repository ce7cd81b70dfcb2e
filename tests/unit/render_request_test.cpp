// render and converge read the same words into the same request, resolved by the same rule.
#include <gtest/gtest.h>

#include "cli/render_request.h"
#include "kernels/types.h"

#include <string>
#include <vector>

namespace {

ht::ImageRequest image_request(ht::RenderCommand command, const std::vector<std::string>& args) {
    ht::ArgParser p(command == ht::RenderCommand::Render ? "render" : "converge");
    ht::add_render_options(p, command);
    std::vector<std::string> all = {"builtin:strand"};
    all.insert(all.end(), args.begin(), args.end());
    p.parse(all);
    return ht::parse_image_request(p);
}

ht::RenderSettings settings(ht::RenderCommand command, const std::vector<std::string>& args) {
    return ht::resolve_settings(ht::Scene{}, image_request(command, args));
}

}  // namespace

TEST(RenderRequest, RenderAndConvergeResolveTheSameWordsAlike) {
    using ht::RenderCommand;
    const std::vector<std::vector<std::string>> cases = {
        {"--model", "zinke", "--max-depth", "3"},
        {"--model", "marschner", "--fiber-field", "near", "--max-depth", "2"},
        {"--indirect", "afs"},
        {"--indirect", "none"},
        {"--indirect", "afs", "--max-depth", "4", "--clamp-indirect", "2.5", "--regularize", "10", "--seed", "7"},
        {"--bvh-oriented", "0.8"},
        {"--bvh-oriented", "0.8", "--bvh-oriented-splits", "1"},
    };
    for (const auto& args : cases) {
        const ht::RenderSettings r = settings(RenderCommand::Render, args), c = settings(RenderCommand::Converge, args);
        EXPECT_EQ(r.max_depth, c.max_depth) << args[1];
        EXPECT_EQ(r.fiber_field, c.fiber_field) << args[1];
        EXPECT_EQ(r.indirect, c.indirect) << args[1];
        EXPECT_EQ(r.clamp_indirect, c.clamp_indirect) << args[1];
        EXPECT_EQ(r.regularize_deg, c.regularize_deg) << args[1];
        EXPECT_EQ(r.bvh_oriented, c.bvh_oriented) << args[1];
        EXPECT_EQ(r.bvh_oriented_splits, c.bvh_oriented_splits) << args[1];
        EXPECT_EQ(r.seed, c.seed) << args[1];
    }
}

TEST(RenderRequest, OrientedNodesAutoOffOrARatio) {
    using ht::RenderCommand;
    for (RenderCommand c : {RenderCommand::Render, RenderCommand::Converge}) {
        EXPECT_EQ(settings(c, {}).bvh_oriented, ht::kAutoOriented);
        EXPECT_EQ(settings(c, {"--bvh-oriented", "auto"}).bvh_oriented, ht::kAutoOriented);
        EXPECT_EQ(settings(c, {"--bvh-oriented", "off"}).bvh_oriented, 0.0f);
        EXPECT_FLOAT_EQ(settings(c, {"--bvh-oriented", "0.5"}).bvh_oriented, 0.5f);
        for (const char* bad : {"most", "0", "1.5"}) {
            try {
                image_request(c, {"--bvh-oriented", bad});
                ADD_FAILURE() << bad << " was taken";
            } catch (const ht::UsageError& e) {
                EXPECT_NE(std::string(e.what()).find("auto, off or a number"), std::string::npos) << e.what();
            }
        }
    }
}

// auto: the builder's ratio from kOrientedVerticesPerSegment path vertices per segment on (where
// the traversal wins the longer build back), with splits always (they need oriented nodes).
TEST(RenderRequest, AutoOrientedNodesWhereTheRenderIsLongEnough) {
    const float on = ht::BvhOptions().obb_ratio;
    ASSERT_GT(on, 0.0f);
    const double per = ht::kOrientedVerticesPerSegment;
    EXPECT_EQ(ht::effective_bvh_oriented(ht::kAutoOriented, 0, per * 1000, 1000), on);
    EXPECT_EQ(ht::effective_bvh_oriented(ht::kAutoOriented, 0, per * 1000 - 1, 1000), 0.0f);
    EXPECT_EQ(ht::effective_bvh_oriented(ht::kAutoOriented, 1, 0, 1000), on);
    EXPECT_EQ(ht::effective_bvh_oriented(0.5f, 0, 0, 1000), 0.5f);
    EXPECT_EQ(ht::effective_bvh_oriented(0.0f, 0, 1e12, 1), 0.0f);
    // the anchor's 3.2M-segment head at 256^2 and depth 5: off at 32 spp (about break-even), on at 64
    EXPECT_EQ(ht::effective_bvh_oriented(ht::kAutoOriented, 0, 256.0 * 256 * 32 * 5, 3200000), 0.0f);
    EXPECT_EQ(ht::effective_bvh_oriented(ht::kAutoOriented, 0, 256.0 * 256 * 64 * 5, 3200000), on);
}

TEST(RenderRequest, OrientedSplitsNeedOrientedNodes) {
    using ht::RenderCommand;
    EXPECT_FLOAT_EQ(settings(RenderCommand::Render, {"--bvh-oriented", "0.8", "--bvh-oriented-splits", "1"})
                        .bvh_oriented_splits,
                    1.0f);
    EXPECT_EQ(settings(RenderCommand::Render, {"--bvh-oriented", "0.8"}).bvh_oriented_splits, 0.0f);
    // oriented nodes are the default, so the splits need no --bvh-oriented
    EXPECT_FLOAT_EQ(settings(RenderCommand::Render, {"--bvh-oriented-splits", "1"}).bvh_oriented_splits, 1.0f);
    for (RenderCommand c : {RenderCommand::Render, RenderCommand::Converge}) {
        EXPECT_THROW(image_request(c, {"--bvh-oriented", "off", "--bvh-oriented-splits", "1"}), ht::UsageError);
        EXPECT_THROW(image_request(c, {"--bvh-oriented", "0.8", "--bvh-oriented-splits", "0"}), ht::UsageError);
        EXPECT_THROW(image_request(c, {"--bvh-oriented", "0.8", "--bvh-oriented-splits", "3"}), ht::UsageError);
    }
}

TEST(RenderRequest, OneRuleForModelFieldAndDepth) {
    using ht::RenderCommand;
    // An explicit --model is taken literally unless --fiber-field says otherwise.
    EXPECT_EQ(settings(RenderCommand::Render, {"--model", "zinke", "--max-depth", "2"}).fiber_field,
              uint32_t(HT_FIELD_MATERIAL));
    EXPECT_EQ(settings(RenderCommand::Render, {"--max-depth", "2"}).fiber_field, uint32_t(HT_FIELD_AUTO));
    EXPECT_EQ(settings(RenderCommand::Render, {"--indirect", "afs"}).max_depth, 1);
    EXPECT_EQ(settings(RenderCommand::Render, {"--indirect", "none"}).max_depth, 1);
    EXPECT_EQ(settings(RenderCommand::Render, {"--indirect", "afs", "--max-depth", "3"}).max_depth, 3);
    EXPECT_THROW(image_request(RenderCommand::Render, {"--indirect", "none", "--max-depth", "3"}), ht::UsageError);
    EXPECT_THROW(image_request(RenderCommand::Converge, {"--model", "zinc"}), ht::UsageError);
    EXPECT_EQ(image_request(RenderCommand::Render, {}).settings.width, 512);
    EXPECT_EQ(image_request(RenderCommand::Converge, {}).settings.width, 256);
    EXPECT_EQ(image_request(RenderCommand::Converge, {"--device", "0,1"}).devices.indices.size(), 2u);
}
