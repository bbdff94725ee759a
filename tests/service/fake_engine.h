// A CPU-only Engine for service tests: no GL, no files. Scenes are canned
// (3 nodes, 1 light, 2 materials, 1 camera), frames carry raw RGBA bytes of
// one colour (width*height*4; the "format" is only a label), and a frame
// thread renders continuous sessions at their fps cap and on-request
// sessions when asked, applying queued updates in order and echoing the last
// update's seq. Every frame reports the stages apply_updates, shade, encode.
//
// Validation mirrors what the real engine answers so the service's status
// mapping can be tested:
//   LoadScene: name must be a bundled scene (else NOT_FOUND), bytes must
//     start with "glTF" (else INVALID_ARGUMENT), at most max_scenes
//     (RESOURCE_EXHAUSTED).
//   OpenSession: unknown scene NOT_FOUND, unknown solver/param or a size
//     outside 1..max INVALID_ARGUMENT, max_sessions RESOURCE_EXHAUSTED.
//   PushUpdate: unknown node/light NOT_FOUND and NaN/Inf INVALID_ARGUMENT,
//     synchronously. A material id past the scene's materials is rejected
//     later, on the frame thread, through FrameSink::OnUpdateRejected (as a
//     render-thread validation would be).
//
// Like the real engine it tells EngineOptions::observer about every frame it
// produces and reports per-session status (frames, fps, pending updates,
// last seq, the sink's dropped frames) in stats().
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "engine/engine.h"
#include "engine/frame_rate.h"

namespace gistream::testing {

class FakeEngine final : public Engine {
 public:
  explicit FakeEngine(const EngineOptions& options = {});
  ~FakeEngine() override;

  DeviceInfo device_info() const override;
  EngineStats stats() const override;
  std::vector<SolverDescription> ListSolvers() const override;
  absl::StatusOr<SceneInfo> LoadScene(const SceneSource& source) override;
  absl::StatusOr<MemoryBudget::Reservation> ReserveUpload(uint64_t bytes,
                                                          const std::string& what) override;
  using Engine::UnloadScene;
  absl::Status UnloadScene(const SceneId& id, const TenantId& tenant) override;
  absl::StatusOr<SessionOpenInfo> OpenSession(const SessionConfig& config,
                                              std::shared_ptr<FrameSink> sink) override;
  absl::Status PushUpdate(const SessionId& id, Update update) override;
  absl::Status RequestFrames(const SessionId& id, uint32_t count) override;
  void CloseSession(const SessionId& id) override;
  absl::StatusOr<EncodedFrame> Render(const RenderRequest& request) override;
  void BeginDrain(std::chrono::milliseconds deadline) override;
  void Shutdown() override;

  // ---- test hooks
  // The budget ReserveUpload reserves from (EngineOptions::max_memory_bytes,
  // else DefaultMemoryLimit()); its bytes in use, and the most seen in use
  // while a LoadScene ran.
  MemoryBudget& upload_budget() { return upload_budget_; }
  uint64_t upload_bytes_during_load() const { return upload_bytes_during_load_.load(); }
  uint32_t session_count() const;
  // Seqs of the updates applied to a session, in the order applied (kept
  // after the session closes).
  std::vector<uint64_t> applied_seqs(const SessionId& id) const;
  // Makes the session fail on the frame thread (OnSessionFailed).
  void FailSession(const SessionId& id, absl::Status status);
  // While held, OpenSession waits at a gate before answering: a test can
  // act while an open is known to be in progress, then let it finish.
  void HoldOpens();
  void ReleaseOpens();
  // OpenSession calls that reached the gate / sessions opened, ever.
  int opens_started() const { return opens_started_.load(); }
  int sessions_opened() const { return sessions_opened_.load(); }
  // EncodedFrames produced by the frame thread that someone still holds.
  int64_t live_frames() const { return live_frames_->load(); }
  uint64_t frames_rendered() const { return frames_rendered_.load(); }
  uint64_t sink_calls_after_close() const { return sink_calls_after_close_.load(); }
  // The most on-request frames any session was owed at once.
  uint64_t max_owed() const { return max_owed_.load(); }

  static constexpr uint32_t kNodes = 3;
  static constexpr uint32_t kLights = 1;
  static constexpr uint32_t kMaterials = 2;

 private:
  MemoryBudget upload_budget_;
  std::atomic<uint64_t> upload_bytes_during_load_{0};
  struct FakeScene {
    SceneInfo info;
    uint64_t version = 1;
  };
  struct FakeSession {
    SessionId id;
    SessionConfig config;
    std::shared_ptr<FrameSink> sink;
    std::vector<Update> pending;
    uint64_t last_update_seq = 0;
    uint64_t frame_number = 0;
    uint64_t owed = 0;
    std::chrono::steady_clock::time_point next_due;
    absl::Status failure;  // set by FailSession; delivered by the frame thread
    bool failed = false;
    uint64_t frames = 0;
    FrameRate rate;
  };

  absl::Status ValidateUpdateLocked(const Update& update, absl::string_view field) const;
  absl::Status ValidateView(const std::string& solver,
                            const std::map<std::string, std::string>& params, uint32_t width,
                            uint32_t height) const;
  EncodedFrame MakeFrameLocked(FakeSession& session, std::vector<Update>& applied,
                               std::vector<std::pair<uint64_t, absl::Status>>& rejected);
  void FrameLoop(std::stop_token stop);

  // Configuration
  const EngineOptions options_;
  std::mutex gate_mutex_;
  std::condition_variable gate_cv_;
  bool gate_held_ = false;
  std::atomic<int> opens_started_{0};
  std::atomic<int> sessions_opened_{0};

  // Runtime data
  mutable std::mutex mutex_;
  std::condition_variable_any wake_;
  std::map<SceneId, FakeScene> scenes_;
  mutable std::map<SessionId, FakeSession> sessions_;  // stats() prunes frame rates
  std::map<SessionId, std::vector<uint64_t>> applied_;
  std::vector<std::shared_ptr<FrameSink>> closed_sinks_;  // called once more after close
  uint64_t next_scene_ = 1;
  uint64_t next_session_ = 1;
  bool shut_down_ = false;
  std::atomic<uint64_t> frames_rendered_{0};
  std::atomic<uint64_t> sink_calls_after_close_{0};
  std::atomic<uint64_t> max_owed_{0};
  std::shared_ptr<std::atomic<int64_t>> live_frames_ = std::make_shared<std::atomic<int64_t>>(0);
  std::jthread thread_;  // last: stopped and joined first
};

}  // namespace gistream::testing
