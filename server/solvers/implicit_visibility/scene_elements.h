// The scene side of the element hierarchy: builds hierarchy::Elements from
// a SceneState's draw list, with the per-mesh preprocessing cached
// (create_surfels and create_hierarchy run once per mesh primitive), and
// keeps what the display and the illumination need per leaf: the mesh
// vertex in world space, the triangle indices, the diffuse albedo. Meshes
// with edges longer than the scene-sized limit are subdivided first
// (hierarchy/subdivide.h), so a leaf is a vertex of that finer mesh.
// Primitives with proxy levels make their elements from one
// (hierarchy/element_source.h) unless `full_detail`; the display then
// draws the full mesh, each vertex's irradiance interpolated from the
// nearest element-mesh triangle's leaves (hierarchy/vertex_transfer.h).
#pragma once

#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "gl/stage_timer.h"
#include "scene/gpu/gpu_scene.h"
#include "solvers/hierarchy/elements.h"
#include "solvers/hierarchy/subdivide.h"
#include "solvers/shading/ggx.h"

namespace gistream {

class SceneElements {
 public:
  bool built() const { return built_; }

  // create_surfels + create_hierarchy (timed as two stages, CPU), then
  // the forest layout. Once per solver: the draw list never changes.
  // `full_detail`: every element from the full mesh, as before proxies.
  void Build(const SceneState& state, const GpuScene& gpu, gl::StageTimer& timer,
             bool full_detail = false);
  // A deformation: the deforming instances' leaves (discs) re-made from
  // their posed meshes (SceneState::NodeMesh, subdivided as at Build);
  // the hierarchy itself remains untouched, as Section 4.2.1 updates
  // deforming models: same leaves, same clusters, same node ids. Call
  // UpdateGeometry next (it recomputes the clusters bottom-up).
  void UpdatePose(const SceneState& state);
  // update_elements: world transforms of every instance (Section 4.2.1).
  void UpdateGeometry(const SceneState& state);
  // Per-leaf albedo (base colour x texture at the vertex uv, linear; a
  // glossy material's white-sky albedo of it, solvers/brdf_albedo.h).
  void UpdateAlbedo(const SceneState& state);

  const hierarchy::Elements& elements() const { return elements_; }
  const std::vector<glm::vec3>& albedo() const { return albedo_; }
  // Per-leaf BRDF (base colour as albedo() before the white-sky albedo,
  // metallic-roughness, F0/F90), from UpdateAlbedo; Lambertian for a leaf
  // without a material.
  const std::vector<shading::Brdf>& brdf() const { return brdf_; }
  // Leaves made from a proxy level (0 with full detail or no proxies).
  int proxy_leaves() const { return proxy_leaves_; }

  // The display mesh: per display vertex its world position, the three
  // leaves whose irradiance it interpolates and their weights (a leaf
  // itself: (leaf, leaf, leaf), (1, 0, 0)); triangles over display
  // vertices.
  const std::vector<glm::vec3>& vertex_world() const { return vertex_world_; }
  const std::vector<glm::uvec3>& vertex_leaves() const { return vertex_leaves_; }
  const std::vector<glm::vec3>& vertex_weights() const { return vertex_weights_; }
  const std::vector<uint32_t>& triangles() const { return triangles_; }

 private:
  struct InstanceSource {
    int node = 0, mesh = 0, primitive = 0;
    // The mesh primitive (or its proxy level) with its long edges
    // subdivided (hierarchy/subdivide.h): the leaves are its vertices.
    std::shared_ptr<const Primitive> elements;
    // What the display draws: `elements` itself, or the full mesh
    // (subdivided alike) when the elements come from a proxy.
    std::shared_ptr<const Primitive> display;
    int display_offset = 0;  // its first display vertex
  };
  // A deforming node's primitive as Build subdivided it: UpdatePose
  // repeats that subdivision on the pose and keeps the tree.
  struct DeformingSource {
    int node = 0, primitive = 0;
    std::shared_ptr<const Primitive> built;  // the subdivided mesh at Build's pose
    hierarchy::Midpoints midpoints;
    std::shared_ptr<const hierarchy::ElementMesh> mesh;  // current surfels, Build's tree
  };
  // Build's steps (Keyed: the element meshes per mesh and primitive).
  struct Keyed;
  // Stage create_surfels: each key's elements (its proxy level or the
  // full mesh, long edges subdivided), surfels and display transfer.
  static void CreateSurfels(const SceneState& state, const GpuScene& gpu, bool full_detail,
                            Keyed& keyed);
  // The display's triangles and each vertex's leaves and weights.
  void BuildDisplayMesh(const Keyed& keyed, const std::vector<size_t>& key_of_source);

  bool built_ = false;
  std::vector<InstanceSource> sources_;
  std::vector<DeformingSource> deforming_;
  hierarchy::Elements elements_;
  std::vector<glm::vec3> vertex_world_;    // per display vertex
  std::vector<glm::uvec3> vertex_leaves_;  // per display vertex
  std::vector<glm::vec3> vertex_weights_;  // per display vertex
  std::vector<uint32_t> triangles_;        // display vertex ids, 3 per triangle
  std::vector<glm::vec3> albedo_;          // per leaf
  std::vector<shading::Brdf> brdf_;        // per leaf
  int proxy_leaves_ = 0;
};

}  // namespace gistream
