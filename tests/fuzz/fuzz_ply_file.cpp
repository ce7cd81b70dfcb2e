// libFuzzer target: bytes -> PLY polylines loader (through load_scene).
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    ht_fuzz::fuzz_file("input.ply", data, size);
    return 0;
}
