// A small GNU-style flag scanner: `--name value`, `--name=value`, boolean
// `--name`, repeatable flags, positional arguments, and `--` to end flags.
// It knows nothing about gistream's commands (options.h does).
#pragma once

#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <absl/strings/string_view.h>

#include "util/status.h"

namespace gistream::client {

struct FlagSpec {
  absl::string_view name;  // without the leading "--"
  bool takes_value = true;
  bool repeatable = false;
};

class ParsedFlags {
 public:
  bool Has(absl::string_view name) const { return values_.count(std::string(name)) != 0; }
  // The value given (the last one for a repeatable flag).
  std::optional<std::string> Get(absl::string_view name) const;
  // Every value in command-line order; empty when not given.
  std::vector<std::string> GetAll(absl::string_view name) const;
  const std::vector<std::string>& positional() const { return positional_; }

 private:
  friend absl::StatusOr<ParsedFlags> ParseFlags(std::span<const std::string>,
                                                std::span<const FlagSpec>);
  std::map<std::string, std::vector<std::string>> values_;
  std::vector<std::string> positional_;
};

// INVALID_ARGUMENT for an unknown flag, a missing value, a value given to a
// boolean flag, or a non-repeatable flag given twice.
absl::StatusOr<ParsedFlags> ParseFlags(std::span<const std::string> args,
                                       std::span<const FlagSpec> specs);

}  // namespace gistream::client
