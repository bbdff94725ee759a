// The stages of ImportGltf after parsing, each validating the part of the
// model it converts. Run in the order declared here: later stages rely on
// the checks of earlier ones (buffer views before accessors, nodes before
// the geometry budget).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene/gltf/gltf_import.h"
#include "scene/scene.h"
#include "scene/gltf/tinygltf.h"
#include "util/status.h"

namespace gistream::gltf {

// gltf_extensions.cpp: the extensions the file uses (extensionsUsed, and
// any found on materials, textures, nodes, meshes and the document) that
// import does not read, sorted: what LoadScene reports as ignored.
std::vector<std::string> IgnoredExtensions(const tinygltf::Model& model);

// gltf_extensions.cpp: what KHR_materials_ior and KHR_materials_specular
// make of a material's dielectric specular layer, F0 = min(((ior - 1) /
// (ior + 1))^2 specularColorFactor, 1) specularFactor and F90 =
// specularFactor (Material::specular_f0 / specular_f90, which the BRDF
// reads: solvers/shading/ggx.h, shaders/common/brdf.glsl):
//   kAbsent   neither extension (F0 0.04, F90 1: ior 1.5);
//   kRead     their factors, applied;
//   kNone     no specular layer (specularFactor 0) on a non-metal: the
//             material is Lambertian, exactly (import sets roughness 1);
//   kIgnored  a specular texture, or an ior below 1: the factors are
//             applied, the texture (or that ior) is not, and the
//             extension is reported as ignored.
enum class DielectricSpecular { kAbsent, kRead, kNone, kIgnored };
struct DielectricFresnel {
  DielectricSpecular kind = DielectricSpecular::kAbsent;
  glm::vec3 f0{0.04f};
  float f90 = 1.0f;
};
DielectricFresnel ClassifyDielectricSpecular(const tinygltf::Material& material);

// gltf_lights.cpp: KHR_lights_punctual lights.
absl::StatusOr<std::vector<Light>> ImportLights(const tinygltf::Model& model);

// gltf_cameras.cpp: perspective cameras. `camera_map` maps each glTF camera
// to its index in the result, or -1 for a skipped orthographic camera.
absl::StatusOr<std::vector<Camera>> ImportCameras(const tinygltf::Model& model,
                                                  std::vector<int>* camera_map);

// gltf_nodes.cpp: the node forest, local transforms, and the default scene.
struct NodeGraph {
  std::vector<Node> nodes;
  std::vector<int> roots;      // the default scene's root nodes
  std::vector<int> instances;  // nodes reachable from `roots`, parents first
};
absl::StatusOr<NodeGraph> ImportNodes(const tinygltf::Model& model,
                                      const std::vector<int>& camera_map,
                                      const ImportLimits& limits);

// gltf_meshes.cpp: triangle and vertex budgets from accessor counts, checked
// before any geometry is read; then the meshes themselves.
absl::Status CheckGeometryBudget(const tinygltf::Model& model, const NodeGraph& graph,
                                 const ImportLimits& limits);
absl::StatusOr<std::vector<Mesh>> ImportMeshes(const tinygltf::Model& model, size_t material_count);

// gltf_skins.cpp: a primitive's JOINTS_0/WEIGHTS_0 and morph targets
// (called by ReadPrimitive once positions are read), the skins, and the
// checks across them once nodes, meshes and skins are in `scene` (target
// counts, node weights, joint indices against each skinned node's skin).
absl::Status ReadSkinAttributes(const tinygltf::Model& model, const tinygltf::Primitive& in,
                                const std::string& field, Primitive* out);
absl::Status ReadMorphTargets(const tinygltf::Model& model, const tinygltf::Primitive& in,
                              const std::string& field, Primitive* out);
absl::StatusOr<std::vector<Skin>> ImportSkins(const tinygltf::Model& model);
absl::Status CheckDeformers(const Scene& scene);

// gltf_animations.cpp: animations, after CheckDeformers (weights channels
// need their node's morph target count).
absl::StatusOr<std::vector<Animation>> ImportAnimations(const tinygltf::Model& model,
                                                        const Scene& scene);

// gltf_materials.cpp: materials, and the images their textures use
// (decoded, within the limits). `budget` as in ParseModel.
absl::Status ImportMaterials(const tinygltf::Model& model, const ImportOptions& options,
                             uint64_t* budget, Scene* scene);

}  // namespace gistream::gltf
