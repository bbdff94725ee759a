#include "solvers/sh_probes/probe_raster.h"

#include <algorithm>
#include <numeric>
#include <span>

#include "gl/buffers.h"
#include "render/proxy_filters.h"

namespace gistream {
namespace {

constexpr GLuint kBatchBinding = 10;  // rasterize*.vert.glsl's BatchProbes
constexpr int kAllFaces = 0x3f;

}  // namespace

absl::StatusOr<ProbeRasterizer> ProbeRasterizer::Create(bool allow_layered) {
  ProbeRasterizer raster;
  // Layered rendering from the vertex shader (ARB_shader_viewport_layer_array)
  // is about 2.3x faster on llvmpipe than the geometry shader's six
  // invocations per triangle; the geometry shader where it is missing.
  absl::StatusOr<gl::Program> layered = absl::UnavailableError("layered rendering not allowed");
  if (allow_layered) {
    layered = gl::Program::Build({{GL_VERTEX_SHADER, "sh_probes/rasterize_layer.vert.glsl"},
                                  {GL_FRAGMENT_SHADER, "sh_probes/rasterize.frag.glsl"}});
  }
  if (layered.ok()) {
    raster.program_ = *std::move(layered);
    raster.instances_per_probe_ = 6;
  } else {
    GS_ASSIGN_OR_RETURN(
        raster.program_,
        gl::Program::Build({{GL_VERTEX_SHADER, "sh_probes/rasterize.vert.glsl"},
                            {GL_GEOMETRY_SHADER, "sh_probes/rasterize.geom.glsl"},
                            {GL_FRAGMENT_SHADER, "sh_probes/rasterize.frag.glsl"}}));
  }
  return raster;
}

void ProbeRasterizer::Draw(const GpuScene& gpu, const SceneState& state, const ProbeLayout& layout,
                           const ProbeAtlas& atlas, const std::vector<int>* probes,
                           bool full_detail) {
  const GLuint fbo = atlas.fbo();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(0, 0, layout.width(), layout.height());
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  for (int i = 0; i < 4; ++i) glEnable(GLenum(GL_CLIP_DISTANCE0 + i));
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  const float one = 1.0f;
  auto clear = [&] {
    for (int i = 0; i < 3; ++i) glClearNamedFramebufferfv(fbo, GL_COLOR, i, zero);
    glClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &one);
  };
  if (!probes) {
    clear();
  } else {
    // Only the batch's tiles (every layer: a layered attachment clears whole).
    glEnable(GL_SCISSOR_TEST);
    for (int p : *probes) {
      glScissor((p % layout.tiles_x) * layout.face_size, (p / layout.tiles_x) * layout.face_size,
                layout.face_size, layout.face_size);
      clear();
    }
    glDisable(GL_SCISSOR_TEST);
  }
  // Near and far planes that bracket the whole grid from any probe.
  const float far = std::max(1.01f * glm::length(glm::vec3(layout.dims) * layout.spacing), 1e-6f);
  SetProbeGridUniforms(program_, layout, 0, false);
  program_.Set("uNear", far * 1e-5f);
  program_.Set("uFar", far);
  program_.Use();
  if (full_detail) {
    DrawFull(gpu, state, layout, probes);
  } else if (probes) {
    DrawProxies(gpu, state, layout, *probes);
  } else {
    std::vector<int> all(size_t(layout.probes()));
    std::iota(all.begin(), all.end(), 0);
    DrawProxies(gpu, state, layout, all);
  }
  for (int i = 0; i < 4; ++i) glDisable(GLenum(GL_CLIP_DISTANCE0 + i));
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void ProbeRasterizer::DrawFull(const GpuScene& gpu, const SceneState& state,
                               const ProbeLayout& layout, const std::vector<int>* probes) {
  const int count = probes ? int(probes->size()) : 0;
  if (count > 0) {
    if (batch_capacity_ < size_t(count)) {
      batch_capacity_ = std::max(size_t(layout.probes()), size_t(count));
      batch_ = gl::ZeroedBuffer(batch_capacity_ * 4);
    }
    gl::Upload(batch_, std::span<const int>(*probes));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBatchBinding, batch_.id());
  }
  program_.Set("uBatchCount", count);
  program_.Set("uProbe", -1);
  program_.Set("uFaceMask", kAllFaces);
  gpu.Draw(program_, state, /*bind_textures=*/true,
           instances_per_probe_ * (probes ? count : layout.probes()));
}

void ProbeRasterizer::DrawProxies(const GpuScene& gpu, const SceneState& state,
                                  const ProbeLayout& layout, const std::vector<int>& probes) {
  program_.Set("uBatchCount", 0);
  for (int p : probes) {
    // Per item and node: the faces that may see its box, and one face
    // texel at its nearest distance from the probe.
    program_.Set("uProbe", p);
    const CubeDrawFilters filters =
        CubeFilters(state, layout.position(layout.cell(p)), layout.face_size,
                    [this](int faces) { program_.Set("uFaceMask", faces); });
    gpu.Draw(program_, state, /*bind_textures=*/true, instances_per_probe_, &filters.item,
             &filters.cluster);
  }
}

}  // namespace gistream
