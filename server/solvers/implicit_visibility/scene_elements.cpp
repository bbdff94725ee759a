#include "solvers/implicit_visibility/scene_elements.h"

#include <algorithm>
#include <cmath>

#include "scene/texture_lookup.h"
#include "solvers/brdf_albedo.h"
#include "solvers/hierarchy/element_source.h"
#include "solvers/hierarchy/subdivide.h"
#include "solvers/hierarchy/vertex_transfer.h"
#include "util/parallel_for.h"

namespace gistream {

// Build's element meshes, one per key: (mesh, primitive) in first-use
// order, a deforming node's instance keyed (-1 - node, primitive) (its
// elements follow its posed mesh, SceneState::NodeMesh, shared with no
// other instance).
struct SceneElements::Keyed {
  std::vector<std::pair<int, int>> keys;
  std::vector<int> key_mesh;  // the scene mesh of each key
  std::vector<std::shared_ptr<hierarchy::ElementMesh>> meshes;
  std::vector<std::shared_ptr<const Primitive>> primitives;  // the elements' (subdivided)
  std::vector<std::shared_ptr<const Primitive>> displays;    // what the display draws
  std::vector<hierarchy::VertexTransfer> transfers;          // display onto elements
  std::vector<hierarchy::Midpoints> midpoints;

  static std::pair<int, int> KeyOf(const SceneState& state, const DrawItem& d) {
    return std::make_pair(state.Deforms(size_t(d.node)) ? -1 - d.node : d.mesh, d.primitive);
  }
  const Primitive& PrimitiveOf(const SceneState& state, size_t k) const {
    const size_t p = size_t(keys[k].second);
    return keys[k].first < 0 ? state.NodeMesh(size_t(-1 - keys[k].first)).primitives[p]
                             : state.scene().meshes[size_t(keys[k].first)].primitives[p];
  }
  size_t Find(const std::pair<int, int>& key) const {
    return size_t(std::find(keys.begin(), keys.end(), key) - keys.begin());
  }
};

void SceneElements::Build(const SceneState& state, const GpuScene& gpu, gl::StageTimer& timer,
                          bool full_detail) {
  Keyed keyed;
  sources_.clear();
  for (const DrawItem& d : gpu.draws()) {
    sources_.push_back({d.node, d.mesh, d.primitive, nullptr, nullptr, 0});
    if (keyed.Find(Keyed::KeyOf(state, d)) == keyed.keys.size()) {
      keyed.keys.push_back(Keyed::KeyOf(state, d));
      keyed.key_mesh.push_back(d.mesh);
    }
  }
  {
    gl::StageTimer::Scope stage(timer, "create_surfels", /*cpu_stage=*/true);
    CreateSurfels(state, gpu, full_detail, keyed);
  }
  {
    gl::StageTimer::Scope stage(timer, "create_hierarchy", /*cpu_stage=*/true);
    ParallelFor(keyed.keys.size(), 1, [&](size_t k) {
      keyed.meshes[k]->tree = hierarchy::CreateHierarchy(keyed.meshes[k]->surfels);
    });
  }
  std::vector<hierarchy::ElementInstance> instances;
  std::vector<size_t> key_of_source(sources_.size());
  for (size_t i = 0; i < sources_.size(); ++i) {
    const size_t k = keyed.Find(Keyed::KeyOf(state, gpu.draws()[i]));
    instances.push_back({keyed.meshes[k], 0, {}});
    sources_[i].elements = keyed.primitives[k];
    sources_[i].display = keyed.displays[k];
    key_of_source[i] = k;
  }
  deforming_.clear();
  for (size_t k = 0; k < keyed.keys.size(); ++k) {
    if (keyed.keys[k].first >= 0) continue;
    deforming_.push_back({-1 - keyed.keys[k].first, keyed.keys[k].second, keyed.primitives[k],
                          std::move(keyed.midpoints[k]), keyed.meshes[k]});
  }
  elements_ = hierarchy::Elements(std::move(instances));
  BuildDisplayMesh(keyed, key_of_source);
  built_ = true;
}

void SceneElements::CreateSurfels(const SceneState& state, const GpuScene& gpu, bool full_detail,
                                  Keyed& keyed) {
  const size_t count = keyed.keys.size();
  keyed.meshes.resize(count);
  keyed.primitives.resize(count);
  keyed.displays.resize(count);
  keyed.transfers.resize(count);
  keyed.midpoints.resize(count);
  std::vector<float> max_edge(count);
  std::vector<int> level(count, -1);
  for (size_t k = 0; k < count; ++k) {
    max_edge[k] = hierarchy::LocalMaxEdge(state, gpu, keyed.key_mesh[k], keyed.keys[k].second);
    // A deforming primitive has no proxies (its pose would void the bound).
    if (keyed.keys[k].first >= 0)
      level[k] = hierarchy::ElementLevel(keyed.PrimitiveOf(state, k), max_edge[k], full_detail);
  }
  ParallelFor(count, 1, [&](size_t k) {
    const Primitive& full = keyed.PrimitiveOf(state, k);
    if (level[k] < 0) {
      keyed.primitives[k] = std::make_shared<const Primitive>(
          hierarchy::SubdivideLongEdges(full, max_edge[k], &keyed.midpoints[k]));
      keyed.displays[k] = keyed.primitives[k];
    } else {
      keyed.primitives[k] = std::make_shared<const Primitive>(hierarchy::SubdivideLongEdges(
          hierarchy::ProxyLevelMesh(full, level[k]), max_edge[k], &keyed.midpoints[k]));
      keyed.displays[k] = std::make_shared<const Primitive>(
          hierarchy::SubdivideLongEdges(hierarchy::SurfaceOf(full), max_edge[k]));
    }
    keyed.meshes[k] = std::make_shared<hierarchy::ElementMesh>();
    keyed.meshes[k]->surfels = hierarchy::CreateSurfels(*keyed.primitives[k]);
  });
  // The full mesh's vertices onto the proxy's triangles, once per key
  // (each a ParallelFor of its own).
  for (size_t k = 0; k < count; ++k) {
    if (keyed.displays[k] != keyed.primitives[k])
      keyed.transfers[k] = hierarchy::TransferVertices(*keyed.displays[k], *keyed.primitives[k]);
  }
}

void SceneElements::BuildDisplayMesh(const Keyed& keyed, const std::vector<size_t>& key_of_source) {
  // The display mesh: a leaf per vertex where the elements are the full
  // mesh, else the full mesh's vertices with their transfer.
  triangles_.clear();
  vertex_leaves_.clear();
  vertex_weights_.clear();
  proxy_leaves_ = 0;
  for (size_t i = 0; i < sources_.size(); ++i) {
    InstanceSource& s = sources_[i];
    const uint32_t leaf_offset = uint32_t(elements_.instances()[i].leaf_offset);
    s.display_offset = int(vertex_leaves_.size());
    for (uint32_t index : s.display->indices)
      triangles_.push_back(uint32_t(s.display_offset) + index);
    if (s.display == s.elements) {
      for (uint32_t v = 0; v < uint32_t(s.elements->positions.size()); ++v) {
        vertex_leaves_.push_back(glm::uvec3(leaf_offset + v));
        vertex_weights_.push_back({1.0f, 0.0f, 0.0f});
      }
      continue;
    }
    proxy_leaves_ += int(s.elements->positions.size());
    const hierarchy::VertexTransfer& t = keyed.transfers[key_of_source[i]];
    for (size_t v = 0; v < t.corner.size(); ++v) {
      vertex_leaves_.push_back(glm::uvec3(leaf_offset) + t.corner[v]);
      vertex_weights_.push_back(t.weight[v]);
    }
  }
  vertex_world_.assign(vertex_leaves_.size(), glm::vec3(0.0f));
}

void SceneElements::UpdatePose(const SceneState& state) {
  if (deforming_.empty()) return;
  std::vector<std::shared_ptr<const Primitive>> posed(deforming_.size());
  ParallelFor(deforming_.size(), 1, [&](size_t k) {
    DeformingSource& d = deforming_[k];
    const Primitive& p = state.NodeMesh(size_t(d.node)).primitives[size_t(d.primitive)];
    posed[k] =
        std::make_shared<const Primitive>(hierarchy::RepeatSubdivision(p, *d.built, d.midpoints));
    auto mesh = std::make_shared<hierarchy::ElementMesh>();
    mesh->surfels = hierarchy::CreateSurfels(*posed[k]);  // one disc per vertex, as at Build
    mesh->tree = d.mesh->tree;
    d.mesh = std::move(mesh);
  });
  // The same instances with the posed meshes: the forest's layout (leaf
  // offsets, node ids) depends only on the trees, which are unchanged.
  std::vector<hierarchy::ElementInstance> instances = elements_.instances();
  for (size_t i = 0; i < sources_.size(); ++i) {
    InstanceSource& s = sources_[i];
    for (size_t k = 0; k < deforming_.size(); ++k) {
      if (deforming_[k].node != s.node || deforming_[k].primitive != s.primitive) continue;
      s.elements = posed[k];
      s.display = posed[k];  // deforming primitives have no proxies
      instances[i].mesh = deforming_[k].mesh;
    }
  }
  elements_ = hierarchy::Elements(std::move(instances));
}

void SceneElements::UpdateGeometry(const SceneState& state) {
  std::vector<glm::mat4> world;
  world.reserve(sources_.size());
  for (const InstanceSource& s : sources_) world.push_back(state.world()[size_t(s.node)]);
  elements_.Update(world);
  ParallelFor(sources_.size(), 1, [&](size_t i) {
    const Primitive& p = *sources_[i].display;
    const size_t offset = size_t(sources_[i].display_offset);
    for (size_t v = 0; v < p.positions.size(); ++v) {
      vertex_world_[offset + v] = glm::vec3(world[i] * glm::vec4(p.positions[v], 1.0f));
    }
  });
}

void SceneElements::UpdateAlbedo(const SceneState& state) {
  const Scene& scene = state.scene();
  albedo_.assign(size_t(elements_.leaf_count()), glm::vec3(1.0f));
  brdf_.assign(size_t(elements_.leaf_count()), shading::Brdf());
  for (size_t i = 0; i < sources_.size(); ++i) {
    const Primitive& p = *sources_[i].elements;
    const Material* m = p.material >= 0 ? &state.materials()[size_t(p.material)] : nullptr;
    const glm::vec3 factor = m ? glm::vec3(m->base_color_factor) : glm::vec3(1.0f);
    const Image* texture =
        m && m->base_color_texture >= 0 ? &scene.images[size_t(m->base_color_texture)] : nullptr;
    const Image* pbr_texture = m && m->metallic_roughness_texture >= 0
                                   ? &scene.images[size_t(m->metallic_roughness_texture)]
                                   : nullptr;
    const glm::vec2 pbr = m ? glm::vec2(m->metallic_factor, m->roughness_factor) : glm::vec2(0, 1);
    const size_t offset = size_t(elements_.instances()[i].leaf_offset);
    for (size_t v = 0; v < p.positions.size(); ++v) {
      glm::vec3 a = factor;
      if (texture && v < p.uvs.size()) {
        // The nearest texel at the vertex (an element's albedo is its
        // vertex's), wrapped by the texture's sampler.
        a *= SampleImage(*texture, m->base_color_uv.Apply(p.uvs[v]), m->base_color_sampler,
                         TextureFilter::kNearest);
      }
      a = glm::clamp(a, 0.0f, 1.0f);  // as the G-buffer and the path tracer
      glm::vec2 mr = pbr;
      if (pbr_texture && v < p.uvs.size()) {  // B: metallic, G: roughness
        const glm::vec3 t = SampleImage(*pbr_texture, m->metallic_roughness_uv.Apply(p.uvs[v]),
                                        m->metallic_roughness_sampler, TextureFilter::kNearest);
        mr *= glm::vec2(t.b, t.g);
      }
      // Light reaching a glossy leaf through links leaves it diffusely, so
      // it passes on what its BRDF reflects of light from all directions
      // (the white-sky albedo, as avg's voxels), not its base colour;
      // Lambertian leaves keep the base colour bitwise. Its direct light
      // leaves through its directional bins with the BRDF (illumination.h).
      mr = glm::clamp(mr, 0.0f, 1.0f);
      if (m) {
        brdf_[offset + v] = {.base_color = a,
                             .metallic = mr.x,
                             .roughness = mr.y,
                             .specular_f0 = m->specular_f0,
                             .specular_f90 = m->specular_f90};
      }
      albedo_[offset + v] = m ? BrdfWhiteSkyAlbedo(a, mr.x, mr.y, m->specular_f0, m->specular_f90)
                              : BrdfWhiteSkyAlbedo(a, mr.x, mr.y);
    }
  }
}

}  // namespace gistream
