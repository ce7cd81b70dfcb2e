#include "cl/kernel_source.h"
#include "scene_test_util.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

TEST(KernelSource, CompatIsEmbeddedWithLineMarkers) {
    std::string s = ht::assemble_kernel_source("types.h");
    EXPECT_NE(s.find("#line 1 \"kernels/types.h\""), std::string::npos);
    EXPECT_NE(s.find("#line 1 \"kernels/compat.h\""), std::string::npos);
    EXPECT_NE(s.find("HtBvhNode"), std::string::npos);
}

namespace {
// A directory of its own (ctest runs these tests in parallel processes: a shared name let one
// test's clean-up delete the directory another was writing into); the kernel directory is reset
// before the directory goes.
struct TempKernelDir {
    ht::test::TempDir tmp;
    const std::string dir = tmp.file("");
    void write(const std::string& name, const std::string& text) { std::ofstream(tmp.file(name)) << text; }
    ~TempKernelDir() { ht::set_kernel_dir(""); }
};
}  // namespace

TEST(KernelSource, AHeaderFirstIncludedInsideAFalseBlockIsStillIncludedLater) {
    // Inlining a header only at its first #include would leave it inside "#if 0" here, and the
    // unconditional include below would then bring nothing: the program would miss `answer`.
    TempKernelDir k;
    k.write("value.h", "#ifndef VALUE_H\n#define VALUE_H\n#define ANSWER 42\n#endif\n");
    k.write("main.cl", "#if 0\n#include \"value.h\"\n#endif\n#include \"value.h\"\nint answer = ANSWER;\n");
    ht::set_kernel_dir(k.dir);
    const std::string s = ht::assemble_kernel_source("main.cl");
    const size_t last_copy = s.rfind("#define ANSWER 42"), endif_of_if0 = s.find("#endif\n#line 3");
    ASSERT_NE(last_copy, std::string::npos);
    ASSERT_NE(endif_of_if0, std::string::npos);
    EXPECT_GT(last_copy, endif_of_if0) << s;
}

TEST(KernelSource, UnconditionalIncludesAreInlinedOnceAndCyclesEnd) {
    TempKernelDir k;
    k.write("a.h", "#ifndef A_H\n#define A_H\n#include \"b.h\"\nA\n#endif\n");
    k.write("b.h", "#ifndef B_H\n#define B_H\n#include \"a.h\"\nB\n#endif\n");
    k.write("main.cl", "#include \"a.h\"\n#include \"b.h\"\n#include \"a.h\"\n");
    ht::set_kernel_dir(k.dir);
    const std::string s = ht::assemble_kernel_source("main.cl");
    size_t count = 0;
    for (size_t p = s.find("\nB\n"); p != std::string::npos; p = s.find("\nB\n", p + 1)) ++count;
    EXPECT_EQ(count, 1u) << s;
}
