// What `render` prints about the one frame it got back:
//
//   wrote out.png: 320x240 png, 81.2 KiB, solver direct, frame 1, scene version 1, 12.34 ms
//     stage       | CPU ms | GPU ms
//     ------------+--------+-------
//     shadow_maps |   0.04 |   0.81
//     ...
#pragma once

#include <string>

#include <absl/strings/string_view.h>

#include "gistream/v1/gistream.pb.h"

namespace gistream::client {

std::string FormatFrameReport(const v1::Frame& frame, absl::string_view written_to);

// "session 7 on scene 3: solver direct (area_samples=16, ...)"
std::string FormatSessionOpened(const v1::SessionOpened& opened);

// "81.2 KiB", "1.4 MiB", "512 B".
std::string FormatBytes(uint64_t bytes);

}  // namespace gistream::client
