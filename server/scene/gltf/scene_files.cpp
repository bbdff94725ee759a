#include "scene/gltf/scene_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "scene/gltf/gltf_import.h"
#include "util/user_string.h"

namespace gistream {
namespace fs = std::filesystem;
namespace {

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// True when `inner` is `outer` or lies below it (both canonical).
bool IsWithin(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (o->empty()) continue;  // trailing separator
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

}  // namespace

absl::StatusOr<std::string> PercentDecode(const std::string& uri, const std::string& field) {
  std::string out;
  out.reserve(uri.size());
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] != '%') {
      out += uri[i];
      continue;
    }
    const int hi = i + 2 < uri.size() ? HexValue(uri[i + 1]) : -1;
    const int lo = i + 2 < uri.size() ? HexValue(uri[i + 2]) : -1;
    if (hi < 0 || lo < 0) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ": malformed %-escape at offset ", i, " of '", Echo(uri), "'"));
    }
    const char c = static_cast<char>(hi * 16 + lo);
    if (c == '\0') {
      return absl::InvalidArgumentError(absl::StrCat(field, ": '", Echo(uri), "' contains %00"));
    }
    out += c;
    i += 2;
  }
  return out;
}

absl::StatusOr<fs::path> ResolveScenePath(const fs::path& base_dir, const std::string& path,
                                          const std::string& field) {
  if (base_dir.empty()) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": external file '", Echo(path),
                     "' refused: a scene sent as bytes may only use data: URIs (or use a .glb)"));
  }
  if (path.empty()) return absl::InvalidArgumentError(absl::StrCat(field, ": empty URI"));
  if (path.find('\0') != std::string::npos || path.find('\\') != std::string::npos) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": '", Echo(path), "' contains a NUL or a backslash"));
  }
  const fs::path relative(path);
  if (relative.is_absolute() || relative.has_root_name() || path.front() == '/') {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": absolute path '", Echo(path), "' refused; URIs must be relative"));
  }
  const size_t colon = path.find(':');
  if (colon != std::string::npos && path.find('/') > colon) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": URI scheme '",
                                                   Echo(path.substr(0, colon)),
                                                   "' is not supported (only data: URIs"
                                                   " and relative paths)"));
  }
  for (const fs::path& part : relative) {
    if (part == "..") {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ": '", Echo(path), "' refused: '..' is not allowed in scene URIs"));
    }
  }
  std::error_code ec;
  const fs::path base = fs::canonical(base_dir, ec);
  if (ec) {
    return absl::FailedPreconditionError(absl::StrCat(
        field, ": scene directory '", base_dir.string(), "' is not usable: ", ec.message()));
  }
  // weakly_canonical follows every symlink that exists, so a link inside the
  // scene directory that points outside it is caught here.
  const fs::path resolved = fs::weakly_canonical(base / relative, ec);
  if (ec || !IsWithin(resolved, base)) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": '", Echo(path), "' resolves outside the scene directory"));
  }
  return resolved;
}

absl::StatusOr<fs::path> ResolveSceneUri(const fs::path& base_dir, const std::string& uri,
                                         const std::string& field) {
  GS_ASSIGN_OR_RETURN(const std::string decoded, PercentDecode(uri, field));
  return ResolveScenePath(base_dir, decoded, field);
}

absl::StatusOr<std::vector<uint8_t>> ReadFileLimited(const fs::path& path, uint64_t max_bytes,
                                                     const std::string& field) {
  const std::string name = Echo(path.filename().string());
  // O_NONBLOCK: opening a FIFO (or a device) for reading would otherwise
  // block until a writer appears, wedging the caller forever. The checks
  // run on the opened descriptor, so the file cannot be swapped between
  // check and read.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    const int err = errno;
    if (err == ENOENT || err == ENOTDIR) {
      return absl::NotFoundError(absl::StrCat(field, ": '", name, "' does not exist"));
    }
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": cannot open '", name, "': ", std::strerror(err)));
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": cannot stat '", name, "': ", std::strerror(errno)));
  }
  if (!S_ISREG(st.st_mode)) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": '", name, "' is not a regular file"));
  }
  const uint64_t size = static_cast<uint64_t>(st.st_size);
  if (size > max_bytes) {
    return absl::ResourceExhaustedError(absl::StrCat(field, ": '", name, "' has ", size,
                                                     " bytes, over the remaining scene budget of ",
                                                     max_bytes, " bytes"));
  }
  std::vector<uint8_t> bytes(size);
  size_t done = 0;
  while (done < size) {
    const ssize_t n = ::read(fd, bytes.data() + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<size_t>(n);
  }
  char extra = 0;
  if (done != size || ::read(fd, &extra, 1) != 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": '", name, "' changed or could not be read"));
  }
  return bytes;
}

}  // namespace gistream
