#include "fake_engine.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <variant>

namespace gistream::testing {

namespace {

using Clock = std::chrono::steady_clock;

const std::set<std::string, std::less<>> kBundledScenes = {"cornell_box", "indirect_room",
                                                           "furnace", "dynamic_block"};

bool Finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::vector<SolverDescription> Solvers() {
  SolverDescription direct;
  direct.name = "direct";
  direct.description = "Direct light with shadow maps; no indirect light.";
  direct.stages = {"shadow_maps", "gbuffer", "shade"};
  direct.params = {
      {"shadow_map_size", ParamType::kInt, "1024", 64, 8192, {}, "Shadow map resolution"},
      {"ambient", ParamType::kFloat, "0", 0, 1, {}, "Constant ambient term"},
  };
  SolverDescription probes;
  probes.name = "sh_probes";
  probes.description = "Spherical-harmonics irradiance probes (Nijasure 2005).";
  probes.stages = {"rasterize_cubemaps", "render_cubemaps", "sh_project", "interpolate", "final"};
  probes.params = {
      {"grid", ParamType::kInt, "8", 2, 64, {}, "Probes per axis"},
      {"bands", ParamType::kEnum, "3", 0, 0, {"2", "3"}, "SH bands"},
  };
  return {direct, probes};
}

}  // namespace

FakeEngine::FakeEngine(const EngineOptions& options)
    : upload_budget_(options.max_memory_bytes),
      options_(options),
      thread_([this](std::stop_token stop) { FrameLoop(stop); }) {}

absl::StatusOr<MemoryBudget::Reservation> FakeEngine::ReserveUpload(uint64_t bytes,
                                                                    const std::string& what) {
  return upload_budget_.Reserve(bytes, what);
}

FakeEngine::~FakeEngine() { Shutdown(); }

DeviceInfo FakeEngine::device_info() const {
  return {"gistream", "fake engine (CPU)", "0.0", "none: fake engine", "fake CPU", 1};
}

EngineStats FakeEngine::stats() const {
  std::lock_guard lock(mutex_);
  EngineStats s;
  s.sessions = static_cast<uint32_t>(sessions_.size());
  s.scenes = static_cast<uint32_t>(scenes_.size());
  s.frames_rendered = frames_rendered_.load();
  for (const auto& [id, scene] : scenes_) s.scene_ids.push_back(id);
  const auto now = Clock::now();
  for (auto& [id, session] : sessions_) {
    SessionStatus& status = s.session_status.emplace_back();
    status.id = id;
    status.scene = session.config.scene;
    status.solver = session.config.solver;
    status.width = session.config.width;
    status.height = session.config.height;
    status.frames = session.frames;
    status.fps = session.rate.PerSecond(now);
    status.dropped_frames = session.sink->dropped_frames();
    status.pending_updates = static_cast<uint32_t>(session.pending.size());
    status.last_update_seq = session.last_update_seq;
  }
  return s;
}

std::vector<SolverDescription> FakeEngine::ListSolvers() const { return Solvers(); }

absl::StatusOr<SceneInfo> FakeEngine::LoadScene(const SceneSource& source) {
  upload_bytes_during_load_.store(
      std::max(upload_bytes_during_load_.load(), upload_budget_.used()));
  std::string name;
  if (!source.name.empty()) {
    if (!kBundledScenes.contains(source.name)) {
      return absl::NotFoundError(
          absl::StrCat("name: no scene '", source.name, "' in ", options_.scene_dir.string()));
    }
    name = source.name;
  } else {
    if (source.bytes.size() < 12 || source.bytes.compare(0, 4, "glTF") != 0) {
      return absl::InvalidArgumentError("gltf: not a binary glTF (bad magic)");
    }
    if (source.bytes.size() > options_.import_limits.max_scene_bytes) {
      return absl::ResourceExhaustedError("gltf: larger than max_scene_bytes");
    }
    name = "inline";
  }
  if (!source.environment_name.empty() && source.environment_name != "sky.hdr") {
    return absl::NotFoundError(
        absl::StrCat("environment_name: no file '", source.environment_name, "'"));
  }

  std::lock_guard lock(mutex_);
  if (shut_down_) return absl::UnavailableError("engine is shut down");
  if (scenes_.size() >= options_.max_scenes) {
    return absl::ResourceExhaustedError(
        absl::StrCat("scenes: ", scenes_.size(), " loaded, the limit is ", options_.max_scenes));
  }
  FakeScene scene;
  SceneInfo& info = scene.info;
  info.id = absl::StrCat(name, "-", next_scene_++);
  for (uint32_t i = 0; i < kNodes; ++i) {
    NodeSummary n;
    n.id = i;
    n.name = absl::StrCat("node", i);
    n.mesh = i < 2 ? static_cast<int>(i) : -1;
    n.translation = glm::vec3(static_cast<float>(i), 0.0f, 0.0f);
    info.nodes.push_back(n);
  }
  LightSummary light;
  light.name = "lamp";
  light.node = 2;
  light.intensity = 10.0f;
  light.position = glm::vec3(0.0f, 1.9f, 0.0f);
  info.lights.push_back(light);
  CameraSummary camera;
  camera.name = "cam";
  camera.yfov = 0.7f;
  camera.position = glm::vec3(0.0f, 1.0f, 4.0f);
  info.cameras.push_back(camera);
  for (uint32_t i = 0; i < kMaterials; ++i) {
    MaterialSummary m;
    m.id = i;
    m.name = absl::StrCat("material", i);
    m.base_color = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
    info.materials.push_back(m);
  }
  info.bounds.Extend(glm::vec3(-1.0f));
  info.bounds.Extend(glm::vec3(1.0f, 2.0f, 1.0f));
  info.triangle_count = 36;
  info.vertex_count = 24;
  info.has_environment = !source.environment_name.empty() || !source.environment_bytes.empty();
  info.version = scene.version;
  SceneInfo result = info;
  scenes_.emplace(result.id, std::move(scene));
  return result;
}

absl::Status FakeEngine::UnloadScene(const SceneId& id, const TenantId& /*tenant*/) {
  std::lock_guard lock(mutex_);
  if (!scenes_.contains(id))
    return absl::NotFoundError(absl::StrCat("scene_id: no scene '", id, "'"));
  for (const auto& [sid, s] : sessions_) {
    if (s.config.scene == id) {
      return absl::FailedPreconditionError(
          absl::StrCat("scene_id: scene '", id, "' is used by session ", sid));
    }
  }
  scenes_.erase(id);
  return absl::OkStatus();
}

absl::Status FakeEngine::ValidateView(const std::string& solver,
                                      const std::map<std::string, std::string>& params,
                                      uint32_t width, uint32_t height) const {
  const std::vector<SolverDescription> solvers = Solvers();
  const auto it = std::find_if(solvers.begin(), solvers.end(),
                               [&](const SolverDescription& s) { return s.name == solver; });
  if (it == solvers.end()) {
    return absl::NotFoundError(absl::StrCat("solver: unknown solver '", solver, "'"));
  }
  for (const auto& param : params) {
    const std::string& key = param.first;  // clang 14 cannot capture a structured binding
    if (std::none_of(it->params.begin(), it->params.end(),
                     [&](const ParamSpec& p) { return p.name == key; })) {
      return absl::InvalidArgumentError(
          absl::StrCat("params.", key, ": unknown parameter of solver ", solver));
    }
  }
  if (width < 1 || width > options_.max_width) {
    return absl::InvalidArgumentError(
        absl::StrCat("width: ", width, " outside 1..", options_.max_width));
  }
  if (height < 1 || height > options_.max_height) {
    return absl::InvalidArgumentError(
        absl::StrCat("height: ", height, " outside 1..", options_.max_height));
  }
  return absl::OkStatus();
}

absl::StatusOr<SessionOpenInfo> FakeEngine::OpenSession(const SessionConfig& config,
                                                        std::shared_ptr<FrameSink> sink) {
  ++opens_started_;
  {
    std::unique_lock lock(gate_mutex_);
    gate_cv_.wait(lock, [this] { return !gate_held_; });
  }
  GS_RETURN_IF_ERROR(ValidateView(config.solver, config.params, config.width, config.height));
  if (!(config.max_fps >= 0.0f) || config.max_fps > options_.max_fps) {
    return absl::InvalidArgumentError(
        absl::StrCat("continuous.max_fps: ", config.max_fps, " outside 0..", options_.max_fps));
  }
  std::lock_guard lock(mutex_);
  if (shut_down_) return absl::UnavailableError("engine is shut down");
  if (!scenes_.contains(config.scene)) {
    return absl::NotFoundError(absl::StrCat("scene_id: no scene '", config.scene, "'"));
  }
  if (sessions_.size() >= options_.max_sessions) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "sessions: ", sessions_.size(), " open, the limit is ", options_.max_sessions));
  }
  FakeSession session;
  session.id = absl::StrCat("session-", next_session_++);
  session.config = config;
  session.sink = std::move(sink);
  session.next_due = Clock::now();
  SessionOpenInfo info;
  info.id = session.id;
  info.scene = config.scene;
  info.solver = config.solver;
  for (const SolverDescription& s : Solvers()) {
    if (s.name != config.solver) continue;
    for (const ParamSpec& p : s.params) info.params[p.name] = p.default_value;
  }
  for (const auto& [k, v] : config.params) info.params[k] = v;
  applied_[session.id];
  sessions_.emplace(session.id, std::move(session));
  ++sessions_opened_;
  wake_.notify_all();
  return info;
}

void FakeEngine::HoldOpens() {
  std::lock_guard lock(gate_mutex_);
  gate_held_ = true;
}

void FakeEngine::ReleaseOpens() {
  {
    std::lock_guard lock(gate_mutex_);
    gate_held_ = false;
  }
  gate_cv_.notify_all();
}

absl::Status FakeEngine::ValidateUpdateLocked(const Update& update, absl::string_view field) const {
  if (const auto* t = std::get_if<NodeTransformUpdate>(&update.change)) {
    if (t->node >= kNodes) {
      return absl::NotFoundError(absl::StrCat(field, ".node_transform.node: no node ", t->node,
                                              " (the scene has ", kNodes, ")"));
    }
    if (!Finite(t->translation) || !Finite(t->scale)) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ".node_transform.translation: not finite"));
    }
  } else if (const auto* l = std::get_if<LightUpdate>(&update.change)) {
    if (l->light >= kLights) {
      return absl::NotFoundError(absl::StrCat(field, ".light.light: no light ", l->light));
    }
    if (l->intensity && !std::isfinite(*l->intensity)) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".light.intensity: not finite"));
    }
  }
  return absl::OkStatus();
}

absl::Status FakeEngine::PushUpdate(const SessionId& id, Update update) {
  std::lock_guard lock(mutex_);
  auto it = sessions_.find(id);
  if (it == sessions_.end()) return absl::NotFoundError(absl::StrCat("session ", id, " is closed"));
  GS_RETURN_IF_ERROR(ValidateUpdateLocked(update, "update"));
  it->second.pending.push_back(std::move(update));
  return absl::OkStatus();
}

absl::Status FakeEngine::RequestFrames(const SessionId& id, uint32_t count) {
  std::lock_guard lock(mutex_);
  auto it = sessions_.find(id);
  if (it == sessions_.end()) return absl::NotFoundError(absl::StrCat("session ", id, " is closed"));
  if (count > 1000) {
    return absl::InvalidArgumentError(absl::StrCat("request_frame.count: ", count, " > 1000"));
  }
  it->second.owed += count;
  if (it->second.owed > max_owed_.load()) max_owed_.store(it->second.owed);
  wake_.notify_all();
  return absl::OkStatus();
}

void FakeEngine::CloseSession(const SessionId& id) {
  std::lock_guard lock(mutex_);
  auto it = sessions_.find(id);
  if (it == sessions_.end()) return;
  closed_sinks_.push_back(std::move(it->second.sink));
  sessions_.erase(it);
  wake_.notify_all();
}

void FakeEngine::FailSession(const SessionId& id, absl::Status status) {
  std::lock_guard lock(mutex_);
  auto it = sessions_.find(id);
  if (it == sessions_.end()) return;
  it->second.failure = std::move(status);
  wake_.notify_all();
}

uint32_t FakeEngine::session_count() const {
  std::lock_guard lock(mutex_);
  return static_cast<uint32_t>(sessions_.size());
}

std::vector<uint64_t> FakeEngine::applied_seqs(const SessionId& id) const {
  std::lock_guard lock(mutex_);
  auto it = applied_.find(id);
  return it == applied_.end() ? std::vector<uint64_t>{} : it->second;
}

EncodedFrame FakeEngine::MakeFrameLocked(FakeSession& session, std::vector<Update>& applied,
                                         std::vector<std::pair<uint64_t, absl::Status>>& rejected) {
  const auto start = Clock::now();
  FakeScene& scene = scenes_.at(session.config.scene);
  bool any_applied = false;
  for (Update& u : session.pending) {
    if (const auto* m = std::get_if<MaterialUpdate>(&u.change); m && m->material >= kMaterials) {
      rejected.emplace_back(u.seq, absl::NotFoundError(absl::StrCat(
                                       "update.material.material: no material ", m->material)));
      continue;
    }
    if (const auto* c = std::get_if<CameraUpdate>(&u.change); c && c->width && c->height) {
      session.config.width = *c->width;
      session.config.height = *c->height;
    }
    ++scene.version;
    session.last_update_seq = u.seq;
    applied_[session.id].push_back(u.seq);
    applied.push_back(std::move(u));
    any_applied = true;
  }
  session.pending.clear();

  EncodedFrame f;
  f.frame_number = ++session.frame_number;
  f.width = session.config.width;
  f.height = session.config.height;
  f.format = session.config.encoding.format;
  f.image.assign(static_cast<size_t>(f.width) * f.height * 4, '\x80');
  f.scene_version = scene.version;
  f.last_update_seq = session.last_update_seq;
  f.timings = {
      {"apply_updates", 0.01, 0.0, !any_applied, true},
      {"shade", 0.02, 0.5, false, false},
      {"encode", 0.03, 0.0, false, true},
  };
  f.stats = {{"fake", 1.0}};
  f.solver = session.config.solver;
  f.total_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return f;
}

absl::StatusOr<EncodedFrame> FakeEngine::Render(const RenderRequest& request) {
  GS_RETURN_IF_ERROR(ValidateView(request.solver, request.params, request.width, request.height));
  std::lock_guard lock(mutex_);
  if (shut_down_) return absl::UnavailableError("engine is shut down");
  if (!scenes_.contains(request.scene)) {
    return absl::NotFoundError(absl::StrCat("scene_id: no scene '", request.scene, "'"));
  }
  for (size_t i = 0; i < request.updates.size(); ++i) {
    GS_RETURN_IF_ERROR(ValidateUpdateLocked(request.updates[i], absl::StrCat("updates[", i, "]")));
  }
  FakeSession once;
  once.id = "render";
  once.config.scene = request.scene;
  once.config.solver = request.solver;
  once.config.width = request.width;
  once.config.height = request.height;
  once.config.encoding = request.encoding;
  once.pending = request.updates;
  std::vector<Update> applied;
  std::vector<std::pair<uint64_t, absl::Status>> rejected;
  EncodedFrame frame = MakeFrameLocked(once, applied, rejected);
  applied_.erase("render");
  if (!rejected.empty()) return rejected.front().second;
  frames_rendered_.fetch_add(1);
  if (options_.observer) options_.observer->OnFrameRendered(frame);
  return frame;
}

void FakeEngine::BeginDrain(std::chrono::milliseconds deadline) {
  std::vector<std::shared_ptr<FrameSink>> sinks;
  {
    std::lock_guard lock(mutex_);
    for (auto& [id, session] : sessions_) sinks.push_back(session.sink);
  }
  for (auto& sink : sinks) sink->OnDraining(deadline);
}

void FakeEngine::Shutdown() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
  std::lock_guard lock(mutex_);
  shut_down_ = true;
  sessions_.clear();
  closed_sinks_.clear();
}

void FakeEngine::FrameLoop(std::stop_token stop) {
  struct Delivery {
    std::shared_ptr<FrameSink> sink;
    std::shared_ptr<const EncodedFrame> frame;
    std::vector<std::pair<uint64_t, absl::Status>> rejected;
    std::optional<absl::Status> failure;
  };
  while (!stop.stop_requested()) {
    std::vector<Delivery> deliveries;
    std::vector<std::shared_ptr<FrameSink>> closed;
    {
      std::unique_lock lock(mutex_);
      wake_.wait_for(lock, stop, std::chrono::milliseconds(1), [] { return false; });
      if (stop.stop_requested()) break;
      closed.swap(closed_sinks_);
      const auto now = Clock::now();
      for (auto& [id, s] : sessions_) {
        if (s.failed) continue;
        if (!s.failure.ok()) {
          s.failed = true;
          deliveries.push_back({s.sink, nullptr, {}, s.failure});
          continue;
        }
        bool due = false;
        if (s.owed > 0) {
          --s.owed;
          due = true;
        } else if (s.config.pacing == Pacing::kContinuous && now >= s.next_due) {
          const float fps = s.config.max_fps > 0.0f ? s.config.max_fps : options_.default_max_fps;
          const auto period =
              std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / fps));
          s.next_due = std::max(s.next_due + period, now);
          due = true;
        }
        if (!due) continue;
        std::vector<Update> applied;
        Delivery d;
        d.sink = s.sink;
        EncodedFrame frame = MakeFrameLocked(s, applied, d.rejected);
        s.frames += 1;
        s.rate.Add(now);
        if (options_.observer) options_.observer->OnFrameRendered(frame);
        live_frames_->fetch_add(1);
        d.frame = std::shared_ptr<const EncodedFrame>(new EncodedFrame(std::move(frame)),
                                                      [live = live_frames_](const EncodedFrame* f) {
                                                        live->fetch_sub(1);
                                                        delete f;
                                                      });
        frames_rendered_.fetch_add(1);
        deliveries.push_back(std::move(d));
      }
    }
    // Sinks are called without the engine lock, as a render thread would;
    // a closed session's sink gets one late frame (allowed by FrameSink).
    for (Delivery& d : deliveries) {
      if (d.failure) {
        d.sink->OnSessionFailed(*d.failure);
        continue;
      }
      for (const auto& [seq, status] : d.rejected) d.sink->OnUpdateRejected(seq, status);
      d.sink->OnFrame(std::move(d.frame));
    }
    for (auto& sink : closed) {
      sink_calls_after_close_.fetch_add(1);
      auto late = std::make_shared<EncodedFrame>();
      late->width = late->height = 1;
      sink->OnFrame(std::move(late));
    }
  }
}

}  // namespace gistream::testing
