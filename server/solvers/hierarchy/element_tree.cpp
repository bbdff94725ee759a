#include "solvers/hierarchy/element_tree.h"

#include <algorithm>
#include <numeric>

namespace gistream::hierarchy {
namespace {

struct Builder {
  const Surfels& s;
  std::vector<ElementTree::Internal> internal;  // build order, renumbered later

  // 6D clustering key of surfel i in a cluster of size `extent`.
  float Key(int i, int dim, float normal_weight) const {
    return dim < 3 ? s.position[size_t(i)][dim] : normal_weight * s.normal[size_t(i)][dim - 3];
  }

  // Splits [begin, end) at the median of its widest key dimension.
  int* Split(int* begin, int* end) const {
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (int* i = begin; i != end; ++i) {
      lo = glm::min(lo, s.position[size_t(*i)]);
      hi = glm::max(hi, s.position[size_t(*i)]);
    }
    const float weight = 0.3f * glm::length(hi - lo);
    int best = 0;
    float widest = -1.0f;
    for (int dim = 0; dim < 6; ++dim) {
      float a = 1e30f, b = -1e30f;
      for (int* i = begin; i != end; ++i) {
        const float k = Key(*i, dim, weight);
        a = std::min(a, k);
        b = std::max(b, k);
      }
      if (b - a > widest) {
        widest = b - a;
        best = dim;
      }
    }
    int* mid = begin + (end - begin) / 2;
    std::nth_element(begin, mid, end,
                     [&](int x, int y) { return Key(x, best, weight) < Key(y, best, weight); });
    return mid;
  }

  // Returns the node: a leaf id, or -(2 + build index) for an internal one
  // (-1 marks an unused child slot).
  int Build(int* begin, int* end) {
    const long n = end - begin;
    if (n == 1) return *begin;
    std::array<int*, 5> cuts;
    if (n <= 4) {
      for (int k = 0; k < 5; ++k) cuts[size_t(k)] = begin + std::min<long>(k, n);
    } else {
      int* mid = Split(begin, end);
      cuts = {begin, Split(begin, mid), mid, Split(mid, end), end};
    }
    ElementTree::Internal node;
    int c = 0;
    for (int k = 0; k < 4; ++k) {
      if (cuts[size_t(k)] == cuts[size_t(k) + 1]) continue;
      node.children[size_t(c++)] = Build(cuts[size_t(k)], cuts[size_t(k) + 1]);
    }
    internal.push_back(node);
    return -int(internal.size()) - 1;
  }
};

int DominantAxis(const glm::vec3& n) {
  const glm::vec3 a = glm::abs(n);
  const int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  return 2 * axis + (n[axis] < 0.0f ? 1 : 0);
}

}  // namespace

ElementTree CreateHierarchy(const Surfels& surfels) {
  ElementTree tree;
  tree.leaf_count = int(surfels.size());
  Builder builder{surfels, {}};
  std::array<std::vector<int>, 6> charts;
  for (int i = 0; i < tree.leaf_count; ++i) {
    if (surfels.area[size_t(i)] > 0.0f)
      charts[size_t(DominantAxis(surfels.normal[size_t(i)]))].push_back(i);
  }
  std::vector<int> raw_roots;
  for (std::vector<int>& chart : charts) {
    if (!chart.empty())
      raw_roots.push_back(builder.Build(chart.data(), chart.data() + chart.size()));
  }

  // Heights (children are built before their parents), then renumber
  // internal nodes by height, stable in build order.
  const size_t count = builder.internal.size();
  for (ElementTree::Internal& node : builder.internal) {
    int h = 0;
    for (int c : node.children) {
      if (c == -1) continue;
      h = std::max(h, c >= 0 ? 0 : builder.internal[size_t(-c - 2)].height);
    }
    node.height = h + 1;
  }
  std::vector<int> order(count);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return builder.internal[size_t(a)].height < builder.internal[size_t(b)].height;
  });
  std::vector<int> new_index(count);
  for (size_t i = 0; i < count; ++i) new_index[size_t(order[i])] = tree.leaf_count + int(i);
  auto remap = [&](int raw) { return raw >= 0 ? raw : new_index[size_t(-raw - 2)]; };
  tree.internal.resize(count);
  tree.parent.assign(size_t(tree.leaf_count) + count, -1);
  for (size_t i = 0; i < count; ++i) {
    ElementTree::Internal node = builder.internal[size_t(order[i])];
    for (int& c : node.children) {
      if (c != -1) c = remap(c);
    }
    tree.internal[i] = node;
  }
  for (size_t i = 0; i < count; ++i) {
    for (int c : tree.internal[i].children) {
      if (c >= 0) tree.parent[size_t(c)] = tree.leaf_count + int(i);
    }
  }
  for (int raw : raw_roots) tree.roots.push_back(remap(raw));
  return tree;
}

}  // namespace gistream::hierarchy
