#include "scene/proxies/proxy_clusters.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "scene/proxies/surface_distance.h"

namespace gistream {
namespace {

class TreeBuilder {
 public:
  TreeBuilder(const Primitive& primitive, const ClusterSettings& settings,
              const LoadControl& control)
      : p_(primitive), settings_(settings), control_(control) {
    const float* xyz = &p_.positions[0].x;
    scale_ = std::max(meshopt_simplifyScale(xyz, p_.positions.size(), sizeof(glm::vec3)), 1e-30f);
    cap_ = settings_.max_relative_error * glm::length(p_.bounds.extent());
  }

  // Builds the node for triangles `tris` (triangle numbers of the
  // primitive) and returns its coarsest stand-in: its copy, or else its
  // children's stand-ins (leaves: their full triangles).
  std::vector<uint32_t> Build(std::vector<uint32_t> tris) {
    // Between nodes: a stop or a passed deadline leaves the rest unbuilt
    // (the caller discards the tree).
    if (stopped()) return {};
    status_ = control_.Check("proxy cluster tree");
    out_of_time_ = !control_.OptionalTimeLeft();
    if (stopped()) return {};
    const int node = int(nodes_.size());
    nodes_.emplace_back();
    Bounds box;
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (uint32_t t : tris) {
      glm::vec3 c(0.0f);
      for (int k = 0; k < 3; ++k) {
        const glm::vec3& v = p_.positions[p_.indices[3 * t + k]];
        box.Extend(v);
        c += v;
      }
      lo = glm::min(lo, c);
      hi = glm::max(hi, c);
    }
    nodes_[size_t(node)].bounds = box;
    std::vector<uint32_t> full, source;
    if (tris.size() <= settings_.leaf_triangles) {
      for (uint32_t t : tris) {
        full.insert(full.end(), p_.indices.begin() + 3 * t, p_.indices.begin() + 3 * t + 3);
      }
      nodes_[size_t(node)].indices = full;
      source = full;
    } else {
      // Median split of the triangle centroids (3x, unnormalised) along
      // the centroid box's longest axis.
      const glm::vec3 extent = hi - lo;
      const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                       : extent.y >= extent.z                       ? 1
                                                                    : 2;
      const auto centroid = [&](uint32_t t) {
        return p_.positions[p_.indices[3 * t]][axis] + p_.positions[p_.indices[3 * t + 1]][axis] +
               p_.positions[p_.indices[3 * t + 2]][axis];
      };
      const auto middle = tris.begin() + std::ptrdiff_t(tris.size() / 2);
      std::nth_element(tris.begin(), middle, tris.end(),
                       [&](uint32_t a, uint32_t b) { return centroid(a) < centroid(b); });
      std::vector<uint32_t> left(tris.begin(), middle), right(middle, tris.end());
      tris = {};
      for (int c = 0; c < 2; ++c) {
        nodes_[size_t(node)].children[c] = int(nodes_.size());
        const std::vector<uint32_t> stand_in = Build(c == 0 ? std::move(left) : std::move(right));
        source.insert(source.end(), stand_in.begin(), stand_in.end());
      }
      if (stopped()) return {};
      full = ClusterTriangles(nodes_, node);
    }
    ProxyLevel level = Simplify(source, full, glm::length(box.extent()));
    if (level.indices.empty()) return source;
    nodes_[size_t(node)].level = std::move(level);
    return nodes_[size_t(node)].level.indices;
  }

  std::vector<ProxyCluster> Take() { return std::move(nodes_); }
  bool stopped() const { return !status_.ok() || out_of_time_; }
  const absl::Status& status() const { return status_; }
  bool out_of_time() const { return out_of_time_; }

 private:
  // The copy of `source` (the children's stand-ins, or a leaf's triangles)
  // with the node's border locked, and its bound against the node's full
  // triangles `full`, measured both ways as BuildProxyLevels does; empty
  // when it would not cut the triangles enough or exceeds the cap.
  ProxyLevel Simplify(const std::vector<uint32_t>& source, const std::vector<uint32_t>& full,
                      float diagonal) const {
    ProxyLevel level;
    if (!(diagonal > 0.0f)) return level;
    const float* xyz = &p_.positions[0].x;
    level.indices.resize(source.size());
    float relative_error = 0.0f;
    level.indices.resize(meshopt_simplify(level.indices.data(), source.data(), source.size(), xyz,
                                          p_.positions.size(), sizeof(glm::vec3), 3, cap_ / scale_,
                                          meshopt_SimplifyLockBorder, &relative_error));
    if (level.indices.empty() ||
        float(level.indices.size()) > settings_.max_kept_fraction * float(full.size())) {
      return {};
    }
    const float spacing =
        std::max(0.5f * relative_error * scale_, settings_.min_relative_spacing * diagonal);
    const TriangleGrid full_grid(p_.positions, full, cap_ / 4.0f);
    const auto deadline = control_.optional_deadline;
    const float there =
        HausdorffBound(p_.positions, level.indices, full_grid, spacing, cap_, deadline);
    if (there >= cap_) return {};
    const TriangleGrid level_grid(p_.positions, level.indices, cap_ / 4.0f);
    const float back = HausdorffBound(p_.positions, full, level_grid, spacing, cap_, deadline);
    if (back >= cap_) return {};
    level.error = std::max(there, back);
    return level;
  }

  const Primitive& p_;
  const ClusterSettings& settings_;
  const LoadControl& control_;
  absl::Status status_;
  bool out_of_time_ = false;
  float scale_ = 1.0f;
  float cap_ = 0.0f;
  std::vector<ProxyCluster> nodes_;
};

}  // namespace

std::vector<ProxyCluster> BuildProxyClusters(const Primitive& primitive,
                                             const ClusterSettings& settings) {
  bool out_of_time = false;
  absl::StatusOr<std::vector<ProxyCluster>> tree =
      BuildProxyClusters(primitive, settings, LoadControl{}, &out_of_time);
  return tree.ok() ? *std::move(tree) : std::vector<ProxyCluster>{};
}

absl::StatusOr<std::vector<ProxyCluster>> BuildProxyClusters(const Primitive& primitive,
                                                             const ClusterSettings& settings,
                                                             const LoadControl& control,
                                                             bool* out_of_time) {
  *out_of_time = false;
  const size_t triangles = primitive.indices.size() / 3;
  if (triangles <= 2 * settings.leaf_triangles || !primitive.joints.empty() ||
      !primitive.targets.empty() || primitive.bounds.empty()) {
    return std::vector<ProxyCluster>{};
  }
  const float diagonal = glm::length(primitive.bounds.extent());
  if (!(diagonal > 0.0f) || !std::isfinite(diagonal)) return std::vector<ProxyCluster>{};
  TreeBuilder builder(primitive, settings, control);
  std::vector<uint32_t> all(triangles);
  std::iota(all.begin(), all.end(), 0u);
  builder.Build(std::move(all));
  GS_RETURN_IF_ERROR(builder.status());
  *out_of_time = builder.out_of_time();
  if (builder.stopped()) return std::vector<ProxyCluster>{};
  return builder.Take();
}

std::vector<uint32_t> ClusterTriangles(const std::vector<ProxyCluster>& clusters, int node) {
  std::vector<uint32_t> out;
  std::vector<int> stack = {node};
  while (!stack.empty()) {
    const ProxyCluster& c = clusters[size_t(stack.back())];
    stack.pop_back();
    if (c.children[0] < 0) {
      out.insert(out.end(), c.indices.begin(), c.indices.end());
    } else {
      stack.push_back(c.children[1]);
      stack.push_back(c.children[0]);
    }
  }
  return out;
}

}  // namespace gistream
