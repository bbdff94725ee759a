#include "solvers/pathtrace/scene_bvh.h"

#include <cmath>
#include <limits>

#include "solvers/shading/sampling.h"

namespace gistream::pathtrace {

namespace {

// Triangle `i` (its first index) of primitive `p` of a node with world
// matrix `m` (normal matrix `nm`); false when it is degenerate.
bool WorldTriangle(const glm::mat4& m, const glm::mat3& nm, const Primitive& p, size_t i,
                   Triangle& t) {
  const uint32_t a = p.indices[i], b = p.indices[i + 1], c = p.indices[i + 2];
  const glm::vec3 p0 = glm::vec3(m * glm::vec4(p.positions[a], 1.0f));
  const glm::vec3 p1 = glm::vec3(m * glm::vec4(p.positions[b], 1.0f));
  const glm::vec3 p2 = glm::vec3(m * glm::vec4(p.positions[c], 1.0f));
  const glm::vec3 cross = glm::cross(p1 - p0, p2 - p0);
  const float len = glm::length(cross);
  if (!(len > 0.0f) || !std::isfinite(len)) return false;
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
  return true;
}

// Calls f(triangle, candidate) for each non-degenerate triangle of node
// `n`'s current mesh, `candidate` counting all its triangles from `first`;
// returns the count after the node.
template <typename F>
uint32_t ForEachTriangle(const SceneState& state, size_t n, uint32_t first, F&& f) {
  const glm::mat4& m = state.world()[n];
  const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(m)));
  uint32_t candidate = first;
  for (const Primitive& p : state.NodeMesh(n).primitives) {  // posed when it deforms
    for (size_t i = 0; i + 2 < p.indices.size(); i += 3, ++candidate) {
      Triangle t;
      if (WorldTriangle(m, nm, p, i, t)) f(t, candidate);
    }
  }
  return candidate;
}

Bounds TriangleBox(const Triangle& t) {
  Bounds b;
  b.Extend(t.p0);
  b.Extend(t.p0 + t.e1);
  b.Extend(t.p0 + t.e2);
  return b;
}

// Embree's copy of the vertices of `ids` (triangles_ indices), three each.
void WriteVertices(const std::vector<Triangle>& triangles, const std::vector<uint32_t>& ids,
                   float* vb) {
  for (size_t j = 0; j < ids.size(); ++j) {
    const Triangle& t = triangles[ids[j]];
    const glm::vec3 v[3] = {t.p0, t.p0 + t.e1, t.p0 + t.e2};
    for (int k = 0; k < 3; ++k) {
      vb[9 * j + 3 * size_t(k)] = v[k].x;
      vb[9 * j + 3 * size_t(k) + 1] = v[k].y;
      vb[9 * j + 3 * size_t(k) + 2] = v[k].z;
    }
  }
}

}  // namespace

absl::StatusOr<std::unique_ptr<SceneBvh>> SceneBvh::Build(const SceneState& state) {
  auto bvh = std::unique_ptr<SceneBvh>(new SceneBvh());
  bvh->device_ = rtcNewDevice(nullptr);
  if (!bvh->device_) return absl::InternalError("pathtrace: Embree device could not start");
  const Scene& scene = state.scene();
  Bounds bounds;
  uint32_t deforming_candidates = 0;
  for (size_t n = 0; n < scene.nodes.size(); ++n) {
    if (scene.nodes[n].mesh < 0) continue;
    const bool deforms = state.Deforms(n);
    const unsigned geometry = deforms ? kDeforming : kRigid;
    const uint32_t after = ForEachTriangle(
        state, n, deforms ? deforming_candidates : 0, [&](const Triangle& t, uint32_t candidate) {
          bvh->geometry_triangles_[geometry].push_back(uint32_t(bvh->triangles_.size()));
          bvh->triangles_.push_back(t);
          if (deforms) {
            bvh->deforming_source_.push_back(candidate);
          } else {
            bvh->rigid_bounds_.Extend(TriangleBox(t));
          }
          bounds.Extend(TriangleBox(t));
        });
    if (deforms) deforming_candidates = after;
  }
  bvh->scale_ = bounds.empty() ? 1.0f : std::max(glm::length(bounds.extent()), 1e-12f);
  const std::vector<uint32_t>& deforming = bvh->geometry_triangles_[kDeforming];
  if (!deforming.empty()) {
    std::vector<Bounds> boxes;
    boxes.reserve(deforming.size());
    for (uint32_t id : deforming) boxes.push_back(TriangleBox(bvh->triangles_[id]));
    bvh->quality_ = RefitQuality(boxes);
  }

  bvh->UpdateEmitters(state);

  bvh->scene_ = rtcNewScene(bvh->device_);
  // Two-level only when something deforms: Embree then builds each
  // geometry with its own quality (HIGH is SAH, REFIT keeps the topology).
  rtcSetSceneBuildQuality(bvh->scene_,
                          deforming.empty() ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_LOW);
  for (unsigned geometry : {kRigid, kDeforming}) {
    const std::vector<uint32_t>& ids = bvh->geometry_triangles_[geometry];
    if (ids.empty()) continue;
    RTCGeometry geom = rtcNewGeometry(bvh->device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * ids.size()));
    auto* ib = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), ids.size()));
    if (!vb || !ib) {
      rtcReleaseGeometry(geom);
      return absl::ResourceExhaustedError("pathtrace: Embree could not allocate geometry");
    }
    WriteVertices(bvh->triangles_, ids, vb);
    for (uint32_t i = 0; i < 3 * uint32_t(ids.size()); ++i) ib[i] = i;
    rtcSetGeometryBuildQuality(
        geom, geometry == kDeforming ? RTC_BUILD_QUALITY_REFIT : RTC_BUILD_QUALITY_HIGH);
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(bvh->scene_, geom, geometry);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(bvh->scene_);
  return bvh;
}

RefitResult SceneBvh::Refit(const SceneState& state) {
  const std::vector<uint32_t>& ids = geometry_triangles_[kDeforming];
  if (ids.empty()) return RefitResult::kNothingDeforms;
  // The posed triangles, in the build's order; the same non-degenerate ones.
  std::vector<Triangle> posed;
  posed.reserve(ids.size());
  bool same = true;
  uint32_t candidates = 0;
  for (int n : state.deforming_nodes()) {
    candidates =
        ForEachTriangle(state, size_t(n), candidates, [&](const Triangle& t, uint32_t candidate) {
          const size_t k = posed.size();
          same = same && k < deforming_source_.size() && deforming_source_[k] == candidate;
          posed.push_back(t);
        });
  }
  if (!same || posed.size() != ids.size()) return RefitResult::kTopology;
  std::vector<Bounds> boxes;
  boxes.reserve(posed.size());
  for (const Triangle& t : posed) boxes.push_back(TriangleBox(t));
  refit_growth_ = quality_.Growth(boxes);
  if (!(refit_growth_ <= RefitQuality::kMaxCostGrowth)) return RefitResult::kQuality;

  Bounds bounds = rigid_bounds_;
  for (size_t j = 0; j < ids.size(); ++j) {
    triangles_[ids[j]] = posed[j];
    bounds.Extend(boxes[j]);
  }
  scale_ = bounds.empty() ? 1.0f : std::max(glm::length(bounds.extent()), 1e-12f);
  RTCGeometry geom = rtcGetGeometry(scene_, kDeforming);
  WriteVertices(triangles_, ids,
                static_cast<float*>(rtcGetGeometryBufferData(geom, RTC_BUFFER_TYPE_VERTEX, 0)));
  rtcUpdateGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0);
  rtcCommitGeometry(geom);
  rtcCommitScene(scene_);  // Embree refits the geometry's BVH: its index buffer is unchanged
  UpdateEmitters(state);   // areas changed
  return RefitResult::kRefit;
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
    const float lum = shading::Luminance(m.emission());
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
  hit.triangle = geometry_triangles_[rh.hit.geomID][rh.hit.primID];
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
