#include "solvers/implicit_visibility/illumination.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "absl/strings/str_cat.h"

#include "gl/buffers.h"
#include "solvers/tail_estimate.h"
#include "gl/compute.h"
#include "implicit_visibility/bindings.glsl"  // shaders/: the slots its passes declare

namespace gistream {
namespace {

constexpr GLbitfield kBarrier = GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT;

// std430 mirror of shaders/implicit_visibility/leaves.glsl.
struct GpuLeaf {
  glm::vec4 position, normal, albedo;  // normal.w: the glossy slot, -1 diffuse
};
GS_STD430_MIRROR(GpuLeaf, 48);

// std430 mirror of GlossyNode in shaders/implicit_visibility/glossy.glsl.
struct GpuGlossyNode {
  glm::vec4 position, normal;
};
GS_STD430_MIRROR(GpuGlossyNode, 32);

// Whether a leaf's light leaves through directional bins: a glossy BRDF
// below kDiffuseRoughness. At roughness 1 the lobe is as wide as the
// hemisphere and the bins resolve it worse than the white-sky albedo does
// (glossy_box with a gold cube of roughness 1, the cube's light in the
// room against pathtrace: 1.04x through bins, 1.01x diffuse; at 0.85:
// 1.07x and 0.88x), and glTF's default material (a metal of roughness 1)
// would cost every leaf a slot.
constexpr float kDiffuseRoughness = 0.9f;

bool Directional(const shading::Brdf& b) {
  return !b.Lambertian() && b.roughness < kDiffuseRoughness;
}

}  // namespace

absl::StatusOr<Illumination> Illumination::Create(int glossy_bins) {
  Illumination il;
  if (glossy_bins > 0) {
    auto bins = hierarchy::DirectionalBins::Create(glossy_bins);
    if (!bins.ok()) {
      return absl::InvalidArgumentError(absl::StrCat(
          "params.glossy_bins: ", glossy_bins, " must be even (the bins are antipodal pairs)"));
    }
    il.bins_ = *std::move(bins);
    GS_ASSIGN_OR_RETURN(il.glossy_direct_, GlossyBinDirect::Create());
    std::vector<glm::vec4> directions;
    for (int j = 0; j < il.bins_->count(); ++j)
      directions.push_back(glm::vec4(il.bins_->direction(j), 0.0f));
    il.bin_directions_ = gl::StorageBuffer(directions);
    il.bin_lut_ =
        gl::StorageBuffer(std::vector<uint32_t>(il.bins_->lut().begin(), il.bins_->lut().end()));
  }
  GS_ASSIGN_OR_RETURN(
      il.glossy_pull_,
      gl::Program::Build({{GL_COMPUTE_SHADER, "implicit_visibility/glossy_pull.comp.glsl"}}));
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

uint64_t Illumination::GlossySlotBytes(int glossy_bins) {
  return uint64_t(std::max(0, glossy_bins)) * sizeof(glm::vec4) + sizeof(GpuGlossyNode) +
         sizeof(GlossyBinElement) + 2 * sizeof(int);
}

void Illumination::UploadElements(const hierarchy::Elements& e,
                                  const std::vector<glm::vec3>& albedo,
                                  const std::vector<shading::Brdf>& brdf) {
  leaf_count_ = e.leaf_count();
  node_count_ = e.node_count();
  level_begin_ = e.level_begin();
  const std::vector<int> node_slot = UploadGlossy(e, brdf);
  std::vector<GpuLeaf> leaves(static_cast<size_t>(leaf_count_));
  for (size_t i = 0; i < leaves.size(); ++i) {
    leaves[i] = {glm::vec4(e.position[i], 0.0f), glm::vec4(e.normal[i], float(node_slot[i])),
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
                   2 * size_t(node_count_) * sizeof(glm::vec4) + glossy_bytes_;
  gpu_bytes_ = element_bytes_ + link_bytes_;
}

void Illumination::UploadLinks(const hierarchy::LeafLinks& links, const hierarchy::CubeBins& bins) {
  std::vector<glm::uvec2> packed(links.source.size());
  for (size_t k = 0; k < packed.size(); ++k) {
    uint32_t bits;
    std::memcpy(&bits, &links.weight[k], sizeof(bits));
    packed[k] = {links.source[k], bits};
  }
  offsets_ = gl::StorageBuffer(links.offset);
  links_ = gl::StorageBuffer(packed);
  std::vector<uint32_t> link_bins((links.bin.size() + 1) / 2 + 1, 0u);
  for (size_t k = 0; k < links.bin.size(); ++k)
    link_bins[k / 2] |= uint32_t(links.bin[k]) << (16 * (k % 2));
  link_bins_ = gl::StorageBuffer(link_bins);
  std::vector<glm::vec4> directions(size_t(bins.count()));
  for (int b = 0; b < bins.count(); ++b) directions[size_t(b)] = glm::vec4(bins.Direction(b), 0.0f);
  receiver_bins_ = gl::StorageBuffer(directions);
  link_bytes_ = packed.size() * sizeof(glm::uvec2) + links.offset.size() * sizeof(uint32_t) +
                link_bins.size() * sizeof(uint32_t);
  gpu_bytes_ = element_bytes_ + link_bytes_;
}

void Illumination::UploadEnvironment(const std::vector<glm::vec3>& e_env) {
  std::vector<glm::vec4> data(size_t(leaf_count_), glm::vec4(0.0f));
  for (size_t i = 0; i < std::min(data.size(), e_env.size()); ++i)
    data[i] = glm::vec4(e_env[i], 0.0f);
  glNamedBufferSubData(e_env_.id(), 0, GLsizeiptr(data.size() * sizeof(glm::vec4)), data.data());
}

std::vector<int> Illumination::UploadGlossy(const hierarchy::Elements& e,
                                            const std::vector<shading::Brdf>& brdf) {
  // Slots: the glossy leaves in leaf order, then every internal node with
  // a glossy child in node order (by height, so each level's slots are
  // contiguous for the pull-up).
  std::vector<int> node_slot(size_t(node_count_), -1);
  slot_node_.clear();
  std::vector<GlossyBinElement> elements;
  const float min_roughness = bins_ ? bins_->ResolvedRoughness() : 1.0f;
  // Past kMaxGlossyWork with one light the direct pass never runs: no
  // slots are kept (their bins would be most of the solver's memory).
  const auto directional = [&](int i) {
    return size_t(i) < brdf.size() && Directional(brdf[size_t(i)]);
  };
  double directional_leaves = 0.0;
  for (int i = 0; bins_ && i < leaf_count_; ++i) directional_leaves += directional(i) ? 1.0 : 0.0;
  glossy_found_ = int(directional_leaves);
  glossy_over_cap_ = bins_ && directional_leaves * bins_->count() > kMaxGlossyWork;
  for (int i = 0; bins_ && !glossy_over_cap_ && i < leaf_count_; ++i) {
    if (!directional(i)) continue;
    const shading::Brdf& b = brdf[size_t(i)];
    node_slot[size_t(i)] = int(slot_node_.size());
    slot_node_.push_back(i);
    elements.push_back({glm::vec4(e.position[size_t(i)], 0.0f),
                        glm::vec4(e.normal[size_t(i)], std::max(b.roughness, min_roughness)),
                        glm::vec4(b.base_color, b.metallic),
                        glm::vec4(b.specular_f0, b.specular_f90)});
  }
  glossy_leaves_ = int(slot_node_.size());
  glossy_level_begin_.assign(1, glossy_leaves_);
  for (size_t h = 1; h < level_begin_.size(); ++h) {
    for (int node = level_begin_[h - 1]; glossy_leaves_ > 0 && node < level_begin_[h]; ++node) {
      bool glossy = false;
      for (int c : e.children[size_t(node)])
        glossy = glossy || (c >= 0 && node_slot[size_t(c)] >= 0);
      if (!glossy) continue;
      node_slot[size_t(node)] = int(slot_node_.size());
      slot_node_.push_back(node);
    }
    glossy_level_begin_.push_back(int(slot_node_.size()));
  }
  std::vector<GpuGlossyNode> nodes;
  for (int node : slot_node_) {
    nodes.push_back(
        {glm::vec4(e.position[size_t(node)], 0.0f), glm::vec4(e.normal[size_t(node)], 0.0f)});
  }
  const size_t slots = slot_node_.size(), m = bins_ ? size_t(bins_->count()) : 0;
  node_slots_ = gl::StorageBuffer(node_slot.empty() ? std::vector<int>{-1} : node_slot);
  slot_nodes_ = gl::StorageBuffer(slot_node_.empty() ? std::vector<int>{-1} : slot_node_);
  glossy_nodes_ = gl::StorageBuffer(nodes.empty() ? std::vector<GpuGlossyNode>(1) : nodes);
  glossy_elements_ =
      gl::StorageBuffer(elements.empty() ? std::vector<GlossyBinElement>(1) : elements);
  // Kept across geometry changes of the same slots: every use refills it.
  const size_t radiance_bytes = std::max<size_t>(1, slots * m) * sizeof(glm::vec4);
  if (!glossy_radiance_ || glossy_radiance_bytes_ != radiance_bytes) {
    glossy_radiance_ = gl::ZeroedBuffer(radiance_bytes);
    glossy_radiance_bytes_ = radiance_bytes;
  }
  glossy_bytes_ = slots * GlossySlotBytes(int(m)) + size_t(node_count_) * sizeof(int);
  return node_slot;
}

bool Illumination::GlossyDirect(const DirectLighting& lighting) {
  if (glossy_leaves_ == 0) return false;
  const int m = bins_->count();
  // Every (glossy leaf, bin) evaluates every light: past kMaxGlossyWork the
  // glossy leaves reflect diffusely this time (Result::glossy_capped).
  const double work = double(glossy_leaves_) * double(m) *
                      double(std::max<size_t>(
                          1, size_t(lighting.punctual_count()) + lighting.area_samples().size()));
  if (work > kMaxGlossyWork) return false;
  // Each bin holds its mean radiance (the links look a bin up anywhere in
  // it): the lobes widened by the bin's solid angle.
  glossy_direct_->Run(lighting, glossy_elements_.id(), glossy_leaves_, bin_directions_.id(), m,
                      glossy_radiance_.id(), bins_->omega_bin());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GLOSSY_PULL_CHILDREN, children_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GLOSSY_PULL_AREAS, areas_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GLOSSY_PULL_NODE_SLOTS, node_slots_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GLOSSY_PULL_SLOT_NODES, slot_nodes_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GLOSSY_PULL_RADIANCE, glossy_radiance_.id());
  glossy_pull_.Set("uGlossyBins", m);
  glossy_pull_.Use();
  for (size_t h = 1; h < glossy_level_begin_.size(); ++h) {
    const int begin = glossy_level_begin_[h - 1], end = glossy_level_begin_[h];
    if (end <= begin) continue;
    glossy_pull_.Set("uBegin", begin);
    glossy_pull_.Set("uEnd", end);
    glDispatchCompute(gl::GroupCount(size_t(end - begin) * size_t(m), 64), 1, 1);
    glMemoryBarrier(kBarrier);
  }
  return true;
}

void Illumination::BindGlossy() {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GATHER_NODE_SLOTS, node_slots_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GATHER_GLOSSY_NODES, glossy_nodes_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GATHER_GLOSSY_RADIANCE, glossy_radiance_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GATHER_BIN_LUT,
                   bin_lut_ ? bin_lut_.id() : node_slots_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GATHER_LINK_BINS, link_bins_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_GATHER_RECEIVER_BINS, receiver_bins_.id());
  gather_.Set("uGlossyBins", glossy_on_ ? bins_->count() : 0);
  gather_.Set("uLutRes", bins_ ? bins_->lut_res() : 1);
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
  BindGlossy();
  gather_.Set("uLeafCount", leaf_count_);
  gather_.Use();
  glDispatchCompute(gl::GroupCount(size_t(leaf_count_), 64), 1, 1);
  glMemoryBarrier(kBarrier);
}

bool Illumination::DirectAtLeaves(const DirectLighting& lighting) {
  // The glossy leaves' direct light per bin first: the leaves' diffuse
  // radiance leaves it out only when it is there.
  glossy_on_ = GlossyDirect(lighting);
  // The first bounce's source: direct light (and environment) at the leaves.
  lighting.Bind(direct_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_LEAF_LEAVES, leaves_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_LEAF_DIRECT_E, e_direct_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_LEAF_ENV_E, e_env_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_LEAF_RADIANCE, radiance_[0].id());
  direct_.Set("uGlossy", glossy_on_ ? 1 : 0);
  direct_.Set("uLeafCount", leaf_count_);
  direct_.Use();
  glDispatchCompute(gl::GroupCount(size_t(leaf_count_), 64), 1, 1);
  glMemoryBarrier(kBarrier);
  Pull(radiance_[0].id());
  return !glossy_over_cap_ && (glossy_leaves_ == 0 || glossy_on_);
}

Illumination::Result Illumination::Run(const DirectLighting& lighting, int max_bounces,
                                       double tolerance, double tail_bound,
                                       const std::stop_token& stop) {
  Result result;
  if (leaf_count_ == 0) return result;
  result.glossy_capped = !DirectAtLeaves(lighting);

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
