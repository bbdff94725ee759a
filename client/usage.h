// Help texts for `gistream --help` and `gistream COMMAND --help`.
#pragma once

#include <optional>

#include <absl/strings/string_view.h>

#include "options.h"

namespace gistream::client {

// The overview when `command` is empty; ends with '\n'.
absl::string_view HelpText(std::optional<Command> command);

}  // namespace gistream::client
