// The scene side of the element hierarchy: builds hierarchy::Elements from
// a SceneState's draw list, with the per-mesh preprocessing cached
// (create_surfels and create_hierarchy run once per mesh primitive), and
// keeps what the display and the illumination need per leaf: the mesh
// vertex in world space, the triangle indices, the diffuse albedo. Meshes
// with edges longer than the scene-sized limit are subdivided first
// (hierarchy/subdivide.h), so a leaf is a vertex of that finer mesh.
#pragma once

#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "gl/stage_timer.h"
#include "scene/gpu_scene.h"
#include "solvers/hierarchy/elements.h"
#include "solvers/hierarchy/subdivide.h"

namespace gistream {

class SceneElements {
 public:
  bool built() const { return built_; }

  // create_surfels + create_hierarchy (timed as two stages, CPU), then
  // the forest layout. Once per solver: the draw list never changes.
  void Build(const SceneState& state, const GpuScene& gpu, gl::StageTimer& timer);
  // A deformation: the deforming instances' leaves (discs) re-made from
  // their posed meshes (SceneState::NodeMesh, subdivided as at Build);
  // the hierarchy itself remains untouched, as Section 4.2.1 updates
  // deforming models: same leaves, same clusters, same node ids. Call
  // UpdateGeometry next (it recomputes the clusters bottom-up).
  void UpdatePose(const SceneState& state);
  // update_elements: world transforms of every instance (Section 4.2.1).
  void UpdateGeometry(const SceneState& state);
  // Per-leaf albedo (base colour x texture at the vertex uv), linear.
  void UpdateAlbedo(const SceneState& state);

  const hierarchy::Elements& elements() const { return elements_; }
  const std::vector<glm::vec3>& vertex_world() const { return vertex_world_; }
  const std::vector<uint32_t>& triangles() const { return triangles_; }
  const std::vector<glm::vec3>& albedo() const { return albedo_; }

 private:
  struct InstanceSource {
    int node = 0, mesh = 0, primitive = 0;
    // The mesh primitive with its long edges subdivided
    // (hierarchy/subdivide.h): the leaves are its vertices.
    std::shared_ptr<const Primitive> elements;
  };
  // A deforming node's primitive as Build subdivided it: UpdatePose
  // repeats that subdivision on the pose and keeps the tree.
  struct DeformingSource {
    int node = 0, primitive = 0;
    std::shared_ptr<const Primitive> built;  // the subdivided mesh at Build's pose
    hierarchy::Midpoints midpoints;
    std::shared_ptr<const hierarchy::ElementMesh> mesh;  // current surfels, Build's tree
  };
  bool built_ = false;
  std::vector<InstanceSource> sources_;
  std::vector<DeformingSource> deforming_;
  hierarchy::Elements elements_;
  std::vector<glm::vec3> vertex_world_;  // per leaf
  std::vector<uint32_t> triangles_;      // leaf ids, 3 per triangle
  std::vector<glm::vec3> albedo_;        // per leaf
};

}  // namespace gistream
