// Skins, per-vertex skinning attributes and morph targets (glTF 2.0 3.7.3
// "Skins" and 3.7.2.2 "Morph Targets"), validated like every accessor.
// They are scene data only: deform.h applies them; rendering does not yet.
#include <algorithm>
#include <cmath>
#include <string>

#include "scene/gltf/gltf_accessors.h"
#include "scene/gltf/gltf_stages.h"
#include "scene/gltf/gltf_util.h"
#include "scene/magnitude_limits.h"
#include "util/log.h"

namespace gistream::gltf {
namespace {

const AccessorSpec kJoints{
    TINYGLTF_TYPE_VEC4,
    {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
    false};
const AccessorSpec kWeights{TINYGLTF_TYPE_VEC4,
                            {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
                            true};
const AccessorSpec kDelta{TINYGLTF_TYPE_VEC3, {TINYGLTF_COMPONENT_TYPE_FLOAT}, false};
const AccessorSpec kMatrices{TINYGLTF_TYPE_MAT4, {TINYGLTF_COMPONENT_TYPE_FLOAT}, false};

absl::StatusOr<AccessorData> VertexAccessor(const tinygltf::Model& model, int index,
                                            const AccessorSpec& spec, const std::string& field,
                                            uint64_t vertices) {
  GS_ASSIGN_OR_RETURN(const AccessorData data, ValidateAccessor(model, index, spec, field));
  if (data.count != vertices) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": ", data.count, " elements but POSITION has ", vertices));
  }
  return data;
}

// Weights are >= 0 and not all zero; they are renormalised to sum to 1
// (exporters quantise them, and only four influences are kept).
absl::Status NormaliseWeights(const std::string& field, std::vector<glm::vec4>* weights) {
  for (size_t i = 0; i < weights->size(); ++i) {
    glm::vec4& w = (*weights)[i];
    for (int j = 0; j < 4; ++j) {
      if (w[j] < 0.0f) {
        return absl::InvalidArgumentError(
            absl::StrCat(field, ": vertex ", i, " has negative weight ", w[j]));
      }
    }
    const float sum = w.x + w.y + w.z + w.w;
    if (!(sum > 0.0f)) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ": vertex ", i, " has all-zero weights"));
    }
    w /= sum;
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status ReadSkinAttributes(const tinygltf::Model& model, const tinygltf::Primitive& in,
                                const std::string& field, Primitive* out) {
  const auto joints = in.attributes.find("JOINTS_0");
  const auto weights = in.attributes.find("WEIGHTS_0");
  const bool has_joints = joints != in.attributes.end();
  const bool has_weights = weights != in.attributes.end();
  if (!has_joints && !has_weights) return absl::OkStatus();
  if (has_joints != has_weights) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ".attributes.", has_joints ? "WEIGHTS_0" : "JOINTS_0",
                     ": missing (JOINTS_0 and WEIGHTS_0 come together)"));
  }
  if (in.attributes.count("JOINTS_1") != 0 || in.attributes.count("WEIGHTS_1") != 0) {
    LogOnce(LogLevel::kWarning, "gltf-joints-1",
            absl::StrCat(field,
                         ".attributes: JOINTS_1/WEIGHTS_1 are ignored; the four "
                         "influences of JOINTS_0/WEIGHTS_0 are renormalised"));
  }
  const uint64_t vertices = out->positions.size();
  const std::string joint_field = field + ".attributes.JOINTS_0";
  const std::string weight_field = field + ".attributes.WEIGHTS_0";
  GS_ASSIGN_OR_RETURN(const AccessorData j,
                      VertexAccessor(model, joints->second, kJoints, joint_field, vertices));
  GS_ASSIGN_OR_RETURN(const AccessorData w,
                      VertexAccessor(model, weights->second, kWeights, weight_field, vertices));
  out->joints = ReadU16Vec4(j);
  GS_ASSIGN_OR_RETURN(const std::vector<float> f, ReadFloatComponents(w));
  out->weights.resize(vertices);
  for (uint64_t i = 0; i < vertices; ++i) {
    out->weights[i] = {f[4 * i], f[4 * i + 1], f[4 * i + 2], f[4 * i + 3]};
  }
  return NormaliseWeights(weight_field, &out->weights);
}

absl::Status ReadMorphTargets(const tinygltf::Model& model, const tinygltf::Primitive& in,
                              const std::string& field, Primitive* out) {
  const uint64_t vertices = out->positions.size();
  for (size_t t = 0; t < in.targets.size(); ++t) {
    const std::string target_field = absl::StrCat(field, ".", Item("targets", t));
    Primitive::MorphTarget target;
    for (const char* name : {"POSITION", "NORMAL"}) {
      const auto it = in.targets[t].find(name);
      if (it == in.targets[t].end()) continue;
      const std::string attr_field = absl::StrCat(target_field, ".", name);
      GS_ASSIGN_OR_RETURN(const AccessorData d,
                          VertexAccessor(model, it->second, kDelta, attr_field, vertices));
      GS_ASSIGN_OR_RETURN(std::vector<glm::vec3> deltas, ReadVec3(d));
      if (std::string_view(name) == "POSITION") {
        for (size_t i = 0; i < deltas.size(); ++i) {
          GS_RETURN_IF_ERROR(CheckPosition(absl::StrCat(attr_field, " element ", i), deltas[i]));
        }
        target.positions = std::move(deltas);
      } else {
        target.normals = std::move(deltas);
      }
    }
    out->targets.push_back(std::move(target));
  }
  // Each delta is within the coordinate limit, but weights up to
  // kMaxMorphWeight sum them: a vertex must stay within the limit however
  // the weights are set (per axis: |p| + kMaxMorphWeight x sum |delta|).
  for (size_t i = 0; i < vertices && !out->targets.empty(); ++i) {
    glm::dvec3 reach = glm::abs(glm::dvec3(out->positions[i]));
    for (const Primitive::MorphTarget& target : out->targets) {
      if (!target.positions.empty()) {
        reach += double(kMaxMorphWeight) * glm::abs(glm::dvec3(target.positions[i]));
      }
    }
    const double far = std::max({reach.x, reach.y, reach.z});
    if (far > double(kMaxCoordinate)) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ".targets: vertex ", i, " reaches ", far, " m at morph weights of +-",
                       kMaxMorphWeight, " (the largest accepted), beyond the coordinate limit of ",
                       kMaxCoordinate, " m"));
    }
  }
  return absl::OkStatus();
}

absl::StatusOr<std::vector<Skin>> ImportSkins(const tinygltf::Model& model) {
  std::vector<Skin> skins(model.skins.size());
  for (size_t s = 0; s < model.skins.size(); ++s) {
    const tinygltf::Skin& in = model.skins[s];
    const std::string field = Item("skins", s);
    Skin& skin = skins[s];
    skin.name = in.name;
    if (in.joints.empty()) {
      return absl::InvalidArgumentError(field + ".joints: empty (a skin needs at least one joint)");
    }
    std::vector<bool> used(model.nodes.size(), false);
    for (size_t k = 0; k < in.joints.size(); ++k) {
      const std::string joint_field = absl::StrCat(field, ".", Item("joints", k));
      GS_RETURN_IF_ERROR(CheckIndex(joint_field, in.joints[k], model.nodes.size(), "nodes"));
      if (used[size_t(in.joints[k])]) {
        return absl::InvalidArgumentError(
            absl::StrCat(joint_field, ": node ", in.joints[k], " is listed twice"));
      }
      used[size_t(in.joints[k])] = true;
    }
    skin.joints = in.joints;
    if (in.skeleton != -1) {
      GS_RETURN_IF_ERROR(CheckIndex(field + ".skeleton", in.skeleton, model.nodes.size(), "nodes"));
      skin.skeleton = in.skeleton;
    }
    skin.inverse_bind_matrices.assign(in.joints.size(), glm::mat4(1.0f));
    if (in.inverseBindMatrices == -1) continue;
    const std::string ibm_field = field + ".inverseBindMatrices";
    GS_ASSIGN_OR_RETURN(const AccessorData d,
                        ValidateAccessor(model, in.inverseBindMatrices, kMatrices, ibm_field));
    if (d.count < in.joints.size()) {
      return absl::InvalidArgumentError(
          absl::StrCat(ibm_field, ": ", d.count, " matrices for ", in.joints.size(), " joints"));
    }
    GS_ASSIGN_OR_RETURN(const std::vector<float> f, ReadFloatComponents(d));
    for (size_t k = 0; k < in.joints.size(); ++k) {
      glm::mat4 m;
      for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) m[c][r] = f[16 * k + size_t(4 * c + r)];  // column-major
      }
      if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f) {
        return absl::InvalidArgumentError(
            absl::StrCat(ibm_field, ": matrix ", k, " is not affine (bottom row not 0, 0, 0, 1)"));
      }
      if (!(std::abs(glm::determinant(glm::mat3(m))) > 1e-12f)) {
        return absl::InvalidArgumentError(absl::StrCat(ibm_field, ": matrix ", k, " is singular"));
      }
      GS_RETURN_IF_ERROR(
          CheckPosition(absl::StrCat(ibm_field, " matrix ", k, " translation"), glm::vec3(m[3])));
      // Its scale (column lengths) within a node's limits: a skinned
      // vertex is moved by it as by a node.
      GS_RETURN_IF_ERROR(
          CheckScale(absl::StrCat(ibm_field, " matrix ", k, " scale"),
                     glm::vec3(glm::length(glm::dvec3(m[0])), glm::length(glm::dvec3(m[1])),
                               glm::length(glm::dvec3(m[2])))));  // (double: 1e30 squared)
      skin.inverse_bind_matrices[k] = m;
    }
  }
  return skins;
}

absl::Status CheckDeformers(const Scene& scene) {
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      if (mesh.primitives[p].targets.size() != mesh.weights.size()) {
        return absl::InvalidArgumentError(absl::StrCat(
            Item("meshes", m), ".", Item("primitives", p),
            ".targets: ", mesh.primitives[p].targets.size(), " targets but the mesh has ",
            mesh.weights.size(), " (every primitive of a mesh has the same number of targets)"));
      }
    }
  }
  for (size_t n = 0; n < scene.nodes.size(); ++n) {
    const Node& node = scene.nodes[n];
    const std::string field = Item("nodes", n);
    if (!node.weights.empty()) {
      const size_t targets = node.mesh >= 0 ? scene.meshes[size_t(node.mesh)].weights.size() : 0;
      if (node.weights.size() != targets) {
        return absl::InvalidArgumentError(absl::StrCat(field, ".weights: ", node.weights.size(),
                                                       " weights but its mesh has ", targets,
                                                       " morph targets"));
      }
    }
    if (node.skin < 0 || node.mesh < 0) continue;
    const size_t joints = scene.skins[size_t(node.skin)].joints.size();
    const std::vector<Primitive>& primitives = scene.meshes[size_t(node.mesh)].primitives;
    for (size_t p = 0; p < primitives.size(); ++p) {
      for (size_t i = 0; i < primitives[p].joints.size(); ++i) {
        const glm::u16vec4 j = primitives[p].joints[i];
        for (int c = 0; c < 4; ++c) {
          if (j[c] >= joints && primitives[p].weights[i][c] > 0.0f) {
            return absl::InvalidArgumentError(absl::StrCat(
                Item("meshes", node.mesh), ".", Item("primitives", p),
                ".attributes.JOINTS_0: vertex ", i, " names joint ", j[c], " but ", field,
                ".skin (", Item("skins", node.skin), ") has ", joints, " joints"));
          }
        }
      }
    }
  }
  return absl::OkStatus();
}

}  // namespace gistream::gltf
