// Argument checks shared by the encoders.
#pragma once

#include <absl/strings/string_view.h>

#include <cstddef>

#include "util/status.h"

namespace gistream {

// width, height > 0 and `elements` == width * height * channels.
absl::Status CheckImageArgs(size_t elements, int width, int height, int channels,
                            absl::string_view what);

}  // namespace gistream
