#include "solvers/sh_probes/sh_probes_solver.h"
#include "solvers/registry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <utility>

#include "gl/buffers.h"
#include "gl/compute.h"
#include "sh_probes/bindings.glsl"  // shaders/: the slots its passes declare
#include "solvers/sh_probes/spherical_harmonics.h"
#include "solvers/tail_estimate.h"

namespace gistream {
namespace {

constexpr GLbitfield kComputeBarrier = GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                                       GL_SHADER_STORAGE_BARRIER_BIT |
                                       GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT;
// The slots its shaders declare (shaders/sh_probes/bindings.glsl).
constexpr GLuint kCoefficientBinding = SH_BINDING_COEFFICIENTS, kValidBinding = SH_BINDING_VALID,
                 kPreviousBinding = SH_BINDING_PREVIOUS, kShownBinding = SH_BINDING_SHOWN,
                 kBatchBinding = SH_BINDING_BATCH, kSeesBinding = SH_BINDING_SEES_CHANGE;
constexpr GLuint kDistanceUnit = SH_UNIT_DISTANCE, kNormalUnit = SH_UNIT_NORMAL,
                 kAlbedoUnit = SH_UNIT_ALBEDO, kMaterialUnit = SH_UNIT_MATERIAL;

float Luminance(const glm::vec4& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

}  // namespace

SolverDescription ShProbesSolver::Describe() {
  SolverDescription d;
  d.name = "sh_probes";
  d.description =
      "Nijasure et al. 2005: cube-map probe grid projected to spherical harmonics, multi-bounce";
  d.stages = {"rasterize_cubemaps", "render_cubemaps", "sh_project", "interpolate", "final"};
  // clang-format off
  d.params = {
      {"grid", ParamType::kInt, "8", 1, 32, {}, "Probes along each axis of the scene bounds"},
      {"spacing", ParamType::kFloat, "0", 0, 1e9, {},
       "Metres between probes; > 0 overrides grid (each axis gets ceil(extent / spacing))"},
      {"face_size", ParamType::kInt, "16", 2, 64, {}, "Cube-map face resolution per probe"},
      {"bands", ParamType::kInt, "3", 1, 3, {}, "SH bands l < bands (1, 4 or 9 coefficients)"},
      {"bounces", ParamType::kInt, "32", 1, 64, {},
       "Most indirect bounces per update: a safety cap; tolerance stops first"},
      {"tolerance", ParamType::kFloat, "0.01", 0, 1, {},
       "Stop when a bounce changes the probes' L_00 by less than this fraction (0: never)"},
      {"tail_estimate", ParamType::kBool, "true", 0, 0, {},
       "Add the geometric tail r / (1 - r) x last increment of the bounces not run (r: the "
       "smallest of the last stable bounce ratios, at most the largest albedo; none if they are "
       "unstable)"},
      {"indirect_shadows", ParamType::kBool, "true", 0, 0, {},
       "Weight each probe by its depth-cube visibility of the point (paper Section 6)"},
      {"hysteresis", ParamType::kFloat, "0.6", 0, 0.99, {},
       "While probes update after a change: fraction of the shown SH kept per frame (0: show "
       "each update at once); the converged solution is shown as it is"},
  };
  // clang-format on
  for (ParamSpec& spec : DirectLightingParams()) {
    if (spec.name == "full_detail") {
      spec.description =
          "Draw the shadow maps and the probes' cube maps from the full meshes instead of their "
          "simplified proxies (docs/ARCHITECTURE.md, Proxy geometry)";
    }
    d.params.push_back(std::move(spec));
  }
  return d;
}

const SolverDescription& ShProbesSolver::description() const {
  static const SolverDescription kDescription = Describe();
  return kDescription;
}

absl::StatusOr<std::unique_ptr<Solver>> ShProbesSolver::Create(const ParamSet& params) {
  auto solver = std::unique_ptr<ShProbesSolver>(new ShProbesSolver());
  ShProbeSettings& s = solver->settings_;
  s.grid.grid = params.GetInt("grid");
  s.grid.spacing = float(params.GetFloat("spacing"));
  s.grid.face_size = params.GetInt("face_size");
  s.bands = params.GetInt("bands");
  s.bounces = params.GetInt("bounces");
  s.tolerance = params.GetFloat("tolerance");
  s.tail_estimate = params.GetBool("tail_estimate");
  s.indirect_shadows = params.GetBool("indirect_shadows");
  s.hysteresis = params.GetFloat("hysteresis");
  s.direct = DirectLightingFromParams(params);
  // The environment lights the probes and the final pass as directional
  // lights (render/environment_lights.h).
  s.direct.environment_lights = true;
  // The grid size alone (spacing needs the scene) is checked here.
  if (s.grid.spacing <= 0.0f) {
    GS_RETURN_IF_ERROR(FitProbeGrid(Bounds{glm::vec3(0.0f), glm::vec3(1.0f)}, s.grid).status());
  }
  GS_ASSIGN_OR_RETURN(solver->lighting_, DirectLighting::Create());
  GS_ASSIGN_OR_RETURN(solver->rasterizer_, ProbeRasterizer::Create());
  GS_ASSIGN_OR_RETURN(
      solver->render_,
      gl::Program::Build({{GL_COMPUTE_SHADER, "sh_probes/render_cubemaps.comp.glsl"}}));
  GS_ASSIGN_OR_RETURN(solver->project_,
                      gl::Program::Build({{GL_COMPUTE_SHADER, "sh_probes/sh_project.comp.glsl"}}));
  GS_ASSIGN_OR_RETURN(solver->interpolate_,
                      gl::Program::Build({{GL_COMPUTE_SHADER, "sh_probes/interpolate.comp.glsl"}}));
  GS_ASSIGN_OR_RETURN(solver->tail_,
                      gl::Program::Build({{GL_COMPUTE_SHADER, "sh_probes/tail.comp.glsl"}}));
  GS_ASSIGN_OR_RETURN(solver->sees_,
                      gl::Program::Build({{GL_COMPUTE_SHADER, "sh_probes/sees_change.comp.glsl"}}));
  GS_ASSIGN_OR_RETURN(solver->blend_,
                      gl::Program::Build({{GL_COMPUTE_SHADER, "sh_probes/blend.comp.glsl"}}));
  GS_ASSIGN_OR_RETURN(solver->final_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                          {GL_FRAGMENT_SHADER, "sh_probes/final.frag.glsl"}}));
  return solver;
}

std::vector<std::string> ShProbesSolver::Plan(const SceneState& state, ChangeMask changes) const {
  changes = EnvironmentAsLights(changes, state);
  // A dimmer (solvers/emission_scale.h) between solves scales the shown
  // probes: Update runs only the final pass (its direct light's buffers).
  if (!full_.active && !schedule_.pending() && !lighting_.pending() &&
      emission_.Factor(state, changes | deferred_)) {
    return {"final"};
  }
  // Albedo is baked into the probes' G-buffer, so a base colour change
  // re-rasterizes like a geometry change; lights and emission only re-shade.
  if (changes & (kChangeShape | kChangeMaterials)) {
    return {"rasterize_cubemaps", "render_cubemaps", "sh_project", "interpolate", "final"};
  }
  // A progressive update under way runs batches of probes: it rasterizes
  // only in the first solve, for a deferred geometry or material change,
  // or while probes wait for it (a light's update, e.g., never does).
  if ((changes & (kChangeLights | kChangeEmission)) || !UpdateComplete()) {
    if (full_.active || (deferred_ & (kChangeShape | kChangeMaterials)) ||
        schedule_.raster_pending()) {
      return {"rasterize_cubemaps", "render_cubemaps", "sh_project", "interpolate", "final"};
    }
    return {"render_cubemaps", "sh_project", "interpolate", "final"};
  }
  return {"final"};
}

absl::Status ShProbesSolver::Update(SolverContext& ctx, ChangeMask changes) {
  changes = EnvironmentAsLights(changes, ctx.state);
  if (full_.active) {
    // A full solve under way goes on; a new layout restarts it, any other
    // change is solved progressively once it is done (the probes' cube
    // maps drawn meanwhile may have seen part of it).
    if (changes & (kChangeShape | kChangeMaterials)) {
      GS_ASSIGN_OR_RETURN(ProbeLayout layout,
                          FitProbeGrid(ctx.gpu.WorldBounds(ctx.state), settings_.grid));
      if (!(layout.dims == layout_.dims && layout.origin == layout_.origin &&
            layout.spacing == layout_.spacing && layout.face_size == layout_.face_size)) {
        return StartSolve(ctx, changes | deferred_, layout);
      }
    }
    deferred_ |= changes;
    return ContinueSolve(ctx);
  }
  changes |= std::exchange(deferred_, ChangeMask(0));
  const bool geometry = changes & (kChangeShape | kChangeMaterials);
  const bool lights = changes & (kChangeShape | kChangeLights | kChangeEmission);
  const bool busy = schedule_.pending() || lighting_.pending();
  if (!geometry && !lights && !busy) {
    for (const char* stage :
         {"rasterize_cubemaps", "render_cubemaps", "sh_project", "interpolate"}) {
      ctx.timer.Skip(stage);
    }
    return absl::OkStatus();
  }
  if (const std::optional<float> k = busy ? std::nullopt : emission_.Factor(ctx.state, changes)) {
    // A dimmer: the probes' indirect light scales with the lights
    // (solvers/emission_scale.h); only the direct light's buffers change.
    for (const char* stage :
         {"rasterize_cubemaps", "render_cubemaps", "sh_project", "interpolate"}) {
      ctx.timer.Skip(stage);
    }
    gl::StageTimer::Scope stage(ctx.timer, "final");
    GS_RETURN_IF_ERROR(lighting_.Update(ctx.state, ctx.gpu, settings_.direct, changes));
    indirect_scale_ = *k;
    return absl::OkStatus();
  }
  if (geometry || !solved_) {
    GS_ASSIGN_OR_RETURN(ProbeLayout layout,
                        FitProbeGrid(ctx.gpu.WorldBounds(ctx.state), settings_.grid));
    const bool same = layout.dims == layout_.dims && layout.origin == layout_.origin &&
                      layout.spacing == layout_.spacing && layout.face_size == layout_.face_size;
    if (!solved_ || !same) return StartSolve(ctx, changes, layout);
  }
  return Progress(ctx, changes);
}

absl::Status ShProbesSolver::StartSolve(SolverContext& ctx, ChangeMask changes,
                                        const ProbeLayout& layout) {
  {
    gl::StageTimer::Scope stage(ctx.timer, "rasterize_cubemaps");
    if (layout.probes() != layout_.probes() || !coefficients_) {
      const size_t coefficient_bytes = size_t(sh::kMaxCoefficients) * size_t(layout.probes()) * 16;
      const size_t per_probe_bytes = size_t(layout.probes()) * 4;
      coefficients_ = gl::ZeroedBuffer(coefficient_bytes);
      shown_coefficients_ = gl::ZeroedBuffer(coefficient_bytes);
      previous_coefficients_ = gl::ZeroedBuffer(coefficient_bytes);
      probe_valid_ = gl::ZeroedBuffer(per_probe_bytes);
      batch_probes_ = gl::ZeroedBuffer(per_probe_bytes);
      sees_change_ = gl::ZeroedBuffer(per_probe_bytes);
    }
    layout_ = layout;
    atlas_.Allocate(layout_);
  }
  full_ = FullSolve{};
  full_.active = true;
  full_.lights = changes & (kChangeShape | kChangeLights | kChangeEmission);
  deferred_ = 0;
  // Section 3: start from L_indirect = 0 and bounce until the change is
  // insignificant or the budget of bounces is spent.
  dc_luminance_.assign(size_t(layout_.probes()), 0.0f);
  bounces_run_ = 0;
  bounce_change_ = 0.0;
  tail_residual_ = std::numeric_limits<double>::infinity();
  cap_reached_ = false;
  tail_applied_ = false;
  tail_ratio_ = 0.0;
  tail_spread_ = 0.0;
  probes_updated_ = 0;
  batches_run_ = 0;
  // What the solve sees from here on; later changes are deferred.
  emission_.Solved(ctx.state);
  moved_.Solved(ctx.state);
  schedule_.Reset(layout_.probes());
  solved_ = true;
  indirect_scale_ = 1.0f;
  if (full_.lights) {
    // The direct light's maps, in slices of half the budget while the
    // cube maps are rasterized; the texels' direct light waits for them.
    gl::StageTimer::Scope stage(ctx.timer, "render_cubemaps");
    GS_RETURN_IF_ERROR(
        lighting_.Update(ctx.state, ctx.gpu, settings_.direct, changes, 0.5 * ctx.budget_ms));
  }
  return ContinueSolve(ctx);
}

absl::Status ShProbesSolver::ContinueSolve(SolverContext& ctx) {
  using Clock = std::chrono::steady_clock;
  using Phase = FullSolve::Phase;
  const auto start = Clock::now();
  const int probes = layout_.probes();
  auto elapsed = [&] {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  };
  probes_updated_ = 0;
  batches_run_ = 0;
  if (lighting_.pending()) {
    gl::StageTimer::Scope stage(ctx.timer, "render_cubemaps");
    lighting_.Continue(ctx.gpu, ctx.state, 0.5 * ctx.budget_ms);
  }
  bool ran = false;
  while (full_.active) {
    // A probe's work in this phase, in ProbeSchedule's units.
    int units = ProbeSchedule::kBounceUnits;
    if (full_.phase == Phase::kRaster) units = ProbeSchedule::kRasterUnits;
    if (full_.phase == Phase::kRender && full_.bounce == 1) units += ProbeSchedule::kDirectUnits;
    // The texels' direct light needs every shadow map.
    if (full_.phase == Phase::kRender && full_.bounce == 1 && lighting_.pending()) break;
    const int count =
        std::min(std::max(ProbeSchedule::kBatchUnits / units, 1), probes - full_.next);
    if (ran && ctx.budget_ms > 0.0 && elapsed() + ms_per_unit_ * units * count > ctx.budget_ms) {
      break;
    }
    std::vector<int> batch(static_cast<size_t>(count));
    for (int i = 0; i < count; ++i) batch[size_t(i)] = full_.next + i;
    const auto batch_start = Clock::now();
    RunSolveBatch(ctx, &batch);
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - batch_start).count();
    ms_per_unit_ = 0.7 * ms_per_unit_ + 0.3 * ms / double(std::max(units * count, 1));
    probes_updated_ += count;
    ++batches_run_;
    ran = true;
    full_.next += count;
    if (full_.next < probes) continue;
    // The end of a phase.
    full_.next = 0;
    if (full_.phase == Phase::kRaster || full_.phase == Phase::kInterpolate) {
      full_.phase = Phase::kRender;
      continue;
    }
    EndSolveBounce(ctx);
  }
  return absl::OkStatus();
}

void ShProbesSolver::RunSolveBatch(SolverContext& ctx, std::vector<int>* batch) {
  using Phase = FullSolve::Phase;
  switch (full_.phase) {
    case Phase::kRaster: {
      gl::StageTimer::Scope stage(ctx.timer, "rasterize_cubemaps");
      RasterizeCubemaps(ctx, batch);
      return;
    }
    case Phase::kInterpolate: {
      gl::StageTimer::Scope stage(ctx.timer, "interpolate");
      Interpolate(batch);
      return;
    }
    case Phase::kRender: {
      if (full_.next == 0 && settings_.tail_estimate) {
        glCopyNamedBufferSubData(coefficients_.id(), previous_coefficients_.id(), 0, 0,
                                 GLsizeiptr(sh::kMaxCoefficients) * layout_.probes() * 16);
      }
      {
        gl::StageTimer::Scope stage(ctx.timer, "render_cubemaps");
        RenderCubemaps(ctx.gpu, /*compute_direct=*/full_.bounce == 1,
                       /*use_indirect=*/full_.bounce > 1, batch);
      }
      gl::StageTimer::Scope stage(ctx.timer, "sh_project");
      full_.change += ProjectToSh(&full_.total, batch);
      return;
    }
  }
}

void ShProbesSolver::EndSolveBounce(SolverContext& ctx) {
  // Frames show the solution so far.
  bounces_run_ = full_.bounce;
  full_.deltas.push_back(full_.change);
  full_.totals.push_back(full_.total);
  bounce_change_ = full_.total > 0.0 ? full_.change / full_.total : 0.0;
  full_.change = full_.total = 0.0;
  glCopyNamedBufferSubData(coefficients_.id(), shown_coefficients_.id(), 0, 0,
                           GLsizeiptr(sh::kMaxCoefficients) * layout_.probes() * 16);
  ++shown_changes_;
  unshown_change_ = 0.0;
  // With the tail on, the solve also ends once the tail-corrected sum is
  // known within the tolerance (TailResidual: the measured ratios' spread
  // through r / (1 - r)); in a bright interior the increments shrink too
  // slowly for the increment test, which ran to the 32-bounce cap.
  tail_residual_ = settings_.tail_estimate
                       ? TailResidual(full_.deltas, full_.totals, LargestAlbedo(ctx.state))
                       : std::numeric_limits<double>::infinity();
  if ((full_.bounce >= 2 && bounce_change_ < settings_.tolerance) || TailSettled() ||
      full_.bounce >= settings_.bounces) {
    FinishSolve(ctx);
  } else {
    ++full_.bounce;
    full_.phase = FullSolve::Phase::kInterpolate;
  }
}

void ShProbesSolver::FinishSolve(SolverContext& ctx) {
  full_.active = false;
  // Stopped by the count, not by the tolerance (a count of 1 cannot test).
  cap_reached_ = bounces_run_ >= 2 && !(bounce_change_ < settings_.tolerance) && !TailSettled();
  if (settings_.tail_estimate) {
    // Geometric tail: increments shrink by r per bounce, so the bounces not
    // run add sum_{j>=1} r^j = r / (1 - r) times the last one. r is the
    // smallest of the last stable ratios, capped (solvers/tail_estimate.h): the
    // former last-ratio estimate always came out above the true albedo and
    // exploded at rho = 0.999 (38,870 for an exact 1000).
    // The ratio is bounded by the scene's largest albedo (base colour
    // factors; textures only scale them down): at rho = 0.999 the former
    // fixed cap of 0.99 left the estimate 87 % low.
    const double albedo_bound = LargestAlbedo(ctx.state);
    const TailEstimate tail = EstimateTail(full_.deltas, albedo_bound);
    tail_ratio_ = tail.ratio;
    tail_spread_ = tail.spread;
    if (tail.applied) {
      gl::StageTimer::Scope stage(ctx.timer, "sh_project");
      // The largest of the bounces' estimates, so more bounces never give
      // less (tail_estimate.h; at rho = 0.999 they drifted down 0.3 %).
      ApplyTail(MonotoneTailFactor(full_.deltas, full_.totals, albedo_bound));
      tail_applied_ = true;
    }
  }
  glCopyNamedBufferSubData(coefficients_.id(), shown_coefficients_.id(), 0, 0,
                           GLsizeiptr(sh::kMaxCoefficients) * layout_.probes() * 16);
  ++shown_changes_;
  unshown_change_ = 0.0;
}

absl::Status ShProbesSolver::Progress(SolverContext& ctx, ChangeMask changes) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const bool geometry = changes & (kChangeShape | kChangeMaterials);
  const bool lights = changes & (kChangeShape | kChangeLights | kChangeEmission);
  if ((geometry || lights) && indirect_scale_ != 1.0f) {
    // The shown solution was a dimmer's k x the solved one: make that the
    // solution, and the texels' direct light the current one.
    Blend(/*hysteresis=*/1.0f, indirect_scale_);
    indirect_scale_ = 1.0f;
    schedule_.NeedDirectAll();
  }
  GS_RETURN_IF_ERROR(ProgressDirectLight(ctx, changes, geometry, lights));
  if (geometry) ScheduleChangedProbes(ctx, changes);

  // Batches of probes for about the frame budget (at least one), each a
  // Gauss-Seidel step from the newest coefficients.
  probes_updated_ = 0;
  batches_run_ = 0;
  bool ran = false;
  while (schedule_.pending()) {
    const ProbeSchedule::Batch batch = schedule_.Peek();
    const double elapsed = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    if (ran && ctx.budget_ms > 0.0 && elapsed + ms_per_unit_ * batch.units > ctx.budget_ms) break;
    const auto batch_start = Clock::now();
    double total = 0.0;
    const double change = RunBatch(ctx, batch, &total);
    if (total > 0.0) unshown_change_ += change / total;
    schedule_.Done(batch, change, total, settings_.tolerance, settings_.bounces);
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - batch_start).count();
    ms_per_unit_ = 0.7 * ms_per_unit_ + 0.3 * ms / std::max(batch.units, 1);
    probes_updated_ += int(batch.probes.size());
    ++batches_run_;
    ran = true;
  }
  for (const char* s : {"rasterize_cubemaps", "render_cubemaps", "sh_project", "interpolate"}) {
    if (!ran) ctx.timer.Skip(s);
  }
  bounce_change_ = schedule_.last_sweep_change();  // a sweep's, not a bounce's
  tail_residual_ = std::numeric_limits<double>::infinity();
  cap_reached_ = schedule_.cap_reached();
  if (ran) ShowProgress(ctx, geometry || lights);
  if (!schedule_.pending() && !lighting_.pending()) emission_.Solved(ctx.state);
  return absl::OkStatus();
}

absl::Status ShProbesSolver::ProgressDirectLight(SolverContext& ctx, ChangeMask changes,
                                                 bool geometry, bool lights) {
  // The shown set of shadow maps stays bound meanwhile. Half the budget
  // while probes wait too, the rest is theirs.
  gl::StageTimer::Scope stage(ctx.timer, "render_cubemaps");
  const uint64_t shown = lighting_.sets_shown();
  const double budget = (schedule_.pending() || geometry) ? 0.5 * ctx.budget_ms : ctx.budget_ms;
  if (lights) {
    GS_RETURN_IF_ERROR(lighting_.Update(ctx.state, ctx.gpu, settings_.direct, changes, budget));
  } else if (lighting_.pending()) {
    lighting_.Continue(ctx.gpu, ctx.state, budget);
  }
  // New maps are shown (drawn in place, or a sliced set finished; the
  // newest set may be drawn next): every texel's direct light changed.
  if ((lights && !lighting_.pending()) || lighting_.sets_shown() != shown) {
    schedule_.NeedDirectAll();
  }
  return absl::OkStatus();
}

void ShProbesSolver::ScheduleChangedProbes(SolverContext& ctx, ChangeMask changes) {
  gl::StageTimer::Scope stage(ctx.timer, "rasterize_cubemaps");
  // Albedo is baked into the cube maps: a material change re-rasterizes
  // every probe; a moved node only the probes that see it.
  Bounds moved = moved_.Since(ctx.gpu, ctx.state);
  moved_.Solved(ctx.state);
  // Per probe, the solid angle of its cube map that may see the change
  // (micro-steradians; 0: unaffected).
  std::vector<int32_t> seen(size_t(layout_.probes()), 0);
  if (changes & kChangeMaterials) {
    std::fill(seen.begin(), seen.end(), ProbeSchedule::kWholeSphere);
  } else if (!moved.empty()) {
    const glm::vec3 pad(1e-3f * glm::length(glm::vec3(layout_.dims) * layout_.spacing));
    moved.Extend(moved.min - pad);
    moved.Extend(moved.max + pad);
    seen = SeesChange(moved);
  }
  probes_affected_ = 0;
  std::vector<glm::vec3> positions(seen.size());
  for (int p = 0; p < layout_.probes(); ++p) {
    positions[size_t(p)] = layout_.position(layout_.cell(p));
    if (seen[size_t(p)] > 0) {
      schedule_.NeedRaster(p);
      ++probes_affected_;
    }
  }
  schedule_.Prioritize(seen, positions, eye_);
}

std::vector<int32_t> ShProbesSolver::SeesChange(const Bounds& moved) {
  SetProbeGridUniforms(sees_, layout_, 0, false);
  glBindTextureUnit(kDistanceUnit, atlas_.distance());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSeesBinding, sees_change_.id());
  sees_.Set("uBoxMin", moved.min);
  sees_.Set("uBoxMax", moved.max);
  sees_.Use();
  glDispatchCompute(GLuint(layout_.probes()), 1, 1);
  glMemoryBarrier(kComputeBarrier);
  std::vector<int32_t> seen(size_t(layout_.probes()));
  glGetNamedBufferSubData(sees_change_.id(), 0, GLsizeiptr(seen.size() * 4), seen.data());
  return seen;
}

double ShProbesSolver::RunBatch(SolverContext& ctx, const ProbeSchedule::Batch& batch,
                                double* total) {
  if (!batch.raster.empty()) {
    gl::StageTimer::Scope stage(ctx.timer, "rasterize_cubemaps");
    RasterizeCubemaps(ctx, &batch.raster);
  }
  {
    gl::StageTimer::Scope stage(ctx.timer, "interpolate");
    Interpolate(&batch.probes);
  }
  {
    gl::StageTimer::Scope stage(ctx.timer, "render_cubemaps");
    std::vector<int> rest;
    for (int p : batch.probes) {
      if (std::find(batch.direct.begin(), batch.direct.end(), p) == batch.direct.end()) {
        rest.push_back(p);
      }
    }
    if (!batch.direct.empty()) RenderCubemaps(ctx.gpu, true, true, &batch.direct);
    if (!rest.empty()) RenderCubemaps(ctx.gpu, false, true, &rest);
  }
  gl::StageTimer::Scope stage(ctx.timer, "sh_project");
  return ProjectToSh(total, &batch.probes);
}

void ShProbesSolver::ShowProgress(SolverContext& ctx, bool changed) {
  // Converged: show the solution. Until then it fades in (hysteresis) in
  // each frame of a change, and after it while the solution is estimated to
  // differ from what is shown by more than a quarter of the tolerance.
  // A blend after the change that moves what is shown by at most half the
  // tolerance is a step (Shown): the view refines across it (a blend every
  // frame restarted its refinement, so the Cornell box's picture stayed at
  // one sample a pixel for the 5 s of probe updates after a move, its light
  // long right but its edges jagged).
  const double tolerance = settings_.tolerance;
  const bool converged = !schedule_.pending();
  if (!converged && !changed && unshown_change_ <= 0.25 * tolerance) return;
  gl::StageTimer::Scope stage(ctx.timer, "sh_project");
  const float hysteresis = converged ? 0.0f : float(settings_.hysteresis);
  const double moved = (1.0 - hysteresis) * unshown_change_;
  Blend(hysteresis, 1.0f, !converged && !changed && moved <= 0.5 * tolerance);
  unshown_change_ *= hysteresis;
}

void ShProbesSolver::Blend(float hysteresis, float scale, bool step) {
  ++(step ? shown_steps_ : shown_changes_);
  const int count = sh::kMaxCoefficients * layout_.probes();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kCoefficientBinding, coefficients_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kShownBinding, shown_coefficients_.id());
  blend_.Set("uCount", count);
  blend_.Set("uHysteresis", hysteresis);
  blend_.Set("uScale", scale);
  blend_.Use();
  glDispatchCompute(gl::GroupCount(size_t(count), 64), 1, 1);
  glMemoryBarrier(kComputeBarrier);
}

void ShProbesSolver::SetBatch(gl::Program& program, const std::vector<int>* probes) {
  const int count = probes ? int(probes->size()) : 0;
  if (count > 0) {
    glNamedBufferSubData(batch_probes_.id(), 0, GLsizeiptr(count) * 4, probes->data());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBatchBinding, batch_probes_.id());
  }
  program.Set("uBatchCount", count);
}

void ShProbesSolver::BindProbeData(gl::Program& program, const gl::Buffer& coefficients) const {
  SetProbeGridUniforms(program, layout_, sh::CoefficientCount(settings_.bands),
                       settings_.indirect_shadows);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kCoefficientBinding, coefficients.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kValidBinding, probe_valid_.id());
  glBindTextureUnit(kDistanceUnit, atlas_.distance());
  glBindTextureUnit(kNormalUnit, atlas_.normal());
  glBindTextureUnit(kAlbedoUnit, atlas_.albedo());
  glBindTextureUnit(kMaterialUnit, atlas_.material());
}

void ShProbesSolver::RasterizeCubemaps(const SolverContext& ctx, const std::vector<int>* probes) {
  rasterizer_.Draw(ctx.gpu, ctx.state, layout_, atlas_, probes, settings_.direct.full_detail);
}

void ShProbesSolver::RenderCubemaps(const GpuScene& gpu, bool compute_direct, bool use_indirect,
                                    const std::vector<int>* probes) {
  BindProbeData(render_, coefficients_);
  gpu.BindMaterials();  // a texel's dielectric F0 and F90 (texel.glsl ProbeTexelBrdf)
  lighting_.Bind(render_);
  SetBatch(render_, probes);
  render_.Set("uComputeDirect", compute_direct ? 1 : 0);
  render_.Set("uUseIndirect", use_indirect ? 1 : 0);
  glBindImageTexture(SH_IMAGE_DIRECT, atlas_.direct(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA32F);
  glBindImageTexture(SH_IMAGE_INDIRECT, atlas_.indirect(), 0, GL_TRUE, 0, GL_READ_ONLY, GL_RGBA32F);
  glBindImageTexture(SH_IMAGE_RADIANCE, atlas_.radiance(), 0, GL_TRUE, 0, GL_WRITE_ONLY,
                     GL_RGBA32F);
  render_.Use();
  DispatchTexels(probes);
}

void ShProbesSolver::DispatchTexels(const std::vector<int>* probes) const {
  if (probes) {
    glDispatchCompute(gl::GroupCount(size_t(layout_.face_size), 8),
                      gl::GroupCount(size_t(layout_.face_size), 8), GLuint(6 * probes->size()));
  } else {
    glDispatchCompute(gl::GroupCount(size_t(layout_.width()), 8),
                      gl::GroupCount(size_t(layout_.height()), 8), 6);
  }
  glMemoryBarrier(kComputeBarrier);
}

double ShProbesSolver::ProjectToSh(double* total, const std::vector<int>* probes) {
  BindProbeData(project_, coefficients_);
  SetBatch(project_, probes);
  glBindImageTexture(SH_IMAGE_RADIANCE, atlas_.radiance(), 0, GL_TRUE, 0, GL_READ_ONLY, GL_RGBA32F);
  project_.Use();
  glDispatchCompute(probes ? GLuint(probes->size()) : GLuint(layout_.probes()), 1, 1);
  glMemoryBarrier(kComputeBarrier);

  // L_00 of every probe (the first probes() entries) and the valid flags.
  const size_t count = size_t(layout_.probes());
  std::vector<glm::vec4> dc(count);
  std::vector<float> valid(count);
  glGetNamedBufferSubData(coefficients_.id(), 0, GLsizeiptr(count * sizeof(glm::vec4)), dc.data());
  glGetNamedBufferSubData(probe_valid_.id(), 0, GLsizeiptr(count * sizeof(float)), valid.data());
  double change = 0.0, sum = 0.0;
  auto visit = [&](size_t p) {
    if (valid[p] < 0.5f) return;
    const float lum = Luminance(dc[p]);
    change += std::abs(double(lum) - double(dc_luminance_[p]));
    dc_luminance_[p] = lum;
  };
  if (probes) {
    for (int p : *probes) visit(size_t(p));
  } else {
    for (size_t p = 0; p < count; ++p) visit(p);
  }
  invalid_probes_ = 0;
  for (size_t p = 0; p < count; ++p) {
    if (valid[p] < 0.5f) {
      ++invalid_probes_;
    } else {
      sum += std::abs(double(dc_luminance_[p]));
    }
  }
  *total = sum;
  return change;
}

void ShProbesSolver::Interpolate(const std::vector<int>* probes) {
  BindProbeData(interpolate_, coefficients_);
  SetBatch(interpolate_, probes);
  glBindImageTexture(SH_IMAGE_INDIRECT, atlas_.indirect(), 0, GL_TRUE, 0, GL_WRITE_ONLY,
                     GL_RGBA32F);
  interpolate_.Use();
  DispatchTexels(probes);
}

void ShProbesSolver::ApplyTail(double scale) {
  const int count = sh::kMaxCoefficients * layout_.probes();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kCoefficientBinding, coefficients_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kPreviousBinding, previous_coefficients_.id());
  tail_.Set("uCount", count);
  tail_.Set("uScale", float(scale));
  tail_.Use();
  glDispatchCompute(gl::GroupCount(size_t(count), 64), 1, 1);
  glMemoryBarrier(kComputeBarrier);
}

absl::Status ShProbesSolver::Shade(SolverContext& ctx, const ViewCamera& camera,
                                   const GBuffer& gbuffer) {
  gl::StageTimer::Scope stage(ctx.timer, "final");
  eye_ = camera.position;  // the next change updates the probes near it first
  gbuffer.BeginShadePass();
  lighting_.Bind(final_);
  BindProbeData(final_, shown_coefficients_);
  final_.Set("uIndirectScale", indirect_scale_);
  fullscreen_.Draw(final_);
  return absl::OkStatus();
}

SolverStats ShProbesSolver::Stats() const {
  return {{"probes", double(layout_.probes())},
          {"probes_invalid", double(invalid_probes_)},
          {"face_size", double(layout_.face_size)},
          {"atlas_texels", double(layout_.texels())},
          {"bounces_run", double(bounces_run_)},
          {"bounce_change", bounce_change_},
          {"residual", TailSettled() ? tail_residual_ : bounce_change_},
          {"tail_residual", std::isfinite(tail_residual_) ? tail_residual_ : -1.0},
          {"cap_reached", cap_reached_ ? 1.0 : 0.0},
          {"probes_pending",
           full_.active ? double(layout_.probes() - full_.next) : double(schedule_.remaining())},
          {"full_solve_pending", full_.active ? 1.0 : 0.0},
          {"probe_sweeps", double(schedule_.sweeps())},
          {"probes_affected", double(probes_affected_)},
          {"probes_updated", double(probes_updated_)},
          {"probe_batches", double(batches_run_)},
          {"shadow_maps_pending", lighting_.pending() ? 1.0 : 0.0},
          {"tail_ratio", tail_ratio_},
          {"tail_applied", tail_applied_ ? 1.0 : 0.0},
          {"tail_ratio_spread", tail_spread_},
          {"probe_gpu_bytes", double(atlas_.gpu_bytes())},
          {"area_samples", double(lighting_.area_samples().size())},
          {"shadow_map_bytes", double(lighting_.gpu_bytes())}};
}

GISTREAM_REGISTER_SOLVER(ShProbesSolver, 30);

}  // namespace gistream
