// The one way to include tinygltf in this project.  Debian's tinygltf would include stb_image
// for texture decoding, which is not installed and not wanted: base colour textures are decoded
// by OpenImageIO (texture_image.h), like every other image the program reads, so tinygltf's
// image decoding and writing stay compiled out and images reach the loader undecoded
// (gltf_texture.h).
#pragma once

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>
