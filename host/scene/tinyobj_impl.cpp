// tinyobjloader's implementation, compiled exactly once (header-only use of Debian's
// libtinyobjloader-dev, so the fuzz build instruments it like the rest of the loaders).
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
