#include "solvers/avg/vpl_shadow_maps.h"

#include <algorithm>
#include <array>

#include "gl/buffers.h"
#include "gl/textures.h"
#include "render/cube_faces.h"
#include "render/proxy_filters.h"
#include "render/shadow_maps.h"

namespace gistream::avg {
namespace {

// std430 mirror of shaders/avg/vpl.glsl's Vpl.
struct GpuVpl {
  glm::vec4 position_far;
  glm::vec4 normal_layer;
  glm::vec4 flux;
  glm::vec4 incident_roughness;
  glm::vec4 base_color_metallic;
  glm::vec4 specular;
};
GS_STD430_MIRROR(GpuVpl, 96);  // shaders/avg/vpl.glsl Vpl

}  // namespace

absl::StatusOr<VplShadowMaps> VplShadowMaps::Create() {
  VplShadowMaps maps;
  GS_ASSIGN_OR_RETURN(maps.program_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "avg/vpl_shadow.vert.glsl"},
                                          {GL_GEOMETRY_SHADER, "avg/vpl_shadow.geom.glsl"},
                                          {GL_FRAGMENT_SHADER, "avg/vpl_shadow.frag.glsl"}}));
  GS_ASSIGN_OR_RETURN(maps.resample_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "avg/vpl_resample.vert.glsl"},
                                          {GL_FRAGMENT_SHADER, "avg/vpl_resample.frag.glsl"}}));
  GS_ASSIGN_OR_RETURN(maps.cube_program_, BuildShadowCubeProgram());
  maps.cube_fbo_ = gl::Framebuffer::Create();
  // The cubes' depths read as values, texel by texel.
  maps.depth_value_ = gl::Sampler::Create();
  glSamplerParameteri(maps.depth_value_.id(), GL_TEXTURE_COMPARE_MODE, GL_NONE);
  glSamplerParameteri(maps.depth_value_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glSamplerParameteri(maps.depth_value_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  maps.empty_vao_ = gl::VertexArray::Create();
  maps.fbo_ = gl::Framebuffer::Create();
  return maps;
}

void VplShadowMaps::Upload(const std::vector<Vpl>& vpls, const Bounds& bounds) {
  std::vector<GpuVpl> data;
  data.reserve(vpls.size());
  for (size_t i = 0; i < vpls.size(); ++i) {
    const Vpl& v = vpls[i];
    data.push_back({glm::vec4(v.position, ShadowFar(bounds, v.position)),
                    glm::vec4(v.normal, float(i)), glm::vec4(v.flux, 0.0f),
                    glm::vec4(v.incident, v.brdf.roughness),
                    glm::vec4(v.brdf.base_color, v.brdf.metallic),
                    glm::vec4(v.brdf.specular_f0, v.brdf.specular_f90)});
  }
  count_ = int(data.size());
  any_glossy_ =
      std::any_of(vpls.begin(), vpls.end(), [](const Vpl& v) { return !v.brdf.Lambertian(); });
  fars_.clear();
  for (const GpuVpl& v : data) fars_.push_back(v.position_far.w);
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
      RenderFromCubes(gpu, state, resolution, first, count);
    }
  } else if (count_ == 0) {
    glClearBufferfv(GL_DEPTH, 0, &one);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void VplShadowMaps::RenderFromCubes(const GpuScene& gpu, const SceneState& state, int resolution,
                                    int first, int count) {
  // A paraboloid map is not linear (straight edges land on arcs,
  // render/proxy_filters.h), a cube face is: each VPL's distance cube is
  // drawn from the proxies within one face texel at each node's nearest
  // distance, into the faces that see the node and the VPL's hemisphere
  // (as render/shadow_maps' cubes, with one geometry shader invocation per
  // triangle: llvmpipe ran the six masked invocations apart, 30 % of the
  // pass at 415K), then resampled into the VPL's map, a batch of VPLs at a
  // time.
  // The cubes only grow (a slice of a re-map draws fewer VPLs).
  const int batch = resolution == cube_resolution_
                        ? std::max(cube_batch_, CubeBatch(resolution, count))
                        : CubeBatch(resolution, count);
  if (batch != cube_batch_ || resolution != cube_resolution_) {
    cubes_ = gl::DepthCompareArray(GL_TEXTURE_CUBE_MAP_ARRAY, resolution, 6 * batch);
    glNamedFramebufferTexture(cube_fbo_.id(), GL_DEPTH_ATTACHMENT, cubes_.id(), 0);
    glNamedFramebufferDrawBuffer(cube_fbo_.id(), GL_NONE);
    cube_batch_ = batch;
    cube_resolution_ = resolution;
  }
  for (int b = first; b < first + count; b += batch) {
    const int n = std::min(batch, first + count - b);
    // RenderRange set the viewport (cubes and maps share the resolution)
    // and the depth test.
    glBindFramebuffer(GL_FRAMEBUFFER, cube_fbo_.id());
    const float one = 1.0f;
    glClearTexSubImage(cubes_.id(), 0, 0, 0, 0, resolution, resolution, 6 * n, GL_DEPTH_COMPONENT,
                       GL_FLOAT, &one);
    // Per VPL of the batch, per node: nothing behind the VPL's hemisphere,
    // else the faces that may see it (the draw's tag) and the coarsest
    // copy within a face texel at its nearest distance
    // (render/proxy_filters.h); one indirect draw list for the batch, a
    // view per VPL (scene/gpu/draw_list.h).
    list_.Clear();
    for (int j = 0; j < n; ++j) {
      const Vpl& vpl = cpu_vpls_[size_t(b + j)];
      const int hemisphere = HemisphereFaceMask(vpl.normal);
      int faces = 0;
      const ClusterFilter cluster_filter = [&](const Bounds& box) {
        faces = CubeFaceMask(box, vpl.position) & hemisphere;
        if (faces == 0 ||
            ParaboloidTexelTolerance(box, vpl.position, vpl.normal, resolution) < 0.0f)
          return -1.0f;
        return CubeTexelTolerance(box, vpl.position, resolution);
      };
      const DrawFilter filter = [&](const DrawItem& item, const glm::mat4& model) {
        return cluster_filter(ItemWorldBounds(state, item, model));
      };
      list_.AddView(gpu, state, &filter, &cluster_filter, faces, DrawTags::kEachBit);
    }
    list_.Upload();
    cube_program_.Use();
    for (int j = 0; j < n; ++j) {
      const Vpl& vpl = cpu_vpls_[size_t(b + j)];
      const float far = fars_[size_t(b + j)];
      const std::array<glm::mat4, 6> view_proj = CubeFaceViewProj(vpl.position, far);
      glProgramUniformMatrix4fv(cube_program_.id(), cube_program_.Location("uFaceViewProj"), 6,
                                GL_FALSE, &view_proj[0][0][0]);
      cube_program_.Set("uCube", j);
      cube_program_.Set("uLightPos", vpl.position);
      cube_program_.Set("uFar", far);
      list_.Draw(gpu, j);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
    resample_.Use();
    resample_.Set("uFirstVpl", b);
    resample_.Set("uResolution", resolution);
    resample_.Set("uCubes", int(kShadowUnit));
    glBindTextureUnit(kShadowUnit, cubes_.id());
    glBindSampler(kShadowUnit, depth_value_.id());
    glBindVertexArray(empty_vao_.id());
    glDrawArraysInstanced(GL_TRIANGLES, 0, 3, n);
    glBindVertexArray(0);
    glBindSampler(kShadowUnit, 0);
  }
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

int VplShadowMaps::CubeBatch(int resolution, int vpls) {
  constexpr int kBatch = 64;
  constexpr uint64_t kMaxBytes = uint64_t(64) << 20;
  const uint64_t cube =
      6 * uint64_t(std::max(resolution, 1)) * uint64_t(std::max(resolution, 1)) * 4;
  const int fit = int(std::clamp<uint64_t>(kMaxBytes / cube, 1, kBatch));
  return std::max(1, std::min(fit, vpls));
}

uint64_t VplShadowMaps::CubeBatchBytes(int resolution, int vpls) {
  return uint64_t(CubeBatch(resolution, vpls)) * 6 * uint64_t(resolution) * uint64_t(resolution) *
         4;
}

uint64_t VplShadowMaps::gpu_bytes() const {
  return uint64_t(layers_) * uint64_t(resolution_) * uint64_t(resolution_) * 4 +
         uint64_t(count_) * sizeof(GpuVpl) +
         uint64_t(cube_batch_) * 6 * uint64_t(cube_resolution_) * uint64_t(cube_resolution_) * 4;
}

}  // namespace gistream::avg
