// Image decoding (server/scene/image_decode.*): the first byte picks the
// kind (texture: PNG/JPEG, environment: HDR/EXR), the rest is the file. An
// image over the pixel limit is refused from its header, so no input can
// allocate more than the limit; a decoded image has exactly w x h x 4
// values.
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz/fuzz_check.h"
#include "scene/gltf/image_decode.h"

using namespace gistream;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const ImageKind kind = (data[0] & 1) ? ImageKind::kEnvironment : ImageKind::kTexture;
  ImportLimits limits;
  // Small limits keep each input quick (the header check is the same).
  limits.max_image_pixels = 1 << 16;
  limits.max_image_dimension = 1024;
  absl::StatusOr<Image> image =
      DecodeImage(std::span<const uint8_t>(data + 1, size - 1), kind, limits, "images[0]");
  if (!image.ok()) {
    FUZZ_CHECK(!image.status().message().empty());
    return 0;
  }
  FUZZ_CHECK(image->width > 0 && image->height > 0);
  FUZZ_CHECK(uint64_t(image->width) * uint64_t(image->height) <= limits.max_image_pixels);
  const size_t values = size_t(image->width) * size_t(image->height) * 4;
  FUZZ_CHECK(image->is_float == (kind == ImageKind::kEnvironment));
  FUZZ_CHECK((image->is_float ? image->pixelsf.size() : image->pixels8.size()) == values);
  return 0;
}
