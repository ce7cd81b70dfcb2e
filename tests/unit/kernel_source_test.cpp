#include "cl/kernel_source.h"

#include <gtest/gtest.h>

TEST(KernelSource, CompatIsEmbeddedWithLineMarkers) {
    std::string s = ht::assemble_kernel_source("types.h");
    EXPECT_NE(s.find("#line 1 \"kernels/types.h\""), std::string::npos);
    EXPECT_NE(s.find("#line 1 \"kernels/compat.h\""), std::string::npos);
    EXPECT_NE(s.find("HtBvhNode"), std::string::npos);
}
