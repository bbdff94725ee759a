#include "solvers/pathtrace/scene_bvh.h"

#include <cmath>
#include <limits>

#include "solvers/pathtrace/sampling.h"

namespace gistream::pathtrace {

absl::StatusOr<std::unique_ptr<SceneBvh>> SceneBvh::Build(const SceneState& state) {
  auto bvh = std::unique_ptr<SceneBvh>(new SceneBvh());
  bvh->device_ = rtcNewDevice(nullptr);
  if (!bvh->device_) return absl::InternalError("pathtrace: Embree device could not start");
  const Scene& scene = state.scene();
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  Bounds bounds;
  for (size_t n = 0; n < scene.nodes.size(); ++n) {
    const int mesh = scene.nodes[n].mesh;
    if (mesh < 0) continue;
    const glm::mat4& m = state.world()[n];
    const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(m)));
    for (const Primitive& p : state.NodeMesh(n).primitives) {  // posed when it deforms
      for (size_t i = 0; i + 2 < p.indices.size(); i += 3) {
        Triangle t;
        const uint32_t a = p.indices[i], b = p.indices[i + 1], c = p.indices[i + 2];
        const glm::vec3 p0 = glm::vec3(m * glm::vec4(p.positions[a], 1.0f));
        const glm::vec3 p1 = glm::vec3(m * glm::vec4(p.positions[b], 1.0f));
        const glm::vec3 p2 = glm::vec3(m * glm::vec4(p.positions[c], 1.0f));
        const glm::vec3 cross = glm::cross(p1 - p0, p2 - p0);
        const float len = glm::length(cross);
        if (!(len > 0.0f) || !std::isfinite(len)) continue;  // degenerate
        t.p0 = p0;
        t.e1 = p1 - p0;
        t.e2 = p2 - p0;
        t.area = 0.5f * len;
        auto unit = [](const glm::vec3& v, const glm::vec3& fallback) {
          const float l = glm::length(v);
          return l > 0.0f && std::isfinite(l) ? v / l : fallback;
        };
        t.normal = cross / len;
        t.n0 = unit(nm * p.normals[a], t.normal);
        t.n1 = unit(nm * p.normals[b], t.normal);
        t.n2 = unit(nm * p.normals[c], t.normal);
        if (glm::dot(t.n0 + t.n1 + t.n2, t.normal) < 0.0f) t.normal = -t.normal;
        if (!p.uvs.empty()) {
          t.uv0 = p.uvs[a];
          t.uv1 = p.uvs[b];
          t.uv2 = p.uvs[c];
        }
        t.material = p.material;
        positions.insert(positions.end(), {p0, p1, p2});
        const uint32_t base = uint32_t(positions.size() - 3);
        indices.insert(indices.end(), {base, base + 1, base + 2});
        bounds.Extend(p0);
        bounds.Extend(p1);
        bounds.Extend(p2);
        bvh->triangles_.push_back(t);
      }
    }
  }
  bvh->scale_ = bounds.empty() ? 1.0f : std::max(glm::length(bounds.extent()), 1e-12f);

  bvh->UpdateEmitters(state);

  bvh->scene_ = rtcNewScene(bvh->device_);
  rtcSetSceneBuildQuality(bvh->scene_, RTC_BUILD_QUALITY_HIGH);
  if (!bvh->triangles_.empty()) {
    RTCGeometry geom = rtcNewGeometry(bvh->device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size()));
    auto* ib = static_cast<uint32_t*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(uint32_t), indices.size() / 3));
    if (!vb || !ib) {
      rtcReleaseGeometry(geom);
      return absl::ResourceExhaustedError("pathtrace: Embree could not allocate geometry");
    }
    for (size_t i = 0; i < positions.size(); ++i) {
      vb[3 * i] = positions[i].x;
      vb[3 * i + 1] = positions[i].y;
      vb[3 * i + 2] = positions[i].z;
    }
    std::copy(indices.begin(), indices.end(), ib);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(bvh->scene_, geom);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(bvh->scene_);
  return bvh;
}

void SceneBvh::UpdateEmitters(const SceneState& state) {
  // Emitters by luminous power; emission is read from the current state.
  emitters_.clear();
  emitter_cdf_.assign(1, 0.0);
  emitter_total_ = 0.0;
  for (size_t i = 0; i < triangles_.size(); ++i) {
    Triangle& t = triangles_[i];
    t.emitter = -1;
    if (t.material < 0) continue;
    const Material& m = state.materials()[size_t(t.material)];
    t.double_sided = m.double_sided;
    const float lum = Luminance(m.emission());
    if (!(lum > 0.0f) || !std::isfinite(lum)) continue;
    t.emitter = int(emitters_.size());
    emitters_.push_back(uint32_t(i));
    emitter_total_ += double(lum) * double(t.area) * (t.double_sided ? 2.0 : 1.0);
    emitter_cdf_.push_back(emitter_total_);
  }
}

SceneBvh::~SceneBvh() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

Hit SceneBvh::Intersect(const glm::vec3& origin, const glm::vec3& dir, float tmax) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = origin.x;
  rh.ray.org_y = origin.y;
  rh.ray.org_z = origin.z;
  rh.ray.dir_x = dir.x;
  rh.ray.dir_y = dir.y;
  rh.ray.dir_z = dir.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = tmax;
  rh.ray.mask = 0xffffffffu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rh);
  Hit hit;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.hit = true;
  hit.t = rh.ray.tfar;
  hit.triangle = rh.hit.primID;
  hit.u = rh.hit.u;
  hit.v = rh.hit.v;
  return hit;
}

bool SceneBvh::Occluded(const glm::vec3& origin, const glm::vec3& dir, float tmax) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  ray.org_x = origin.x;
  ray.org_y = origin.y;
  ray.org_z = origin.z;
  ray.dir_x = dir.x;
  ray.dir_y = dir.y;
  ray.dir_z = dir.z;
  ray.tnear = 0.0f;
  ray.tfar = tmax;
  ray.mask = 0xffffffffu;
  rtcOccluded1(scene_, &context, &ray);
  return ray.tfar < 0.0f;  // Embree sets tfar = -inf on a hit
}

}  // namespace gistream::pathtrace
