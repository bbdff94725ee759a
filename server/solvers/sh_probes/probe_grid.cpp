#include "solvers/sh_probes/probe_grid.h"

#include <algorithm>
#include <cmath>

#include "gl/textures.h"

namespace gistream {
namespace {

// The atlas: six layers (cube faces), read with texelFetch.
gl::Texture LayeredTexture(GLenum format, int width, int height) {
  return gl::LayeredTarget(format, width, height, 6);
}

}  // namespace

absl::StatusOr<ProbeLayout> FitProbeGrid(const Bounds& bounds, const ProbeGridSettings& settings) {
  ProbeLayout layout;
  layout.face_size = settings.face_size;
  glm::vec3 lo = bounds.empty() ? glm::vec3(-1.0f) : bounds.min;
  glm::vec3 hi = bounds.empty() ? glm::vec3(1.0f) : bounds.max;
  const float largest = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-6f});
  for (int a = 0; a < 3; ++a) {
    if (hi[a] - lo[a] < 1e-3f * largest) {
      const float mid = 0.5f * (lo[a] + hi[a]);
      lo[a] = mid - 0.05f * largest;
      hi[a] = mid + 0.05f * largest;
    }
  }
  const glm::vec3 extent = hi - lo;
  for (int a = 0; a < 3; ++a) {
    if (settings.spacing > 0.0f) {
      const double n = std::ceil(double(extent[a]) / double(settings.spacing));
      if (!(n <= 256.0)) {
        return absl::ResourceExhaustedError(absl::StrCat(
            "params.spacing: ", settings.spacing, " m gives more than 256 probes along ",
            std::string(1, "xyz"[a]), " (scene extent ", extent[a], " m)"));
      }
      layout.dims[a] = std::max(1, int(n));
    } else {
      layout.dims[a] = settings.grid;
    }
  }
  layout.origin = lo;
  layout.spacing = extent / glm::vec3(layout.dims);
  const int probes = layout.probes();
  layout.tiles_x = int(std::ceil(std::sqrt(double(probes))));
  layout.tiles_y = (probes + layout.tiles_x - 1) / layout.tiles_x;
  if (layout.texels() > kMaxProbeTexels) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "params.grid/params.face_size: ", layout.dims.x, "x", layout.dims.y, "x", layout.dims.z,
        " probes with ", layout.face_size, "x", layout.face_size, " faces need ", layout.texels(),
        " cube-map texels, over the limit of ", kMaxProbeTexels));
  }
  return layout;
}

void ProbeAtlas::Allocate(const ProbeLayout& layout) {
  if (layout.width() == width_ && layout.height() == height_ && fbo_) return;
  width_ = layout.width();
  height_ = layout.height();
  distance_ = LayeredTexture(GL_R32F, width_, height_);
  normal_ = LayeredTexture(GL_RGBA8_SNORM, width_, height_);
  // 32-bit floats: an 8-bit albedo rounds 0.999 up to 1.0 (and 0.9 to
  // 0.902), so at high albedo the probes' bounces created energy and never
  // converged (issue 14); a half float is truncated by llvmpipe's render
  // target conversion (0.999 -> 0.998535, 0.99 -> 0.98975, the measured
  // bounce ratios), which lost 0.05 % a bounce and left the furnace at
  // rho = 0.999 at 0.68 of the exact radiance (issue 29, item 4).
  albedo_ = LayeredTexture(GL_RGBA32F, width_, height_);
  // 8 bits: metallic 0 and roughness 1 (Lambertian) are exact.
  material_ = LayeredTexture(GL_RG8, width_, height_);
  depth_ = LayeredTexture(GL_DEPTH_COMPONENT32F, width_, height_);
  direct_ = LayeredTexture(GL_RGBA32F, width_, height_);
  indirect_ = LayeredTexture(GL_RGBA32F, width_, height_);
  radiance_ = LayeredTexture(GL_RGBA32F, width_, height_);
  fbo_ =
      gl::FramebufferOf({distance_.id(), normal_.id(), albedo_.id(), material_.id()}, depth_.id());
  bytes_ = layout.texels() * kAtlasBytesPerTexel;
}

void SetProbeGridUniforms(gl::Program& program, const ProbeLayout& layout, int coefficients,
                          bool indirect_shadows) {
  // One block for every probe-grid program; each uses part of it.
  program.SetOptional("uGridOrigin", layout.origin);
  program.SetOptional("uGridSpacing", layout.spacing);
  program.SetOptional("uGridDims", layout.dims);
  program.SetOptional("uFaceSize", layout.face_size);
  program.SetOptional("uAtlasTiles", layout.tiles_x);
  program.SetOptional("uAtlasTileCount", glm::ivec2(layout.tiles_x, layout.tiles_y));
  program.SetOptional("uProbeCount", layout.probes());
  program.SetOptional("uCoefficients", coefficients);
  program.SetOptional("uIndirectShadows", indirect_shadows ? 1 : 0);
}

}  // namespace gistream
