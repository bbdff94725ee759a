// Engine implementation: bookkeeping of scenes and sessions on the calling
// threads (under one mutex), every GL object on the render thread. Which
// thread owns what is stated as clang thread-safety annotations: fields
// ABSL_GUARDED_BY(mutex_) need the mutex, fields ABSL_GUARDED_BY(render_role_)
// belong to the render thread (util/thread_role.h), and -Wthread-safety
// (clang builds, CI's sanitizer trees) checks every access.
#pragma once

#include <atomic>
#include <deque>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <stop_token>
#include <string>
#include <unordered_map>

#include "absl/base/thread_annotations.h"
#include "gl/memory_info.h"
#include "gl/stage_timer.h"
#include "render/camera.h"
#include "render/gbuffer.h"
#include "render/refinement.h"
#include "solvers/moved_bounds.h"
#include "render/view_passes.h"
#include "scene/gpu/gpu_scene.h"
#include "scene/state/scene_state.h"
#include "engine/engine.h"
#include "engine/frame_encoder.h"
#include "engine/frame_rate.h"
#include "engine/render_thread.h"
#include "solvers/solver.h"
#include "util/heap_trim.h"
#include "util/memory_accounts.h"
#include "util/mutex.h"
#include "util/thread_role.h"

namespace gistream {

class EngineImpl final : public Engine {
 public:
  explicit EngineImpl(const EngineOptions& options)
      : options_(options), accounts_(options.max_memory_bytes, options.quotas) {}
  ~EngineImpl() override;
  absl::Status Start();

  DeviceInfo device_info() const override { return device_; }
  EngineStats stats() const override ABSL_LOCKS_EXCLUDED(mutex_);
  std::vector<SolverDescription> ListSolvers() const override;
  absl::StatusOr<SceneInfo> LoadScene(const SceneSource& source) override
      ABSL_LOCKS_EXCLUDED(mutex_);
  absl::StatusOr<MemoryBudget::Reservation> ReserveUpload(uint64_t bytes,
                                                          const std::string& what) override;
  using Engine::UnloadScene;
  absl::Status UnloadScene(const SceneId& id, const TenantId& tenant) override
      ABSL_LOCKS_EXCLUDED(mutex_);
  absl::StatusOr<SessionOpenInfo> OpenSession(const SessionConfig& config,
                                              std::shared_ptr<FrameSink> sink) override
      ABSL_LOCKS_EXCLUDED(mutex_);
  absl::Status PushUpdate(const SessionId& id, Update update) override ABSL_LOCKS_EXCLUDED(mutex_);
  absl::Status RequestFrames(const SessionId& id, uint32_t count) override
      ABSL_LOCKS_EXCLUDED(mutex_);
  absl::Status RequestKeyFrame(const SessionId& id) override ABSL_LOCKS_EXCLUDED(mutex_);
  void CloseSession(const SessionId& id) override ABSL_LOCKS_EXCLUDED(mutex_);
  absl::StatusOr<EncodedFrame> Render(const RenderRequest& request) override
      ABSL_LOCKS_EXCLUDED(mutex_);
  void BeginDrain(std::chrono::milliseconds deadline) override ABSL_LOCKS_EXCLUDED(mutex_);
  void Shutdown() override ABSL_LOCKS_EXCLUDED(mutex_);
  void SetServingListener(std::function<void(bool serving)> listener) override
      ABSL_LOCKS_EXCLUDED(mutex_);

 private:
  // Guards the scene and session maps, and the record fields marked
  // `mutex-guarded` below (fields of nested records, which the analysis
  // cannot tie to this mutex).
  mutable Mutex mutex_;
  // The render thread, which owns the GL context and every field below
  // marked ABSL_GUARDED_BY(render_role_).
  ThreadRole render_role_{"render thread"};

  // Shared between threads; fields after `mutex-guarded` need mutex_.
  struct SceneRecord {
    SceneId id;
    TenantId tenant;          // the owner; other tenants do not find `id`
    std::string source_name;  // scene-directory name, "" when uploaded
    std::shared_ptr<const Scene> scene;
    uint32_t light_instances = 0;
    uint64_t upload_bytes = 0;  // glTF and environment bytes sent by the client
    // mutex-guarded: the references that keep the scene (engine.h).
    int sessions = 0;                             // open sessions and Render calls on it
    int loads = 0;                                // LoadScene calls not yet undone by UnloadScene
    RenderThread::Clock::time_point last_used{};  // for idle_timeout
  };
  struct SessionRecord {
    SessionId id;
    SessionConfig config;
    ParamSet params;
    std::string solver_key;
    std::shared_ptr<SceneRecord> scene;
    std::shared_ptr<FrameSink> sink;
    bool transient = false;  // a Render() call, not a client session
    // Requested when the session closes (its client left, a Render's
    // deadline passed) or the server stops: its frame's long loops end
    // within a step (SolverContext::stop).
    std::stop_source stop;
    // mutex-guarded:
    std::deque<Update> pending;
    uint32_t requested = 0;
    bool key_frame_requested = false;
    bool closed = false;
    RenderThread::Clock::time_point last_request{};  // the client's, for idle_timeout
    // What ExpireIdle saw last: a continuous session whose frames reach its
    // client (more frames, no more drops) is not idle.
    uint64_t idle_seen_frames = 0;
    uint64_t idle_seen_dropped = 0;
    // At rest (render thread writes; stats() reads): no frames rendered
    // until something changes.
    std::atomic<bool> resting{false};
    // For stats(), updated after each frame (mutex-guarded).
    uint64_t frames = 0;
    uint64_t last_seq = 0;
    uint32_t width = 0, height = 0;
    mutable FrameRate rate;  // stats() prunes it
  };

  // Render-thread-only state.
  struct SolverEntry {
    std::unique_ptr<Solver> solver;
    uint64_t version = 0;
    bool fresh = true;
    uint64_t last_used = 0;         // solver_clock_ at its last frame
    MemoryCharge memory;            // its estimate, held while it lives
    double solve_estimate_s = 0.0;  // its complete solve, reference seconds
  };
  struct GpuSceneRecord {
    TenantId tenant;
    std::unique_ptr<SceneState> state;
    std::unique_ptr<GpuScene> gpu;
    std::map<std::string, SolverEntry> solvers;  // by solver_key
    // The scene's CPU copy and GPU upload (estimated before it), and the
    // upload's measured GPU bytes in the tenant's gpu_bytes quota.
    MemoryCharge memory;
    // The scene's animation clock: when its playing animations last
    // advanced (SceneState::Advance, by the time between frames).
    std::optional<RenderThread::Clock::time_point> animation_tick;
  };
  // Drops least recently used solvers of `scene` beyond
  // options_.max_solvers_per_scene, sparing `keep` and those of open
  // sessions on `owner`. Render thread.
  void EvictIdleSolvers(GpuSceneRecord& scene, const SceneRecord* owner, const std::string& keep)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_) ABSL_LOCKS_EXCLUDED(mutex_);
  // Destroys a dropped solver now, or, while a background job of it still
  // runs (Solver::BackgroundBusy), keeps it in retiring_ until the job
  // ends (asked to stop: Solver::CancelBackground, so within a step): its
  // destructor would wait for the job on the render thread. ReapRetired (every Tick) destroys those
  // whose jobs ended. Render thread.
  void Retire(std::unique_ptr<Solver> solver) ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  void ReapRetired() ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // Asks every solver's background job to stop (shutdown, a lost context).
  void CancelBackgroundJobs() ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // Drops scene `id`'s GPU record, its solvers through Retire.
  void DropGpuScene(const SceneId& id) ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // Asks the render thread to return freed heap to the system soon
  // (heap_trimmer_): after a load, whatever its outcome. Any thread.
  void RequestHeapTrim();
  HeapTrimmer heap_trimmer_ ABSL_GUARDED_BY(render_role_);
  std::vector<std::unique_ptr<Solver>> retiring_ ABSL_GUARDED_BY(render_role_);
  uint64_t solver_clock_ ABSL_GUARDED_BY(render_role_) = 0;
  struct ViewRecord {
    ViewCamera camera;
    GBuffer gbuffer;
    uint64_t frame_number = 0;
    uint64_t last_seq = 0;
    bool camera_changed = true;
    uint64_t camera_version = 0;  // camera changes so far (the refinement's key)
    // The view's jittered samples (render/refinement.h), and the transforms
    // of the picture it shows (what moved since, for the history).
    Refinement refinement;
    // The camera the picture in the HDR target was shaded from, and the
    // one the reprojected picture was (render/refinement.h, `reproject`).
    glm::mat4 shown_view_projection{1.0f}, reproject_view_projection{1.0f};
    glm::vec3 shown_eye{0.0f}, reproject_eye{0.0f};
    MovedBounds shown_transforms;
    // The solver's stats after the slice that shaded sample 0: a frame
    // requested on its own reports its solve, not its last refinement
    // slice's no-op update.
    SolverStats solve_stats;
    bool initialized = false;  // camera set from the config
    // Timings of the slices of a frame still in progress (a sliced solver's
    // Render), summed into the frame that completes it.
    std::vector<StageTiming> carry;
    double carry_ms = 0.0;
    std::vector<std::string> plan;              // the solver's plan, over the frame's slices
    RenderThread::Clock::time_point poll_at{};  // next poll of a pending update
    RenderThread::Clock::time_point next_due{};
    // Set by Tick before each frame: no other session had a frame due, so
    // this frame's sliced work may use more of a slow cap's interval
    // (EngineImpl::FrameBudgetMs).
    bool alone = false;
    FrameEncoder encoder;  // image/video encoding, unchanged-frame detection
    // At rest (continuous sessions): the last frame showed the finished
    // picture of this scene version and solver and equalled the one before.
    // Until something changes, the view renders nothing; keep-alives repeat
    // `frame` without an image (EngineImpl::StillAtRest, SendKeepAlive).
    struct Rest {
      uint64_t scene_version = 0;
      const Solver* solver = nullptr;
      EncodedFrame frame;  // the last frame's header, no image
    };
    std::optional<Rest> rest;
    // Set by ProduceFrame: this frame changed nothing and left no work.
    bool settled = false;
    // The last camera change and scene change this view showed: when, and
    // its frame number then (frame stats *_since_*_change).
    struct Since {
      RenderThread::Clock::time_point time{};
      uint64_t frame = 0;
    };
    Since camera_since, scene_since;
    uint64_t scene_version_seen = 0;
    // Its G-buffer, readback and encoder buffers at memory_width x
    // memory_height (ReserveView).
    MemoryCharge memory;
    uint32_t memory_width = 0, memory_height = 0;
  };

  // LoadScene's steps. A named load's claim on its name (loading_): when
  // this call leads the load of the name, the claim ends it on return,
  // whatever the outcome, and wakes the loads that wait for it.
  class NameClaim {
   public:
    NameClaim(EngineImpl& engine, std::string key) : engine_(engine), key_(std::move(key)) {}
    ~NameClaim() ABSL_LOCKS_EXCLUDED(engine_.mutex_);
    NameClaim(const NameClaim&) = delete;
    NameClaim& operator=(const NameClaim&) = delete;

   private:
    friend class EngineImpl;
    EngineImpl& engine_;
    const std::string key_;                        // tenant + "\n" + name
    std::shared_ptr<std::promise<void>> leading_;  // set when this call loads the name
  };
  // The tenant's scene of that name, described, when it has one (or one
  // loaded meanwhile by a concurrent load of the name, which this waits
  // for); nullopt when this call is to load it (`claim` then leads).
  absl::StatusOr<std::optional<SceneInfo>> JoinNamedLoad(const SceneSource& source,
                                                         NameClaim& claim)
      ABSL_LOCKS_EXCLUDED(mutex_);
  // Gives an imported scene's record its id and a place in scenes_, within
  // the server's and the tenant's scene limits.
  absl::Status RegisterScene(const SceneSource& source, const std::shared_ptr<SceneRecord>& record)
      ABSL_LOCKS_EXCLUDED(mutex_);
  // The scene's GPU copy, holding `memory` (its reservation) and the
  // tenant's GPU quota; ABORTED when it was unloaded while it loaded.
  absl::StatusOr<SceneInfo> UploadScene(const SceneRecord& record, MemoryBudget::Reservation memory)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_) ABSL_LOCKS_EXCLUDED(mutex_);

  // RESOURCE_EXHAUSTED when one more active session would push the render
  // thread past EngineOptions::max_render_busy. Needs mutex_.
  absl::Status AdmitByRenderTimeLocked() const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  absl::StatusOr<std::shared_ptr<SessionRecord>> CreateSession(const SessionConfig& config,
                                                               std::shared_ptr<FrameSink> sink,
                                                               bool transient)
      ABSL_LOCKS_EXCLUDED(mutex_);
  absl::Status ValidateConfig(const SessionConfig& config) const;
  // `tenant`'s scene `id`, or NOT_FOUND (also for another tenant's id).
  absl::StatusOr<std::shared_ptr<SceneRecord>> FindSceneLocked(const TenantId& tenant,
                                                               const SceneId& id) const
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  // Forgets `scene` when nothing references it any more and frees its GPU
  // copy on the render thread; true when it did.
  bool DropIfUnreferencedLocked(const std::shared_ptr<SceneRecord>& scene)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  TenantQuota QuotaOf(const TenantId& tenant) const;
  // Checks `tenant`'s scene quotas for one more scene of `upload_bytes`.
  absl::Status CheckSceneQuotaLocked(const TenantId& tenant, uint64_t upload_bytes) const
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  // Fair share of the render thread between tenants (issue 30, item 3):
  // each tenant's render time so far is in tenant_render_ms_. A session
  // with a frame due whose tenant is more than kFairSliceMs ahead of the least render time
  // among the tenants with a frame due (FairShareWanting, at the start of
  // each Tick) waits (FairShareAhead), so a saturated thread is shared per
  // tenant, not per session: a tenant with four streams gets what one with
  // one gets. Work-conserving: a tenant alone, or the one furthest behind,
  // never waits. Sessions within a tenant keep Tick's round robin.
  // FairShareWanting also forgets tenants with no session and limits an
  // idle tenant's credit to kFairWindowMs.
  struct FrameDemand {
    std::vector<TenantId> tenants;  // with a frame due now
    std::set<SessionId> sessions;   // whose frame is due now
  };
  FrameDemand FairShareWanting(const std::vector<std::shared_ptr<SessionRecord>>& order,
                               RenderThread::Clock::time_point now)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_) ABSL_LOCKS_EXCLUDED(mutex_);
  bool FairShareAhead(const TenantId& tenant, const std::vector<TenantId>& wanting)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  std::unordered_map<TenantId, double> tenant_render_ms_ ABSL_GUARDED_BY(render_role_);
  std::atomic<uint64_t> fair_share_deferrals_{0};

  // Ends sessions and frees scenes idle for options_.idle_timeout. Render thread.
  void ExpireIdle() ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_) ABSL_LOCKS_EXCLUDED(mutex_);

  // Render thread.
  // Whether `session`'s view is due for a frame now (an on-request frame
  // is then taken from its count; a resting view with an update or a key
  // frame request wakes up), and when it next could be (into `next`);
  // nullopt for a closed session.
  std::optional<bool> TakeTurn(SessionRecord& session, ViewRecord& view,
                               RenderThread::Clock::time_point& next)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_) ABSL_LOCKS_EXCLUDED(mutex_);
  RenderThread::Clock::time_point Tick() ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_)
      ABSL_LOCKS_EXCLUDED(mutex_);
  void RenderFrame(SessionRecord& session, ViewRecord& view)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_) ABSL_LOCKS_EXCLUDED(mutex_);
  // Samples per pixel `session`'s view accumulates when still: its
  // refine_samples (or the default); 1 for a solver that does not shade
  // from the G-buffer (pathtrace refines itself) and while an animation
  // plays (no two frames show the same state).
  uint32_t RefineTarget(const SessionRecord& session, const Solver& solver,
                        const SceneState& state) const ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // Whether `view`, at rest, still shows the finished picture: the same
  // scene version and solver, nothing animating (session updates and key
  // frame requests are checked by the caller, under the lock).
  bool StillAtRest(const SessionRecord& session, const ViewRecord& view)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // Frame stats frames_since_camera_change, ms_since_camera_change and the
  // same for the scene: set, or updated in place.
  static void SetSinceChangeStats(const ViewRecord& view, RenderThread::Clock::time_point now,
                                  std::vector<std::pair<std::string, double>>& stats);
  // A keep-alive for a view at rest: the last frame again, no image, no GL.
  void SendKeepAlive(SessionRecord& session, ViewRecord& view, RenderThread::Clock::time_point now)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_) ABSL_LOCKS_EXCLUDED(mutex_);
  // Shades refinement sample `sample` of `view` at its jitter (G-buffer,
  // the solver's final pass), adds it to the view's accumulation and shows
  // the picture (with the history a change kept, render/refinement.h).
  absl::Status ShadeSample(GpuSceneRecord& scene, SolverEntry& entry, SolverContext& ctx,
                           ViewRecord& view, const Refinement::Sample& sample,
                           uint32_t refine_target) ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);

  // One frame of `session`'s view, a pipeline of named steps:
  // ApplyUpdates (stage apply_updates), ReserveView, DeformScene (deform),
  // AcquireSolver, PlanAndSolve (the solver's Plan and Update: its
  // stages), Draw (the G-buffer and the solver's final pass per
  // refinement sample, ShadeSample), ReadBack (readback), EncodeFrame
  // (encode) and Publish (the frame's timings, plan and stats). Null (no
  // frame yet) when a frame requested on its own is not complete: the
  // slice's timings are carried to the frame that completes it
  // (CarrySlice).
  absl::StatusOr<std::shared_ptr<EncodedFrame>> ProduceFrame(SessionRecord& session,
                                                             ViewRecord& view,
                                                             std::deque<Update> updates)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // The solver's work budget for this frame: the session's frame_budget_ms
  // when it set one, else the engine's default; a continuous session
  // capped slowly that is alone with a frame due (view.alone) may use up
  // to half its frame interval (at most 3x the default), so a sliced solve catches up in about the
  // time it takes solved at once instead of 1 / (budget x fps) times that
  // (issue 27: sh_probes' probes, 30 ms a frame at 10 fps, took 8 s to
  // finish after an interaction where a full solve takes 2 s).
  double FrameBudgetMs(const SessionRecord& session, const ViewRecord& view) const
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // Poses skinned and morphed meshes once per scene version (stage deform).
  void DeformScene(GpuSceneRecord& scene) ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // The session's solver on `scene`, built (within the memory budget,
  // evicting idle ones) when it has none.
  absl::StatusOr<SolverEntry*> AcquireSolver(const SessionRecord& session, GpuSceneRecord& scene)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // The solver's Plan for the scene's changes since it last ran (added to
  // the view's plan, reported against the stages run) and its Update; the
  // changes it saw.
  absl::StatusOr<ChangeMask> PlanAndSolve(ViewRecord& view, SolverEntry& entry, SolverContext& ctx)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // Keeps an incomplete frame's slice timings in the view; returns null.
  std::shared_ptr<EncodedFrame> CarrySlice(ViewRecord& view, RenderThread::Clock::time_point start)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // What the draw step of a frame needs beside the view.
  struct FrameDraw {
    uint32_t refine_target = 1;  // RefineTarget
    bool no_updates = true;      // the frame applied no update
    RenderThread::Clock::time_point frame_start;
  };
  // Shades the view's next refinement samples (as many as the frame's
  // budget allows when it brought no update, else one), or shows the
  // finished accumulation again; the first sample shaded, nullopt when none.
  absl::StatusOr<std::optional<Refinement::Sample>> Draw(const SessionRecord& session,
                                                         ViewRecord& view, GpuSceneRecord& scene,
                                                         SolverEntry& entry, SolverContext& ctx,
                                                         const FrameDraw& draw)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // Fills the encoded frame's header: timings (with the carried slices')
  // against the plan, numbers, the solver's and the view's stats; decides
  // whether the view has settled (RenderFrame then rests it).
  void Publish(SessionRecord& session, ViewRecord& view, const GpuSceneRecord& scene,
               const SolverEntry& entry, const std::optional<Refinement::Sample>& sample,
               const FrameDraw& draw, EncodedFrame& frame)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // The view's first camera, then the updates in order: camera updates to
  // the view, the rest to the scene (those its state refuses reported to
  // the session's sink); stage apply_updates.
  void ApplyUpdates(SessionRecord& session, ViewRecord& view, GpuSceneRecord& scene,
                    const std::deque<Update>& updates) ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // The view's picture read back: float HDR for EXR, else tone-mapped
  // 8-bit. INTERNAL naming the solver and `stages()` when a pixel is NaN
  // or Inf (no such frame leaves the server).
  struct ReadPixels {
    std::vector<float> hdr;
    std::vector<uint8_t> ldr;
  };
  absl::StatusOr<ReadPixels> ReadBack(const SessionRecord& session, ViewRecord& view,
                                      const std::function<std::string()>& stages)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // Encodes `pixels` into `frame`, or marks it unchanged when they equal
  // the last frame's (unless a key frame was asked for).
  absl::Status EncodeFrame(SessionRecord& session, ViewRecord& view, const ReadPixels& pixels,
                           EncodedFrame& frame) ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_)
      ABSL_LOCKS_EXCLUDED(mutex_);
  // The view's convergence and memory stats a frame carries (issue 27).
  void AddViewStats(ViewRecord& view, const GpuSceneRecord& scene, const Solver& solver,
                    const SceneState& state, uint32_t refine_target,
                    std::vector<std::pair<std::string, double>>& stats)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // Frees a closed session's view; a solver that no open session uses any
  // more and whose background job runs is dropped, the job cancelled
  // (nobody waits for what it would deliver).
  void ReleaseSessionGpu(const SessionId& id, const SceneId& scene, const std::string& solver_key)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_) ABSL_LOCKS_EXCLUDED(mutex_);
  // Reserves `view`'s G-buffer, readback and encoder buffers for its
  // camera's size, again when that changes (a camera update resizes it).
  absl::Status ReserveView(const SessionRecord& session, const GpuSceneRecord& scene,
                           ViewRecord& view) ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // Estimates the session's solver (solvers/memory_estimate.h), reserves it
  // from accounts_ and creates it into `entry`; on failure nothing is held.
  absl::Status BuildSolver(const SessionRecord& session, const GpuSceneRecord& scene,
                           SolverEntry& entry) ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  // A lost context (or an injected reset): fails every session and Render
  // UNAVAILABLE, health NOT_SERVING, then recreates the context and
  // re-uploads every scene from its CPU state (health SERVING again); exits
  // the process (code 70) when that fails.
  // True when a reset was handled (every view, `view` of a caller too, is
  // gone).
  bool CheckGpuReset() ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_) ABSL_LOCKS_EXCLUDED(mutex_);
  absl::Status RecoverFromGpuReset() ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);
  void NotifyServing(bool serving) ABSL_LOCKS_EXCLUDED(mutex_);
  // Recomputes the GL object bytes and queries the driver's GPU memory into
  // the atomics below; unless `force`, at most every 250 ms.
  void RefreshMemoryStats(bool force) ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_);

  EngineOptions options_;
  MemoryAccounts accounts_;  // the server's budget and tenants' gpu_bytes quotas
  DeviceInfo device_;
  std::unique_ptr<RenderThread> render_thread_;

  std::map<SceneId, std::shared_ptr<SceneRecord>> scenes_ ABSL_GUARDED_BY(mutex_);
  // Named loads under way, by tenant + "\n" + name: a second load of the
  // name waits for the first (LoadScene).
  std::map<std::string, std::shared_future<void>> loading_ ABSL_GUARDED_BY(mutex_);
  std::map<SessionId, std::shared_ptr<SessionRecord>> sessions_ ABSL_GUARDED_BY(mutex_);
  bool shut_down_ ABSL_GUARDED_BY(mutex_) = false;
  bool draining_ ABSL_GUARDED_BY(mutex_) = false;  // BeginDrain: no new sessions or loads
  std::atomic<uint64_t> frames_rendered_{0};
  std::atomic<uint64_t> keep_alives_at_rest_{0};  // frames sent without rendering
  std::atomic<bool> gpu_lost_{false};
  uint64_t gpu_resets_ ABSL_GUARDED_BY(render_role_) = 0;
  bool started_ ABSL_GUARDED_BY(render_role_) = false;  // Start's job ran (render_thread_ is set)
  std::function<void(bool)> serving_listener_ ABSL_GUARDED_BY(mutex_);
  // Written by RefreshMemoryStats (render thread), read by stats().
  std::atomic<uint64_t> gl_object_bytes_{0};
  std::atomic<uint32_t> retiring_solvers_{0};
  std::atomic<uint32_t> background_jobs_{0};
  std::atomic<uint64_t> gpu_memory_total_{0};
  std::atomic<uint64_t> gpu_memory_available_{0};

  // Render thread only.
  std::unordered_map<SceneId, GpuSceneRecord> gpu_scenes_ ABSL_GUARDED_BY(render_role_);
  std::unordered_map<SessionId, ViewRecord> views_ ABSL_GUARDED_BY(render_role_);
  std::unique_ptr<ViewPasses> passes_ ABSL_GUARDED_BY(render_role_);
  gl::StageTimer timer_ ABSL_GUARDED_BY(render_role_);
  SessionId last_served_ ABSL_GUARDED_BY(render_role_);
  std::optional<gl::GpuMemoryQuery> memory_query_ ABSL_GUARDED_BY(render_role_);
  RenderThread::Clock::time_point memory_refreshed_ ABSL_GUARDED_BY(render_role_){};
};

}  // namespace gistream
