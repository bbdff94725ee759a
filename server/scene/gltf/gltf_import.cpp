#include "scene/gltf/gltf_import.h"

#include <absl/strings/str_join.h>

#include <algorithm>
#include <string>

#include "scene/gltf/gltf_accessors.h"
#include "scene/gltf/gltf_parse.h"
#include "scene/gltf/gltf_preflight.h"
#include "scene/gltf/gltf_stages.h"
#include "scene/magnitude_limits.h"
#include "scene/proxies/proxy_levels.h"
#include "scene/gltf/scene_files.h"
#include "util/user_string.h"

namespace gistream {
namespace {

// Totals over node instances. Bounds use the 8 transformed corners of each
// primitive's box: cheap per instance, and never smaller than the truth.
void ComputeTotals(const gltf::NodeGraph& graph, Scene* scene) {
  const std::vector<glm::mat4> world = WorldMatrices(*scene, scene->nodes);
  for (int n : graph.instances) {
    const Node& node = scene->nodes[size_t(n)];
    if (node.mesh < 0) continue;
    for (const Primitive& p : scene->meshes[size_t(node.mesh)].primitives) {
      scene->triangle_count += p.indices.size() / 3;
      scene->vertex_count += p.positions.size();
      if (p.bounds.empty()) continue;
      for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 local((corner & 1) ? p.bounds.max.x : p.bounds.min.x,
                              (corner & 2) ? p.bounds.max.y : p.bounds.min.y,
                              (corner & 4) ? p.bounds.max.z : p.bounds.min.z);
        scene->bounds.Extend(glm::vec3(world[size_t(n)] * glm::vec4(local, 1.0f)));
      }
    }
  }
}

// The magnitude limits (scene/magnitude_limits.h) that import stages cannot
// check one value at a time: local vertex positions, and world positions
// and scales through the node hierarchy.
absl::Status CheckMagnitudes(const Scene& scene) {
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const std::vector<Primitive>& primitives = scene.meshes[m].primitives;
    for (size_t p = 0; p < primitives.size(); ++p) {
      if (primitives[p].bounds.empty()) continue;
      const std::string field =
          absl::StrCat("meshes[", m, "].primitives[", p, "].attributes.POSITION");
      GS_RETURN_IF_ERROR(CheckPosition(field + " min", primitives[p].bounds.min));
      GS_RETURN_IF_ERROR(CheckPosition(field + " max", primitives[p].bounds.max));
    }
  }
  return CheckWorldExtent(scene, scene.nodes, WorldMatrices(scene, scene.nodes), "");
}

// A file name on Linux is at most 255 bytes (NAME_MAX), suffix included.
constexpr size_t kMaxSceneNameBytes = 250;

bool IsSceneName(const std::string& name) {
  if (name.empty() || name.front() == '.' || name.size() > kMaxSceneNameBytes) return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '.' || c == '-';
    if (!ok) return false;
  }
  return true;
}

bool EndsWith(const std::string& s, std::string_view suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

absl::StatusOr<Scene> ImportGltf(std::span<const uint8_t> bytes, const ImportOptions& options) {
  const ImportLimits& limits = options.limits;
  if (bytes.size() > limits.max_scene_bytes || bytes.size() > UINT32_MAX) {
    return absl::ResourceExhaustedError(
        absl::StrCat("scene: ", bytes.size(), " bytes exceed the limit of ",
                     std::min<uint64_t>(limits.max_scene_bytes, UINT32_MAX), " bytes"));
  }
  if (options.memory != nullptr) {
    // The bytes and the parser's copy of their buffers (a .glb's binary
    // chunk, base64 data: URIs decoded).
    GS_RETURN_IF_ERROR(options.memory->Reserve(
        2 * uint64_t(bytes.size()), absl::StrCat("gltf: ", bytes.size(), " bytes while parsing")));
  }
  uint64_t budget = limits.max_scene_bytes - bytes.size();  // for external files
  GS_ASSIGN_OR_RETURN(const gltf::Container container, gltf::SplitContainer(bytes));
  GS_RETURN_IF_ERROR(gltf::PreflightJson(container, options));
  const LoadControl no_control;
  const LoadControl& control = options.control != nullptr ? *options.control : no_control;
  GS_ASSIGN_OR_RETURN(const tinygltf::Model model,
                      gltf::ParseModel(bytes, container, options, &budget));
  GS_RETURN_IF_ERROR(control.Check("import: after parsing"));
  GS_RETURN_IF_ERROR(gltf::ValidateBufferViews(model));

  Scene scene;
  scene.name = options.name;
  scene.ignored_extensions = gltf::IgnoredExtensions(model);
  GS_ASSIGN_OR_RETURN(scene.lights, gltf::ImportLights(model));
  std::vector<int> camera_map;
  GS_ASSIGN_OR_RETURN(scene.cameras, gltf::ImportCameras(model, &camera_map));
  GS_ASSIGN_OR_RETURN(gltf::NodeGraph graph, gltf::ImportNodes(model, camera_map, limits));
  GS_RETURN_IF_ERROR(gltf::CheckGeometryBudget(model, graph, limits));
  GS_RETURN_IF_ERROR(gltf::ImportMaterials(model, options, &budget, &scene));
  GS_ASSIGN_OR_RETURN(scene.meshes, gltf::ImportMeshes(model, scene.materials.size()));
  GS_ASSIGN_OR_RETURN(scene.skins, gltf::ImportSkins(model));
  scene.nodes = std::move(graph.nodes);
  scene.roots = graph.roots;
  GS_RETURN_IF_ERROR(gltf::CheckDeformers(scene));
  GS_ASSIGN_OR_RETURN(scene.animations, gltf::ImportAnimations(model, scene));
  ComputeTotals(graph, &scene);
  GS_RETURN_IF_ERROR(CheckMagnitudes(scene));
  GS_RETURN_IF_ERROR(control.Check("import: before the proxies"));
  ProxyReport report;
  GS_RETURN_IF_ERROR(BuildSceneProxies(&scene, control, &report));
  if (options.proxy_report != nullptr) *options.proxy_report = report;
  return scene;
}

absl::StatusOr<Scene> ImportSceneByName(const std::filesystem::path& scene_dir,
                                        const std::string& name, const ImportLimits& limits,
                                        ImportMemory* memory, const LoadControl* control,
                                        ProxyReport* proxy_report) {
  if (!IsSceneName(name)) {
    return absl::InvalidArgumentError(
        absl::StrCat("name: '", Echo(name), "' is not a scene name ([A-Za-z0-9_.-]+, at most ",
                     kMaxSceneNameBytes, " bytes)"));
  }
  std::vector<std::string> candidates;
  if (EndsWith(name, ".glb") || EndsWith(name, ".gltf")) {
    candidates = {name};
  } else {
    candidates = {name + ".glb", name + ".gltf"};
  }
  for (const std::string& file : candidates) {
    GS_ASSIGN_OR_RETURN(const std::filesystem::path path,
                        ResolveScenePath(scene_dir, file, "name"));
    absl::StatusOr<std::vector<uint8_t>> bytes =
        ReadFileLimited(path, limits.max_scene_bytes, "name");
    if (absl::IsNotFound(bytes.status())) continue;
    if (!bytes.ok()) return bytes.status();
    ImportOptions options;
    options.limits = limits;
    options.base_dir = scene_dir;
    options.name = std::filesystem::path(file).stem().string();
    options.memory = memory;
    options.control = control;
    options.proxy_report = proxy_report;
    return ImportGltf(*bytes, options);
  }
  return absl::NotFoundError(absl::StrCat(
      "name: no scene '", Echo(name), "' (tried ",
      absl::StrJoin(candidates, ", ",
                    [](std::string* out, const std::string& c) { out->append(Echo(c)); }),
      ")"));
}

}  // namespace gistream
