#include "render/emitter_polygons.h"

#include <algorithm>
#include <cmath>

namespace gistream {
namespace {

// Triangles that may form one polygon: same radiance, same side, same plane.
struct Group {
  glm::vec3 normal;
  float offset;  // dot(normal, p) on the plane
  glm::vec3 radiance;
  std::vector<int> triangles;
};

double Cross2(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Andrew's monotone chain: counter-clockwise hull without collinear points.
std::vector<glm::dvec2> ConvexHull(std::vector<glm::dvec2> p) {
  std::sort(p.begin(), p.end(), [](const glm::dvec2& a, const glm::dvec2& b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  std::vector<glm::dvec2> hull(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && Cross2(hull[k - 2], hull[k - 1], p[i]) <= 0.0) --k;
    hull[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && Cross2(hull[k - 2], hull[k - 1], p[i - 1]) <= 0.0) --k;
    hull[k++] = p[i - 1];
  }
  hull.resize(k - 1);
  return hull;
}

double Area2(const std::vector<glm::dvec2>& poly) {
  double a = 0.0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec2& p = poly[i];
    const glm::dvec2& q = poly[(i + 1) % poly.size()];
    a += p.x * q.y - q.x * p.y;
  }
  return 0.5 * a;
}

EmitterPolygon FromTriangle(const EmitterTriangle& t) {
  EmitterPolygon p;
  p.vertices[0] = t.p0;
  p.vertices[1] = t.p1;
  p.vertices[2] = t.p2;
  p.vertex_count = 3;
  p.normal = t.normal;
  p.radiance = t.radiance;
  p.area = t.area;
  return p;
}

}  // namespace

EmitterPolygons MergeEmitterPolygons(const std::vector<EmitterTriangle>& emitters) {
  EmitterPolygons out;
  if (emitters.empty()) return out;
  // Planes are compared relative to the emitters' extent (scale-free).
  glm::vec3 lo = emitters[0].p0, hi = emitters[0].p0;
  for (const EmitterTriangle& t : emitters) {
    for (const glm::vec3& p : {t.p0, t.p1, t.p2}) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  }
  const float plane_tolerance = 1e-5f * std::max(glm::length(hi - lo), 1e-30f);
  std::vector<Group> groups;
  for (size_t i = 0; i < emitters.size(); ++i) {
    const EmitterTriangle& t = emitters[i];
    const float offset = glm::dot(t.normal, t.p0);
    Group* found = nullptr;
    for (Group& g : groups) {
      if (g.radiance == t.radiance && glm::dot(g.normal, t.normal) > 1.0f - 1e-5f &&
          std::abs(g.offset - offset) <= plane_tolerance) {
        found = &g;
        break;
      }
    }
    if (found == nullptr) {
      // Every group is at least one polygon: too many planes, no exact term.
      if (groups.size() >= size_t(kMaxEmitterPolygons)) return {};
      groups.push_back({t.normal, offset, t.radiance, {}});
      found = &groups.back();
    }
    found->triangles.push_back(int(i));
  }

  out.polygon_of_triangle.assign(emitters.size(), -1);
  for (const Group& g : groups) {
    // Hull in the plane's 2D basis (u, v, normal right-handed).
    const glm::dvec3 n(g.normal);
    const glm::dvec3 helper = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 u = glm::normalize(glm::cross(helper, n));
    const glm::dvec3 v = glm::cross(n, u);
    std::vector<glm::dvec2> points;
    double area_sum = 0.0;
    for (int ti : g.triangles) {
      const EmitterTriangle& t = emitters[size_t(ti)];
      for (const glm::vec3& p : {t.p0, t.p1, t.p2}) {
        points.push_back({glm::dot(glm::dvec3(p), u), glm::dot(glm::dvec3(p), v)});
      }
      area_sum += double(t.area);
    }
    const std::vector<glm::dvec2> hull = ConvexHull(std::move(points));
    const double hull_area = hull.size() >= 3 ? Area2(hull) : 0.0;
    if (g.triangles.size() > 1 && hull.size() <= size_t(EmitterPolygon::kMaxVertices) &&
        std::abs(hull_area - area_sum) <= 1e-4 * area_sum) {
      EmitterPolygon p;
      const double offset = double(g.offset);
      for (const glm::dvec2& q : hull) {  // counter-clockwise about the normal
        p.vertices[size_t(p.vertex_count++)] = glm::vec3(q.x * u + q.y * v + offset * n);
      }
      p.normal = g.normal;
      p.radiance = g.radiance;
      p.area = float(area_sum);
      for (int ti : g.triangles) out.polygon_of_triangle[size_t(ti)] = int(out.polygons.size());
      out.polygons.push_back(p);
    } else {
      for (int ti : g.triangles) {
        if (out.polygons.size() >= size_t(kMaxEmitterPolygons)) return {};
        out.polygon_of_triangle[size_t(ti)] = int(out.polygons.size());
        out.polygons.push_back(FromTriangle(emitters[size_t(ti)]));
      }
    }
  }
  return out;
}

}  // namespace gistream
