// EngineImpl's render thread between frames: Tick (whose turn, fair share
// between tenants), rest and keep-alives, retiring solvers, idle expiry.
#include "engine/engine_impl.h"

#include <algorithm>
#include <limits>
#include <set>
#include <utility>

#include "engine/engine_common.h"
#include "util/log.h"

namespace gistream {
using namespace engine_internal;  // NOLINT(build/namespaces): engine_common.h

namespace {

// Fair share between tenants (EngineImpl::FairShareAhead): how far (ms of
// render time) a tenant may run ahead of the one that used least before it
// waits, and how much credit an idle tenant keeps.
constexpr double kFairSliceMs = 30.0;
constexpr double kFairWindowMs = 200.0;

}  // namespace

Clock::time_point EngineImpl::Tick() {
  if (started_) CheckGpuReset();  // also between frames (an injected reset)
  ExpireIdle();
  ReapRetired();
  // Once a dropped scene's solvers are gone too, its freed heap goes back
  // to the system (RSS follows the budget down after an unload).
  if (retiring_.empty() && heap_trimmer_.Poll(Clock::now())) {
    Log(LogLevel::kDebug, "returned freed heap memory to the system (malloc_trim)");
  }
  // Snapshot the sessions, ordered so the one after the last served comes
  // first: every due session gets one frame per round.
  std::vector<std::shared_ptr<SessionRecord>> order;
  {
    MutexLock lock(mutex_);
    auto start = sessions_.upper_bound(last_served_);
    for (auto it = start; it != sessions_.end(); ++it) order.push_back(it->second);
    for (auto it = sessions_.begin(); it != start; ++it) order.push_back(it->second);
  }
  Clock::time_point next = Clock::time_point::max();
  const FrameDemand demand = FairShareWanting(order, Clock::now());
  for (const auto& session : order) {
    // Fair share: a tenant more than a slice of render time ahead of the
    // tenant that used least (among those with a frame due) waits.
    // (A session with no frame due goes on below: its next turn is timed.)
    if (demand.sessions.count(session->id) > 0 &&
        FairShareAhead(session->scene->tenant, demand.tenants)) {
      fair_share_deferrals_.fetch_add(1, std::memory_order_relaxed);
      next = std::min(next, Clock::now() + std::chrono::milliseconds(1));
      continue;
    }
    ViewRecord& view = views_[session->id];
    const std::optional<bool> due_now = TakeTurn(*session, view, next);
    if (!due_now) continue;  // closed
    const bool due = *due_now;
    if (due && view.rest) {
      if (StillAtRest(*session, view)) {
        const auto now = Clock::now();
        if (now - view.encoder.last_sent() >= kKeepAlivePeriod) SendKeepAlive(*session, view, now);
        next = std::min(next, view.encoder.last_sent() + kKeepAlivePeriod);
        continue;
      }
      view.rest.reset();
      session->resting = false;
    }
    if (!due) {
      if (session->config.pacing == Pacing::kContinuous) next = std::min(next, view.next_due);
      continue;
    }
    const float fps =
        session->config.max_fps > 0.0f ? session->config.max_fps : options_.default_max_fps;
    const auto start = Clock::now();
    const uint64_t resets = gpu_resets_;
    view.alone = demand.sessions.size() <= 1;
    RenderFrame(*session, view);
    last_served_ = session->id;
    tenant_render_ms_[session->scene->tenant] +=
        std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    // A GPU reset during the frame dropped every view (`view` too).
    if (gpu_resets_ != resets) return Clock::now();
    if (session->config.pacing == Pacing::kContinuous) {
      view.next_due = start + std::chrono::duration_cast<Clock::duration>(
                                  std::chrono::duration<double>(1.0 / double(fps)));
      next = std::min(next, view.next_due);
    } else {
      MutexLock lock(mutex_);
      if (session->requested > 0) next = std::min(next, std::max(view.poll_at, Clock::now()));
    }
  }
  // Idle sessions and scenes are looked for at least every second.
  if (options_.idle_timeout.count() > 0) {
    next = std::min(next, Clock::now() + std::chrono::seconds(1));
  }
  // Retired solvers are destroyed soon after their jobs end.
  if (!retiring_.empty()) next = std::min(next, Clock::now() + std::chrono::milliseconds(50));
  next = std::min(next, heap_trimmer_.due());
  return next;
}

EngineImpl::FrameDemand EngineImpl::FairShareWanting(
    const std::vector<std::shared_ptr<SessionRecord>>& order, Clock::time_point now) {
  std::set<TenantId> present, wanting;
  std::set<SessionId> sessions;
  {
    MutexLock lock(mutex_);
    for (const auto& session : order) {
      present.insert(session->scene->tenant);
      if (session->closed) continue;
      const auto view = views_.find(session->id);
      bool wants = view == views_.end();  // its first frame
      if (!wants && session->config.pacing == Pacing::kOnRequest) {
        wants = session->requested > 0 && now >= view->second.poll_at;
      } else if (!wants) {
        wants = now >= view->second.next_due &&
                (!view->second.rest || !session->pending.empty() || session->key_frame_requested);
      }
      if (wants) {
        wanting.insert(session->scene->tenant);
        sessions.insert(session->id);
      }
    }
  }
  std::erase_if(tenant_render_ms_, [&](const auto& t) { return present.count(t.first) == 0; });
  // A tenant that was idle (or is new) banks no more than kFairWindowMs of
  // credit: it cannot then hold the thread for longer than that.
  double lead = 0.0;
  for (const TenantId& t : wanting) lead = std::max(lead, tenant_render_ms_[t]);
  for (const TenantId& t : wanting) {
    tenant_render_ms_[t] = std::max(tenant_render_ms_[t], lead - kFairWindowMs);
  }
  return {{wanting.begin(), wanting.end()}, std::move(sessions)};
}

bool EngineImpl::FairShareAhead(const TenantId& tenant, const std::vector<TenantId>& wanting) {
  double floor = std::numeric_limits<double>::infinity();
  for (const TenantId& t : wanting) floor = std::min(floor, tenant_render_ms_[t]);
  return tenant_render_ms_[tenant] > floor + kFairSliceMs;
}

std::optional<bool> EngineImpl::TakeTurn(SessionRecord& session, ViewRecord& view,
                                         Clock::time_point& next) {
  MutexLock lock(mutex_);
  if (session.closed) return std::nullopt;
  if (session.config.pacing == Pacing::kOnRequest) {
    // A frame waiting on a background job is polled, not spun on.
    const bool due = session.requested > 0 && Clock::now() >= view.poll_at;
    if (due) session.requested -= 1;
    if (session.requested > 0 && !due) next = std::min(next, view.poll_at);
    return due;
  }
  // At rest, only an update or a key frame request makes it due.
  if (view.rest && (!session.pending.empty() || session.key_frame_requested)) {
    view.rest.reset();
    session.resting = false;
  }
  return Clock::now() >= view.next_due;
}

void EngineImpl::Retire(std::unique_ptr<Solver> solver) {
  if (!solver || !solver->BackgroundBusy()) return;
  solver->CancelBackground();  // its loops end within a step
  retiring_.push_back(std::move(solver));
  RefreshMemoryStats(/*force=*/true);
}

void EngineImpl::CancelBackgroundJobs() {
  for (auto& [id, scene] : gpu_scenes_) {
    for (auto& [key, entry] : scene.solvers) {
      if (entry.solver) entry.solver->CancelBackground();
    }
  }
  for (auto& solver : retiring_) solver->CancelBackground();
}

void EngineImpl::ReapRetired() {
  if (std::erase_if(retiring_, [](const auto& s) { return !s->BackgroundBusy(); }) > 0) {
    RefreshMemoryStats(/*force=*/true);
  }
}

void EngineImpl::DropGpuScene(const SceneId& id) {
  auto it = gpu_scenes_.find(id);
  if (it == gpu_scenes_.end()) return;
  for (auto& [key, entry] : it->second.solvers) Retire(std::move(entry.solver));
  gpu_scenes_.erase(it);
  heap_trimmer_.Request(Clock::now());
}

void EngineImpl::RequestHeapTrim() {
  render_thread_->Post([this] {
    render_role_.Assert();
    heap_trimmer_.Request(Clock::now());
  });
}

void EngineImpl::ExpireIdle() {
  if (options_.idle_timeout.count() <= 0) return;
  const auto now = Clock::now();
  std::vector<std::shared_ptr<SessionRecord>> expired;
  std::vector<SceneId> freed;
  {
    MutexLock lock(mutex_);
    if (shut_down_) return;
    for (const auto& [id, s] : sessions_) {
      if (s->config.pacing == Pacing::kContinuous) {
        // A viewer that only watches sends nothing, yet reads its frames
        // (and one still waiting for its first frame waits on us).
        const uint64_t dropped = s->sink->dropped_frames();
        if (s->frames == 0 ||
            (s->frames > s->idle_seen_frames && dropped == s->idle_seen_dropped)) {
          s->last_request = now;
        }
        s->idle_seen_frames = s->frames;
        s->idle_seen_dropped = dropped;
      }
      if (!s->transient && !s->closed && now - s->last_request > options_.idle_timeout) {
        s->closed = true;  // no more frames; CloseSession follows from the client's side
        expired.push_back(s);
      }
    }
    // A scene no session or Render uses, idle that long, goes even if its
    // loader never unloaded it.
    for (auto it = scenes_.begin(); it != scenes_.end();) {
      const SceneRecord& scene = *it->second;
      if (scene.sessions == 0 && now - scene.last_used > options_.idle_timeout &&
          gpu_scenes_.count(it->first) > 0) {
        freed.push_back(it->first);
        it = scenes_.erase(it);
      } else {
        ++it;
      }
    }
  }
  const auto seconds = std::chrono::duration<double>(options_.idle_timeout).count();
  for (const auto& s : expired) {
    Log(LogLevel::kInfo, {s->id, s->config.scene}, "idle: ending the session");
    s->sink->OnSessionFailed(absl::DeadlineExceededError(
        absl::StrCat("session: no request from the client for ", seconds, " s (--idle-timeout)")));
  }
  for (const SceneId& id : freed) {
    DropGpuScene(id);
    Log(LogLevel::kInfo, {"", id}, absl::StrCat("idle for ", seconds, " s: unloaded"));
  }
  if (!freed.empty()) RefreshMemoryStats(/*force=*/true);
}

// Frame stats of how long the view's picture has had since the last change
// of each kind (set or updated in place).
void EngineImpl::SetSinceChangeStats(const ViewRecord& view, RenderThread::Clock::time_point now,
                                     std::vector<std::pair<std::string, double>>& stats) {
  const auto set = [&](const char* name, double value) {
    for (auto& [n, v] : stats) {
      if (n == name) {
        v = value;
        return;
      }
    }
    stats.emplace_back(name, value);
  };
  const auto since = [&](const char* frames, const char* ms, const ViewRecord::Since& s) {
    set(frames, double(view.frame_number - s.frame));
    set(ms, std::chrono::duration<double, std::milli>(now - s.time).count());
  };
  since("frames_since_camera_change", "ms_since_camera_change", view.camera_since);
  since("frames_since_scene_change", "ms_since_scene_change", view.scene_since);
}

uint32_t EngineImpl::RefineTarget(const SessionRecord& session, const Solver& solver,
                                  const SceneState& state) const {
  if (!solver.NeedsGBuffer() || AnyAnimationPlaying(state)) return 1;
  return session.config.refine_samples > 0 ? session.config.refine_samples
                                           : options_.refine_samples;
}

bool EngineImpl::StillAtRest(const SessionRecord& session, const ViewRecord& view) {
  const auto scene_it = gpu_scenes_.find(session.scene->id);
  if (scene_it == gpu_scenes_.end()) return false;
  const GpuSceneRecord& scene = scene_it->second;
  if (scene.state->version() != view.rest->scene_version) return false;
  if (AnyAnimationPlaying(*scene.state)) return false;
  const auto solver_it = scene.solvers.find(session.solver_key);
  return solver_it != scene.solvers.end() && solver_it->second.solver.get() == view.rest->solver;
}

void EngineImpl::SendKeepAlive(SessionRecord& session, ViewRecord& view,
                               RenderThread::Clock::time_point now) {
  auto frame = std::make_shared<EncodedFrame>(view.rest->frame);
  frame->frame_number = ++view.frame_number;
  SetSinceChangeStats(view, now, frame->stats);
  keep_alives_at_rest_.fetch_add(1);
  {
    MutexLock lock(mutex_);
    session.frames += 1;  // reaches the client: not idle (ExpireIdle)
  }
  view.encoder.MarkSent(*frame, now);
  session.sink->OnFrame(std::move(frame));
}

}  // namespace gistream
