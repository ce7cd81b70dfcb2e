// libFuzzer target: bytes -> OBJ line-element loader (tinyobjloader) (through load_scene).
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    ht_fuzz::fuzz_file("input.obj", data, size);
    return 0;
}
