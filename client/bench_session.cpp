#include "bench_session.h"

#include <absl/strings/str_cat.h>

#include "connection.h"

namespace gistream::client {

BenchSession::~BenchSession() {
  StopUpdates();
  if (stream_) stream_->Cancel();
  if (sender_.joinable()) sender_.join();
  if (reader_.joinable()) reader_.join();
}

absl::Status BenchSession::Open(v1::Gistream::Stub& stub, const v1::SessionConfig& config,
                                ResumeOptions resume) {
  absl::StatusOr<std::unique_ptr<ResumableSession>> stream =
      ResumableSession::Open(stub, config, server_, std::move(resume));
  if (!stream.ok()) {
    std::lock_guard lock(mutex_);
    error_ = DescribeStatus(stream.status());
    return stream.status();
  }
  stream_ = *std::move(stream);
  reader_ = std::thread([this] { ReadLoop(); });
  if (update_hz_ > 0.0) sender_ = std::thread([this] { SendLoop(); });
  return absl::OkStatus();
}

bool BenchSession::failed() const {
  std::lock_guard lock(mutex_);
  return !error_.empty();
}

void BenchSession::SetWindow(BenchClock::time_point start, BenchClock::time_point end) {
  std::lock_guard lock(mutex_);
  window_set_ = true;
  window_start_ = start;
  window_end_ = end;
  intervals_ = std::make_unique<FrameIntervals>(start, end);
}

void BenchSession::StopUpdates() {
  {
    std::lock_guard lock(mutex_);
    if (!stop_updates_) stopped_at_ = BenchClock::now();
    stop_updates_ = true;
  }
  stop_cv_.notify_all();
}

bool BenchSession::Settled() const {
  std::lock_guard lock(mutex_);
  return settle_ms_.has_value() || !error_.empty();
}

size_t BenchSession::Unanswered() const {
  std::lock_guard lock(mutex_);
  return tracker_.unanswered();
}

int BenchSession::LiveFrames() const {
  std::lock_guard lock(mutex_);
  return live_frames_;
}

void BenchSession::AppendLatencies(std::vector<double>& out) const {
  std::lock_guard lock(mutex_);
  out.insert(out.end(), tracker_.latencies_ms().begin(), tracker_.latencies_ms().end());
}

void BenchSession::SendTick() {
  std::vector<v1::Update> updates = workload_.UpdatesForTick(tick_++);
  for (v1::Update& update : updates) {
    uint64_t seq = 0;
    {
      std::lock_guard lock(mutex_);
      if (stop_updates_) return;
      seq = next_seq_++;
      last_seq_sent_ = seq;
      if (keep_settle_frames_) {
        sent_.push_back(update);
        sent_.back().set_seq(seq);
      }
      const BenchClock::time_point now = BenchClock::now();
      const bool measured = window_set_ && now >= window_start_ && now < window_end_;
      // Registered before the send: the answering frame may come back
      // before SendUpdate returns.
      tracker_.OnSend(seq, now, measured);
      if (measured) ++updates_sent_;
    }
    update.set_seq(seq);
    if (!stream_->SendUpdate(update)) return;  // the call ended; the reader reports why
  }
}

void BenchSession::SendLoop() {
  // Open loop: ticks on a fixed schedule from the first frame on, whatever
  // the frames do. A sender that falls behind skips the missed ticks
  // instead of bursting.
  while (!first_frame_ && !stop_updates_) {
    std::unique_lock lock(mutex_);
    stop_cv_.wait_for(lock, std::chrono::milliseconds(20));
  }
  const auto period = std::chrono::duration_cast<BenchClock::duration>(
      std::chrono::duration<double>(1.0 / update_hz_));
  BenchClock::time_point next = BenchClock::now();
  while (!stop_updates_) {
    SendTick();
    next += period;
    const BenchClock::time_point now = BenchClock::now();
    if (next < now) next = now;
    std::unique_lock lock(mutex_);
    stop_cv_.wait_until(lock, next, [this] { return stop_updates_.load(); });
  }
}

void BenchSession::ReadLoop() {
  v1::SessionEvent event;
  while (stream_->Next(&event)) {
    const BenchClock::time_point now = BenchClock::now();
    if (event.has_rejected()) {
      std::lock_guard lock(mutex_);
      tracker_.OnRejected(event.rejected().seq());
      continue;
    }
    if (!event.has_frame()) continue;
    const v1::Frame& frame = event.frame();
    // A stat of the frame, `absent` where an older server does not send it.
    const auto stat = [&](const char* name, double absent) {
      const auto it = frame.stats().find(name);
      return it == frame.stats().end() ? absent : it->second;
    };
    // The GI update is complete and the still picture refined
    // (refine_samples reached refine_target).
    const bool complete = stat("update_complete", 1.0) != 0.0 &&
                          stat("refine_samples", 1.0) >= stat("refine_target", 1.0);
    {
      std::lock_guard lock(mutex_);
      if (keep_settle_frames_ && !frame.image().empty()) last_image_ = frame.image();
      if (keep_settle_frames_ && window_set_ && now >= window_start_) {
        traced_frames_.push_back(
            {std::chrono::duration<double, std::milli>(now - window_start_).count(),
             frame.frame_number(), frame.last_update_seq(), stop_updates_.load(), last_image_,
             stat("update_complete", 1.0), stat("at_rest", 0.0),
             stat("frames_since_scene_change", 0.0), stat("refine_samples", 1.0)});
      }
      tracker_.OnFrame(frame.last_update_seq(), now);
      if (stop_updates_ && !settle_ms_ && frame.last_update_seq() >= last_seq_sent_) {
        const double ms = std::chrono::duration<double, std::milli>(now - stopped_at_).count();
        // A still frame (no image: the pixels did not change) shows the last.
        if (keep_settle_frames_) {
          settle_frames_.push_back({ms, frame.image().empty() ? last_image_ : frame.image()});
        }
        if (complete) settle_ms_ = ms;  // settled
      }
      if (window_set_ && intervals_->Add(now)) {
        ++live_frames_;
        dropped_ += frame.dropped_frames();
        bytes_ += frame.image().size();
        std::lock_guard stages_lock(stages_.mutex);
        stages_.collector.Add(frame, now);
      }
    }
    // Measuring error over time (keep_settle_frames_, --reference-spp),
    // the interaction starts from the picture a viewer was looking at: updates
    // wait for the first complete frame (a continuous stream of moves
    // before it measured the first solve's wait, not catching up).
    if (!keep_settle_frames_ || complete) first_frame_ = true;
    if (!first_frame_) continue;
    // Closed loop: the next tick's updates go out as each frame arrives
    // (the first right after the first frame).
    if (update_hz_ <= 0.0 && !stop_updates_) SendTick();
  }
  const absl::Status status = stream_->Finish();
  if (!status.ok() && !stream_->cancelled_by_client()) {
    std::lock_guard lock(mutex_);
    error_ = DescribeStatus(status);
  }
}

void BenchSession::Close() {
  StopUpdates();
  if (sender_.joinable()) sender_.join();
  if (stream_) stream_->CloseWrites(std::chrono::seconds(10));
  if (reader_.joinable()) reader_.join();
}

std::vector<BenchSession::SettleFrame> BenchSession::SettleFrames() const {
  std::lock_guard lock(mutex_);
  return settle_frames_;
}

std::vector<BenchSession::TracedFrame> BenchSession::TracedFrames() const {
  std::lock_guard lock(mutex_);
  return traced_frames_;
}

std::vector<v1::Update> BenchSession::StateOfSeq(uint64_t seq) const {
  std::lock_guard lock(mutex_);
  std::vector<v1::Update> state;
  for (const v1::Update& u : sent_) {
    if (u.seq() > seq) break;  // sent in seq order
    state.push_back(u);
  }
  return state;
}

std::vector<v1::Update> BenchSession::LastState() const {
  std::lock_guard lock(mutex_);
  return sent_;
}

SessionMeasurement BenchSession::Result() const {
  std::lock_guard lock(mutex_);
  SessionMeasurement m;
  m.server = server_;
  m.window_s = std::chrono::duration<double>(window_end_ - window_start_).count();
  if (intervals_) intervals_->Finish(m);
  m.dropped_frames = dropped_;
  m.bytes = bytes_;
  m.updates_sent = updates_sent_;
  m.updates_rejected = tracker_.rejected();
  m.updates_unanswered = tracker_.unanswered();
  m.latencies_ms = tracker_.latencies_ms();
  m.settle_ms = settle_ms_;
  m.error = error_;
  if (stream_) {
    for (const ResumableSession::Move& move : stream_->moves()) {
      m.moves += 1;
      if (move.gap_ms) m.move_gap_ms.push_back(*move.gap_ms);
      if (move.ms_to_acked) m.move_to_acked_ms.push_back(*move.ms_to_acked);
    }
  }
  return m;
}

}  // namespace gistream::client
