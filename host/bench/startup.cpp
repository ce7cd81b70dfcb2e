#include "bench/startup.h"

#include "bench/median.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>
#include <sys/wait.h>

extern char** environ;

namespace ht {
namespace fs = std::filesystem;

namespace {

struct StartupRun {
    double seconds = 0, build_ms = 0;
    bool cached = false;
};

// One render in a child process whose caches live in `caches`; its stderr goes to a log that the
// "done:" line (kernel build milliseconds, cached or not) is read from.
StartupRun run_render(const std::string& exe, const std::string& scene, const fs::path& caches) {
    const fs::path log = caches / "render.log", image = caches / "first.exr";
    std::vector<std::string> args = {exe, "render", scene, "--width", "64", "--height", "64", "--spp", "1",
                                     "-o", image.string(), "--verbose"};
    std::vector<std::string> env_strings;
    for (char** e = environ; *e; ++e) {
        const std::string s = *e;
        if (s.rfind("HAIRTRACE_CACHE_DIR=", 0) == 0 || s.rfind("POCL_CACHE_DIR=", 0) == 0) continue;
        env_strings.push_back(s);
    }
    env_strings.push_back("HAIRTRACE_CACHE_DIR=" + (caches / "hairtrace").string());
    env_strings.push_back("POCL_CACHE_DIR=" + (caches / "pocl").string());
    std::vector<char*> argv, envp;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    for (auto& e : env_strings) envp.push_back(e.data());
    envp.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    const auto t0 = std::chrono::steady_clock::now();
    pid_t pid = 0;
    const int err = posix_spawn(&pid, exe.c_str(), &actions, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    if (err != 0) throw std::runtime_error("bench --startup: cannot start " + exe);
    int status = 0;
    waitpid(pid, &status, 0);
    StartupRun run;
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ifstream in(log);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw std::runtime_error("bench --startup: `hairtrace render " + scene + "` failed:\n" + text);
    // "... kernel build 5309 ms" or "... kernel build 12 ms (cached)"
    const std::string label = "kernel build ";
    const size_t at = text.find(label);
    if (at != std::string::npos) {
        const size_t end = text.find('\n', at);
        const std::string rest = text.substr(at + label.size(), end == std::string::npos ? end : end - at - label.size());
        run.build_ms = std::strtod(rest.c_str(), nullptr);
        run.cached = rest.find("(cached)") != std::string::npos;
    }
    return run;
}

}  // namespace

nlohmann::json measure_startup(const std::string& exe, const std::string& scene, int reps, bool print) {
    const fs::path root = fs::temp_directory_path() / ("hairtrace-startup-" + std::to_string(::getpid()));
    std::vector<double> cold_s, cold_build, cached_s, cached_build;
    bool cached_hit = true;
    try {
        for (int k = 0; k < reps; ++k) {
            fs::remove_all(root);
            fs::create_directories(root);
            const StartupRun cold = run_render(exe, scene, root);
            cold_s.push_back(cold.seconds);
            cold_build.push_back(cold.build_ms);
            const StartupRun warm = run_render(exe, scene, root);
            cached_s.push_back(warm.seconds);
            cached_build.push_back(warm.build_ms);
            cached_hit = cached_hit && warm.cached;
        }
    } catch (...) {
        fs::remove_all(root);
        throw;
    }
    fs::remove_all(root);
    nlohmann::json js = {{"scene", scene},
                         {"reps", reps},
                         {"cold_seconds", median(cold_s)},
                         {"cold_build_ms", median(cold_build)},
                         {"cached_seconds", median(cached_s)},
                         {"cached_build_ms", median(cached_build)},
                         {"cached_from_binary_cache", cached_hit}};
    if (print)
        std::printf("first image of %s (64 x 64, 1 spp, fresh process, median of %d):\n"
                    "  empty caches  %.2f s (kernel build %.0f ms)\n"
                    "  binary cache  %.2f s (kernel build %.0f ms%s)\n",
                    scene.c_str(), reps, median(cold_s), median(cold_build), median(cached_s),
                    median(cached_build), cached_hit ? "" : "; NOT from the cache");
    return js;
}

}  // namespace ht
