#include "service/session_reactor.h"

#include <algorithm>
#include <utility>

#include "service/translate.h"
#include "util/log.h"

namespace gistream::service {

namespace pb = ::gistream::v1;

// ---------------------------------------------------------------- sink

void SessionSink::Detach() {
  std::lock_guard lock(mutex_);
  reactor_ = nullptr;
}

void SessionSink::OnFrame(std::shared_ptr<const EncodedFrame> frame) {
  std::lock_guard lock(mutex_);
  if (reactor_ != nullptr) reactor_->DeliverFrame(std::move(frame));
}

void SessionSink::OnUpdateRejected(uint64_t seq, const absl::Status& status) {
  std::lock_guard lock(mutex_);
  if (reactor_ != nullptr) reactor_->DeliverRejected(seq, status);
}

void SessionSink::OnSessionFailed(const absl::Status& status) {
  std::lock_guard lock(mutex_);
  if (reactor_ != nullptr) reactor_->DeliverFailure(status);
}

void SessionSink::OnDraining(std::chrono::milliseconds deadline) {
  std::lock_guard lock(mutex_);
  if (reactor_ != nullptr) reactor_->DeliverDraining(deadline);
}

// ---------------------------------------------------------------- reactor
//
// Locking: SessionSink::mutex_ may be held while taking mutex_ (render
// thread), never the other way round, and no Engine method is called with
// mutex_ held (the engine may wait for its render thread, which may be
// waiting for mutex_ inside a sink call). StartRead/StartWrite/Finish are
// called with mutex_ held: gRPC runs our reactions on its own threads, never
// inline, so this cannot re-enter.

SessionReactor::SessionReactor(Engine& engine, WorkerPool& pool,
                               grpc::CallbackServerContext* context, const Options& options,
                               TenantId tenant)
    : engine_(engine),
      pool_(pool),
      context_(context),
      options_(options),
      tenant_(std::move(tenant)),
      sink_(std::make_shared<SessionSink>(this)) {
  read_in_flight_ = true;
  StartRead(&request_);
}

void SessionReactor::OnReadDone(bool ok) {
  // gRPC does not run OnDone while a reaction runs, so `this` stays valid
  // here even after unlocking.
  std::unique_lock lock(mutex_);
  // read_in_flight_ stays true while request_ is being handled, so no other
  // thread's PumpLocked starts the next read into it.
  if (!ok) {
    read_in_flight_ = false;
    reads_done_ = true;
    if (state_ == State::kAwaitConfig) {
      state_ = State::kClosed;
      RequestFinishLocked(
          cancelled_ ? grpc::Status::CANCELLED
                     : grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                                    "config: the stream ended before the first SessionRequest "
                                    "(which must be a config)"),
          /*flush=*/false);
    }
    PumpLocked();
    return;
  }
  if (cancelled_ || finish_status_.has_value()) {
    read_in_flight_ = false;
    PumpLocked();
    return;
  }
  const State state = state_;
  const SessionId id = session_id_;
  const Pacing pacing = pacing_;
  lock.unlock();
  if (state == State::kAwaitConfig) {
    HandleFirstRequest();
    return;
  }
  // An open session: the engine validates and queues; errors become events.
  const Handled handled = HandleSessionRequest(id, pacing);
  lock.lock();
  read_in_flight_ = false;
  frames_wanted_ += handled.frames_requested;
  if (!handled.status.ok() && !finish_status_.has_value()) {
    QueueRejectedLocked(handled.rejected_seq, handled.status);
  }
  PumpLocked();
  lock.unlock();
  if (handled.frames_requested > 0) GrantFrames();
}

void SessionReactor::HandleFirstRequest() {
  if (request_.kind_case() == pb::SessionRequest::kConfig) {
    HandleConfig(request_.config());
    return;
  }
  std::unique_lock lock(mutex_);
  read_in_flight_ = false;
  state_ = State::kClosed;
  RequestFinishLocked(
      grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                   request_.kind_case() == pb::SessionRequest::kUpdate
                       ? "config: the first SessionRequest must be a config, got an update"
                       : "config: the first SessionRequest must be a config"),
      /*flush=*/false);
  PumpLocked();
}

SessionReactor::Handled SessionReactor::HandleSessionRequest(const SessionId& id, Pacing pacing) {
  Handled out;
  switch (request_.kind_case()) {
    case pb::SessionRequest::kUpdate: {
      out.rejected_seq = request_.update().seq();
      {
        // For the update-to-frame latency (OnUpdateAnswered): when it came.
        std::lock_guard arrivals_lock(mutex_);
        if (update_arrivals_.size() >= kMaxTrackedUpdates) update_arrivals_.pop_front();
        update_arrivals_.emplace_back(out.rejected_seq, std::chrono::steady_clock::now());
      }
      absl::StatusOr<Update> update = UpdateFromProto(request_.update(), "update");
      out.status = update.ok() ? engine_.PushUpdate(id, *std::move(update)) : update.status();
      break;
    }
    case pb::SessionRequest::kRequestFrame: {
      const uint32_t count =
          request_.request_frame().count() == 0 ? 1 : request_.request_frame().count();
      if (request_.request_frame().key_frame()) out.status = engine_.RequestKeyFrame(id);
      if (pacing == Pacing::kContinuous) {
        // Ignored by the engine's pacing, but the client's sign of life.
        if (out.status.ok()) out.status = engine_.RequestFrames(id, count);
      } else if (out.status.ok()) {
        out.frames_requested = count;  // passed on by GrantFrames
      }
      break;
    }
    case pb::SessionRequest::kConfig:
      out.status = absl::InvalidArgumentError(
          "config: the session is already configured; change it with updates");
      break;
    case pb::SessionRequest::KIND_NOT_SET:
    default: out.status = absl::InvalidArgumentError("kind: empty SessionRequest"); break;
  }
  return out;
}

void SessionReactor::HandleConfig(const pb::SessionConfig& proto) {
  absl::StatusOr<SessionConfig> config = SessionConfigFromProto(proto);
  std::unique_lock lock(mutex_);
  read_in_flight_ = false;                         // the next read starts once the session is open
  if (cancelled_ || finish_status_.has_value()) {  // OnCancel ran meanwhile
    state_ = State::kClosed;
    PumpLocked();
    return;
  }
  if (!config.ok()) {
    state_ = State::kClosed;
    RequestFinishLocked(ToGrpcStatus(config.status()), /*flush=*/false);
    PumpLocked();
    return;
  }
  pacing_ = config->pacing;
  if (pacing_ == Pacing::kOnRequest) slot_.set_capacity(kOnRequestWindow);
  scene_id_ = config->scene;
  config->tenant = tenant_;
  state_ = State::kOpening;  // from here until the worker is done, nothing finishes the call
  lock.unlock();

  absl::Status submitted =
      pool_.Submit([this, cfg = *std::move(config)]() mutable { OpenOnWorker(std::move(cfg)); });
  if (!submitted.ok()) {
    lock.lock();
    state_ = State::kClosed;
    RequestFinishLocked(ToGrpcStatus(submitted), /*flush=*/false);
    PumpLocked();
  }
}

void SessionReactor::OpenOnWorker(SessionConfig config) {
  absl::StatusOr<SessionOpenInfo> opened = engine_.OpenSession(config, sink_);

  Engine& engine = engine_;
  WorkerPool& pool = pool_;
  SessionId to_close;
  std::unique_lock lock(mutex_);
  if (!opened.ok()) {
    state_ = State::kClosed;
    RequestFinishLocked(ToGrpcStatus(opened.status()), /*flush=*/false);
  } else {
    state_ = State::kOpen;
    session_id_ = opened->id;
    Log(LogLevel::kInfo, {opened->id, opened->scene},
        absl::StrCat("opened (", opened->solver, ", ", config.width, "x", config.height, ", ",
                     config.pacing == Pacing::kOnRequest ? "on request" : "continuous",
                     ") by tenant ", tenant_, " at ", context_->peer()));
    if (cancelled_) {
      to_close = TakeSessionToCloseLocked();
      RequestFinishLocked(grpc::Status::CANCELLED, /*flush=*/false);
    } else {
      pb::SessionEvent event;
      SessionOpenedToProto(*opened, event.mutable_opened());
      events_.push_front(std::move(event));  // before any frame that arrived meanwhile
    }
  }
  PumpLocked();
  lock.unlock();
  // `this` may be gone from here on.
  CloseSessionAsync(engine, pool, to_close);
}

void SessionReactor::OnWriteDone(bool ok) {
  SessionId to_close;
  {
    std::lock_guard lock(mutex_);
    write_in_flight_ = false;
    frame_write_in_flight_ = false;
    if (!ok) {
      // The stream is broken (client gone or call cancelled).
      to_close = TakeSessionToCloseLocked();
      RequestFinishLocked(grpc::Status(grpc::StatusCode::UNAVAILABLE, "write failed"),
                          /*flush=*/false);
    }
    PumpLocked();
  }
  GrantFrames();                                // a frame written makes room for the next
  CloseSessionAsync(engine_, pool_, to_close);  // safe: inside a reaction
}

void SessionReactor::OnCancel() {
  SessionId to_close;
  {
    std::lock_guard lock(mutex_);
    cancelled_ = true;
    // While opening, the worker sees cancelled_ and finishes the call.
    if (state_ != State::kOpening) {
      to_close = TakeSessionToCloseLocked();
      RequestFinishLocked(grpc::Status::CANCELLED, /*flush=*/false);
      PumpLocked();
    }
  }
  if (!to_close.empty()) Log(LogLevel::kInfo, {to_close, scene_id_}, "cancelled");
  CloseSessionAsync(engine_, pool_, to_close);
}

void SessionReactor::OnDone() {
  sink_->Detach();  // no sink call is inside this reactor now, and none will be
  SessionId to_close;
  {
    // Also waits for a thread that called Finish to leave its critical section.
    std::lock_guard lock(mutex_);
    to_close = TakeSessionToCloseLocked();
  }
  if (!to_close.empty()) Log(LogLevel::kInfo, {to_close, scene_id_}, "closed");
  CloseSessionAsync(engine_, pool_, to_close);
  delete this;
}

// ---------------------------------------------------------------- from the sink

void SessionReactor::DeliverFrame(std::shared_ptr<const EncodedFrame> frame) {
  std::lock_guard lock(mutex_);
  if (cancelled_ || finish_status_.has_value() ||
      (state_ != State::kOpen && state_ != State::kOpening)) {
    return;
  }
  if (pacing_ == Pacing::kOnRequest && frames_in_engine_ > 0) --frames_in_engine_;
  // Continuous: replaces an unsent frame; video: see FrameSlot.
  const FrameSlot::Offered offered = slot_.Offer(std::move(frame));
  if (offered.dropped > 0) {
    dropped_ += offered.dropped;
    sink_->dropped_.fetch_add(offered.dropped);
    observer().OnFramesDropped(offered.dropped);
  }
  if (offered.request_key_frame) {
    // Not on the render thread (this runs inside the engine's sink call).
    (void)pool_.Submit([&engine = engine_, id = session_id_] { (void)engine.RequestKeyFrame(id); });
  }
  PumpLocked();
}

void SessionReactor::DeliverRejected(uint64_t seq, const absl::Status& status) {
  std::lock_guard lock(mutex_);
  if (cancelled_ || finish_status_.has_value()) return;
  QueueRejectedLocked(seq, status);
  PumpLocked();
}

void SessionReactor::DeliverDraining(std::chrono::milliseconds deadline) {
  std::lock_guard lock(mutex_);
  if (cancelled_ || finish_status_.has_value()) return;
  Log(LogLevel::kInfo, {session_id_, scene_id_},
      absl::StrCat("told the client to move within ", deadline.count(), " ms (draining)"));
  // A control event: queued ahead of frames and never dropped.
  pb::SessionEvent event;
  event.mutable_draining()->set_deadline_ms(
      static_cast<uint32_t>(std::clamp<int64_t>(deadline.count(), 0, UINT32_MAX)));
  event.mutable_draining()->set_reason("the server is shutting down");
  events_.push_back(std::move(event));
  PumpLocked();
}

void SessionReactor::DeliverFailure(const absl::Status& status) {
  std::lock_guard lock(mutex_);
  Log(LogLevel::kWarning, {session_id_, scene_id_}, absl::StrCat("failed: ", status.ToString()));
  RequestFinishLocked(ToGrpcStatus(status.ok() ? absl::InternalError("session failed") : status),
                      /*flush=*/true);
  PumpLocked();
}

// ---------------------------------------------------------------- helpers

void SessionReactor::RequestFinishLocked(grpc::Status status, bool flush) {
  if (finish_status_.has_value()) {
    if (!flush) flush_before_finish_ = false;  // a later hard stop still cuts the flush short
    return;
  }
  finish_status_ = std::move(status);
  flush_before_finish_ = flush;
}

void SessionReactor::PumpLocked() {
  if (finish_called_ || state_ == State::kOpening) return;

  // Half-closed by the client: end once on-request frames asked for arrived.
  if (reads_done_ && !finish_status_.has_value() && state_ == State::kOpen &&
      (pacing_ == Pacing::kContinuous || (frames_wanted_ == 0 && frames_in_engine_ == 0))) {
    RequestFinishLocked(grpc::Status::OK, /*flush=*/true);
  }
  if (finish_status_.has_value() && !flush_before_finish_) {
    events_.clear();
    slot_.Clear();
  }

  if (!write_in_flight_) {
    if (!events_.empty()) {
      response_ = std::move(events_.front());
      events_.pop_front();
      write_in_flight_ = true;
      StartWrite(&response_);
    } else if (!slot_.empty()) {
      const std::shared_ptr<const EncodedFrame> next = slot_.Take();
      NoteFrameSentLocked(*next);
      response_.Clear();
      pb::Frame* frame = response_.mutable_frame();
      FrameToProto(*next, frame);
      frame->set_dropped_frames(next->dropped_frames + dropped_);
      dropped_ = 0;
      write_in_flight_ = true;
      frame_write_in_flight_ = true;
      StartWrite(&response_);
    }
  }

  if (finish_status_.has_value()) {
    if (!write_in_flight_) {
      finish_called_ = true;
      observer().OnRpcFinished("Session", FromGrpcCode(finish_status_->error_code()));
      if (!finish_status_->ok()) {
        const absl::StatusCode code = FromGrpcCode(finish_status_->error_code());
        observer().OnRpcFailed("Session", code);
        Log(LogLevel::kInfo, {session_id_, scene_id_},
            absl::StrCat("Session from ", context_->peer(), " failed: ",
                         absl::StatusCodeToString(code), ": ", finish_status_->error_message()));
      }
      Finish(*finish_status_);  // OnDone may follow on another thread; it waits for mutex_
    }
    return;
  }

  if (state_ == State::kOpen && !read_in_flight_ && !reads_done_ && !cancelled_ &&
      events_.size() < options_.max_queued_events) {
    read_in_flight_ = true;
    StartRead(&request_);
  }
}

uint32_t SessionReactor::TakeFrameGrantLocked() {
  if (pacing_ != Pacing::kOnRequest || state_ != State::kOpen || cancelled_ ||
      finish_status_.has_value()) {
    return 0;
  }
  const uint64_t outstanding =
      uint64_t{frames_in_engine_} + slot_.size() + (frame_write_in_flight_ ? 1 : 0);
  if (outstanding >= kOnRequestWindow) return 0;
  const auto grant =
      static_cast<uint32_t>(std::min<uint64_t>(frames_wanted_, kOnRequestWindow - outstanding));
  frames_wanted_ -= grant;
  frames_in_engine_ += grant;
  return grant;
}

void SessionReactor::GrantFrames() {
  std::unique_lock lock(mutex_);
  const uint32_t grant = TakeFrameGrantLocked();
  if (grant == 0) return;
  const SessionId id = session_id_;
  lock.unlock();
  const absl::Status status = engine_.RequestFrames(id, grant);
  if (status.ok()) return;
  // The engine will not render them (e.g. the session was closed or the
  // server is shutting down): forget what was asked for and say why.
  lock.lock();
  frames_in_engine_ -= std::min(frames_in_engine_, grant);
  frames_wanted_ = 0;
  if (!finish_status_.has_value()) QueueRejectedLocked(0, status);
  PumpLocked();
}

SessionId SessionReactor::TakeSessionToCloseLocked() {
  if (state_ != State::kOpen || session_closed_) return {};
  session_closed_ = true;
  return session_id_;
}

void SessionReactor::QueueRejectedLocked(uint64_t seq, const absl::Status& status) {
  observer().OnUpdateRejected(status.code());
  // Answered by the rejection, not by a frame: not an update-to-frame latency.
  std::erase_if(update_arrivals_, [seq](const auto& arrival) { return arrival.first == seq; });
  Log(LogLevel::kDebug, {session_id_, scene_id_},
      absl::StrCat("update seq ", seq, " rejected: ", absl::StatusCodeToString(status.code()), ": ",
                   status.message()));
  pb::SessionEvent event;
  UpdateRejectedToProto(seq, status, event.mutable_rejected());
  events_.push_back(std::move(event));
}

void SessionReactor::NoteFrameSentLocked(const EncodedFrame& frame) {
  observer().OnFrameSent(frame.image.size());
  // Updates this frame answers first (it echoes their sequence numbers;
  // rejected ones are echoed too): their arrival to now. Sequence numbers
  // increase along the stream.
  const auto now = std::chrono::steady_clock::now();
  while (!update_arrivals_.empty() && update_arrivals_.front().first <= frame.last_update_seq) {
    observer().OnUpdateAnswered(
        std::chrono::duration<double>(now - update_arrivals_.front().second).count());
    update_arrivals_.pop_front();
  }
}

ServerObserver& SessionReactor::observer() const {
  static ServerObserver none;
  return options_.observer ? *options_.observer : none;
}

void SessionReactor::CloseSessionAsync(Engine& engine, WorkerPool& pool, const SessionId& id) {
  if (id.empty()) return;
  // CloseSession may wait for the render thread: keep it off gRPC's threads
  // when the pool has room, else close inline (never leak the session).
  std::function<void()> close = [&engine, id] { engine.CloseSession(id); };
  if (!pool.Submit(close).ok()) close();
}

}  // namespace gistream::service
