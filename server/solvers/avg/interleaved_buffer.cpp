#include "solvers/avg/interleaved_buffer.h"

namespace gistream::avg {

void InterleavedBuffer::Resize(uint32_t width, uint32_t height) {
  if (fbo_ && width == width_ && height == height_) return;
  width_ = width;
  height_ = height;
  tile_ = glm::ivec2((int(width) + kSide - 1) / kSide, (int(height) + kSide - 1) / kSide);
  const glm::ivec2 size = split_size();
  auto target = [&] {
    gl::Texture t = gl::Texture::Create(GL_TEXTURE_2D);
    glTextureStorage2D(t.id(), 1, GL_RGBA32F, size.x, size.y);
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
  };
  indirect_ = target();
  direct_ = target();
  fbo_ = gl::Framebuffer::Create();
  glNamedFramebufferTexture(fbo_.id(), GL_COLOR_ATTACHMENT0, indirect_.id(), 0);
  glNamedFramebufferTexture(fbo_.id(), GL_COLOR_ATTACHMENT1, direct_.id(), 0);
  const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(fbo_.id(), 2, buffers);
}

uint64_t InterleavedBuffer::gpu_bytes() const {
  const glm::ivec2 size = split_size();
  return 2ull * uint64_t(size.x) * uint64_t(size.y) * 16ull;
}

}  // namespace gistream::avg
