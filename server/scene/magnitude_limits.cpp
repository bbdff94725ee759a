#include "scene/magnitude_limits.h"

#include <algorithm>
#include <absl/strings/string_view.h>

#include <cmath>

namespace gistream {
namespace {

const char* Axis(int i) { return i == 0 ? "x" : i == 1 ? "y" : "z"; }

}  // namespace

absl::Status CheckMagnitude(const std::string& field, double v, double lo, double hi) {
  if (!(v >= lo && v <= hi)) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": ", v, " is out of range [", lo, ", ", hi, "]"));
  }
  return absl::OkStatus();
}

absl::Status CheckPosition(const std::string& field, const glm::vec3& p) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(p[i])) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ".", Axis(i), ": ", p[i], " is not finite"));
    }
    if (std::abs(p[i]) > kMaxCoordinate) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".", Axis(i), ": ", p[i],
                                                     " is beyond the world extent limit of +-",
                                                     kMaxCoordinate, " m"));
    }
  }
  return absl::OkStatus();
}

absl::Status CheckScale(const std::string& field, const glm::vec3& s) {
  for (int i = 0; i < 3; ++i) {
    const float a = std::abs(s[i]);
    if (!(a >= kMinScale && a <= kMaxScale)) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".", Axis(i), ": ", s[i],
                                                     " is out of range: |scale| must be in [",
                                                     kMinScale, ", ", kMaxScale, "]"));
    }
  }
  return absl::OkStatus();
}

absl::StatusOr<glm::quat> CheckUnitQuaternion(const std::string& field, const glm::quat& q) {
  const glm::dvec4 v(q.w, q.x, q.y, q.z);
  for (int i = 0; i < 4; ++i) {
    if (!std::isfinite(v[i])) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".", absl::string_view(&"wxyz"[i], 1),
                                                     ": ", float(v[i]), " is not finite"));
    }
  }
  const double len = glm::length(v);
  if (!(len > 0.0)) return absl::InvalidArgumentError(field + ": zero-length quaternion");
  if (std::abs(len - 1.0) > kQuaternionTolerance) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": length ", len, " is not 1 (within ",
                                                   kQuaternionTolerance,
                                                   "); rotations must be unit quaternions"));
  }
  return glm::quat(float(v[0] / len), float(v[1] / len), float(v[2] / len), float(v[3] / len));
}

absl::Status CheckWorldExtent(const Scene& scene, const std::vector<Node>& nodes,
                              const std::vector<glm::mat4>& world, const std::string& prefix) {
  for (size_t n = 0; n < nodes.size(); ++n) {
    const glm::mat4& m = world[n];
    const std::string node = absl::StrCat("nodes[", n, "]");
    for (int c = 0; c < 3; ++c) {
      const float s = glm::length(glm::vec3(m[c]));
      if (!(s >= kMinScale && s <= kMaxScale)) {
        return absl::InvalidArgumentError(
            absl::StrCat(prefix, node, ": world scale ", Axis(c), " ", s, " is out of range [",
                         kMinScale, ", ", kMaxScale, "] (the product of its ancestors' scales)"));
      }
    }
    GS_RETURN_IF_ERROR(
        CheckPosition(absl::StrCat(prefix, node, ": world position"), glm::vec3(m[3])));
    if (nodes[n].mesh < 0 || size_t(nodes[n].mesh) >= scene.meshes.size()) continue;
    for (const Primitive& p : scene.meshes[size_t(nodes[n].mesh)].primitives) {
      if (p.bounds.empty()) continue;
      for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 local((corner & 1) ? p.bounds.max.x : p.bounds.min.x,
                              (corner & 2) ? p.bounds.max.y : p.bounds.min.y,
                              (corner & 4) ? p.bounds.max.z : p.bounds.min.z);
        GS_RETURN_IF_ERROR(CheckPosition(absl::StrCat(prefix, node, ": mesh vertex in world space"),
                                         glm::vec3(m * glm::vec4(local, 1.0f))));
      }
    }
  }
  return absl::OkStatus();
}

float MaxEmission(const Material& m) {
  const glm::vec3 e = m.emissive_factor * m.emissive_strength;
  return std::max({e.x, e.y, e.z});
}

float MaxLightStrength(const Light& l) {
  const glm::vec3 e = l.color * l.intensity;
  return std::max({e.x, e.y, e.z});
}

float MaxPixel(const Image& image) {
  float out = 0.0f;
  if (image.is_float) {
    for (size_t i = 0; i < image.pixelsf.size(); ++i) {
      if (i % 4 != 3) out = std::max(out, image.pixelsf[i]);
    }
  } else {
    for (size_t i = 0; i < image.pixels8.size(); ++i) {
      if (i % 4 != 3) out = std::max(out, float(image.pixels8[i]) / 255.0f);
    }
  }
  return out;
}

}  // namespace gistream
