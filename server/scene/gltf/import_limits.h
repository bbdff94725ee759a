// Limits every scene import enforces before anything is allocated on the
// GPU. gistreamd exposes each one as a flag.
#pragma once

#include <cstdint>

namespace gistream {

struct ImportLimits {
  uint64_t max_scene_bytes = 256ull << 20;     // glb/gltf bytes, buffers included
  uint64_t max_triangles = 4'000'000;          // over all mesh instances
  uint64_t max_image_pixels = 8192ull * 8192;  // per image, width*height
  uint32_t max_image_dimension = 16384;        // per side
  uint32_t max_nodes = 100'000;
  // What a frame costs besides its triangles (issue 30): the primitives
  // drawn over all node instances (each a command in every pass's draw
  // list, 100 bytes per pass and view, and a walk on the CPU), and the
  // materials (the material table every pass binds).
  uint64_t max_draw_items = 262'144;
  uint32_t max_materials = 65'536;
  // All decoded images of a scene together: a small PNG can decode to the
  // per-image maximum, so the encoded size alone does not bound memory.
  uint64_t max_total_image_pixels = 4 * 8192ull * 8192;
};

}  // namespace gistream
