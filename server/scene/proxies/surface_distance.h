// Distances between triangle surfaces, for the proxy levels' recorded
// geometric error (scene/proxies/proxy_levels.h). A uniform grid answers "how far
// is this point from the surface"; the one-sided Hausdorff bound samples
// the other surface densely enough that, the distance to a surface being
// 1-Lipschitz, the sampled maximum plus the samples' covering radius is an
// upper bound, not an estimate.
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace gistream {

// Nearest-triangle distance queries over one triangle list.
class TriangleGrid {
 public:
  // `cell`: the grid's cell size (> 0); the cell count is capped, so a
  // small cell on a large mesh is enlarged.
  TriangleGrid(std::span<const glm::vec3> positions, std::span<const uint32_t> indices, float cell);

  // Distance from `p` to the nearest triangle, or `cap` when none lies
  // closer than `cap`. With `enough` >= 0 the search stops at the first
  // triangle within `enough` and returns its distance: an upper bound of
  // the nearest one's, itself at most `enough` (a caller taking a maximum
  // over samples needs no more).
  float Distance(const glm::vec3& p, float cap, float enough = -1.0f) const;

 private:
  std::span<const glm::vec3> positions_;
  std::span<const uint32_t> indices_;
  glm::vec3 origin_{0.0f};
  glm::ivec3 dims_{0};
  float cell_ = 1.0f;
  std::vector<uint32_t> cell_start_;  // CSR: triangles of cell c are
  std::vector<uint32_t> cell_tris_;   // cell_tris_[cell_start_[c] .. cell_start_[c + 1])
};

// Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision
// Detection, Sec. 5.1.5).
glm::vec3 ClosestPointOnTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b,
                                 const glm::vec3& c);

// An upper bound of the one-sided Hausdorff distance from the triangles
// `from` to the surface `to` (both index `positions`): every triangle of
// `from` is sampled on a barycentric grid whose sub-triangles have edges
// <= `spacing`, and the bound is the largest sample distance plus the
// covering radius (the largest sub-triangle edge / sqrt(3)). Returns `cap`
// as soon as a sample is `cap` or farther away, or once `deadline` has
// passed (checked every 64 triangles: a load's time budget,
// scene/gltf/load_control.h).
float HausdorffBound(
    std::span<const glm::vec3> positions, std::span<const uint32_t> from, const TriangleGrid& to,
    float spacing, float cap,
    std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max());

}  // namespace gistream
