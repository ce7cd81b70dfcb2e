// Shared harness for the scene-loader fuzz targets.
//
// The loaders only take paths (there is no from-memory entry point), so each input is written to
// a file in a private directory on tmpfs (/dev/shm, falling back to $TMPDIR or /tmp) and loaded
// through ht::load_scene, exactly as `hairtrace render FILE` would.  The file name's extension
// selects the loader.
//
// Verdicts:
//   * ht::SceneError                      -> expected rejection of hostile input; fine.
//   * a scene that loads                  -> must honour scene_contract.h, else abort().  Setting
//     HT_FUZZ_IGNORE to a comma-separated list of contract categories (strands, camera, light, textures)
//     tolerates violations already reported, so that a long run can dig past them.
//   * any other exception                 -> abort() (a finding: loaders must only throw SceneError).
//   * crashes, sanitizer reports, timeouts, allocations above -malloc_limit_mb -> libFuzzer
//     reports them itself.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "scene/scene.h"
#include "scene_contract.h"

namespace ht_fuzz {

// A private scratch directory, created once per process and removed at normal exit (a crash
// leaves it behind, with the crashing input in it, which is harmless and occasionally handy).
class ScratchDir {
public:
    static const std::string& path() {
        static ScratchDir dir;
        return dir.path_;
    }

private:
    ScratchDir() {
        const char* bases[] = {"/dev/shm", std::getenv("TMPDIR"), "/tmp"};
        for (const char* base : bases) {
            if (!base || !*base) continue;
            std::string templ = std::string(base) + "/hairtrace-fuzz-XXXXXX";
            if (mkdtemp(&templ[0])) {
                path_ = templ;
                return;
            }
        }
        std::perror("hairtrace fuzz: mkdtemp");
        std::abort();
    }
    ~ScratchDir() {
        // Only the files the targets create live here (see input_path); remove what may exist.
        for (const char* name : {"input.hair", "input.data", "input.gltf", "input.glb"})
            unlink((path_ + "/" + name).c_str());
        rmdir(path_.c_str());
    }
    std::string path_;
};

inline std::string input_path(const char* file_name) {
    return ScratchDir::path() + "/" + file_name;
}

// Replaces the file at `path` with exactly `size` bytes of `data`.
inline void write_input(const std::string& path, const uint8_t* data, size_t size) {
    const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0) {
        std::perror("hairtrace fuzz: open");
        std::abort();
    }
    size_t done = 0;
    while (done < size) {
        const ssize_t n = write(fd, data + done, size - done);
        if (n <= 0) {
            std::perror("hairtrace fuzz: write");
            std::abort();
        }
        done += static_cast<size_t>(n);
    }
    close(fd);
}

// Loads `path` (a file or a builtin: spec) and applies the verdicts above.
// True when the category of `violation` ("camera: ...") is listed in HT_FUZZ_IGNORE.
inline bool ignored_category(const std::string& violation) {
    static const std::string ignore = [] {
        const char* e = std::getenv("HT_FUZZ_IGNORE");
        return "," + std::string(e ? e : "") + ",";
    }();
    const std::string category = violation.substr(0, violation.find(':'));
    return ignore.find("," + category + ",") != std::string::npos;
}

// HT_FUZZ_VERBOSE=1 prints each verdict (for checking what seeds and reproducers exercise).
inline void load_and_judge(const std::string& path) {
    static const bool verbose = std::getenv("HT_FUZZ_VERBOSE") != nullptr;
    try {
        const ht::Scene scene = ht::load_scene(path, fuzz_load_options());
        if (verbose)
            std::fprintf(stderr, "LOADED: %zu strands, %zu points, %zu warnings\n",
                         scene.strands.strand_count(), scene.strands.point_count(),
                         scene.warnings.size());
        const std::string violation = scene_contract_violation(scene);
        if (!violation.empty() && !ignored_category(violation)) {
            std::fprintf(stderr, "FINDING: %s loaded but breaks the scene contract: %s\n",
                         path.c_str(), violation.c_str());
            std::abort();
        }
    } catch (const ht::SceneError& e) {
        // Expected: the loader refused hostile input with a proper message.
        if (verbose) std::fprintf(stderr, "REJECTED: %s\n", e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "FINDING: %s threw a non-SceneError exception: %s\n", path.c_str(),
                     e.what());
        std::abort();
    } catch (...) {
        std::fprintf(stderr, "FINDING: %s threw a non-std exception\n", path.c_str());
        std::abort();
    }
}

// Writes the input to the scratch file `file_name` and loads it.
inline void fuzz_file(const char* file_name, const uint8_t* data, size_t size) {
    const std::string path = input_path(file_name);
    write_input(path, data, size);
    load_and_judge(path);
}

}  // namespace ht_fuzz
