// EngineImpl's sessions: config checks, admission, open, updates and frame
// requests, close, and Render (a transient session's first frame).
#include "engine/engine_impl.h"

#include <absl/strings/str_format.h>

#include <algorithm>
#include <cmath>
#include <future>
#include <utility>

#include "engine/engine_common.h"
#include "scene/state/validate_update.h"
#include "solvers/registry.h"
#include "util/log.h"
#include "util/user_string.h"

namespace gistream {
using namespace engine_internal;  // NOLINT(build/namespaces): engine_common.h

namespace {

// A frame's solver work may take at most this long before it yields.
constexpr double kMaxFrameBudgetMs = 10'000.0;

// Sink that hands the first frame of a Render() call to a promise.
class PromiseSink final : public FrameSink {
 public:
  std::future<absl::StatusOr<EncodedFrame>> future() { return promise_.get_future(); }
  void OnFrame(std::shared_ptr<const EncodedFrame> frame) override { Set(*frame); }
  void OnUpdateRejected(uint64_t /*seq*/, const absl::Status& status) override { Set(status); }
  void OnSessionFailed(const absl::Status& status) override { Set(status); }

 private:
  void Set(absl::StatusOr<EncodedFrame> value) {
    MutexLock lock(mutex_);
    if (done_) return;
    done_ = true;
    promise_.set_value(std::move(value));
  }
  Mutex mutex_;
  bool done_ ABSL_GUARDED_BY(mutex_) = false;
  std::promise<absl::StatusOr<EncodedFrame>> promise_;
};

}  // namespace

absl::Status EngineImpl::ValidateConfig(const SessionConfig& c) const {
  if (c.width == 0 || c.height == 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(c.width == 0 ? "width" : "height", ": must be at least 1, got 0"));
  }
  if (c.width > options_.max_width || c.height > options_.max_height) {
    return absl::ResourceExhaustedError(absl::StrCat("width x height: ", c.width, "x", c.height,
                                                     " exceeds the limit of ", options_.max_width,
                                                     "x", options_.max_height));
  }
  if (c.encoding.quality < 1 || c.encoding.quality > 100) {
    return absl::InvalidArgumentError(
        absl::StrCat("encoding.quality: ", c.encoding.quality, " is out of range [1, 100]"));
  }
  if (!std::isfinite(c.encoding.exposure) || std::abs(c.encoding.exposure) > 30.0f) {
    return absl::InvalidArgumentError(
        absl::StrCat("encoding.exposure: ", c.encoding.exposure, " is out of range [-30, 30]"));
  }
  GS_RETURN_IF_ERROR(ValidateEncoding(c.encoding));
  if (!std::isfinite(c.frame_budget_ms) || c.frame_budget_ms < 0.0 ||
      c.frame_budget_ms > kMaxFrameBudgetMs) {
    return absl::InvalidArgumentError(absl::StrCat(
        "frame_budget_ms: ", c.frame_budget_ms, " is out of range [0, ", kMaxFrameBudgetMs, "]"));
  }
  if (c.refine_reproject && *c.refine_reproject > EngineOptions::kMaxRefineHistory) {
    return absl::InvalidArgumentError(absl::StrCat("refine_reproject: ", *c.refine_reproject,
                                                   " is outside [0, ",
                                                   EngineOptions::kMaxRefineHistory, "]"));
  }
  if (c.refine_history && *c.refine_history > EngineOptions::kMaxRefineHistory) {
    return absl::InvalidArgumentError(absl::StrCat("refine_history: ", *c.refine_history,
                                                   " is outside [0, ",
                                                   EngineOptions::kMaxRefineHistory, "]"));
  }
  if (c.refine_samples > EngineOptions::kMaxRefineSamples) {
    return absl::InvalidArgumentError(absl::StrCat("refine_samples: ", c.refine_samples,
                                                   " is out of range [0, ",
                                                   EngineOptions::kMaxRefineSamples, "]"));
  }
  if (!std::isfinite(c.max_fps) || c.max_fps < 0.0f || c.max_fps > options_.max_fps) {
    return absl::InvalidArgumentError(
        absl::StrCat("max_fps: ", c.max_fps, " is out of range [0, ", options_.max_fps, "]"));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::shared_ptr<EngineImpl::SessionRecord>> EngineImpl::CreateSession(
    const SessionConfig& config, std::shared_ptr<FrameSink> sink, bool transient) {
  GS_RETURN_IF_ERROR(ValidateConfig(config));
  GS_ASSIGN_OR_RETURN(const SolverDescription* solver, FindSolver(config.solver));
  GS_ASSIGN_OR_RETURN(ParamSet params, ValidateParams(*solver, config.params));

  auto session = std::make_shared<SessionRecord>();
  session->config = config;
  session->params = params;
  session->solver_key = absl::StrCat(config.solver, "?", params.Key());
  session->sink = std::move(sink);
  session->transient = transient;

  MutexLock lock(mutex_);
  if (shut_down_) return Unavailable();
  if (draining_ && !transient) return Draining();
  if (gpu_lost_) return GpuLost();
  GS_ASSIGN_OR_RETURN(session->scene, FindSceneLocked(config.tenant, config.scene));
  if (config.camera) {
    GS_RETURN_IF_ERROR(ValidateUpdate(*session->scene->scene, Update{0, *config.camera},
                                      options_.max_width, options_.max_height));
  }
  if (!transient) {
    uint32_t open = 0, tenant_open = 0;
    for (const auto& [id, s] : sessions_) {
      open += s->transient ? 0 : 1;
      tenant_open += !s->transient && s->config.tenant == config.tenant ? 1 : 0;
    }
    if (open >= options_.max_sessions) {
      return absl::ResourceExhaustedError(
          absl::StrCat("sessions: ", open, " sessions are open, the limit (--max-sessions)"));
    }
    GS_RETURN_IF_ERROR(AdmitByRenderTimeLocked());
    if (const uint32_t limit = QuotaOf(config.tenant).sessions; limit > 0 && tenant_open >= limit) {
      return QuotaExceeded(config.tenant, "sessions", tenant_open, 1, limit);
    }
  }
  session->id = RandomId(transient ? "render" : "session");
  session->last_request = Clock::now();
  session->width = config.width;
  session->height = config.height;
  session->scene->sessions += 1;
  sessions_[session->id] = session;
  return session;
}

absl::Status EngineImpl::AdmitByRenderTimeLocked() const {
  if (options_.max_render_busy <= 0.0 || !render_thread_) return absl::OkStatus();
  uint32_t active = 0;
  for (const auto& [id, s] : sessions_) active += !s->transient && !s->resting.load() ? 1 : 0;
  if (active == 0) return absl::OkStatus();  // nothing measured costs anything yet
  // The next session is assumed to cost what an active one costs on
  // average now: its share of the render thread's busy time.
  const double busy = render_thread_->busy_ratio();
  const double expected = busy + busy / active;
  if (expected <= options_.max_render_busy) return absl::OkStatus();
  return absl::ResourceExhaustedError(absl::StrFormat(
      "capacity: the render thread was busy %.0f %% of the last 5 s with %u active session(s); "
      "one more would need about %.0f %%, over the limit of %.0f %% (--max-render-busy). "
      "Retry in a few seconds, or on another server",
      100.0 * busy, active, 100.0 * expected, 100.0 * options_.max_render_busy));
}

absl::StatusOr<SessionOpenInfo> EngineImpl::OpenSession(const SessionConfig& config,
                                                        std::shared_ptr<FrameSink> sink) {
  GS_ASSIGN_OR_RETURN(std::shared_ptr<SessionRecord> session,
                      CreateSession(config, std::move(sink), /*transient=*/false));
  render_thread_->Wake();
  Log(LogLevel::kDebug, {session->id, config.scene},
      absl::StrCat("engine session created (", config.solver, ", ", config.width, "x",
                   config.height, ")"));
  return SessionOpenInfo{session->id, config.scene, config.solver, session->params.values()};
}

absl::Status EngineImpl::PushUpdate(const SessionId& id, Update update) {
  MutexLock lock(mutex_);
  if (shut_down_) return Unavailable();
  auto it = sessions_.find(id);
  if (it == sessions_.end())
    return absl::NotFoundError(absl::StrCat("session: no session '", Echo(id), "'"));
  SessionRecord& session = *it->second;
  GS_RETURN_IF_ERROR(
      ValidateUpdate(*session.scene->scene, update, options_.max_width, options_.max_height));
  session.pending.push_back(std::move(update));
  session.last_request = Clock::now();
  // Continuous sessions pick updates up at their next frame (at once when
  // the view is at rest: hence the wake); on-request sessions when a frame
  // is requested.
  if (session.config.pacing == Pacing::kContinuous) render_thread_->Wake();
  return absl::OkStatus();
}

absl::Status EngineImpl::RequestFrames(const SessionId& id, uint32_t count) {
  {
    MutexLock lock(mutex_);
    if (shut_down_) return Unavailable();
    auto it = sessions_.find(id);
    if (it == sessions_.end()) {
      return absl::NotFoundError(absl::StrCat("session: no session '", Echo(id), "'"));
    }
    it->second->requested += std::max<uint32_t>(count, 1);
    it->second->last_request = Clock::now();
  }
  render_thread_->Wake();
  return absl::OkStatus();
}

absl::Status EngineImpl::RequestKeyFrame(const SessionId& id) {
  {
    MutexLock lock(mutex_);
    if (shut_down_) return Unavailable();
    auto it = sessions_.find(id);
    if (it == sessions_.end()) {
      return absl::NotFoundError(absl::StrCat("session: no session '", Echo(id), "'"));
    }
    it->second->key_frame_requested = true;
    it->second->last_request = Clock::now();
  }
  render_thread_->Wake();
  return absl::OkStatus();
}

void EngineImpl::CloseSession(const SessionId& id) {
  std::shared_ptr<SessionRecord> session;
  {
    MutexLock lock(mutex_);
    auto it = sessions_.find(id);
    if (it == sessions_.end()) return;
    session = it->second;
    session->closed = true;
    session->stop.request_stop();
    session->scene->sessions -= 1;
    session->scene->last_used = Clock::now();
    sessions_.erase(it);
    if (shut_down_) return;
    // The last reference of a scene already unloaded frees it.
    if (DropIfUnreferencedLocked(session->scene)) {
      Log(LogLevel::kInfo, {"", session->scene->id}, "unloaded (its last session ended)");
    }
  }
  render_thread_->Post([this, id, scene = session->scene->id, key = session->solver_key] {
    render_role_.Assert();
    ReleaseSessionGpu(id, scene, key);
  });
}

void EngineImpl::ReleaseSessionGpu(const SessionId& id, const SceneId& scene,
                                   const std::string& solver_key) {
  if (views_.erase(id) > 0) RefreshMemoryStats(/*force=*/true);
  const auto scene_it = gpu_scenes_.find(scene);
  if (scene_it == gpu_scenes_.end()) return;
  const auto entry = scene_it->second.solvers.find(solver_key);
  if (entry == scene_it->second.solvers.end() || !entry->second.solver ||
      !entry->second.solver->BackgroundBusy()) {
    return;
  }
  {
    MutexLock lock(mutex_);
    for (const auto& [sid, s] : sessions_) {
      if (s->scene->id == scene && s->solver_key == solver_key) return;  // still used
    }
  }
  Log(LogLevel::kInfo, {"", scene},
      absl::StrCat("cancelling solver ", solver_key, "'s background job (no session uses it)"));
  Retire(std::move(entry->second.solver));
  scene_it->second.solvers.erase(entry);
}

absl::StatusOr<EncodedFrame> EngineImpl::Render(const RenderRequest& request) {
  SessionConfig config;
  config.tenant = request.tenant;
  config.scene = request.scene;
  config.solver = request.solver;
  config.params = request.params;
  config.width = request.width;
  config.height = request.height;
  config.encoding = request.encoding;
  config.pacing = Pacing::kOnRequest;
  config.camera = request.camera;
  config.frame_budget_ms = request.frame_budget_ms;
  config.refine_samples = request.refine_samples;
  auto sink = std::make_shared<PromiseSink>();
  auto result = sink->future();
  GS_ASSIGN_OR_RETURN(std::shared_ptr<SessionRecord> session,
                      CreateSession(config, sink, /*transient=*/true));
  absl::Status status;
  for (const Update& u : request.updates) {
    status = PushUpdate(session->id, u);
    if (!status.ok()) break;
  }
  if (status.ok()) status = RequestFrames(session->id, 1);
  if (!status.ok()) {
    CloseSession(session->id);
    return status;
  }
  // Sliced work yields between slices, so a cancel stops it within one
  // slice: the closed session is skipped at its next turn.
  while (result.wait_for(std::chrono::milliseconds(20)) != std::future_status::ready) {
    if (request.cancelled && request.cancelled()) {
      CloseSession(session->id);
      return absl::CancelledError(
          "render: cancelled (the client left, its deadline passed or the server is stopping)");
    }
  }
  absl::StatusOr<EncodedFrame> frame = result.get();
  CloseSession(session->id);
  return frame;
}

}  // namespace gistream
