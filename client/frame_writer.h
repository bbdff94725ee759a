// Where `stream` and `script` put the frames: DIR/frame_00000.jpg, ... for
// image formats; one raw stream DIR/stream.h264 (.hevc, .obu) that ffmpeg
// and ffprobe read for video formats. A frame that arrives `unchanged`
// (no image: the server did not re-send the same picture) is saved as a
// copy of the last picture, so every frame still has its file; in a video
// stream it adds nothing.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "gistream/v1/gistream.pb.h"
#include "util/status.h"

namespace gistream::client {

class FrameWriter {
 public:
  // Creates `dir` (and its parents) if missing. `requested` names frames
  // that do not say their format.
  static absl::StatusOr<FrameWriter> Create(const std::filesystem::path& dir,
                                            v1::ImageFormat requested);

  // DIR/frame_NNNNN.EXT, five digits (more past 99999), extension by the
  // frame's own format; DIR/stream.EXT for video formats.
  std::filesystem::path PathFor(uint64_t index, v1::ImageFormat format) const;

  // Writes frame `index`'s image bytes (video: appends its access unit).
  // INTERNAL when a changed frame has none, or when an unchanged frame
  // comes before any picture.
  absl::Status Write(uint64_t index, const v1::Frame& frame);

  const std::filesystem::path& dir() const { return dir_; }

 private:
  FrameWriter(std::filesystem::path dir, v1::ImageFormat requested)
      : dir_(std::move(dir)), requested_(requested) {}
  std::filesystem::path dir_;
  v1::ImageFormat requested_;
  std::string last_image_;                 // image formats: the last picture
  std::unique_ptr<std::ofstream> stream_;  // video formats: the open stream file
};

}  // namespace gistream::client
