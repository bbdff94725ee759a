// The shared element hierarchy of `implicit_visibility`
// (server/solvers/hierarchy/: vertex discs, trees of up to four children
// per chart, leaves first) as antiradiance Patches, relaid out depth-first
// (Section 4.1) so push walks forward and pull backward.
#pragma once

#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "scene/gpu/gpu_scene.h"
#include "scene/state/scene_state.h"
#include "solvers/antiradiance/patches.h"
#include "solvers/hierarchy/elements.h"

namespace gistream::antiradiance {

// leaf_albedo / leaf_tag (and leaf_cells, world space, when given) are
// indexed by the shared hierarchy's leaf ids.
Patches PatchesFromElements(const hierarchy::Elements& elements,
                            const std::vector<glm::vec3>& leaf_albedo,
                            const std::vector<int>& leaf_tag,
                            const std::vector<std::vector<CellQuad>>* leaf_cells = nullptr);

// Each vertex's third of its triangles, (v, mid(v, q), centroid, mid(v, r))
// per adjacent triangle (v, q, r): the area a surfel stands for
// (hierarchy/surfels.h), in the primitive's space, per vertex.
std::vector<std::vector<CellQuad>> VertexCells(const Primitive& primitive);

// Per-mesh preprocessing kept between calls (meshes never change, only
// their placement): the shared hierarchy and the surfels' cells.
// A primitive near a double-sided emitter is refined around it
// (near_field.h), which depends on where both are: `near_key` holds what
// its refinement was made for (empty: none).
struct SurfelMesh {
  std::shared_ptr<hierarchy::ElementMesh> elements;
  std::vector<std::vector<CellQuad>> cells;  // local space, per vertex
  std::vector<float> near_key;
};
using SurfelCache = std::map<std::pair<int, int>, SurfelMesh>;

// create_surfels + create_hierarchy (shared, once per mesh primitive via
// `cache`) for every draw of the scene, placed by the current transforms;
// tags are material ids. Primitives with proxy levels give their surfels
// from one (hierarchy/element_source.h) unless `full_detail`; the display
// splats at the G-buffer's full-detail pixels, within 1.5 leaf radii.
Patches SurfelPatches(const SceneState& state, const GpuScene& gpu, SurfelCache& cache,
                      bool full_detail = false);

}  // namespace gistream::antiradiance
