// The view-dependent passes every frame shares, whatever the solver:
// G-buffer rasterization, refinement accumulation, tone mapping, readback.
#pragma once

#include <vector>

#include "gl/fullscreen_pass.h"
#include "gl/program.h"
#include "render/camera.h"
#include "render/gbuffer.h"
#include "scene/gpu/draw_list.h"
#include "scene/gpu/gpu_scene.h"

namespace gistream {

class ViewPasses {
 public:
  static absl::StatusOr<ViewPasses> Create();

  // Resizes `gbuffer` to the camera (RESOURCE_EXHAUSTED when the GPU cannot
  // hold it, see GBuffer::Resize) and rasterises the scene into it: one
  // indirect multi-draw per set of material textures (scene/gpu/draw_list.h),
  // so many primitives or instances cost what their triangles cost, not a
  // draw call each (issue 30). The list is rebuilt only when the scene's
  // state changes (its serial and version), not per refinement sample.
  // Where no geometry covers a pixel, the environment's radiance along its
  // ray is the background's emission (shaders/render/sky.frag.glsl), as
  // pathtrace's camera rays see it; black without an environment.
  absl::Status DrawGBuffer(const SceneState& state, const GpuScene& gpu, const ViewCamera& camera,
                           GBuffer& gbuffer);
  // Refinement (render/refinement.h): folds the HDR radiance just shaded
  // into the accumulation as its sample `index` (0 starts it: a copy;
  // then a running mean, weight 1 / (index + 1)). ShowAccumulation then
  // puts the picture into the HDR target.
  void Accumulate(const GBuffer& gbuffer, uint32_t index);
  // The picture shown so far (the HDR target) becomes the history, before
  // a sample is shaded over it.
  void KeepHistory(const GBuffer& gbuffer);
  // Carried anti-aliasing (render/refinement.h): the pixel-centre sample
  // just shaded (the HDR target; in alpha the distance from `eye` to the
  // G-buffer's surface) is kept in the history target; CaptureCarry keeps
  // the complete mean and that centre as the carried pair.
  void KeepCentre(const GBuffer& gbuffer, const glm::vec3& eye);
  void CaptureCarry(const GBuffer& gbuffer);
  // Reprojection across a camera move (render/refinement.h): the picture
  // shown (the HDR target), with its centre sample's distance from its
  // camera's eye in alpha (KeepCentre's, in the history target), becomes
  // the previous picture, before the new camera's first sample is shaded.
  void KeepShown(const GBuffer& gbuffer);
  // What the view shows, into the HDR target for tone mapping and
  // readback: the mean of the accumulation's `samples` samples, with the
  // history at `history_weight` samples where it is valid
  // (shaders/render/show_refined.frag.glsl), or the carried picture at
  // `carry_weight` samples, or the previous picture reprojected from the
  // camera `previous_view_projection` (eye `previous_eye`) at
  // `reproject_weight` samples; the mean alone when all weights are 0.
  struct Shown {
    uint32_t samples = 1;
    float history_weight = 0.0f;
    glm::ivec2 invalid_min{0}, invalid_max{0};  // pixels without history
    float carry_weight = 0.0f;
    float reproject_weight = 0.0f;
    glm::mat4 previous_view_projection{1.0f};
    glm::vec3 previous_eye{0.0f};
    glm::mat4 inverse_view_projection{1.0f};  // this view's, without jitter
    glm::vec3 eye{0.0f};
  };
  void ShowAccumulation(const GBuffer& gbuffer, const Shown& shown);
  // HDR radiance -> gbuffer.ldr(): exposure 2^ev, filmic curve, sRGB.
  // Also counts the HDR pixels that are not finite (NonFinitePixels).
  void Tonemap(const GBuffer& gbuffer, float exposure_ev);
  // Pixels of the last Tonemap's HDR input with a NaN or Inf channel (the
  // tone map draws them black). Reads 4 bytes back; call after the LDR
  // readback, which has waited for the pass already.
  uint32_t NonFinitePixels() const;

  // Readbacks, rows top first (GL stores them bottom first).
  std::vector<float> ReadHdr(const GBuffer& gbuffer) const;    // RGBA float
  std::vector<uint8_t> ReadLdr(const GBuffer& gbuffer) const;  // RGBA8

 private:
  void DrawSky(const SceneState& state, const GpuScene& gpu, const ViewCamera& camera);

  gl::Program gbuffer_;
  gl::Program sky_;  // the G-buffer's environment background
  // The G-buffer's draw list, and the state it was made from.
  DrawList gbuffer_list_;
  struct ListKey {
    uint64_t serial = 0, version = 0;
    const GpuScene* gpu = nullptr;
    bool operator==(const ListKey&) const = default;
  };
  ListKey gbuffer_list_key_;
  gl::Program tonemap_;
  gl::Program copy_hdr_;      // the HDR target's texels, for accumulation
  gl::Program show_refined_;  // the mean with the history
  gl::Program keep_centre_;   // a centre sample with its surface's distance
  gl::Program keep_shown_;    // the picture shown with its centres' distances
  gl::FullscreenPass fullscreen_;
  gl::Buffer non_finite_;  // one uint, SSBO binding 7 of the tone map
};

}  // namespace gistream
