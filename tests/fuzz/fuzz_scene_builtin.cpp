// libFuzzer target: text -> "builtin:" + text through load_scene (spec parsing: NAME?k=v&k=v,
// integer and float parsing, size limits, generation).
#include <string>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    // Specs come from the command line or a glTF string: no embedded NULs in practice, but they
    // must not break anything either, so pass the bytes through unchanged.
    const std::string spec(reinterpret_cast<const char*>(data), size);
    ht_fuzz::load_and_judge("builtin:" + spec);
    return 0;
}
