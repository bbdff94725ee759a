// What `gistream solvers` prints: per solver its description, stages and a
// parameter table (name | type | default | range | meaning).
#pragma once

#include <string>

#include "gistream/v1/gistream.pb.h"

namespace gistream::client {

std::string FormatSolverList(const v1::ListSolversResponse& solvers);

// "[1, 1024]", "[0, 1]", "true|false", "a|b|c"; "-" when unbounded.
std::string FormatParamRange(const v1::ParamSpec& param);

}  // namespace gistream::client
