// sh_probes' progressive update after a change (docs/ARCHITECTURE.md,
// "Frames keep coming"): which probes are re-rendered next, and when the
// update has converged. Bookkeeping only, no GL.
//
// A sweep visits every probe once, in priority order: the probes whose
// cube maps see the change first, those that see more of it (a larger
// solid angle of their cube map) before those that see less, then the
// rest; ties nearer the camera first. A probe's work in a sweep is a
// bounce (interpolate, render, project: Gauss-Seidel over the grid,
// reading the newest coefficients of every probe), preceded by
// re-rasterizing its cube map and recomputing its texels' direct light
// when the change requires. Probes are grouped into
// batches of about kBatchUnits of work; the batches depend on the change
// and the order only, never on time, so the same change reaches the same
// solution however many frames it is spread over. Sweeps repeat until one
// changes the probes' L_00 by less than the tolerance (relative to their
// total) with no work flag left, or `max_sweeps` ran since the last change.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace gistream {

class ProbeSchedule {
 public:
  // Relative cost of a probe's work, measured on the Cornell box at the
  // defaults (6488 triangles, 64 area samples, llvmpipe): rasterizing its
  // cube map ~2 ms, its texels' direct light ~1.4 ms, a bounce ~0.3 ms.
  static constexpr int kRasterUnits = 7;
  static constexpr int kDirectUnits = 4;
  static constexpr int kBounceUnits = 1;
  static constexpr int kBatchUnits = 64;
  // A probe's whole sphere in Prioritize's unit (micro-steradians).
  static constexpr int32_t kWholeSphere = 12'566'370;  // 4 pi 1e6, truncated as the shader does

  struct Batch {
    std::vector<int> probes;  // in sweep order
    std::vector<int> raster;  // those whose cube maps are re-rasterized
    std::vector<int> direct;  // those whose direct light is recomputed
    int units = 0;
  };

  // `probes` probes in index order, nothing pending.
  void Reset(int probes);
  // A change: the next sweep starts now. `seen` is, per probe, how much of
  // its cube map sees the change (a solid angle, any unit; 0: none): the
  // probes that see more of it first, since their projections change most,
  // then by distance from `eye`, then by index.
  void Prioritize(const std::vector<int32_t>& seen, const std::vector<glm::vec3>& positions,
                  const glm::vec3& eye);
  void NeedRaster(int probe);  // and its direct light
  void NeedDirectAll();

  bool pending() const { return pending_; }
  // Whether a probe still waits for its cube maps to be re-rasterized.
  bool raster_pending() const;
  // The next batch of the sweep (empty when nothing is pending).
  Batch Peek() const;
  // Marks Peek()'s batch done: `change` is the sum over its valid probes of
  // |L_00 luminance - its value before|; at the end of a sweep `total` (the
  // sum of |L_00 luminance| over valid probes) decides whether another
  // sweep runs.
  void Done(const Batch& batch, double change, double total, double tolerance, int max_sweeps);

  int probes() const { return int(order_.size()); }
  int remaining() const { return pending_ ? probes() - next_ : 0; }
  int sweeps() const { return sweeps_; }                     // since the last change
  double last_sweep_change() const { return last_change_; }  // relative
  bool cap_reached() const { return cap_reached_; }

 private:
  int Units(int probe) const;
  bool AnyFlag() const;

  std::vector<int> order_;
  std::vector<uint8_t> raster_, direct_;
  size_t next_ = 0;
  bool pending_ = false;
  int sweeps_ = 0;
  double change_ = 0.0;
  double last_change_ = 0.0;
  bool cap_reached_ = false;
};

}  // namespace gistream
