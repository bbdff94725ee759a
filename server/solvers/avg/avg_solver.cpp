#include "solvers/avg/avg_solver.h"
#include "solvers/registry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include <glm/gtc/constants.hpp>

#include "avg/bindings.glsl"  // shaders/: the slots its passes declare
#include "solvers/tail_estimate.h"

namespace gistream {
namespace {

float Luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

// One VPL map layer may not exceed this (GL_MAX_ARRAY_TEXTURE_LAYERS is at
// least 2048 on GL 4.5; the vpls range keeps within it) nor the atlas 1 GiB.
constexpr double kMaxAtlasBytes = 1024.0 * 1024.0 * 1024.0;

}  // namespace

SolverDescription AvgSolver::Describe() {
  SolverDescription d;
  d.name = "avg";
  d.description =
      "Instant radiosity: VPLs traced through an approximate visibility grid (Bashford-Rogers "
      "et al.), paraboloid VPL shadow maps, interleaved sampling with a geometry-aware filter";
  d.stages = {"voxelize", "trace_vpls", "vpl_shadow_maps", "gbuffer", "illuminate", "filter"};
  // clang-format off
  d.params = {
      {"vpls", ParamType::kInt, "1024", 16, 2048, {},
       "Virtual point lights placed per solution (16 subsets of vpls/16 for interleaved shading)"},
      {"grid", ParamType::kInt, "64", 8, 256, {},
       "Voxels per axis of the approximate visibility grid (fitted to the scene bounds)"},
      {"bounces", ParamType::kInt, "8", 1, avg::VplTraceSettings::kMaxBounces, {},
       "VPL generations per light path at most (with the split, most paths end sooner)"},
      {"roulette", ParamType::kBool, "true", 0, 0, {},
       "Keller's split: of N paths round(N mean_albedo^b) go on after b reflections (false: "
       "every path runs `bounces`)"},
      {"tail_estimate", ParamType::kBool, "true", 0, 0, {},
       "When `bounces` cuts the paths short, the last generation's VPLs also carry the "
       "generations not traced (geometric tail of the measured flux, at most the largest albedo)"},
      {"shadow_res", ParamType::kInt, "64", 8, 512, {},
       "Resolution of each VPL's paraboloid shadow map"},
      {"visibility", ParamType::kBool, "true", 0, 0, {},
       "Shadow-test VPL light (false: no VPL shadow maps, the paper's FPS(NV))"},
      {"clamp", ParamType::kFloat, "0.02", 0.0, 1.0, {},
       "Geometry-term bias d as a fraction of the scene diagonal: G = cos cos / (r^2 + d^2)"},
      {"still_vpls", ParamType::kInt, "2048", 0, 2048, {},
       "VPLs of a still view: once nothing changed since the shown VPLs, still_vpls - vpls more "
       "are traced and mapped in the background and joined to them (at most vpls: none)"},
      {"area_samples", ParamType::kInt, "32", 1, 1024, {},
       "Direct light: stratified samples over emissive surfaces, each with a shadow map"},
      {"direct_shadow_res", ParamType::kInt, "256", 16, 4096, {},
       "Direct light: shadow map resolution per cube face / directional map"},
      {"full_detail", ParamType::kBool, "false", 0, 0, {},
       "Voxelize and draw the direct-light and VPL shadow maps from the full meshes instead of "
       "their simplified proxies (docs/ARCHITECTURE.md, Proxy geometry)"},
  };
  // clang-format on
  return d;
}

const SolverDescription& AvgSolver::description() const {
  static const SolverDescription kDescription = Describe();
  return kDescription;
}

absl::StatusOr<std::unique_ptr<Solver>> AvgSolver::Create(const ParamSet& params) {
  auto solver = std::unique_ptr<AvgSolver>(new AvgSolver());
  solver->grid_resolution_ = params.GetInt("grid");
  solver->trace_settings_.vpls = params.GetInt("vpls");
  solver->trace_settings_.bounces = params.GetInt("bounces");
  solver->trace_settings_.roulette = params.GetBool("roulette");
  solver->tail_estimate_ = params.GetBool("tail_estimate");
  solver->shadow_resolution_ = params.GetInt("shadow_res");
  solver->visibility_ = params.GetBool("visibility");
  solver->clamp_ = float(params.GetFloat("clamp"));
  solver->still_vpls_ = params.GetInt("still_vpls");
  const int layers = std::max(solver->trace_settings_.vpls, solver->still_vpls_);
  solver->direct_settings_.area_samples = params.GetInt("area_samples");
  solver->direct_settings_.shadow_resolution = params.GetInt("direct_shadow_res");
  solver->full_detail_ = params.GetBool("full_detail");
  solver->direct_settings_.full_detail = solver->full_detail_;
  // The environment as directional lights, for the direct light and the
  // VPLs' paths (render/environment_lights.h).
  solver->direct_settings_.environment_lights = true;
  // Two atlases: the shown one and the one a re-map draws into.
  const double atlas =
      2.0 * double(layers) * solver->shadow_resolution_ * solver->shadow_resolution_ * 4.0;
  if (atlas > kMaxAtlasBytes) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "params.shadow_res: ", layers, " VPL maps of ", solver->shadow_resolution_, "^2 need ",
        int64_t(atlas / 1048576.0),
        " MiB for the two atlases (shown and re-mapped), more than the 1024 MiB limit; lower "
        "shadow_res, vpls or still_vpls"));
  }
  GLint max_layers = 0;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
  if (layers > max_layers) {
    return absl::ResourceExhaustedError(
        absl::StrCat(solver->still_vpls_ > solver->trace_settings_.vpls ? "params.still_vpls: "
                                                                        : "params.vpls: ",
                     layers, " exceeds this GPU's ", max_layers, " shadow-map array layers"));
  }
  GS_ASSIGN_OR_RETURN(solver->shadow_maps_, avg::VplShadowMaps::Create());
  GS_ASSIGN_OR_RETURN(solver->remap_, avg::VplShadowMaps::Create());
  GS_ASSIGN_OR_RETURN(solver->direct_, DirectLighting::Create());
  GS_ASSIGN_OR_RETURN(solver->illuminate_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                          {GL_FRAGMENT_SHADER, "avg/illuminate.frag.glsl"}}));
  GS_ASSIGN_OR_RETURN(solver->filter_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                          {GL_FRAGMENT_SHADER, "avg/filter.frag.glsl"}}));
  return solver;
}

bool AvgSolver::NeedsVoxelize(ChangeMask changes) {
  // The grid holds geometry and albedo.
  return (changes & (kChangeShape | kChangeMaterials)) != 0;
}

bool AvgSolver::NeedsTrace(ChangeMask changes) {
  return NeedsVoxelize(changes) || (changes & (kChangeLights | kChangeEmission)) != 0;
}

std::vector<std::string> AvgSolver::Plan(const SceneState& state, ChangeMask changes) const {
  changes = EnvironmentAsLights(changes, state);
  // A background trace under way (or due) may be taken, or the next one
  // started, in any frame: its stages are reported in the frame that
  // takes it, and the re-map starts there.
  const bool busy = trace_job_.running() || trace_job_.again() || extend_job_.running();
  if (NeedsVoxelize(changes) || (trace_job_.running() && job_voxelizes_) || NeedsVoxelize(due_)) {
    return {"voxelize", "trace_vpls", "vpl_shadow_maps", "gbuffer", "illuminate", "filter"};
  }
  if (NeedsTrace(changes) || busy)
    return {"trace_vpls", "vpl_shadow_maps", "gbuffer", "illuminate", "filter"};
  if (remap_pending_ || direct_.pending()) {
    return {"vpl_shadow_maps", "gbuffer", "illuminate", "filter"};
  }
  // Camera (or environment, which avg does not use): VPLs and shadow maps
  // are view-independent.
  return {"gbuffer", "illuminate", "filter"};
}

void AvgSolver::ContinueRemap(SolverContext& ctx) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const int total = int(remap_layers_.size());
  while (remap_next_ < total) {
    int count = total - remap_next_;
    const double elapsed = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    if (ctx.budget_ms > 0.0 && remap_next_ > 0 && elapsed >= ctx.budget_ms) break;
    if (ctx.budget_ms > 0.0) {
      // No estimate yet: a few maps measure one.
      count = ms_per_map_ > 0.0 ? std::clamp(int((ctx.budget_ms - elapsed) / ms_per_map_), 1, count)
                                : std::min(count, 4);
    }
    const auto slice = Clock::now();
    // Consecutive layers in one instanced draw each.
    for (int i = remap_next_; i < remap_next_ + count;) {
      int j = i + 1;
      while (j < remap_next_ + count &&
             remap_layers_[size_t(j)] == remap_layers_[size_t(j - 1)] + 1) {
        ++j;
      }
      remap_.RenderRange(ctx.gpu, ctx.state, shadow_resolution_, remap_layers_[size_t(i)], j - i,
                         full_detail_);
      i = j;
    }
    glFinish();  // the slice's GPU time sizes the next slice
    const double per_map =
        std::chrono::duration<double, std::milli>(Clock::now() - slice).count() / double(count);
    ms_per_map_ = ms_per_map_ > 0.0 ? 0.5 * (ms_per_map_ + per_map) : per_map;
    remap_next_ += count;
    vpl_maps_redrawn_ += count;
    if (ctx.budget_ms > 0.0 &&
        std::chrono::duration<double, std::milli>(Clock::now() - start).count() >= ctx.budget_ms) {
      break;
    }
  }
  if (remap_next_ >= total) {
    std::swap(shadow_maps_, remap_);  // the old atlas is the next re-map's target
    mapped_vpls_ = std::move(remap_vpls_);
    mapped_path_first_ = std::move(remap_path_first_);
    mapped_bounds_ = remap_bounds_;
    remap_vpls_.clear();
    remap_path_first_.clear();
    remap_layers_.clear();
    // The shown maps saw the geometry as it was when the re-map started,
    // and any change noted since (a background trace of it is under way).
    unmapped_change_ = std::exchange(remap_change_, Bounds{});
    unmapped_all_ = std::exchange(remap_all_, false);
    shown_version_ = remap_version_;
    remap_pending_ = false;
  }
}

void AvgSolver::StartRemap(SolverContext& ctx, const Bounds& grid_bounds) {
  remap_.Upload(trace_.vpls, grid_bounds);
  remap_vpls_ = trace_.vpls;
  remap_path_first_ = trace_.path_first;
  remap_bounds_ = grid_bounds;
  remap_layers_.clear();
  remap_next_ = 0;
  remap_pending_ = true;
  remap_change_ = Bounds{};
  remap_all_ = false;
  vpl_maps_kept_ = 0;
  // A map depends on its VPL's position and normal, its far plane (from
  // the grid box) and the geometry in its hemisphere (z >= 0 in the VPL's
  // frame, shaders/avg/vpl_shadow.geom.glsl). Path i's k-th VPL is looked
  // up where the shown set held path i's k-th VPL.
  const bool comparable = !unmapped_all_ && !(mapped_bounds_.min != grid_bounds.min) &&
                          !(mapped_bounds_.max != grid_bounds.max);
  const float margin = 1e-4f * glm::length(grid_bounds.extent());
  auto sees_change = [&](const avg::Vpl& v) {
    if (unmapped_change_.empty()) return false;
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 c((corner & 1) ? unmapped_change_.max.x : unmapped_change_.min.x,
                        (corner & 2) ? unmapped_change_.max.y : unmapped_change_.min.y,
                        (corner & 4) ? unmapped_change_.max.z : unmapped_change_.min.z);
      if (glm::dot(c - v.position, v.normal) > -margin) return true;
    }
    return false;  // wholly behind the VPL: never drawn into its map
  };
  std::vector<std::pair<int, int>> copies;
  const size_t paths = trace_.path_first.size();
  for (size_t i = 0; i < paths; ++i) {
    const uint32_t first = trace_.path_first[i];
    const uint32_t end = i + 1 < paths ? trace_.path_first[i + 1] : uint32_t(trace_.vpls.size());
    const bool shown = comparable && i < mapped_path_first_.size();
    const uint32_t old_first = shown ? mapped_path_first_[i] : 0;
    const uint32_t old_end = !shown                              ? 0
                             : i + 1 < mapped_path_first_.size() ? mapped_path_first_[i + 1]
                                                                 : uint32_t(mapped_vpls_.size());
    for (uint32_t j = first; j < end; ++j) {
      const avg::Vpl& v = trace_.vpls[j];
      const uint32_t old = old_first + (j - first);
      if (shown && old < old_end && mapped_vpls_[old].position == v.position &&
          mapped_vpls_[old].normal == v.normal && !sees_change(v)) {
        copies.emplace_back(int(old), int(j));
      } else {
        remap_layers_.push_back(int(j));
      }
    }
  }
  if (!copies.empty()) remap_.CopyLayers(shadow_maps_, copies, shadow_resolution_);
  vpl_maps_kept_ = int(copies.size());
  ContinueRemap(ctx);
}

bool AvgSolver::SamePlacement(const std::vector<avg::Vpl>& a, const std::vector<avg::Vpl>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].position != b[i].position || a[i].normal != b[i].normal) return false;
  }
  return true;
}

void AvgSolver::NoteGeometryChange(const Bounds& moved, bool everywhere) {
  if (everywhere) {
    unmapped_all_ = true;
    if (remap_pending_) remap_all_ = true;
  } else {
    unmapped_change_.Extend(moved);
    if (remap_pending_) remap_change_.Extend(moved);
  }
}

void AvgSolver::StartTrace(const SolverContext& ctx) {
  auto job = std::make_shared<TraceJob>(ctx.state);
  job->changes = std::exchange(due_, ChangeMask(kChangeNone));
  job->voxelize = NeedsVoxelize(job->changes) || !grid_;
  if (job->voxelize) {
    job->moved = moved_.Since(ctx.gpu, ctx.state);
    moved_.Solved(ctx.state);
    // Only moved nodes (a material change alters albedo everywhere; a
    // geometry change with no moved box is a change MovedBounds cannot see).
    job->rebuild = !grid_ || (job->changes & kChangeMaterials) || job->moved.empty();
    // The maps' geometry: a material change alone leaves it as it was.
    NoteGeometryChange(job->moved, (job->changes & kChangeShape) && job->moved.empty());
  }
  // The clamp scales with the current geometry (moved or scaled nodes), not
  // the load-time Scene::bounds: a scene scaled to millimetres would
  // otherwise keep a metre-sized d and lose all indirect light.
  const Bounds scene_bounds = ctx.gpu.WorldBounds(ctx.state);
  job->clamp_distance = clamp_ * (scene_bounds.empty() ? 0.0f : glm::length(scene_bounds.extent()));
  job->grid = std::exchange(grid_, std::nullopt);
  job->paths = std::move(paths_);
  paths_ = avg::VplPathCache{};
  job_voxelizes_ = job->voxelize;
  const int resolution = grid_resolution_;
  const bool full_detail = full_detail_;
  const bool environment_lights = direct_settings_.environment_lights;
  avg::VplTraceSettings settings = trace_settings_;
  settings.tail_bound = tail_estimate_ ? LargestAlbedo(ctx.state) : 0.0;
  // A light change on a still view's VPLs (nothing to voxelize): its
  // second set is traced again too (a dimmer then keeps every map).
  std::optional<avg::VplTraceSettings> extension;
  if (extended_ && !job->voxelize) {
    extension = settings;
    extension->vpls = still_vpls_ - trace_settings_.vpls;
  }
  trace_job_.Start(std::move(job), [resolution, full_detail, settings, extension,
                                    environment_lights](TraceJob& j) {
    if (j.voxelize) {
      j.times.Time("voxelize", [&] {
        j.partial = !j.rebuild && j.grid && j.grid->Revoxelize(j.state, j.moved);
        if (j.partial) {
          const glm::vec3 cells = j.grid->rewritten().extent() / j.grid->voxel_size();
          j.voxels_rewritten = std::round(double(cells.x)) * std::round(double(cells.y)) *
                               std::round(double(cells.z));
        } else {
          j.grid = avg::VoxelGrid::Build(j.state, resolution, full_detail);
          j.voxels_rewritten = std::pow(double(j.grid->resolution()), 3.0);
        }
      });
    }
    j.times.Time("trace_vpls", [&] {
      j.grid_bounds.Extend(j.grid->origin());
      j.grid_bounds.Extend(j.grid->origin() + j.grid->extent());
      const std::vector<avg::VplLight> lights =
          avg::CollectVplLights(j.state, j.grid_bounds.center(),
                                0.5f * glm::length(j.grid_bounds.extent()), environment_lights);
      // After moved nodes only the paths whose rays cross the rewritten
      // voxels are traced again (Laine et al. 2007); the VPLs equal a full
      // trace's.
      j.trace = j.partial
                    ? avg::RetraceVpls(*j.grid, lights, settings, j.grid->rewritten(), j.paths)
                    : avg::TraceVpls(*j.grid, lights, settings, &j.paths);
      if (extension) j.joined = avg::TraceSecondSet(*j.grid, lights, *extension, j.trace);
    });
  });
}

void AvgSolver::TakeTrace(SolverContext& ctx, TraceJob& job) {
  // The job's CPU time is reported in the frame that takes its VPLs.
  job.times.RecordInto(ctx.timer);
  if (job.voxelize) {
    voxels_partial_ = job.partial;
    voxels_rewritten_ = job.voxels_rewritten;
  } else {
    ctx.timer.Skip("voxelize");
  }
  grid_ = std::move(job.grid);
  voxels_filled_ = grid_->filled();
  voxel_bytes_ = grid_->bytes();
  paths_ = std::move(job.paths);
  trace_ = std::move(job.trace);
  clamp_distance_ = job.clamp_distance;
  traced_ = true;
  gl::StageTimer::Scope stage(ctx.timer, "vpl_shadow_maps");
  // A VPL's paraboloid map depends on its position, its normal and the
  // geometry only: when a light change left every path where it was (a
  // dimmer, a colour; the paths are quasi-random in the path index), the
  // maps stay and only the VPLs' flux is new.
  const bool maps_valid = !job.voxelize && !(job.changes & kChangeShape) && !unmapped_all_ &&
                          unmapped_change_.empty() && !remap_pending_;
  // A still view's second set, traced again with the first (StartTrace),
  // stays where all its VPLs stayed too; else vpls again, the second set
  // coming after.
  if (job.joined && maps_valid && SamePlacement(mapped_vpls_, job.joined->vpls)) {
    still_vpls_shown_ = job.joined->vpls.size() - trace_.vpls.size();
    trace_ = std::move(*job.joined);
    extended_ = true;
  } else {
    still_vpls_shown_ = 0;
    extended_ = false;
  }
  const bool same_placement = maps_valid && SamePlacement(mapped_vpls_, trace_.vpls);
  vpl_maps_kept_ = 0;
  if (!visibility_ || same_placement) {
    shadow_maps_.Upload(trace_.vpls, job.grid_bounds);
    mapped_vpls_ = trace_.vpls;
    mapped_path_first_ = trace_.path_first;
    mapped_bounds_ = job.grid_bounds;
    remap_pending_ = false;  // a re-map of older VPLs is moot
    vpl_maps_kept_ = same_placement ? int(trace_.vpls.size()) : 0;
    shown_version_ = job.state.version();
  } else {
    // New maps are drawn into the other atlas in slices of the frame
    // budget; frames show the last VPLs and maps until all are drawn.
    remap_version_ = job.state.version();
    StartRemap(ctx, job.grid_bounds);
  }
}

void AvgSolver::StartExtension(const SolverContext& ctx) {
  auto job = std::make_shared<ExtendJob>(ctx.state);
  job->grid = &*grid_;
  job->grid_bounds = mapped_bounds_;
  job->base = trace_;
  avg::VplTraceSettings settings = trace_settings_;
  settings.vpls = still_vpls_ - trace_settings_.vpls;
  settings.tail_bound = tail_estimate_ ? LargestAlbedo(ctx.state) : 0.0;
  const bool environment_lights = direct_settings_.environment_lights;
  extend_job_.Start(std::move(job), [settings, environment_lights](ExtendJob& j) {
    j.times.Time("trace_vpls", [&] {
      const std::vector<avg::VplLight> lights =
          avg::CollectVplLights(j.state, j.grid_bounds.center(),
                                0.5f * glm::length(j.grid_bounds.extent()), environment_lights);
      j.trace = avg::TraceSecondSet(*j.grid, lights, settings, j.base);
    });
  });
}

void AvgSolver::TakeExtension(SolverContext& ctx, ExtendJob& job) {
  job.times.RecordInto(ctx.timer);
  ctx.timer.Skip("voxelize");
  extended_ = true;
  still_vpls_shown_ = job.trace.vpls.size() - job.base.vpls.size();
  trace_ = std::move(job.trace);
  gl::StageTimer::Scope stage(ctx.timer, "vpl_shadow_maps");
  vpl_maps_kept_ = 0;
  if (!visibility_) {
    shadow_maps_.Upload(trace_.vpls, job.grid_bounds);
    mapped_vpls_ = trace_.vpls;
    mapped_path_first_ = trace_.path_first;
    return;
  }
  // The shown VPLs' maps are copied, the second set's drawn in slices.
  remap_version_ = shown_version_;
  StartRemap(ctx, job.grid_bounds);
}

absl::Status AvgSolver::Update(SolverContext& ctx, ChangeMask changes) {
  changes = EnvironmentAsLights(changes, ctx.state);
  const bool first = !started_;
  latest_version_ = ctx.state.version();
  if (first) unmapped_all_ = true;
  vpl_maps_redrawn_ = 0;
  if (first || NeedsTrace(changes)) {
    // A still view's second set is of the old state: motion does not wait.
    extend_job_.Cancel();
    // The next job covers it; a running one traces older data.
    due_ |= first ? ChangeMask(kChangeAll) : changes;
    if (trace_job_.running()) trace_job_.Again();
    // The direct lights' shadow maps are drawn on this thread, sliced by
    // the frame budget like the VPL maps (they do not feed the VPLs).
    gl::StageTimer::Scope stage(ctx.timer, "vpl_shadow_maps");
    GS_RETURN_IF_ERROR(
        direct_.Update(ctx.state, ctx.gpu, direct_settings_, changes, ctx.budget_ms));
  } else if (direct_.pending()) {
    gl::StageTimer::Scope stage(ctx.timer, "vpl_shadow_maps");
    direct_.Continue(ctx.gpu, ctx.state, ctx.budget_ms);
  }
  bool taken = false;
  if (std::shared_ptr<TraceJob> job = trace_job_.TakeIfDone()) {
    TakeTrace(ctx, *job);
    taken = true;
  } else if (std::shared_ptr<ExtendJob> extension = extend_job_.TakeIfDone()) {
    TakeExtension(ctx, *extension);  // a cancelled one is never taken
    taken = true;
  } else if (remap_pending_) {
    gl::StageTimer::Scope stage(ctx.timer, "vpl_shadow_maps");
    ContinueRemap(ctx);
  }
  if (due_ != kChangeNone && !trace_job_.running() && !extend_job_.running()) {
    // Voxelize and trace run on the CPU pool on a copy of the scene state;
    // frames show the last VPLs and maps meanwhile, and before the first
    // job's, direct light alone (the render thread never waits for a job).
    StartTrace(ctx);
    started_ = true;
  } else if (due_ == kChangeNone && !trace_job_.running() && !extend_job_.running() &&
             !remap_pending_ && ExtensionDue()) {
    StartExtension(ctx);
  }
  if (!taken) {
    ctx.timer.Skip("voxelize");
    ctx.timer.Skip("trace_vpls");
  }
  ctx.timer.Skip("vpl_shadow_maps");  // reported run when any part above ran
  if (UpdateComplete()) shown_version_ = latest_version_;
  return absl::OkStatus();
}

absl::Status AvgSolver::Shade(SolverContext& ctx, const ViewCamera& camera,
                              const GBuffer& gbuffer) {
  const glm::ivec2 size(int(gbuffer.width()), int(gbuffer.height()));
  // Two RGBA32F targets over the view rounded up to whole 4x4 tiles.
  constexpr uint64_t kSide = avg::InterleavedBuffer::kSide;
  GS_RETURN_IF_ERROR(split_memory_.Fit(
      ctx, 0,
      (uint64_t(size.x) + kSide - 1) / kSide * kSide * ((uint64_t(size.y) + kSide - 1) / kSide) *
          kSide * 32,
      absl::StrCat("avg: width x height ", size.x, "x", size.y, " (its interleaved buffers)")));
  split_.Resize(gbuffer.width(), gbuffer.height());
  {
    gl::StageTimer::Scope stage(ctx.timer, "illuminate");
    const glm::ivec2 split = split_.split_size();
    glBindFramebuffer(GL_FRAMEBUFFER, split_.fbo());
    glViewport(0, 0, split.x, split.y);
    glDisable(GL_DEPTH_TEST);
    gbuffer.BindTextures();
    direct_.Bind(illuminate_);
    shadow_maps_.Bind();
    illuminate_.Set("uImageSize", size);
    illuminate_.Set("uTileSize", split_.tile());
    illuminate_.Set("uVplCount", shadow_maps_.count());
    illuminate_.Set("uClamp2", clamp_distance_ * clamp_distance_);
    illuminate_.Set("uVisibility", visibility_ ? 1 : 0);
    illuminate_.Set("uVplTexel", 2.0f / float(shadow_resolution_));
    illuminate_.Set("uCameraPos", camera.position);  // glossy receivers' view direction
    fullscreen_.Draw(illuminate_);
  }
  {
    gl::StageTimer::Scope stage(ctx.timer, "filter");
    glBindFramebuffer(GL_FRAMEBUFFER, gbuffer.hdr_fbo());
    glViewport(0, 0, size.x, size.y);
    gbuffer.BindTextures();
    glBindTextureUnit(AVG_UNIT_SPLIT_INDIRECT, split_.indirect());
    glBindTextureUnit(AVG_UNIT_SPLIT_DIRECT, split_.direct());
    filter_.Set("uImageSize", size);
    filter_.Set("uTileSize", split_.tile());
    filter_.Set("uCameraPos", camera.position);
    filter_.Set("uPixelAngle", 2.0f * std::tan(0.5f * camera.yfov) / float(std::max(size.y, 1)));
    filter_.Set("uNormalCos", 0.9f);
    filter_.Set("uTentEverywhere", shadow_maps_.any_glossy() ? 1 : 0);
    fullscreen_.Draw(filter_);
  }
  return absl::OkStatus();
}

SolverStats AvgSolver::Stats() const {
  glm::vec3 flux(0.0f);
  for (const avg::Vpl& v : trace_.vpls) flux += v.flux;
  return {
      {"vpls", double(trace_.vpls.size())},
      {"vpl_paths", double(trace_.paths)},
      {"vpl_paths_escaped", double(trace_.escaped)},
      {"light_power", double(Luminance(trace_.light_power))},
      {"vpl_flux", double(Luminance(flux))},
      {"tail_ratio", trace_.tail_ratio},
      {"grid", double(traced_ ? grid_resolution_ : 0)},
      {"voxels_filled", double(voxels_filled_)},
      {"voxel_bytes", double(voxel_bytes_)},
      {"trace_pending", trace_job_.running() || trace_job_.again() ? 1.0 : 0.0},
      {"still_vpls", double(still_vpls_shown_)},
      {"still_pending", extend_job_.running() || ExtensionDue() ? 1.0 : 0.0},
      {"gi_versions_behind", double(latest_version_ - std::min(shown_version_, latest_version_))},
      {"vpl_shadow_bytes", double(shadow_maps_.gpu_bytes())},
      {"vpl_maps_redrawn", double(vpl_maps_redrawn_)},
      {"vpl_maps_kept", double(vpl_maps_kept_)},
      {"vpl_maps_pending",
       remap_pending_ ? double(remap_layers_.size()) - double(remap_next_) : 0.0},
      {"vpls_kept", double(trace_.kept_vpls)},
      {"vpls_retraced", double(trace_.vpls.size() - trace_.kept_vpls)},
      {"vpl_paths_kept", double(trace_.kept_paths)},
      {"vpl_paths_retraced", double(trace_.retraced_paths)},
      {"voxels_rewritten", voxels_rewritten_},
      {"voxelize_partial", voxels_partial_ ? 1.0 : 0.0},
      {"direct_area_samples", double(direct_.area_samples().size())},
      {"direct_shadow_bytes", double(direct_.gpu_bytes())},
      {"split_bytes", double(split_.gpu_bytes())}};
}

GISTREAM_REGISTER_SOLVER(AvgSolver, 40);

}  // namespace gistream
