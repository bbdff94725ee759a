#include "solvers/sh_probes/probe_raster.h"

#include <algorithm>
#include <numeric>

#include "render/proxy_filters.h"
#include "util/log.h"

namespace gistream {
namespace {

constexpr int kAllFaces = 0x3f;

}  // namespace

absl::StatusOr<ProbeRasterizer> ProbeRasterizer::Create(const Options& options) {
  ProbeRasterizer raster;
  raster.draw_list_ = options.draw_list;
  std::vector<std::string> defines;
  if (options.draw_list) defines.push_back("GS_DRAW_LIST");
  // Layered rendering from the vertex shader (ARB_shader_viewport_layer_array)
  // needs no geometry shader; the geometry shader where it is missing.
  absl::StatusOr<gl::Program> layered = absl::UnavailableError("layered rendering not allowed");
  if (options.allow_layered) {
    layered = gl::Program::Build({{GL_VERTEX_SHADER, "sh_probes/rasterize_layer.vert.glsl"},
                                  {GL_FRAGMENT_SHADER, "sh_probes/rasterize.frag.glsl"}},
                                 defines);
  }
  if (layered.ok()) {
    raster.program_ = *std::move(layered);
    raster.layered_ = true;
    return raster;
  }
  if (options.allow_layered) {
    LogOnce(LogLevel::kInfo, "sh_probes_layered",
            absl::StrCat("sh_probes: the geometry shader draws the probe faces (no layered "
                         "vertex output: ",
                         layered.status().message().substr(0, 200), ")"));
  }
  GS_ASSIGN_OR_RETURN(raster.program_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "sh_probes/rasterize.vert.glsl"},
                                          {GL_GEOMETRY_SHADER, "sh_probes/rasterize.geom.glsl"},
                                          {GL_FRAGMENT_SHADER, "sh_probes/rasterize.frag.glsl"}},
                                         defines));
  return raster;
}

void ProbeRasterizer::Draw(const GpuScene& gpu, const SceneState& state, const ProbeLayout& layout,
                           const ProbeAtlas& atlas, const std::vector<int>* probes,
                           bool full_detail) {
  std::vector<int> all;
  if (!probes) {
    all.resize(size_t(layout.probes()));
    std::iota(all.begin(), all.end(), 0);
  }
  const std::vector<int>& listed = probes ? *probes : all;
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
    for (int i = 0; i < 4; ++i) glClearNamedFramebufferfv(fbo, GL_COLOR, i, zero);
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
  if (draw_list_) {
    DrawFromList(gpu, state, layout, listed, full_detail);
  } else {
    DrawItemByItem(gpu, state, layout, listed, full_detail);
  }
  for (int i = 0; i < 4; ++i) glDisable(GLenum(GL_CLIP_DISTANCE0 + i));
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void ProbeRasterizer::DrawFromList(const GpuScene& gpu, const SceneState& state,
                                   const ProbeLayout& layout, const std::vector<int>& probes,
                                   bool full_detail) {
  // Per probe a view: per item and node, a record for each face that may
  // see its box, at one face texel's tolerance at its nearest distance.
  // kProbesPerList probes per upload bound the list's memory.
  int faces = kAllFaces;
  for (size_t first = 0; first < probes.size(); first += kProbesPerList) {
    const size_t end = std::min(probes.size(), first + kProbesPerList);
    list_.Clear();
    for (size_t i = first; i < end; ++i) {
      faces = kAllFaces;
      const CubeDrawFilters filters = CubeFilters(state, layout.position(layout.cell(probes[i])),
                                                  layout.face_size, [&faces](int f) { faces = f; });
      list_.AddView(gpu, state, full_detail ? nullptr : &filters.item,
                    full_detail ? nullptr : &filters.cluster, faces, DrawTags::kEachBit,
                    DrawTextures::kBind);
    }
    list_.Upload();
    for (size_t i = first; i < end; ++i) {
      program_.Set("uProbe", probes[i]);
      list_.Draw(gpu, int(i - first));
    }
  }
}

uint64_t ProbeRasterizer::ListBytes(const GpuScene& gpu) {
  return DrawList::MaxBytes(gpu, kProbesPerList, 6);
}

void ProbeRasterizer::DrawItemByItem(const GpuScene& gpu, const SceneState& state,
                                     const ProbeLayout& layout, const std::vector<int>& probes,
                                     bool full_detail) {
  // The layered program draws face f as instance f, the geometry shader
  // every face in uFaceMask.
  const int instances = layered_ ? 6 : 1;
  for (int p : probes) {
    program_.Set("uProbe", p);
    program_.Set("uFaceMask", kAllFaces);
    if (full_detail) {
      gpu.Draw(program_, state, /*bind_textures=*/true, instances);
      continue;
    }
    const CubeDrawFilters filters =
        CubeFilters(state, layout.position(layout.cell(p)), layout.face_size,
                    [this](int faces) { program_.Set("uFaceMask", faces); });
    gpu.Draw(program_, state, /*bind_textures=*/true, instances, &filters.item, &filters.cluster);
  }
}

}  // namespace gistream
