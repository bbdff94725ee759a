// LoadScene's first step, on the caller's thread: the glTF (by name from the
// scene directory, or uploaded bytes) parsed and validated, and the
// environment map read and decoded, before anything reaches the GPU. What
// it reads and decodes is reserved in `transient` first
// (scene/gltf/import_memory.h). The proxies stop at `max_load_time` (the scene
// loads without the rest, `proxies` says how much); the source's stop ends
// it between stages and slices.
#pragma once

#include <chrono>
#include <filesystem>

#include "scene/gltf/import_limits.h"
#include "scene/gltf/import_memory.h"
#include "scene/gltf/load_control.h"
#include "scene/scene.h"
#include "engine/engine.h"
#include "util/status.h"

namespace gistream {

struct ImportedScene {
  Scene scene;
  ProxyReport proxies;
};

absl::StatusOr<ImportedScene> ImportSceneSource(const SceneSource& source,
                                                const std::filesystem::path& scene_dir,
                                                const ImportLimits& limits,
                                                std::chrono::milliseconds max_load_time,
                                                ImportMemory& transient);

}  // namespace gistream
