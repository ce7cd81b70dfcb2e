// Shared helpers of the tests that run the hairtrace binary (header only: the test globs take
// *.cpp): a scratch directory, a command's exit status, a file's bytes.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include "io/image_io.h"

namespace clitest {

// A fresh directory under the system temp dir, removed with everything in it at scope exit.
struct TempDir {
    std::filesystem::path path;
    explicit TempDir(const std::string& prefix) {
        path = std::filesystem::temp_directory_path() /
               (prefix + std::to_string(::getpid()) + "_" + std::to_string(std::rand()));
        std::filesystem::create_directories(path);
    }
    ~TempDir() { std::filesystem::remove_all(path); }
    std::string operator/(const std::string& f) const { return (path / f).string(); }
};

// The exit status of a shell command (as the shell reports it).
inline int run(const std::string& cmd) { return WEXITSTATUS(std::system(cmd.c_str())); }

inline std::string slurp(const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

// The rgb floats of an image file (width and height dropped: the tests compare equal-size images).
inline std::vector<float> image(const std::string& p) {
    int w, h;
    return ht::read_rgb_image(p, w, h);
}

}  // namespace clitest
