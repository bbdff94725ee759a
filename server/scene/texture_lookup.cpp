#include "scene/texture_lookup.h"

#include <algorithm>
#include <cmath>

namespace gistream {
namespace {

float SrgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// uv moved by whole periods of `wrap` (1 for repeat, 2 for mirrored
// repeat; clamped to [-1, 2] for clamp to edge) so any finite coordinate
// becomes a small texel index with the same texels; non-finite: 0.
float Reduce(float u, int wrap) {
  if (!std::isfinite(u)) return 0.0f;
  switch (wrap) {
    case TextureSampler::kClampToEdge: return std::clamp(u, -1.0f, 2.0f);
    case TextureSampler::kMirroredRepeat: return u - 2.0f * std::floor(0.5f * u);
    default: return u - std::floor(u);
  }
}

}  // namespace

glm::vec3 ImageTexel(const Image& image, int x, int y) {
  const size_t i = (size_t(y) * size_t(image.width) + size_t(x)) * 4;
  if (image.is_float) return {image.pixelsf[i], image.pixelsf[i + 1], image.pixelsf[i + 2]};
  glm::vec3 c = glm::vec3(image.pixels8[i], image.pixels8[i + 1], image.pixels8[i + 2]) / 255.0f;
  if (image.srgb) c = {SrgbToLinear(c.x), SrgbToLinear(c.y), SrgbToLinear(c.z)};
  return c;
}

int WrapTexel(int i, int size, int wrap) {
  if (size <= 1) return 0;
  switch (wrap) {
    case TextureSampler::kClampToEdge: return i < 0 ? 0 : (i >= size ? size - 1 : i);
    case TextureSampler::kMirroredRepeat: {
      // Period 2 size: 0..size-1 then size-1..0 (GL 4.6, 8.14.2).
      const int period = 2 * size;
      const int m = ((i % period) + period) % period;
      return m < size ? m : period - 1 - m;
    }
    default: return ((i % size) + size) % size;
  }
}

glm::vec3 SampleImage(const Image& image, glm::vec2 uv, const TextureSampler& sampler,
                      TextureFilter filter) {
  if (image.width <= 0 || image.height <= 0) return glm::vec3(1.0f);
  if ((image.is_float ? image.pixelsf.size() : image.pixels8.size()) <
      size_t(image.width) * size_t(image.height) * 4) {
    return glm::vec3(1.0f);
  }
  const float x = Reduce(uv.x, sampler.wrap_s) * float(image.width);
  const float y = Reduce(uv.y, sampler.wrap_t) * float(image.height);
  const auto at = [&](int tx, int ty) {
    return ImageTexel(image, WrapTexel(tx, image.width, sampler.wrap_s),
                      WrapTexel(ty, image.height, sampler.wrap_t));
  };
  if (filter == TextureFilter::kNearest || sampler.mag_filter == TextureSampler::kNearest) {
    return at(int(std::floor(x)), int(std::floor(y)));
  }
  // Bilinear between the four texel centres around (x, y) (GL 4.6, 8.14.2).
  const float bx = std::floor(x - 0.5f), by = std::floor(y - 0.5f);
  const int x0 = int(bx), y0 = int(by);
  const float fx = (x - 0.5f) - bx, fy = (y - 0.5f) - by;
  return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), fx),
                  glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx), fy);
}

}  // namespace gistream
