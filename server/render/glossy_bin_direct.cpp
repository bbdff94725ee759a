#include "render/glossy_bin_direct.h"

#include "gl/buffers.h"
#include "gl/compute.h"

namespace gistream {

GS_STD430_MIRROR(GlossyBinElement, 64);

absl::StatusOr<GlossyBinDirect> GlossyBinDirect::Create() {
  GlossyBinDirect pass;
  GS_ASSIGN_OR_RETURN(
      pass.program_,
      gl::Program::Build({{GL_COMPUTE_SHADER, "render/glossy_bin_direct.comp.glsl"}}));
  return pass;
}

void GlossyBinDirect::Run(const DirectLighting& lighting, GLuint elements, int count,
                          GLuint directions, int bins, GLuint radiance, float bin_omega) {
  if (count <= 0 || bins <= 0) return;
  lighting.Bind(program_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GS_BINDING_GLOSSY_BIN_ELEMENTS, elements);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GS_BINDING_GLOSSY_BIN_DIRECTIONS, directions);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GS_BINDING_GLOSSY_BIN_RADIANCE, radiance);
  program_.Set("uCount", count);
  program_.Set("uBins", bins);
  program_.Set("uBinOmega", bin_omega);
  program_.Use();
  glDispatchCompute(gl::GroupCount(size_t(count) * size_t(bins), 64), 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
}

}  // namespace gistream
