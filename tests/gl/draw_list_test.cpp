// The indirect draw list (scene/gpu/draw_list.h, issue 19): instances of one
// mesh at the same proxy choice become one instanced command, and a depth
// cube drawn from the list (a record per face, the layer written by the
// vertex shader or by the geometry shader fallback) is bitwise the cube
// GpuScene::Draw draws item by item into all six faces with the same
// filters, at full detail and through proxies.
#include <gtest/gtest.h>

#include <array>
#include <functional>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "gl/textures.h"

#include "render/cube_faces.h"
#include "render/proxy_filters.h"
#include "render/shadow_maps.h"
#include "scene/gpu/draw_list.h"
#include "scene/gpu/gpu_scene.h"
#include "scene/proxies/proxy_levels.h"
#include "support/gl_context.h"
#include "support/test_meshes.h"

namespace gistream {
namespace draw_list_test {

constexpr int kResolution = 128;
constexpr int kSpheres = 5;
const glm::vec3 kLight(0.3f, 2.0f, 0.2f);

// A floor (40 x 40 quads) and kSpheres node instances of one UV sphere
// mesh in a row above it, with proxies.
std::shared_ptr<const Scene> InstancedScene() {
  Scene scene;
  scene.meshes.push_back({"floor", {testing::FloorGrid(40)}});
  scene.meshes.push_back({"sphere", {testing::UvSphere({0.0f, 0.0f, 0.0f}, 0.15f, 48, 96)}});
  Node floor;
  floor.mesh = 0;
  scene.nodes.push_back(floor);
  for (int i = 0; i < kSpheres; ++i) {
    Node sphere;
    sphere.mesh = 1;
    sphere.translation = glm::vec3(-0.8f + 0.4f * float(i), 0.4f, 0.0f);
    scene.nodes.push_back(sphere);
  }
  for (int n = 0; n < int(scene.nodes.size()); ++n) {
    scene.roots.push_back(n);
    const Bounds& local = scene.meshes[size_t(scene.nodes[size_t(n)].mesh)].primitives[0].bounds;
    scene.bounds.Extend(
        local.Transformed(glm::translate(glm::mat4(1.0f), scene.nodes[size_t(n)].translation)));
  }
  BuildSceneProxies(&scene);
  return std::make_shared<const Scene>(std::move(scene));
}

class DrawListTest : public testing::GlContextTest {
 protected:
  void SetUp() override {
    GlContextTest::SetUp();
    scene_ = InstancedScene();
    state_ = std::make_unique<SceneState>(scene_);
    auto gpu = GpuScene::Upload(*state_);
    ASSERT_TRUE(gpu.ok()) << gpu.status();
    gpu_ = std::move(*gpu);
    far_ = ShadowFar(scene_->bounds, kLight);
  }

  // Cube 0 around kLight as depths, 6 faces in order, drawn by `draw` with
  // `program` bound and its cube uniforms set.
  std::vector<float> Cube(gl::Program& program, const std::function<void()>& draw) {
    gl::Texture cubes = gl::DepthCompareArray(GL_TEXTURE_CUBE_MAP_ARRAY, kResolution, 6);
    gl::Framebuffer fbo = gl::Framebuffer::Create();
    glNamedFramebufferTexture(fbo.id(), GL_DEPTH_ATTACHMENT, cubes.id(), 0);
    glNamedFramebufferDrawBuffer(fbo.id(), GL_NONE);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
    glViewport(0, 0, kResolution, kResolution);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glClear(GL_DEPTH_BUFFER_BIT);
    const std::array<glm::mat4, 6> view_proj = CubeFaceViewProj(kLight, far_);
    program.Use();
    glProgramUniformMatrix4fv(program.id(), program.Location("uFaceViewProj"), 6, GL_FALSE,
                              &view_proj[0][0][0]);
    program.Set("uCube", 0);
    program.Set("uLightPos", kLight);
    program.Set("uFar", far_);
    draw();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    std::vector<float> depth(size_t(6) * kResolution * kResolution);
    glGetTextureImage(cubes.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                      GLsizei(depth.size() * sizeof(float)), depth.data());
    return depth;
  }

  std::shared_ptr<const Scene> scene_;
  std::unique_ptr<SceneState> state_;
  std::unique_ptr<GpuScene> gpu_;
  float far_ = 1.0f;
};

TEST_F(DrawListTest, InstancesOfOneMeshAreOneInstancedCommand) {
  DrawList list;
  const int tag = 7;
  const int view = list.AddView(*gpu_, *state_, nullptr, nullptr, tag);
  const std::vector<DrawCommand> commands = list.Commands(view);
  // Full detail: the floor once, the sphere's kSpheres instances as one.
  ASSERT_EQ(commands.size(), 2u);
  uint32_t instances = 0, triangles = 0;
  for (const DrawCommand& c : commands) {
    instances += c.instance_count;
    triangles += c.count / 3 * c.instance_count;
    EXPECT_TRUE(c.instance_count == 1 || c.instance_count == kSpheres) << c.instance_count;
  }
  EXPECT_EQ(instances, 1u + kSpheres);
  uint32_t scene_triangles = 0;
  for (const DrawItem& d : gpu_->draws()) scene_triangles += d.index_count / 3;
  EXPECT_EQ(triangles, scene_triangles);
  // A second view follows the first, its base instances past its records.
  const int second = list.AddView(*gpu_, *state_, nullptr, nullptr, tag);
  EXPECT_EQ(second, 1);
  for (const DrawCommand& c : list.Commands(second)) EXPECT_GE(c.base_instance, instances);
}

TEST_F(DrawListTest, ListCubeIsBitwiseThePerItemCube) {
  // The program the passes use (the layer written by the vertex shader
  // where the GL has ARB_shader_viewport_layer_array) and the geometry
  // shader fallback, each drawn from a list with a record per face.
  auto layered = BuildShadowCubeProgram();
  ASSERT_TRUE(layered.ok()) << layered.status();
  auto fallback = gl::Program::Build({{GL_VERTEX_SHADER, "render/shadow_cube.vert.glsl"},
                                      {GL_GEOMETRY_SHADER, "render/shadow_cube.geom.glsl"},
                                      {GL_FRAGMENT_SHADER, "render/shadow_cube.frag.glsl"}},
                                     {"GS_DRAW_LIST"});
  ASSERT_TRUE(fallback.ok()) << fallback.status();
  // The same shaders drawn item by item (uModel; every face of the cube).
  auto item_program = gl::Program::Build({{GL_VERTEX_SHADER, "render/shadow_cube.vert.glsl"},
                                          {GL_GEOMETRY_SHADER, "render/shadow_cube.geom.glsl"},
                                          {GL_FRAGMENT_SHADER, "render/shadow_cube.frag.glsl"}});
  ASSERT_TRUE(item_program.ok()) << item_program.status();
  int faces = 0x3f;
  const CubeDrawFilters filters =
      CubeFilters(*state_, kLight, kResolution, [&faces](int f) { faces = f; });
  for (const bool full_detail : {true, false}) {
    SCOPED_TRACE(full_detail ? "full detail" : "proxies");
    const DrawFilter* item = full_detail ? nullptr : &filters.item;
    const ClusterFilter* cluster = full_detail ? nullptr : &filters.cluster;
    const std::vector<float> by_item =
        Cube(*item_program, [&] { gpu_->Draw(*item_program, *state_, false, 1, item, cluster); });
    size_t covered = 0;
    for (float d : by_item) covered += d < 1.0f ? 1 : 0;
    EXPECT_GT(covered, size_t(kResolution * kResolution / 8)) << "the cube shows the scene";
    for (gl::Program* program : {&*layered, &*fallback}) {
      DrawList list;
      const std::vector<float> by_list = Cube(*program, [&] {
        faces = 0x3f;
        list.AddView(*gpu_, *state_, item, cluster, faces, DrawTags::kEachBit);
        list.Upload();
        list.Draw(*gpu_, 0);
      });
      EXPECT_EQ(by_list, by_item) << (program == &*layered ? "layered" : "geometry shader");
    }
  }
}

}  // namespace draw_list_test
}  // namespace gistream
