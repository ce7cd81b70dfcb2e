// libFuzzer target: bytes -> Cem Yuksel .hair loader (through load_scene, as `hairtrace` loads it).
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    ht_fuzz::fuzz_file("input.hair", data, size);
    return 0;
}
