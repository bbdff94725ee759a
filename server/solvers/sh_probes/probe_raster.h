// sh_probes' rasterize_cubemaps pass (Nijasure et al. 2005, Section 4.1):
// each listed probe's cube-map G-buffer (distance, normal, albedo) drawn
// into its tiles of the ProbeAtlas. From the proxies (issue 19): per probe,
// per item and cluster node the coarsest copy within one face texel at the
// node's nearest distance, 2 d / face_size, into the faces that can see
// the node (render/proxy_filters: CubeFilters); `full_detail` draws the
// full meshes into every face, as before proxies.
//
// Submission (issue 19): one indirect draw list (scene/gpu/draw_list.h) per
// pass, a view per probe with a record per face that may see each node,
// its draws grouped by the textures they sample; each probe costs one
// glMultiDrawElementsIndirect per texture set, and the node instances of a
// mesh are instanced commands. Item by item (Options::draw_list off) is the
// reference the tests compare with.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "gl/handle.h"
#include "gl/program.h"
#include "scene/gpu/draw_list.h"
#include "scene/gpu/gpu_scene.h"
#include "solvers/sh_probes/probe_grid.h"

namespace gistream {

class ProbeRasterizer {
 public:
  struct Options {
    // The vertex shader writes the layer where the driver has
    // ARB_shader_viewport_layer_array; else (or off) a geometry shader.
    bool allow_layered = true;
    // Off: GpuScene::Draw item by item, per probe (the tests' reference).
    bool draw_list = true;
  };
  static absl::StatusOr<ProbeRasterizer> Create(const Options& options);
  static absl::StatusOr<ProbeRasterizer> Create() { return Create(Options{}); }

  // Clears and draws the tiles of `probes` (null: every probe of `layout`).
  void Draw(const GpuScene& gpu, const SceneState& state, const ProbeLayout& layout,
            const ProbeAtlas& atlas, const std::vector<int>* probes, bool full_detail);

  bool layered() const { return layered_; }

  // Probes per draw list upload (a solver's batch is smaller), and the
  // bytes such a list may take for `gpu` (MemoryEstimate).
  static constexpr size_t kProbesPerList = 16;
  static uint64_t ListBytes(const GpuScene& gpu);

 private:
  void DrawFromList(const GpuScene& gpu, const SceneState& state, const ProbeLayout& layout,
                    const std::vector<int>& probes, bool full_detail);
  void DrawItemByItem(const GpuScene& gpu, const SceneState& state, const ProbeLayout& layout,
                      const std::vector<int>& probes, bool full_detail);

  gl::Program program_;
  bool layered_ = false;
  bool draw_list_ = true;
  DrawList list_;  // a view per probe of the last Draw
};

}  // namespace gistream
