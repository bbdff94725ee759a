#include "scene/state/animation.h"

#include <algorithm>
#include <cmath>

#include "util/status.h"

namespace gistream {
namespace {

// Index k of the key interval [times[k], times[k + 1]] holding t, which
// lies strictly inside [times.front(), times.back()].
size_t Interval(const std::vector<float>& times, float t) {
  const auto it = std::upper_bound(times.begin(), times.end(), t);
  return size_t(it - times.begin()) - 1;
}

// The value element of key k (CUBICSPLINE keys are in-tangent, value,
// out-tangent: glTF 2.0 Appendix C).
const float* Value(const AnimationSampler& s, size_t k) {
  const size_t c = size_t(s.components);
  return s.interpolation == Interpolation::kCubicSpline ? &s.values[(3 * k + 1) * c]
                                                        : &s.values[k * c];
}

glm::quat Quat(const float* v) { return glm::quat(v[3], v[0], v[1], v[2]); }

void StoreQuat(const glm::quat& q, float* out) {
  out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
}

}  // namespace

glm::quat SlerpShortest(const glm::quat& a, const glm::quat& b, float s) {
  // q and -q are the same rotation; take the one within 90 degrees of a so
  // that the path is the shorter arc (glTF 2.0 Appendix C, "Spherical
  // Linear Interpolation").
  float d = glm::dot(a, b);
  const glm::quat b2 = d < 0.0f ? -b : b;
  d = std::abs(d);
  if (d > 0.9995f) return glm::normalize(a + s * (b2 - a));  // nearly equal: lerp is exact enough
  const float angle = std::acos(std::min(d, 1.0f));
  const float sin_angle = std::sin(angle);
  const float wa = std::sin((1.0f - s) * angle) / sin_angle;
  const float wb = std::sin(s * angle) / sin_angle;
  return glm::normalize(wa * a + wb * b2);
}

std::vector<float> SampleSampler(const AnimationSampler& s, AnimationPath path, float t) {
  GS_CHECK(!s.times.empty() && s.components > 0);
  const size_t c = size_t(s.components);
  std::vector<float> out(c);
  const float* v = nullptr;
  if (!(t > s.times.front())) {
    v = Value(s, 0);
  } else if (!(t < s.times.back())) {
    v = Value(s, s.times.size() - 1);
  }
  if (v != nullptr) {
    std::copy(v, v + c, out.begin());
    return out;
  }
  const size_t k = Interval(s.times, t);
  const float td = s.times[k + 1] - s.times[k];
  const float u = (t - s.times[k]) / td;  // in [0, 1)
  const float* v0 = Value(s, k);
  const float* v1 = Value(s, k + 1);
  switch (s.interpolation) {
    case Interpolation::kStep: std::copy(v0, v0 + c, out.begin()); break;
    case Interpolation::kLinear:
      if (path == AnimationPath::kRotation) {
        StoreQuat(SlerpShortest(Quat(v0), Quat(v1), u), out.data());
      } else {
        for (size_t i = 0; i < c; ++i) out[i] = v0[i] + u * (v1[i] - v0[i]);
      }
      break;
    case Interpolation::kCubicSpline: {
      // Cubic Hermite spline, glTF 2.0 Appendix C: with b_k the out-tangent
      // of key k and a_{k+1} the in-tangent of key k+1, both scaled by the
      // interval td,
      //   p(u) = (2u^3 - 3u^2 + 1) v_k + td (u^3 - 2u^2 + u) b_k
      //        + (-2u^3 + 3u^2) v_{k+1} + td (u^3 - u^2) a_{k+1}.
      const float* b0 = v0 + c;  // out-tangent of key k
      const float* a1 = v1 - c;  // in-tangent of key k + 1
      const float u2 = u * u, u3 = u2 * u;
      const float h00 = 2 * u3 - 3 * u2 + 1, h10 = td * (u3 - 2 * u2 + u);
      const float h01 = -2 * u3 + 3 * u2, h11 = td * (u3 - u2);
      for (size_t i = 0; i < c; ++i) out[i] = h00 * v0[i] + h10 * b0[i] + h01 * v1[i] + h11 * a1[i];
      if (path == AnimationPath::kRotation) {
        const glm::quat q = Quat(out.data());
        const float len = glm::length(q);
        // The spline of unit keys can pass near zero only with wild
        // tangents; fall back to the nearer key then.
        StoreQuat(len > 1e-6f ? q / len : Quat(u < 0.5f ? v0 : v1), out.data());
      }
      break;
    }
  }
  return out;
}

std::vector<NodeOverride> SampleAnimation(const Animation& animation, float t, AnimationTime mode) {
  if (mode == AnimationTime::kLoop) {
    const float duration = animation.end - animation.start;
    if (duration > 0.0f && std::isfinite(t)) {
      float r = std::fmod(t - animation.start, duration);
      if (r < 0.0f) r += duration;
      t = animation.start + r;
    } else {
      t = animation.start;
    }
  }
  std::vector<NodeOverride> out;
  for (const AnimationChannel& ch : animation.channels) {
    const AnimationSampler& s = animation.samplers[size_t(ch.sampler)];
    const std::vector<float> v = SampleSampler(s, ch.path, t);
    auto it = std::find_if(out.begin(), out.end(),
                           [&](const NodeOverride& o) { return o.node == ch.node; });
    if (it == out.end()) {
      out.push_back(NodeOverride{.node = ch.node});
      it = out.end() - 1;
    }
    switch (ch.path) {
      case AnimationPath::kTranslation: it->translation = glm::vec3(v[0], v[1], v[2]); break;
      case AnimationPath::kRotation: it->rotation = Quat(v.data()); break;
      case AnimationPath::kScale: it->scale = glm::vec3(v[0], v[1], v[2]); break;
      case AnimationPath::kWeights: it->weights = v; break;
    }
  }
  return out;
}

void ApplyOverrides(std::span<const NodeOverride> overrides, std::vector<Node>* nodes) {
  for (const NodeOverride& o : overrides) {
    Node& n = (*nodes)[size_t(o.node)];
    if (o.translation) n.translation = *o.translation;
    if (o.rotation) n.rotation = *o.rotation;
    if (o.scale) n.scale = *o.scale;
    if (!o.weights.empty()) n.weights = o.weights;
  }
}

}  // namespace gistream
