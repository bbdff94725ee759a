// Parameter schemas and validated parameter sets, for anything that takes
// named parameters (solvers, the direct-light estimator they share).
// Parameters travel as strings (as on the command line: --param key=value)
// and are checked against the schema: type, range, choices.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "util/status.h"

namespace gistream {

enum class ParamType { kInt, kFloat, kBool, kEnum };

struct ParamSpec {
  std::string name;
  ParamType type = ParamType::kFloat;
  std::string default_value;
  double min = 0.0;  // kInt, kFloat
  double max = 0.0;
  std::vector<std::string> choices;  // kEnum
  std::string description;           // one line
  int multiple_of = 1;               // kInt: values must be multiples of this
};

// Parameter values after validation: every schema entry present.
class ParamSet {
 public:
  int GetInt(const std::string& name) const;
  double GetFloat(const std::string& name) const;
  bool GetBool(const std::string& name) const;
  const std::string& GetString(const std::string& name) const;
  const std::map<std::string, std::string>& values() const { return values_; }
  // Canonical "k=v;k=v" form, used as a cache key.
  std::string Key() const;

 private:
  friend absl::StatusOr<ParamSet> ValidateParams(const std::string&, const std::vector<ParamSpec>&,
                                                 const std::map<std::string, std::string>&);
  std::map<std::string, std::string> values_;
};

// INVALID_ARGUMENT naming "params.NAME" for unknown names (the message
// names `owner`, e.g. "solver 'avg'"), bad types, values out of range;
// defaults fill what is not given.
absl::StatusOr<ParamSet> ValidateParams(const std::string& owner,
                                        const std::vector<ParamSpec>& schema,
                                        const std::map<std::string, std::string>& given);

}  // namespace gistream
