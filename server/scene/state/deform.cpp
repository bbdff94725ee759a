#include "scene/state/deform.h"

#include <algorithm>
#include <cmath>

#include "util/status.h"

namespace gistream {
namespace {

// A morph or blend can cancel a normal; keep the bind-pose one then.
glm::vec3 SafeNormalize(const glm::vec3& n, const glm::vec3& fallback) {
  const float len = glm::length(n);
  return len > 1e-20f && std::isfinite(len) ? n / len : fallback;
}

}  // namespace

std::vector<glm::mat4> JointMatrices(const Skin& skin, std::span<const glm::mat4> world,
                                     int mesh_node) {
  const glm::mat4 to_mesh = glm::inverse(world[size_t(mesh_node)]);
  std::vector<glm::mat4> out(skin.joints.size());
  for (size_t j = 0; j < skin.joints.size(); ++j) {
    out[j] = to_mesh * world[size_t(skin.joints[j])] * skin.inverse_bind_matrices[j];
  }
  return out;
}

bool NodeMeshDeforms(const Scene& scene, size_t node) {
  const Node& n = scene.nodes[node];
  if (n.mesh < 0 || size_t(n.mesh) >= scene.meshes.size()) return false;
  for (const Primitive& p : scene.meshes[size_t(n.mesh)].primitives) {
    if (!p.targets.empty() || (n.skin >= 0 && !p.joints.empty())) return true;
  }
  return false;
}

std::span<const float> MorphWeights(const Scene& scene, const Node& node) {
  if (!node.weights.empty()) return node.weights;
  if (node.mesh < 0) return {};
  return scene.meshes[size_t(node.mesh)].weights;
}

void DeformPrimitive(const Primitive& p, std::span<const float> morph_weights,
                     std::span<const glm::mat4> joint_matrices, std::vector<glm::vec3>* positions,
                     std::vector<glm::vec3>* normals) {
  *positions = p.positions;
  *normals = p.normals;
  const size_t targets = std::min(morph_weights.size(), p.targets.size());
  for (size_t t = 0; t < targets; ++t) {
    const float w = morph_weights[t];
    if (w == 0.0f) continue;
    const Primitive::MorphTarget& target = p.targets[t];
    for (size_t i = 0; i < target.positions.size(); ++i) (*positions)[i] += w * target.positions[i];
    for (size_t i = 0; i < target.normals.size(); ++i) (*normals)[i] += w * target.normals[i];
  }
  if (p.joints.empty() || joint_matrices.empty()) {
    if (targets > 0) {
      for (size_t i = 0; i < normals->size(); ++i) {
        (*normals)[i] = SafeNormalize((*normals)[i], p.normals[i]);
      }
    }
    return;
  }
  std::vector<glm::mat3> normal_matrices(joint_matrices.size());
  for (size_t j = 0; j < joint_matrices.size(); ++j) {
    normal_matrices[j] = glm::transpose(glm::inverse(glm::mat3(joint_matrices[j])));
  }
  for (size_t i = 0; i < positions->size(); ++i) {
    const glm::vec4 pos((*positions)[i], 1.0f);
    const glm::vec3 nrm = (*normals)[i];
    glm::vec3 ps(0.0f), ns(0.0f);
    for (int k = 0; k < 4; ++k) {
      const float w = p.weights[i][k];
      if (w == 0.0f) continue;
      const size_t j = p.joints[i][k];
      GS_CHECK(j < joint_matrices.size());
      ps += w * glm::vec3(joint_matrices[j] * pos);
      ns += w * (normal_matrices[j] * nrm);
    }
    (*positions)[i] = ps;
    (*normals)[i] = SafeNormalize(ns, p.normals[i]);
  }
}

}  // namespace gistream
