// The warning for MPI ranks whose CPU binding leaves cores of the node idle (split/distributed.h).
#include <gtest/gtest.h>

#include "split/distributed.h"

#ifdef __linux__
#include <sched.h>
#include <unistd.h>

TEST(CpuBinding, OneRankBoundToOneCoreOfSeveralIsWarnedAbout) {
    if (sysconf(_SC_NPROCESSORS_ONLN) < 2) GTEST_SKIP() << "needs a machine with two CPUs";
    cpu_set_t saved, one;
    ASSERT_EQ(sched_getaffinity(0, sizeof saved, &saved), 0);
    int first = 0;
    while (!CPU_ISSET(first, &saved)) ++first;
    CPU_ZERO(&one);
    CPU_SET(first, &one);
    ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
    const std::string one_rank = ht::cpu_binding_warning(1);
    const std::string per_core = ht::cpu_binding_warning(int(sysconf(_SC_NPROCESSORS_ONLN)));
    ASSERT_EQ(sched_setaffinity(0, sizeof saved, &saved), 0);  // before any expectation can fail
    EXPECT_NE(one_rank.find("--bind-to none"), std::string::npos) << one_rank;
    EXPECT_EQ(per_core, "") << "one rank per core uses every core";
}

TEST(CpuBinding, UnboundProcessIsNotWarnedAbout) {
    cpu_set_t set;
    ASSERT_EQ(sched_getaffinity(0, sizeof set, &set), 0);
    if (CPU_COUNT(&set) < sysconf(_SC_NPROCESSORS_ONLN)) GTEST_SKIP() << "the test itself runs bound";
    EXPECT_EQ(ht::cpu_binding_warning(1), "");
}
#endif
