// The illumination stage on the GPU (Dong et al. 2007, Section 4.3.1):
// leaves, pushed-down links and the node tree as shader storage buffers;
// direct light at the leaves from the shared shadow maps, then per bounce
// a gather at the leaves and a pull-up by height level, in GL compute.
// Glossy elements (Section 4.3, "we augment our bin structure and store
// the outgoing radiance per direction in it"): every glossy leaf (a
// non-Lambertian BRDF of roughness below 0.9), and every node above one,
// has a slot of directional bins
// (hierarchy/directional_bins.h) holding the direct light it reflects
// toward each bin, with its BRDF (shaders/implicit_visibility/glossy.glsl);
// a link adds its source's bin toward the receiver. Light that reaches a
// glossy leaf through links leaves it diffusely, with its white-sky albedo
// (the paper's GPU version keeps indirect interreflection diffuse).
#pragma once

#include <optional>
#include <stop_token>
#include <vector>

#include "gl/handle.h"
#include "gl/program.h"
#include "render/direct_lighting.h"
#include "render/glossy_bin_direct.h"
#include "solvers/hierarchy/cube_bins.h"
#include "solvers/hierarchy/directional_bins.h"
#include "solvers/hierarchy/elements.h"
#include "solvers/hierarchy/links.h"
#include "solvers/hierarchy/refine_push.h"
#include "solvers/shading/ggx.h"

namespace gistream {

class Illumination {
 public:
  // glossy_bins: the directional bins of the glossy elements (even,
  // 8..4096); 0: every leaf reflects diffusely with its white-sky albedo.
  static absl::StatusOr<Illumination> Create(int glossy_bins);

  // Uploads the tree (children, areas), the leaves' discs and the glossy
  // slots (from `brdf`, per leaf);
  // after update_elements or a material change.
  void UploadElements(const hierarchy::Elements& elements, const std::vector<glm::vec3>& albedo,
                      const std::vector<shading::Brdf>& brdf);
  // Uploads the leaves' links and the directions of `bins`, the receivers'
  // bins they fill (a glossy source is looked up toward the receiver along
  // its link's bin); after refine_push.
  void UploadLinks(const hierarchy::LeafLinks& links, const hierarchy::CubeBins& bins);
  // Environment irradiance through each leaf's open bins (zero: none).
  void UploadEnvironment(const std::vector<glm::vec3>& e_env);

  struct Result {
    int bounces = 0;
    // sum |dE| / sum |E| of the last bounce (luminance), or the tail's
    // TailResidual when that ended the solve (tail_stopped).
    double residual = 0.0;
    bool tail_stopped = false;   // ended once the tail-corrected sum was known
    bool monotone = true;        // no leaf's indirect luminance fell between bounces
    bool cap_reached = false;    // stopped by max_bounces with residual >= tolerance
    bool cancelled = false;      // stopped by `stop` (the frame's cancellation)
    bool tail_applied = false;   // the bounces not run were added (solvers/tail_estimate.h)
    double tail_ratio = 0.0;     // their ratio r (0: no tail)
    bool glossy_capped = false;  // glossy leaves reflected diffusely: too many x lights
  };
  // Direct light at the leaves, then gathers with pull-ups until a
  // bounce's residual is below `tolerance` (from the second bounce on; 0:
  // never), or with a tail the tail-corrected sum is known well within it
  // (TailSettled, as sh_probes), or `max_bounces` ran, or `stop` is
  // requested (checked every bounce). Leaves the indirect irradiance per
  // leaf in indirect().
  // `tail_bound` > 0: then adds the geometric tail of the bounces not run
  // (solvers/tail_estimate.h; its ratio at most `tail_bound`, the scene's
  // largest albedo): each leaf's indirect irradiance gets f x its last
  // increment, f from MonotoneTailFactor.
  Result Run(const DirectLighting& lighting, int max_bounces, double tolerance,
             double tail_bound = 0.0, const std::stop_token& stop = {});

  GLuint indirect() const { return e_indirect_.id(); }
  uint64_t gpu_bytes() const { return gpu_bytes_; }
  // Leaves with a glossy BRDF (with slots or not).
  int glossy_leaves() const { return glossy_found_; }
  int glossy_slots() const { return int(slot_node_.size()); }
  // The most (glossy leaf, bin, light) evaluations of the direct pass:
  // about 1 s on llvmpipe (ClearCoatTest's 20,430 glossy leaves x 128 bins
  // x 64 area samples took 14 s, the whole illumination otherwise 0.4 s,
  // and it runs on the render thread); glossy_box needs 37,632. Past it the
  // glossy leaves reflect diffusely that time (Result::glossy_capped); past
  // it with one light they get no slots.
  static constexpr double kMaxGlossyWork = 1e7;
  // Bytes of directional bins per glossy slot, for the memory estimate.
  static uint64_t GlossySlotBytes(int glossy_bins);

 private:
  // The first bounce's source: the glossy leaves' bins (GlossyDirect),
  // then every leaf's direct and environment light and its radiance,
  // pulled up. False when the glossy leaves reflect diffusely this time
  // for their cost (Result::glossy_capped).
  bool DirectAtLeaves(const DirectLighting& lighting);
  // One bounce: every leaf gathers over its links from radiance_[in] into
  // radiance_[1 - in] and e_indirect_.
  void Gather(int in);
  void Pull(GLuint radiance);
  // The glossy slots' bins: the direct light the glossy leaves reflect,
  // then pulled up to the nodes above them. False when there are none or
  // the pass would cost too much (the leaves then reflect diffusely).
  bool GlossyDirect(const DirectLighting& lighting);
  // Slots of the glossy leaves and of the nodes above them; their buffers.
  std::vector<int> UploadGlossy(const hierarchy::Elements& e,
                                const std::vector<shading::Brdf>& brdf);
  void BindGlossy();
  std::vector<glm::vec4> ReadIndirect() const;
  // e_indirect = current + f (current - previous), per leaf (RGB).
  void ApplyTail(const std::vector<glm::vec4>& current, const std::vector<glm::vec4>& previous,
                 double f);

  gl::Program direct_, gather_, pull_, glossy_pull_;
  gl::Buffer leaves_, children_, areas_, e_direct_, e_env_, offsets_, links_, e_indirect_;
  gl::Buffer radiance_[2];
  std::vector<int> level_begin_;
  int leaf_count_ = 0, node_count_ = 0;
  uint64_t element_bytes_ = 0, link_bytes_ = 0, gpu_bytes_ = 0;

  // Glossy elements (null bins_: none).
  std::optional<hierarchy::DirectionalBins> bins_;
  std::optional<GlossyBinDirect> glossy_direct_;
  gl::Buffer bin_directions_, bin_lut_;
  gl::Buffer node_slots_, slot_nodes_, glossy_nodes_, glossy_elements_, glossy_radiance_;
  gl::Buffer link_bins_, receiver_bins_;  // per link its bin, two per uint; bin directions
  std::vector<int> slot_node_;            // per slot: its node (leaves' slots first)
  std::vector<int> glossy_level_begin_;   // internal slots of height h: [begin[h-1], begin[h])
  int glossy_leaves_ = 0;                 // with slots
  int glossy_found_ = 0;
  bool glossy_over_cap_ = false;  // glossy leaves x bins alone pass the cap: no slots
  bool glossy_on_ = false;        // this illumination's glossy bins are filled
  size_t glossy_radiance_bytes_ = 0;
  uint64_t glossy_bytes_ = 0;
};

}  // namespace gistream
