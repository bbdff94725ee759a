// The VPLs on the GPU (an SSBO) and their low-resolution shadow maps (paper
// Sec. III-C): one paraboloid (hemisphere) map per VPL, all in one 2D
// array texture (the atlas, one layer per VPL). In full detail one
// instanced draw per scene draw item covers every VPL; with proxies each
// VPL draws its own cut of the proxy trees into a distance cube, which is
// then resampled into its map.
#pragma once

#include <utility>
#include <vector>

#include "gl/handle.h"
#include "avg/bindings.glsl"  // shaders/: the slots its passes declare
#include "gl/program.h"
#include "scene/gpu/draw_list.h"
#include "scene/gpu/gpu_scene.h"
#include "solvers/avg/vpl_tracer.h"

namespace gistream::avg {

class VplShadowMaps {
 public:
  static absl::StatusOr<VplShadowMaps> Create();

  // Uploads the VPLs (SSBO binding kVplBinding); far planes from `bounds`.
  void Upload(const std::vector<Vpl>& vpls, const Bounds& bounds);
  // Draws every VPL's map at `resolution`^2 (needs Upload first).
  void Render(const GpuScene& gpu, const SceneState& state, int resolution,
              bool full_detail = false);
  // Draws the maps of VPLs [first, first + count) only (a slice of a
  // re-map spread over frames); the other layers keep what they hold.
  // With proxies, each VPL draws a distance cube at `resolution`^2 per
  // face: per item and cluster node the coarsest copy within one face texel
  // at the node's nearest distance (2 d / N), only into the faces that may
  // see the node and face the VPL's hemisphere, nothing of nodes behind it
  // (render/proxy_filters.h); each map texel then takes the cube's distance
  // in its centre's direction (shaders/avg/vpl_resample.frag.glsl), 64 VPLs
  // a batch. A cube is linear, so big proxy triangles land where they
  // belong; a paraboloid map would bend their edges by up to (L / d)^2 / 8;
  // `full_detail` (or a scene without proxies) draws every triangle in one
  // instanced draw per item for the whole slice, as before proxies.
  void RenderRange(const GpuScene& gpu, const SceneState& state, int resolution, int first,
                   int count, bool full_detail = false);
  // Copies map layers of `from` (drawn for the same far planes) into this
  // atlas, (source layer, destination layer) pairs: the maps of VPLs an
  // incremental update kept (needs Upload first).
  void CopyLayers(const VplShadowMaps& from, const std::vector<std::pair<int, int>>& layers,
                  int resolution);
  // Binds the VPL buffer, and the maps to kShadowUnit.
  void Bind();

  int count() const { return count_; }
  // Whether any uploaded VPL reflects through a glossy lobe (the filter
  // then reconstructs every receiver with the tent).
  bool any_glossy() const { return any_glossy_; }
  const gl::Texture& maps() const { return maps_; }
  uint64_t gpu_bytes() const;

  // VPLs per batch of distance cubes for `vpls` VPLs at `resolution`: up
  // to 64, fewer where 64 cubes would pass 64 MiB (at most 1 cube).
  static int CubeBatch(int resolution, int vpls);
  // The bytes of that batch's cubes (32-bit depth, six faces each).
  static uint64_t CubeBatchBytes(int resolution, int vpls);

  // The slots its shaders declare (shaders/avg/bindings.glsl).
  static constexpr GLuint kVplBinding = AVG_BINDING_VPLS;
  static constexpr GLuint kShadowUnit = AVG_UNIT_VPL_SHADOWS;

 private:
  void Allocate(int layers, int resolution);
  // The proxy path of RenderRange: distance cubes, resampled.
  void RenderFromCubes(const GpuScene& gpu, const SceneState& state, int resolution, int first,
                       int count);

  gl::Program program_;       // every triangle as it is (full detail)
  gl::Program resample_;      // proxies: a batch of distance cubes into the maps
  gl::Program cube_program_;  // render/shadow_cube.{vert,geom,frag}
  gl::Texture cubes_;         // the batch's distance cubes (6 layers each)
  gl::Framebuffer cube_fbo_;
  DrawList list_;                             // a batch's VPL cubes, a view per VPL
  int cube_batch_ = 0, cube_resolution_ = 0;  // VPLs per batch (0: none yet)
  gl::Sampler depth_value_;
  gl::VertexArray empty_vao_;
  std::vector<float> fars_;  // each VPL's far plane
  gl::Buffer vpls_;
  std::vector<Vpl> cpu_vpls_;  // positions and normals for the per-VPL proxy filter
  gl::Texture maps_;
  gl::Framebuffer fbo_;
  int count_ = 0;
  bool any_glossy_ = false;
  int layers_ = 0, resolution_ = 0;
};

}  // namespace gistream::avg
