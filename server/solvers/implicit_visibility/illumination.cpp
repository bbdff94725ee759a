#include "solvers/implicit_visibility/illumination.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "gl/buffers.h"
#include "solvers/tail_estimate.h"
#include "gl/compute.h"
#include "implicit_visibility/bindings.glsl"  // shaders/: the slots its passes declare

namespace gistream {
namespace {

constexpr GLbitfield kBarrier = GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT;

// std430 mirror of shaders/implicit_visibility/leaves.glsl.
struct GpuLeaf {
  glm::vec4 position, normal, albedo;
};
GS_STD430_MIRROR(GpuLeaf, 48);

}  // namespace

absl::StatusOr<Illumination> Illumination::Create() {
  Illumination il;
  GS_ASSIGN_OR_RETURN(
      il.direct_,
      gl::Program::Build({{GL_COMPUTE_SHADER, "implicit_visibility/leaf_direct.comp.glsl"}}));
  GS_ASSIGN_OR_RETURN(
      il.gather_,
      gl::Program::Build({{GL_COMPUTE_SHADER, "implicit_visibility/gather.comp.glsl"}}));
  GS_ASSIGN_OR_RETURN(
      il.pull_, gl::Program::Build({{GL_COMPUTE_SHADER, "implicit_visibility/pull.comp.glsl"}}));
  return il;
}

void Illumination::UploadElements(const hierarchy::Elements& e,
                                  const std::vector<glm::vec3>& albedo) {
  leaf_count_ = e.leaf_count();
  node_count_ = e.node_count();
  level_begin_ = e.level_begin();
  std::vector<GpuLeaf> leaves(static_cast<size_t>(leaf_count_));
  for (size_t i = 0; i < leaves.size(); ++i) {
    leaves[i] = {glm::vec4(e.position[i], 0.0f), glm::vec4(e.normal[i], 0.0f),
                 glm::vec4(i < albedo.size() ? albedo[i] : glm::vec3(0.0f), 0.0f)};
  }
  std::vector<glm::ivec4> children(static_cast<size_t>(node_count_));
  for (size_t i = 0; i < children.size(); ++i) {
    children[i] = {e.children[i][0], e.children[i][1], e.children[i][2], e.children[i][3]};
  }
  leaves_ = gl::StorageBuffer(leaves);
  children_ = gl::StorageBuffer(children);
  areas_ = gl::StorageBuffer(e.area);
  const size_t leaf_vec4 = size_t(leaf_count_) * sizeof(glm::vec4);
  if (!e_direct_ || !e_env_) {
    e_direct_ = gl::ZeroedBuffer(leaf_vec4);
    e_indirect_ = gl::ZeroedBuffer(leaf_vec4);
    e_env_ = gl::ZeroedBuffer(leaf_vec4);
    for (gl::Buffer& r : radiance_) r = gl::ZeroedBuffer(size_t(node_count_) * sizeof(glm::vec4));
  }
  element_bytes_ = leaves.size() * sizeof(GpuLeaf) + children.size() * 20 + 3 * leaf_vec4 +
                   2 * size_t(node_count_) * sizeof(glm::vec4);
  gpu_bytes_ = element_bytes_ + link_bytes_;
}

void Illumination::UploadLinks(const hierarchy::LeafLinks& links) {
  std::vector<glm::uvec2> packed(links.source.size());
  for (size_t k = 0; k < packed.size(); ++k) {
    uint32_t bits;
    std::memcpy(&bits, &links.weight[k], sizeof(bits));
    packed[k] = {links.source[k], bits};
  }
  offsets_ = gl::StorageBuffer(links.offset);
  links_ = gl::StorageBuffer(packed);
  link_bytes_ = packed.size() * sizeof(glm::uvec2) + links.offset.size() * sizeof(uint32_t);
  gpu_bytes_ = element_bytes_ + link_bytes_;
}

void Illumination::UploadEnvironment(const std::vector<glm::vec3>& e_env) {
  std::vector<glm::vec4> data(size_t(leaf_count_), glm::vec4(0.0f));
  for (size_t i = 0; i < std::min(data.size(), e_env.size()); ++i)
    data[i] = glm::vec4(e_env[i], 0.0f);
  glNamedBufferSubData(e_env_.id(), 0, GLsizeiptr(data.size() * sizeof(glm::vec4)), data.data());
}

void Illumination::Pull(GLuint radiance) {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_PULL_CHILDREN, children_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_PULL_AREAS, areas_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_PULL_RADIANCE, radiance);
  pull_.Use();
  for (size_t h = 1; h < level_begin_.size(); ++h) {
    const int begin = level_begin_[h - 1], end = level_begin_[h];
    if (end <= begin) continue;
    pull_.Set("uBegin", begin);
    pull_.Set("uEnd", end);
    glDispatchCompute(gl::GroupCount(size_t(end - begin), 64), 1, 1);
    glMemoryBarrier(kBarrier);
  }
}

std::vector<glm::vec4> Illumination::ReadIndirect() const {
  std::vector<glm::vec4> e(static_cast<size_t>(leaf_count_));
  if (!e.empty()) {
    glGetNamedBufferSubData(e_indirect_.id(), 0, GLsizeiptr(e.size() * sizeof(glm::vec4)),
                            e.data());
  }
  return e;
}

void Illumination::ApplyTail(const std::vector<glm::vec4>& current,
                             const std::vector<glm::vec4>& previous, double f) {
  std::vector<glm::vec4> e(current.size());
  for (size_t i = 0; i < e.size(); ++i) {
    const glm::dvec3 c(current[i]), p(i < previous.size() ? glm::dvec3(previous[i]) : c);
    // A leaf's increment may be negative (light moving between leaves):
    // the sum stays at or above zero.
    e[i] = glm::vec4(glm::max(c + f * (c - p), glm::dvec3(0.0)), current[i].w);
  }
  if (!e.empty())
    glNamedBufferSubData(e_indirect_.id(), 0, GLsizeiptr(e.size() * sizeof(glm::vec4)), e.data());
}

void Illumination::Gather(int in) {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GATHER_LEAVES, leaves_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GATHER_DIRECT_E, e_direct_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GATHER_ENV_E, e_env_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GATHER_OFFSETS, offsets_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GATHER_LINKS, links_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GATHER_RADIANCE_IN, radiance_[in].id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GATHER_RADIANCE_OUT, radiance_[1 - in].id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GATHER_INDIRECT_E, e_indirect_.id());
  gather_.Set("uLeafCount", leaf_count_);
  gather_.Use();
  glDispatchCompute(gl::GroupCount(size_t(leaf_count_), 64), 1, 1);
  glMemoryBarrier(kBarrier);
}

Illumination::Result Illumination::Run(const DirectLighting& lighting, int max_bounces,
                                       double tolerance, double tail_bound,
                                       const std::stop_token& stop) {
  Result result;
  if (leaf_count_ == 0) return result;
  // The first bounce's source: direct light (and environment) at the leaves.
  lighting.Bind(direct_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_LEAF_LEAVES, leaves_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_LEAF_DIRECT_E, e_direct_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_LEAF_ENV_E, e_env_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_LEAF_RADIANCE, radiance_[0].id());
  direct_.Set("uLeafCount", leaf_count_);
  direct_.Use();
  glDispatchCompute(gl::GroupCount(size_t(leaf_count_), 64), 1, 1);
  glMemoryBarrier(kBarrier);
  Pull(radiance_[0].id());

  const float zero = 0.0f;
  glClearNamedBufferData(e_indirect_.id(), GL_R32F, GL_RED, GL_FLOAT, &zero);
  std::vector<glm::vec4> previous(size_t(leaf_count_), glm::vec4(0.0f)), current;
  std::vector<double> deltas, totals;  // per bounce: sum |dE|, sum |E| (luminance)
  auto lum = [](const glm::vec4& e) {
    return 0.2126 * double(e.r) + 0.7152 * double(e.g) + 0.0722 * double(e.b);
  };
  // The bounces not run (solvers/tail_estimate.h), when they form a
  // geometric series: f x the last bounce's increment.
  auto finish = [&] {
    if (!(tail_bound > 0.0)) return;
    const TailEstimate tail = EstimateTail(deltas, tail_bound);
    if (!tail.applied) return;
    result.tail_ratio = tail.ratio;
    result.tail_applied = true;
    ApplyTail(current, previous, MonotoneTailFactor(deltas, totals, tail_bound));
  };
  int in = 0;
  for (int bounce = 1; bounce <= max_bounces; ++bounce) {
    if (stop.stop_requested()) {
      result.cancelled = true;
      return result;
    }
    Gather(in);
    in = 1 - in;
    Pull(radiance_[in].id());
    // Residual of this bounce (the change it made): the stopping test.
    if (bounce > 1) previous = std::move(current);
    current = ReadIndirect();
    double change = 0.0, total = 0.0;
    for (size_t i = 0; i < current.size(); ++i) {
      const double c = lum(current[i]), p = lum(previous[i]);
      change += std::abs(c - p);
      total += std::abs(c);
      if (c < p * (1.0 - 1e-4) - 1e-30) result.monotone = false;
    }
    deltas.push_back(change);
    totals.push_back(total);
    result.residual = total > 0.0 ? change / total : 0.0;
    result.bounces = bounce;
    // The first bounce's residual is 1 by definition (from nothing).
    if (bounce >= 2 && result.residual < tolerance) {
      finish();
      return result;
    }
    // In a bright scene the increments shrink too slowly for that test;
    // the tail-corrected sum may be known long before (tail_estimate.h).
    const double tail_residual = tail_bound > 0.0 ? TailResidual(deltas, totals, tail_bound)
                                                  : std::numeric_limits<double>::infinity();
    if (TailSettled(tail_residual, tolerance)) {
      result.residual = tail_residual;
      result.tail_stopped = true;
      finish();
      return result;
    }
  }
  // Bounce 1 alone cannot test convergence; a cap of 1 is the user's choice.
  result.cap_reached = max_bounces >= 2 && !(result.residual < tolerance);
  finish();
  return result;
}

}  // namespace gistream
