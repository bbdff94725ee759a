#include "session_stream.h"

#include <absl/strings/str_cat.h>

#include "connection.h"

namespace gistream::client {

absl::StatusOr<std::unique_ptr<SessionStream>> SessionStream::Open(v1::Gistream::Stub& stub,
                                                                   const v1::SessionConfig& config,
                                                                   absl::string_view server) {
  std::unique_ptr<SessionStream> session(new SessionStream(std::string(server)));
  session->stream_ = stub.Session(&session->context_);

  v1::SessionRequest request;
  *request.mutable_config() = config;
  v1::SessionEvent event;
  if (!session->Send(request) || !session->Next(&event)) {
    // The server ended the call (e.g. INVALID_ARGUMENT for the config).
    absl::Status status = session->Finish();
    if (status.ok()) status = absl::UnavailableError("the server closed the session at once");
    return status;
  }
  if (!event.has_opened()) {
    session->Cancel();
    return absl::InternalError(
        absl::StrCat("protocol error: the server's first session event is not `opened` but ",
                     event.GetDescriptor()->FindFieldByNumber(event.event_case())->name()));
  }
  session->opened_ = event.opened();
  return session;
}

SessionStream::~SessionStream() {
  if (!status_taken_) {
    Cancel();
    v1::SessionEvent ignored;
    while (Next(&ignored)) {
    }
    Finish().IgnoreError();
  }
  if (watchdog_.joinable()) watchdog_.join();
}

bool SessionStream::Send(const v1::SessionRequest& request) {
  std::lock_guard lock(write_mutex_);
  if (writes_closed_) return false;
  if (!stream_->Write(request)) {
    writes_closed_ = true;  // the call is over; Next/Finish tell why
    return false;
  }
  return true;
}

bool SessionStream::SendUpdate(const v1::Update& update) {
  v1::SessionRequest request;
  *request.mutable_update() = update;
  return Send(request);
}

bool SessionStream::RequestFrame(uint32_t count) {
  v1::SessionRequest request;
  request.mutable_request_frame()->set_count(count);
  return Send(request);
}

bool SessionStream::Next(v1::SessionEvent* event) {
  if (reads_done_) return false;
  if (!stream_->Read(event)) {
    reads_done_ = true;
    return false;
  }
  return true;
}

void SessionStream::CloseWrites(std::chrono::milliseconds grace) {
  {
    std::lock_guard lock(write_mutex_);
    if (writes_closed_) return;
    writes_closed_ = true;
    stream_->WritesDone();
  }
  watchdog_ = std::thread([this, grace] {
    std::unique_lock lock(watchdog_mutex_);
    if (!watchdog_cv_.wait_for(lock, grace, [this] { return finished_; })) {
      grace_expired_ = true;
      Cancel();
    }
  });
}

void SessionStream::Cancel() {
  cancelled_by_client_ = true;
  context_.TryCancel();
}

absl::Status SessionStream::Finish() {
  GS_CHECK(!status_taken_);
  status_taken_ = true;
  const grpc::Status status = stream_->Finish();
  {
    std::lock_guard lock(watchdog_mutex_);
    finished_ = true;
  }
  watchdog_cv_.notify_all();
  return FromGrpc(status, server_);
}

}  // namespace gistream::client
