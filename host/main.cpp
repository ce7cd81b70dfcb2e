// hairtrace command line: render, merge, info, devices, bench, converge, fiber.
//
// Exit codes: 0 success; 2 bad input or usage, 3 device or runtime failure (which exception is
// which: core/errors.h); 128+N interrupted by signal N after saving the checkpoint and images.
#include "bench/bench.h"
#include "cl/device.h"
#include "cli/commands.h"
#include "cli/fiber_command.h"
#include "core/errors.h"
#include "io/image_io.h"

#include <cstdio>
#include <string>
#include <vector>

using namespace ht;

namespace {

const char* kTopHelp =
    "hairtrace " HT_VERSION " - photo-realistic hair rendering (Zinke et al. 2004) on OpenCL\n"
    "\n"
    "usage: hairtrace <command> [arguments] [options]\n"
    "\n"
    "commands:\n"
    "  render SCENE -o OUT ...   render a scene to images (.exr linear, .png sRGB; -o repeatable)\n"
    "  merge PARTS... -o OUT     combine `render --sample-range A:B` parts exactly (render farms)\n"
    "  tonemap IN.exr -o OUT.png exposure and tone mapping of render's PNG output, for any linear image\n"
    "  info SCENE [--json]       strands, points, segments, bounds, materials, BVH statistics\n"
    "  devices [--json]          list OpenCL platforms and devices (indices for --device)\n"
    "  bench [...]               BVH build and ray throughput benchmark (validated hits)\n"
    "  converge SCENE --reference REF.exr --configs ... --spp 1,2,4,...\n"
    "                            error against render time per configuration (CSV + log-log plot)\n"
    "  fiber eval|sample|furnace|afs ...   query the fibre scattering models\n"
    "  help [COMMAND]            this text, or a command's complete options (same as COMMAND --help)\n"
    "  version                   print the version\n"
    "\n"
    "SCENE is a .gltf/.glb, a Cem Yuksel .hair, a USC-HairSalon .data file, or builtin:strand /\n"
    "builtin:ball (the paper's Fig. 5 strand and Fig. 6 ball).\n"
    "\n"
    "exit codes: 0 ok, 2 bad input or usage, 3 device or runtime failure,\n"
    "            128+N interrupted by signal N (render saves its checkpoint and images first).\n"
    "environment: HAIRTRACE_KERNEL_DIR (load kernels from a folder instead of the embedded\n"
    "copies), HAIRTRACE_CACHE_DIR (compiled kernels and the image formats this build writes, 'off' to\n"
    "disable).\n";

using Command = int (*)(const std::vector<std::string>&);

// fiber_main is overloaded (the tests pass streams); this picks the command's.
int fiber_command(const std::vector<std::string>& args) { return fiber_main(args); }

const std::vector<std::pair<std::string, Command>> kCommands = {
    {"render", cmd_render}, {"merge", cmd_merge},     {"info", cmd_info},   {"devices", cmd_devices},
    {"bench", bench_main}, {"converge", cmd_converge}, {"fiber", fiber_command},
    {"tonemap", cmd_tonemap},
};

Command find_command(const std::string& name) {
    for (const auto& [n, c] : kCommands)
        if (n == name) return c;
    return nullptr;
}

UsageError unknown_command(const std::string& name) {
    std::vector<std::string> names = {"help", "version"};
    for (const auto& c : kCommands) names.push_back(c.first);
    return UsageError("unknown command '" + name + "'" + did_you_mean(name, names) + "; hairtrace --help lists them");
}

int dispatch(const std::vector<std::string>& argv) {
    if (argv.empty()) {
        std::fputs(kTopHelp, stderr);
        return kExitUsage;
    }
    const std::string& name = argv[0];
    std::vector<std::string> rest(argv.begin() + 1, argv.end());
    if (Command c = find_command(name)) return c(rest);
    if (name == "version" || name == "--version") {
        std::printf("hairtrace %s\n", HT_VERSION);
        return kExitOk;
    }
    if (name == "help" || name == "--help" || name == "-h") {
        if (rest.empty()) {
            std::fputs(kTopHelp, stdout);
            return kExitOk;
        }
        if (Command c = find_command(rest[0])) return c({"--help"});
        throw unknown_command(rest[0]);
    }
    throw unknown_command(name);
}

int fail(const std::string& message, int code) {
    std::fprintf(stderr, "hairtrace: %s\n", message.c_str());
    return code;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return dispatch(std::vector<std::string>(argv + 1, argv + argc));
    } catch (const cl::Error& e) {
        return fail(std::string("OpenCL error in ") + e.what() + ": " + cl_error_name(e.err()), kExitRuntime);
    } catch (const std::bad_alloc&) {
        return fail("out of host memory", kExitRuntime);
    } catch (const std::exception& e) {
        return fail(e.what(), exit_code_for(e));
    }
}
