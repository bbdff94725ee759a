// glTF import (server/scene/gltf_*): any bytes either import or answer a
// status; an imported scene has consistent geometry (indices in range, one
// normal per position), finite world matrices and magnitudes in the limits
// (scene/magnitude_limits.h). Limits are small so that each input is quick.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz/fuzz_check.h"
#include "scene/gltf/gltf_import.h"
#include "scene/gpu/scene_memory.h"
#include "scene/state/scene_state.h"

using namespace gistream;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ImportOptions options;
  options.name = "fuzz";
  options.limits.max_scene_bytes = 1 << 20;
  options.limits.max_triangles = 100'000;
  options.limits.max_image_pixels = 1 << 20;
  options.limits.max_total_image_pixels = 1 << 21;
  options.limits.max_image_dimension = 4096;
  options.limits.max_nodes = 10'000;
  absl::StatusOr<Scene> scene = ImportGltf(std::span<const uint8_t>(data, size), options);
  if (!scene.ok()) {
    FUZZ_CHECK(!scene.status().message().empty());
    return 0;
  }
  for (const Mesh& mesh : scene->meshes) {
    for (const Primitive& p : mesh.primitives) {
      FUZZ_CHECK(p.indices.size() % 3 == 0);
      FUZZ_CHECK(p.normals.empty() || p.normals.size() == p.positions.size());
      for (uint32_t i : p.indices) FUZZ_CHECK(i < p.positions.size());
      for (const glm::vec3& v : p.positions) {
        FUZZ_CHECK(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
      }
    }
  }
  for (const Image& image : scene->images) {
    FUZZ_CHECK(uint64_t(image.width) * uint64_t(image.height) <= options.limits.max_image_pixels);
    FUZZ_CHECK(image.pixels8.size() + image.pixelsf.size() ==
               size_t(image.width) * size_t(image.height) * 4);
  }
  (void)CountSceneBytes(*scene);
  SceneState state(std::make_shared<const Scene>(*std::move(scene)));
  FUZZ_CHECK(state.CheckMagnitudes("").ok());
  for (const glm::mat4& m : state.world()) {
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) FUZZ_CHECK(std::isfinite(m[c][r]));
    }
  }
  return 0;
}
