#include "support/deforming_scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>

namespace gistream::testing {

Scene MakeDeformingTube(int rings, int sides, float length, float radius, glm::vec3 origin) {
  Scene scene;
  scene.name = "deforming_tube";
  Primitive p;
  Primitive::MorphTarget bulge;
  for (int r = 0; r < rings; ++r) {
    const float y = length * float(r) / float(rings - 1);
    // Upper-joint weight rises across the middle third of the tube.
    const float w = std::clamp((y / length - 1.0f / 3.0f) * 3.0f, 0.0f, 1.0f);
    const float swell = std::sin(std::numbers::pi_v<float> * y / length);
    for (int s = 0; s < sides; ++s) {
      const float a = 2.0f * std::numbers::pi_v<float> * float(s) / float(sides);
      const glm::vec3 n(std::cos(a), 0.0f, std::sin(a));
      p.positions.push_back(glm::vec3(0.0f, y, 0.0f) + radius * n);
      p.normals.push_back(n);
      p.uvs.emplace_back(float(s) / float(sides), y / length);
      p.joints.emplace_back(0, 1, 0, 0);
      p.weights.emplace_back(1.0f - w, w, 0.0f, 0.0f);
      bulge.positions.push_back(0.5f * radius * swell * n);
      bulge.normals.push_back(glm::vec3(0.0f, -0.2f * swell, 0.0f));
    }
  }
  for (int r = 0; r + 1 < rings; ++r) {
    for (int s = 0; s < sides; ++s) {
      const uint32_t a = uint32_t(r * sides + s), b = uint32_t(r * sides + (s + 1) % sides);
      const uint32_t c = a + uint32_t(sides), d = b + uint32_t(sides);
      p.indices.insert(p.indices.end(), {a, c, b, b, c, d});
    }
  }
  for (const glm::vec3& v : p.positions) p.bounds.Extend(v);
  p.targets.push_back(bulge);
  p.material = 0;
  Mesh mesh;
  mesh.name = "tube";
  mesh.primitives.push_back(std::move(p));
  mesh.weights = {0.0f};
  scene.meshes.push_back(std::move(mesh));
  Material material;
  material.base_color_factor = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
  scene.materials.push_back(material);

  Node tube;
  tube.name = "tube";
  tube.mesh = 0;
  tube.skin = 0;
  tube.translation = origin;
  Node root;
  root.name = "root_joint";
  root.translation = origin;
  root.children = {DeformingTube::kBendJoint};
  Node bend;
  bend.name = "bend_joint";
  bend.parent = DeformingTube::kRootJoint;
  bend.translation = glm::vec3(0.0f, 0.5f * length, 0.0f);
  scene.nodes = {tube, root, bend};
  scene.roots = {DeformingTube::kTubeNode, DeformingTube::kRootJoint};

  Skin skin;
  skin.name = "tube_skin";
  skin.joints = {DeformingTube::kRootJoint, DeformingTube::kBendJoint};
  // Inverse bind matrices: the joints' rest world transforms, inverted.
  skin.inverse_bind_matrices = {
      glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, -0.5f * length, 0.0f))};
  skin.skeleton = DeformingTube::kRootJoint;
  scene.skins.push_back(skin);
  // The IBMs are relative to the root joint, which sits at `origin` like the
  // tube's node: the rest pose is the tube itself.

  Animation bend_anim;
  bend_anim.name = "bend";
  AnimationSampler sampler;
  sampler.times = {0.0f, 2.0f};
  const glm::quat q0(1.0f, 0.0f, 0.0f, 0.0f);
  const glm::quat q1 = glm::angleAxis(DeformingTube::kBendAngle, glm::vec3(0.0f, 0.0f, 1.0f));
  sampler.values = {q0.x, q0.y, q0.z, q0.w, q1.x, q1.y, q1.z, q1.w};
  sampler.components = 4;
  bend_anim.samplers.push_back(sampler);
  bend_anim.channels.push_back({0, DeformingTube::kBendJoint, AnimationPath::kRotation});
  bend_anim.start = 0.0f;
  bend_anim.end = 2.0f;
  scene.animations.push_back(bend_anim);

  for (const Node& n : scene.nodes) {
    if (n.mesh < 0) continue;
    scene.triangle_count += scene.meshes[0].primitives[0].indices.size() / 3;
    scene.vertex_count += scene.meshes[0].primitives[0].positions.size();
  }
  scene.bounds = scene.meshes[0].primitives[0].bounds;
  scene.bounds.min += origin;
  scene.bounds.max += origin;
  return scene;
}

}  // namespace gistream::testing
