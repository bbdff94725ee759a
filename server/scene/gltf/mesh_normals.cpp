#include "scene/gltf/mesh_normals.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace gistream {
namespace {

// Triangles whose planes differ by less than this are smoothed together
// (Blender's auto-smooth default).
const float kCosCrease = std::cos(glm::radians(30.0f));
// Comparing every corner with every triangle around its vertex costs the
// sum of squared valences; past this many operations per corner a cheaper
// rule is used (see CornerNormals).
constexpr uint64_t kMaxWorkPerCorner = 64;

struct Faces {
  std::vector<glm::vec3> weighted;  // cross product: direction * 2 * area
  std::vector<glm::vec3> unit;      // zero for degenerate triangles
};

Faces FaceNormals(const Primitive& p) {
  const size_t n = p.indices.size() / 3;
  Faces f{std::vector<glm::vec3>(n), std::vector<glm::vec3>(n, glm::vec3(0.0f))};
  for (size_t t = 0; t < n; ++t) {
    const glm::vec3& a = p.positions[p.indices[3 * t]];
    const glm::vec3& b = p.positions[p.indices[3 * t + 1]];
    const glm::vec3& c = p.positions[p.indices[3 * t + 2]];
    const glm::vec3 cross = glm::cross(b - a, c - a);
    const float len = glm::length(cross);
    if (len > 0.0f && std::isfinite(len)) {
      f.weighted[t] = cross;
      f.unit[t] = cross / len;
    } else {
      f.weighted[t] = glm::vec3(0.0f);
    }
  }
  return f;
}

glm::vec3 NormalizeOr(const glm::vec3& v, const glm::vec3& fallback) {
  const float len = glm::length(v);
  return len > 0.0f && std::isfinite(len) ? v / len : fallback;
}

// The normal each triangle corner should get, before vertices are split.
std::vector<glm::vec3> CornerNormals(const Primitive& p, const Faces& faces) {
  const size_t vertices = p.positions.size();
  const size_t corners = p.indices.size();
  // Triangles around each vertex, as offsets into `around`.
  std::vector<uint32_t> start(vertices + 1, 0);
  for (uint32_t v : p.indices) ++start[v + 1];
  for (size_t v = 0; v < vertices; ++v) start[v + 1] += start[v];
  std::vector<uint32_t> around(corners);
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  for (size_t c = 0; c < corners; ++c) around[fill[p.indices[c]]++] = static_cast<uint32_t>(c / 3);

  std::vector<glm::vec3> smooth(vertices, glm::vec3(0.0f));
  uint64_t work = 0;
  for (size_t v = 0; v < vertices; ++v) {
    const uint64_t valence = start[v + 1] - start[v];
    work += valence * valence;
    for (uint32_t k = start[v]; k < start[v + 1]; ++k) smooth[v] += faces.weighted[around[k]];
  }
  const glm::vec3 up(0.0f, 0.0f, 1.0f);
  const bool exact = work <= kMaxWorkPerCorner * corners;

  std::vector<glm::vec3> out(corners);
  for (size_t c = 0; c < corners; ++c) {
    const uint32_t v = p.indices[c];
    const glm::vec3& own = faces.unit[c / 3];
    const glm::vec3 all = NormalizeOr(smooth[v], own == glm::vec3(0.0f) ? up : own);
    if (own == glm::vec3(0.0f)) {
      out[c] = all;  // a degenerate triangle takes whatever its vertex has
    } else if (exact) {
      // Sum the triangles around v that lie within the crease angle of this one.
      glm::vec3 sum(0.0f);
      for (uint32_t k = start[v]; k < start[v + 1]; ++k) {
        if (glm::dot(faces.unit[around[k]], own) >= kCosCrease) sum += faces.weighted[around[k]];
      }
      out[c] = NormalizeOr(sum, own);
    } else {
      // Cheaper rule for very high valences: the vertex's smooth normal
      // unless it is beyond the crease angle from this triangle.
      out[c] = glm::dot(all, own) >= kCosCrease ? all : own;
    }
  }
  return out;
}

}  // namespace

void GenerateNormals(Primitive* p) {
  const Faces faces = FaceNormals(*p);
  const std::vector<glm::vec3> corner = CornerNormals(*p, faces);

  // Corners of one vertex with bitwise-equal normals share it; each other
  // normal gets a copy of the vertex, chained through `next_copy`.
  constexpr uint32_t kNone = UINT32_MAX;
  const size_t original = p->positions.size();
  p->normals.assign(original, glm::vec3(0.0f));
  std::vector<bool> assigned(original, false);
  std::vector<uint32_t> next_copy(original, kNone);
  const bool has_uvs = p->uvs.size() == original;
  for (size_t c = 0; c < p->indices.size(); ++c) {
    uint32_t v = p->indices[c];
    if (!assigned[v]) {
      assigned[v] = true;
      p->normals[v] = corner[c];
      continue;
    }
    while (p->normals[v] != corner[c] && next_copy[v] != kNone) v = next_copy[v];
    if (p->normals[v] != corner[c]) {
      const uint32_t copy = static_cast<uint32_t>(p->positions.size());
      p->positions.push_back(p->positions[v]);
      if (has_uvs) p->uvs.push_back(p->uvs[v]);
      p->normals.push_back(corner[c]);
      next_copy.push_back(kNone);
      next_copy[v] = copy;
      v = copy;
    }
    p->indices[c] = v;
  }
  // Vertices no triangle uses still need a unit normal.
  for (size_t v = 0; v < original; ++v) {
    if (!assigned[v]) p->normals[v] = glm::vec3(0.0f, 0.0f, 1.0f);
  }
}

}  // namespace gistream
