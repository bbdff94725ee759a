#include "file_io.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include <absl/strings/str_cat.h>

namespace gistream::client {

absl::StatusOr<std::string> ReadFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    return absl::NotFoundError(absl::StrCat(path.string(), ": no such file"));
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  if (!in || !(bytes << in.rdbuf())) {
    return absl::UnavailableError(
        absl::StrCat(path.string(), ": cannot read: ", std::strerror(errno)));
  }
  return std::move(bytes).str();
}

absl::Status WriteFile(const std::filesystem::path& path, absl::string_view bytes) {
  std::error_code ec;
  if (path.has_parent_path()) {
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec) {
      return absl::PermissionDeniedError(
          absl::StrCat(path.parent_path().string(), ": cannot create directory: ", ec.message()));
    }
  }
  std::filesystem::path temporary = path;
  temporary += ".part";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::filesystem::remove(temporary, ec);
      return absl::PermissionDeniedError(
          absl::StrCat(path.string(), ": cannot write: ", std::strerror(errno)));
    }
  }
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    return absl::PermissionDeniedError(
        absl::StrCat(path.string(), ": cannot write: ", ec.message()));
  }
  return absl::OkStatus();
}

}  // namespace gistream::client
