// glTF 2.0 import (tinygltf with its file system and image decoding switched
// off). Every URI, accessor, buffer view, index and the node graph are
// validated with overflow-safe arithmetic before a Scene is returned.
#pragma once

#include <filesystem>
#include <span>
#include <string>

#include "scene/gltf/import_limits.h"
#include "scene/gltf/import_memory.h"
#include "scene/gltf/load_control.h"
#include "scene/scene.h"
#include "util/status.h"

namespace gistream {

struct ImportOptions {
  ImportLimits limits;
  // Directory external (non data:) URIs may name files in. Empty: external
  // URIs are refused. Absolute paths and ".." are refused always.
  std::filesystem::path base_dir;
  std::string name;  // scene name for messages and Scene::name
  // When set: the glTF bytes, external files and decoded images are
  // reserved here before they are parsed or decoded (held by the caller
  // until the scene itself is reserved).
  ImportMemory* memory = nullptr;
  // When set: the proxies' time budget and the caller's stop, checked
  // between stages and slices (scene/gltf/load_control.h); `proxy_report` gets
  // what the proxies got done.
  const LoadControl* control = nullptr;
  ProxyReport* proxy_report = nullptr;
};

// Imports a .glb or a .gltf (JSON) held in memory. Errors:
// INVALID_ARGUMENT naming the field ("accessors[3].count: ..."), or
// RESOURCE_EXHAUSTED when a limit is exceeded.
absl::StatusOr<Scene> ImportGltf(std::span<const uint8_t> bytes, const ImportOptions& options);

// Reads `name` (a scene name like "cornell_box", or "cornell_box.glb") from
// `scene_dir`, trying .glb then .gltf, and imports it with external URIs
// resolved inside `scene_dir`. NOT_FOUND when no such scene.
absl::StatusOr<Scene> ImportSceneByName(const std::filesystem::path& scene_dir,
                                        const std::string& name, const ImportLimits& limits,
                                        ImportMemory* memory = nullptr,
                                        const LoadControl* control = nullptr,
                                        ProxyReport* proxy_report = nullptr);

// Resolves a relative URI against `base_dir`, refusing absolute paths, "..",
// and anything that leaves `base_dir` through symlinks.
absl::StatusOr<std::filesystem::path> ResolveSceneUri(const std::filesystem::path& base_dir,
                                                      const std::string& uri,
                                                      const std::string& field);

}  // namespace gistream
