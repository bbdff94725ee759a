#include "render/gbuffer.h"

#include <string>

#include "gl/buffers.h"
#include "gl/fault_injection.h"
#include "gl/textures.h"
#include "util/status.h"

namespace gistream {

absl::Status GBuffer::Resize(uint32_t width, uint32_t height) {
  if (width == width_ && height == height_ && fbo_) return absl::OkStatus();
  *this = GBuffer();  // free the old targets before allocating new ones
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  if (width == 0 || height == 0 || width > uint32_t(max_size) || height > uint32_t(max_size)) {
    return absl::ResourceExhaustedError(
        absl::StrCat("width x height: ", width, "x", height,
                     " is not a texture size this GPU offers (1 to ", max_size, " per side)"));
  }
  // Only this function's errors below; earlier ones were reported already.
  while (glGetError() != GL_NO_ERROR) {
  }
  const int w = int(width), h = int(height);
  position_ = gl::RenderTarget(GL_RGBA32F, w, h);
  normal_ = gl::RenderTarget(GL_RGBA16F, w, h);
  albedo_ = gl::RenderTarget(GL_RGBA8, w, h);
  emission_ = gl::RenderTarget(GL_RGBA32F, w, h);
  specular_ = gl::RenderTarget(GL_RGBA16F, w, h);
  depth_ = gl::RenderTarget(GL_DEPTH_COMPONENT32F, w, h);
  hdr_ = gl::RenderTarget(GL_RGBA32F, w, h, /*linear=*/true);
  ldr_ = gl::RenderTarget(GL_RGBA8, w, h);
  accumulation_ = gl::RenderTarget(GL_RGBA32F, w, h);
  history_ = gl::RenderTarget(GL_RGBA32F, w, h);
  carry_mean_ = gl::RenderTarget(GL_RGBA32F, w, h);
  carry_centre_ = gl::RenderTarget(GL_RGBA32F, w, h);
  previous_ = gl::RenderTarget(GL_RGBA32F, w, h);
  fbo_ = gl::FramebufferOf(
      {position_.id(), normal_.id(), albedo_.id(), emission_.id(), specular_.id()}, depth_.id());
  hdr_fbo_ = gl::FramebufferOf({hdr_.id()});
  ldr_fbo_ = gl::FramebufferOf({ldr_.id()});
  accumulation_fbo_ = gl::FramebufferOf({accumulation_.id()});
  history_fbo_ = gl::FramebufferOf({history_.id()});
  carry_mean_fbo_ = gl::FramebufferOf({carry_mean_.id()});
  carry_centre_fbo_ = gl::FramebufferOf({carry_centre_.id()});
  previous_fbo_ = gl::FramebufferOf({previous_.id()});
  view_ = gl::ZeroedBuffer(sizeof(glm::vec4));

  // Allocation failures are the client's size meeting this GPU's memory,
  // not a bug: an error status for the session, never an abort.
  const GLenum error = gl::AllocationError();
  bool complete = true;
  for (const gl::Framebuffer* f : {&fbo_, &hdr_fbo_, &ldr_fbo_, &accumulation_fbo_, &history_fbo_,
                                   &carry_mean_fbo_, &carry_centre_fbo_, &previous_fbo_}) {
    complete = complete &&
               glCheckNamedFramebufferStatus(f->id(), GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  }
  if (error != GL_NO_ERROR || !complete) {
    *this = GBuffer();
    const std::string why = error == GL_OUT_OF_MEMORY ? "GL_OUT_OF_MEMORY"
                            : error != GL_NO_ERROR ? absl::StrCat("GL error 0x", absl::Hex(error))
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

void GBuffer::SetEye(const glm::vec3& eye) {
  if (!view_) return;  // no targets (Resize failed or never ran)
  const glm::vec4 block(eye, 1.0f);
  gl::Upload(view_, std::span<const glm::vec4>(&block, 1));
}

void GBuffer::BeginShadePass() const {
  glBindFramebuffer(GL_FRAMEBUFFER, hdr_fbo_.id());
  glViewport(0, 0, GLsizei(width_), GLsizei(height_));
  glDisable(GL_DEPTH_TEST);
  BindTextures();
  glBindBufferBase(GL_UNIFORM_BUFFER, GS_UBO_VIEW, view_.id());
}

void GBuffer::BindTextures(GLuint first_unit) const {
  glBindTextureUnit(first_unit + 0, position_.id());
  glBindTextureUnit(first_unit + 1, normal_.id());
  glBindTextureUnit(first_unit + 2, albedo_.id());
  glBindTextureUnit(first_unit + 3, emission_.id());
  glBindTextureUnit(GS_UNIT_GBUFFER_SPECULAR, specular_.id());
}

}  // namespace gistream
