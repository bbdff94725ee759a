// Bytes a scene holds, for the server's memory budget (util/memory_budget.h):
// its CPU copy after import (geometry, decoded images, environment) and
// what GpuScene::Upload will allocate for it (vertex and index buffers,
// textures with their mip chains). Counted, nothing allocated.
#pragma once

#include <cstdint>

#include "scene/scene.h"

namespace gistream {

struct SceneBytes {
  uint64_t cpu = 0;
  uint64_t gpu = 0;
  uint64_t total() const { return cpu + gpu; }
};

SceneBytes CountSceneBytes(const Scene& scene);

}  // namespace gistream
