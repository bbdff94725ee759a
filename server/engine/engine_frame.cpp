// EngineImpl's frame: RenderFrame and ProduceFrame's named steps (apply
// updates, reserve, deform, acquire and build the solver, plan and solve,
// draw, read back, encode, publish).
#include "engine/engine_impl.h"

#include <absl/strings/str_format.h>
#include <absl/strings/str_join.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <utility>

#include "engine/engine_common.h"
#include "solvers/registry.h"
#include "util/cpu_pool.h"
#include "util/log.h"

namespace gistream {
using namespace engine_internal;  // NOLINT(build/namespaces): engine_common.h

namespace {

// How often a frame that waits on a solver's background job polls it.
constexpr auto kPollInterval = std::chrono::milliseconds(2);

// Adds `slice`'s stage times into `total` (by stage name; a stage is
// skipped only if it was skipped in every slice).
void MergeTimings(std::vector<StageTiming>& total, std::vector<StageTiming> slice) {
  if (total.empty()) {
    total = std::move(slice);
    return;
  }
  for (StageTiming& t : slice) {
    auto it = std::find_if(total.begin(), total.end(),
                           [&](const StageTiming& s) { return s.name == t.name; });
    if (it == total.end()) {
      total.push_back(std::move(t));
      continue;
    }
    it->cpu_ms += t.cpu_ms;
    it->gpu_ms += t.gpu_ms;
    // A stage skipped in the first slices and run in a later one (a
    // background job taken) is what the run says it is.
    if (it->skipped && !t.skipped) it->cpu_stage = t.cpu_stage;
    it->skipped = it->skipped && t.skipped;
  }
}

// Every stage of the solver's table appears in the frame: one the solver
// did not report is reported skipped. A stage that ran outside the plan is
// a solver bug (its Plan and Update disagree), logged once per solver and
// stage; tests/gl/stage_plan_test.cpp holds every solver to its plan.
void ReportAgainstPlan(const SolverDescription& solver, const std::vector<std::string>& plan,
                       std::vector<StageTiming>& timings) {
  for (const std::string& stage : solver.stages) {
    auto it = std::find_if(timings.begin(), timings.end(),
                           [&](const StageTiming& t) { return t.name == stage; });
    const bool planned = std::find(plan.begin(), plan.end(), stage) != plan.end();
    if (it == timings.end()) {
      StageTiming skipped;
      skipped.name = stage;
      skipped.skipped = true;
      timings.push_back(std::move(skipped));
    } else if (!it->skipped && !planned) {
      LogOnce(LogLevel::kWarning, absl::StrCat("unplanned:", solver.name, ":", stage),
              absl::StrCat("solver ", solver.name, " ran stage ", stage,
                           " which its plan for this change does not name"));
    }
  }
}

}  // namespace

void EngineImpl::RenderFrame(SessionRecord& session, ViewRecord& view) {
  // Lines logged while this frame renders (solvers included) name it.
  const ScopedLogContext log_context({session.id, session.scene->id});
  // The CPU pool's loops and background jobs it starts are its tenant's
  // (util/cpu_pool.h: workers are shared between tenants).
  const CpuTenantScope cpu_tenant(session.config.tenant);
  std::deque<Update> updates;
  {
    MutexLock lock(mutex_);
    updates.swap(session.pending);
  }
  absl::StatusOr<std::shared_ptr<EncodedFrame>> frame =
      ProduceFrame(session, view, std::move(updates));
  if (CheckGpuReset()) return;  // the session failed with every other one
  if (frame.ok() && *frame == nullptr) {
    // A slice of a frame still in progress: the session stays due.
    MutexLock lock(mutex_);
    session.requested += 1;
    return;
  }
  if (!frame.ok()) {
    Log(LogLevel::kError, absl::StrCat("frame failed: ", frame.status().ToString()));
    session.sink->OnSessionFailed(frame.status());
    MutexLock lock(mutex_);
    session.closed = true;
    return;
  }
  frames_rendered_.fetch_add(1);
  {
    MutexLock lock(mutex_);
    session.frames += 1;
    session.last_seq = (*frame)->last_update_seq;
    session.width = (*frame)->width;
    session.height = (*frame)->height;
    session.rate.Add(Clock::now());
  }
  if (options_.observer) options_.observer->OnFrameRendered(**frame);
  // A view's first frame allocated its G-buffer: count it before the client
  // sees the frame.
  RefreshMemoryStats(/*force=*/(*frame)->frame_number == 1);
  // A continuous session's unchanged frame goes out only with news (an
  // update's echo) or as a keep-alive (FrameEncoder::HoldBack).
  const auto now = Clock::now();
  if (session.config.pacing == Pacing::kContinuous && view.settled) {
    // Rest: from here on the view renders nothing until something changes;
    // its keep-alives repeat this frame's header (kept without an image,
    // with zero stage times: they render nothing).
    ViewRecord::Rest rest{(*frame)->scene_version, nullptr, **frame};
    rest.frame.image.clear();
    rest.frame.unchanged = true;
    rest.frame.key_frame = false;
    rest.frame.total_ms = 0.0;
    for (StageTiming& t : rest.frame.timings) {
      t.cpu_ms = t.gpu_ms = 0.0;
      t.skipped = true;
    }
    for (auto& [name, value] : rest.frame.stats) {
      if (name == "at_rest") value = 1.0;
    }
    const auto scene_it = gpu_scenes_.find(session.scene->id);
    if (scene_it != gpu_scenes_.end()) {
      const auto solver_it = scene_it->second.solvers.find(session.solver_key);
      if (solver_it != scene_it->second.solvers.end()) {
        rest.solver = solver_it->second.solver.get();
        view.rest = std::move(rest);
        session.resting = true;
      }
    }
  }
  if (session.config.pacing == Pacing::kContinuous && view.encoder.HoldBack(**frame, now)) return;
  view.encoder.MarkSent(**frame, now);
  session.sink->OnFrame(*std::move(frame));
}

absl::Status EngineImpl::ShadeSample(GpuSceneRecord& scene, SolverEntry& entry, SolverContext& ctx,
                                     ViewRecord& view, const Refinement::Sample& sample,
                                     uint32_t refine_target) {
  ViewCamera camera = view.camera;
  camera.jitter = Refinement::Jitter(sample.jitter);
  if (sample.keep_history) {
    // Before this sample is shaded over the picture shown: it is the
    // history, but not where something moved since.
    passes_->KeepHistory(view.gbuffer);
    view.refinement.SetHistoryInvalid(
        MovedPixels(view.camera, view.shown_transforms.Since(*scene.gpu, *scene.state)));
  }
  if (sample.reproject) {
    // Before the new camera's first sample is shaded over the picture
    // shown: it is the picture the frames of the move reproject.
    passes_->KeepShown(view.gbuffer);
    view.reproject_view_projection = view.shown_view_projection;
    view.reproject_eye = view.shown_eye;
  }
  if (sample.index == 0) view.shown_transforms.Solved(*scene.state);
  if (entry.solver->NeedsGBuffer()) {
    gl::StageTimer::Scope stage(timer_, "gbuffer");
    GS_RETURN_IF_ERROR(passes_->DrawGBuffer(*scene.state, *scene.gpu, camera, view.gbuffer));
  } else {
    GS_RETURN_IF_ERROR(view.gbuffer.Resize(camera.width, camera.height));
    timer_.Skip("gbuffer");
  }
  GS_RETURN_IF_ERROR(entry.solver->Shade(ctx, camera, view.gbuffer));
  view.refinement.Added();
  if (refine_target > 1) {
    gl::StageTimer::Scope stage(timer_, "refine");
    if (sample.centre) passes_->KeepCentre(view.gbuffer, camera.position);
    passes_->Accumulate(view.gbuffer, sample.index);
    const Refinement::PixelBox& invalid = view.refinement.history_invalid();
    passes_->ShowAccumulation(
        view.gbuffer,
        {view.refinement.samples(), view.refinement.HistoryWeight(refine_target), invalid.min,
         invalid.max, view.refinement.CarryWeight(refine_target),
         view.refinement.ReprojectWeight(refine_target), view.reproject_view_projection,
         view.reproject_eye, glm::inverse(view.camera.Projection() * view.camera.View()),
         view.camera.position});
    if (view.refinement.CaptureCarry(refine_target)) passes_->CaptureCarry(view.gbuffer);
  } else {
    timer_.Skip("refine");
  }
  if (sample.index == 0) view.solve_stats = entry.solver->Stats();
  // The camera the picture now shown was shaded from (without its jitter).
  view.shown_view_projection = view.camera.Projection() * view.camera.View();
  view.shown_eye = view.camera.position;
  return absl::OkStatus();
}

void EngineImpl::ApplyUpdates(SessionRecord& session, ViewRecord& view, GpuSceneRecord& scene,
                              const std::deque<Update>& updates) {
  SceneState& state = *scene.state;
  if (!view.initialized) {
    view.initialized = true;
    view.camera = DefaultCamera(state, session.config.width, session.config.height);
    if (session.config.camera) ApplyCameraUpdate(state, *session.config.camera, view.camera);
  }
  gl::StageTimer::Scope stage(timer_, "apply_updates", /*cpu_stage=*/true);
  // The animation clock first, so that a seek among the updates is exact.
  const auto now = Clock::now();
  if (scene.animation_tick) {
    state.Advance(std::chrono::duration<double>(now - *scene.animation_tick).count());
  }
  scene.animation_tick = now;
  ChangeMask materials = kChangeNone;
  for (const Update& u : updates) {
    if (const auto* camera = std::get_if<CameraUpdate>(&u.change)) {
      ApplyCameraUpdate(state, *camera, view.camera);
      view.camera_changed = true;
      view.camera_version += 1;
    } else if (absl::Status limits = state.CheckApply(u.change); !limits.ok()) {
      // Within its own limits, but not with the current state (a world
      // position through the hierarchy, colour x intensity, ...).
      session.sink->OnUpdateRejected(u.seq, limits);
    } else {
      materials |= state.Apply(u.change) & (kChangeMaterials | kChangeEmission);
    }
    view.last_seq = std::max(view.last_seq, u.seq);
  }
  if (materials) scene.gpu->UpdateMaterials(state);
}

absl::StatusOr<EngineImpl::ReadPixels> EngineImpl::ReadBack(
    const SessionRecord& session, ViewRecord& view, const std::function<std::string()>& stages) {
  const EncodingOptions& enc = session.config.encoding;
  ReadPixels out;
  if (enc.format == ImageFormat::kExr) {
    timer_.Skip("tonemap");
    gl::StageTimer::Scope stage(timer_, "readback");
    out.hdr = passes_->ReadHdr(view.gbuffer);
  } else {
    {
      gl::StageTimer::Scope stage(timer_, "tonemap");
      passes_->Tonemap(view.gbuffer, enc.exposure);
    }
    gl::StageTimer::Scope stage(timer_, "readback");
    out.ldr = passes_->ReadLdr(view.gbuffer);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  // No frame with NaN or Inf leaves the server: it is a solver bug (inputs
  // are bounded, scene/magnitude_limits.h), reported as such. EXR scans the
  // float readback it has anyway; JPEG/PNG count in the tone-map pass, which
  // reads every HDR pixel already, and read back one counter.
  const size_t non_finite = enc.format == ImageFormat::kExr
                                ? size_t(std::count_if(out.hdr.begin(), out.hdr.end(),
                                                       [](float v) { return !std::isfinite(v); }))
                                : size_t(passes_->NonFinitePixels());
  if (non_finite > 0) {
    return absl::InternalError(absl::StrCat(
        "solver '", session.config.solver, "' (stages ", stages(), "): produced ", non_finite,
        enc.format == ImageFormat::kExr ? " non-finite values" : " non-finite pixels",
        "; the frame is not sent"));
  }
  return out;
}

absl::Status EngineImpl::EncodeFrame(SessionRecord& session, ViewRecord& view,
                                     const ReadPixels& pixels, EncodedFrame& frame) {
  const EncodingOptions& enc = session.config.encoding;
  // Pixels equal to the last frame's are not encoded again (the frame
  // says `unchanged`), unless a key frame was asked for.
  bool key_frame = false;
  {
    MutexLock lock(mutex_);
    key_frame = std::exchange(session.key_frame_requested, false);
  }
  const std::span<const uint8_t> bytes =
      enc.format == ImageFormat::kExr
          ? std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(pixels.hdr.data()),
                                     pixels.hdr.size() * sizeof(float))
          : std::span<const uint8_t>(pixels.ldr);
  const bool same = !enc.send_unchanged && view.encoder.SameAsLast(bytes);
  frame.unchanged = same && !key_frame;
  if (frame.unchanged) {
    timer_.Skip("encode");
    frame.key_frame = false;
    return absl::OkStatus();
  }
  gl::StageTimer::Scope stage(timer_, "encode", /*cpu_stage=*/true);
  const int w = int(view.gbuffer.width()), h = int(view.gbuffer.height());
  const float fps =
      session.config.max_fps > 0.0f ? session.config.max_fps : options_.default_max_fps;
  GS_ASSIGN_OR_RETURN(EncodedImage image,
                      view.encoder.Encode(enc, fps, pixels.ldr, pixels.hdr, w, h, key_frame));
  frame.image = std::move(image.bytes);
  frame.key_frame = image.key_frame;
  return absl::OkStatus();
}

void EngineImpl::AddViewStats(ViewRecord& view, const GpuSceneRecord& scene, const Solver& solver,
                              const SceneState& state, uint32_t refine_target,
                              std::vector<std::pair<std::string, double>>& stats) {
  stats.emplace_back("camera_changed", view.camera_changed ? 1.0 : 0.0);
  // How long the picture has had to converge since the last change of each
  // kind (issue 27): frames sent and milliseconds since the camera moved
  // and since the scene version this view shows changed.
  {
    const auto now = Clock::now();
    const bool first = view.frame_number == 1;
    if (view.camera_changed || first) view.camera_since = {now, view.frame_number};
    if (state.version() != view.scene_version_seen || first) {
      view.scene_since = {now, view.frame_number};
      view.scene_version_seen = state.version();
    }
    SetSinceChangeStats(view, now, stats);
  }
  stats.emplace_back("scene_gpu_bytes", double(scene.gpu->gpu_bytes()));
  stats.emplace_back("cached_solvers", double(scene.solvers.size()));
  // 0 while the solver's view-independent update runs on (slices, a
  // background job): the frame shows the last consistent solution.
  stats.emplace_back("update_complete", solver.UpdateComplete() ? 1.0 : 0.0);
  // Refinement progress: samples per pixel in the picture shown, of the
  // view's target (1 of 1 when it does not refine).
  stats.emplace_back("refine_samples", double(view.refinement.samples()));
  stats.emplace_back("refine_target", double(refine_target));
  // The weight, in samples, of the picture shown before the last change
  // of what the view shows (0: none; render/refinement.h).
  stats.emplace_back("refine_history", double(view.refinement.HistoryWeight(refine_target)));
  // The carried anti-aliasing's weight in samples (0: none).
  stats.emplace_back("refine_carry", double(view.refinement.CarryWeight(refine_target)));
  // The reprojected picture's weight after a camera move (0: none).
  stats.emplace_back("refine_reproject", double(view.refinement.ReprojectWeight(refine_target)));
}

double EngineImpl::FrameBudgetMs(const SessionRecord& session, const ViewRecord& view) const {
  if (session.config.frame_budget_ms > 0.0) return session.config.frame_budget_ms;
  const double base = options_.frame_budget_ms;
  if (!view.alone || session.config.pacing != Pacing::kContinuous) return base;
  const float fps =
      session.config.max_fps > 0.0f ? session.config.max_fps : options_.default_max_fps;
  // At most kAloneBudgetFactor x the default: a session that another one's
  // frame becomes due behind (a cap of 0.1 fps would otherwise give it 5 s)
  // waits no more than a few default slices.
  constexpr double kAloneBudgetFactor = 3.0;
  return fps > 0.0f ? std::clamp(0.5 * 1000.0 / double(fps), base, kAloneBudgetFactor * base)
                    : base;
}

absl::StatusOr<std::shared_ptr<EncodedFrame>> EngineImpl::ProduceFrame(SessionRecord& session,
                                                                       ViewRecord& view,
                                                                       std::deque<Update> updates) {
  auto scene_it = gpu_scenes_.find(session.scene->id);
  if (scene_it == gpu_scenes_.end()) {
    return absl::InternalError(absl::StrCat("scene '", session.scene->id, "' has no GPU data"));
  }
  GpuSceneRecord& scene = scene_it->second;
  const auto frame_start = Clock::now();
  timer_.Reset();
  view.settled = false;

  ApplyUpdates(session, view, scene, updates);
  GS_RETURN_IF_ERROR(ReserveView(session, scene, view));
  DeformScene(scene);
  GS_ASSIGN_OR_RETURN(SolverEntry * entry, AcquireSolver(session, scene));
  SolverContext ctx{*scene.state, *scene.gpu, timer_};
  ctx.reserve = accounts_.ReserverFor(scene.tenant);
  ctx.budget_ms = FrameBudgetMs(session, view);
  ctx.stop = session.stop.get_token();
  GS_ASSIGN_OR_RETURN(const ChangeMask changes, PlanAndSolve(view, *entry, ctx));
  if (!entry->solver->UpdateComplete() && session.config.pacing == Pacing::kOnRequest) {
    // Its view-independent update runs on (slices, a background job): a
    // frame requested on its own waits for it, the other sessions' frames
    // in between, polling every kPollInterval.
    view.poll_at = Clock::now() + kPollInterval;
    return CarrySlice(view, frame_start);
  }
  const FrameDraw draw{RefineTarget(session, *entry->solver, *scene.state), updates.empty(),
                       frame_start};
  GS_ASSIGN_OR_RETURN(const std::optional<Refinement::Sample> sample,
                      Draw(session, view, scene, *entry, ctx, draw));
  const bool refined = view.refinement.samples() >= draw.refine_target;
  if (session.config.pacing == Pacing::kOnRequest &&
      (!entry->solver->FrameComplete() || !refined)) {
    // A frame requested on its own is sent complete (every pathtrace
    // sample, every refinement sample): keep this slice's timings and run
    // the next slice at the session's next turn, after the other sessions'
    // frames.
    return CarrySlice(view, frame_start);
  }
  auto frame = std::make_shared<EncodedFrame>();
  GS_ASSIGN_OR_RETURN(const ReadPixels pixels, ReadBack(session, view, [&] {
                        return absl::StrJoin(entry->solver->Plan(*scene.state, changes), ", ");
                      }));
  GS_RETURN_IF_ERROR(EncodeFrame(session, view, pixels, *frame));
  Publish(session, view, scene, *entry, sample, draw, *frame);
  return frame;
}

void EngineImpl::DeformScene(GpuSceneRecord& scene) {
  // Skinned and morphed meshes are posed on the GPU once per scene version,
  // for every rasterising pass of every session; a scene without them has
  // no deform stage.
  if (scene.gpu->DeformPending(*scene.state)) {
    gl::StageTimer::Scope stage(timer_, "deform");
    scene.gpu->Deform(*scene.state);
  } else if (scene.gpu->deforms()) {
    timer_.Skip("deform");
  }
}

absl::StatusOr<EngineImpl::SolverEntry*> EngineImpl::AcquireSolver(const SessionRecord& session,
                                                                   GpuSceneRecord& scene) {
  SolverEntry& entry = scene.solvers[session.solver_key];
  if (!entry.solver) {
    EvictIdleSolvers(scene, session.scene.get(), session.solver_key);
    if (absl::Status built = BuildSolver(session, scene, entry); !built.ok()) {
      scene.solvers.erase(session.solver_key);
      return built;
    }
  }
  entry.last_used = ++solver_clock_;
  return &entry;
}

absl::StatusOr<ChangeMask> EngineImpl::PlanAndSolve(ViewRecord& view, SolverEntry& entry,
                                                    SolverContext& ctx) {
  const ChangeMask changes = entry.fresh ? kChangeAll : ctx.state.ChangesSince(entry.version);
  // The engine asks the solver which of its stages this change needs; the
  // frame reports every stage of the solver's table against that plan.
  for (std::string& stage : entry.solver->Plan(ctx.state, changes)) {
    if (std::find(view.plan.begin(), view.plan.end(), stage) == view.plan.end()) {
      view.plan.push_back(std::move(stage));
    }
  }
  GS_RETURN_IF_ERROR(entry.solver->Update(ctx, changes));
  entry.version = ctx.state.version();
  entry.fresh = false;
  return changes;
}

std::shared_ptr<EncodedFrame> EngineImpl::CarrySlice(ViewRecord& view,
                                                     Clock::time_point frame_start) {
  MergeTimings(view.carry, timer_.Finish());
  view.carry_ms += std::chrono::duration<double, std::milli>(Clock::now() - frame_start).count();
  return nullptr;
}

absl::StatusOr<std::optional<Refinement::Sample>> EngineImpl::Draw(
    const SessionRecord& session, ViewRecord& view, GpuSceneRecord& scene, SolverEntry& entry,
    SolverContext& ctx, const FrameDraw& draw) {
  // A still view refines (render/refinement.h): this frame shades sample
  // `sample` at its sub-pixel jitter, or, once the samples are all in
  // (nullopt), shows their mean again and shades nothing.
  const SceneState& state = *scene.state;
  const std::optional<Solver::ShownCount> shown = entry.solver->Shown();
  const std::optional<Refinement::Sample> sample = view.refinement.Next(
      {state.version(), view.camera_version, entry.solver.get(), view.camera.width,
       view.camera.height, entry.solver->UpdateComplete(),
       shown ? std::optional(shown->changes) : std::nullopt, shown ? shown->steps : 0},
      draw.refine_target, session.config.refine_history.value_or(options_.refine_history),
      options_.refine_carry, session.config.refine_reproject.value_or(options_.refine_reproject));
  if (!sample) {
    // No change since the picture was complete, so the solver's plan is
    // its changeless one, all of it shading, none of it run; unless its
    // update goes on (a solver that counts what it shows, Solver::Shown,
    // runs its update's stages under a complete picture).
    if (view.carry.empty() && entry.solver->UpdateComplete()) view.plan.clear();
    timer_.Skip("gbuffer");
    gl::StageTimer::Scope stage(timer_, "refine");
    passes_->ShowAccumulation(view.gbuffer, {view.refinement.samples()});
    return sample;
  }
  // Frames that bring no update (a still view refining, a Render's slices)
  // shade as many samples as fit the frame's budget; a frame that applied
  // an update shades one, so interaction keeps its latency.
  const bool more = draw.no_updates && draw.refine_target > 1;
  if (more) glFinish();  // the solver's work is not this sample's
  const auto ms = [](Clock::duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
  };
  for (std::optional<Refinement::Sample> next = sample; next;
       next = view.refinement.Continue(draw.refine_target)) {
    const auto sample_start = Clock::now();
    GS_RETURN_IF_ERROR(ShadeSample(scene, entry, ctx, view, *next, draw.refine_target));
    if (!more || ctx.stop.stop_requested()) break;
    glFinish();
    const auto now = Clock::now();
    if (ms(now - draw.frame_start) + ms(now - sample_start) > ctx.budget_ms) break;
  }
  return sample;
}

void EngineImpl::Publish(SessionRecord& session, ViewRecord& view, const GpuSceneRecord& scene,
                         const SolverEntry& entry, const std::optional<Refinement::Sample>& sample,
                         const FrameDraw& draw, EncodedFrame& frame) {
  const SceneState& state = *scene.state;
  frame.timings = std::move(view.carry);
  view.carry.clear();
  MergeTimings(frame.timings, timer_.Finish());
  ReportAgainstPlan(entry.solver->description(), view.plan, frame.timings);
  frame.planned_stages = std::move(view.plan);
  view.plan.clear();
  frame.frame_number = ++view.frame_number;
  frame.width = view.gbuffer.width();
  frame.height = view.gbuffer.height();
  frame.format = session.config.encoding.format;
  frame.scene_version = state.version();
  frame.last_update_seq = view.last_seq;
  frame.solver = session.config.solver;
  frame.stats = session.config.pacing == Pacing::kOnRequest && sample && sample->index > 0
                    ? std::move(view.solve_stats)
                    : entry.solver->Stats();
  AddViewStats(view, scene, *entry.solver, state, draw.refine_target, frame.stats);
  // What BuildSolver estimated for a complete solve (this server's seconds).
  frame.stats.emplace_back("solve_estimate_s", entry.solve_estimate_s);
  // The solver work this frame was allowed (FrameBudgetMs).
  frame.stats.emplace_back("budget_ms", FrameBudgetMs(session, view));
  // Settled: the picture equals the last one, no update came with it and
  // the solver owes nothing (no slices, no background job, no animation):
  // a continuous view then rests (RenderFrame). Keep-alives at rest say 1.
  const bool refined = view.refinement.samples() >= draw.refine_target;
  view.settled = frame.unchanged && refined && draw.no_updates && !view.camera_changed &&
                 entry.solver->UpdateComplete() && entry.solver->FrameComplete() &&
                 !entry.solver->BackgroundBusy() && !AnyAnimationPlaying(state);
  frame.stats.emplace_back("at_rest", 0.0);
  view.camera_changed = false;
  frame.total_ms =
      view.carry_ms +
      std::chrono::duration<double, std::milli>(Clock::now() - draw.frame_start).count();
  view.carry_ms = 0.0;
}

void EngineImpl::EvictIdleSolvers(GpuSceneRecord& scene, const SceneRecord* owner,
                                  const std::string& keep) {
  if (scene.solvers.size() <= options_.max_solvers_per_scene) return;
  std::set<std::string> live{keep};
  {
    MutexLock lock(mutex_);
    for (const auto& [id, s] : sessions_) {
      if (s->scene.get() == owner) live.insert(s->solver_key);
    }
  }
  while (scene.solvers.size() > options_.max_solvers_per_scene) {
    auto victim = scene.solvers.end();
    for (auto it = scene.solvers.begin(); it != scene.solvers.end(); ++it) {
      if (live.count(it->first) == 0 &&
          (victim == scene.solvers.end() || it->second.last_used < victim->second.last_used)) {
        victim = it;
      }
    }
    if (victim == scene.solvers.end()) return;  // every cached solver is in use
    Log(LogLevel::kInfo, {"", owner->id}, absl::StrCat("dropping idle solver ", victim->first));
    Retire(std::move(victim->second.solver));
    scene.solvers.erase(victim);
  }
}

absl::Status EngineImpl::ReserveView(const SessionRecord& session, const GpuSceneRecord& scene,
                                     ViewRecord& view) {
  const uint32_t w = view.camera.width, h = view.camera.height;
  if (w == view.memory_width && h == view.memory_height) return absl::OkStatus();
  // The old size's buffers go with the resize (G-buffer, encoder reopened).
  view.memory.Release();
  view.memory_width = view.memory_height = 0;
  GS_ASSIGN_OR_RETURN(
      view.memory,
      accounts_.Reserve(scene.tenant, EstimateFrameBytes(w, h, session.config.encoding.format),
                        uint64_t(w) * h * GBuffer::kBytesPerPixel,
                        absl::StrCat("width x height: ", w, "x", h,
                                     " (its G-buffer, readback and encoder buffers)")));
  view.memory_width = w;
  view.memory_height = h;
  return absl::OkStatus();
}

absl::Status EngineImpl::BuildSolver(const SessionRecord& session, const GpuSceneRecord& scene,
                                     SolverEntry& entry) {
  // One place for every solver: its memory (solvers/memory_estimate.h) is
  // reserved and its time (solvers/work_estimate.h) checked, both
  // estimated from the parameters and the scene, before anything is built.
  GS_ASSIGN_OR_RETURN(
      MemoryEstimate estimate,
      EstimateSolverMemory(session.config.solver, session.params, *scene.state, *scene.gpu));
  GS_ASSIGN_OR_RETURN(MemoryCharge memory,
                      accounts_.Reserve(scene.tenant, estimate.cpu_bytes(), estimate.gpu_bytes(),
                                        estimate.Describe(session.config.solver, session.params)));
  GS_ASSIGN_OR_RETURN(
      const WorkEstimate work,
      EstimateSolverWork(session.config.solver, session.params, *scene.state, *scene.gpu));
  const double speed = options_.solve_speed > 0.0 ? options_.solve_speed : 1.0;
  if (options_.max_solve_seconds > 0.0 && work.seconds() / speed > options_.max_solve_seconds) {
    return absl::ResourceExhaustedError(absl::StrFormat(
        "%s: a complete solve is estimated at %.3g s, over the server's limit of %.3g s "
        "(--max-solve-seconds, at --solve-speed %.3g); lower the named parameters",
        work.Describe(session.config.solver, session.params), work.seconds() / speed,
        options_.max_solve_seconds, speed));
  }
  GS_ASSIGN_OR_RETURN(entry.solver, CreateSolver(session.config.solver, session.params));
  entry.memory = std::move(memory);
  entry.solve_estimate_s = work.seconds() / speed;
  return absl::OkStatus();
}

}  // namespace gistream
