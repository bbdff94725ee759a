#include "solvers/antiradiance/patches.h"

#include <algorithm>
#include <numeric>

namespace gistream::antiradiance {
namespace {

struct Leaf {
  CellQuad cell;  // the triangle, its last corner repeated
  glm::vec3 centre, normal, albedo;
  float area, radius;
  int tag;
};

void Split(const SourceTriangle& t, float max_edge, int depth, std::vector<Leaf>& out) {
  const float e = std::max(
      {glm::length(t.p[1] - t.p[0]), glm::length(t.p[2] - t.p[1]), glm::length(t.p[0] - t.p[2])});
  if (e > max_edge && depth < 12) {
    const glm::vec3 a = 0.5f * (t.p[0] + t.p[1]), b = 0.5f * (t.p[1] + t.p[2]),
                    c = 0.5f * (t.p[2] + t.p[0]);
    for (const auto& q :
         {std::array<glm::vec3, 3>{t.p[0], a, c}, std::array<glm::vec3, 3>{a, t.p[1], b},
          std::array<glm::vec3, 3>{c, b, t.p[2]}, std::array<glm::vec3, 3>{a, b, c}}) {
      Split({q, t.normal, t.albedo, t.tag}, max_edge, depth + 1, out);
    }
    return;
  }
  Leaf l;
  l.cell = {t.p[0], t.p[1], t.p[2], t.p[2]};
  l.centre = (t.p[0] + t.p[1] + t.p[2]) / 3.0f;
  l.normal = t.normal;
  l.albedo = t.albedo;
  l.tag = t.tag;
  l.area = 0.5f * glm::length(glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]));
  l.radius = 0.0f;
  for (const glm::vec3& p : t.p) l.radius = std::max(l.radius, glm::length(p - l.centre));
  if (l.area > 0.0f) out.push_back(l);  // degenerate triangles carry no light
}

class Builder {
 public:
  Builder(const std::vector<Leaf>& leaves, Patches& out) : leaves_(leaves), out_(out) {}

  // Emits the subtree over leaves idx[begin, end) in depth-first order.
  int Build(std::vector<int>& idx, size_t begin, size_t end) {
    const int node = out_.size();
    out_.position.emplace_back();
    out_.normal.emplace_back();
    out_.area.push_back(0.0f);
    out_.radius.push_back(0.0f);
    out_.albedo.emplace_back(0.0f);
    out_.tag.push_back(-1);
    out_.children.push_back({-1, -1, -1, -1});
    out_.cell_begin.push_back(uint32_t(out_.cell.size()));
    if (end - begin == 1) {
      const Leaf& l = leaves_[size_t(idx[begin])];
      out_.cell.push_back(l.cell);
      out_.position[size_t(node)] = l.centre;
      out_.normal[size_t(node)] = l.normal;
      out_.area[size_t(node)] = l.area;
      out_.radius[size_t(node)] = l.radius;
      out_.albedo[size_t(node)] = l.albedo;
      out_.tag[size_t(node)] = l.tag;
      return node;
    }
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (size_t i = begin; i < end; ++i) {
      lo = glm::min(lo, leaves_[size_t(idx[i])].centre);
      hi = glm::max(hi, leaves_[size_t(idx[i])].centre);
    }
    const float size = glm::length(hi - lo);
    auto key = [&](int i, int axis) {
      const Leaf& l = leaves_[size_t(i)];
      return axis < 3 ? l.centre[axis] : 0.3f * size * l.normal[axis - 3];
    };
    int axis = 0;
    float widest = -1.0f;
    for (int a = 0; a < 6; ++a) {
      float mn = 1e30f, mx = -1e30f;
      for (size_t i = begin; i < end; ++i)
        mn = std::min(mn, key(idx[i], a)), mx = std::max(mx, key(idx[i], a));
      if (mx - mn > widest) widest = mx - mn, axis = a;
    }
    const size_t mid = begin + (end - begin) / 2;
    std::nth_element(idx.begin() + long(begin), idx.begin() + long(mid), idx.begin() + long(end),
                     [&](int a, int b) { return key(a, axis) < key(b, axis); });
    const int c0 = Build(idx, begin, mid);
    const int c1 = Build(idx, mid, end);
    out_.children[size_t(node)] = {c0, c1, -1, -1};
    const float a0 = out_.area[size_t(c0)], a1 = out_.area[size_t(c1)];
    const float a = a0 + a1;
    const glm::vec3 p = (a0 * out_.position[size_t(c0)] + a1 * out_.position[size_t(c1)]) / a;
    const glm::vec3 n = a0 * out_.normal[size_t(c0)] + a1 * out_.normal[size_t(c1)];
    out_.position[size_t(node)] = p;
    out_.normal[size_t(node)] =
        glm::length(n) > 1e-12f * a ? glm::normalize(n) : out_.normal[size_t(c0)];
    out_.area[size_t(node)] = a;
    out_.radius[size_t(node)] =
        std::max(glm::length(out_.position[size_t(c0)] - p) + out_.radius[size_t(c0)],
                 glm::length(out_.position[size_t(c1)] - p) + out_.radius[size_t(c1)]);
    return node;
  }

 private:
  const std::vector<Leaf>& leaves_;
  Patches& out_;
};

}  // namespace

std::vector<int> Patches::Leaves() const {
  std::vector<int> leaves;
  for (int i = 0; i < size(); ++i) {
    if (is_leaf(i)) leaves.push_back(i);
  }
  return leaves;
}

uint64_t CountLeaves(const std::vector<std::vector<SourceTriangle>>& groups, float max_edge) {
  uint64_t leaves = 0;
  for (const std::vector<SourceTriangle>& group : groups) {
    for (const SourceTriangle& t : group) {
      float e = std::max({glm::length(t.p[1] - t.p[0]), glm::length(t.p[2] - t.p[1]),
                          glm::length(t.p[0] - t.p[2])});
      int depth = 0;
      while (e > max_edge && depth < 12) {  // as Split
        e *= 0.5f;
        ++depth;
      }
      leaves += uint64_t(1) << (2 * depth);
    }
  }
  return leaves;
}

Patches BuildPatches(const std::vector<std::vector<SourceTriangle>>& groups, float max_edge) {
  Patches out;
  for (const std::vector<SourceTriangle>& group : groups) {
    std::vector<Leaf> leaves;
    for (const SourceTriangle& t : group) Split(t, max_edge, 0, leaves);
    if (leaves.empty()) continue;
    std::vector<int> idx(leaves.size());
    std::iota(idx.begin(), idx.end(), 0);
    Builder builder(leaves, out);
    out.roots.push_back(builder.Build(idx, 0, idx.size()));
  }
  out.cell_begin.push_back(uint32_t(out.cell.size()));
  return out;
}

int AddBackFaces(Patches& p, const std::function<bool(int tag)>& two_sided) {
  const bool cells = p.cell_begin.size() == size_t(p.size()) + 1;
  if (cells) p.cell_begin.pop_back();  // the end sentinel, pushed again below
  const std::vector<int> roots = p.roots;
  const int original = p.size();
  const uint32_t original_cells = uint32_t(p.cell.size());
  int mirrored = 0;
  for (size_t r = 0; r < roots.size(); ++r) {
    // Depth-first layout: a root's subtree runs up to the next root.
    const int begin = roots[r], end = r + 1 < roots.size() ? roots[r + 1] : original;
    bool all = begin < end;
    for (int i = begin; i < end && all; ++i) all = !p.is_leaf(i) || two_sided(p.tag[size_t(i)]);
    if (!all) continue;
    const int offset = p.size() - begin;
    for (int i = begin; i < end; ++i) {
      const size_t k = size_t(i);
      p.position.push_back(p.position[k]);
      p.normal.push_back(-p.normal[k]);
      p.area.push_back(p.area[k]);
      p.radius.push_back(p.radius[k]);
      p.albedo.push_back(p.albedo[k]);
      p.tag.push_back(p.tag[k]);
      std::array<int, 4> children = p.children[k];
      for (int& c : children) c = c >= 0 ? c + offset : -1;
      p.children.push_back(children);
      if (cells) {
        const uint32_t from = p.cell_begin[k];
        const uint32_t to = k + 1 < size_t(original) ? p.cell_begin[k + 1] : original_cells;
        p.cell_begin.push_back(uint32_t(p.cell.size()));
        for (uint32_t c = from; c < to; ++c) {
          const CellQuad q = p.cell[c];
          p.cell.push_back(q);
        }
      }
    }
    p.roots.push_back(begin + offset);
    ++mirrored;
  }
  if (cells) p.cell_begin.push_back(uint32_t(p.cell.size()));
  return mirrored;
}

}  // namespace gistream::antiradiance
