// The illumination stage on the GPU (Dong et al. 2007, Section 4.3.1):
// leaves, pushed-down links and the node tree as shader storage buffers;
// direct light at the leaves from the shared shadow maps, then per bounce
// a gather at the leaves and a pull-up by height level, in GL compute.
#pragma once

#include <stop_token>

#include <vector>

#include "gl/handle.h"
#include "gl/program.h"
#include "render/direct_lighting.h"
#include "solvers/hierarchy/elements.h"
#include "solvers/hierarchy/links.h"
#include "solvers/hierarchy/refine_push.h"

namespace gistream {

class Illumination {
 public:
  static absl::StatusOr<Illumination> Create();

  // Uploads the tree (children, areas) and the leaves' discs; after
  // update_elements.
  void UploadElements(const hierarchy::Elements& elements, const std::vector<glm::vec3>& albedo);
  // Uploads the leaves' links; after refine_push.
  void UploadLinks(const hierarchy::LeafLinks& links);
  // Environment irradiance through each leaf's open bins (zero: none).
  void UploadEnvironment(const std::vector<glm::vec3>& e_env);

  struct Result {
    int bounces = 0;
    // sum |dE| / sum |E| of the last bounce (luminance), or the tail's
    // TailResidual when that ended the solve (tail_stopped).
    double residual = 0.0;
    bool tail_stopped = false;  // ended once the tail-corrected sum was known
    bool monotone = true;       // no leaf's indirect luminance fell between bounces
    bool cap_reached = false;   // stopped by max_bounces with residual >= tolerance
    bool cancelled = false;     // stopped by `stop` (the frame's cancellation)
    bool tail_applied = false;  // the bounces not run were added (solvers/tail_estimate.h)
    double tail_ratio = 0.0;    // their ratio r (0: no tail)
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

 private:
  // One bounce: every leaf gathers over its links from radiance_[in] into
  // radiance_[1 - in] and e_indirect_.
  void Gather(int in);
  void Pull(GLuint radiance);
  std::vector<glm::vec4> ReadIndirect() const;
  // e_indirect = current + f (current - previous), per leaf (RGB).
  void ApplyTail(const std::vector<glm::vec4>& current, const std::vector<glm::vec4>& previous,
                 double f);

  gl::Program direct_, gather_, pull_;
  gl::Buffer leaves_, children_, areas_, e_direct_, e_env_, offsets_, links_, e_indirect_;
  gl::Buffer radiance_[2];
  std::vector<int> level_begin_;
  int leaf_count_ = 0, node_count_ = 0;
  uint64_t element_bytes_ = 0, link_bytes_ = 0, gpu_bytes_ = 0;
};

}  // namespace gistream
