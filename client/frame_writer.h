// Where `stream` and `script` put the frames: DIR/frame_00000.jpg, ...
#pragma once

#include <cstdint>
#include <filesystem>

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
  // frame's own format.
  std::filesystem::path PathFor(uint64_t index, v1::ImageFormat format) const;

  // Writes frame `index`'s image bytes. INTERNAL when the frame has none.
  absl::Status Write(uint64_t index, const v1::Frame& frame) const;

  const std::filesystem::path& dir() const { return dir_; }

 private:
  FrameWriter(std::filesystem::path dir, v1::ImageFormat requested)
      : dir_(std::move(dir)), requested_(requested) {}
  std::filesystem::path dir_;
  v1::ImageFormat requested_;
};

}  // namespace gistream::client
