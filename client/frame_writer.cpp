#include "frame_writer.h"

#include <cstdio>
#include <system_error>

#include <absl/strings/str_cat.h>

#include "file_io.h"
#include "image_format.h"

namespace gistream::client {

absl::StatusOr<FrameWriter> FrameWriter::Create(const std::filesystem::path& dir,
                                                v1::ImageFormat requested) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir, ec)) {
    return absl::FailedPreconditionError(absl::StrCat(dir.string(),
                                                      ": cannot create output directory",
                                                      ec ? absl::StrCat(": ", ec.message()) : ""));
  }
  return FrameWriter(dir, requested);
}

std::filesystem::path FrameWriter::PathFor(uint64_t index, v1::ImageFormat format) const {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%05llu", static_cast<unsigned long long>(index));
  return dir_ / absl::StrCat(name, ImageFormatExtension(format));
}

absl::Status FrameWriter::Write(uint64_t index, const v1::Frame& frame) const {
  if (frame.image().empty()) {
    return absl::InternalError(
        absl::StrCat("frame ", frame.frame_number(), " arrived without image bytes"));
  }
  const v1::ImageFormat format =
      frame.format() == v1::IMAGE_FORMAT_UNSPECIFIED ? requested_ : frame.format();
  return WriteFile(PathFor(index, format), frame.image());
}

}  // namespace gistream::client
