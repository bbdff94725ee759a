// Events an operator counts, in domain terms (no gRPC, no Prometheus): the
// engine reports the work it does (frames produced, with their timings), the
// gRPC layer reports what clients were told (frames dropped for a slow
// reader, updates rejected, calls that failed). server/metrics/ implements
// this to feed the Prometheus endpoint; tests may implement it to count.
//
// Every method may be called from any thread (the render thread, gRPC's
// threads, the worker pool), concurrently: implementations must be
// thread-safe, must not block, and must not call back into the Engine.
#pragma once

#include <cstdint>
#include <string_view>

#include <absl/status/status.h>

namespace gistream {

struct EncodedFrame;

class ServerObserver {
 public:
  virtual ~ServerObserver() = default;

  // Engine (render thread): a frame was produced, for a session or a
  // Render call; frame.solver, total_ms and timings are filled in.
  virtual void OnFrameRendered(const EncodedFrame& /*frame*/) {}
  // gRPC layer: `count` frames were replaced by newer ones before they
  // were written to their (slow) client.
  virtual void OnFramesDropped(uint64_t /*count*/) {}
  // gRPC layer: an update was answered with UpdateRejected (bad field,
  // unknown id, or refused when applied); the session went on.
  virtual void OnUpdateRejected(absl::StatusCode /*code*/) {}
  // gRPC layer: a call (`method`: "LoadScene", "Session", ...) ended with a
  // status other than OK.
  virtual void OnRpcFailed(std::string_view /*method*/, absl::StatusCode /*code*/) {}
  // gRPC layer: a call ended, with any status (OK included).
  virtual void OnRpcFinished(std::string_view /*method*/, absl::StatusCode /*code*/) {}
  // gRPC layer: a frame's image of `bytes` was handed to a client's stream
  // (a session's frame or a Render's answer).
  virtual void OnFrameSent(uint64_t /*bytes*/) {}
  // gRPC layer: the first frame showing an update (its sequence number
  // echoed) was handed to the client `seconds` after the update arrived.
  virtual void OnUpdateAnswered(double /*seconds*/) {}
};

}  // namespace gistream
