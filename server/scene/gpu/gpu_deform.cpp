#include "scene/gpu/gpu_deform.h"

#include <algorithm>

#include "gl/buffers.h"
#include "gl/compute.h"
#include "scene/state/deform.h"
#include "scene/gpu/gpu_scene.h"

namespace gistream {
namespace {

constexpr size_t kLocalSize = 64;  // deform.comp.glsl's local_size_x

// std430 mirror of deform.comp.glsl's SkinVertex.
struct SkinVertex {
  glm::uvec4 joints;
  glm::vec4 weights;
};
GS_STD430_MIRROR(SkinVertex, 32);

// A buffer of at least `bytes` for per-frame uploads, regrown when short.
void Reserve(gl::Buffer* buffer, size_t* capacity, size_t bytes) {
  if (*buffer && *capacity >= bytes) return;
  *capacity = std::max<size_t>(bytes, 64);
  *buffer = gl::ZeroedBuffer(*capacity);
}

}  // namespace

absl::StatusOr<std::unique_ptr<GpuDeform>> GpuDeform::Create(const SceneState& state,
                                                             std::span<const DrawItem> draws) {
  auto deform = std::unique_ptr<GpuDeform>(new GpuDeform());
  GS_ASSIGN_OR_RETURN(deform->program_,
                      gl::Program::Build({{GL_COMPUTE_SHADER, "scene/deform.comp.glsl"}}));
  const Scene& scene = state.scene();
  std::vector<SkinVertex> skin;
  std::vector<glm::vec4> morph;
  for (const DrawItem& d : draws) {
    if (!state.Deforms(size_t(d.node))) continue;
    const Primitive& p = scene.meshes[size_t(d.mesh)].primitives[size_t(d.primitive)];
    Job job;
    job.node = d.node;
    job.count = d.vertex_count;
    job.src = uint32_t(d.rest_vertex);
    job.dst = uint32_t(d.base_vertex);
    if (scene.nodes[size_t(d.node)].skin >= 0 && !p.joints.empty()) {
      job.skin = int32_t(skin.size());
      for (size_t v = 0; v < p.joints.size(); ++v) {
        skin.push_back({glm::uvec4(p.joints[v]), p.weights[v]});
      }
    }
    job.morph = uint32_t(morph.size());
    job.targets = uint32_t(p.targets.size());
    for (const Primitive::MorphTarget& t : p.targets) {
      for (size_t v = 0; v < p.positions.size(); ++v) {
        morph.emplace_back(v < t.positions.size() ? t.positions[v] : glm::vec3(0.0f), 0.0f);
        morph.emplace_back(v < t.normals.size() ? t.normals[v] : glm::vec3(0.0f), 0.0f);
      }
    }
    deform->jobs_.push_back(job);
  }
  deform->skin_ = gl::StorageBuffer(skin);
  deform->morph_ = gl::StorageBuffer(morph);
  deform->gpu_bytes_ = skin.size() * sizeof(SkinVertex) + morph.size() * sizeof(glm::vec4);
  return deform;
}

void GpuDeform::Run(const SceneState& state, GLuint vertices) {
  if (jobs_.empty()) return;
  const Scene& scene = state.scene();
  // Joint matrices (deform.h's JointMatrices, with the normal matrix beside
  // each) and morph weights (padded to the target count with zeros, as
  // DeformPrimitive counts missing weights) of every job, one upload each.
  std::vector<glm::mat4> joints;
  std::vector<float> weights;
  std::vector<std::pair<uint32_t, uint32_t>> offsets;  // per job: first joint, first weight
  for (const Job& job : jobs_) {
    const Node& node = state.nodes()[size_t(job.node)];
    offsets.emplace_back(uint32_t(joints.size()), uint32_t(weights.size()));
    if (job.skin >= 0) {
      for (const glm::mat4& j :
           JointMatrices(scene.skins[size_t(node.skin)], state.world(), job.node)) {
        joints.push_back(j);
        joints.emplace_back(glm::transpose(glm::inverse(glm::mat3(j))));
      }
    }
    const std::span<const float> w = MorphWeights(scene, node);
    for (uint32_t t = 0; t < job.targets; ++t) weights.push_back(t < w.size() ? w[t] : 0.0f);
  }
  Reserve(&joints_, &joint_capacity_, joints.size() * sizeof(glm::mat4));
  Reserve(&weights_, &weight_capacity_, weights.size() * sizeof(float));
  gl::Upload(joints_, std::span<const glm::mat4>(joints));
  gl::Upload(weights_, std::span<const float>(weights));

  program_.Use();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GS_BINDING_DEFORM_VERTICES, vertices);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GS_BINDING_DEFORM_SKIN, skin_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GS_BINDING_DEFORM_MORPH, morph_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GS_BINDING_DEFORM_JOINTS, joints_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GS_BINDING_DEFORM_WEIGHTS, weights_.id());
  for (size_t i = 0; i < jobs_.size(); ++i) {
    const Job& job = jobs_[i];
    program_.Set("uCount", unsigned(job.count));
    program_.Set("uSrc", unsigned(job.src));
    program_.Set("uDst", unsigned(job.dst));
    program_.Set("uSkin", int(job.skin));
    program_.Set("uMorph", unsigned(job.morph));
    program_.Set("uTargets", unsigned(job.targets));
    program_.Set("uJoints", unsigned(offsets[i].first));
    program_.Set("uWeights", unsigned(offsets[i].second));
    gl::Dispatch(job.count, kLocalSize);
  }
  // The posed vertices feed vertex fetch (every rasterising pass) and
  // buffer reads.
  glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                  GL_BUFFER_UPDATE_BARRIER_BIT);
}

}  // namespace gistream
