// gistream's version as both binaries print it (`--version`) and the server
// reports it (ServerStatus.version): CMake's project version, plus
// "+<git commit>" when the build ran in a git checkout ("0.1.0+b28fa76a1c2d").
#pragma once

#include <string_view>

namespace gistream {

std::string_view Version();

}  // namespace gistream
