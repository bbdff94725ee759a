// What `stream` and `script` share around a session: ending it cleanly and
// telling what was written.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <absl/strings/str_cat.h>

#include "commands.h"
#include "frame_writer.h"
#include "options.h"
#include "session_stream.h"
#include "util/log.h"
#include "util/status.h"

namespace gistream::client {

// A continuous session's config: scene, solver and its parameters, size,
// encoding, the fps cap, and the view's camera when the options set one.
v1::SessionConfig ContinuousConfig(const std::string& scene_id, const SolverOptions& solver,
                                   const ViewOptions& view, float max_fps);

// Half-closes the session (if not yet), drains what the server still
// sends, and finishes the call. OK when the server ended it normally, or
// when it ignored the half-close and the grace period cancelled it (a
// warning). InterruptedError() when the user's second Ctrl-C cancelled it;
// the server's status otherwise.
// Either stream type (SessionStream, ResumableSession).
template <typename Stream>
absl::Status EndSession(Stream& stream) {
  stream.CloseWrites();
  v1::SessionEvent event;
  while (stream.Next(&event)) {
    if (event.has_rejected()) {
      Log(LogLevel::kWarning, absl::StrCat("update seq ", event.rejected().seq(),
                                           " rejected: ", event.rejected().message()));
    }
  }
  const absl::Status status = stream.Finish();
  if (status.ok() || !stream.cancelled_by_client() || !absl::IsCancelled(status)) return status;
  if (stream.grace_expired()) {
    Log(LogLevel::kWarning,
        "the server did not end the session after the client's half-close; cancelled it");
    return absl::OkStatus();
  }
  return InterruptedError();
}

// "wrote 30 frames to out (frame_00000.jpg .. frame_00029.jpg)"; for a
// video format, "wrote P pictures to out/stream.h264 (N frames received)"
// where `pictures` counts the frames that carried an image (default: all).
std::string FormatWrittenFrames(const FrameWriter& writer, uint64_t count, v1::ImageFormat format,
                                std::optional<uint64_t> pictures = std::nullopt);

// A frame's solver/engine stat by name (Frame.stats), 0 when absent.
double FrameStatValue(const v1::Frame& frame, const std::string& name);

// What the last frame's picture had converged to (issue 27): "last
// picture: refined 16/16 samples per pixel, GI complete, at rest; 3.2 s
// since the camera moved, 5.0 s since the scene changed".
std::string FormatConvergence(const v1::Frame& last);

// One line for an update, for messages: "node_transform (node 7)".
std::string DescribeUpdate(const v1::Update& update);

}  // namespace gistream::client
