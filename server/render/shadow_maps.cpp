#include "render/shadow_maps.h"

#include <algorithm>
#include <array>

#include <glm/gtc/matrix_transform.hpp>

#include "gl/textures.h"
#include "render/cube_faces.h"
#include "render/proxy_filters.h"
#include "absl/strings/str_cat.h"
#include "util/log.h"

namespace gistream {
namespace {

// Binds `fbo` for a depth-only pass over a square `resolution` target.
void BeginDepthPass(GLuint fbo, int resolution) {
  glNamedFramebufferDrawBuffer(fbo, GL_NONE);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(0, 0, resolution, resolution);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
}

}  // namespace

float ShadowFar(const Bounds& bounds, const glm::vec3& p) {
  if (bounds.empty()) return 1.0f;
  float far = 0.0f;
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 c((i & 1) ? bounds.max.x : bounds.min.x, (i & 2) ? bounds.max.y : bounds.min.y,
                      (i & 4) ? bounds.max.z : bounds.min.z);
    far = std::max(far, glm::length(c - p));
  }
  return std::max(far * 1.01f, 1e-6f);
}

absl::StatusOr<gl::Program> BuildShadowCubeProgram() {
  // The vertex shader writes the layer where the GL allows it (no geometry
  // shader runs), else a geometry shader does.
  absl::StatusOr<gl::Program> layered =
      gl::Program::Build({{GL_VERTEX_SHADER, "render/shadow_cube.vert.glsl"},
                          {GL_FRAGMENT_SHADER, "render/shadow_cube.frag.glsl"}},
                         {"GS_DRAW_LIST", "GS_LAYER_FROM_VERTEX"});
  if (layered.ok()) return layered;
  LogOnce(LogLevel::kInfo, "shadow_cube_layered",
          absl::StrCat("shadow cubes: the geometry shader draws the faces (no layered vertex "
                       "output: ",
                       layered.status().message().substr(0, 200), ")"));
  return gl::Program::Build({{GL_VERTEX_SHADER, "render/shadow_cube.vert.glsl"},
                             {GL_GEOMETRY_SHADER, "render/shadow_cube.geom.glsl"},
                             {GL_FRAGMENT_SHADER, "render/shadow_cube.frag.glsl"}},
                            {"GS_DRAW_LIST"});
}

absl::StatusOr<ShadowMaps> ShadowMaps::Create() {
  ShadowMaps maps;
  GS_ASSIGN_OR_RETURN(maps.cube_program_, BuildShadowCubeProgram());
  GS_ASSIGN_OR_RETURN(maps.dir_program_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "render/shadow_dir.vert.glsl"},
                                          {GL_FRAGMENT_SHADER, "render/shadow_dir.frag.glsl"}},
                                         {"GS_DRAW_LIST"}));
  maps.fbo_ = gl::Framebuffer::Create();
  return maps;
}

void ShadowMaps::Allocate(int cube_count, int directional_count, int resolution) {
  if (cube_count != cube_count_ || resolution != resolution_) {
    cubes_ =
        gl::DepthCompareArray(GL_TEXTURE_CUBE_MAP_ARRAY, resolution, 6 * std::max(cube_count, 1));
  }
  if (directional_count != dir_count_ || resolution != resolution_) {
    directional_ =
        gl::DepthCompareArray(GL_TEXTURE_2D_ARRAY, resolution, std::max(directional_count, 1));
  }
  cube_count_ = cube_count;
  dir_count_ = directional_count;
  resolution_ = resolution;
}

uint64_t ShadowMaps::gpu_bytes() const {
  const uint64_t face = uint64_t(resolution_) * uint64_t(resolution_) * 4;
  return face * (6 * uint64_t(std::max(cube_count_, 1)) + uint64_t(std::max(dir_count_, 1)));
}

void ShadowMaps::RenderCube(const GpuScene& gpu, const SceneState& state, int index,
                            const glm::vec3& position, float far, bool full_detail) {
  const std::array<glm::mat4, 6> view_proj = CubeFaceViewProj(position, far);
  glNamedFramebufferTexture(fbo_.id(), GL_DEPTH_ATTACHMENT, cubes_.id(), 0);
  BeginDepthPass(fbo_.id(), resolution_);
  cube_program_.Use();
  glProgramUniformMatrix4fv(cube_program_.id(), cube_program_.Location("uFaceViewProj"), 6,
                            GL_FALSE, &view_proj[0][0][0]);
  cube_program_.Set("uCube", index);
  cube_program_.Set("uLightPos", position);
  cube_program_.Set("uFar", far);
  // Clear only this cube's six layers.
  const float one = 1.0f;
  glClearTexSubImage(cubes_.id(), 0, 0, 0, 6 * index, resolution_, resolution_, 6,
                     GL_DEPTH_COMPONENT, GL_FLOAT, &one);
  // Per item, and per node of an item's cluster tree at the node's own box
  // (a node near the light keeps its detail, the rest of its primitive
  // need not): the faces that may see the box (each draw's tag), and a
  // texel at its nearest distance.
  int faces = 0x3f;
  const CubeDrawFilters filters =
      CubeFilters(state, position, resolution_, [&faces](int f) { faces = f; });
  list_.Clear();
  if (full_detail) {
    list_.AddView(gpu, state, nullptr, nullptr, faces, DrawTags::kEachBit);
  } else {
    list_.AddView(gpu, state, &filters.item, &filters.cluster, faces, DrawTags::kEachBit);
  }
  list_.Upload();
  list_.Draw(gpu, 0);
}

glm::mat4 ShadowMaps::RenderDirectional(const GpuScene& gpu, const SceneState& state, int index,
                                        const glm::vec3& direction, bool full_detail) {
  const Bounds b = gpu.WorldBounds(state);
  const glm::vec3 center = b.empty() ? glm::vec3(0.0f) : b.center();
  const float radius = b.empty() ? 1.0f : std::max(0.5f * glm::length(b.extent()), 1e-6f);
  const glm::vec3 dir = glm::normalize(direction);
  const glm::vec3 up = std::abs(dir.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  const glm::mat4 view = glm::lookAt(center - dir * (2.0f * radius), center, up);
  const glm::mat4 proj = glm::ortho(-radius, radius, -radius, radius, 0.0f, 4.0f * radius);
  const glm::mat4 view_proj = proj * view;

  glNamedFramebufferTextureLayer(fbo_.id(), GL_DEPTH_ATTACHMENT, directional_.id(), 0, index);
  BeginDepthPass(fbo_.id(), resolution_);
  glClear(GL_DEPTH_BUFFER_BIT);
  dir_program_.Set("uViewProj", view_proj);
  dir_program_.Use();
  // An orthographic texel is 2 radius / resolution wide everywhere.
  const float texel = 2.0f * radius / float(resolution_);
  const DrawFilter filter = [texel](const DrawItem&, const glm::mat4&) { return texel; };
  const int no_tag = 0;
  list_.Clear();
  list_.AddView(gpu, state, full_detail ? nullptr : &filter, nullptr, no_tag);
  list_.Upload();
  list_.Draw(gpu, 0);
  return view_proj;
}

void ShadowMaps::Bind(GLuint cube_unit, GLuint dir_unit) const {
  glBindTextureUnit(cube_unit, cubes_.id());
  glBindTextureUnit(dir_unit, directional_.id());
}

}  // namespace gistream
