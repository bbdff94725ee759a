// The direct light reflected by glossy elements toward each of a set of
// directional bins (shaders/render/glossy_bin_direct.comp.glsl): the
// directional solvers' glossy elements start from it, antiradiance's
// glossy leaves and implicit_visibility's glossy elements (their notes).
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "absl/status/statusor.h"
#include "gl/handle.h"
#include "gl/program.h"
#include "render/direct_lighting.h"

namespace gistream {

// std430 mirror of GlossyBinElement in glossy_bin_direct.comp.glsl.
struct GlossyBinElement {
  glm::vec4 position;       // xyz centre
  glm::vec4 normal;         // xyz unit normal, w roughness (raised to what the bins resolve)
  glm::vec4 base_metallic;  // rgb base colour, a metallic
  glm::vec4 specular;       // rgb dielectric F0, a dielectric F90
};

class GlossyBinDirect {
 public:
  static absl::StatusOr<GlossyBinDirect> Create();

  // Writes count x bins vec4 radiances, element-major, into `radiance`
  // (at least that large) from `elements` (count GlossyBinElement) and
  // `directions` (bins vec4 unit directions), lit by `lighting` as it
  // stands (its shadow maps bound). bin_omega > 0: each lobe is widened
  // by that solid angle (sr), so a bin holds the lobe's mean over it; 0:
  // the BRDF at the bin's centre.
  void Run(const DirectLighting& lighting, GLuint elements, int count, GLuint directions, int bins,
           GLuint radiance, float bin_omega = 0.0f);

 private:
  gl::Program program_;
};

}  // namespace gistream
