// The path tracer's copy of the scene: world-space triangles in an Embree 3
// BVH, with per-triangle shading data and the emissive triangles' power
// distribution. Independent of the rasterizing solvers' code so that it can
// judge them.
#pragma once

#include <memory>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "scene/scene_state.h"
#include "util/status.h"

namespace gistream::pathtrace {

struct Triangle {
  glm::vec3 p0, e1, e2;  // p0 and edges, world space
  glm::vec3 n0, n1, n2;  // vertex normals, world space
  glm::vec2 uv0, uv1, uv2;
  glm::vec3 normal;  // unit geometric normal, oriented like the vertex normals
  float area = 0.0f;
  int material = -1;  // -1: default material
  int emitter = -1;   // index into `emitters` or -1
  // glTF doubleSided material: the back face is a surface with the flipped
  // normal, so an emitter emits from both faces (twice the power).
  bool double_sided = false;
};

struct Hit {
  bool hit = false;
  float t = 0.0f;
  uint32_t triangle = 0;
  float u = 0.0f, v = 0.0f;  // barycentrics of p1 and p2
};

class SceneBvh {
 public:
  // Builds from the current state. Fails only if Embree cannot start.
  static absl::StatusOr<std::unique_ptr<SceneBvh>> Build(const SceneState& state);
  ~SceneBvh();
  SceneBvh(const SceneBvh&) = delete;
  SceneBvh& operator=(const SceneBvh&) = delete;

  // Rebuilds the emitter table after an emission change (no BVH rebuild).
  void UpdateEmitters(const SceneState& state);

  Hit Intersect(const glm::vec3& origin, const glm::vec3& dir, float tmax) const;
  bool Occluded(const glm::vec3& origin, const glm::vec3& dir, float tmax) const;

  const std::vector<Triangle>& triangles() const { return triangles_; }
  const std::vector<uint32_t>& emitters() const { return emitters_; }  // triangle ids
  // Emitter selection by luminous power (lum(L_e) x area x faces, 2 for a
  // double-sided emitter).
  const std::vector<double>& emitter_cdf() const { return emitter_cdf_; }
  double emitter_total() const { return emitter_total_; }
  float scene_scale() const { return scale_; }  // bounds diagonal

 private:
  SceneBvh() = default;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<Triangle> triangles_;
  std::vector<uint32_t> emitters_;
  std::vector<double> emitter_cdf_;
  double emitter_total_ = 0.0;
  float scale_ = 1.0f;
};

}  // namespace gistream::pathtrace
