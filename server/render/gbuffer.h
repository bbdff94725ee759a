// Per-view G-buffer: world position (w = 1 on geometry), normal, albedo
// (a: metallic), emission (a: roughness), specular (rgb: dielectric F0, a:
// F90), depth, and the eye it was drawn
// from; plus the HDR radiance target the solvers shade into and
// the 8-bit target tone mapping writes, and the mean of a view's
// refinement samples with the history kept across a change, the
// anti-aliasing carried across one, and the last picture shown, which a
// camera move reprojects (render/refinement.h).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "gl/bindings.h"
#include "gl/handle.h"
#include "util/status.h"

namespace gistream {

class GBuffer {
 public:
  // (Re)allocates the targets. RESOURCE_EXHAUSTED naming the size when it
  // exceeds the GPU's largest texture or the GPU cannot allocate it
  // (GL_OUT_OF_MEMORY, incomplete framebuffer); the G-buffer is then empty.
  absl::Status Resize(uint32_t width, uint32_t height);
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  // Bytes its textures hold: position RGBA32F, normal RGBA16F, albedo RGBA8,
  // emission RGBA32F, specular RGBA16F, depth 32F, hdr RGBA32F, ldr RGBA8,
  // accumulation RGBA32F, history RGBA32F, carry mean and centre RGBA32F,
  // previous RGBA32F = 156 per pixel.
  uint64_t gpu_bytes() const { return uint64_t(width_) * height_ * kBytesPerPixel; }
  static constexpr uint64_t kBytesPerPixel =
      16 + 8 + 4 + 16 + 8 + 4 + 16 + 4 + 16 + 16 + 16 + 16 + 16;

  GLuint fbo() const { return fbo_.id(); }          // the four G-buffer targets + depth
  GLuint hdr_fbo() const { return hdr_fbo_.id(); }  // the radiance target
  GLuint position() const { return position_.id(); }
  GLuint normal() const { return normal_.id(); }
  GLuint albedo() const { return albedo_.id(); }
  GLuint emission() const { return emission_.id(); }
  GLuint specular() const { return specular_.id(); }
  GLuint depth() const { return depth_.id(); }
  GLuint hdr() const { return hdr_.id(); }
  GLuint ldr_fbo() const { return ldr_fbo_.id(); }  // tone-mapped RGBA8
  GLuint ldr() const { return ldr_.id(); }
  GLuint accumulation_fbo() const { return accumulation_fbo_.id(); }  // refinement mean
  GLuint accumulation() const { return accumulation_.id(); }
  GLuint history_fbo() const { return history_fbo_.id(); }  // the picture before a change
  GLuint history() const { return history_.id(); }
  // The last complete picture's mean and its pixel-centre sample, whose
  // difference is the anti-aliasing carried across a change (the history
  // target then holds the current accumulation's pixel-centre sample).
  GLuint carry_mean_fbo() const { return carry_mean_fbo_.id(); }
  GLuint carry_mean() const { return carry_mean_.id(); }
  GLuint carry_centre_fbo() const { return carry_centre_fbo_.id(); }
  GLuint carry_centre() const { return carry_centre_.id(); }
  // The picture shown before a camera move, with the distance from that
  // camera's eye to the surface each pixel showed in alpha (0: background).
  GLuint previous_fbo() const { return previous_fbo_.id(); }
  GLuint previous() const { return previous_.id(); }

  // Binds position/normal/albedo/emission to texture units first..first+3
  // (shaders/render/gbuffer_read.glsl reads them at GS_UNIT_GBUFFER) and
  // specular to GS_UNIT_GBUFFER_SPECULAR.
  void BindTextures(GLuint first_unit = GS_UNIT_GBUFFER) const;
  // The eye the G-buffer was drawn from (glossy surfaces' view direction;
  // render/view_passes sets it with each G-buffer pass).
  void SetEye(const glm::vec3& eye);
  // Starts a solver's final shading pass: the HDR target bound with the
  // view's viewport, no depth test, the G-buffer textures bound and the eye
  // as uniform block GS_UBO_VIEW. The pass itself is a gl::FullscreenPass draw.
  void BeginShadePass() const;

 private:
  uint32_t width_ = 0, height_ = 0;
  gl::Texture position_, normal_, albedo_, emission_, specular_, depth_, hdr_, ldr_, accumulation_,
      history_, carry_mean_, carry_centre_, previous_;
  gl::Framebuffer fbo_, hdr_fbo_, ldr_fbo_, accumulation_fbo_, history_fbo_, carry_mean_fbo_,
      carry_centre_fbo_, previous_fbo_;
  gl::Buffer view_;  // std140 { vec4 eye; }
};

}  // namespace gistream
