// The GPU deformation pass: morphs and skins the vertices of every node
// instance whose mesh deforms (SceneState::Deforms) into that instance's
// own range of GpuScene's vertex buffer, which every rasterising pass
// (G-buffer, shadow maps, probe and VPL passes) then draws. The formulas
// are scene/state/deform.h's, the CPU reference it is tested against
// (tests/gl/gpu_deform_test.cpp); shaders/scene/deform.comp.glsl.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "gl/bindings.h"
#include "gl/handle.h"
#include "gl/program.h"
#include "scene/state/scene_state.h"
#include "util/status.h"

namespace gistream {

struct DrawItem;

class GpuDeform {
 public:
  // The skin and morph-target data of the deforming draws among `draws`.
  static absl::StatusOr<std::unique_ptr<GpuDeform>> Create(const SceneState& state,
                                                           std::span<const DrawItem> draws);

  // Poses every deforming draw from `state` (its nodes' joints and morph
  // weights) into `vertices` (GpuScene's interleaved buffer).
  void Run(const SceneState& state, GLuint vertices);

  size_t draw_count() const { return jobs_.size(); }
  uint64_t gpu_bytes() const { return gpu_bytes_; }

 private:
  struct Job {
    int node = 0;
    uint32_t count = 0;  // vertices
    uint32_t src = 0;    // rest-pose vertices
    uint32_t dst = 0;    // posed vertices
    int32_t skin = -1;   // first SkinVertex, -1: not skinned
    uint32_t morph = 0;  // first delta
    uint32_t targets = 0;
  };

  gl::Program program_;
  gl::Buffer skin_;
  gl::Buffer morph_;
  gl::Buffer joints_;   // per frame: joint and normal matrices of every job
  gl::Buffer weights_;  // per frame: morph weights of every job
  size_t joint_capacity_ = 0;
  size_t weight_capacity_ = 0;
  std::vector<Job> jobs_;
  uint64_t gpu_bytes_ = 0;
};

}  // namespace gistream
