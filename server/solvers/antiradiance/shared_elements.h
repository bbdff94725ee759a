// The shared element hierarchy of `implicit_visibility`
// (server/solvers/hierarchy/: vertex discs, trees of up to four children
// per chart, leaves first) as antiradiance Patches, relaid out depth-first
// (Section 4.1) so push walks forward and pull backward.
#pragma once

#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "scene/gpu_scene.h"
#include "scene/scene_state.h"
#include "solvers/antiradiance/patches.h"
#include "solvers/hierarchy/elements.h"

namespace gistream::antiradiance {

// leaf_albedo / leaf_tag are indexed by the shared hierarchy's leaf ids.
Patches PatchesFromElements(const hierarchy::Elements& elements,
                            const std::vector<glm::vec3>& leaf_albedo,
                            const std::vector<int>& leaf_tag);

// Per-mesh preprocessing kept between calls (meshes never change, only
// their placement).
using SurfelCache = std::map<std::pair<int, int>, std::shared_ptr<hierarchy::ElementMesh>>;

// create_surfels + create_hierarchy (shared, once per mesh primitive via
// `cache`) for every draw of the scene, placed by the current transforms;
// tags are material ids.
Patches SurfelPatches(const SceneState& state, const GpuScene& gpu, SurfelCache& cache);

}  // namespace gistream::antiradiance
