// tinygltf's implementation, compiled once. See scene/gltf/tinygltf.h for the
// switches; external buffers reach tinygltf only through the FsCallbacks that
// gltf_parse.cpp supplies.

// tinygltf 2.7's (unused) writer names std::ofstream even with TINYGLTF_NO_FS,
// which drops the include.
#include <fstream>

#define TINYGLTF_IMPLEMENTATION
#include "scene/gltf/tinygltf.h"
