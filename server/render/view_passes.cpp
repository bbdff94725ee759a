#include "render/view_passes.h"
#include "gl/bindings.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace gistream {
namespace {

template <typename T>
std::vector<T> ReadTexture(GLuint texture, uint32_t width, uint32_t height, GLenum type) {
  const size_t row = size_t(width) * 4;
  std::vector<T> pixels(row * height);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(texture, 0, GL_RGBA, type, GLsizei(pixels.size() * sizeof(T)), pixels.data());
  // Flip to top-row-first.
  std::vector<T> tmp(row);
  for (uint32_t y = 0; y < height / 2; ++y) {
    T* a = pixels.data() + y * row;
    T* b = pixels.data() + (height - 1 - y) * row;
    std::memcpy(tmp.data(), a, row * sizeof(T));
    std::memcpy(a, b, row * sizeof(T));
    std::memcpy(b, tmp.data(), row * sizeof(T));
  }
  return pixels;
}

// A full-screen pass of the view into one of its G-buffer's targets
// (without blending; Tonemap's leaves blending as it is).
void BeginViewPass(GLuint fbo, const GBuffer& gbuffer) {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(0, 0, GLsizei(gbuffer.width()), GLsizei(gbuffer.height()));
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
}

}  // namespace

absl::StatusOr<ViewPasses> ViewPasses::Create() {
  ViewPasses passes;
  GS_ASSIGN_OR_RETURN(passes.gbuffer_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "render/gbuffer.vert.glsl"},
                                          {GL_FRAGMENT_SHADER, "render/gbuffer.frag.glsl"}},
                                         {"GS_DRAW_LIST"}));
  GS_ASSIGN_OR_RETURN(passes.sky_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                          {GL_FRAGMENT_SHADER, "render/sky.frag.glsl"}}));
  GS_ASSIGN_OR_RETURN(passes.tonemap_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                          {GL_FRAGMENT_SHADER, "render/tonemap.frag.glsl"}}));
  GS_ASSIGN_OR_RETURN(passes.copy_hdr_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                          {GL_FRAGMENT_SHADER, "render/copy_hdr.frag.glsl"}}));
  GS_ASSIGN_OR_RETURN(passes.show_refined_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                          {GL_FRAGMENT_SHADER, "render/show_refined.frag.glsl"}}));
  GS_ASSIGN_OR_RETURN(passes.keep_centre_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                          {GL_FRAGMENT_SHADER, "render/keep_centre.frag.glsl"}}));
  GS_ASSIGN_OR_RETURN(passes.keep_shown_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                          {GL_FRAGMENT_SHADER, "render/keep_shown.frag.glsl"}}));
  passes.non_finite_ = gl::Buffer::Create();
  glNamedBufferStorage(passes.non_finite_.id(), sizeof(GLuint), nullptr,
                       GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
  return passes;
}

absl::Status ViewPasses::DrawGBuffer(const SceneState& state, const GpuScene& gpu,
                                     const ViewCamera& camera, GBuffer& gbuffer) {
  GS_RETURN_IF_ERROR(gbuffer.Resize(camera.width, camera.height));
  gbuffer.SetEye(camera.position);
  glBindFramebuffer(GL_FRAMEBUFFER, gbuffer.fbo());
  glViewport(0, 0, GLsizei(camera.width), GLsizei(camera.height));
  const float zero[4] = {0, 0, 0, 0};
  for (GLint i = 0; i < 4; ++i) glClearBufferfv(GL_COLOR, i, zero);
  const float one = 1.0f;
  glClearBufferfv(GL_DEPTH, 0, &one);
  if (gpu.environment_texture() != 0) DrawSky(state, gpu, camera);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  // Clip planes from the glTF camera or the current geometry (camera.h).
  const ViewCamera view = WithDepthRange(camera, state, gpu.WorldBounds(state));
  gbuffer_.Set("uViewProj", view.Projection() * view.View());
  gbuffer_.Set("uEye", view.position);
  gbuffer_.Use();
  const ListKey key{state.serial(), state.version(), &gpu};
  if (key != gbuffer_list_key_) {
    const int no_tag = 0;
    gbuffer_list_.Clear();
    gbuffer_list_.AddView(gpu, state, nullptr, nullptr, no_tag, DrawTags::kValue,
                          DrawTextures::kBind);
    gbuffer_list_.Upload();
    gbuffer_list_key_ = key;
  }
  gbuffer_list_.Draw(gpu, 0);
  return absl::OkStatus();
}

void ViewPasses::DrawSky(const SceneState& state, const GpuScene& gpu, const ViewCamera& camera) {
  // Every pixel, before the geometry overwrites its own: no depth test (so
  // no depth write either).
  glDisable(GL_DEPTH_TEST);
  const float aspect = float(camera.width) / float(std::max<uint32_t>(camera.height, 1));
  const float t = std::tan(0.5f * camera.yfov);
  sky_.Set("uRight", camera.rotation * glm::vec3(t * aspect, 0.0f, 0.0f));
  sky_.Set("uUp", camera.rotation * glm::vec3(0.0f, t, 0.0f));
  sky_.Set("uForward", camera.rotation * glm::vec3(0.0f, 0.0f, -1.0f));
  sky_.Set("uJitter", camera.jitter);
  sky_.Set("uSize", glm::vec2(float(camera.width), float(camera.height)));
  sky_.Set("uRotation", state.environment_rotation());
  sky_.Set("uIntensity", state.environment_intensity());
  glBindTextureUnit(GS_UNIT_ENVIRONMENT, gpu.environment_texture());
  fullscreen_.Draw(sky_);
}

void ViewPasses::Accumulate(const GBuffer& gbuffer, uint32_t index) {
  const GLint w = GLint(gbuffer.width()), h = GLint(gbuffer.height());
  if (index == 0) {
    glBlitNamedFramebuffer(gbuffer.hdr_fbo(), gbuffer.accumulation_fbo(), 0, 0, w, h, 0, 0, w, h,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
    return;
  }
  // mean_{k+1} = mean_k + (x - mean_k) / (k + 1), by blending: source
  // weight a = 1 / (k + 1), destination 1 - a (a float target blends in
  // float).
  glBindFramebuffer(GL_FRAMEBUFFER, gbuffer.accumulation_fbo());
  glViewport(0, 0, w, h);
  glDisable(GL_DEPTH_TEST);
  glEnable(GL_BLEND);
  glBlendColor(0.0f, 0.0f, 0.0f, 1.0f / float(index + 1));
  glBlendFunc(GL_CONSTANT_ALPHA, GL_ONE_MINUS_CONSTANT_ALPHA);
  glBindTextureUnit(GS_UNIT_HDR, gbuffer.hdr());
  fullscreen_.Draw(copy_hdr_);
  glDisable(GL_BLEND);
}

void ViewPasses::KeepHistory(const GBuffer& gbuffer) {
  const GLint w = GLint(gbuffer.width()), h = GLint(gbuffer.height());
  glBlitNamedFramebuffer(gbuffer.hdr_fbo(), gbuffer.history_fbo(), 0, 0, w, h, 0, 0, w, h,
                         GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

void ViewPasses::KeepCentre(const GBuffer& gbuffer, const glm::vec3& eye) {
  BeginViewPass(gbuffer.history_fbo(), gbuffer);
  glBindTextureUnit(GS_UNIT_HDR, gbuffer.hdr());
  glBindTextureUnit(GS_UNIT_GBUFFER_POSITION, gbuffer.position());
  glBindTextureUnit(GS_UNIT_GBUFFER_EMISSION, gbuffer.emission());
  keep_centre_.Set("uEye", eye);
  fullscreen_.Draw(keep_centre_);
}

void ViewPasses::KeepShown(const GBuffer& gbuffer) {
  BeginViewPass(gbuffer.previous_fbo(), gbuffer);
  glBindTextureUnit(GS_UNIT_HDR, gbuffer.hdr());
  glBindTextureUnit(GS_UNIT_REFINE_HISTORY, gbuffer.history());
  fullscreen_.Draw(keep_shown_);
}

void ViewPasses::CaptureCarry(const GBuffer& gbuffer) {
  const GLint w = GLint(gbuffer.width()), h = GLint(gbuffer.height());
  glBlitNamedFramebuffer(gbuffer.accumulation_fbo(), gbuffer.carry_mean_fbo(), 0, 0, w, h, 0, 0, w,
                         h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBlitNamedFramebuffer(gbuffer.history_fbo(), gbuffer.carry_centre_fbo(), 0, 0, w, h, 0, 0, w, h,
                         GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

void ViewPasses::ShowAccumulation(const GBuffer& gbuffer, const Shown& shown) {
  const GLint w = GLint(gbuffer.width()), h = GLint(gbuffer.height());
  const bool carry = shown.carry_weight > 0.0f;
  const bool reproject = shown.reproject_weight > 0.0f;
  if (!(shown.history_weight > 0.0f) && !carry && !reproject) {
    glBlitNamedFramebuffer(gbuffer.accumulation_fbo(), gbuffer.hdr_fbo(), 0, 0, w, h, 0, 0, w, h,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
    return;
  }
  BeginViewPass(gbuffer.hdr_fbo(), gbuffer);
  glBindTextureUnit(GS_UNIT_REFINE_MEAN, gbuffer.accumulation());
  glBindTextureUnit(GS_UNIT_REFINE_HISTORY, gbuffer.history());
  glBindTextureUnit(GS_UNIT_CARRY_MEAN, gbuffer.carry_mean());
  glBindTextureUnit(GS_UNIT_CARRY_CENTRE, gbuffer.carry_centre());
  glBindTextureUnit(GS_UNIT_REPROJECT_PREVIOUS, gbuffer.previous());
  show_refined_.Set("uSamples", float(std::max(shown.samples, 1u)));
  show_refined_.Set("uHistoryWeight", reproject ? shown.reproject_weight
                                      : carry   ? shown.carry_weight
                                                : shown.history_weight);
  show_refined_.Set("uCarry", carry ? 1 : 0);
  show_refined_.Set("uReproject", reproject ? 1 : 0);
  show_refined_.Set("uPreviousViewProjection", shown.previous_view_projection);
  show_refined_.Set("uPreviousEye", shown.previous_eye);
  show_refined_.Set("uInverseViewProjection", shown.inverse_view_projection);
  show_refined_.Set("uEye", shown.eye);
  show_refined_.Set("uInvalidMin", shown.invalid_min);
  show_refined_.Set("uInvalidMax", shown.invalid_max);
  fullscreen_.Draw(show_refined_);
}

void ViewPasses::Tonemap(const GBuffer& gbuffer, float exposure_ev) {
  glBindFramebuffer(GL_FRAMEBUFFER, gbuffer.ldr_fbo());
  glViewport(0, 0, GLsizei(gbuffer.width()), GLsizei(gbuffer.height()));
  glDisable(GL_DEPTH_TEST);
  glBindTextureUnit(GS_UNIT_HDR, gbuffer.hdr());
  tonemap_.Set("uExposureScale", std::exp2(exposure_ev));
  const GLuint zero = 0;
  glNamedBufferSubData(non_finite_.id(), 0, sizeof(zero), &zero);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GS_BINDING_NON_FINITE, non_finite_.id());
  fullscreen_.Draw(tonemap_);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
}

uint32_t ViewPasses::NonFinitePixels() const {
  GLuint count = 0;
  glGetNamedBufferSubData(non_finite_.id(), 0, sizeof(count), &count);
  return count;
}

std::vector<float> ViewPasses::ReadHdr(const GBuffer& gbuffer) const {
  return ReadTexture<float>(gbuffer.hdr(), gbuffer.width(), gbuffer.height(), GL_FLOAT);
}

std::vector<uint8_t> ViewPasses::ReadLdr(const GBuffer& gbuffer) const {
  return ReadTexture<uint8_t>(gbuffer.ldr(), gbuffer.width(), gbuffer.height(), GL_UNSIGNED_BYTE);
}

}  // namespace gistream
