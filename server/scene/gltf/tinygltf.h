// The one way gistream includes tinygltf: with its file system access, its
// image decoding (stb) and its external image loading compiled out. Every
// translation unit must see the same switches, so include this header, never
// <tiny_gltf.h> directly.
#pragma once

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NO_FS

#include <tiny_gltf.h>
