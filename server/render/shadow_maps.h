// Shadow maps shared by every solver: a cube-map array for point-like
// casters (point and spot lights, area-light samples, later VPLs), each
// drawn in one layered pass, and a 2D array for directional lights.
#pragma once

#include <vector>

#include "gl/handle.h"
#include "gl/program.h"
#include "scene/gpu/draw_list.h"
#include "scene/gpu/gpu_scene.h"

namespace gistream {

class ShadowMaps {
 public:
  static absl::StatusOr<ShadowMaps> Create();

  // (Re)allocates storage when the counts or the resolution change.
  void Allocate(int cube_count, int directional_count, int resolution);

  // Renders cube `index` around `position`; depth = distance / far. Each
  // item draws its coarsest proxy level within one texel's world size at
  // its distance, into the faces that can see it (render/proxy_filters.h),
  // in one indirect draw (scene/gpu/draw_list.h); `full_detail` draws every
  // item in full into every face.
  void RenderCube(const GpuScene& gpu, const SceneState& state, int index,
                  const glm::vec3& position, float far, bool full_detail = false);
  // Renders directional map `index` (proxies within one texel unless
  // `full_detail`); returns its view-projection matrix.
  glm::mat4 RenderDirectional(const GpuScene& gpu, const SceneState& state, int index,
                              const glm::vec3& direction, bool full_detail = false);

  // Binds the cube array to `cube_unit` and the 2D array to `dir_unit`.
  void Bind(GLuint cube_unit, GLuint dir_unit) const;

  int resolution() const { return resolution_; }
  const gl::Texture& cubes() const { return cubes_; }  // depth, 6 layers per cube
  uint64_t gpu_bytes() const;

 private:
  gl::Program cube_program_;
  gl::Program dir_program_;
  gl::Texture cubes_;
  gl::Texture directional_;
  gl::Framebuffer fbo_;
  DrawList list_;
  int cube_count_ = -1, dir_count_ = -1, resolution_ = 0;
};

// The distance-cube program (render/shadow_cube.*), drawn from a DrawList
// whose records' tags are faces (DrawTags::kEachBit of a face mask): the
// shadow cubes here and avg's VPL cubes.
absl::StatusOr<gl::Program> BuildShadowCubeProgram();

// Farthest distance from `p` to the scene bounds, the far plane of a caster.
float ShadowFar(const Bounds& bounds, const glm::vec3& p);

}  // namespace gistream
