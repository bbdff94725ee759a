// Image decoding through OpenImageIO with every reader but the named one
// switched off (no try_all_readers), magic bytes checked first, and the
// pixel count checked against the limit before pixels are decoded.
#pragma once

#include <span>
#include <string>

#include "scene/gltf/import_limits.h"
#include "scene/gltf/import_memory.h"
#include "scene/scene.h"
#include "util/status.h"

namespace gistream {

enum class ImageKind {
  kTexture,      // PNG or JPEG, kept 8-bit RGBA
  kEnvironment,  // Radiance HDR or OpenEXR, converted to linear float RGBA
};

// Detects the format from magic bytes: "png", "jpeg", "hdr", "exr", or "".
std::string DetectImageFormat(std::span<const uint8_t> bytes);

// Decodes `bytes`. `field` names the source in error messages
// ("images[2]"). INVALID_ARGUMENT for a format the kind does not allow or a
// corrupt file; RESOURCE_EXHAUSTED for an image over the limits, or whose
// decoded pixels `memory` (when given) cannot reserve, checked from the
// header before any pixel is decoded.
absl::StatusOr<Image> DecodeImage(std::span<const uint8_t> bytes, ImageKind kind,
                                  const ImportLimits& limits, const std::string& field,
                                  ImportMemory* memory = nullptr);

}  // namespace gistream
