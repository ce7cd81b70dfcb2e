// The kernel build options are declared once (kernels/features.h) and every one the host emits
// is read by some kernel: an option no kernel reads is a feature that silently does nothing.
#include <gtest/gtest.h>

#include "bvh/device_geometry.h"
#include "cl/kernel_source.h"
#include "render/features.h"

#include <set>
#include <sstream>
#include <string>

using namespace ht;

namespace {

// Every feature switch has its 0/1 default in kernels/features.h (an undefined name would not
// compile here).
#define HT_FEATURE_DEFAULT_IS_BOOL(name, meaning) \
    static_assert(HT_FEATURE_##name == 0 || HT_FEATURE_##name == 1, "HT_FEATURE_" #name);
HT_FEATURE_SWITCHES(HT_FEATURE_DEFAULT_IS_BOOL)
#undef HT_FEATURE_DEFAULT_IS_BOOL

std::set<std::string> defined_names(const std::string& options) {
    std::set<std::string> out;
    std::istringstream in(options);
    std::string tok;
    while (in >> tok)
        if (tok.rfind("-D", 0) == 0) out.insert(tok.substr(2, tok.find('=') - 2));
    return out;
}

// The render program's source: all of its builds (host/render/renderer.cpp).
std::string render_program_source() {
    return assemble_kernel_source("stages/trace.cl") + assemble_kernel_source("stages/shade.cl") +
           assemble_kernel_source("stages/intersect_shadow_afs.cl") + assemble_kernel_source("stages/lists.cl");
}

}  // namespace

TEST(KernelFeatures, EveryEmittedDefineIsReadByAKernel) {
    KernelFeatures all;
    for (bool& on : all.on) on = true;
    all.paging.pages = 4;
    all.paging.page_log2 = 10;
    const std::string options = kernel_build_options(all) + estimator_build_options(2.0f, 10.0f, 0.05f, true, true, true, 0.2f, true);
    const std::set<std::string> names = defined_names(options);
    EXPECT_GE(names.size(), kFeatureCount + 7);
    const std::string src = render_program_source();
    for (const std::string& name : names)
        EXPECT_EQ(options_read_by(src, "-D" + name + "=1"), "-D" + name + "=1")
            << name << " is emitted but no kernel reads it";
}

TEST(KernelFeatures, AProgramIsBuiltWithTheDefinesItReadsOnly) {
    const std::string src = "#ifndef HT_A\n#define HT_A 1\n#endif\n"
                            "  #  ifndef HT_B\n#define HT_B 0\n#endif\n"
                            "#if HT_A\nint a;\n#endif\n"
                            "#define HT_DERIVED (HT_C && 1)\n"
                            "int HT_DX; /* HT_D in a comment, and a longer name */\n// HT_E too\n";
    EXPECT_EQ(options_read_by(src, "-cl-std=CL1.2 -DHT_A=0 -DHT_B=1 -DHT_C=1 -DHT_D=1 -DHT_E -cl-mad-enable"),
              "-cl-std=CL1.2 -DHT_A=0 -DHT_C=1 -cl-mad-enable");
    // the trace stages read neither the lights, the fibre models nor their lobes: scenes that
    // differ in them share that build
    const std::string trace = assemble_kernel_source("stages/trace.cl");
    EXPECT_EQ(options_read_by(trace, "-DHT_FEATURE_LIGHT_SPOT=0 -DHT_FEATURE_MODEL_ZINKE=0 -DHT_FEATURE_LOBE_TT=0"), "");
    const std::string shade = assemble_kernel_source("stages/shade.cl");
    EXPECT_EQ(options_read_by(shade, "-DHT_FEATURE_LIGHT_SPOT=0 -DHT_FEATURE_MODEL_ZINKE=0"),
              "-DHT_FEATURE_LIGHT_SPOT=0 -DHT_FEATURE_MODEL_ZINKE=0");
}

TEST(KernelFeatures, OneDefinePerSwitchAndEveryMeaningSaid) {
    const std::set<std::string> names = defined_names(kernel_build_options(KernelFeatures{}));
    for (size_t i = 0; i < kFeatureCount; ++i) {
        EXPECT_EQ(names.count(feature_define(Feature(i))), 1u);
        EXPECT_GT(std::string(feature_meaning(Feature(i))).size(), 3u);
    }
    EXPECT_EQ(describe_features(KernelFeatures{}).size(), kFeatureCount + 1);  // + the geometry line
}

TEST(KernelFeatures, EstimatorOptionsAreEmptyWhenOff) {
    EXPECT_EQ(estimator_build_options(0, 0, 0, false, false), "");
    EXPECT_NE(estimator_build_options(3, 0, 0, false, false).find("HT_CLAMP_INDIRECT"), std::string::npos);
    EXPECT_NE(estimator_build_options(0, 0, 0.05f, false, false).find("HT_LIGHT_THRESHOLD"), std::string::npos);
    EXPECT_NE(estimator_build_options(0, 0, 0, false, false, false, 0.2f).find("HT_LIGHT_GUIDE"), std::string::npos);
    EXPECT_NE(estimator_build_options(0, 0, 0, false, false, false, 0, true).find("HT_LIGHT_VERTICES"), std::string::npos);
}
