// ValidateUpdate: ids, finiteness and ranges, each message naming the field.
#include "scene/state/validate_update.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "gltf_test_util.h"

namespace gistream {
namespace validate_update_test {

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

// Three nodes: a light, a camera, a mesh; two materials.
Scene TestScene() {
  Scene s;
  s.nodes.resize(3);
  s.nodes[0].light = 0;
  s.nodes[1].camera = 0;
  s.nodes[2].mesh = 0;
  s.lights.resize(1);
  s.cameras.resize(1);
  s.meshes.resize(1);
  s.materials.resize(2);
  return s;
}

NodeTransformUpdate NodeAt(uint32_t node) {
  NodeTransformUpdate u;
  u.node = node;
  return u;
}

LightUpdate LightAt(uint32_t light) {
  LightUpdate u;
  u.light = light;
  return u;
}

absl::Status Validate(Change change, const Scene& scene = TestScene()) {
  return ValidateUpdate(scene, Update{1, std::move(change)}, 4096, 2048);
}

TEST(ValidateUpdate, AcceptsGoodUpdates) {
  NodeTransformUpdate node = NodeAt(2);
  node.translation = {1, 2, 3};
  EXPECT_TRUE(Validate(node).ok());
  LightUpdate light;
  light.color = glm::vec3(1, 0.5f, 0);
  light.intensity = 0.0f;
  light.inner_cone_angle = 0.2f;
  light.outer_cone_angle = 0.2f;
  EXPECT_TRUE(Validate(light).ok());
  CameraUpdate camera;
  camera.look_at = LookAt{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}};
  camera.yfov_degrees = 60.0f;
  camera.width = 4096;
  camera.height = 1;
  EXPECT_TRUE(Validate(camera).ok());
  MaterialUpdate material;
  material.material = 1;
  material.base_color = glm::vec4(1.0f);
  material.emissive = glm::vec3(0, 5, 0);
  material.emissive_strength = 100.0f;
  EXPECT_TRUE(Validate(material).ok());
}

TEST(ValidateUpdate, UnknownIds) {
  EXPECT_ERROR(Validate(NodeAt(3)), kInvalidArgument,
               "update.node_transform.node: 3 is out of range (the scene has 3 nodes)");
  EXPECT_ERROR(Validate(LightAt(1)), kInvalidArgument,
               "update.light.light: 1 is out of range (the scene has 1 light instances)");
  MaterialUpdate material;
  material.material = 2;
  EXPECT_ERROR(Validate(material), kInvalidArgument, "update.material.material: 2 is out of range");
  CameraUpdate camera;
  camera.scene_camera = 1;
  EXPECT_ERROR(Validate(camera), kInvalidArgument, "update.camera.scene_camera: 1 is out of range");
}

TEST(ValidateUpdate, NodeTransformNumbers) {
  NodeTransformUpdate u = NodeAt(0);
  u.translation.y = kNaN;
  EXPECT_ERROR(Validate(u), kInvalidArgument,
               "update.node_transform.translation.y: nan is not finite");
  u = NodeAt(0);
  u.rotation.z = kInf;
  EXPECT_ERROR(Validate(u), kInvalidArgument,
               "update.node_transform.rotation.z: inf is not finite");
  u = NodeAt(0);
  u.rotation = glm::quat(0, 0, 0, 0);
  EXPECT_ERROR(Validate(u), kInvalidArgument,
               "update.node_transform.rotation: zero-length quaternion");
  u = NodeAt(0);
  u.scale.z = 0.0f;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.node_transform.scale.z: 0");
  u = NodeAt(0);
  u.matrix = glm::mat4(1.0f);
  (*u.matrix)[3][1] = -kInf;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.node_transform.matrix[3][1]: -inf");
  (*u.matrix)[3][1] = 0.0f;
  (*u.matrix)[1][1] = 0.0f;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.node_transform.matrix: singular");
  (*u.matrix)[1][1] = 1.0f;
  (*u.matrix)[2][3] = 0.5f;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.node_transform.matrix: bottom row");
}

TEST(ValidateUpdate, LightNumbers) {
  LightUpdate u;
  u.intensity = -1.0f;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.light.intensity: -1 is below 0");
  u = LightUpdate{};
  u.color = glm::vec3(1, -0.5f, 0);
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.light.color.g: -0.5 is below 0");
  u = LightUpdate{};
  u.position = glm::vec3(0, 0, kNaN);
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.light.position.z: nan");
  u = LightUpdate{};
  u.direction = glm::vec3(0);
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.light.direction: zero-length vector");
  u = LightUpdate{};
  u.outer_cone_angle = 2.0f;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.light.outer_cone_angle: 2 exceeds pi/2");
  u = LightUpdate{};
  u.inner_cone_angle = -0.1f;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.light.inner_cone_angle: -0.1 is below 0");
  u = LightUpdate{};
  u.inner_cone_angle = 0.5f;
  u.outer_cone_angle = 0.4f;
  EXPECT_ERROR(Validate(u), kInvalidArgument,
               "update.light.inner_cone_angle: 0.5 exceeds outer_cone_angle 0.4");
}

TEST(ValidateUpdate, CameraNumbers) {
  CameraUpdate u;
  u.look_at = LookAt{{1, 2, 3}, {1, 2, 3}, {0, 1, 0}};
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.camera.look_at: eye equals target");
  u.look_at = LookAt{{0, 0, 0}, {0, 5, 0}, {0, 1, 0}};
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.camera.look_at.up: parallel");
  u.look_at = LookAt{{0, kInf, 0}, {0, 0, 0}, {0, 1, 0}};
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.camera.look_at.eye.y: inf");
  u = CameraUpdate{};
  u.pose = CameraPose{{0, 0, 0}, glm::quat(0, 0, 0, 0)};
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.camera.pose.rotation: zero-length");
  u.scene_camera = 0;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "mutually exclusive");
  for (const float fov : {0.0f, 1e-6f, 0.09f, 179.5f, -5.0f, kNaN}) {
    u = CameraUpdate{};
    u.yfov_degrees = fov;
    EXPECT_ERROR(Validate(u), kInvalidArgument, "update.camera.yfov_degrees:");
  }
}

TEST(ValidateUpdate, Resize) {
  CameraUpdate u;
  u.width = 640;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.camera.height: missing");
  u = CameraUpdate{};
  u.height = 480;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.camera.width: missing");
  u.width = 0;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.camera.width: 0 is out of range [1, 4096]");
  u.width = 4097;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.camera.width: 4097");
  u.width = 640;
  u.height = 2049;
  EXPECT_ERROR(Validate(u), kInvalidArgument,
               "update.camera.height: 2049 is out of range [1, 2048]");
}

TEST(ValidateUpdate, MaterialNumbers) {
  MaterialUpdate u;
  u.base_color = glm::vec4(0.5f, 1.5f, 0, 1);
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.material.base_color.g: 1.5 exceeds 1");
  u.base_color = glm::vec4(0.5f, kNaN, 0, 1);
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.material.base_color.g: nan is not finite");
  u = MaterialUpdate{};
  u.emissive = glm::vec3(-1, 0, 0);
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.material.emissive.r: -1 is below 0");
  u = MaterialUpdate{};
  u.emissive_strength = kInf;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.material.emissive_strength: inf");
  u = MaterialUpdate{};
  u.metallic = 1.5f;
  EXPECT_ERROR(Validate(u), kInvalidArgument,
               "update.material.metallic: 1.5 exceeds the limit of 1");
  u = MaterialUpdate{};
  u.roughness = -0.5f;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.material.roughness: -0.5 is below 0");
  u.roughness = kNaN;
  EXPECT_ERROR(Validate(u), kInvalidArgument, "update.material.roughness: nan is not finite");
  u.roughness = 0.25f;
  u.metallic = 1.0f;
  EXPECT_TRUE(Validate(u).ok());
}

TEST(ValidateUpdate, Environment) {
  EnvironmentUpdate u;
  u.intensity = 2.0f;
  EXPECT_ERROR(Validate(u), kInvalidArgument,
               "update.environment: the scene has no environment map");
  Scene scene = TestScene();
  scene.environment = Environment{};
  EXPECT_TRUE(Validate(u, scene).ok());
  u.intensity = -2.0f;
  EXPECT_ERROR(Validate(u, scene), kInvalidArgument, "update.environment.intensity: -2 is below 0");
  u = EnvironmentUpdate{};
  u.rotation = kNaN;
  EXPECT_ERROR(Validate(u, scene), kInvalidArgument, "update.environment.rotation: nan");
}

}  // namespace validate_update_test
}  // namespace gistream
