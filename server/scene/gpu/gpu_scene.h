// The GPU copy of a scene: one vertex and one index buffer for every
// primitive, a material table (SSBO), textures, and the draw list (one item
// per node instance of a primitive). Geometry is uploaded once; transforms
// and materials are refreshed from SceneState when they change. Lives on
// the render thread.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "gl/bindings.h"
#include "gl/buffers.h"
#include "gl/handle.h"
#include "gl/program.h"
#include "scene/gpu/gpu_deform.h"
#include "scene/state/scene_state.h"
#include "util/status.h"

namespace gistream {

// std430 layout of shaders/common/scene.glsl's Material.
struct GpuMaterial {
  glm::vec4 base_color;  // linear RGBA
  glm::vec4 emission;    // rgb: emitted radiance (nits), a: unused
  glm::ivec4 textures;   // x: base colour, y: emissive, w: metallic-roughness texture or -1;
                         // z: 1 when double-sided
  glm::vec4 pbr;         // x: metallic factor, y: roughness factor
  glm::vec4 specular;    // rgb: dielectric F0, a: dielectric F90 (Material)
  // KHR_texture_transform rows (Material's UvTransform u, v): base colour
  // 0-1, emissive 2-3, metallic-roughness 4-5.
  glm::vec4 uv_transform[6];
};
GS_STD430_MIRROR(GpuMaterial, 176);  // shaders/common/scene.glsl Material

struct DrawItem {
  uint32_t first_index = 0;
  uint32_t index_count = 0;
  int32_t base_vertex = 0;
  // The primitive's rest-pose vertices: base_vertex, unless the node
  // deforms (SceneState::Deforms) and draws its own posed copy.
  int32_t rest_vertex = 0;
  uint32_t vertex_count = 0;
  int material = -1;  // -1: default material
  int node = 0;
  int mesh = 0;
  int primitive = 0;
  // Its proxy levels (scene/proxies/proxy_levels.h): levels()[first_level ..
  // first_level + level_count), finest first.
  int first_level = 0;
  int level_count = 0;
  // Its cluster tree (scene/proxies/proxy_clusters.h): clusters()[first_cluster ..
  // first_cluster + cluster_count), root first; 0: none.
  int first_cluster = 0;
  int cluster_count = 0;
};

// One simplified level of a primitive in the index buffer (drawn with the
// item's base vertex) and its geometric error bound, local units.
struct DrawLevel {
  uint32_t first_index = 0;
  uint32_t index_count = 0;
  float error = 0.0f;
};

// One node of a primitive's cluster tree on the GPU: its local box, its
// full triangles (leaves only) and its simplified copy (index_count 0:
// none), both drawn with the item's base vertex; children are indices
// relative to the item's first cluster.
struct DrawCluster {
  Bounds bounds;
  DrawLevel full;
  DrawLevel level;
  int children[2] = {-1, -1};
};

// How a view-independent pass draws each item: called right before the
// item is drawn (it may set per-item uniforms), it returns the largest
// world-space geometric error the pass tolerates there; the coarsest proxy
// level within it is drawn, the full mesh when none is; < 0 skips the item.
using DrawFilter = std::function<float(const DrawItem& item, const glm::mat4& model)>;
// Per cluster of an item that has a tree (called after the item's
// DrawFilter, right before the node is drawn or opened): the world-space
// error tolerated within the node's world box `world`; < 0 skips the node.
using ClusterFilter = std::function<float(const Bounds& world)>;
// One draw of a walk (GpuScene::Walk): `range` of `item`'s indices (the
// full mesh, a proxy level, or a cluster node's copy or leaf) under `model`.
using DrawVisitor =
    std::function<void(const DrawItem& item, const glm::mat4& model, const DrawLevel& range)>;

// The textures a material samples (GpuScene's white 1x1 where it has
// none): draws with equal sets can share one binding.
struct MaterialTextures {
  GLuint base_color = 0;
  GLuint emissive = 0;
  GLuint metallic_roughness = 0;
  // Each texture's sampler object (its glTF sampler); 0 for the default
  // (repeat, trilinear: the texture's own parameters).
  GLuint base_color_sampler = 0;
  GLuint emissive_sampler = 0;
  GLuint metallic_roughness_sampler = 0;
  auto operator<=>(const MaterialTextures&) const = default;
};

class GpuScene {
 public:
  static absl::StatusOr<std::unique_ptr<GpuScene>> Upload(const SceneState& state);

  // Refreshes materials from the state (cheap; call after material changes).
  void UpdateMaterials(const SceneState& state);
  // Whether the scene has deforming node instances (gpu_deform.h), and
  // whether `state` changed their shape since they were last posed.
  bool deforms() const { return deform_ != nullptr; }
  bool DeformPending(const SceneState& state) const;
  // Re-poses the deforming node instances when DeformPending.
  void Deform(const SceneState& state);

  // Issues every draw with `program`: sets uModel, uNormalMatrix, uMaterial,
  // binds the material textures (units kBaseColorUnit, kEmissiveUnit,
  // kMetallicRoughnessUnit) when
  // `bind_textures`. Materials are bound as SSBO binding kMaterialBinding.
  // `instances` > 1 draws each item that many times (gl_InstanceID).
  // With `filter`, each item's level comes from it (see DrawFilter);
  // without, every item is drawn in full, as before proxies. With
  // `cluster_filter` too, an item with a cluster tree is drawn node by
  // node instead: from the root down, a node's copy where its error is
  // within the node's tolerance, else its children (leaves: in full).
  void Draw(gl::Program& program, const SceneState& state, bool bind_textures, int instances = 1,
            const DrawFilter* filter = nullptr,
            const ClusterFilter* cluster_filter = nullptr) const;
  // What Draw would draw, without drawing: `visit` gets each range in
  // Draw's order, the filters called as Draw calls them (a DrawList builds
  // its commands from this).
  void Walk(const SceneState& state, const DrawFilter* filter, const ClusterFilter* cluster_filter,
            const DrawVisitor& visit) const;

  const std::vector<DrawItem>& draws() const { return draws_; }
  const std::vector<DrawLevel>& levels() const { return levels_; }
  const std::vector<DrawCluster>& clusters() const { return clusters_; }
  // The coarsest of `item`'s levels whose error times `scale` is within
  // `tolerance` (world units); -1: the full mesh.
  int PickLevel(const DrawItem& item, float scale, float tolerance) const;
  // Bounds of what Draw draws under the current transforms (the 8 corners
  // of each primitive's box: never smaller than the truth). Unlike
  // Scene::bounds, follows moved nodes.
  Bounds WorldBounds(const SceneState& state) const;
  uint64_t gpu_bytes() const { return gpu_bytes_; }
  // The environment map (equirectangular RGBA32F, one level, texels read
  // with texelFetch) for the view's background; 0 when the scene has none.
  GLuint environment_texture() const { return environment_.id(); }
  // The interleaved vertex buffer (position, normal, uv: 8 floats each).
  GLuint vertex_buffer() const { return vertices_.id(); }
  // The vertex array every draw of the scene uses; a draw list (scene/
  // draw_list.h) binds its records to kDrawRecordBufferBinding and enables
  // kDrawModelAttrib.. and kDrawTagAttrib while it draws.
  GLuint vertex_array() const { return vao_.id(); }
  // The material table as Draw binds it (SSBO kMaterialBinding); `item`'s
  // material index in it (the default material last), and its textures
  // and their binding (units kBaseColorUnit, kEmissiveUnit,
  // kMetallicRoughnessUnit).
  void BindMaterials() const;
  static int MaterialIndex(const SceneState& state, const DrawItem& item);
  MaterialTextures TexturesOf(const SceneState& state, const DrawItem& item) const;
  static void BindTextures(const MaterialTextures& textures);
  // Units kBaseColorUnit.. back to their textures' own parameters (other
  // passes use those unit numbers): Draw and a draw list call it when done.
  static void UnbindSamplers();

  static constexpr GLuint kMaterialBinding = GS_BINDING_MATERIALS;
  static constexpr GLuint kBaseColorUnit = GS_UNIT_BASE_COLOR;
  static constexpr GLuint kEmissiveUnit = GS_UNIT_EMISSIVE;
  static constexpr GLuint kMetallicRoughnessUnit = GS_UNIT_METALLIC_ROUGHNESS;
  // shaders/common/scene_vertex.glsl's aDrawModel (4 locations), aDrawInfo.
  static constexpr GLuint kDrawModelAttrib = 3;
  static constexpr GLuint kDrawTagAttrib = 7;
  static constexpr GLuint kDrawRecordBufferBinding = 1;

 private:
  // Upload's steps. The vertex and index buffers: every primitive once,
  // then its proxy levels and cluster trees, a deforming instance's own
  // vertex copy; one DrawItem per instance and primitive.
  void UploadGeometry(const SceneState& state);
  // (first, count) per mesh and primitive.
  using MeshRanges = std::vector<std::vector<std::pair<int, int>>>;
  MeshRanges AppendProxyLevels(const Scene& scene, std::vector<uint32_t>& indices);
  MeshRanges AppendClusters(const Scene& scene, std::vector<uint32_t>& indices);
  // The vertex layout, and a draw list's per-instance records.
  void CreateVertexArray();
  // One texture per scene image, the 1x1 white fallback, the environment;
  // a sampler object per distinct non-default glTF sampler the materials use.
  void UploadTextures(const Scene& scene);
  GLuint SamplerOf(const TextureSampler& sampler) const;

  gl::VertexArray vao_;
  gl::Buffer vertices_;
  gl::Buffer indices_;
  gl::Buffer materials_;
  std::vector<gl::Texture> textures_;               // per scene image
  gl::Texture white_;                               // 1x1 fallback
  std::map<TextureSampler, gl::Sampler> samplers_;  // the non-default ones
  gl::Texture environment_;                         // empty when the scene has none
  std::vector<DrawItem> draws_;
  std::vector<DrawLevel> levels_;
  std::vector<DrawCluster> clusters_;
  std::unique_ptr<GpuDeform> deform_;  // null when nothing deforms
  uint64_t deformed_version_ = 0;      // the state version deform_ last posed
  uint64_t gpu_bytes_ = 0;
};

}  // namespace gistream
