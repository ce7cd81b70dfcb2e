// The one way to include tinygltf in this project.  Debian's tinygltf would include stb_image
// for texture decoding, which is not installed and not needed: hair scenes take no textures, so
// image decoding and writing are compiled out and images are skipped (see gltf.cpp).
#pragma once

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>
