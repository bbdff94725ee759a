// sh_probes' rasterize_cubemaps pass (Nijasure et al. 2005, Section 4.1):
// each listed probe's cube-map G-buffer (distance, normal, albedo) drawn
// into its tiles of the ProbeAtlas. From the proxies (issue 19): per probe,
// per item and cluster node the coarsest copy within one face texel at the
// node's nearest distance, 2 d / face_size, into the faces that can see
// the node (render/proxy_filters: CubeFilters); `full_detail` draws every
// probe's faces from the full meshes in one instanced draw, as before
// proxies.
#pragma once

#include <vector>

#include "gl/handle.h"
#include "gl/program.h"
#include "scene/gpu_scene.h"
#include "solvers/sh_probes/probe_grid.h"

namespace gistream {

class ProbeRasterizer {
 public:
  // The layered vertex-shader program where the driver has
  // ARB_shader_viewport_layer_array (and `allow_layered`), else the
  // geometry-shader one.
  static absl::StatusOr<ProbeRasterizer> Create(bool allow_layered = true);

  // Clears and draws the tiles of `probes` (null: every probe of `layout`).
  void Draw(const GpuScene& gpu, const SceneState& state, const ProbeLayout& layout,
            const ProbeAtlas& atlas, const std::vector<int>* probes, bool full_detail);

  bool layered() const { return instances_per_probe_ == 6; }

 private:
  // Every listed probe in one instanced draw of the full meshes.
  void DrawFull(const GpuScene& gpu, const SceneState& state, const ProbeLayout& layout,
                const std::vector<int>* probes);
  // One draw per probe from the proxies, culled per face.
  void DrawProxies(const GpuScene& gpu, const SceneState& state, const ProbeLayout& layout,
                   const std::vector<int>& probes);

  gl::Program program_;
  int instances_per_probe_ = 1;  // 6: the layered vertex-shader variant
  gl::Buffer batch_;             // the listed probes (ints), for DrawFull
  size_t batch_capacity_ = 0;
};

}  // namespace gistream
