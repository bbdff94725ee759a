// Update validation: unknown ids, NaN/Inf anywhere, out-of-range values are
// INVALID_ARGUMENT naming the field; good updates pass.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "scene/validate_update.h"

namespace gistream {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

Scene TwoNodeScene() {
  Scene s;
  s.nodes.resize(2);
  s.nodes[0].name = "block";
  s.nodes[1].name = "lamp";
  s.nodes[1].light = 0;
  s.lights.resize(1);
  s.materials.resize(1);
  s.roots = {0, 1};
  s.environment = Environment{};
  return s;
}

void ExpectInvalid(const Change& change, const std::string& field) {
  const absl::Status st = ValidateUpdate(TwoNodeScene(), Update{1, change}, 1024, 1024);
  EXPECT_EQ(st.code(), absl::StatusCode::kInvalidArgument) << st;
  EXPECT_NE(std::string(st.message()).find(field), std::string::npos)
      << "message: " << st.message() << "\nexpected to name: " << field;
}

TEST(ValidateUpdate, GoodUpdatesPass) {
  const Scene s = TwoNodeScene();
  NodeTransformUpdate t;
  t.node = 1;
  t.translation = {1, 2, 3};
  EXPECT_TRUE(ValidateUpdate(s, {1, t}, 64, 64).ok());
  LightUpdate l;
  l.intensity = 5.0f;
  EXPECT_TRUE(ValidateUpdate(s, {2, l}, 64, 64).ok());
  CameraUpdate c;
  c.look_at = LookAt{{0, 0, 1}, {0, 0, 0}, {0, 1, 0}};
  c.width = 64;
  c.height = 32;
  EXPECT_TRUE(ValidateUpdate(s, {3, c}, 64, 64).ok());
}

TEST(ValidateUpdate, UnknownIds) {
  NodeTransformUpdate t;
  t.node = 2;
  ExpectInvalid(t, "node");
  LightUpdate l;
  l.light = 1;
  ExpectInvalid(l, "light");
  MaterialUpdate m;
  m.material = 7;
  ExpectInvalid(m, "material");
  CameraUpdate c;
  c.scene_camera = 0;  // the scene has no camera
  ExpectInvalid(c, "scene_camera");
}

TEST(ValidateUpdate, NonFiniteNumbersNameTheirField) {
  NodeTransformUpdate t;
  t.translation.y = kNaN;
  ExpectInvalid(t, "translation.y");
  NodeTransformUpdate r;
  r.rotation.w = kInf;
  ExpectInvalid(r, "rotation");
  LightUpdate l;
  l.intensity = kInf;
  ExpectInvalid(l, "intensity");
  LightUpdate p;
  p.position = glm::vec3(0, kNaN, 0);
  ExpectInvalid(p, "position");
  CameraUpdate c;
  c.yfov_degrees = kNaN;
  ExpectInvalid(c, "yfov");
  CameraUpdate e;
  e.look_at = LookAt{{kInf, 0, 0}, {0, 0, 0}, {0, 1, 0}};
  ExpectInvalid(e, "eye");
  MaterialUpdate m;
  m.base_color = glm::vec4(kNaN, 0, 0, 1);
  ExpectInvalid(m, "base_color");
  EnvironmentUpdate env;
  env.intensity = kNaN;
  ExpectInvalid(env, "intensity");
}

TEST(ValidateUpdate, RangesAreChecked) {
  LightUpdate l;
  l.intensity = -1.0f;
  ExpectInvalid(l, "intensity");
  LightUpdate cone;
  cone.inner_cone_angle = 1.0f;
  cone.outer_cone_angle = 0.5f;
  ExpectInvalid(cone, "cone");
  NodeTransformUpdate s;
  s.scale = {0, 1, 1};
  ExpectInvalid(s, "scale");
  NodeTransformUpdate q;
  q.rotation = glm::quat(0, 0, 0, 0);
  ExpectInvalid(q, "rotation");
  CameraUpdate fov;
  fov.yfov_degrees = 180.0f;
  ExpectInvalid(fov, "yfov");
  CameraUpdate big;
  big.width = 4096;
  big.height = 10;
  ExpectInvalid(big, "width");
  CameraUpdate half;
  half.width = 10;
  ExpectInvalid(half, "height");
  CameraUpdate same;
  same.look_at = LookAt{{1, 1, 1}, {1, 1, 1}, {0, 1, 0}};
  ExpectInvalid(same, "look_at");
}

}  // namespace
}  // namespace gistream
