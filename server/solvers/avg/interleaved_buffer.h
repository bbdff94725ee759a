// Render targets of interleaved sampling (paper Sec. III-C, after Keller &
// Heidrich 2001 and Segovia et al. 2006): the image split into 4 x 4 tiles
// of ceil(w / 4) x ceil(h / 4) pixels; pixel (x, y) lives in tile
// (x mod 4, y mod 4) at (x / 4, y / 4). Two RGBA32F targets: indirect and
// direct irradiance.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "gl/handle.h"

namespace gistream::avg {

class InterleavedBuffer {
 public:
  static constexpr int kSide = 4;  // 4 x 4 = 16 VPL subsets

  void Resize(uint32_t width, uint32_t height);
  GLuint fbo() const { return fbo_.id(); }
  GLuint indirect() const { return indirect_.id(); }
  GLuint direct() const { return direct_.id(); }
  glm::ivec2 tile() const { return tile_; }
  glm::ivec2 split_size() const { return tile_ * kSide; }
  uint64_t gpu_bytes() const;

 private:
  uint32_t width_ = 0, height_ = 0;
  glm::ivec2 tile_{0};
  gl::Texture indirect_, direct_;
  gl::Framebuffer fbo_;
};

}  // namespace gistream::avg
