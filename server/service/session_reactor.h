// One interactive session: the server side of the bidirectional Session
// stream. The first read must be a config (-> Engine::OpenSession, answered
// with `opened`); later reads carry updates (-> Engine::PushUpdate; an error
// becomes an UpdateRejected event and the session goes on) and frame
// requests (-> Engine::RequestFrames, kOnRequestWindow frames at a time).
//
// Writes: at most one in flight. Control events (opened, rejected, draining) wait in a
// small queue and are never dropped: while it is full the reactor stops
// reading, so a client that floods bad updates without reading is slowed,
// not buffered. A continuous session's frames are never queued: the newest
// unsent frame replaces an older one and the count of replaced frames rides
// on the next frame sent (Frame.dropped_frames). For video formats a
// dropped frame is followed by a key-frame request, and delta frames are
// dropped until the key frame. An on-request session gets every frame it
// asked for: the engine is asked for the next ones only as earlier ones
// are written, so a slow reader slows its own frames and holds at most
// kOnRequestWindow of them.
//
// The client half-closing the stream ends the session once what is queued
// is written (on-request sessions also wait for the frames they asked for);
// the status is then OK. A cancelled call (client gone, deadline, server
// shutdown) closes the engine session at once.
#pragma once

#include <atomic>
#include <cstdint>
#include <chrono>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>

#include <grpcpp/grpcpp.h>

#include "gistream/v1/gistream.grpc.pb.h"
#include "engine/engine.h"
#include "service/frame_slot.h"
#include "service/worker_pool.h"

namespace gistream::service {

class SessionReactor;

// The FrameSink the Engine holds (shared_ptr). Forwards to the reactor until
// Detach(); afterwards calls are dropped, so the engine may call it briefly
// after CloseSession and after the reactor is gone.
class SessionSink final : public FrameSink {
 public:
  explicit SessionSink(SessionReactor* reactor) : reactor_(reactor) {}
  // Returns once no call into the reactor is in progress; none follow.
  void Detach();

  void OnFrame(std::shared_ptr<const EncodedFrame> frame) override;
  void OnUpdateRejected(uint64_t seq, const absl::Status& status) override;
  void OnSessionFailed(const absl::Status& status) override;
  void OnDraining(std::chrono::milliseconds deadline) override;
  uint64_t dropped_frames() const override { return dropped_.load(); }

 private:
  friend class SessionReactor;
  std::mutex mutex_;
  SessionReactor* reactor_;           // null once detached
  std::atomic<uint64_t> dropped_{0};  // the reactor's drops, over the session's life
};

class SessionReactor final
    : public grpc::ServerBidiReactor<::gistream::v1::SessionRequest, ::gistream::v1::SessionEvent> {
 public:
  /// On-request frames outstanding at once (in the engine, unsent, being written).
  static constexpr uint32_t kOnRequestWindow = 2;

  struct Options {
    /// Control events (opened, rejected) waiting to be written before the
    /// reactor stops reading from the client.
    size_t max_queued_events = 32;
    /// Told about dropped frames, rejected updates and a failed call; may be null.
    std::shared_ptr<ServerObserver> observer;
  };

  // Deletes itself in OnDone. `tenant`: the authenticated caller, who must
  // own the configured scene.
  SessionReactor(Engine& engine, WorkerPool& pool, grpc::CallbackServerContext* context,
                 const Options& options, TenantId tenant);

  void OnReadDone(bool ok) override;
  void OnWriteDone(bool ok) override;
  void OnCancel() override;
  void OnDone() override;

 private:
  friend class SessionSink;
  enum class State {
    kAwaitConfig,  // first read outstanding
    kOpening,      // OpenSession running on the worker pool; no read outstanding
    kOpen,         // engine session exists
    kClosed,       // no engine session (config failed or it was closed)
  };

  ~SessionReactor() override = default;

  // Called through SessionSink (render thread).
  void DeliverFrame(std::shared_ptr<const EncodedFrame> frame);
  void DeliverRejected(uint64_t seq, const absl::Status& status);
  void DeliverFailure(const absl::Status& status);
  void DeliverDraining(std::chrono::milliseconds deadline);

  // The first request of the stream: a config opens the session, anything
  // else ends the call (INVALID_ARGUMENT). Not under mutex_.
  void HandleFirstRequest();
  void HandleConfig(const ::gistream::v1::SessionConfig& config);
  // A request on an open session, passed to the engine (not under mutex_):
  // what was rejected (its seq and why) and how many frames were asked for.
  struct Handled {
    uint64_t rejected_seq = 0;
    absl::Status status;
    uint32_t frames_requested = 0;
  };
  Handled HandleSessionRequest(const SessionId& id, Pacing pacing);
  void OpenOnWorker(SessionConfig config);
  // Requests the end of the call; with `flush` the queued event and frame
  // are written first. The first request wins.
  void RequestFinishLocked(grpc::Status status, bool flush);
  // Moves the call along: starts the next write, the next read, or Finish.
  // Must be the last thing a caller does with `this` before unlocking, as
  // Finish may lead to OnDone on another thread (which waits for mutex_).
  void PumpLocked();
  // Takes the session id for CloseSession exactly once ("" when none).
  SessionId TakeSessionToCloseLocked();
  static void CloseSessionAsync(Engine& engine, WorkerPool& pool, const SessionId& id);
  // On-request sessions: the frames to pass to the engine now (counted as
  // in the engine), keeping kOnRequestWindow outstanding.
  uint32_t TakeFrameGrantLocked();
  // Passes TakeFrameGrantLocked's frames to the engine. Call from a
  // reaction (so `this` stays valid) without mutex_.
  void GrantFrames();
  // Counts, logs and queues an UpdateRejected event.
  void QueueRejectedLocked(uint64_t seq, const absl::Status& status);
  // Reports a frame handed to the stream: its bytes, and the latency of
  // the updates it answers first (update_arrivals_).
  void NoteFrameSentLocked(const EncodedFrame& frame);
  ServerObserver& observer() const;

  // Configuration
  Engine& engine_;
  WorkerPool& pool_;
  grpc::CallbackServerContext* const context_;
  const Options options_;
  const TenantId tenant_;
  const std::shared_ptr<SessionSink> sink_;

  // Runtime data. request_ belongs to whoever holds the outstanding read,
  // response_ to the outstanding write; everything else is under mutex_.
  ::gistream::v1::SessionRequest request_;
  ::gistream::v1::SessionEvent response_;
  std::mutex mutex_;
  State state_ = State::kAwaitConfig;
  SessionId session_id_;
  SceneId scene_id_;  // from the config, for log lines
  bool session_closed_ = false;
  Pacing pacing_ = Pacing::kContinuous;
  // On-request flow control: the frames the client asked for reach the
  // engine kOnRequestWindow at a time (in the engine, unsent, or being
  // written), so every one is delivered and a slow reader holds at most
  // that many frames.
  uint64_t frames_wanted_ = 0;     // asked for by the client, not yet passed to the engine
  uint32_t frames_in_engine_ = 0;  // passed to the engine, not yet delivered
  bool frame_write_in_flight_ = false;
  bool read_in_flight_ = false;
  bool reads_done_ = false;  // client half-closed (or the read failed)
  bool cancelled_ = false;
  bool write_in_flight_ = false;
  std::deque<::gistream::v1::SessionEvent> events_;
  FrameSlot slot_;        // the unsent frame(s)
  uint32_t dropped_ = 0;  // frames replaced since the last frame written
  // Updates not yet answered by a frame: sequence number and arrival, the
  // newest kMaxTrackedUpdates (older ones are not measured).
  static constexpr size_t kMaxTrackedUpdates = 256;
  std::deque<std::pair<uint64_t, std::chrono::steady_clock::time_point>> update_arrivals_;
  std::optional<grpc::Status> finish_status_;
  bool flush_before_finish_ = false;
  bool finish_called_ = false;
};

}  // namespace gistream::service
