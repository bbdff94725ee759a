#include "render/direct_lighting.h"

#include <algorithm>
#include <cmath>

namespace gistream {
namespace {

// std430 mirrors of shaders/render/direct_light.glsl.
struct GpuPunctual {
  glm::vec4 position_type;
  glm::vec4 direction;
  glm::vec4 intensity;
  glm::vec4 cone_shadow;
};
struct GpuAreaSample {
  glm::vec4 position_area;
  glm::vec4 normal_shadow;
  glm::vec4 radiance_far;
};

template <typename T>
void Upload(gl::Buffer& buffer, const std::vector<T>& data) {
  buffer = gl::Buffer::Create();
  const T zero{};
  glNamedBufferStorage(buffer.id(), GLsizeiptr(std::max<size_t>(data.size(), 1) * sizeof(T)),
                       data.empty() ? &zero : data.data(), 0);
}

}  // namespace

std::vector<ParamSpec> DirectLightingParams() {
  return {{"area_samples", ParamType::kInt, "64", 1, 1024, {},
           "Stratified sample points over all emissive surfaces, each with a shadow map"},
          {"shadow_res", ParamType::kInt, "256", 16, 4096, {},
           "Shadow map resolution per cube face / directional map"}};
}

DirectLightingSettings DirectLightingFromParams(const ParamSet& params) {
  DirectLightingSettings settings;
  settings.area_samples = params.GetInt("area_samples");
  settings.shadow_resolution = params.GetInt("shadow_res");
  return settings;
}

absl::StatusOr<DirectLighting> DirectLighting::Create() {
  DirectLighting lighting;
  GS_ASSIGN_OR_RETURN(lighting.shadows_, ShadowMaps::Create());
  return lighting;
}

absl::Status DirectLighting::Update(const SceneState& state, const GpuScene& gpu,
                                    const DirectLightingSettings& settings, ChangeMask changes) {
  std::vector<EmitterTriangle> emitters = CollectEmitters(state);
  std::vector<EmitterSample> emitter_samples = SampleEmitters(emitters, settings.area_samples);

  int cube_count = 0, dir_count = 0;
  for (const LightInstance& l : state.lights()) {
    (l.light.type == LightType::kDirectional ? dir_count : cube_count)++;
  }
  cube_count += int(emitter_samples.size());
  // One cube per point/spot light and area sample, in one cube-map array:
  // refuse what the GL or memory cannot hold rather than render unshadowed.
  GLint max_layers = 0;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
  const uint64_t bytes = uint64_t(settings.shadow_resolution) * uint64_t(settings.shadow_resolution) *
                         4 * (6 * uint64_t(cube_count) + uint64_t(dir_count));
  if (6 * int64_t(cube_count) > int64_t(max_layers) || bytes > kMaxShadowBytes) {
    return absl::InvalidArgumentError(absl::StrCat(
        "params.area_samples/params.shadow_res: ", cube_count, " shadow cubes (",
        emitter_samples.size(), " area samples + point/spot lights) at ", settings.shadow_resolution,
        "^2 need ", 6 * cube_count, " layers and ", bytes >> 20,
        " MiB; this GL allows ", max_layers / 6, " cubes and the limit is ",
        kMaxShadowBytes >> 20, " MiB"));
  }
  emitters_ = std::move(emitters);
  samples_ = std::move(emitter_samples);
  // A new layout reallocates the maps; moved geometry changes what every
  // map sees: both redraw everything.
  const bool all_stale = (changes & kChangeGeometry) || cube_count != int(cube_views_.size()) ||
                         dir_count != int(dir_views_.size()) ||
                         settings.shadow_resolution != shadow_resolution_;
  shadows_.Allocate(cube_count, dir_count, settings.shadow_resolution);
  shadow_resolution_ = settings.shadow_resolution;
  if (all_stale) {
    cube_views_.assign(size_t(cube_count), CubeView{glm::vec3(0.0f), -1.0f});
    dir_views_.assign(size_t(dir_count), DirView{glm::vec3(0.0f), glm::mat4(1.0f)});
  }
  maps_redrawn_ = 0;
  auto cube_map = [&](int index, const glm::vec3& origin, float far) {
    const CubeView view{origin, far};
    if (cube_views_[size_t(index)] == view) return;
    shadows_.RenderCube(gpu, state, index, origin, far);
    cube_views_[size_t(index)] = view;
    ++maps_redrawn_;
  };

  std::vector<GpuPunctual> punctual;
  std::vector<glm::mat4> dir_matrices;
  int cube = 0;
  const Bounds bounds = gpu.WorldBounds(state);  // follows moved nodes
  for (const LightInstance& l : state.lights()) {
    GpuPunctual g{};
    const float type = l.light.type == LightType::kPoint ? 0.0f
                       : l.light.type == LightType::kSpot ? 1.0f : 2.0f;
    g.position_type = glm::vec4(l.position, type);
    g.direction = glm::vec4(l.direction, 0.0f);
    g.intensity = glm::vec4(l.light.color * l.light.intensity, 0.0f);
    // KHR_lights_punctual: scale = 1 / max(0.001, cos(inner) - cos(outer)),
    // offset = -cos(outer) * scale.
    const float cos_outer = std::cos(l.light.outer_cone_angle);
    const float scale = 1.0f / std::max(0.001f, std::cos(l.light.inner_cone_angle) - cos_outer);
    if (l.light.type == LightType::kDirectional) {
      const int index = int(dir_matrices.size());
      DirView& view = dir_views_[size_t(index)];
      if (all_stale || view.direction != l.direction) {
        view = {l.direction, shadows_.RenderDirectional(gpu, state, index, l.direction)};
        ++maps_redrawn_;
      }
      dir_matrices.push_back(view.view_proj);
      g.cone_shadow = glm::vec4(0.0f, 0.0f, float(index), 0.0f);
    } else {
      const float far = ShadowFar(bounds, l.position);
      cube_map(cube, l.position, far);
      g.cone_shadow = glm::vec4(scale, -cos_outer * scale, float(cube), far);
      ++cube;
    }
    punctual.push_back(g);
  }
  std::vector<GpuAreaSample> samples;
  samples.reserve(samples_.size());
  for (const EmitterSample& s : samples_) {
    // Start the shadow rays a hair in front of the emitter so the emitter
    // does not shadow itself.
    const float far = ShadowFar(bounds, s.position);
    const glm::vec3 origin = s.position + s.normal * (far * 1e-5f);
    cube_map(cube, origin, far);
    samples.push_back({glm::vec4(origin, s.area), glm::vec4(s.normal, float(cube)),
                       glm::vec4(s.radiance, far)});
    ++cube;
  }
  punctual_count_ = int(punctual.size());
  Upload(punctual_, punctual);
  Upload(samples_buffer_, samples);
  Upload(dir_matrices_, dir_matrices);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return absl::OkStatus();
}

void DirectLighting::Bind(gl::Program& program) const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, punctual_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, samples_buffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, dir_matrices_.id());
  shadows_.Bind(kCubeShadowUnit, kDirShadowUnit);
  program.Set("uPunctualCount", punctual_count_);
  program.Set("uAreaSampleCount", int(samples_.size()));
  program.Set("uShadowTexel", 2.0f / float(std::max(shadow_resolution_, 1)));
}

}  // namespace gistream
