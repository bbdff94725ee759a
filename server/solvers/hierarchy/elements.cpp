#include "solvers/hierarchy/elements.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_inverse.hpp>

#include "util/parallel_for.h"
#include "util/constants.h"

namespace gistream::hierarchy {
namespace {

float Angle(const glm::vec3& a, const glm::vec3& b) {
  return std::acos(std::clamp(glm::dot(a, b), -1.0f, 1.0f));
}

}  // namespace

Elements::Elements(std::vector<ElementInstance> instances) : instances_(std::move(instances)) {
  // Leaves: instance by instance.
  for (ElementInstance& inst : instances_) {
    inst.leaf_offset = leaf_count_;
    leaf_count_ += inst.mesh->tree.leaf_count;
  }
  // Internal nodes of all instances, sorted by height (stable).
  struct Pending {
    int instance, local, height;
  };
  std::vector<Pending> pending;
  int max_height = 0;
  for (size_t i = 0; i < instances_.size(); ++i) {
    const ElementTree& tree = instances_[i].mesh->tree;
    instances_[i].node_of_internal.assign(tree.internal.size(), -1);
    for (size_t k = 0; k < tree.internal.size(); ++k) {
      pending.push_back({int(i), int(k), tree.internal[k].height});
      max_height = std::max(max_height, tree.internal[k].height);
    }
  }
  std::stable_sort(pending.begin(), pending.end(),
                   [](const Pending& a, const Pending& b) { return a.height < b.height; });
  level_begin_.assign(size_t(max_height) + 1, leaf_count_ + int(pending.size()));
  for (size_t k = 0; k < pending.size(); ++k) {
    const int id = leaf_count_ + int(k);
    instances_[size_t(pending[k].instance)].node_of_internal[size_t(pending[k].local)] = id;
    for (int h = pending[k].height - 1; h >= 0 && level_begin_[size_t(h)] > id; --h) {
      level_begin_[size_t(h)] = id;
    }
  }
  // level_begin_[h-1] .. level_begin_[h]: internal nodes of height h.
  const size_t nodes = size_t(leaf_count_) + pending.size();
  position.assign(nodes, glm::vec3(0.0f));
  normal.assign(nodes, glm::vec3(0.0f, 1.0f, 0.0f));
  area.assign(nodes, 0.0f);
  radius.assign(nodes, 0.0f);
  cone.assign(nodes, 0.0f);
  slab.assign(nodes, glm::vec2(0.0f));
  parent.assign(nodes, -1);
  children.assign(nodes, {-1, -1, -1, -1});
  instance_of_leaf.assign(size_t(leaf_count_), 0);
  for (size_t i = 0; i < instances_.size(); ++i) {
    const ElementInstance& inst = instances_[i];
    const ElementTree& tree = inst.mesh->tree;
    auto global = [&](int local) {
      return local < tree.leaf_count ? inst.leaf_offset + local
                                     : inst.node_of_internal[size_t(local - tree.leaf_count)];
    };
    for (int l = 0; l < tree.leaf_count; ++l)
      instance_of_leaf[size_t(inst.leaf_offset + l)] = int(i);
    for (size_t k = 0; k < tree.internal.size(); ++k) {
      const int id = inst.node_of_internal[k];
      for (size_t c = 0; c < 4; ++c) {
        const int child = tree.internal[k].children[c];
        if (child < 0) continue;
        children[size_t(id)][c] = global(child);
        parent[size_t(global(child))] = id;
      }
    }
    for (int root : tree.roots) roots_.push_back(global(root));
  }
}

void Elements::Update(const std::vector<glm::mat4>& instance_world) {
  // Leaves (Section 4.2.1): transformed discs. Under an affine map the area
  // of a surface patch with unit normal n scales by |det M| |M^-T n|.
  ParallelFor(instances_.size(), 1, [&](size_t i) {
    const ElementInstance& inst = instances_[i];
    const Surfels& s = inst.mesh->surfels;
    const glm::mat4& m = instance_world[i];
    const glm::mat3 linear(m);
    const glm::mat3 normal_matrix = glm::inverseTranspose(linear);
    const float det = std::abs(glm::determinant(linear));
    for (size_t v = 0; v < s.size(); ++v) {
      const size_t id = size_t(inst.leaf_offset) + v;
      const glm::vec3 p = glm::vec3(m * glm::vec4(s.position[v], 1.0f));
      const glm::vec3 n = normal_matrix * s.normal[v];
      const float len = glm::length(n);
      const bool ok = len > 0.0f && std::isfinite(len) && std::isfinite(det);
      position[id] = p;
      normal[id] = ok ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
      area[id] = ok ? s.area[v] * det * len : 0.0f;
      radius[id] = std::sqrt(area[id] / kPi);
      cone[id] = 0.0f;
      const float h = glm::dot(normal[id], p);
      slab[id] = glm::vec2(h, h);
    }
  });
  // Internal nodes, one height level after the other (children first).
  for (size_t h = 1; h < level_begin_.size(); ++h) {
    const int begin = level_begin_[h - 1], end = level_begin_[h];
    ParallelFor(size_t(end - begin), 256, [&](size_t k) {
      const size_t id = size_t(begin) + k;
      const std::array<int, 4>& ch = children[id];
      float a = 0.0f;
      glm::vec3 p(0.0f), n(0.0f);
      int count = 0, largest = -1;
      for (int c : ch) {
        if (c < 0) continue;
        a += area[size_t(c)];
        p += area[size_t(c)] * position[size_t(c)];
        n += area[size_t(c)] * normal[size_t(c)];
        if (largest < 0 || area[size_t(c)] > area[size_t(largest)]) largest = c;
        ++count;
      }
      if (count == 0) return;
      if (!(a > 0.0f)) {
        p = glm::vec3(0.0f);
        for (int c : ch) {
          if (c >= 0) p += position[size_t(c)] / float(count);
        }
      } else {
        p /= a;
      }
      const float len = glm::length(n);
      n = len > 1e-20f && std::isfinite(len) ? n / len : normal[size_t(largest)];
      float r = 0.0f, cone_angle = 0.0f;
      glm::vec2 range(1e30f, -1e30f);
      for (int c : ch) {
        if (c < 0) continue;
        const size_t cs = size_t(c);
        r = std::max(r, glm::length(position[cs] - p) + radius[cs]);
        cone_angle = std::max(cone_angle, Angle(n, normal[cs]) + cone[cs]);
        if (cone[cs] == 0.0f && glm::dot(n, normal[cs]) > 1.0f - kParallel) {
          range = glm::vec2(std::min(range.x, slab[cs].x), std::max(range.y, slab[cs].y));
        } else {
          const float hc = glm::dot(n, position[cs]);
          range = glm::vec2(std::min(range.x, hc - radius[cs]), std::max(range.y, hc + radius[cs]));
        }
      }
      position[id] = p;
      normal[id] = n;
      area[id] = a;
      radius[id] = r;
      // Children within kParallel of one normal count as one plane.
      cone[id] = cone_angle < 1e-3f ? 0.0f : std::min(cone_angle, kPi);
      slab[id] = range;
    });
  }
}

}  // namespace gistream::hierarchy
