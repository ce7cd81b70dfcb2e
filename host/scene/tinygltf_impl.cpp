// tinygltf's implementation, compiled exactly once (header-only library).
#define TINYGLTF_IMPLEMENTATION
#include "scene/tinygltf_config.h"
