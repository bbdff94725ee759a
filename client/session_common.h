// What `stream` and `script` share around a session: ending it cleanly and
// telling what was written.
#pragma once

#include <cstdint>
#include <string>

#include "frame_writer.h"
#include "session_stream.h"
#include "util/status.h"

namespace gistream::client {

// Half-closes the session (if not yet), drains what the server still
// sends, and finishes the call. OK when the server ended it normally, or
// when it ignored the half-close and the grace period cancelled it (a
// warning). InterruptedError() when the user's second Ctrl-C cancelled it;
// the server's status otherwise.
absl::Status EndSession(SessionStream& stream);

// "wrote 30 frames to out (frame_00000.jpg .. frame_00029.jpg)"
std::string FormatWrittenFrames(const FrameWriter& writer, uint64_t count, v1::ImageFormat format);

// One line for an update, for messages: "node_transform (node 7)".
std::string DescribeUpdate(const v1::Update& update);

}  // namespace gistream::client
