// Instant radiosity's light paths through the approximate visibility grid
// (paper Sec. III-B): rays leave the lights (cosine-distributed over
// emissive surfaces, by intensity for point and spot lights, parallel for
// directional lights), are marched through the voxels, leave a VPL at each
// hit and continue by cosine sampling up to `bounces` times, optionally cut
// short by Russian roulette. Runs on the CPU (multi-threaded over paths).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/avg/vpl_lights.h"
#include "solvers/avg/voxel_grid.h"

namespace gistream::avg {

struct Vpl {
  glm::vec3 position{0.0f};  // on the voxel's mean surface plane, nudged off it
  glm::vec3 normal{0.0f};    // unit, facing the side the light came from
  glm::vec3 flux{0.0f};      // reflected power (W): incident flux x voxel albedo
  int bounce = 1;            // 1: first indirect bounce (lit directly by a light)
};

struct VplTraceSettings {
  int vpls = 1024;       // VPLs to place (paths are added until there are this many)
  int bounces = 8;       // VPL generations per path at most (1..kMaxBounces)
  bool roulette = true;  // Russian roulette after each VPL
  int threads = 0;       // 1: on the calling thread; else the CPU pool
  // With roulette a path ends on its own (after 1 / (1 - albedo) VPLs on
  // average), so the cap only bounds stiff scenes' paths.
  static constexpr int kMaxBounces = 1024;
};

struct VplTraceResult {
  std::vector<Vpl> vpls;
  uint64_t paths = 0;    // light paths used (the estimator's N)
  uint64_t escaped = 0;  // paths whose first ray left the grid
  glm::vec3 light_power{0.0f};
};

VplTraceResult TraceVpls(const VoxelGrid& grid, const std::vector<VplLight>& lights,
                         const VplTraceSettings& settings);

// Cosine-distributed direction around unit n from (u1, u2).
glm::vec3 SampleCosine(const glm::vec3& n, float u1, float u2);

}  // namespace gistream::avg
