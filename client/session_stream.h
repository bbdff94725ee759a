// One Session call (bidirectional stream) with the bookkeeping the sync
// gRPC API leaves to us: config first, `opened` before anything else,
// writes serialized, half-close with a grace period, and a destructor that
// always cancels, drains and finishes the call.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>

#include <absl/strings/string_view.h>
#include <grpcpp/grpcpp.h>

#include "gistream/v1/gistream.grpc.pb.h"
#include "util/status.h"

namespace gistream::client {

class SessionStream {
 public:
  using Clock = std::chrono::steady_clock;

  // Starts the call, sends `config` and waits for `opened`. An invalid
  // config comes back as the call's status (INVALID_ARGUMENT naming the
  // field). `server` only names the address in errors.
  static absl::StatusOr<std::unique_ptr<SessionStream>> Open(v1::Gistream::Stub& stub,
                                                             const v1::SessionConfig& config,
                                                             absl::string_view server);
  ~SessionStream();
  SessionStream(const SessionStream&) = delete;
  SessionStream& operator=(const SessionStream&) = delete;

  const v1::SessionOpened& opened() const { return opened_; }

  // Thread-safe among themselves and with CloseWrites. False once writes
  // are closed or the call has ended (Next then returns false too).
  bool SendUpdate(const v1::Update& update);
  bool RequestFrame(uint32_t count = 1);

  // Blocks for the next event; false at the end of the call. One reader.
  bool Next(v1::SessionEvent* event);

  // Half-closes the call: no more requests. If the server has not ended
  // the call `grace` later, it is cancelled. Idempotent; does not block on
  // the server (safe from an interrupt handler when nothing else writes).
  void CloseWrites(std::chrono::milliseconds grace = std::chrono::seconds(5));

  // Cancels the call now; pending Next calls return false. Thread-safe.
  void Cancel();

  // After Next returned false: the call's status. A cancel this object
  // made (Cancel, or CloseWrites's grace running out) is not an error of
  // the server: see cancelled_by_client().
  absl::Status Finish();
  bool cancelled_by_client() const { return cancelled_by_client_; }
  // True when CloseWrites's grace period ran out.
  bool grace_expired() const { return grace_expired_; }

 private:
  explicit SessionStream(std::string server) : server_(std::move(server)) {}
  bool Send(const v1::SessionRequest& request);

  const std::string server_;
  grpc::ClientContext context_;
  std::unique_ptr<grpc::ClientReaderWriter<v1::SessionRequest, v1::SessionEvent>> stream_;
  v1::SessionOpened opened_;

  std::mutex write_mutex_;
  bool writes_closed_ = false;  // guarded by write_mutex_

  std::mutex watchdog_mutex_;
  std::condition_variable watchdog_cv_;
  bool finished_ = false;  // guarded by watchdog_mutex_
  std::thread watchdog_;

  bool reads_done_ = false;
  bool status_taken_ = false;
  std::atomic<bool> cancelled_by_client_{false};
  std::atomic<bool> grace_expired_{false};
};

}  // namespace gistream::client
