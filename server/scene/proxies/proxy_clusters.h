// Per-cluster proxy levels (issue 19): a primitive's triangles split into a
// k-d tree of spatial clusters, every node holding a simplified copy of its
// triangles made with the node's border locked, and that copy's measured
// error bound (scene/proxies/surface_distance.h). A pass walks the tree per view and
// draws, per node, its copy when the error is below what the view can show
// at the node's nearest distance, or else its children (leaves: their full
// triangles). Locked borders keep every vertex on a node's boundary, so
// whichever nodes a view picks, neighbours meet edge for edge: the drawn
// surface is watertight wherever the full mesh is (docs/ARCHITECTURE.md,
// "Proxy geometry").
#pragma once

#include <cstddef>
#include <vector>

#include "scene/gltf/load_control.h"
#include "scene/scene.h"

namespace gistream {

struct ClusterSettings {
  // A leaf holds at most this many triangles; primitives with at most
  // twice as many keep no tree (their whole-primitive levels suffice).
  size_t leaf_triangles = 2048;
  // A node's copy is kept only when it has at most this fraction of the
  // triangles it replaces.
  float max_kept_fraction = 0.5f;
  // Copies stop at this error (relative to the primitive's box diagonal).
  float max_relative_error = 0.02f;
  // The error measurement's sample spacing is at least this fraction of
  // the node's box diagonal (its covering radius adds to the bound: a flat
  // node's copy records diagonal / 433). 1/100 cut the import time 4x but
  // kept so many leaves next to a light in full that the 415K Cornell
  // box's first frame went from 2x to 4.4x the 6.5K one (RESULTS.md).
  float min_relative_spacing = 1.0f / 250.0f;
};

// The tree of `primitive`, root first (children after their parent); empty
// for primitives that are small, skinned or morphed.
std::vector<ProxyCluster> BuildProxyClusters(const Primitive& primitive,
                                             const ClusterSettings& settings = {});

// The same, checking `control` before every node: a stop ends the build
// with its status (stage "proxy cluster tree"), a passed optional deadline
// with an empty tree and `*out_of_time` set (the primitive keeps its
// whole-primitive levels).
absl::StatusOr<std::vector<ProxyCluster>> BuildProxyClusters(const Primitive& primitive,
                                                             const ClusterSettings& settings,
                                                             const LoadControl& control,
                                                             bool* out_of_time);

// The full triangles of node `node` (its leaves' indices, in leaf order).
std::vector<uint32_t> ClusterTriangles(const std::vector<ProxyCluster>& clusters, int node);

}  // namespace gistream
