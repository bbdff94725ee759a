// Texel lookups of a material's texture on the CPU (pathtrace's shading,
// implicit_visibility's element albedos), following the texture's glTF
// sampler as the GPU's sampler objects do (scene/gpu/gpu_scene.cpp): wrap
// per axis (repeat, clamp to edge, mirrored repeat), nearest or bilinear.
// One level: no mipmaps (a path tracer's ray sees a point, not a footprint).
#pragma once

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace gistream {

// Linear RGB of texel (x, y) of `image` (both in range; an 8-bit image
// decoded from sRGB when it says so, a float image as is).
glm::vec3 ImageTexel(const Image& image, int x, int y);

// Texel index `i` of an axis of `size` texels under `wrap`
// (TextureSampler::kRepeat, kClampToEdge or kMirroredRepeat), in [0, size).
int WrapTexel(int i, int size, int wrap);

enum class TextureFilter {
  kSampler,  // the sampler's magFilter (bilinear unless NEAREST)
  kNearest,  // the nearest texel whatever the sampler
};

// Linear RGB of `image` at `uv` (an 8-bit image decoded from sRGB when it
// says so; a float image as is); white for an empty image. A non-finite
// coordinate reads as 0.
glm::vec3 SampleImage(const Image& image, glm::vec2 uv, const TextureSampler& sampler,
                      TextureFilter filter = TextureFilter::kSampler);

}  // namespace gistream
