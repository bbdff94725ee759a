// The render engine's domain API: scenes, sessions, updates, frames. No
// gRPC here; server/service/grpc/ translates protobuf to and from
// these types. All methods are thread-safe and never touch GL on the
// calling thread: GL work is posted to the render thread, which owns the
// context.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "scene/gltf/import_limits.h"
#include "scene/scene.h"
#include "scene/updates.h"
#include "engine/observer.h"
#include "solvers/solver_params.h"
#include "util/memory_budget.h"
#include "util/stage_timing.h"
#include "util/status.h"
#include "util/tenancy.h"

namespace gistream {

using SceneId = std::string;
using SessionId = std::string;

// kH264/kHevc: Annex-B access units; kAv1: low-overhead OBUs; one per frame
// from a per-session encoder (service/frame_encoder.h).
enum class ImageFormat { kJpeg, kPng, kExr, kH264, kHevc, kAv1 };

struct EncodingOptions {
  ImageFormat format = ImageFormat::kJpeg;
  int quality = 90;       // JPEG 1..100
  float exposure = 0.0f;  // EV stops before tone mapping (8-bit formats)
  // Video formats: target bitrate in kbit/s (0: constant quality at `crf`,
  // x264's 1..51 scale), a key frame at least every `key_frame_interval`
  // encoded frames.
  uint32_t bitrate_kbps = 0;
  int crf = 23;
  uint32_t key_frame_interval = 120;
  // libavcodec encoders to try, in order (tests pin "libx264"); empty:
  // NVENC first, then the software encoder.
  std::vector<std::string> video_encoders;
  // Send frames whose pixels did not change as full frames (default: they
  // go out without an image, see EncodedFrame::unchanged).
  bool send_unchanged = false;
};

struct EncodedFrame {
  uint64_t frame_number = 0;
  uint32_t width = 0;
  uint32_t height = 0;
  ImageFormat format = ImageFormat::kJpeg;
  std::string image;  // encoded bytes
  uint64_t scene_version = 0;
  uint64_t last_update_seq = 0;
  std::vector<StageTiming> timings;
  // The stages of the solver's table its Plan() named for this frame's
  // changes (the others are reported skipped).
  std::vector<std::string> planned_stages;
  std::vector<std::pair<std::string, double>> stats;
  std::string solver;
  double total_ms = 0.0;
  uint32_t dropped_frames = 0;  // filled in by the sink that dropped them
  bool key_frame = true;        // decodable on its own (every JPEG/PNG/EXR frame)
  // The pixels equal the last frame's: `image` is empty and the client keeps
  // showing what it has. A continuous session sends such frames only as
  // keep-alives (about once a second); an on-request one answers with them.
  bool unchanged = false;
};

// ---------------------------------------------------------------- scenes

struct SceneSource {
  // Who loads it: the scene belongs to this tenant, other tenants' calls do
  // not find its id, and a named scene is shared only among its sessions.
  TenantId tenant{kDefaultTenant};
  std::string name;               // scene in the scene directory, or
  std::string bytes;              // a glb / self-contained gltf
  std::string environment_name;   // optional, inside the scene directory, or
  std::string environment_bytes;  // optional HDR/EXR bytes
  float environment_intensity = 1.0f;
  // A copy of a named scene that no other load shares (and none finds).
  bool private_copy = false;
  // Polled between the load's stages and slices: non-OK (CANCELLED when the
  // client left, DEADLINE_EXCEEDED when its deadline passed) stops the load
  // with that code, nothing kept (scene/gltf/load_control.h). Empty: never.
  std::function<absl::Status()> stop;
};

struct NodeSummary {
  uint32_t id = 0;
  std::string name;
  int parent = -1;
  int mesh = -1;
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 scale{1.0f};
};

struct LightSummary {
  uint32_t id = 0;
  std::string name;
  LightType type = LightType::kPoint;
  uint32_t node = 0;
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};
  float inner_cone_angle = 0.0f;
  float outer_cone_angle = 0.0f;
};

struct CameraSummary {
  uint32_t id = 0;
  std::string name;
  uint32_t node = 0;
  float yfov = 0.0f;
  glm::vec3 position{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
};

struct MaterialSummary {
  uint32_t id = 0;
  std::string name;
  glm::vec4 base_color{1.0f};
  glm::vec3 emissive{0.0f};  // factor x strength
  glm::vec3 emissive_factor{0.0f};
  float emissive_strength = 1.0f;  // KHR_materials_emissive_strength
};

// One of the scene's glTF animations (AnimationUpdate plays it).
struct AnimationSummary {
  uint32_t id = 0;
  std::string name;
  float start = 0.0f;  // seconds: its first and last key
  float end = 0.0f;
};

struct SceneInfo {
  SceneId id;
  std::vector<NodeSummary> nodes;
  std::vector<LightSummary> lights;
  std::vector<CameraSummary> cameras;
  std::vector<MaterialSummary> materials;
  std::vector<AnimationSummary> animations;
  Bounds bounds;
  uint64_t triangle_count = 0;
  uint64_t vertex_count = 0;
  uint32_t emissive_triangle_count = 0;
  bool has_environment = false;
  uint64_t version = 0;
  // Primitives whose proxy cluster trees (or levels) were not built because
  // the load ran past EngineOptions::max_load_time: they draw their
  // whole-primitive levels (or the full mesh). 0 for a scene loaded before.
  uint32_t proxy_trees_skipped = 0;
  uint32_t proxy_levels_skipped = 0;
  // glTF extensions the file uses that the render ignores (Scene's).
  std::vector<std::string> ignored_extensions;
  std::vector<std::string> import_warnings;
};

// ---------------------------------------------------------------- sessions

enum class Pacing { kContinuous, kOnRequest };

struct SessionConfig {
  TenantId tenant{kDefaultTenant};  // must own `scene`
  SceneId scene;
  std::string solver = "direct";
  std::map<std::string, std::string> params;
  uint32_t width = 640;
  uint32_t height = 480;
  EncodingOptions encoding;
  Pacing pacing = Pacing::kContinuous;
  float max_fps = 0.0f;  // 0: the engine's default cap
  std::optional<CameraUpdate> camera;
  // Solver work per frame before it yields to other sessions (ms; 0: the
  // engine's default). Sliceable solvers spread longer work over frames.
  double frame_budget_ms = 0.0;
  // Samples per pixel a still view accumulates (render/refinement.h): 1
  // shades pixel centres only; 0: the engine's default
  // (EngineOptions::refine_samples).
  uint32_t refine_samples = 0;
  // The weight, in samples, of the picture kept as history when what the
  // view shows changes under the same camera (render/refinement.h), at
  // most EngineOptions::kMaxRefineHistory; 0 keeps none; unset:
  // EngineOptions::refine_history. Not in the gRPC API yet.
  std::optional<uint32_t> refine_history;
  // The weight, in samples, of the picture shown before a camera move,
  // reprojected into the new view (render/refinement.h), at most
  // EngineOptions::kMaxRefineHistory; 0: none; unset:
  // EngineOptions::refine_reproject. Not in the gRPC API yet.
  std::optional<uint32_t> refine_reproject;
};

struct SessionOpenInfo {
  SessionId id;
  SceneId scene;
  std::string solver;
  std::map<std::string, std::string> params;  // defaults filled in
};

// Receives a session's output. Called on the render thread: must not block
// and must not call back into the Engine. It may still be called briefly
// after CloseSession returns, so an implementation that outlives its
// consumer must detach itself (e.g. a mutex-guarded pointer).
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  virtual void OnFrame(std::shared_ptr<const EncodedFrame> frame) = 0;
  virtual void OnUpdateRejected(uint64_t seq, const absl::Status& status) = 0;
  // The session cannot go on (e.g. a GPU reset); no frames follow.
  virtual void OnSessionFailed(const absl::Status& status) = 0;
  // The server is draining: the session ends within `deadline` (its client
  // should move). Frames go on until then. Must not block.
  virtual void OnDraining(std::chrono::milliseconds /*deadline*/) {}
  // Frames this sink received but replaced with newer ones before they
  // reached the client (a slow reader), so far. Read by Engine::stats() from
  // any thread: must not block.
  virtual uint64_t dropped_frames() const { return 0; }
};

// ---------------------------------------------------------------- render

struct RenderRequest {
  TenantId tenant{kDefaultTenant};  // must own `scene`
  SceneId scene;
  std::string solver = "direct";
  std::map<std::string, std::string> params;
  uint32_t width = 640;
  uint32_t height = 480;
  EncodingOptions encoding;
  std::optional<CameraUpdate> camera;
  std::vector<Update> updates;   // camera updates here change only this frame
  double frame_budget_ms = 0.0;  // per slice, as SessionConfig's (0: the default)
  uint32_t refine_samples = 0;   // as SessionConfig's: the frame's samples per pixel
  // Polled while the frame is being made: true stops the work within one
  // slice and Render returns CANCELLED (the client left, its deadline
  // passed, the server is shutting down).
  std::function<bool()> cancelled;
};

// ---------------------------------------------------------------- engine

struct EngineOptions {
  int egl_device = -1;  // -1: first hardware device, else Mesa's software one
  std::filesystem::path scene_dir = "scenes";
  ImportLimits import_limits;
  // A scene load's optional work (proxy levels and cluster trees, issue 19)
  // stops this long after the load began; the scene loads without the rest
  // (SceneInfo::proxy_trees_skipped). gistreamd --max-load-seconds.
  std::chrono::milliseconds max_load_time{60'000};
  uint32_t max_sessions = 32;
  // Admission by GPU time (issue 31): a new session is refused when the
  // render thread's busy share over the last 5 s plus one active session's
  // share (busy / active sessions) would exceed this; 0: off.
  double max_render_busy = 0.0;
  uint32_t max_scenes = 16;
  // Per-tenant limits (util/tenancy.h); a tenant not listed has none of its
  // own. Exceeding one answers RESOURCE_EXHAUSTED naming the quota.
  std::map<TenantId, TenantQuota> quotas;
  // Sessions without a client request (update, frame or key frame request)
  // and scenes unused by any session or Render for this long are freed
  // (sessions end with DEADLINE_EXCEEDED); 0: never. A continuous session
  // whose frames reach its client (none dropped) is in use.
  std::chrono::milliseconds idle_timeout{0};
  // GI solutions (solver instances) cached per scene, one per solver and
  // parameter set; beyond this the least recently used one that no open
  // session uses is dropped with its GPU memory.
  uint32_t max_solvers_per_scene = 8;
  // A solver whose complete solve is estimated over this many seconds on
  // the reference machine (solvers/work_estimate.h), divided by
  // solve_speed, is refused with RESOURCE_EXHAUSTED naming its parameters
  // before anything is built; 0: no limit (gistreamd --max-solve-seconds).
  double max_solve_seconds = 300.0;
  // How many times faster than the reference machine (2 cores, llvmpipe)
  // this server solves (gistreamd --solve-speed; 1: the reference).
  double solve_speed = 1.0;
  uint32_t max_width = 4096;
  uint32_t max_height = 4096;
  float default_max_fps = 30.0f;
  float max_fps = 240.0f;
  // Default SessionConfig::frame_budget_ms, and the budget of Render calls.
  double frame_budget_ms = 30.0;
  // Default SessionConfig::refine_samples (gistreamd --refine-samples); at
  // most kMaxRefineSamples.
  uint32_t refine_samples = 16;
  static constexpr uint32_t kMaxRefineSamples = 1024;
  // Default SessionConfig::refine_history (gistreamd --refine-history): 0,
  // off, every change restarts the picture. On the object workload the
  // history lowered the error of the first frames after a stop but raised
  // the error during the motion (docs/RESULTS.md), so it stays opt-in.
  uint32_t refine_history = 0;
  static constexpr uint32_t kMaxRefineHistory = 64;
  // gistreamd --refine-carry: a change under a still camera carries the
  // last complete picture's anti-aliasing over (render/refinement.h) when
  // refine_history is 0.
  bool refine_carry = true;
  // Default SessionConfig::refine_reproject (gistreamd --refine-reproject):
  // the frames of a camera move show the new pixel centres with the
  // picture before, reprojected, at this weight in samples.
  uint32_t refine_reproject = 4;
  // Told about every frame produced (see observer.h); may be null.
  std::shared_ptr<ServerObserver> observer;
  // The server-wide memory budget (util/memory_budget.h): decoded images
  // and scenes, solver state (estimated before it is built) and views'
  // G-buffers reserve their bytes from it; 0: DefaultMemoryLimit().
  uint64_t max_memory_bytes = 0;
  // Test-only fault injection (gl/fault_injection.h): a directory where the
  // files gpu_reset, gpu_reset_fail and gpu_oom trigger a simulated GPU
  // reset, a reset whose recovery fails, and one GL_OUT_OF_MEMORY. Empty:
  // off. gistreamd takes it from $GISTREAM_TEST_FAULT_DIR.
  std::filesystem::path test_fault_dir;
};

struct DeviceInfo {
  std::string vendor;
  std::string renderer;
  std::string version;
  std::string egl_device;  // which EGL device was picked and why
  std::string cpu_model;   // from /proc/cpuinfo, for benchmark reports
  uint32_t cpu_threads = 0;
};

// One open client session (Render calls are not listed).
struct SessionStatus {
  SessionId id;
  TenantId tenant;
  SceneId scene;
  std::string solver;
  uint32_t width = 0;  // of the last frame (the configured size before the first)
  uint32_t height = 0;
  uint64_t frames = 0;           // frames rendered for this session
  double fps = 0.0;              // frames per second over the last 5 s (or since it opened)
  uint64_t dropped_frames = 0;   // its sink's FrameSink::dropped_frames()
  uint32_t pending_updates = 0;  // queued, not yet applied
  uint64_t last_update_seq = 0;  // highest sequence number applied so far
  bool at_rest = false;          // its view rests: nothing rendered until a change
};

struct EngineStats {
  uint32_t sessions = 0;
  uint32_t scenes = 0;
  uint64_t frames_rendered = 0;
  // Keep-alive frames of views at rest: sent without rendering anything
  // (no GL work, no readback, no encode; not in frames_rendered).
  uint64_t keep_alives_at_rest = 0;
  std::vector<SceneId> scene_ids;
  std::vector<TenantId> scene_tenants;        // the owner of each of scene_ids
  std::vector<SessionStatus> session_status;  // by session id
  // Bytes held by the GL objects the engine accounts for: every scene's
  // GpuScene (vertex/index buffers, materials, textures), every cached
  // solver's main buffers and textures (Solver::gpu_bytes: shadow maps,
  // probe atlas, element/link buffers) and every view's G-buffer and
  // targets; shader programs and small uniform buffers are not counted.
  // Refreshed on the render thread after loads, unloads, closed sessions,
  // a view's first frame and (at most 4 times a second) frames.
  uint64_t gl_object_bytes = 0;
  // Dropped solvers (their scene unloaded, or evicted) kept until their
  // background job ends (counted in gl_object_bytes meanwhile).
  uint32_t retiring_solvers = 0;
  // Solvers, cached or retiring, whose background job runs on the CPU pool
  // (refreshed with gl_object_bytes).
  uint32_t background_jobs = 0;
  // What the driver reports through GL_NVX_gpu_memory_info or
  // GL_ATI_meminfo (queried with gl_object_bytes); 0 when it does not tell.
  // ATI reports no total, only what is free.
  uint64_t gpu_memory_total_bytes = 0;
  uint64_t gpu_memory_available_bytes = 0;
  // The memory budget (EngineOptions::max_memory_bytes): reserved by
  // scenes, solvers and views now, and the limit.
  uint64_t memory_used_bytes = 0;
  uint64_t memory_limit_bytes = 0;
  // Capacity (issue 31): the render thread's busy share of the last 5 s
  // (every session's GL work and readback runs there), the sessions that
  // cost render time now (open, not at rest), and the limit of
  // EngineOptions::max_render_busy (0: off).
  double render_busy_ratio = 0.0;
  uint32_t active_sessions = 0;
  // Fair share (issue 30, item 3): times a due frame waited because its
  // tenant had used more render time than another tenant with a frame due.
  // Grows only while the render thread is saturated by several tenants.
  uint64_t fair_share_deferrals = 0;
  double max_render_busy = 0.0;
  bool draining = false;  // BeginDrain: every session is told to move
};

class Engine {
 public:
  // Creates the EGL context on a new render thread. FAILED_PRECONDITION
  // when no usable EGL device / GL 4.5 context exists.
  static absl::StatusOr<std::unique_ptr<Engine>> Create(const EngineOptions& options);
  virtual ~Engine() = default;

  virtual DeviceInfo device_info() const = 0;
  virtual EngineStats stats() const = 0;
  virtual std::vector<SolverDescription> ListSolvers() const = 0;

  // Blocking (parses on the caller's thread, uploads on the render thread).
  // Scene ids are unguessable (128 random bits). Each LoadScene holds a
  // reference to the scene until UnloadScene drops it; sessions and Render
  // calls hold one while they run. The scene is freed when the last goes
  // (or, unused, after EngineOptions::idle_timeout). A named scene loaded
  // again by its tenant is the same scene (another reference).
  virtual absl::StatusOr<SceneInfo> LoadScene(const SceneSource& source) = 0;
  // Reserves the bytes of an upload the caller holds (a LoadScene request's
  // scene and environment bytes, kept until its load ends) from the
  // server's memory budget, before the load waits for a worker: uploads
  // queued together cannot pass the budget, and one that does not fit is
  // refused before it is copied or parsed (RESOURCE_EXHAUSTED naming
  // `what`). LoadScene reserves what it copies and parses itself.
  virtual absl::StatusOr<MemoryBudget::Reservation> ReserveUpload(uint64_t bytes,
                                                                  const std::string& what) = 0;
  // Drops one LoadScene reference of `tenant`'s scene `id`; NOT_FOUND for
  // an id of another tenant, as for one that does not exist.
  virtual absl::Status UnloadScene(const SceneId& id, const TenantId& tenant) = 0;
  absl::Status UnloadScene(const SceneId& id) { return UnloadScene(id, TenantId(kDefaultTenant)); }

  // Validates the config (scene id, solver, params, resolution, encoding).
  virtual absl::StatusOr<SessionOpenInfo> OpenSession(const SessionConfig& config,
                                                      std::shared_ptr<FrameSink> sink) = 0;
  // Validates the update now (ids, NaN/Inf, ranges) and queues it; it is
  // applied in order on the render thread before the session's next frame.
  virtual absl::Status PushUpdate(const SessionId& id, Update update) = 0;
  // On-request pacing: render `count` more frames.
  virtual absl::Status RequestFrames(const SessionId& id, uint32_t count) = 0;
  // The session's next frame is a key frame with its full image, changed or
  // not (a client that joins a stream or lost frames).
  virtual absl::Status RequestKeyFrame(const SessionId& id) {
    return absl::UnimplementedError(absl::StrCat("session '", id, "': key frames on request"));
  }
  // Frees the session; its sink receives nothing more once the render
  // thread has seen the close (see FrameSink).
  virtual void CloseSession(const SessionId& id) = 0;

  // Blocking: one frame for one set of updates.
  virtual absl::StatusOr<EncodedFrame> Render(const RenderRequest& request) = 0;

  // Tells every open session's sink that the server drains (OnDraining)
  // and refuses new sessions and loads (UNAVAILABLE naming the drain);
  // frames and updates of open sessions go on. Shutdown follows.
  virtual void BeginDrain(std::chrono::milliseconds /*deadline*/) {}

  // Stops accepting work, finishes the frames in flight, frees GPU memory.
  virtual void Shutdown() = 0;

  // Called (on the render thread, must not block) with false when the GPU
  // context is lost (every session and Render then fails UNAVAILABLE) and
  // with true once it is recreated and the scenes re-uploaded; the gRPC
  // server turns it into the health status.
  virtual void SetServingListener(std::function<void(bool serving)> /*listener*/) {}
};

}  // namespace gistream
