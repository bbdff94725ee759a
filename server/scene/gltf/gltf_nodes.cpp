#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <string>

#include "scene/gltf/gltf_stages.h"
#include "scene/gltf/gltf_util.h"
#include "scene/magnitude_limits.h"

namespace gistream::gltf {
namespace {

absl::Status CheckLength(const std::string& field, size_t size, size_t expected) {
  if (size != 0 && size != expected) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": ", size, " values, expected ", expected));
  }
  return absl::OkStatus();
}

absl::Status CheckScale(const std::string& field, const glm::dvec3& s) {
  for (int i = 0; i < 3; ++i) {
    if (s[i] == 0.0) {
      return absl::InvalidArgumentError(absl::StrCat(
          field, "[", i, "]: 0; a zero scale collapses the geometry (remove the node instead)"));
    }
  }
  return absl::OkStatus();
}

// glTF matrices are column-major. A node matrix must be a rotation and a
// non-zero scale followed by a translation; shear has no TRS form.
absl::Status DecomposeMatrix(const std::vector<double>& m, const std::string& field, Node* node) {
  GS_RETURN_IF_ERROR(CheckFinite(field, m));
  GS_RETURN_IF_ERROR(CheckRange(field, m, -kMaxFloat, kMaxFloat));
  if (m[3] != 0.0 || m[7] != 0.0 || m[11] != 0.0 || m[15] != 1.0) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": bottom row (", m[3], ", ", m[7], ", ",
                                                   m[11], ", ", m[15], ") is not (0, 0, 0, 1)"));
  }
  glm::dvec3 axis[3];
  glm::dvec3 scale;
  for (int c = 0; c < 3; ++c) {
    axis[c] = glm::dvec3(m[4 * c], m[4 * c + 1], m[4 * c + 2]);
    scale[c] = glm::length(axis[c]);
  }
  GS_RETURN_IF_ERROR(CheckScale(field + " scale", scale));
  if (glm::dot(glm::cross(axis[0], axis[1]), axis[2]) < 0.0) scale.x = -scale.x;  // mirror
  glm::dmat3 r;
  for (int c = 0; c < 3; ++c) r[c] = axis[c] / scale[c];
  const glm::dmat3 error = glm::transpose(r) * r - glm::dmat3(1.0);
  for (int c = 0; c < 3; ++c) {
    if (glm::length(error[c]) > 1e-4) {
      return absl::InvalidArgumentError(
          field + ": has shear, which a translation/rotation/scale cannot represent");
    }
  }
  node->translation = glm::vec3(m[12], m[13], m[14]);
  node->rotation = glm::normalize(glm::quat(glm::quat_cast(r)));
  node->scale = glm::vec3(scale);
  GS_RETURN_IF_ERROR(gistream::CheckPosition(field + " translation", node->translation));
  return gistream::CheckScale(field + " scale", node->scale);
}

absl::Status ReadTrs(const tinygltf::Node& in, const std::string& field, Node* node) {
  GS_RETURN_IF_ERROR(CheckLength(field + ".translation", in.translation.size(), 3));
  GS_RETURN_IF_ERROR(CheckLength(field + ".rotation", in.rotation.size(), 4));
  GS_RETURN_IF_ERROR(CheckLength(field + ".scale", in.scale.size(), 3));
  GS_RETURN_IF_ERROR(CheckRange(field + ".translation", in.translation, -kMaxFloat, kMaxFloat));
  GS_RETURN_IF_ERROR(CheckRange(field + ".rotation", in.rotation, -kMaxFloat, kMaxFloat));
  GS_RETURN_IF_ERROR(CheckRange(field + ".scale", in.scale, -kMaxFloat, kMaxFloat));
  if (!in.translation.empty()) {
    node->translation = glm::vec3(in.translation[0], in.translation[1], in.translation[2]);
    GS_RETURN_IF_ERROR(gistream::CheckPosition(field + ".translation", node->translation));
  }
  if (!in.rotation.empty()) {
    // glTF stores x, y, z, w; glm::quat takes w first.
    const glm::quat q(float(in.rotation[3]), float(in.rotation[0]), float(in.rotation[1]),
                      float(in.rotation[2]));
    GS_ASSIGN_OR_RETURN(node->rotation, gistream::CheckUnitQuaternion(field + ".rotation", q));
  }
  if (!in.scale.empty()) {
    const glm::dvec3 s(in.scale[0], in.scale[1], in.scale[2]);
    GS_RETURN_IF_ERROR(CheckScale(field + ".scale", s));
    node->scale = glm::vec3(s);
    GS_RETURN_IF_ERROR(gistream::CheckScale(field + ".scale", node->scale));
  }
  return absl::OkStatus();
}

absl::Status ReadNode(const tinygltf::Model& model, size_t index,
                      const std::vector<int>& camera_map, Node* node) {
  const tinygltf::Node& in = model.nodes[index];
  const std::string field = Item("nodes", index);
  node->name = in.name;
  if (in.mesh != -1) {
    GS_RETURN_IF_ERROR(CheckIndex(field + ".mesh", in.mesh, model.meshes.size(), "meshes"));
    node->mesh = in.mesh;
  }
  if (in.camera != -1) {
    GS_RETURN_IF_ERROR(CheckIndex(field + ".camera", in.camera, model.cameras.size(), "cameras"));
    node->camera = camera_map[size_t(in.camera)];
  }
  if (const auto ext = in.extensions.find("KHR_lights_punctual"); ext != in.extensions.end()) {
    const std::string light_field = field + ".extensions.KHR_lights_punctual.light";
    if (!ext->second.IsObject() || !ext->second.Get("light").IsInt()) {
      return absl::InvalidArgumentError(light_field + ": missing or not an integer");
    }
    const int light = ext->second.Get("light").GetNumberAsInt();
    GS_RETURN_IF_ERROR(CheckIndex(light_field, light, model.lights.size(), "lights"));
    node->light = light;
  }
  if (in.skin != -1) {
    GS_RETURN_IF_ERROR(CheckIndex(field + ".skin", in.skin, model.skins.size(), "skins"));
    node->skin = in.skin;
  }
  GS_RETURN_IF_ERROR(CheckFinite(field + ".weights", in.weights));
  node->weights.assign(in.weights.begin(), in.weights.end());
  if (!in.matrix.empty()) {
    GS_RETURN_IF_ERROR(CheckLength(field + ".matrix", in.matrix.size(), 16));
    if (!in.translation.empty() || !in.rotation.empty() || !in.scale.empty()) {
      return absl::InvalidArgumentError(field + ": has both matrix and translation/rotation/scale");
    }
    return DecomposeMatrix(in.matrix, field + ".matrix", node);
  }
  return ReadTrs(in, field, node);
}

// Every node has at most one parent and no node is its own ancestor.
absl::Status LinkChildren(const tinygltf::Model& model, std::vector<Node>* nodes) {
  for (size_t i = 0; i < model.nodes.size(); ++i) {
    const std::vector<int>& children = model.nodes[i].children;
    for (size_t k = 0; k < children.size(); ++k) {
      const std::string field = absl::StrCat(Item("nodes", i), ".", Item("children", k));
      const int child = children[k];
      GS_RETURN_IF_ERROR(CheckIndex(field, child, nodes->size(), "nodes"));
      Node& c = (*nodes)[size_t(child)];
      if (size_t(child) == i) {
        return absl::InvalidArgumentError(
            absl::StrCat(field, ": node ", child, " is its own child (a cycle)"));
      }
      if (c.parent >= 0) {
        return absl::InvalidArgumentError(absl::StrCat(field, ": node ", child,
                                                       " already has parent nodes[", c.parent,
                                                       "]; a node may have only one parent"));
      }
      c.parent = static_cast<int>(i);
      (*nodes)[i].children.push_back(child);
    }
  }
  return absl::OkStatus();
}

// With at most one parent each, a node that no parentless node reaches sits
// on (or below) a cycle.
absl::Status CheckAcyclic(const std::vector<Node>& nodes) {
  std::vector<bool> reached(nodes.size(), false);
  std::vector<int> stack;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].parent < 0) stack.push_back(static_cast<int>(i));
  }
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    reached[size_t(n)] = true;
    for (int c : nodes[size_t(n)].children) stack.push_back(c);
  }
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (reached[i]) continue;
    // Walk up from i; the walk loops, so the node seen twice is on the cycle.
    std::vector<bool> seen(nodes.size(), false);
    int n = static_cast<int>(i);
    while (!seen[size_t(n)]) {
      seen[size_t(n)] = true;
      n = nodes[size_t(n)].parent;
    }
    // Parent links run against the children lists; reverse them for the
    // message, which reads parent -> child.
    std::vector<int> up;
    for (int m = nodes[size_t(n)].parent; m != n; m = nodes[size_t(m)].parent) up.push_back(m);
    std::string chain = Item("nodes", n);
    for (size_t k = up.size(), printed = 0; k-- > 0; ++printed) {
      if (printed == 8) {
        absl::StrAppend(&chain, " -> ...");
        break;
      }
      absl::StrAppend(&chain, " -> ", Item("nodes", up[k]));
    }
    absl::StrAppend(&chain, " -> ", Item("nodes", n));
    return absl::InvalidArgumentError(absl::StrCat(Item("nodes", nodes[size_t(n)].parent),
                                                   ".children: the node graph has a cycle (", chain,
                                                   ")"));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::vector<int>> DefaultSceneRoots(const tinygltf::Model& model,
                                                   const std::vector<Node>& nodes) {
  std::vector<int> roots;
  if (model.scenes.empty()) {
    // No scene: every parentless node is shown.
    for (size_t i = 0; i < nodes.size(); ++i) {
      if (nodes[i].parent < 0) roots.push_back(static_cast<int>(i));
    }
    return roots;
  }
  const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
  GS_RETURN_IF_ERROR(CheckIndex("scene", scene, model.scenes.size(), "scenes"));
  const std::vector<int>& listed = model.scenes[size_t(scene)].nodes;
  std::vector<bool> used(nodes.size(), false);
  for (size_t k = 0; k < listed.size(); ++k) {
    const std::string field = absl::StrCat(Item("scenes", scene), ".", Item("nodes", k));
    const int n = listed[k];
    GS_RETURN_IF_ERROR(CheckIndex(field, n, nodes.size(), "nodes"));
    if (nodes[size_t(n)].parent >= 0) {
      return absl::InvalidArgumentError(absl::StrCat(
          field, ": node ", n, " is not a root (child of nodes[", nodes[size_t(n)].parent, "])"));
    }
    if (used[size_t(n)]) {
      return absl::InvalidArgumentError(absl::StrCat(field, ": node ", n, " is listed twice"));
    }
    used[size_t(n)] = true;
    roots.push_back(n);
  }
  return roots;
}

}  // namespace

absl::StatusOr<NodeGraph> ImportNodes(const tinygltf::Model& model,
                                      const std::vector<int>& camera_map,
                                      const ImportLimits& limits) {
  if (model.nodes.size() > limits.max_nodes) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "nodes: ", model.nodes.size(), " nodes exceed the limit of ", limits.max_nodes));
  }
  NodeGraph graph;
  graph.nodes.resize(model.nodes.size());
  for (size_t i = 0; i < model.nodes.size(); ++i) {
    GS_RETURN_IF_ERROR(ReadNode(model, i, camera_map, &graph.nodes[i]));
  }
  GS_RETURN_IF_ERROR(LinkChildren(model, &graph.nodes));
  GS_RETURN_IF_ERROR(CheckAcyclic(graph.nodes));
  GS_ASSIGN_OR_RETURN(graph.roots, DefaultSceneRoots(model, graph.nodes));

  std::vector<int> stack(graph.roots.rbegin(), graph.roots.rend());
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    graph.instances.push_back(n);
    const std::vector<int>& children = graph.nodes[size_t(n)].children;
    stack.insert(stack.end(), children.rbegin(), children.rend());
  }
  return graph;
}

}  // namespace gistream::gltf
