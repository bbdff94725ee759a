#include "render/direct_lighting.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "gl/buffers.h"

namespace gistream {

// The emitters as convex polygons for the exact term, each with the range
// of area samples on it (samples reordered by polygon; polygons without a
// sample last, where the shader uses the visibility of all samples before).
std::vector<DirectLighting::GpuPolygon> DirectLighting::PolygonsOf(
    const std::vector<EmitterTriangle>& emitters, std::vector<EmitterSample>& samples) {
  const EmitterPolygons merged = MergeEmitterPolygons(emitters);
  if (merged.polygons.empty()) return {};
  auto polygon_of = [&](const EmitterSample& s) {
    return merged.polygon_of_triangle[size_t(s.triangle)];
  };
  std::stable_sort(samples.begin(), samples.end(),
                   [&](const EmitterSample& a, const EmitterSample& b) {
                     return polygon_of(a) < polygon_of(b);
                   });
  std::vector<GpuPolygon> with, without;
  size_t next = 0;
  for (size_t p = 0; p < merged.polygons.size(); ++p) {
    const EmitterPolygon& poly = merged.polygons[p];
    GpuPolygon g{};
    g.radiance_count = glm::vec4(poly.radiance, float(poly.vertex_count));
    g.normal = glm::vec4(poly.normal, 0.0f);
    const size_t first = next;
    while (next < samples.size() && polygon_of(samples[next]) == int(p)) ++next;
    g.samples = glm::ivec4(int(first), int(next - first), 0, 0);
    for (int v = 0; v < poly.vertex_count; ++v)
      g.vertices[v] = glm::vec4(poly.vertices[size_t(v)], 1.0f);
    (next > first ? with : without).push_back(g);
  }
  with.insert(with.end(), without.begin(), without.end());
  return with;
}

std::vector<ParamSpec> DirectLightingParams() {
  // clang-format off
  return {{"area_samples", ParamType::kInt, "64", 1, 1024, {},
           "Stratified sample points over all emissive surfaces, each with a shadow map"},
          {"shadow_res", ParamType::kInt, "256", 16, 4096, {},
           "Shadow map resolution per cube face / directional map"},
          {"full_detail", ParamType::kBool, "false", 0, 0, {},
           "Draw the shadow maps from the full meshes instead of their simplified proxies "
           "(docs/ARCHITECTURE.md, Proxy geometry)"}};
  // clang-format on
}

DirectLightingSettings DirectLightingFromParams(const ParamSet& params) {
  DirectLightingSettings settings;
  settings.area_samples = params.GetInt("area_samples");
  settings.shadow_resolution = params.GetInt("shadow_res");
  settings.full_detail = params.GetBool("full_detail");
  return settings;
}

absl::StatusOr<DirectLighting> DirectLighting::Create() {
  DirectLighting lighting;
  GS_ASSIGN_OR_RETURN(lighting.shadows_, ShadowMaps::Create());
  GS_ASSIGN_OR_RETURN(lighting.back_, ShadowMaps::Create());
  return lighting;
}

absl::StatusOr<uint64_t> DirectLighting::ShadowBytes(const SceneState& state, size_t area_samples,
                                                     size_t environment_lights, int resolution) {
  int cube_count = int(area_samples), dir_count = int(environment_lights);
  for (const LightInstance& l : state.lights()) {
    (l.light.type == LightType::kDirectional ? dir_count : cube_count)++;
  }
  // One cube per point/spot light and area sample, in one cube-map array:
  // refuse what the GL or memory cannot hold rather than render unshadowed.
  GLint max_layers = 0;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
  const uint64_t bytes = uint64_t(resolution) * uint64_t(resolution) * 4 *
                         (6 * uint64_t(cube_count) + uint64_t(dir_count));
  if (6 * int64_t(cube_count) > int64_t(max_layers) || bytes > kMaxShadowBytes) {
    return absl::InvalidArgumentError(
        absl::StrCat("params.area_samples/params.shadow_res: ", cube_count, " shadow cubes (",
                     area_samples, " area samples + point/spot lights) at ", resolution, "^2 need ",
                     6 * cube_count, " layers and ", bytes >> 20, " MiB; this GL allows ",
                     max_layers / 6, " cubes and the limit is ", kMaxShadowBytes >> 20, " MiB"));
  }
  return bytes;
}

DirectLighting::Pending DirectLighting::NextLightSet(
    const SceneState& state, const GpuScene& gpu, const DirectLightingSettings& settings,
    std::vector<EmitterTriangle> emitters, std::vector<EmitterSample> samples,
    const std::vector<EnvironmentRegionLight>& environment) {
  // The light set to show next: buffers, and where every map is drawn from.
  Pending next;
  next.emitters = std::move(emitters);
  next.samples = std::move(samples);
  next.polygons = PolygonsOf(next.emitters, next.samples);
  next.resolution = settings.shadow_resolution;
  next.full_detail = settings.full_detail;
  const Bounds bounds = gpu.WorldBounds(state);  // follows moved nodes
  int cube = 0;
  for (const LightInstance& l : state.lights()) {
    GpuPunctual g{};
    const float type = l.light.type == LightType::kPoint  ? 0.0f
                       : l.light.type == LightType::kSpot ? 1.0f
                                                          : 2.0f;
    g.position_type = glm::vec4(l.position, type);
    g.direction = glm::vec4(l.direction, 0.0f);
    g.intensity = glm::vec4(l.light.color * l.light.intensity, 0.0f);
    // KHR_lights_punctual: scale = 1 / max(0.001, cos(inner) - cos(outer)),
    // offset = -cos(outer) * scale.
    const float cos_outer = std::cos(l.light.outer_cone_angle);
    const float scale = 1.0f / std::max(0.001f, std::cos(l.light.inner_cone_angle) - cos_outer);
    if (l.light.type == LightType::kDirectional) {
      g.cone_shadow = glm::vec4(0.0f, 0.0f, float(next.dir_views.size()), 0.0f);
      next.dir_views.push_back({l.direction, glm::mat4(1.0f)});
    } else {
      const float far = ShadowFar(bounds, l.position);
      g.cone_shadow = glm::vec4(scale, -cos_outer * scale, float(cube++), far);
      next.cube_views.push_back({l.position, far});
    }
    next.punctual.push_back(g);
  }
  // The environment's regions: directional lights (type 2) shining away
  // from them, illuminance their L d(omega) sum.
  for (const EnvironmentRegionLight& l : environment) {
    GpuPunctual g{};
    g.position_type = glm::vec4(0.0f, 0.0f, 0.0f, 2.0f);
    g.direction = glm::vec4(-l.to_sky, 0.0f);
    g.intensity = glm::vec4(l.irradiance, 0.0f);
    g.cone_shadow = glm::vec4(0.0f, 0.0f, float(next.dir_views.size()), 0.0f);
    next.dir_views.push_back({-l.to_sky, glm::mat4(1.0f)});
    next.punctual.push_back(g);
  }
  for (const EmitterSample& sample : next.samples) {
    // Start the shadow rays a hair in front of the emitter so the emitter
    // does not shadow itself.
    const float far = ShadowFar(bounds, sample.position);
    const glm::vec3 origin = sample.position + sample.normal * (far * 1e-5f);
    next.area.push_back({glm::vec4(origin, sample.area), glm::vec4(sample.normal, float(cube++)),
                         glm::vec4(sample.radiance, far)});
    next.cube_views.push_back({origin, far});
  }
  return next;
}

absl::Status DirectLighting::Update(const SceneState& state, const GpuScene& gpu,
                                    const DirectLightingSettings& settings, ChangeMask changes,
                                    double budget_ms) {
  std::vector<EmitterTriangle> emitters = CollectEmitters(state);
  std::vector<EmitterSample> emitter_samples = SampleEmitters(emitters, settings.area_samples);
  const std::vector<EnvironmentRegionLight> environment =
      settings.environment_lights ? EnvironmentLights(state)
                                  : std::vector<EnvironmentRegionLight>{};
  GS_ASSIGN_OR_RETURN(
      const uint64_t bytes,
      ShadowBytes(state, emitter_samples.size(), environment.size(), settings.shadow_resolution));
  Pending next = NextLightSet(state, gpu, settings, std::move(emitters), std::move(emitter_samples),
                              environment);
  const int cube_count = int(next.cube_views.size());
  const int dir_count = int(next.dir_views.size());

  // A new layout reallocates the maps; moved geometry changes what every
  // map sees: both redraw everything. Otherwise only the maps whose origin,
  // range or direction moved.
  // A set still being drawn means the shown maps saw older geometry: all
  // of them are stale too.
  const bool all_stale =
      (changes & kChangeShape) || pending_ != nullptr || cube_count != int(cube_views_.size()) ||
      dir_count != int(dir_views_.size()) || settings.shadow_resolution != shadow_resolution_ ||
      settings.full_detail != full_detail_;
  maps_redrawn_ = 0;
  // The second set doubles the maps' memory: only when both fit the limit.
  if (all_stale && budget_ms > 0.0 && drawn_once_ && 2 * bytes <= kMaxShadowBytes) {
    // Sliced: every map is drawn into the other set, a budget's worth per
    // frame, while the shown set (maps and buffers that agree) stays bound.
    for (size_t i = 0; i < next.cube_views.size(); ++i) next.cube_draws.push_back(int(i));
    for (size_t i = 0; i < next.dir_views.size(); ++i) next.dir_draws.push_back(int(i));
    if (pending_ && SameLayout(*pending_, next)) {
      // A set is being drawn into maps of the same layout: it is finished
      // first and shown (its maps saw this change's geometry or the one
      // before, newer than the shown set's), then this one is drawn. Were
      // it replaced, changes every frame would keep the shown set, the
      // shadows of where things were when they started to move, for as
      // long as they move (a set takes a few frames' budgets).
      queued_ = std::make_unique<Pending>(std::move(next));
    } else {
      queued_.reset();
      back_.Allocate(cube_count, dir_count, settings.shadow_resolution);
      pending_ = std::make_unique<Pending>(std::move(next));
    }
    Advance(gpu, state, budget_ms);
    return absl::OkStatus();
  }
  pending_.reset();  // drawn in place below, from this change's light set
  queued_.reset();
  dropped_since_shown_ = false;
  // In place: the stale maps of the shown set.
  shadows_.Allocate(cube_count, dir_count, settings.shadow_resolution);
  for (size_t i = 0; i < next.cube_views.size(); ++i) {
    if (all_stale || !(cube_views_[i] == next.cube_views[i])) next.cube_draws.push_back(int(i));
  }
  for (size_t i = 0; i < next.dir_views.size(); ++i) {
    if (all_stale || dir_views_[i].direction != next.dir_views[i].direction) {
      next.dir_draws.push_back(int(i));
    } else {
      next.dir_views[i].view_proj = dir_views_[i].view_proj;
    }
  }
  Draw(gpu, state, shadows_, next, 0.0);
  Commit(std::move(next));
  return absl::OkStatus();
}

bool DirectLighting::Draw(const GpuScene& gpu, const SceneState& state, ShadowMaps& target,
                          Pending& set, double budget_ms) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto over = [&] {
    return budget_ms > 0.0 &&
           std::chrono::duration<double, std::milli>(Clock::now() - start).count() >= budget_ms;
  };
  bool drew = false;
  while (set.next_dir < set.dir_draws.size()) {
    if (drew && over()) return false;
    const int i = set.dir_draws[set.next_dir++];
    set.dir_views[size_t(i)].view_proj = target.RenderDirectional(
        gpu, state, i, set.dir_views[size_t(i)].direction, set.full_detail);
    ++maps_redrawn_;
    drew = true;
  }
  while (set.next_cube < set.cube_draws.size()) {
    if (drew && over()) return false;
    const int i = set.cube_draws[set.next_cube++];
    target.RenderCube(gpu, state, i, set.cube_views[size_t(i)].origin,
                      set.cube_views[size_t(i)].far, set.full_detail);
    ++maps_redrawn_;
    drew = true;
    if (budget_ms > 0.0) glFinish();  // the budget counts the GPU's time too
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return true;
}

void DirectLighting::Continue(const GpuScene& gpu, const SceneState& state, double budget_ms) {
  if (!pending_) return;
  // No change since the last call: the changes paused or stopped, and the
  // newest state is what will be shown longest. A set that waits behind
  // one less than half drawn is drawn now instead of after it (once per set
  // shown, so that changes every other frame still get sets shown).
  if (queued_ && !dropped_since_shown_ && 2 * DrawnMaps(*pending_) < TotalMaps(*pending_)) {
    pending_ = std::move(queued_);
    dropped_since_shown_ = true;
  }
  Advance(gpu, state, budget_ms);
}

void DirectLighting::Advance(const GpuScene& gpu, const SceneState& state, double budget_ms) {
  maps_redrawn_ = 0;
  if (!Draw(gpu, state, back_, *pending_, budget_ms)) return;
  // Every map of the new set is drawn: show it.
  std::swap(shadows_, back_);
  Commit(std::move(*pending_));
  ++sets_shown_;
  dropped_since_shown_ = false;
  // The newest change's set, if one came while it was drawn, is next, into
  // the maps just hidden (sized anew: they may be of the set shown before,
  // another layout).
  pending_ = std::move(queued_);
  if (pending_) {
    back_.Allocate(int(pending_->cube_views.size()), int(pending_->dir_views.size()),
                   pending_->resolution);
  }
}

size_t DirectLighting::DrawnMaps(const Pending& set) { return set.next_cube + set.next_dir; }

size_t DirectLighting::TotalMaps(const Pending& set) {
  return set.cube_draws.size() + set.dir_draws.size();
}

bool DirectLighting::SameLayout(const Pending& a, const Pending& b) {
  return a.resolution == b.resolution && a.full_detail == b.full_detail &&
         a.cube_views.size() == b.cube_views.size() && a.dir_views.size() == b.dir_views.size();
}

void DirectLighting::Commit(Pending set) {
  emitters_ = std::move(set.emitters);
  samples_ = std::move(set.samples);
  shadow_resolution_ = set.resolution;
  full_detail_ = set.full_detail;
  cube_views_ = std::move(set.cube_views);
  dir_views_ = std::move(set.dir_views);
  std::vector<glm::mat4> dir_matrices;
  for (const DirView& view : dir_views_) dir_matrices.push_back(view.view_proj);
  punctual_count_ = int(set.punctual.size());
  punctual_ = gl::StorageBuffer(set.punctual);
  samples_buffer_ = gl::StorageBuffer(set.area);
  dir_matrices_ = gl::StorageBuffer(dir_matrices);
  polygon_count_ = int(set.polygons.size());
  polygons_ = gl::StorageBuffer(set.polygons);
  drawn_once_ = true;
}

void DirectLighting::Bind(gl::Program& program) const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GS_BINDING_PUNCTUAL_LIGHTS, punctual_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GS_BINDING_AREA_SAMPLES, samples_buffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GS_BINDING_DIR_SHADOW_MATRICES, dir_matrices_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kPolygonBinding, polygons_.id());
  shadows_.Bind(kCubeShadowUnit, kDirShadowUnit);
  program.Set("uPunctualCount", punctual_count_);
  program.Set("uAreaSampleCount", int(samples_.size()));
  program.Set("uPolygonCount", polygon_count_);
  program.Set("uShadowTexel", 2.0f / float(std::max(shadow_resolution_, 1)));
}

}  // namespace gistream
