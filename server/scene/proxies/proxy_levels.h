// Proxy geometry for the view-independent GI passes (issue 19): per
// primitive, simplified levels made at load time by meshoptimizer's
// edge-collapse simplifier (vertices kept, indices only), each with an
// upper bound of its geometric error measured on the mesh
// (scene/proxies/surface_distance.h). A pass draws the coarsest level whose error
// is below what its resolution can show (docs/ARCHITECTURE.md, "Proxy
// geometry"); the G-buffer and the path tracer keep the full mesh.
#pragma once

#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "scene/gltf/load_control.h"
#include "scene/scene.h"

namespace gistream {

struct ProxySettings {
  // Primitives with fewer triangles keep no proxy.
  size_t min_triangles = 256;
  // Each level aims at this fraction of the triangles of the one before.
  float reduction = 0.25f;
  // Levels stop at this error (relative to the primitive's box diagonal):
  // coarser ones would suit no pass.
  float max_relative_error = 0.02f;
  // The error measurement's sample spacing is at least this fraction of
  // the diagonal (its covering radius, spacing / sqrt(3), adds to the bound).
  float min_relative_spacing = 1.0f / 250.0f;
};

// The levels of one primitive, finest first; empty for primitives that are
// small, skinned or morphed (their deformed shape would void the bound).
std::vector<ProxyLevel> BuildProxyLevels(const Primitive& primitive,
                                         const ProxySettings& settings = {});

// The same, checking `control` before every level: a stop ends the build
// with its status, a passed optional deadline keeps the levels made so far
// and sets `*out_of_time`.
absl::StatusOr<std::vector<ProxyLevel>> BuildProxyLevels(const Primitive& primitive,
                                                         const ProxySettings& settings,
                                                         const LoadControl& control,
                                                         bool* out_of_time);

// Fills Primitive::proxies of every mesh, and Primitive::clusters
// (scene/proxies/proxy_clusters.h) of those with proxies.
void BuildSceneProxies(Scene* scene, const ProxySettings& settings = {});

// The same within `control`: every primitive's levels first, then the
// trees (the costly part), so a passed optional deadline leaves the levels
// and drops the trees not finished (`report` counts what is missing). A
// stop returns its status naming the primitive and stage
// ("meshes[2].primitives[0]: proxy cluster tree: ...").
absl::Status BuildSceneProxies(Scene* scene, const LoadControl& control, ProxyReport* report,
                               const ProxySettings& settings = {});

// The coarsest of `levels` (finest first; anything with an `error`) whose
// error times `scale` is at most `tolerance` (world units); -1 for the full
// mesh.
template <typename Level>
int PickProxyLevel(std::span<const Level> levels, float scale, float tolerance) {
  int pick = -1;
  for (size_t i = 0; i < levels.size(); ++i) {
    if (levels[i].error * scale <= tolerance) pick = int(i);
  }
  return pick;
}

// An upper bound of the factor by which `model` stretches a length
// (sqrt of the largest absolute row sum of A^T A, A its 3x3 part; exact for
// rotation times uniform scale): a local error times this bounds the world
// error.
float MaxScale(const glm::mat4& model);

}  // namespace gistream
