// The path tracer's copy of the scene: world-space triangles in an Embree 3
// BVH, with per-triangle shading data and the emissive triangles' power
// distribution. Independent of the rasterizing solvers' code so that it can
// judge them.
//
// A scene without deforming meshes is one geometry in a single-level,
// high-quality BVH. A scene with them is two geometries in Embree's
// two-level BVH (scene build quality LOW): the rigid triangles (built
// once, SAH) and the deforming meshes' triangles (build quality REFIT), so
// that a deformation refits the second alone (Refit) instead of rebuilding.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "scene/state/scene_state.h"
#include "solvers/pathtrace/refit_quality.h"
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

// What SceneBvh::Refit did.
enum class RefitResult {
  kRefit,           // the deforming triangles moved, their BVH refit
  kTopology,        // not refit: another set of non-degenerate triangles
  kQuality,         // not refit: the refit tree's cost grew too much
  kNothingDeforms,  // not refit: the scene has no deforming mesh
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

  // After a deformation (and nothing else that moves triangles): the
  // deforming meshes' triangles at `state`'s pose, their BVH refit (same
  // topology, every box recomputed bottom-up from the posed triangles by
  // Embree's refit builder) and the emitter table updated. Anything but
  // kRefit leaves the BVH as it was, for the caller to rebuild: kTopology
  // when the posed mesh has another set of non-degenerate triangles than
  // the built one, kQuality when the shadow tree's cost grew beyond
  // RefitQuality::kMaxCostGrowth (refit_quality.h).
  RefitResult Refit(const SceneState& state);
  // The shadow tree's cost growth the last Refit measured (1 before any).
  double refit_growth() const { return refit_growth_; }

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
  // Embree geometry ids.
  static constexpr unsigned kRigid = 0;
  static constexpr unsigned kDeforming = 1;

  SceneBvh() = default;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<Triangle> triangles_;
  // Per Embree geometry: its primitives' indices into triangles_.
  std::array<std::vector<uint32_t>, 2> geometry_triangles_;
  // Per deforming triangle: its index among the deforming nodes' triangles
  // (degenerate ones included), in node, primitive and index order: a
  // refit must find the same ones non-degenerate.
  std::vector<uint32_t> deforming_source_;
  Bounds rigid_bounds_;   // of the rigid triangles, for scene_scale
  RefitQuality quality_;  // over the deforming triangles at the build
  double refit_growth_ = 1.0;
  std::vector<uint32_t> emitters_;
  std::vector<double> emitter_cdf_;
  double emitter_total_ = 0.0;
  float scale_ = 1.0f;
};

}  // namespace gistream::pathtrace
