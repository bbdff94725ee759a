// The probe grid of Nijasure et al. 2005, Section 4.1: a uniform grid fitted
// to the scene bounds with a probe at every cell centre, and the atlas that
// holds every probe's cube map. Face f of probe p is tile p of layer f of
// each 2D-array texture, so all probes and faces are one layered target
// (rasterized in one instanced pass, shaded and projected by compute).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "gl/handle.h"
#include "gl/program.h"
#include "scene/scene.h"
#include "util/status.h"

namespace gistream {

struct ProbeLayout {
  glm::ivec3 dims{1};
  glm::vec3 origin{0.0f};   // grid corner (bounds min, padded)
  glm::vec3 spacing{1.0f};  // cell size
  int face_size = 16;
  int tiles_x = 1, tiles_y = 1;  // atlas tiles across and down

  int probes() const { return dims.x * dims.y * dims.z; }
  int width() const { return tiles_x * face_size; }
  int height() const { return tiles_y * face_size; }
  uint64_t texels() const { return uint64_t(width()) * uint64_t(height()) * 6; }
  glm::vec3 position(const glm::ivec3& c) const { return origin + (glm::vec3(c) + 0.5f) * spacing; }
  // The cell of probe `probe` (x fastest, then y, then z).
  glm::ivec3 cell(int probe) const {
    return {probe % dims.x, (probe / dims.x) % dims.y, probe / (dims.x * dims.y)};
  }
};

struct ProbeGridSettings {
  int grid = 8;          // probes per axis, when spacing == 0
  float spacing = 0.0f;  // metres between probes; > 0 overrides grid
  int face_size = 16;
};

// Atlas texels are capped so a request cannot exhaust GPU memory.
constexpr uint64_t kMaxProbeTexels = uint64_t(1) << 23;
// GPU bytes per atlas texel: distance R32F, normal RGBA8, albedo RGBA32F,
// material RG8, depth 32 bits, direct, indirect and radiance RGBA32F.
constexpr uint64_t kAtlasBytesPerTexel = 4 + 4 + 16 + 2 + 4 + 16 * 3;

// Fits the grid to `bounds`. An axis with no extent (a flat scene) gets a
// slab one tenth of the largest extent thick, so probes never sit on the
// plane. Errors name the parameter that makes the atlas too large.
absl::StatusOr<ProbeLayout> FitProbeGrid(const Bounds& bounds, const ProbeGridSettings& settings);

// The cube-map G-buffer and the per-texel lighting of every probe.
class ProbeAtlas {
 public:
  // (Re)allocates when the layout's atlas size changed.
  void Allocate(const ProbeLayout& layout);

  GLuint fbo() const { return fbo_.id(); }
  GLuint distance() const { return distance_.id(); }  // R32F, 0 where nothing was hit
  GLuint normal() const { return normal_.id(); }      // RGBA8 snorm, w = 1: back face
  GLuint albedo() const { return albedo_.id(); }      // RGBA32F
  GLuint material() const { return material_.id(); }  // RG8 metallic, roughness
  // RGBA32F: the direct light's radiance reflected towards the probe.
  GLuint direct() const { return direct_.id(); }
  GLuint indirect() const { return indirect_.id(); }  // RGBA32F E_indirect
  GLuint radiance() const { return radiance_.id(); }  // RGBA32F outgoing radiance
  uint64_t gpu_bytes() const { return bytes_; }

 private:
  int width_ = 0, height_ = 0;
  gl::Texture distance_, normal_, albedo_, material_, depth_, direct_, indirect_, radiance_;
  gl::Framebuffer fbo_;
  uint64_t bytes_ = 0;
};

// Sets probe_grid.glsl's uniforms on `program`.
void SetProbeGridUniforms(gl::Program& program, const ProbeLayout& layout, int coefficients,
                          bool indirect_shadows);

}  // namespace gistream
