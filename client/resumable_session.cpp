#include "resumable_session.h"

#include <algorithm>
#include <thread>

#include <absl/strings/str_cat.h>
#include <absl/strings/str_format.h>
#include <google/protobuf/descriptor.h>
#include <google/protobuf/reflection.h>

#include "util/log.h"

namespace gistream::client {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;

// Fields that name an update's target (a node, a light, a material).
bool IsTargetField(const FieldDescriptor& field) {
  return field.cpp_type() == FieldDescriptor::CPPTYPE_UINT32 &&
         (field.name() == "node" || field.name() == "light" || field.name() == "material");
}

double MsSince(ResumableSession::Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(ResumableSession::Clock::now() - t).count();
}

}  // namespace

bool ResumableStatus(const absl::Status& status) {
  switch (status.code()) {
    case absl::StatusCode::kUnavailable:
    case absl::StatusCode::kCancelled:
    case absl::StatusCode::kInternal:
    case absl::StatusCode::kUnknown: return true;
    default: return false;
  }
}

std::string UpdateTargetKey(const v1::Update& update) {
  if (update.change_case() == v1::Update::CHANGE_NOT_SET ||
      update.change_case() == v1::Update::kAnimation) {
    return "";
  }
  // The change's kind, its target and the fields it sets (proto3: the
  // fields that differ from their defaults, which is what the server reads).
  const google::protobuf::OneofDescriptor* oneof =
      update.GetDescriptor()->FindOneofByName("change");
  const FieldDescriptor* which = update.GetReflection()->GetOneofFieldDescriptor(update, oneof);
  if (which == nullptr || which->cpp_type() != FieldDescriptor::CPPTYPE_MESSAGE) return "";
  const Message& change = update.GetReflection()->GetMessage(update, which);
  std::vector<const FieldDescriptor*> fields;
  change.GetReflection()->ListFields(change, &fields);
  std::string key = absl::StrCat(which->number(), ":");
  for (const FieldDescriptor* field : fields) {
    if (IsTargetField(*field)) {
      absl::StrAppend(&key, field->name(), "=", change.GetReflection()->GetUInt32(change, field),
                      ";");
    } else {
      absl::StrAppend(&key, field->number(), ",");
    }
  }
  return key;
}

absl::StatusOr<std::shared_ptr<MoveTarget>> MoveGroup::Acquire(
    const ConnectionOptions& connection, const v1::LoadSceneRequest& load,
    const std::shared_ptr<MoveTarget>& failed) {
  std::lock_guard lock(mutex_);  // the others wait for the one loading
  if (current_ && current_ != failed) return current_;
  auto target = std::make_shared<MoveTarget>();
  target->connection = std::make_unique<Connection>(connection);
  GS_ASSIGN_OR_RETURN(target->scene, LoadedScene::Load(*target->connection, load, /*keep=*/false));
  current_ = target;
  return target;
}

absl::StatusOr<std::unique_ptr<ResumableSession>> ResumableSession::Open(
    v1::Gistream::Stub& stub, const v1::SessionConfig& config, absl::string_view server,
    ResumeOptions resume) {
  GS_ASSIGN_OR_RETURN(std::unique_ptr<SessionStream> stream,
                      SessionStream::Open(stub, config, server));
  std::unique_ptr<ResumableSession> session(
      new ResumableSession(std::string(server), config, std::move(resume)));
  session->stream_ = std::move(stream);
  return session;
}

ResumableSession::~ResumableSession() {
  std::shared_ptr<SessionStream> stream;
  {
    std::lock_guard lock(mutex_);
    cancelled_ = true;  // a move under way stops at its next attempt
    stream = stream_;
  }
  if (stream) stream->Cancel();
  if (mover_.joinable()) mover_.join();
}

v1::SessionOpened ResumableSession::opened() const {
  std::lock_guard lock(mutex_);
  return stream_->opened();
}

bool ResumableSession::SendUpdate(const v1::Update& update) {
  std::lock_guard lock(mutex_);
  if (writes_closed_ || cancelled_) return false;
  if (resume_.give_up_after_s > 0.0) {
    std::string key = UpdateTargetKey(update);
    if (!key.empty()) std::erase_if(log_, [&](const Logged& logged) { return logged.key == key; });
    log_.push_back({std::move(key), ++logged_, update});
  }
  // Under the lock: a move replays the log and swaps the call under it
  // too, so an update is either in its replay or sent on the new call.
  const bool sent = stream_->SendUpdate(update);
  return sent || resume_.give_up_after_s > 0.0;
}

bool ResumableSession::RequestFrame(uint32_t count) {
  std::lock_guard lock(mutex_);
  if (writes_closed_ || cancelled_) return false;
  frames_requested_ += count;
  // Under the lock, as SendUpdate: a request is either owed by the call a
  // move leaves (and asked again of the new one) or sent on the new call.
  const bool sent = stream_->RequestFrame(count);
  return sent || resume_.give_up_after_s > 0.0;
}

void ResumableSession::RequestOwedFrames(SessionStream& stream, bool handshake,
                                         std::deque<v1::SessionEvent>& first_events) {
  if (!on_request_) return;
  uint64_t owed = frames_requested_ - std::min(frames_received_, frames_requested_);
  bool handshake_kept = false;
  if (handshake) {
    if (owed == 0) {
      // Nobody asked for the frame that proved the new server works.
      std::erase_if(first_events, [](const v1::SessionEvent& e) { return e.has_frame(); });
    } else {
      owed -= 1;  // it answers the first request owed
      handshake_kept = true;
    }
  }
  if (owed > 0) stream.RequestFrame(uint32_t(std::min<uint64_t>(owed, UINT32_MAX)));
  // The new call's count: the kept handshake is received when handed out.
  frames_requested_ = owed + (handshake_kept ? 1 : 0);
  frames_received_ = 0;
}

void ResumableSession::OnFrame(const v1::Frame& frame, const SessionStream* from) {
  std::lock_guard lock(mutex_);
  const Clock::time_point now = Clock::now();
  const std::optional<Clock::time_point> previous = std::exchange(last_frame_at_, now);
  acked_seq_ = std::max(acked_seq_, frame.last_update_seq());
  if (!move_started_ || moves_.empty()) return;
  Move& move = moves_.back();
  if (from == moved_from_) {
    // The old server's, while a drain's move is under way: what it
    // acknowledges the new server must show too.
    move.acked_seq = std::max(move.acked_seq, frame.last_update_seq());
    return;
  }
  if (!move.ms_to_frame) {
    move.ms_to_frame = MsSince(*move_started_);
    move.gap_ms = std::chrono::duration<double, std::milli>(now - previous.value_or(now)).count();
  }
  if (!move.ms_to_acked && frame.last_update_seq() >= move.acked_seq) {
    move.ms_to_acked = MsSince(*move_started_);
    Log(LogLevel::kInfo,
        absl::StrCat("session resumed: frames again ", *move.ms_to_frame,
                     " ms after the move began, with every acknowledged update (seq ",
                     move.acked_seq, ") ", *move.ms_to_acked, " ms after"));
    move_started_.reset();
  }
}

bool ResumableSession::Next(v1::SessionEvent* event) {
  for (;;) {
    std::shared_ptr<SessionStream> stream;
    bool pending = false;
    {
      std::lock_guard lock(mutex_);
      if (ended_) return false;  // Finish was taken
      stream = stream_;
      if (!pending_events_.empty()) {
        *event = std::move(pending_events_.front());
        pending_events_.pop_front();
        pending = true;
      }
    }
    if (pending) {  // what a drain's move read from the new call first
      if (event->has_frame()) {
        {
          std::lock_guard lock(mutex_);
          frames_received_ += 1;
        }
        OnFrame(event->frame(), stream.get());
      }
      return true;
    }
    if (stream->Next(event)) {
      if (event->has_draining()) {
        OnDraining(event->draining());
        continue;
      }
      if (event->has_frame()) {
        if (!DeliverFrame(*event, stream)) continue;
        OnFrame(event->frame(), stream.get());
      }
      return true;
    }
    const absl::Status status = stream->Finish();
    switch (OnCallEnded(stream, status)) {
      case CallEnd::kEnded: return false;
      case CallEnd::kReplaced: continue;  // the call a move left
      case CallEnd::kResume: break;
    }
    Log(LogLevel::kWarning,
        absl::StrCat("the session's call ended (", DescribeStatus(status), "): moving it"));
    const absl::Status moved = MoveTo(DescribeStatus(status), /*make_before_break=*/false);
    if (!moved.ok()) {
      std::lock_guard lock(mutex_);
      final_status_ = moved;
      ended_ = true;
      return false;
    }
  }
}

void ResumableSession::OnDraining(const v1::Draining& draining) {
  bool move = false;
  {
    std::lock_guard lock(mutex_);
    move = resume_.give_up_after_s > 0.0 && !writes_closed_ && !cancelled_;
  }
  Log(LogLevel::kInfo,
      absl::StrCat("the server drains (", draining.reason(), "; ", draining.deadline_ms(),
                   " ms left)", move ? ": moving the session" : ""));
  if (!move) return;
  // Make before break: the move runs beside this reader, which goes on
  // with the old server's frames until the swap.
  std::lock_guard lock(mutex_);
  if (moving_) return;
  moving_ = true;
  move_result_ = absl::OkStatus();
  if (mover_.joinable()) mover_.join();  // an earlier one, finished
  mover_ = std::thread([this] {
    const absl::Status moved = MoveTo("draining", /*make_before_break=*/true);
    std::lock_guard done(mutex_);
    move_result_ = moved;
    moving_ = false;
    move_cv_.notify_all();
  });
}

bool ResumableSession::DeliverFrame(const v1::SessionEvent& event,
                                    const std::shared_ptr<SessionStream>& stream) {
  // After a move, frames rendered before the replayed updates were
  // applied show the scene as loaded: not shown. A frame the old call
  // still delivered after a drain's move swapped it out is older than the
  // new server's first: dropped.
  std::lock_guard lock(mutex_);
  if (stream != stream_) return false;
  frames_received_ += 1;  // shown or not, it answered a request
  if (event.frame().last_update_seq() < hide_below_seq_) return false;
  hide_below_seq_ = 0;
  return true;
}

ResumableSession::CallEnd ResumableSession::OnCallEnded(
    const std::shared_ptr<SessionStream>& stream, const absl::Status& status) {
  std::unique_lock lock(mutex_);
  // A drain's move under way: its outcome decides.
  move_cv_.wait(lock, [this] { return !moving_; });
  if (stream == stream_ && !move_result_.ok() && !writes_closed_ && !cancelled_) {
    final_status_ = move_result_;
    ended_ = true;
    return CallEnd::kEnded;
  }
  if (stream != stream_) return CallEnd::kReplaced;
  if (resume_.give_up_after_s > 0.0 && !writes_closed_ && !cancelled_ &&
      !stream->cancelled_by_client() && ResumableStatus(status)) {
    return CallEnd::kResume;
  }
  final_status_ = status;
  ended_ = true;
  last_cancelled_by_client_ = stream->cancelled_by_client();
  last_grace_expired_ = stream->grace_expired();
  return CallEnd::kEnded;
}

void ResumableSession::BeginMove(const std::string& reason, Clock::time_point start) {
  std::lock_guard lock(mutex_);
  Move move;
  move.reason = reason;
  move.at_s = std::chrono::duration<double>(start - opened_at_).count();
  move.acked_seq = acked_seq_;
  moves_.push_back(move);
  move_started_ = start;
  moved_from_ = stream_.get();
}

size_t ResumableSession::ReplayLog(SessionStream& stream, uint64_t* replayed_seq,
                                   uint64_t* replayed_upto) {
  std::lock_guard lock(mutex_);
  size_t replayed = 0;
  for (const Logged& logged : log_) {
    if (!stream.SendUpdate(logged.update)) break;
    ++replayed;
    *replayed_seq = std::max(*replayed_seq, logged.update.seq());
  }
  *replayed_upto = logged_;
  return replayed;
}

bool ResumableSession::AwaitReplayedFrame(SessionStream& stream, uint64_t replayed_seq,
                                          std::deque<v1::SessionEvent>& first_events) {
  // Paced on request, the new server renders one when asked
  // (RequestOwedFrames).
  if (on_request_) stream.RequestFrame(1);
  v1::SessionEvent event;
  while (stream.Next(&event)) {
    const bool framed = event.has_frame() && event.frame().last_update_seq() >= replayed_seq;
    if (!event.has_frame() || framed) first_events.push_back(event);
    if (framed) return true;
  }
  return false;
}

std::shared_ptr<SessionStream> ResumableSession::SwapIn(std::unique_ptr<SessionStream> stream,
                                                        std::shared_ptr<MoveTarget> target,
                                                        std::deque<v1::SessionEvent> first_events,
                                                        uint64_t replayed_upto,
                                                        uint64_t replayed_seq,
                                                        bool make_before_break) {
  std::lock_guard lock(mutex_);
  // What was sent on the old call meanwhile (logged after the replay). The
  // new call's first frame predates it: not shown (the old call may have
  // shown those updates already; the picture must not go back), and
  // frames are shown from the one that has them.
  uint64_t newest_seq = replayed_seq;
  for (const Logged& logged : log_) {
    if (logged.number <= replayed_upto) continue;
    stream->SendUpdate(logged.update);
    newest_seq = std::max(newest_seq, logged.update.seq());
  }
  const bool first_frame_current = newest_seq == replayed_seq;
  if (!first_frame_current) {
    std::erase_if(first_events, [](const v1::SessionEvent& e) { return e.has_frame(); });
  }
  RequestOwedFrames(*stream, make_before_break && first_frame_current, first_events);
  std::shared_ptr<SessionStream> old =
      std::exchange(stream_, std::shared_ptr<SessionStream>(std::move(stream)));
  targets_.push_back(std::move(target));
  pending_events_ = std::move(first_events);
  hide_below_seq_ = newest_seq;
  if (writes_closed_) stream_->CloseWrites();
  return old;
}

absl::Status ResumableSession::MoveTo(const std::string& reason, bool make_before_break) {
  const Clock::time_point start = Clock::now();
  BeginMove(reason, start);
  const auto give_up = start + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double>(resume_.give_up_after_s));
  auto backoff = std::chrono::milliseconds(100);
  absl::Status last;
  std::shared_ptr<MoveTarget> failed_target;
  for (int attempt = 1;; ++attempt) {
    {
      std::lock_guard lock(mutex_);
      moves_.back().attempts = attempt;
      if (writes_closed_ || cancelled_) return absl::CancelledError("closed during a move");
    }
    // A fresh channel (the old one's connection may still lead to the
    // server that drains), shared with the group's other sessions.
    ConnectionOptions options = resume_.connection;
    options.timeout_seconds = std::min(options.timeout_seconds, resume_.give_up_after_s);
    MoveGroup own;
    MoveGroup& group = resume_.group ? *resume_.group : own;
    absl::StatusOr<std::shared_ptr<MoveTarget>> target =
        group.Acquire(options, resume_.load, failed_target);
    absl::StatusOr<std::unique_ptr<SessionStream>> stream = absl::UnavailableError("no scene");
    if (target.ok()) {
      v1::SessionConfig config = config_;
      config.set_scene_id((*target)->scene->id());
      stream = SessionStream::Open((*target)->connection->stub(), config, server_);
      if (!stream.ok()) failed_target = *target;
    } else {
      stream = target.status();
    }
    std::deque<v1::SessionEvent> first_events;
    uint64_t replayed_upto = 0, replayed_seq = 0;
    size_t replayed = 0;
    if (stream.ok()) replayed = ReplayLog(**stream, &replayed_seq, &replayed_upto);
    // A drain: the old server still streams; switch once the new one has a
    // frame that shows the replayed updates (earlier ones would show the
    // scene as loaded: the block jumping back for a frame).
    if (stream.ok() && make_before_break &&
        !AwaitReplayedFrame(**stream, replayed_seq, first_events)) {
      const absl::Status ended = (*stream)->Finish();
      stream = ended.ok() ? absl::UnavailableError("the new session ended before a frame") : ended;
      failed_target = target.ok() ? *target : nullptr;
    }
    if (stream.ok()) {
      std::shared_ptr<SessionStream> old =
          SwapIn(*std::move(stream), *std::move(target), std::move(first_events), replayed_upto,
                 replayed_seq, make_before_break);
      Log(LogLevel::kInfo,
          absl::StrCat("session moved (", reason, ") after ", attempt, " attempt(s), ",
                       MsSince(start), " ms: replayed ", replayed, " update(s)"));
      old->Cancel();
      return absl::OkStatus();
    }
    last = stream.status();
    if (!ResumableStatus(last) && !absl::IsResourceExhausted(last) && !absl::IsNotFound(last)) {
      break;  // refused for itself: another try gets the same answer
    }
    if (Clock::now() + backoff > give_up) break;
    std::this_thread::sleep_for(backoff);
    backoff = std::min(backoff * 2, std::chrono::milliseconds(1000));
  }
  std::lock_guard lock(mutex_);
  moves_.back().error = DescribeStatus(last);
  move_started_.reset();
  return absl::Status(last.code(),
                      absl::StrCat("could not move the session (", reason, "): ", last.message()));
}

void ResumableSession::CloseWrites(std::chrono::milliseconds grace) {
  std::lock_guard lock(mutex_);
  writes_closed_ = true;
  stream_->CloseWrites(grace);
}

void ResumableSession::Cancel() {
  std::shared_ptr<SessionStream> stream;
  {
    std::lock_guard lock(mutex_);
    cancelled_ = true;
    stream = stream_;
  }
  stream->Cancel();
}

absl::Status ResumableSession::Finish() {
  std::lock_guard lock(mutex_);
  return final_status_;
}

bool ResumableSession::cancelled_by_client() const {
  std::lock_guard lock(mutex_);
  return last_cancelled_by_client_ || cancelled_;
}

bool ResumableSession::grace_expired() const {
  std::lock_guard lock(mutex_);
  return last_grace_expired_;
}

std::vector<ResumableSession::Move> ResumableSession::moves() const {
  std::lock_guard lock(mutex_);
  return moves_;
}

size_t ResumableSession::logged_updates() const {
  std::lock_guard lock(mutex_);
  return log_.size();
}

std::string FormatMove(const ResumableSession::Move& move) {
  std::string line = absl::StrFormat("moved at %.1f s (%s), %d attempt%s: ", move.at_s, move.reason,
                                     move.attempts, move.attempts == 1 ? "" : "s");
  if (!move.error.empty()) return absl::StrCat(line, "gave up: ", move.error);
  absl::StrAppend(&line, move.ms_to_frame
                             ? absl::StrFormat("the new server's first frame after %.0f ms "
                                               "(%.0f ms without frames)",
                                               *move.ms_to_frame, move.gap_ms.value_or(0.0))
                             : "no frame since");
  if (move.ms_to_acked) {
    absl::StrAppend(&line,
                    absl::StrFormat(", with every acknowledged update (seq %d) after %.0f ms",
                                    move.acked_seq, *move.ms_to_acked));
  }
  return line;
}

}  // namespace gistream::client
