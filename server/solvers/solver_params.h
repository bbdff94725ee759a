// Solver parameter schema and validated parameter sets. Parameters travel
// as strings (as on the command line: --param key=value) and are checked
// against the schema: type, range, choices.
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

struct SolverDescription {
  std::string name;
  std::string description;
  std::vector<std::string> stages;
  std::vector<ParamSpec> params;
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
  friend absl::StatusOr<ParamSet> ValidateParams(const SolverDescription&,
                                                 const std::map<std::string, std::string>&);
  std::map<std::string, std::string> values_;
};

// INVALID_ARGUMENT naming "params.NAME" for unknown names, bad types, values
// out of range; defaults fill what is not given.
absl::StatusOr<ParamSet> ValidateParams(const SolverDescription& solver,
                                        const std::map<std::string, std::string>& given);

}  // namespace gistream
