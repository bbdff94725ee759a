#include "scene/gpu/gpu_scene.h"

#include <algorithm>

#include <glm/gtc/matrix_inverse.hpp>

#include "gl/buffers.h"
#include "gl/fault_injection.h"
#include "scene/proxies/proxy_levels.h"

namespace gistream {
namespace {

struct Vertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec2 uv;
};
static_assert(sizeof(Vertex) == 32);

GpuMaterial ToGpu(const Material& m) {
  GpuMaterial g;
  g.base_color = m.base_color_factor;
  g.emission = glm::vec4(m.emission(), 0.0f);
  g.textures = glm::ivec4(m.base_color_texture, m.emissive_texture, m.double_sided ? 1 : 0,
                          m.metallic_roughness_texture);
  g.pbr = glm::vec4(m.metallic_factor, m.roughness_factor, 0.0f, 0.0f);
  g.specular = glm::vec4(m.specular_f0, m.specular_f90);
  const UvTransform* uv[3] = {&m.base_color_uv, &m.emissive_uv, &m.metallic_roughness_uv};
  for (int k = 0; k < 3; ++k) {
    g.uv_transform[2 * k] = glm::vec4(uv[k]->u, 0.0f);
    g.uv_transform[2 * k + 1] = glm::vec4(uv[k]->v, 0.0f);
  }
  return g;
}

gl::Texture UploadImage(const Image& image) {
  gl::Texture tex = gl::Texture::Create(GL_TEXTURE_2D);
  const int levels = 1 + int(std::floor(std::log2(float(std::max(image.width, image.height)))));
  if (image.is_float) {
    glTextureStorage2D(tex.id(), levels, GL_RGBA32F, image.width, image.height);
    glTextureSubImage2D(tex.id(), 0, 0, 0, image.width, image.height, GL_RGBA, GL_FLOAT,
                        image.pixelsf.data());
  } else {
    glTextureStorage2D(tex.id(), levels, image.srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, image.width,
                       image.height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(tex.id(), 0, 0, 0, image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE,
                        image.pixels8.data());
  }
  glGenerateTextureMipmap(tex.id());
  glTextureParameteri(tex.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(tex.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(tex.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTextureParameteri(tex.id(), GL_TEXTURE_WRAP_T, GL_REPEAT);
  return tex;
}

}  // namespace

namespace {

// Import bounds images by --max-image-pixels and a per-side limit that may
// exceed what this GPU can hold; that is the client's data meeting this
// GPU, so a status, not a silently black texture.
absl::Status CheckTextureSizes(const Scene& scene) {
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  for (size_t i = 0; i < scene.images.size(); ++i) {
    const Image& image = scene.images[i];
    if (image.width > max_size || image.height > max_size) {
      return absl::ResourceExhaustedError(absl::StrCat(
          "images: texture ", i, image.name.empty() ? "" : absl::StrCat(" '", image.name, "'"),
          " is ", image.width, "x", image.height, ", larger than this GPU's largest texture (",
          max_size, " per side)"));
    }
  }
  if (scene.environment) {
    const Image& env = scene.environment->image;
    if (env.width > max_size || env.height > max_size) {
      return absl::ResourceExhaustedError(
          absl::StrCat("environment: the map is ", env.width, "x", env.height,
                       ", larger than this GPU's largest texture (", max_size, " per side)"));
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<std::unique_ptr<GpuScene>> GpuScene::Upload(const SceneState& state) {
  GS_RETURN_IF_ERROR(CheckTextureSizes(state.scene()));
  // Only this upload's errors below; earlier ones were reported already.
  while (glGetError() != GL_NO_ERROR) {
  }
  auto gpu = std::make_unique<GpuScene>();
  gpu->UploadGeometry(state);
  if (!state.deforming_nodes().empty()) {
    GS_ASSIGN_OR_RETURN(gpu->deform_, GpuDeform::Create(state, gpu->draws_));
    gpu->gpu_bytes_ += gpu->deform_->gpu_bytes();
    gpu->deform_->Run(state, gpu->vertices_.id());
  }
  gpu->deformed_version_ = state.version();
  gpu->UploadTextures(state.scene());
  gpu->materials_ = gl::Buffer::Create();
  glNamedBufferStorage(gpu->materials_.id(),
                       GLsizeiptr((state.scene().materials.size() + 1) * sizeof(GpuMaterial)),
                       nullptr, GL_DYNAMIC_STORAGE_BIT);
  gpu->UpdateMaterials(state);
  // Out of GPU memory is RESOURCE_EXHAUSTED for this load (the objects made
  // so far are freed with `gpu`), not a scene that renders wrong.
  if (const GLenum error = gl::AllocationError(); error == GL_OUT_OF_MEMORY) {
    return absl::ResourceExhaustedError(
        absl::StrCat("scene: the GPU could not hold its ", gpu->gpu_bytes_ >> 20,
                     " MiB of geometry and textures (GL_OUT_OF_MEMORY)"));
  } else if (error != GL_NO_ERROR) {
    return absl::InternalError(
        absl::StrCat("scene: uploading to the GPU failed with GL error 0x", absl::Hex(error)));
  }
  return gpu;
}

void GpuScene::UploadGeometry(const SceneState& state) {
  const Scene& scene = state.scene();
  // Geometry: one vertex/index range per primitive, shared by its instances.
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;
  struct Range {
    uint32_t first_index, index_count;
    int32_t base_vertex;
  };
  std::vector<std::vector<Range>> ranges(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    for (const Primitive& p : scene.meshes[m].primitives) {
      Range r{uint32_t(indices.size()), uint32_t(p.indices.size()), int32_t(vertices.size())};
      for (size_t v = 0; v < p.positions.size(); ++v) {
        vertices.push_back(
            {p.positions[v], p.normals[v], p.uvs.empty() ? glm::vec2(0.0f) : p.uvs[v]});
      }
      indices.insert(indices.end(), p.indices.begin(), p.indices.end());
      ranges[m].push_back(r);
    }
  }
  const auto level_ranges = AppendProxyLevels(scene, indices);
  const auto cluster_ranges = AppendClusters(scene, indices);
  for (size_t n = 0; n < scene.nodes.size(); ++n) {
    const int mesh = scene.nodes[n].mesh;
    if (mesh < 0) continue;
    for (size_t p = 0; p < ranges[size_t(mesh)].size(); ++p) {
      const Range& r = ranges[size_t(mesh)][p];
      const uint32_t count = uint32_t(scene.meshes[size_t(mesh)].primitives[p].positions.size());
      int32_t base = r.base_vertex;
      if (state.Deforms(n)) {  // its own copy, which the deformation pass poses
        base = int32_t(vertices.size());
        vertices.resize(vertices.size() + count);
        std::copy_n(vertices.begin() + r.base_vertex, count, vertices.begin() + base);
      }
      draws_.push_back({r.first_index, r.index_count, base, r.base_vertex, count,
                        scene.meshes[size_t(mesh)].primitives[p].material, int(n), mesh, int(p)});
      std::tie(draws_.back().first_level, draws_.back().level_count) =
          level_ranges[size_t(mesh)][p];
      std::tie(draws_.back().first_cluster, draws_.back().cluster_count) =
          cluster_ranges[size_t(mesh)][p];
    }
  }
  vertices_ = gl::StorageBuffer(vertices);
  indices_ = gl::StorageBuffer(indices);
  gpu_bytes_ += vertices.size() * sizeof(Vertex) + indices.size() * sizeof(uint32_t);
  CreateVertexArray();
}

GpuScene::MeshRanges GpuScene::AppendProxyLevels(const Scene& scene,
                                                 std::vector<uint32_t>& indices) {
  // Proxy levels after every full mesh, each drawn with its primitive's
  // base vertex; (first level, count) per mesh and primitive.
  MeshRanges level_ranges(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    for (const Primitive& p : scene.meshes[m].primitives) {
      level_ranges[m].push_back({int(levels_.size()), int(p.proxies.size())});
      for (const ProxyLevel& level : p.proxies) {
        levels_.push_back({uint32_t(indices.size()), uint32_t(level.indices.size()), level.error});
        indices.insert(indices.end(), level.indices.begin(), level.indices.end());
      }
    }
  }
  return level_ranges;
}

GpuScene::MeshRanges GpuScene::AppendClusters(const Scene& scene, std::vector<uint32_t>& indices) {
  // Cluster trees after the levels: each leaf's full triangles and each
  // node's copy; (first cluster, count) per mesh and primitive.
  MeshRanges cluster_ranges(scene.meshes.size());
  const auto append = [&](const std::vector<uint32_t>& list, float error) {
    const DrawLevel range{uint32_t(indices.size()), uint32_t(list.size()), error};
    indices.insert(indices.end(), list.begin(), list.end());
    return range;
  };
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    for (const Primitive& p : scene.meshes[m].primitives) {
      cluster_ranges[m].push_back({int(clusters_.size()), int(p.clusters.size())});
      for (const ProxyCluster& c : p.clusters) {
        DrawCluster& d = clusters_.emplace_back();
        d.bounds = c.bounds;
        d.full = append(c.indices, 0.0f);
        d.level = append(c.level.indices, c.level.error);
        d.children[0] = c.children[0];
        d.children[1] = c.children[1];
      }
    }
  }
  return cluster_ranges;
}

void GpuScene::CreateVertexArray() {
  vao_ = gl::VertexArray::Create();
  const GLuint vao = vao_.id();
  glVertexArrayVertexBuffer(vao, 0, vertices_.id(), 0, sizeof(Vertex));
  glVertexArrayElementBuffer(vao, indices_.id());
  const GLuint offsets[3] = {offsetof(Vertex, position), offsetof(Vertex, normal),
                             offsetof(Vertex, uv)};
  const GLint sizes[3] = {3, 3, 2};
  for (GLuint a = 0; a < 3; ++a) {
    glEnableVertexArrayAttrib(vao, a);
    glVertexArrayAttribFormat(vao, a, sizes[a], GL_FLOAT, GL_FALSE, offsets[a]);
    glVertexArrayAttribBinding(vao, a, 0);
  }
  // A draw list's records (scene/gpu/draw_list.h): the model matrix's columns
  // and the tag, one per instance from the list's buffer at binding 1, so
  // a command's base instance picks its first record. Enabled only while a
  // list draws.
  for (GLuint c = 0; c < 4; ++c) {
    glVertexArrayAttribFormat(vao, kDrawModelAttrib + c, 4, GL_FLOAT, GL_FALSE,
                              GLuint(c * sizeof(glm::vec4)));
    glVertexArrayAttribBinding(vao, kDrawModelAttrib + c, kDrawRecordBufferBinding);
  }
  glVertexArrayAttribIFormat(vao, kDrawTagAttrib, 2, GL_INT, GLuint(sizeof(glm::mat4)));
  glVertexArrayAttribBinding(vao, kDrawTagAttrib, kDrawRecordBufferBinding);
  glVertexArrayBindingDivisor(vao, kDrawRecordBufferBinding, 1);
}

void GpuScene::UploadTextures(const Scene& scene) {
  for (const Image& image : scene.images) {
    textures_.push_back(UploadImage(image));
    gpu_bytes_ +=
        uint64_t(image.width) * uint64_t(image.height) * (image.is_float ? 16 : 4) * 4 / 3;
  }
  for (const Material& m : scene.materials) {
    for (const TextureSampler& t :
         {m.base_color_sampler, m.emissive_sampler, m.metallic_roughness_sampler}) {
      if (t == TextureSampler{} || samplers_.contains(t)) continue;
      // glTF's sampler values are GL's enums (glTF 2.0 5.26); absent
      // filters are the default texture's (linear, trilinear).
      gl::Sampler sampler = gl::Sampler::Create();
      glSamplerParameteri(sampler.id(), GL_TEXTURE_WRAP_S, t.wrap_s);
      glSamplerParameteri(sampler.id(), GL_TEXTURE_WRAP_T, t.wrap_t);
      glSamplerParameteri(sampler.id(), GL_TEXTURE_MAG_FILTER,
                          t.mag_filter != 0 ? t.mag_filter : GL_LINEAR);
      glSamplerParameteri(sampler.id(), GL_TEXTURE_MIN_FILTER,
                          t.min_filter != 0 ? t.min_filter : GL_LINEAR_MIPMAP_LINEAR);
      samplers_.emplace(t, std::move(sampler));
    }
  }
  Image white;
  white.width = white.height = 1;
  white.pixels8 = {255, 255, 255, 255};
  white_ = UploadImage(white);
  if (scene.environment && !scene.environment->image.pixelsf.empty()) {
    const Image& env = scene.environment->image;
    environment_ = gl::Texture::Create(GL_TEXTURE_2D);
    glTextureStorage2D(environment_.id(), 1, GL_RGBA32F, env.width, env.height);
    glTextureSubImage2D(environment_.id(), 0, 0, 0, env.width, env.height, GL_RGBA, GL_FLOAT,
                        env.pixelsf.data());
    glTextureParameteri(environment_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(environment_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gpu_bytes_ += uint64_t(env.width) * uint64_t(env.height) * 16;
  }
}

void GpuScene::UpdateMaterials(const SceneState& state) {
  std::vector<GpuMaterial> table;
  table.reserve(state.materials().size() + 1);
  for (const Material& m : state.materials()) table.push_back(ToGpu(m));
  table.push_back(ToGpu(Material{}));  // the default material, last
  glNamedBufferSubData(materials_.id(), 0, GLsizeiptr(table.size() * sizeof(GpuMaterial)),
                       table.data());
}

bool GpuScene::DeformPending(const SceneState& state) const {
  return deform_ && state.version() != deformed_version_ &&
         (state.ChangesSince(deformed_version_) & kChangeDeformation);
}

void GpuScene::Deform(const SceneState& state) {
  if (DeformPending(state)) deform_->Run(state, vertices_.id());
  deformed_version_ = state.version();
}

void GpuScene::Walk(const SceneState& state, const DrawFilter* filter,
                    const ClusterFilter* cluster_filter, const DrawVisitor& visit) const {
  for (const DrawItem& d : draws_) {
    const glm::mat4& model = state.world()[size_t(d.node)];
    DrawLevel range{d.first_index, d.index_count, 0.0f};
    const bool by_cluster = filter && cluster_filter && d.cluster_count > 0;
    if (filter) {
      const float tolerance = (*filter)(d, model);
      if (tolerance < 0.0f) continue;
      const int level = by_cluster ? -1 : PickLevel(d, MaxScale(model), tolerance);
      if (level >= 0) range = levels_[size_t(d.first_level + level)];
    }
    if (!by_cluster) {
      visit(d, model, range);
      continue;
    }
    // The tree, root first: a node's copy where it is within the node's
    // tolerance (scaled as PickLevel does), else its children.
    const float scale = MaxScale(model);
    std::vector<int> open = {0};
    while (!open.empty()) {
      const DrawCluster& c = clusters_[size_t(d.first_cluster + open.back())];
      open.pop_back();
      const float tolerance = (*cluster_filter)(c.bounds.Transformed(model));
      if (tolerance < 0.0f) continue;
      if (c.level.index_count > 0 && c.level.error * scale <= tolerance) {
        visit(d, model, c.level);
      } else if (c.children[0] < 0) {
        visit(d, model, c.full);
      } else {
        open.push_back(c.children[1]);
        open.push_back(c.children[0]);
      }
    }
  }
}

void GpuScene::Draw(gl::Program& program, const SceneState& state, bool bind_textures,
                    int instances, const DrawFilter* filter,
                    const ClusterFilter* cluster_filter) const {
  glBindVertexArray(vao_.id());
  BindMaterials();
  const DrawItem* current = nullptr;  // the item whose uniforms are set
  Walk(state, filter, cluster_filter,
       [&](const DrawItem& d, const glm::mat4& model, const DrawLevel& range) {
         if (current != &d) {
           current = &d;
           program.Set("uModel", model);
           program.SetOptional("uNormalMatrix", glm::inverseTranspose(glm::mat3(model)));
           program.SetOptional("uMaterial", MaterialIndex(state, d));
           if (bind_textures) BindTextures(TexturesOf(state, d));
         }
         glDrawElementsInstancedBaseVertex(
             GL_TRIANGLES, GLsizei(range.index_count), GL_UNSIGNED_INT,
             reinterpret_cast<const void*>(uintptr_t(range.first_index) * sizeof(uint32_t)),
             std::max(instances, 1), d.base_vertex);
       });
  glBindVertexArray(0);
  UnbindSamplers();
}

void GpuScene::BindMaterials() const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kMaterialBinding, materials_.id());
}

int GpuScene::MaterialIndex(const SceneState& state, const DrawItem& item) {
  return item.material >= 0 ? item.material : int(state.materials().size());
}

MaterialTextures GpuScene::TexturesOf(const SceneState& state, const DrawItem& item) const {
  const Material* m = item.material >= 0 ? &state.materials()[size_t(item.material)] : nullptr;
  const auto texture = [&](int index) {
    return index >= 0 ? textures_[size_t(index)].id() : white_.id();
  };
  if (m == nullptr) return {white_.id(), white_.id(), white_.id()};
  return {texture(m->base_color_texture),         texture(m->emissive_texture),
          texture(m->metallic_roughness_texture), SamplerOf(m->base_color_sampler),
          SamplerOf(m->emissive_sampler),         SamplerOf(m->metallic_roughness_sampler)};
}

GLuint GpuScene::SamplerOf(const TextureSampler& sampler) const {
  if (sampler == TextureSampler{}) return 0;
  const auto it = samplers_.find(sampler);
  return it != samplers_.end() ? it->second.id() : 0;
}

void GpuScene::UnbindSamplers() {
  for (GLuint unit : {kBaseColorUnit, kEmissiveUnit, kMetallicRoughnessUnit})
    glBindSampler(unit, 0);
}

void GpuScene::BindTextures(const MaterialTextures& textures) {
  glBindTextureUnit(kBaseColorUnit, textures.base_color);
  glBindTextureUnit(kEmissiveUnit, textures.emissive);
  glBindTextureUnit(kMetallicRoughnessUnit, textures.metallic_roughness);
  glBindSampler(kBaseColorUnit, textures.base_color_sampler);
  glBindSampler(kEmissiveUnit, textures.emissive_sampler);
  glBindSampler(kMetallicRoughnessUnit, textures.metallic_roughness_sampler);
}

int GpuScene::PickLevel(const DrawItem& item, float scale, float tolerance) const {
  return PickProxyLevel(std::span<const DrawLevel>(levels_).subspan(size_t(item.first_level),
                                                                    size_t(item.level_count)),
                        scale, tolerance);
}

Bounds GpuScene::WorldBounds(const SceneState& state) const {
  Bounds bounds;
  for (const DrawItem& d : draws_) {
    const Bounds& local = state.NodeMesh(size_t(d.node)).primitives[size_t(d.primitive)].bounds;
    bounds.Extend(local.Transformed(state.world()[size_t(d.node)]));
  }
  return bounds;
}

}  // namespace gistream
