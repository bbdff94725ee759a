// EngineImpl's scenes: LoadScene step by step, shared loads by name,
// upload on the render thread, unload, quotas.
#include "engine/engine_impl.h"

#include <cmath>
#include <future>
#include <utility>

#include "engine/engine_common.h"
#include "engine/scene_import.h"
#include "engine/scene_info.h"
#include "scene/gpu/scene_memory.h"
#include "util/cpu_pool.h"
#include "util/log.h"
#include "util/user_string.h"

namespace gistream {
using namespace engine_internal;  // NOLINT(build/namespaces): engine_common.h

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

}  // namespace gistream
