#include "solvers/avg/vpl_shadow_maps.h"

#include <algorithm>
#include <cmath>

#include "gl/buffers.h"
#include "gl/textures.h"
#include "render/proxy_filters.h"
#include "render/shadow_maps.h"

namespace gistream::avg {
namespace {

// std430 mirror of shaders/avg/vpl.glsl's Vpl.
struct GpuVpl {
  glm::vec4 position_far;
  glm::vec4 normal_layer;
  glm::vec4 flux;
};
GS_STD430_MIRROR(GpuVpl, 48);  // shaders/avg/vpl.glsl Vpl

}  // namespace

absl::StatusOr<VplShadowMaps> VplShadowMaps::Create() {
  VplShadowMaps maps;
  GS_ASSIGN_OR_RETURN(maps.program_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "avg/vpl_shadow.vert.glsl"},
                                          {GL_GEOMETRY_SHADER, "avg/vpl_shadow.geom.glsl"},
                                          {GL_FRAGMENT_SHADER, "avg/vpl_shadow.frag.glsl"}}));
  GS_ASSIGN_OR_RETURN(maps.tessellating_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "avg/vpl_shadow.vert.glsl"},
                                          {GL_TESS_CONTROL_SHADER, "avg/vpl_shadow.tesc.glsl"},
                                          {GL_TESS_EVALUATION_SHADER, "avg/vpl_shadow.tese.glsl"},
                                          {GL_FRAGMENT_SHADER, "avg/vpl_shadow.frag.glsl"}}));
  maps.fbo_ = gl::Framebuffer::Create();
  return maps;
}

void VplShadowMaps::Upload(const std::vector<Vpl>& vpls, const Bounds& bounds) {
  std::vector<GpuVpl> data;
  data.reserve(vpls.size());
  for (size_t i = 0; i < vpls.size(); ++i) {
    const Vpl& v = vpls[i];
    data.push_back({glm::vec4(v.position, ShadowFar(bounds, v.position)),
                    glm::vec4(v.normal, float(i)), glm::vec4(v.flux, 0.0f)});
  }
  count_ = int(data.size());
  vpls_ = gl::StorageBuffer(data);
  cpu_vpls_ = vpls;
}

void VplShadowMaps::Allocate(int layers, int resolution) {
  if (maps_ && layers == layers_ && resolution == resolution_) return;
  maps_ = gl::DepthCompareArray(GL_TEXTURE_2D_ARRAY, resolution, layers);
  layers_ = layers;
  resolution_ = resolution;
}

void VplShadowMaps::Render(const GpuScene& gpu, const SceneState& state, int resolution,
                           bool full_detail) {
  RenderRange(gpu, state, resolution, 0, count_, full_detail);
}

void VplShadowMaps::RenderRange(const GpuScene& gpu, const SceneState& state, int resolution,
                                int first, int count, bool full_detail) {
  Allocate(std::max(count_, 1), resolution);
  first = std::clamp(first, 0, count_);
  count = std::clamp(count, 0, count_ - first);
  // Layered attachment: the geometry shader picks the layer (the VPL).
  glNamedFramebufferTexture(fbo_.id(), GL_DEPTH_ATTACHMENT, maps_.id(), 0);
  glNamedFramebufferDrawBuffer(fbo_.id(), GL_NONE);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, resolution, resolution);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  const float one = 1.0f;
  if (count > 0) {
    // The slice's layers only.
    glClearTexSubImage(maps_.id(), 0, 0, 0, first, resolution, resolution, count,
                       GL_DEPTH_COMPONENT, GL_FLOAT, &one);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kVplBinding, vpls_.id());
    if (full_detail || (gpu.levels().empty() && gpu.clusters().empty())) {
      program_.Use();
      program_.Set("uFirstVpl", first);
      gpu.Draw(program_, state, false, count);
    } else {
      // Proxies are tessellated (vpl_shadow.tesc.glsl), so their big
      // triangles follow the map's curves.
      tessellating_.Use();
      tessellating_.Set("uMaxAngle", std::sqrt(8.0f / float(resolution)));
      glEnable(GL_CLIP_DISTANCE0);  // the hemisphere (vpl_shadow.tese.glsl)
      for (int i = first; i < first + count; ++i) {
        const Vpl& vpl = cpu_vpls_[size_t(i)];
        // Per node: nothing behind the VPL's hemisphere, else the coarsest
        // copy within a map texel at the node's nearest distance.
        const ClusterFilter cluster_filter = [&](const Bounds& box) {
          return ParaboloidTexelTolerance(box, vpl.position, vpl.normal, resolution);
        };
        const DrawFilter filter = [&](const DrawItem& item, const glm::mat4& model) {
          return cluster_filter(ItemWorldBounds(state, item, model));
        };
        tessellating_.Set("uFirstVpl", i);
        gpu.Draw(tessellating_, state, false, 1, &filter, &cluster_filter, GL_PATCHES);
      }
      glDisable(GL_CLIP_DISTANCE0);
    }
  } else if (count_ == 0) {
    glClearBufferfv(GL_DEPTH, 0, &one);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void VplShadowMaps::CopyLayers(const VplShadowMaps& from,
                               const std::vector<std::pair<int, int>>& layers, int resolution) {
  Allocate(std::max(count_, 1), resolution);
  if (!from.maps_ || from.resolution_ != resolution) return;
  // Runs of consecutive layers (a kept path's VPLs move together) in one copy each.
  for (size_t i = 0; i < layers.size();) {
    size_t j = i + 1;
    while (j < layers.size() && layers[j].first == layers[j - 1].first + 1 &&
           layers[j].second == layers[j - 1].second + 1) {
      ++j;
    }
    glCopyImageSubData(from.maps_.id(), GL_TEXTURE_2D_ARRAY, 0, 0, 0, layers[i].first, maps_.id(),
                       GL_TEXTURE_2D_ARRAY, 0, 0, 0, layers[i].second, resolution, resolution,
                       GLsizei(j - i));
    i = j;
  }
}

void VplShadowMaps::Bind() {
  // Without visibility no map is drawn; a 1-texel stand-in keeps the
  // sampler complete.
  if (!maps_) Allocate(1, 1);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kVplBinding, vpls_.id());
  glBindTextureUnit(kShadowUnit, maps_.id());
}

uint64_t VplShadowMaps::gpu_bytes() const {
  return uint64_t(layers_) * uint64_t(resolution_) * uint64_t(resolution_) * 4 +
         uint64_t(count_) * sizeof(GpuVpl);
}

}  // namespace gistream::avg
