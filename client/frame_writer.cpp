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
  if (IsVideoFormat(format)) return dir_ / absl::StrCat("stream", ImageFormatExtension(format));
  char name[64];
  std::snprintf(name, sizeof name, "frame_%05llu", static_cast<unsigned long long>(index));
  return dir_ / absl::StrCat(name, ImageFormatExtension(format));
}

absl::Status FrameWriter::Write(uint64_t index, const v1::Frame& frame) {
  const v1::ImageFormat format =
      frame.format() == v1::IMAGE_FORMAT_UNSPECIFIED ? requested_ : frame.format();
  if (frame.image().empty() && !frame.unchanged()) {
    return absl::InternalError(
        absl::StrCat("frame ", frame.frame_number(), " arrived without image bytes"));
  }
  if (IsVideoFormat(format)) {
    if (frame.image().empty()) return absl::OkStatus();  // the decoder keeps its picture
    const std::filesystem::path path = PathFor(index, format);
    if (!stream_) {
      stream_ = std::make_unique<std::ofstream>(path, std::ios::binary | std::ios::trunc);
    }
    stream_->write(frame.image().data(), std::streamsize(frame.image().size()));
    stream_->flush();
    if (!*stream_) return absl::InternalError(absl::StrCat(path.string(), ": write failed"));
    return absl::OkStatus();
  }
  if (frame.image().empty()) {
    if (last_image_.empty()) {
      return absl::InternalError(absl::StrCat("frame ", frame.frame_number(),
                                              " is unchanged but no picture came before it"));
    }
    return WriteFile(PathFor(index, format), last_image_);
  }
  last_image_ = frame.image();
  return WriteFile(PathFor(index, format), frame.image());
}

}  // namespace gistream::client
