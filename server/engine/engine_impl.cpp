// EngineImpl: start, drain and shutdown, stats, and recovery from a GPU
// reset. Its other jobs are in engine_scenes.cpp (loading and unloading),
// engine_sessions.cpp (sessions and Render), engine_tick.cpp (the render
// thread's turns, rest and expiry) and engine_frame.cpp (a frame's steps).
#include "engine/engine_impl.h"

#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <utility>

#include "engine/engine_common.h"
#include "gl/fault_injection.h"
#include "solvers/registry.h"
#include "util/log.h"

namespace gistream {
using namespace engine_internal;  // NOLINT(build/namespaces): engine_common.h

namespace {

std::string CpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  }
  return "unknown";
}

std::string GlString(GLenum name) {
  const GLubyte* s = glGetString(name);
  return s ? reinterpret_cast<const char*>(s) : "";
}

}  // namespace

absl::StatusOr<std::unique_ptr<Engine>> Engine::Create(const EngineOptions& options) {
  auto engine = std::make_unique<EngineImpl>(options);
  GS_RETURN_IF_ERROR(engine->Start());
  return engine;
}

absl::Status EngineImpl::Start() {
  if (!options_.test_fault_dir.empty()) {
    gl::SetFaultDirectory(options_.test_fault_dir);
    Log(LogLevel::kWarning,
        absl::StrCat("test fault injection is on: ", options_.test_fault_dir.string()));
  }
  GS_ASSIGN_OR_RETURN(render_thread_, RenderThread::Start(options_.egl_device, [this] {
                        render_role_.Bind();  // the scheduler runs on the render thread
                        return Tick();
                      }));
  return render_thread_->Call<absl::Status>(
      [this]() -> absl::Status {
        render_role_.Bind();
        device_.vendor = GlString(GL_VENDOR);
        device_.renderer = GlString(GL_RENDERER);
        device_.version = GlString(GL_VERSION);
        device_.egl_device = render_thread_->context().description();
        device_.cpu_model = CpuModel();
        device_.cpu_threads = std::thread::hardware_concurrency();
        GLint major = 0, minor = 0;
        glGetIntegerv(GL_MAJOR_VERSION, &major);
        glGetIntegerv(GL_MINOR_VERSION, &minor);
        if (major * 10 + minor < 45) {
          return absl::FailedPreconditionError(
              absl::StrCat("OpenGL 4.5 is required, the context offers ", major, ".", minor));
        }
        GS_ASSIGN_OR_RETURN(ViewPasses passes, ViewPasses::Create());
        passes_ = std::make_unique<ViewPasses>(std::move(passes));
        memory_query_.emplace();
        RefreshMemoryStats(/*force=*/true);
        started_ = true;
        return absl::OkStatus();
      },
      Unavailable());
}

EngineImpl::~EngineImpl() { Shutdown(); }

void EngineImpl::BeginDrain(std::chrono::milliseconds deadline) {
  std::vector<std::shared_ptr<SessionRecord>> sessions;
  {
    MutexLock lock(mutex_);
    if (shut_down_ || draining_) return;
    draining_ = true;
    for (auto& [id, s] : sessions_) {
      if (!s->transient) sessions.push_back(s);
    }
  }
  Log(LogLevel::kInfo, absl::StrCat("draining: ", sessions.size(),
                                    " session(s) told to move within ", deadline.count(), " ms"));
  for (auto& s : sessions) s->sink->OnDraining(deadline);
}

void EngineImpl::Shutdown() {
  std::vector<std::shared_ptr<SessionRecord>> sessions;
  {
    MutexLock lock(mutex_);
    if (shut_down_) return;
    shut_down_ = true;
    for (auto& [id, s] : sessions_) {
      s->stop.request_stop();  // a frame in progress ends within a step
      sessions.push_back(s);
    }
  }
  if (!render_thread_) return;
  // Free every GL object on the thread that owns the context.
  render_thread_->Stop([this] {
    render_role_.Assert();
    // Every job is asked to stop before any solver is destroyed: one
    // solver's destructor waits for its job, which may be queued on the
    // pool behind another's.
    CancelBackgroundJobs();
    views_.clear();
    gpu_scenes_.clear();
    retiring_.clear();
    passes_.reset();
    timer_ = gl::StageTimer();
    glFinish();
  });
  for (auto& s : sessions) s->sink->OnSessionFailed(Unavailable());
  MutexLock lock(mutex_);
  sessions_.clear();
  scenes_.clear();
}

EngineStats EngineImpl::stats() const {
  const auto now = FrameRate::Clock::now();
  MutexLock lock(mutex_);
  EngineStats out;
  for (const auto& [id, s] : sessions_) {
    if (s->transient) continue;
    out.sessions += 1;
    SessionStatus& status = out.session_status.emplace_back();
    status.id = id;
    status.tenant = s->config.tenant;
    status.scene = s->config.scene;
    status.solver = s->config.solver;
    status.width = s->width;
    status.height = s->height;
    status.frames = s->frames;
    status.fps = s->rate.PerSecond(now);
    status.dropped_frames = s->sink->dropped_frames();
    status.pending_updates = uint32_t(s->pending.size());
    status.last_update_seq = s->last_seq;
    status.at_rest = s->resting.load();
    out.active_sessions += status.at_rest ? 0 : 1;
  }
  out.render_busy_ratio = render_thread_ ? render_thread_->busy_ratio() : 0.0;
  out.max_render_busy = options_.max_render_busy;
  out.draining = draining_;
  out.scenes = uint32_t(scenes_.size());
  out.frames_rendered = frames_rendered_.load();
  out.keep_alives_at_rest = keep_alives_at_rest_.load();
  out.fair_share_deferrals = fair_share_deferrals_.load();
  for (const auto& [id, s] : scenes_) {
    out.scene_ids.push_back(id);
    out.scene_tenants.push_back(s->tenant);
  }
  out.gl_object_bytes = gl_object_bytes_.load();
  out.retiring_solvers = retiring_solvers_.load();
  out.background_jobs = background_jobs_.load();
  out.gpu_memory_total_bytes = gpu_memory_total_.load();
  out.gpu_memory_available_bytes = gpu_memory_available_.load();
  out.memory_used_bytes = accounts_.server().used();
  out.memory_limit_bytes = accounts_.server().limit();
  return out;
}

void EngineImpl::RefreshMemoryStats(bool force) {
  const auto now = Clock::now();
  if (!force && now - memory_refreshed_ < std::chrono::milliseconds(250)) return;
  memory_refreshed_ = now;
  uint64_t bytes = 0;
  uint32_t jobs = 0;
  for (const auto& [id, scene] : gpu_scenes_) {
    bytes += scene.gpu ? scene.gpu->gpu_bytes() : 0;
    for (const auto& [key, entry] : scene.solvers) {
      bytes += entry.solver ? entry.solver->gpu_bytes() : 0;
      jobs += entry.solver && entry.solver->BackgroundBusy() ? 1 : 0;
    }
  }
  for (const auto& [id, view] : views_) bytes += view.gbuffer.gpu_bytes();
  for (const auto& solver : retiring_) {
    bytes += solver->gpu_bytes();
    jobs += solver->BackgroundBusy() ? 1 : 0;
  }
  gl_object_bytes_ = bytes;
  background_jobs_ = jobs;
  retiring_solvers_ = uint32_t(retiring_.size());
  if (memory_query_ && memory_query_->supported()) {
    const gl::GpuMemoryInfo info = memory_query_->Query();
    gpu_memory_total_ = info.total_bytes;
    gpu_memory_available_ = info.available_bytes;
  }
}

std::vector<SolverDescription> EngineImpl::ListSolvers() const { return AllSolverDescriptions(); }

bool EngineImpl::CheckGpuReset() {
  GLenum reset = GL_NO_ERROR;
  const gl::InjectedReset injected = gl::TakeInjectedReset();
  if (injected != gl::InjectedReset::kNone) {
    reset = GL_GUILTY_CONTEXT_RESET;
  } else if (render_thread_->context().robust()) {
    reset = glGetGraphicsResetStatus();
  }
  if (reset == GL_NO_ERROR) return false;
  // The context is gone with every object in it: every session on this GPU
  // is affected. New calls are refused (UNAVAILABLE) from here on, health
  // answers NOT_SERVING, and every session and pending Render fails with
  // UNAVAILABLE so clients reconnect.
  gpu_lost_ = true;
  gpu_resets_ += 1;
  NotifyServing(false);
  Log(LogLevel::kError, absl::StrCat("GPU reset (0x", absl::Hex(reset),
                                     injected != gl::InjectedReset::kNone ? ", injected" : "",
                                     "): failing all sessions, recreating the context"));
  std::vector<std::shared_ptr<SessionRecord>> sessions;
  {
    MutexLock lock(mutex_);
    for (auto& [id, s] : sessions_) {
      if (!s->closed) sessions.push_back(s);
      s->closed = true;
    }
  }
  for (auto& s : sessions) {
    s->sink->OnSessionFailed(
        absl::UnavailableError("GPU reset: the render context was lost; open a new session"));
  }
  const absl::Status recovered = injected == gl::InjectedReset::kResetAndFailRecovery
                                     ? absl::InternalError("injected failure (gpu_reset_fail)")
                                     : RecoverFromGpuReset();
  if (!recovered.ok()) {
    // Nothing can render any more: exit so the orchestrator restarts us.
    Log(LogLevel::kError, absl::StrCat("GPU reset: recovery failed (", recovered.ToString(),
                                       "); exiting with status 70"));
    std::_Exit(70);
  }
  gpu_lost_ = false;
  NotifyServing(true);
  return true;
}

absl::Status EngineImpl::RecoverFromGpuReset() {
  // Every GL object belongs to the lost context: drop them (deleting names
  // of a lost context is allowed and does nothing), keeping each scene's
  // CPU state (SceneState: the import plus every update applied so far).
  // Solvers are rebuilt on their sessions' next frames; their and the
  // views' reservations are given back with them.
  views_.clear();
  CancelBackgroundJobs();
  for (auto& [id, scene] : gpu_scenes_) {
    scene.solvers.clear();
    scene.gpu.reset();
  }
  retiring_.clear();  // (waits for their jobs: their names are the lost context's)
  passes_.reset();
  timer_ = gl::StageTimer();
  memory_query_.reset();
  GS_RETURN_IF_ERROR(render_thread_->RecreateContext());
  GS_ASSIGN_OR_RETURN(ViewPasses passes, ViewPasses::Create());
  passes_ = std::make_unique<ViewPasses>(std::move(passes));
  memory_query_.emplace();
  for (auto& [id, scene] : gpu_scenes_) {
    auto uploaded = GpuScene::Upload(*scene.state);
    if (!uploaded.ok()) {
      return absl::Status(
          uploaded.status().code(),
          absl::StrCat("re-uploading scene '", id, "': ", uploaded.status().message()));
    }
    scene.gpu = std::move(uploaded).value();
  }
  RefreshMemoryStats(/*force=*/true);
  Log(LogLevel::kInfo, absl::StrCat("GPU reset: recovered (context recreated, ", gpu_scenes_.size(),
                                    " scene(s) re-uploaded)"));
  return absl::OkStatus();
}

void EngineImpl::SetServingListener(std::function<void(bool serving)> listener) {
  MutexLock lock(mutex_);
  serving_listener_ = std::move(listener);
}

void EngineImpl::NotifyServing(bool serving) {
  std::function<void(bool)> listener;
  {
    MutexLock lock(mutex_);
    listener = serving_listener_;
  }
  if (listener) listener(serving);
}

}  // namespace gistream
