// libFuzzer target: bytes -> glTF loader, parse AND scene building (node hierarchy, accessors,
// materials, cameras, lights, hairtrace_builtin), through load_scene.
//
// One target covers both container forms: an input starting with the GLB magic "glTF" is saved
// as .glb (binary container path: load_glb's header checks, then tinygltf), anything else as
// .gltf (JSON text).  Content-based dispatch lets mutations move between the two, and a GLB seed
// whose JSON chunk is mutated still reaches the JSON parser.  External buffer URIs resolve
// relative to the private scratch directory.
#include <cstring>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    ht_fuzz::fuzz_file(glb ? "input.glb" : "input.gltf", data, size);
    return 0;
}
