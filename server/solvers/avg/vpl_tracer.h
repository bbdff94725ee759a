// Instant radiosity's light paths through the approximate visibility grid
// (paper Sec. III-B): rays leave the lights (cosine-distributed over
// emissive surfaces, by intensity for point and spot lights, parallel for
// directional lights), are marched through the voxels, leave a VPL at each
// hit and continue by cosine sampling up to `bounces` times. Paths end as
// in Keller's instant radiosity (1997, Sec. 3): of N paths, the first
// round(N rho-bar^b) (in index order) go on after b reflections, rho-bar the
// scene's mean albedo, so the VPL budget sets N and the total flux is
// exact, not a roulette's noise. Runs on the CPU (multi-threaded over paths).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/avg/vpl_lights.h"
#include "solvers/avg/voxel_grid.h"
#include "solvers/shading/ggx.h"

namespace gistream::avg {

struct Vpl {
  glm::vec3 position{0.0f};  // on the voxel's mean surface plane, nudged off it
  glm::vec3 normal{0.0f};    // unit, facing the side the light came from
  glm::vec3 flux{0.0f};      // reflected power (W): incident flux x voxel albedo
  int bounce = 1;            // 1: first indirect bounce (lit directly by a light)
  // Where its light came from (unit, away from the surface) and the
  // voxel's BRDF: a glossy VPL reflects its flux in the BRDF's lobe around
  // the mirror direction (shaders/avg/vpl.glsl VplEmission), a Lambertian
  // one with the cosine.
  glm::vec3 incident{0.0f, 0.0f, 1.0f};
  shading::Brdf brdf;
};

struct VplTraceSettings {
  int vpls = 1024;       // VPLs at most (sets N: see SplitCounts)
  int bounces = 8;       // VPL generations per path at most (1..kMaxBounces)
  bool roulette = true;  // paths end by Keller's split (else all run `bounces`)
  int threads = 0;       // 1: on the calling thread; else the CPU pool
  // > 0: when `bounces` cut the split's generations short, the last
  // generation's VPLs also carry the generations not traced, the
  // geometric tail of the measured per-bounce flux (solvers/
  // tail_estimate.h), its ratio at most this (the largest albedo); 0: no.
  double tail_bound = 0.0;
  // Path i takes point i + sample_offset of the quasi-random sequence: a
  // still view's second set of paths (AvgSolver, `still_vpls`) goes on
  // where the first set's N paths ended, so the two are one sequence.
  uint64_t sample_offset = 0;
  // With the split paths end on their own (N rho-bar^b of them reach
  // bounce b), so the cap only bounds stiff scenes' paths.
  static constexpr int kMaxBounces = 1024;
};

struct VplTraceResult {
  std::vector<Vpl> vpls;
  uint64_t paths = 0;    // light paths used (the estimator's N)
  uint64_t escaped = 0;  // paths whose first ray left the grid
  glm::vec3 light_power{0.0f};
  std::vector<uint32_t> path_first;  // per used path, the index of its first VPL
  // An incremental trace (RetraceVpls): cached paths kept and retraced,
  // the VPLs of the used paths among each, and new paths traced.
  uint64_t kept_paths = 0, retraced_paths = 0, new_paths = 0;
  uint64_t kept_vpls = 0, retraced_vpls = 0;
  double tail_ratio = 0.0;  // the tail's ratio r (0: none added)
};

// One ray of a light path as marched: from `origin` along `dir` to the far
// side of the voxel it hit (t_end), or out of the grid (t_end infinite).
struct VplRay {
  glm::vec3 origin{0.0f}, dir{0.0f};
  float t_end = 0.0f;
};

// One light path as traced, with what it depends on.
struct VplPath {
  std::vector<Vpl> vpls;     // flux not yet divided by its bounce's path count
  std::vector<VplRay> rays;  // every ray it marched
  bool escaped = false;      // its first ray left the grid
};

// The paths behind the last trace (paths 0..N-1 in index order), the
// lights they started from and the split they were traced for: an
// incremental trace keeps the ones the change left valid.
struct VplPathCache {
  std::vector<VplPath> paths;
  std::vector<VplLight> lights;
  std::vector<uint64_t> counts;  // SplitCounts they were traced for
};

// Keller's split for a budget of `vpls` VPLs: counts[b] paths reach
// bounce b + 1 (counts[0] = N, counts[b] = round(N rho^b) while positive,
// at most `bounces` entries), N the largest whose counts sum to at most
// `vpls`. Empty when nothing fits.
std::vector<uint64_t> SplitCounts(int vpls, int bounces, float mean_albedo);

// Traces from scratch; with `cache`, it keeps the paths.
VplTraceResult TraceVpls(const VoxelGrid& grid, const std::vector<VplLight>& lights,
                         const VplTraceSettings& settings, VplPathCache* cache = nullptr);

// Incremental instant radiosity (Laine et al. 2007, Sec. 3, for moving
// geometry): `grid` differs from the one `cache` was traced on only inside
// `changed` (VoxelGrid::rewritten()). A cached path none of whose rays
// comes within a voxel of `changed` marches through the same voxels to the
// same hits, so it is kept as it is; the others are retraced (same path
// index, same random numbers) and the paths packed again in index order.
// The result equals TraceVpls on `grid` bitwise. Different lights (an
// emitter moved) retrace everything.
VplTraceResult RetraceVpls(const VoxelGrid& grid, const std::vector<VplLight>& lights,
                           const VplTraceSettings& settings, const Bounds& changed,
                           VplPathCache& cache);

// Two traces of the same lights and grid as one estimate (a still view's
// VPLs, AvgSolver `still_vpls`): each is an unbiased estimate of the
// light's VPLs, so their union with every VPL's flux weighted by its set's
// share of the paths, N_a / (N_a + N_b) and N_b / (N_a + N_b), is one of
// N_a + N_b paths. `b`'s paths follow `a`'s (path_first shifted); `a`'s
// VPLs count as kept, `b`'s as new.
VplTraceResult JoinTraces(const VplTraceResult& a, const VplTraceResult& b);
// A still view's VPLs: `second.vpls` more traced after `first`'s paths in
// the quasi-random sequence (sample_offset = first.paths) and joined to
// `first`.
VplTraceResult TraceSecondSet(const VoxelGrid& grid, const std::vector<VplLight>& lights,
                              VplTraceSettings second, const VplTraceResult& first);
// Whether a ray of `path` passes within `pad` of `box`.
bool PathTouches(const VplPath& path, const Bounds& box, const glm::vec3& pad);

// Cosine-distributed direction around unit n from (u1, u2).
glm::vec3 SampleCosine(const glm::vec3& n, float u1, float u2);

}  // namespace gistream::avg
