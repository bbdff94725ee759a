// Bytes a scene holds, for the server's memory budget (util/memory_budget.h):
// its CPU copy after import (geometry, decoded images, environment) and
// what GpuScene::Upload will allocate for it (vertex and index buffers,
// textures with their mip chains), and the G-buffer's draw list of it.
// Counted, nothing allocated.
#pragma once

#include <cstdint>

#include "scene/scene.h"

namespace gistream {

struct SceneBytes {
  uint64_t cpu = 0;
  uint64_t gpu = 0;
  uint64_t total() const { return cpu + gpu; }
};

// A draw list's command (20 bytes) and record (80), scene/gpu/draw_list.h.
inline constexpr uint64_t kDrawListBytesPerDraw = 100;

SceneBytes CountSceneBytes(const Scene& scene);

}  // namespace gistream
