// Opens an in-memory image with exactly one OpenImageIO reader (the one for
// `format`): no file system, no other plugin sees the bytes. Only the
// header is read; the caller checks the spec before reading pixels.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "encode/exr_header.h"
#include "util/status.h"

namespace gistream {

struct MemoryImageReader {
  // A JPEG's bytes without their metadata segments (encode/jpeg_markers.h);
  // empty for other formats. Declared first: the proxy reads it.
  std::vector<uint8_t> owned_bytes;
  // The proxy must outlive the reader that reads through it.
  std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy;
  std::unique_ptr<OIIO::ImageInput> input;
  OIIO::ImageSpec spec;
};

// `field` names the source in errors ("images[2]", "image"); an EXR's
// header is held to `exr_limits` before OpenEXR sizes buffers from it.
absl::StatusOr<MemoryImageReader> OpenImageFromMemory(std::span<const uint8_t> bytes,
                                                      const std::string& format,
                                                      const std::string& field,
                                                      const ExrHeaderLimits& exr_limits = {});

}  // namespace gistream
