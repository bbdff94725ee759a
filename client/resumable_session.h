// A continuous session that outlives its server (issue 31, drain and
// resume). It keeps what it needs to rebuild its state elsewhere: the
// scene's source (the LoadSceneRequest), the session's config and every
// update sent since the scene was loaded (compacted: a later update that
// sets the same fields of the same target replaces an earlier one). When
// the server says it drains (a Draining event) or the call breaks
// (UNAVAILABLE, or a stream reset by a balancer when the server died), it
// connects again to the same address (through a balancer: another
// server), loads the scene, opens the session with the same config, sends
// the updates again with their sequence numbers, and goes on: Next keeps
// returning events. No acknowledged update is lost: every update is
// replayed, acknowledged (echoed by a frame) or not.
//
// The interface is SessionStream's, so `stream`, `bench` and `script` use
// either. A session paced on request (`script`) gets, on the new server,
// the frames it had asked for and not yet received.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "connection.h"
#include "gistream/v1/gistream.pb.h"
#include "options.h"
#include "scene_loader.h"
#include "session_stream.h"
#include "util/status.h"

namespace gistream::client {

// Where sessions that moved went: a connection and the scene loaded there.
struct MoveTarget {
  std::unique_ptr<Connection> connection;
  // Unloaded when the last user is gone; declared after the connection it
  // calls on, so destroyed before it.
  std::unique_ptr<LoadedScene> scene;
};

// Sessions of one client that move together (bench's sessions, whose
// server died under all of them) load the scene once: the first to move
// loads it, the others open their sessions on the same scene. A target
// that fails a session (its server went away too) is loaded anew.
class MoveGroup {
 public:
  // The group's current target, loading one when there is none or when
  // `failed` is the current one. Blocks while another session loads.
  absl::StatusOr<std::shared_ptr<MoveTarget>> Acquire(const ConnectionOptions& connection,
                                                      const v1::LoadSceneRequest& load,
                                                      const std::shared_ptr<MoveTarget>& failed);

 private:
  std::mutex mutex_;
  std::shared_ptr<MoveTarget> current_;
};

struct ResumeOptions {
  // Where to connect again (the same address: a balancer routes the call
  // to a server that serves) and the scene to load there.
  ConnectionOptions connection;
  v1::LoadSceneRequest load;
  // How long one move may keep trying (connect, load, open) before the
  // session fails with the last error; 0 turns resuming off.
  double give_up_after_s = 15.0;
  // Shared by the sessions that should land together (may be null: the
  // session loads its own copy).
  std::shared_ptr<MoveGroup> group;
};

// Whether a session's call that ended with `status` (not cancelled by this
// client) can be resumed elsewhere: the server went away (UNAVAILABLE,
// CANCELLED by its shutdown) or a proxy reset the stream (INTERNAL,
// UNKNOWN). A refusal of the request itself (INVALID_ARGUMENT, NOT_FOUND,
// RESOURCE_EXHAUSTED, ...) is not.
bool ResumableStatus(const absl::Status& status);

// The update log's key: updates with the same key set the same fields of
// the same target, so a later one makes an earlier one redundant. Empty for
// updates that do not compact (animation playback, whose effect depends on
// order and time).
std::string UpdateTargetKey(const v1::Update& update);

class ResumableSession {
 public:
  using Clock = std::chrono::steady_clock;

  // One move to another server.
  struct Move {
    std::string reason;      // "draining" or the broken call's status
    double at_s = 0.0;       // since the session opened
    uint64_t acked_seq = 0;  // the last update a frame had echoed before it
    int attempts = 0;
    // From the failure (or the Draining event) to the first frame of the
    // new session, and to the first frame that shows every acknowledged
    // update (its last_update_seq >= acked_seq); unset until seen.
    std::optional<double> ms_to_frame, ms_to_acked;
    // What the viewer saw: the time without frames, from the last frame
    // of the old server to the first of the new. A drain moves while the
    // old server still streams (make before break), so it is about one
    // frame interval; a server that died leaves the whole move as a gap.
    std::optional<double> gap_ms;
    std::string error;  // set when the move gave up
  };

  // Opens the first session on `stub` (the scene `config` names is loaded
  // already, by the caller).
  static absl::StatusOr<std::unique_ptr<ResumableSession>> Open(v1::Gistream::Stub& stub,
                                                                const v1::SessionConfig& config,
                                                                absl::string_view server,
                                                                ResumeOptions resume);
  ~ResumableSession();
  ResumableSession(const ResumableSession&) = delete;
  ResumableSession& operator=(const ResumableSession&) = delete;

  // The current session's (after a move, the new server's).
  v1::SessionOpened opened() const;

  // Logs the update, then sends it on the current call. True unless writes
  // are closed: an update sent while a move is under way is replayed by it.
  bool SendUpdate(const v1::Update& update);
  // Asks for `count` frames (on-request pacing). A move asks the new server
  // for those the old one had not delivered. True unless writes are closed.
  bool RequestFrame(uint32_t count = 1);
  // Blocks for the next event, moving to another server when this one
  // drains or goes away; false at the end (Finish says why). One reader.
  bool Next(v1::SessionEvent* event);
  void CloseWrites(std::chrono::milliseconds grace = std::chrono::seconds(5));
  void Cancel();
  absl::Status Finish();
  bool cancelled_by_client() const;
  bool grace_expired() const;

  std::vector<Move> moves() const;
  size_t logged_updates() const;

 private:
  ResumableSession(std::string server, v1::SessionConfig config, ResumeOptions resume)
      : server_(std::move(server)), config_(std::move(config)), resume_(std::move(resume)) {}
  // Connects, loads, opens and replays until it works or the move's time
  // is up; then swaps the call and cancels the old one. On the reader
  // thread when the call broke, on mover_ when the server drains (the
  // reader goes on with the old server's frames meanwhile).
  // With `make_before_break` (a drain) the swap waits for the new call's
  // first frame, which the reader then delivers first.
  absl::Status MoveTo(const std::string& reason, bool make_before_break);
  // MoveTo's steps. The move's record (moves_) and its start.
  void BeginMove(const std::string& reason, Clock::time_point start);
  // Sends the update log on `stream`; *replayed_seq the newest seq sent,
  // *replayed_upto the log's number at the replay; the count sent.
  size_t ReplayLog(SessionStream& stream, uint64_t* replayed_seq, uint64_t* replayed_upto);
  // A drain's move: reads `stream` until a frame shows every replayed
  // update, keeping it and the events before it in `first_events`; false
  // when the call ended first.
  bool AwaitReplayedFrame(SessionStream& stream, uint64_t replayed_seq,
                          std::deque<v1::SessionEvent>& first_events);
  // Swaps `stream` in (sending what was logged after the replay) and
  // returns the old call.
  std::shared_ptr<SessionStream> SwapIn(std::unique_ptr<SessionStream> stream,
                                        std::shared_ptr<MoveTarget> target,
                                        std::deque<v1::SessionEvent> first_events,
                                        uint64_t replayed_upto, uint64_t replayed_seq,
                                        bool make_before_break);
  // Next's steps. A draining notice: starts a drain's move on mover_ when
  // the session may move.
  void OnDraining(const v1::Draining& draining);
  // Whether a frame read from `stream` is delivered (not one of a call a
  // move swapped out, nor one from before the replayed updates).
  bool DeliverFrame(const v1::SessionEvent& event, const std::shared_ptr<SessionStream>& stream);
  // After `stream` ended with `status`: kEnded (final_status_ set),
  // kReplaced (a move swapped it) or kResume (move it now).
  enum class CallEnd { kEnded, kReplaced, kResume };
  CallEnd OnCallEnded(const std::shared_ptr<SessionStream>& stream, const absl::Status& status);
  void OnFrame(const v1::Frame& frame, const SessionStream* from);
  // On-request pacing: at a move's swap (under the lock), asks `stream` for
  // the frames the old call owes. `handshake`: `first_events` holds the
  // frame a drain's move asked for to see the new server's first picture
  // (showing every update sent); it answers the first frame owed, or is
  // dropped when nothing was owed.
  void RequestOwedFrames(SessionStream& stream, bool handshake,
                         std::deque<v1::SessionEvent>& first_events);

  const std::string server_;
  const v1::SessionConfig config_;
  const ResumeOptions resume_;
  const Clock::time_point opened_at_ = Clock::now();

  mutable std::mutex mutex_;  // guards everything below
  std::shared_ptr<SessionStream> stream_;
  // In order, compacted: an entry per UpdateTargetKey, numbered as sent.
  struct Logged {
    std::string key;
    uint64_t number = 0;
    v1::Update update;
  };
  std::vector<Logged> log_;
  uint64_t logged_ = 0;  // the last number given
  // A drain's new call, its events up to its first frame (make before
  // break: the swap waits for it); the reader hands them out first.
  std::deque<v1::SessionEvent> pending_events_;
  // On-request pacing: frames asked of the current call, and received
  // from it (their difference is what a move asks the next server for).
  const bool on_request_ = config_.has_on_request();
  uint64_t frames_requested_ = 0, frames_received_ = 0;
  // After a move: the new call's frames older than its replay are skipped.
  uint64_t hide_below_seq_ = 0;
  bool writes_closed_ = false;
  bool cancelled_ = false;
  uint64_t acked_seq_ = 0;
  std::vector<Move> moves_;
  std::optional<Clock::time_point> move_started_;
  const SessionStream* moved_from_ = nullptr;  // the call the move leaves
  std::optional<Clock::time_point> last_frame_at_;
  std::thread mover_;  // a drain's move
  bool moving_ = false;
  absl::Status move_result_;
  std::condition_variable move_cv_;
  // The servers moved to: their connection and scene (unloaded at the end).
  std::vector<std::shared_ptr<MoveTarget>> targets_;
  absl::Status final_status_;
  bool ended_ = false;  // Next returned false: final_status_ holds why
  bool last_cancelled_by_client_ = false;
  bool last_grace_expired_ = false;
};

// "moved at 3.2 s (draining), 1 attempt: the new server's first frame
// after 2100 ms (70 ms without frames), with every acknowledged update
// (seq 17) after 2100 ms"
std::string FormatMove(const ResumableSession::Move& move);

}  // namespace gistream::client
