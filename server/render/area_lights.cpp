#include "render/area_lights.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace gistream {
namespace {

float Luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

float RadicalInverse2(uint32_t bits) {
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return float(bits) * 2.3283064365386963e-10f;
}

}  // namespace

std::vector<EmitterTriangle> CollectEmitters(const SceneState& state) {
  std::vector<EmitterTriangle> out;
  const Scene& scene = state.scene();
  for (size_t n = 0; n < scene.nodes.size(); ++n) {
    const int mesh = scene.nodes[n].mesh;
    if (mesh < 0) continue;
    const glm::mat4& m = state.world()[n];
    for (const Primitive& p : state.NodeMesh(n).primitives) {  // posed when it deforms
      if (p.material < 0) continue;
      const Material& mat = state.materials()[size_t(p.material)];
      if (!mat.emissive()) continue;
      for (size_t i = 0; i + 2 < p.indices.size(); i += 3) {
        EmitterTriangle t;
        t.p0 = glm::vec3(m * glm::vec4(p.positions[p.indices[i]], 1.0f));
        t.p1 = glm::vec3(m * glm::vec4(p.positions[p.indices[i + 1]], 1.0f));
        t.p2 = glm::vec3(m * glm::vec4(p.positions[p.indices[i + 2]], 1.0f));
        const glm::vec3 cross = glm::cross(t.p1 - t.p0, t.p2 - t.p0);
        const float len = glm::length(cross);
        if (!(len > 0.0f) || !std::isfinite(len)) continue;
        t.area = 0.5f * len;
        t.normal = cross / len;
        // Emit on the side the authored vertex normals point to.
        const glm::vec3 vn =
            glm::mat3(glm::transpose(glm::inverse(m))) *
            (p.normals[p.indices[i]] + p.normals[p.indices[i + 1]] + p.normals[p.indices[i + 2]]);
        if (glm::dot(vn, t.normal) < 0.0f) t.normal = -t.normal;
        t.radiance = mat.emission();
        out.push_back(t);
        if (mat.double_sided) {
          // glTF 2.0 (3.9.2, doubleSided): the back face is a surface with
          // the flipped normal, so it emits too. Listed as a second,
          // one-sided triangle (winding reversed to match), which every
          // consumer (area samples, VPL paths, power sums) handles as is.
          std::swap(t.p1, t.p2);
          t.normal = -t.normal;
          out.push_back(t);
        }
      }
    }
  }
  return out;
}

glm::vec3 EmittedPower(const std::vector<EmitterTriangle>& emitters) {
  glm::vec3 power(0.0f);
  for (const EmitterTriangle& t : emitters) power += glm::pi<float>() * t.radiance * t.area;
  return power;
}

std::vector<EmitterSample> SampleEmitters(const std::vector<EmitterTriangle>& emitters, int count) {
  std::vector<EmitterSample> out;
  if (emitters.empty() || count <= 0) return out;
  // CDF over triangles by luminous power L * A.
  std::vector<double> cdf(emitters.size() + 1, 0.0);
  for (size_t i = 0; i < emitters.size(); ++i) {
    cdf[i + 1] = cdf[i] + double(Luminance(emitters[i].radiance)) * double(emitters[i].area);
  }
  const double total = cdf.back();
  if (!(total > 0.0)) return out;
  out.reserve(size_t(count));
  for (int i = 0; i < count; ++i) {
    // Hammersley point (u, v); u picks the triangle and a coordinate in it.
    const double u = (double(i) + 0.5) / double(count) * total;
    const float v = RadicalInverse2(uint32_t(i));
    const size_t t = size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()) - 1;
    const size_t ti = std::min(t, emitters.size() - 1);
    const EmitterTriangle& tri = emitters[ti];
    const double w = cdf[ti + 1] - cdf[ti];
    const float u1 = float(std::clamp((u - cdf[ti]) / w, 0.0, 1.0));
    // Uniform point on the triangle from (u1, v).
    const float su = std::sqrt(u1);
    const float b0 = 1.0f - su, b1 = su * (1.0f - v), b2 = su * v;
    EmitterSample s;
    s.position = b0 * tri.p0 + b1 * tri.p1 + b2 * tri.p2;
    s.normal = tri.normal;
    s.radiance = tri.radiance;
    s.triangle = int(ti);
    // pdf(y) = lum_t / total (per unit area), so A_i = total / (N lum_t).
    s.area = float(total / (double(count) * double(Luminance(tri.radiance))));
    out.push_back(s);
  }
  return out;
}

}  // namespace gistream
