// The one CPU implementation of morphing and skinning (glTF 2.0 3.7.2.2
// "Morph Targets" and 3.7.3 "Skins"). Stages that need deformed positions
// on the CPU call this; a GPU version must reproduce it (and be tested
// against it) rather than re-derive the formulas.
#pragma once

#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace gistream {

// Joint matrices that map a skinned mesh's bind-space vertices into the
// mesh node's local space, so the node's world matrix still applies after
// skinning:  J_j = inverse(world[mesh_node]) * world[joints[j]] * IBM_j
// (glTF 2.0 3.7.3.3 "Joint Hierarchy": the skinned mesh node's own
// transform is not part of the skinning). `world` holds every node's world
// matrix (WorldMatrices of the posed nodes).
std::vector<glm::mat4> JointMatrices(const Skin& skin, std::span<const glm::mat4> world,
                                     int mesh_node);

// Whether node `node` draws a mesh that deforms: a primitive with morph
// targets, or with JOINTS_0 under a skin on the node. SceneState keeps a
// posed copy of such a node's mesh.
bool NodeMeshDeforms(const Scene& scene, size_t node);

// Morph weights in effect on a node: its own when it has them, else its
// mesh's defaults.
std::span<const float> MorphWeights(const Scene& scene, const Node& node);

// Deforms one primitive:
//   morph (3.7.2.2):  p' = p + sum_i w_i dP_i,   n' = n + sum_i w_i dN_i
//   skin (linear blend skinning, 3.7.3.3):
//                     p'' = sum_k W_k (J_{j_k} p'),
//                     n'' = normalize(sum_k W_k (N_{j_k} n')),
// with N_j the inverse transpose of J_j's upper 3x3 and (j_k, W_k) the
// vertex's four joints and weights. Influences with zero weight are
// skipped (their joint index is not read). A primitive without joints, or
// an empty `joint_matrices`, is only morphed; `morph_weights` may be
// shorter than the target list (missing weights count as 0).
// `positions` and `normals` are resized to the vertex count.
void DeformPrimitive(const Primitive& primitive, std::span<const float> morph_weights,
                     std::span<const glm::mat4> joint_matrices, std::vector<glm::vec3>* positions,
                     std::vector<glm::vec3>* normals);

}  // namespace gistream
