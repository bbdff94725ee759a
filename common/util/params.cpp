#include "util/params.h"
#include "util/user_string.h"

#include <absl/strings/str_join.h>

#include <charconv>
#include <cmath>
#include <limits>

namespace gistream {
namespace {

// The whole string must be a number: no spaces, no leading '+', no suffix.
template <typename T>
bool ParseWhole(const std::string& text, T* out) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, *out);
  return !text.empty() && ec == std::errc() && ptr == end;
}

std::string FormatDouble(double v) {
  char buf[32];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof(buf), v);  // shortest round trip
  return std::string(buf, ptr);
}

// Returns the canonical spelling of `value`, or an error naming the field.
absl::StatusOr<std::string> Canonical(const ParamSpec& spec, const std::string& value,
                                      const std::string& field) {
  switch (spec.type) {
    case ParamType::kInt: {
      long long v = 0;
      if (!ParseWhole(value, &v)) {
        return absl::InvalidArgumentError(
            absl::StrCat(field, ": '", Echo(value), "' is not an integer"));
      }
      if (double(v) < spec.min || double(v) > spec.max || v < std::numeric_limits<int>::min() ||
          v > std::numeric_limits<int>::max()) {
        return absl::InvalidArgumentError(absl::StrCat(field, ": ", v, " is out of range [",
                                                       FormatDouble(spec.min), ", ",
                                                       FormatDouble(spec.max), "]"));
      }
      if (spec.multiple_of > 1 && v % spec.multiple_of != 0) {
        return absl::InvalidArgumentError(
            absl::StrCat(field, ": ", v, " is not a multiple of ", spec.multiple_of));
      }
      return std::to_string(v);
    }
    case ParamType::kFloat: {
      double v = 0.0;
      if (!ParseWhole(value, &v)) {
        return absl::InvalidArgumentError(
            absl::StrCat(field, ": '", Echo(value), "' is not a number"));
      }
      if (!std::isfinite(v)) {
        return absl::InvalidArgumentError(
            absl::StrCat(field, ": '", Echo(value), "' is not finite"));
      }
      if (v < spec.min || v > spec.max) {
        return absl::InvalidArgumentError(absl::StrCat(field, ": ", value, " is out of range [",
                                                       FormatDouble(spec.min), ", ",
                                                       FormatDouble(spec.max), "]"));
      }
      return FormatDouble(v);
    }
    case ParamType::kBool:
      if (value == "true" || value == "1") return std::string("true");
      if (value == "false" || value == "0") return std::string("false");
      return absl::InvalidArgumentError(
          absl::StrCat(field, ": '", Echo(value), "' is not a boolean (true, false, 1, 0)"));
    case ParamType::kEnum:
      for (const std::string& choice : spec.choices) {
        if (value == choice) return value;
      }
      return absl::InvalidArgumentError(absl::StrCat(field, ": '", Echo(value), "' is not one of ",
                                                     absl::StrJoin(spec.choices, ", ")));
  }
  return absl::InternalError(absl::StrCat(field, ": unknown parameter type"));
}

const std::string& Value(const std::map<std::string, std::string>& values,
                         const std::string& name) {
  const auto it = values.find(name);
  if (it == values.end()) CheckFailed(__FILE__, __LINE__, ("unknown parameter " + name).c_str());
  return it->second;
}

}  // namespace

absl::StatusOr<ParamSet> ValidateParams(const std::string& owner,
                                        const std::vector<ParamSpec>& schema,
                                        const std::map<std::string, std::string>& given) {
  for (const auto& [name, value] : given) {
    bool known = false;
    for (const ParamSpec& spec : schema) known = known || spec.name == name;
    if (!known) {
      std::vector<std::string> names;
      for (const ParamSpec& spec : schema) names.push_back(spec.name);
      return absl::InvalidArgumentError(
          absl::StrCat("params.", Echo(name), ": unknown parameter of ", owner,
                       " (known: ", names.empty() ? "none" : absl::StrJoin(names, ", "), ")"));
    }
  }
  ParamSet set;
  for (const ParamSpec& spec : schema) {
    const auto it = given.find(spec.name);
    const bool is_default = it == given.end();
    const std::string field = absl::StrCat("params.", spec.name, is_default ? " (default)" : "");
    GS_ASSIGN_OR_RETURN(set.values_[spec.name],
                        Canonical(spec, is_default ? spec.default_value : it->second, field));
  }
  return set;
}

int ParamSet::GetInt(const std::string& name) const {
  int v = 0;
  GS_CHECK(ParseWhole(Value(values_, name), &v));
  return v;
}

double ParamSet::GetFloat(const std::string& name) const {
  double v = 0.0;
  GS_CHECK(ParseWhole(Value(values_, name), &v));
  return v;
}

bool ParamSet::GetBool(const std::string& name) const { return Value(values_, name) == "true"; }

const std::string& ParamSet::GetString(const std::string& name) const {
  return Value(values_, name);
}

std::string ParamSet::Key() const {
  std::string key;
  for (const auto& [name, value] : values_) {
    absl::StrAppend(&key, key.empty() ? "" : ";", name, "=", value);
  }
  return key;
}

}  // namespace gistream
