#include "engine/engine_impl.h"

#include <absl/strings/str_format.h>
#include <absl/strings/str_join.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <future>
#include <iterator>
#include <limits>
#include <random>
#include <set>
#include <thread>
#include <utility>

#include "encode/encode.h"
#include "scene/gltf/gltf_import.h"
#include "scene/gltf/image_decode.h"
#include "gl/fault_injection.h"
#include "scene/magnitude_limits.h"
#include "scene/gltf/scene_files.h"
#include "scene/gpu/scene_memory.h"
#include "scene/state/validate_update.h"
#include "engine/scene_import.h"
#include "engine/scene_info.h"
#include "solvers/registry.h"
#include "util/cpu_pool.h"
#include "util/log.h"
#include "util/user_string.h"

namespace gistream {
namespace {

using Clock = RenderThread::Clock;

// A frame's solver work may take at most this long before it yields.
constexpr double kMaxFrameBudgetMs = 10'000.0;
// How often a frame that waits on a solver's background job polls it.
constexpr auto kPollInterval = std::chrono::milliseconds(2);
// Fair share between tenants (EngineImpl::FairShareAhead): how far (ms of
// render time) a tenant may run ahead of the one that used least before it
// waits, and how much credit an idle tenant keeps.
constexpr double kFairSliceMs = 30.0;
constexpr double kFairWindowMs = 200.0;

absl::Status Unavailable() { return absl::UnavailableError("server is shutting down"); }
absl::Status Draining() {
  return absl::UnavailableError(
      "server is draining: load the scene and open the session on another");
}
absl::Status GpuLost() {
  return absl::UnavailableError(
      "GPU reset: the render context was lost; the server is recovering, try again");
}

// "prefix-" and 128 random bits in hex: ids nobody can guess or enumerate.
std::string RandomId(std::string_view prefix) {
  std::random_device random;  // the kernel's CSPRNG (getrandom) on Linux
  std::string id = absl::StrCat(absl::string_view(prefix.data(), prefix.size()), "-");
  for (int i = 0; i < 4; ++i) absl::StrAppend(&id, absl::Hex(random(), absl::kZeroPad8));
  return id;
}

// How far a quota would be exceeded, as the message of RESOURCE_EXHAUSTED.
absl::Status QuotaExceeded(const TenantId& tenant, std::string_view quota, uint64_t used,
                           uint64_t adding, uint64_t limit) {
  return absl::ResourceExhaustedError(
      absl::StrCat("quota ", absl::string_view(quota.data(), quota.size()), " of tenant '", tenant,
                   "': ", used, " held + ", adding, " exceeds its limit of ", limit));
}

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

bool AnyAnimationPlaying(const SceneState& state) {
  return std::any_of(state.animations().begin(), state.animations().end(),
                     [](const AnimationPlayback& a) { return a.playing; });
}

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

// ---------------------------------------------------------------- scenes

absl::StatusOr<MemoryBudget::Reservation> EngineImpl::ReserveUpload(uint64_t bytes,
                                                                    const std::string& what) {
  return accounts_.server().Reserve(bytes, what);
}

namespace {

// LoadScene's request checks, before anything is read or reserved.
absl::Status CheckSceneSource(const SceneSource& source, const ImportLimits& limits) {
  if (source.name.empty() == source.bytes.empty()) {
    return absl::InvalidArgumentError("source: give exactly one of name or gltf bytes");
  }
  if (source.bytes.size() > limits.max_scene_bytes) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "gltf: ", source.bytes.size(), " bytes exceed the limit of ", limits.max_scene_bytes));
  }
  if (!std::isfinite(source.environment_intensity) || source.environment_intensity < 0.0f) {
    return absl::InvalidArgumentError(absl::StrCat(
        "environment_intensity: ", source.environment_intensity, " must be finite and >= 0"));
  }
  return absl::OkStatus();
}

bool HasEnvironment(const SceneSource& source) {
  return !source.environment_name.empty() || !source.environment_bytes.empty();
}

// A named scene loaded twice by one tenant is the same scene (its state
// shared among that tenant's sessions, never with another tenant's):
// loads by name without an environment or a private copy.
bool SharesByName(const SceneSource& source) {
  return !source.name.empty() && !HasEnvironment(source) && !source.private_copy;
}

}  // namespace

// LoadScene, step by step: the request's checks; a load of a name this
// tenant has (or is loading) joins it; else the import on this thread
// (parse, validate, decode: nothing reaches the GPU before it has
// passed), the scene's memory reserved, its record registered, and the
// upload on the render thread.
absl::StatusOr<SceneInfo> EngineImpl::LoadScene(const SceneSource& source) {
  GS_RETURN_IF_ERROR(CheckSceneSource(source, options_.import_limits));
  const CpuTenantScope cpu_tenant(source.tenant);  // the import's loops (util/cpu_pool.h)
  // What the import parsed and decoded is freed by the time this returns
  // (the upload soon after, with its request): the heap is trimmed then.
  struct TrimHeapAfter {
    EngineImpl* engine;
    ~TrimHeapAfter() { engine->RequestHeapTrim(); }
  } trim_heap_after{this};
  NameClaim claim(*this, source.tenant + "\n" + source.name);
  if (SharesByName(source)) {
    GS_ASSIGN_OR_RETURN(std::optional<SceneInfo> joined, JoinNamedLoad(source, claim));
    if (joined) return *std::move(joined);
  }
  // What the import reads and decodes is reserved before it is decoded,
  // and held until the scene itself is.
  ImportMemory transient(accounts_.server());
  GS_ASSIGN_OR_RETURN(ImportedScene imported,
                      ImportSceneSource(source, options_.scene_dir, options_.import_limits,
                                        options_.max_load_time, transient));
  auto record = std::make_shared<SceneRecord>();
  record->tenant = source.tenant;
  record->upload_bytes = source.bytes.size() + source.environment_bytes.size();
  record->loads = 1;
  record->last_used = Clock::now();
  record->source_name = SharesByName(source) ? source.name : "";
  record->scene = std::make_shared<const Scene>(std::move(imported.scene));
  record->light_instances = uint32_t(LightInstanceNodes(*record->scene).size());
  // The files and the parser's copies are gone and the decoded images are
  // the scene's now: its own reservation (CPU copy and GPU upload, held by
  // its GPU record until the scene is freed) takes over from the import's.
  transient.Release();
  const SceneBytes scene_bytes = CountSceneBytes(*record->scene);
  GS_ASSIGN_OR_RETURN(
      MemoryBudget::Reservation memory,
      accounts_.server().Reserve(
          scene_bytes.total(),
          absl::StrCat("scene: its geometry and images (", FormatBytes(scene_bytes.cpu), " CPU, ",
                       FormatBytes(scene_bytes.gpu), " GPU)")));
  GS_RETURN_IF_ERROR(RegisterScene(source, record));
  absl::StatusOr<SceneInfo> info = render_thread_->Call<absl::StatusOr<SceneInfo>>(
      [this, record, memory = std::make_shared<MemoryBudget::Reservation>(std::move(memory))] {
        render_role_.Assert();
        return UploadScene(*record, std::move(*memory));
      },
      Unavailable());
  if (!info.ok()) {
    MutexLock lock(mutex_);
    scenes_.erase(record->id);
    return info;
  }
  info->proxy_trees_skipped = imported.proxies.trees_skipped;
  info->proxy_levels_skipped = imported.proxies.levels_skipped;
  return info;
}

EngineImpl::NameClaim::~NameClaim() {
  if (!leading_) return;
  {
    MutexLock lock(engine_.mutex_);
    engine_.loading_.erase(key_);
  }
  leading_->set_value();
}

absl::StatusOr<std::optional<SceneInfo>> EngineImpl::JoinNamedLoad(const SceneSource& source,
                                                                   NameClaim& claim) {
  std::shared_ptr<SceneRecord> existing;
  std::shared_future<void> other_load;
  {
    MutexLock lock(mutex_);
    if (shut_down_) return Unavailable();
    if (draining_) return Draining();
    // A load of this name in flight first: its record is registered before
    // its upload has run, so joining the record then could find no GPU
    // scene yet (a spurious ABORTED, seen under ASan with 12 concurrent loads).
    if (auto it = loading_.find(claim.key_); it != loading_.end()) {
      other_load = it->second;
    } else {
      for (auto& [id, record] : scenes_) {
        if (record->source_name == source.name && record->tenant == source.tenant) {
          existing = record;
        }
      }
      if (existing) {
        existing->loads += 1;
        existing->last_used = Clock::now();
      } else {
        claim.leading_ = std::make_shared<std::promise<void>>();
        loading_[claim.key_] = claim.leading_->get_future().share();
      }
    }
  }
  if (other_load.valid()) {
    // Loads of one name at the same moment are one load (issue 30): wait
    // for the first (polling the caller's stop), then take the scene it
    // made, or load it here if it failed.
    while (other_load.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
      if (source.stop) GS_RETURN_IF_ERROR(source.stop());
    }
    return LoadScene(source);
  }
  if (!existing) return std::nullopt;  // this call leads: it loads the name
  // Its upload may still be queued (this job runs after it), or may have
  // failed, or the scene may have been unloaded since.
  absl::StatusOr<std::optional<SceneInfo>> joined =
      render_thread_->Call<absl::StatusOr<std::optional<SceneInfo>>>(
          [this, existing]() -> absl::StatusOr<std::optional<SceneInfo>> {
            render_role_.Assert();
            auto it = gpu_scenes_.find(existing->id);
            if (it == gpu_scenes_.end()) {
              return absl::AbortedError(
                  absl::StrCat("name: scene '", Echo(existing->id),
                               "' was unloaded or failed to load meanwhile; load it again"));
            }
            return DescribeScene(existing->id, *it->second.state);
          },
          Unavailable());
  if (!joined.ok()) {
    // The caller holds nothing: give back the hold taken above.
    MutexLock lock(mutex_);
    if (existing->loads > 0) existing->loads -= 1;
  }
  return joined;
}

absl::Status EngineImpl::RegisterScene(const SceneSource& source,
                                       const std::shared_ptr<SceneRecord>& record) {
  MutexLock lock(mutex_);
  if (shut_down_) return Unavailable();
  if (draining_) return Draining();
  if (gpu_lost_) return GpuLost();
  if (scenes_.size() >= options_.max_scenes) {
    return absl::ResourceExhaustedError(absl::StrCat("scenes: the server holds ", scenes_.size(),
                                                     " scenes, the limit (--max-scenes)"));
  }
  GS_RETURN_IF_ERROR(CheckSceneQuotaLocked(record->tenant, record->upload_bytes));
  record->id = RandomId(source.name.empty() ? "upload" : source.name);
  scenes_[record->id] = record;
  return absl::OkStatus();
}

absl::StatusOr<SceneInfo> EngineImpl::UploadScene(const SceneRecord& record,
                                                  MemoryBudget::Reservation memory) {
  {
    // An UnloadScene of this id (listed by stats() while it loads) may
    // have come first: its GPU copy would then never be freed.
    MutexLock lock(mutex_);
    if (scenes_.count(record.id) == 0) {
      return absl::AbortedError(
          absl::StrCat("scene_id: '", Echo(record.id), "' was unloaded while it loaded"));
    }
  }
  GpuSceneRecord gpu;
  gpu.memory.server = std::move(memory);
  gpu.tenant = record.tenant;
  gpu.state = std::make_unique<SceneState>(record.scene);
  GS_ASSIGN_OR_RETURN(gpu.gpu, GpuScene::Upload(*gpu.state));
  // The tenant's gpu_bytes quota counts the upload as measured, with its
  // solvers' estimates and its views (MemoryAccounts).
  GS_ASSIGN_OR_RETURN(
      gpu.memory.tenant_gpu,
      accounts_.ReserveTenantGpu(record.tenant, gpu.gpu->gpu_bytes(), "scene: its GPU upload"));
  SceneInfo described = DescribeScene(record.id, *gpu.state);
  gpu_scenes_[record.id] = std::move(gpu);
  RefreshMemoryStats(/*force=*/true);
  return described;
}

absl::Status EngineImpl::UnloadScene(const SceneId& id, const TenantId& tenant) {
  MutexLock lock(mutex_);
  if (shut_down_) return Unavailable();
  GS_ASSIGN_OR_RETURN(std::shared_ptr<SceneRecord> scene, FindSceneLocked(tenant, id));
  if (scene->loads == 0) {
    return absl::FailedPreconditionError(
        absl::StrCat("scene_id: scene '", Echo(id), "' was unloaded already; it is freed when its ",
                     scene->sessions, " session(s) and render(s) end"));
  }
  scene->loads -= 1;
  if (DropIfUnreferencedLocked(scene)) {
    Log(LogLevel::kInfo, {"", id}, "unloaded");
  } else {
    Log(LogLevel::kInfo, {"", id},
        absl::StrCat("unload: still held by ", scene->loads, " load(s) and ", scene->sessions,
                     " session(s)/render(s)"));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::shared_ptr<EngineImpl::SceneRecord>> EngineImpl::FindSceneLocked(
    const TenantId& tenant, const SceneId& id) const {
  auto it = scenes_.find(id);
  // Another tenant's scene is answered as one that does not exist.
  if (it == scenes_.end() || it->second->tenant != tenant) {
    return absl::NotFoundError(absl::StrCat("scene_id: no scene '", Echo(id), "'"));
  }
  return it->second;
}

bool EngineImpl::DropIfUnreferencedLocked(const std::shared_ptr<SceneRecord>& scene) {
  if (scene->loads > 0 || scene->sessions > 0) return false;
  auto it = scenes_.find(scene->id);
  if (it == scenes_.end() || it->second != scene) return false;
  scenes_.erase(it);
  if (!shut_down_) {
    render_thread_->Post([this, id = scene->id] {
      render_role_.Assert();
      DropGpuScene(id);
      RefreshMemoryStats(/*force=*/true);
    });
  }
  return true;
}

TenantQuota EngineImpl::QuotaOf(const TenantId& tenant) const {
  auto it = options_.quotas.find(tenant);
  return it == options_.quotas.end() ? TenantQuota{} : it->second;
}

absl::Status EngineImpl::CheckSceneQuotaLocked(const TenantId& tenant,
                                               uint64_t upload_bytes) const {
  const TenantQuota quota = QuotaOf(tenant);
  uint32_t scenes = 0;
  uint64_t uploaded = 0;
  for (const auto& [id, s] : scenes_) {
    if (s->tenant != tenant) continue;
    scenes += 1;
    uploaded += s->upload_bytes;
  }
  if (quota.scenes > 0 && scenes + 1 > quota.scenes) {
    return QuotaExceeded(tenant, "scenes", scenes, 1, quota.scenes);
  }
  if (quota.upload_bytes > 0 && uploaded + upload_bytes > quota.upload_bytes) {
    return QuotaExceeded(tenant, "upload_bytes", uploaded, upload_bytes, quota.upload_bytes);
  }
  return absl::OkStatus();
}

// ---------------------------------------------------------------- sessions

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

// ---------------------------------------------------------------- render thread

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
  const std::optional<Refinement::Sample> sample = view.refinement.Next(
      {state.version(), view.camera_version, entry.solver.get(), view.camera.width,
       view.camera.height, entry.solver->UpdateComplete()},
      draw.refine_target, session.config.refine_history.value_or(options_.refine_history),
      options_.refine_carry, session.config.refine_reproject.value_or(options_.refine_reproject));
  if (!sample) {
    // No change since the picture was complete, so the solver's plan is
    // its changeless one, all of it shading, none of it run.
    if (view.carry.empty()) view.plan.clear();
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
