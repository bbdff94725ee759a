// The scene's surface elements in world space: every node instance of every
// mesh primitive contributes its cached ElementTree, concatenated into one
// pointer-less forest (Section 4.3.1): all leaves first (instance by
// instance, in vertex order, so a leaf is a vertex of the displayed mesh),
// then all internal nodes sorted by height. UpdateElements (Section 4.2.1)
// recomputes positions, normals, areas and bounds bottom-up after node
// transforms changed; the hierarchy itself never changes.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/hierarchy/element_tree.h"

namespace gistream::hierarchy {

// Normals closer than this (1 - cos) count as equal (a node's coplanar
// slab; a link's planes).
inline constexpr float kParallel = 1e-6f;

// One mesh primitive's cached preprocessing (local space).
struct ElementMesh {
  Surfels surfels;
  ElementTree tree;
};

// One placement of an ElementMesh (a glTF node instance of a primitive).
struct ElementInstance {
  std::shared_ptr<const ElementMesh> mesh;
  int leaf_offset = 0;                // its leaves are [leaf_offset, leaf_offset + leaf_count)
  std::vector<int> node_of_internal;  // global id of local internal node i
};

class Elements {
 public:
  // Lays out the forest; positions are set by Update.
  explicit Elements(std::vector<ElementInstance> instances);
  Elements() = default;

  // World positions, normals (unit) and areas of the leaves from each
  // instance's world matrix, then the internal nodes bottom-up: position
  // and normal area-weighted averages, area the sum, bounding radius,
  // normal cone and the extent along the normal (for the coplanar test).
  void Update(const std::vector<glm::mat4>& instance_world);

  int node_count() const { return int(position.size()); }
  int leaf_count() const { return leaf_count_; }
  bool is_leaf(int node) const { return node < leaf_count_; }
  const std::vector<ElementInstance>& instances() const { return instances_; }
  // Internal node ids of height h are [level_begin[h-1], level_begin[h]).
  const std::vector<int>& level_begin() const { return level_begin_; }
  const std::vector<int>& roots() const { return roots_; }

  // Per node (world space).
  std::vector<glm::vec3> position;
  std::vector<glm::vec3> normal;  // unit (a cancelled average keeps the largest child's)
  std::vector<float> area;
  std::vector<float> radius;    // bounding sphere of the leaves' discs
  std::vector<float> cone;      // half-angle (radians) of the leaves' normals about normal
  std::vector<glm::vec2> slab;  // min/max of n . p over the leaves (n = this node's normal)
  std::vector<int> parent;      // -1 for roots
  std::vector<std::array<int, 4>> children;  // internal nodes; -1 unused; leaves all -1
  std::vector<int> instance_of_leaf;

 private:
  std::vector<ElementInstance> instances_;
  std::vector<int> level_begin_;
  std::vector<int> roots_;
  int leaf_count_ = 0;
};

}  // namespace gistream::hierarchy
