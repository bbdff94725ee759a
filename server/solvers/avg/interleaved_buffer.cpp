#include "solvers/avg/interleaved_buffer.h"

#include "gl/textures.h"

namespace gistream::avg {

void InterleavedBuffer::Resize(uint32_t width, uint32_t height) {
  if (fbo_ && width == width_ && height == height_) return;
  width_ = width;
  height_ = height;
  tile_ = glm::ivec2((int(width) + kSide - 1) / kSide, (int(height) + kSide - 1) / kSide);
  const glm::ivec2 size = split_size();
  indirect_ = gl::RenderTarget(GL_RGBA32F, size.x, size.y);
  direct_ = gl::RenderTarget(GL_RGBA32F, size.x, size.y);
  fbo_ = gl::FramebufferOf({indirect_.id(), direct_.id()});
}

uint64_t InterleavedBuffer::gpu_bytes() const {
  const glm::ivec2 size = split_size();
  return 2ull * uint64_t(size.x) * uint64_t(size.y) * 16ull;
}

}  // namespace gistream::avg
