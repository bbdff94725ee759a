#include "render/gbuffer.h"

#include <string>

#include "gl/fault_injection.h"
#include "util/status.h"

namespace gistream {
namespace {
gl::Texture Target(GLenum format, uint32_t w, uint32_t h) {
  gl::Texture t = gl::Texture::Create(GL_TEXTURE_2D);
  glTextureStorage2D(t.id(), 1, format, GLsizei(w), GLsizei(h));
  glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}
}  // namespace

absl::Status GBuffer::Resize(uint32_t width, uint32_t height) {
  if (width == width_ && height == height_ && fbo_) return absl::OkStatus();
  *this = GBuffer();  // free the old targets before allocating new ones
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  if (width == 0 || height == 0 || width > uint32_t(max_size) || height > uint32_t(max_size)) {
    return absl::ResourceExhaustedError(absl::StrCat("width x height: ", width, "x", height,
                                                     " is not a texture size this GPU offers (1 to ",
                                                     max_size, " per side)"));
  }
  // Only this function's errors below; earlier ones were reported already.
  while (glGetError() != GL_NO_ERROR) {
  }
  position_ = Target(GL_RGBA32F, width, height);
  normal_ = Target(GL_RGBA16F, width, height);
  albedo_ = Target(GL_RGBA8, width, height);
  emission_ = Target(GL_RGBA32F, width, height);
  depth_ = Target(GL_DEPTH_COMPONENT32F, width, height);
  hdr_ = Target(GL_RGBA32F, width, height);
  glTextureParameteri(hdr_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(hdr_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  ldr_ = Target(GL_RGBA8, width, height);

  fbo_ = gl::Framebuffer::Create();
  glNamedFramebufferTexture(fbo_.id(), GL_COLOR_ATTACHMENT0, position_.id(), 0);
  glNamedFramebufferTexture(fbo_.id(), GL_COLOR_ATTACHMENT1, normal_.id(), 0);
  glNamedFramebufferTexture(fbo_.id(), GL_COLOR_ATTACHMENT2, albedo_.id(), 0);
  glNamedFramebufferTexture(fbo_.id(), GL_COLOR_ATTACHMENT3, emission_.id(), 0);
  glNamedFramebufferTexture(fbo_.id(), GL_DEPTH_ATTACHMENT, depth_.id(), 0);
  const GLenum draw[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                          GL_COLOR_ATTACHMENT3};
  glNamedFramebufferDrawBuffers(fbo_.id(), 4, draw);
  hdr_fbo_ = gl::Framebuffer::Create();
  glNamedFramebufferTexture(hdr_fbo_.id(), GL_COLOR_ATTACHMENT0, hdr_.id(), 0);
  ldr_fbo_ = gl::Framebuffer::Create();
  glNamedFramebufferTexture(ldr_fbo_.id(), GL_COLOR_ATTACHMENT0, ldr_.id(), 0);

  // Allocation failures are the client's size meeting this GPU's memory,
  // not a bug: an error status for the session, never an abort.
  const GLenum error = gl::AllocationError();
  bool complete = true;
  for (const gl::Framebuffer* f : {&fbo_, &hdr_fbo_, &ldr_fbo_}) {
    complete = complete &&
               glCheckNamedFramebufferStatus(f->id(), GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  }
  if (error != GL_NO_ERROR || !complete) {
    *this = GBuffer();
    const std::string why = error == GL_OUT_OF_MEMORY ? "GL_OUT_OF_MEMORY"
                            : error != GL_NO_ERROR    ? absl::StrCat("GL error 0x", absl::Hex(error))
                                                      : "incomplete framebuffer";
    return absl::ResourceExhaustedError(
        absl::StrCat("width x height: ", width, "x", height, " needs ",
                     (uint64_t(width) * height * kBytesPerPixel) >> 20,
                     " MiB of G-buffer, which the GPU could not allocate (", why, ")"));
  }
  width_ = width;
  height_ = height;
  return absl::OkStatus();
}

void GBuffer::BeginShadePass() const {
  glBindFramebuffer(GL_FRAMEBUFFER, hdr_fbo_.id());
  glViewport(0, 0, GLsizei(width_), GLsizei(height_));
  glDisable(GL_DEPTH_TEST);
  BindTextures();
}

void GBuffer::BindTextures(GLuint first_unit) const {
  glBindTextureUnit(first_unit + 0, position_.id());
  glBindTextureUnit(first_unit + 1, normal_.id());
  glBindTextureUnit(first_unit + 2, albedo_.id());
  glBindTextureUnit(first_unit + 3, emission_.id());
}

}  // namespace gistream
