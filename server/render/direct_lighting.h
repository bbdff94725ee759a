// Direct light for every solver: punctual lights and stratified area-light
// samples as GPU buffers, each with its shadow map. shaders/render/
// direct_light.glsl evaluates it. Later solvers reuse this for their direct
// light and first bounce.
#pragma once

#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "gl/bindings.h"
#include "gl/buffers.h"
#include "gl/handle.h"
#include "gl/program.h"
#include "render/area_lights.h"
#include "render/emitter_polygons.h"
#include "render/shadow_maps.h"
#include "scene/gpu/gpu_scene.h"
#include "render/environment_lights.h"
#include "scene/updates.h"
#include "util/params.h"

namespace gistream {

struct DirectLightingSettings {
  int area_samples = 64;  // stratified points over all emissive surfaces
  int shadow_resolution = 256;
  // Shadow maps from the full meshes instead of proxies (issue 19).
  bool full_detail = false;
  // The environment map as its cut's directional lights, each with a
  // shadow map (render/environment_lights.h), for the solvers that light
  // it no other way; false: not lit here.
  bool environment_lights = false;
};

// The parameters every solver that uses DirectLighting offers
// (`area_samples`, `shadow_res`, `full_detail`), and the settings they give.
std::vector<ParamSpec> DirectLightingParams();
DirectLightingSettings DirectLightingFromParams(const ParamSet& params);

class DirectLighting {
 public:
  static absl::StatusOr<DirectLighting> Create();

  // Rebuilds the light buffers and redraws the shadow maps that `changes`
  // made stale. Call when geometry, lights or emission changed, or the
  // settings did. A geometry change (or a new shadow-map layout) redraws
  // every map; otherwise only the maps whose origin, range or direction
  // moved are redrawn, so an intensity, colour or emission-strength change
  // redraws none and moving one light redraws only its maps.
  // INVALID_ARGUMENT naming params.area_samples/params.shadow_res when the
  // shadow cubes exceed the GL's array layers or kMaxShadowBytes (nothing
  // is changed).
  //
  // With `budget_ms` > 0 a change that makes every map stale (after the
  // first set) is drawn into a second set of maps, about `budget_ms` of
  // drawing per call, while the shown set (maps and light buffers that
  // agree) stays bound; Continue() draws more, and the new set is shown
  // once every map of it is drawn (pending() is false again). Twice the
  // shadow-map memory while that is used. A change while a set of the same
  // layout is drawn queues its set: the one being drawn is finished and
  // shown first, so the shadows follow changes that come every frame, a
  // set's drawing time behind (sets_shown() counts them). Continue (no
  // change since the last call) draws the queued set at once instead when
  // the one being drawn is less than half drawn, once per set shown.
  absl::Status Update(const SceneState& state, const GpuScene& gpu,
                      const DirectLightingSettings& settings, ChangeMask changes = kChangeAll,
                      double budget_ms = 0.0);
  void Continue(const GpuScene& gpu, const SceneState& state, double budget_ms);
  bool pending() const { return pending_ != nullptr; }
  // Sets drawn in slices and shown so far.
  uint64_t sets_shown() const { return sets_shown_; }

  // Binds buffers (SSBO 1..3 and 12), shadow maps (units 4, 5) and sets uniforms
  // of a program that includes render/direct_light.glsl.
  void Bind(gl::Program& program) const;

  int punctual_count() const { return punctual_count_; }
  const std::vector<EmitterSample>& area_samples() const { return samples_; }
  const std::vector<EmitterTriangle>& emitters() const { return emitters_; }
  // Polygons of the exact unoccluded term (0: the disc estimate is used).
  int emitter_polygons() const { return polygon_count_; }
  uint64_t gpu_bytes() const { return shadows_.gpu_bytes() + back_.gpu_bytes(); }
  // Shadow maps (cube-map sets and directional maps) the last Update drew.
  int maps_redrawn() const { return maps_redrawn_; }

  static constexpr GLuint kCubeShadowUnit = GS_UNIT_CUBE_SHADOWS;
  static constexpr uint64_t kMaxShadowBytes = uint64_t(2) << 30;
  static constexpr GLuint kDirShadowUnit = GS_UNIT_DIR_SHADOWS;
  static constexpr GLuint kPolygonBinding = GS_BINDING_EMITTER_POLYGONS;

 private:
  // Where each shadow map was drawn from: it stays valid while the
  // geometry does not move and this does not change.
  struct CubeView {
    glm::vec3 origin{0.0f};
    float far = 0.0f;
    bool operator==(const CubeView&) const = default;
  };
  struct DirView {
    glm::vec3 direction{0.0f};
    glm::mat4 view_proj{1.0f};
  };

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
  GS_STD430_MIRROR(GpuPunctual, 64);    // render/direct_light.glsl PunctualLight
  GS_STD430_MIRROR(GpuAreaSample, 48);  // AreaSample
  struct GpuPolygon {
    glm::vec4 radiance_count;  // rgb radiance, w: vertex count
    glm::vec4 normal;          // xyz emitting side
    glm::ivec4 samples;        // x: first area sample, y: how many
    glm::vec4 vertices[EmitterPolygon::kMaxVertices];
  };
  GS_STD430_MIRROR(GpuPolygon, 48 + 16 * EmitterPolygon::kMaxVertices);  // EmitterPolygon
  static std::vector<GpuPolygon> PolygonsOf(const std::vector<EmitterTriangle>& emitters,
                                            std::vector<EmitterSample>& samples);
  // A light set: its buffers, where each map is drawn from, and the maps
  // still to draw.
  struct Pending {
    std::vector<EmitterTriangle> emitters;
    std::vector<EmitterSample> samples;
    int resolution = 0;
    bool full_detail = false;
    std::vector<GpuPunctual> punctual;
    std::vector<GpuAreaSample> area;
    std::vector<GpuPolygon> polygons;
    std::vector<CubeView> cube_views;
    std::vector<DirView> dir_views;
    std::vector<int> cube_draws, dir_draws;
    size_t next_cube = 0, next_dir = 0;
  };
  // Draws `set`'s remaining maps into `target` (about `budget_ms` of them
  // when > 0, at least one); true when none remains.
  bool Draw(const GpuScene& gpu, const SceneState& state, ShadowMaps& target, Pending& set,
            double budget_ms);
  // Shows `set`: its buffers and views become the bound ones.
  void Commit(Pending set);
  // Whether `b`'s maps can be drawn into the maps allocated for `a`.
  static bool SameLayout(const Pending& a, const Pending& b);
  static size_t DrawnMaps(const Pending& set);
  static size_t TotalMaps(const Pending& set);
  // Draws more of pending_ (which must be set); shows it once whole, then
  // queued_ becomes pending_.
  void Advance(const GpuScene& gpu, const SceneState& state, double budget_ms);
  // Update's steps. The shadow maps' bytes for the state's lights and
  // `area_samples` samples at `resolution`, or INVALID_ARGUMENT naming the
  // parameters when the GL's layers or kMaxShadowBytes cannot hold them.
  static absl::StatusOr<uint64_t> ShadowBytes(const SceneState& state, size_t area_samples,
                                              size_t environment_lights, int resolution);
  // The light set to show next: its buffers (punctual lights, area
  // samples, emitter polygons) and where each map is drawn from; no map is
  // marked to draw yet.
  static Pending NextLightSet(const SceneState& state, const GpuScene& gpu,
                              const DirectLightingSettings& settings,
                              std::vector<EmitterTriangle> emitters,
                              std::vector<EmitterSample> samples,
                              const std::vector<EnvironmentRegionLight>& environment);

  ShadowMaps shadows_;  // shown
  ShadowMaps back_;     // drawn into while a sliced set is pending
  std::unique_ptr<Pending> pending_;
  std::unique_ptr<Pending> queued_;  // the newest set, after pending_
  uint64_t sets_shown_ = 0;
  bool dropped_since_shown_ = false;  // Continue dropped a set for queued_
  bool drawn_once_ = false;
  std::vector<CubeView> cube_views_;
  std::vector<DirView> dir_views_;
  int maps_redrawn_ = 0;
  gl::Buffer punctual_;
  gl::Buffer samples_buffer_;
  gl::Buffer dir_matrices_;
  gl::Buffer polygons_;
  int polygon_count_ = 0;
  std::vector<EmitterTriangle> emitters_;
  std::vector<EmitterSample> samples_;
  int punctual_count_ = 0;
  int shadow_resolution_ = 0;
  bool full_detail_ = false;
};

}  // namespace gistream
