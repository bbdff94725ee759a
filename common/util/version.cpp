#include "util/version.h"

#include "gistream_version.h"  // generated into the build tree by cmake/GitVersion.cmake

namespace gistream {

std::string_view Version() { return GISTREAM_VERSION; }

}  // namespace gistream
