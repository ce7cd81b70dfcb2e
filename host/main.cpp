#include "bench/bench.h"
#include "cl/device.h"

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

int main(int argc, char** argv) {
    try {
        // `hairtrace bench ...`: the full CLI wires the scene source to ht::load_scene.
        if (argc > 1 && std::string(argv[1]) == "bench")
            return ht::bench_main(std::vector<std::string>(argv + 2, argv + argc));
        for (auto& d : ht::list_devices()) std::printf("%d %s\n", d.index, d.name.c_str());
        return 0;
    } catch (const ht::DeviceError& e) {
        std::fprintf(stderr, "hairtrace: %s\n", e.what());
        return 3;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "hairtrace: %s\n", e.what());
        return 1;
    }
}
