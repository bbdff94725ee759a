#include <numeric>
#include <string>

#include "scene/gltf/gltf_accessors.h"
#include "scene/gltf/gltf_stages.h"
#include "scene/gltf/gltf_util.h"
#include "scene/gltf/mesh_normals.h"
#include "util/log.h"

namespace gistream::gltf {
namespace {

// Triangles are imported: lists as they are, strips and fans as the lists
// they draw (TrianglesOf). Points and lines have no area, so they cannot
// take part in light transport: skipped with a log line.
absl::StatusOr<bool> IsTriangles(const tinygltf::Primitive& p, const std::string& field) {
  switch (p.mode) {
    case -1:  // tinygltf: not given, which means TRIANGLES
    case TINYGLTF_MODE_TRIANGLES:
    case TINYGLTF_MODE_TRIANGLE_STRIP:
    case TINYGLTF_MODE_TRIANGLE_FAN: return true;
    case TINYGLTF_MODE_POINTS:
    case TINYGLTF_MODE_LINE:
    case TINYGLTF_MODE_LINE_LOOP:
    case TINYGLTF_MODE_LINE_STRIP:
      LogOnce(LogLevel::kWarning, "gltf-points-lines",
              absl::StrCat(field, ".mode: ", p.mode,
                           " (points/lines) has no area; such primitives are skipped"));
      return false;
  }
  return absl::InvalidArgumentError(absl::StrCat(field, ".mode: ", p.mode, " is not a glTF mode"));
}

bool IsStripOrFan(int mode) {
  return mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

// The triangles a primitive of `mode` draws from `count` vertices (or indices).
uint64_t TriangleCount(int mode, uint64_t count) {
  if (IsStripOrFan(mode)) return count >= 3 ? count - 2 : 0;
  return count / 3;
}

// The triangle list a strip or fan of vertex sequence `v` draws (glTF 2.0
// Sec. 3.7.2.1: strip triangle i = {v_i, v_{i+(1+i%2)}, v_{i+(2-i%2)}},
// fan triangle i = {v_{i+1}, v_{i+2}, v_0}, so every triangle keeps the
// first one's winding); degenerate ones (a repeated vertex, as strips use
// to join runs) are left out.
std::vector<uint32_t> TrianglesOf(int mode, const std::vector<uint32_t>& v) {
  std::vector<uint32_t> out;
  for (size_t i = 0; i + 2 < v.size(); ++i) {
    const bool strip = mode == TINYGLTF_MODE_TRIANGLE_STRIP;
    const uint32_t a = strip ? v[i] : v[i + 1];
    const uint32_t b = strip ? v[i + 1 + i % 2] : v[i + 2];
    const uint32_t c = strip ? v[i + 2 - i % 2] : v[0];
    if (a == b || b == c || a == c) continue;
    out.insert(out.end(), {a, b, c});
  }
  return out;
}

std::string PrimitiveField(size_t mesh, size_t primitive) {
  return absl::StrCat(Item("meshes", mesh), ".", Item("primitives", primitive));
}

absl::StatusOr<int> PositionAccessor(const tinygltf::Model& model, const tinygltf::Primitive& p,
                                     const std::string& field) {
  const auto it = p.attributes.find("POSITION");
  if (it == p.attributes.end()) {
    return absl::InvalidArgumentError(field + ".attributes.POSITION: missing");
  }
  GS_RETURN_IF_ERROR(
      CheckIndex(field + ".attributes.POSITION", it->second, model.accessors.size(), "accessors"));
  return it->second;
}

const AccessorSpec kVec3Float{TINYGLTF_TYPE_VEC3, {TINYGLTF_COMPONENT_TYPE_FLOAT}, false};
const AccessorSpec kTexcoord{TINYGLTF_TYPE_VEC2,
                             {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                              TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
                             true};
const AccessorSpec kIndices{
    TINYGLTF_TYPE_SCALAR,
    {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
     TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
    false};

// Normalizes file normals; false when one cannot be normalized.
bool NormalizeAll(std::vector<glm::vec3>* normals) {
  for (glm::vec3& n : *normals) {
    const float len = glm::length(n);
    if (!(len > 1e-20f) || !std::isfinite(len)) return false;
    n /= len;
  }
  return true;
}

absl::StatusOr<gistream::Primitive> ReadPrimitive(const tinygltf::Model& model,
                                                  const tinygltf::Primitive& in,
                                                  const std::string& field, size_t material_count) {
  gistream::Primitive out;
  if (in.material != -1) {
    GS_RETURN_IF_ERROR(CheckIndex(field + ".material", in.material, material_count, "materials"));
    out.material = in.material;
  }
  GS_ASSIGN_OR_RETURN(const int position_index, PositionAccessor(model, in, field));
  GS_ASSIGN_OR_RETURN(
      const AccessorData positions,
      ValidateAccessor(model, position_index, kVec3Float, field + ".attributes.POSITION"));
  GS_ASSIGN_OR_RETURN(out.positions, ReadVec3(positions));
  const uint64_t vertices = positions.count;

  bool has_normals = false;
  if (const auto it = in.attributes.find("NORMAL"); it != in.attributes.end()) {
    const std::string normal_field = field + ".attributes.NORMAL";
    GS_ASSIGN_OR_RETURN(const AccessorData normals,
                        ValidateAccessor(model, it->second, kVec3Float, normal_field));
    if (normals.count != vertices) {
      return absl::InvalidArgumentError(
          absl::StrCat(normal_field, ": ", normals.count, " elements but POSITION has ", vertices));
    }
    GS_ASSIGN_OR_RETURN(out.normals, ReadVec3(normals));
    has_normals = NormalizeAll(&out.normals);
    if (!has_normals) {
      LogOnce(LogLevel::kWarning, "gltf-zero-normal",
              absl::StrCat(normal_field, ": zero-length normals; normals regenerated"));
    }
  }
  if (const auto it = in.attributes.find("TEXCOORD_0"); it != in.attributes.end()) {
    const std::string uv_field = field + ".attributes.TEXCOORD_0";
    GS_ASSIGN_OR_RETURN(const AccessorData uvs,
                        ValidateAccessor(model, it->second, kTexcoord, uv_field));
    if (uvs.count != vertices) {
      return absl::InvalidArgumentError(
          absl::StrCat(uv_field, ": ", uvs.count, " elements but POSITION has ", vertices));
    }
    GS_ASSIGN_OR_RETURN(out.uvs, ReadVec2(uvs));
  }

  const bool list = !IsStripOrFan(in.mode);
  if (in.indices != -1) {
    const std::string index_field = field + ".indices";
    GS_ASSIGN_OR_RETURN(const AccessorData indices,
                        ValidateAccessor(model, in.indices, kIndices, index_field));
    if (list && indices.count % 3 != 0) {
      return absl::InvalidArgumentError(
          absl::StrCat(index_field, ": ", indices.count, " indices do not form whole triangles"));
    }
    GS_ASSIGN_OR_RETURN(out.indices, ReadIndices(indices, vertices, index_field));
  } else {
    if ((list && vertices % 3 != 0) || vertices > UINT32_MAX) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ".attributes.POSITION: ", vertices,
                       " vertices without indices do not form whole triangles"));
    }
    out.indices.resize(vertices);
    std::iota(out.indices.begin(), out.indices.end(), 0u);
  }
  if (!list) out.indices = TrianglesOf(in.mode, out.indices);

  GS_RETURN_IF_ERROR(ReadSkinAttributes(model, in, field, &out));
  GS_RETURN_IF_ERROR(ReadMorphTargets(model, in, field, &out));
  if (!has_normals) GenerateNormals(&out);
  for (const glm::vec3& p : out.positions) out.bounds.Extend(p);
  return out;
}

}  // namespace

absl::Status CheckGeometryBudget(const tinygltf::Model& model, const NodeGraph& graph,
                                 const ImportLimits& limits) {
  std::vector<uint64_t> instances(model.meshes.size(), 0);
  for (int n : graph.instances) {
    if (graph.nodes[size_t(n)].mesh >= 0) ++instances[size_t(graph.nodes[size_t(n)].mesh)];
  }
  uint64_t triangles = 0;
  uint64_t instanced = 0;
  uint64_t vertices = 0;
  uint64_t draw_items = 0;
  if (model.materials.size() > limits.max_materials) {
    return absl::ResourceExhaustedError(absl::StrCat("materials: ", model.materials.size(),
                                                     " materials exceed the limit of ",
                                                     limits.max_materials, " (--max-materials)"));
  }
  for (size_t m = 0; m < model.meshes.size(); ++m) {
    if (!MulAdd(model.meshes[m].primitives.size(), instances[m], draw_items, &draw_items)) {
      return absl::ResourceExhaustedError(absl::StrCat("meshes[", m, "]: draw counts overflow"));
    }
    for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
      const tinygltf::Primitive& prim = model.meshes[m].primitives[p];
      const std::string field = PrimitiveField(m, p);
      GS_ASSIGN_OR_RETURN(const bool triangles_drawn, IsTriangles(prim, field));
      if (!triangles_drawn) continue;
      GS_ASSIGN_OR_RETURN(const int position, PositionAccessor(model, prim, field));
      const uint64_t count = model.accessors[size_t(position)].count;
      uint64_t tris = TriangleCount(prim.mode, count);
      if (prim.indices != -1) {
        GS_RETURN_IF_ERROR(
            CheckIndex(field + ".indices", prim.indices, model.accessors.size(), "accessors"));
        tris = TriangleCount(prim.mode, model.accessors[size_t(prim.indices)].count);
      }
      if (!MulAdd(1, vertices, count, &vertices) || !MulAdd(1, triangles, tris, &triangles) ||
          !MulAdd(tris, instances[m], instanced, &instanced)) {
        return absl::ResourceExhaustedError(field + ": geometry counts overflow");
      }
    }
  }
  if (draw_items > limits.max_draw_items) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "meshes: ", draw_items,
        " primitives drawn (primitives x the nodes instancing their mesh) exceed the limit of ",
        limits.max_draw_items, " (--max-draw-items)"));
  }
  if (triangles > limits.max_triangles || instanced > limits.max_triangles) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "meshes: ", std::max(triangles, instanced),
        " triangles (over all node instances) exceed the limit of ", limits.max_triangles));
  }
  // A triangle list never needs more than three vertices per triangle; this
  // also bounds memory when many primitives share one large vertex accessor.
  const uint64_t max_vertices = 3 * limits.max_triangles;
  if (vertices > max_vertices) {
    return absl::ResourceExhaustedError(absl::StrCat("meshes: ", vertices,
                                                     " vertices exceed the limit of ", max_vertices,
                                                     " (3 per allowed triangle)"));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::vector<Mesh>> ImportMeshes(const tinygltf::Model& model,
                                               size_t material_count) {
  std::vector<Mesh> meshes(model.meshes.size());
  for (size_t m = 0; m < model.meshes.size(); ++m) {
    meshes[m].name = model.meshes[m].name;
    for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
      const tinygltf::Primitive& prim = model.meshes[m].primitives[p];
      const std::string field = PrimitiveField(m, p);
      GS_ASSIGN_OR_RETURN(const bool triangles_drawn, IsTriangles(prim, field));
      if (!triangles_drawn) continue;
      GS_ASSIGN_OR_RETURN(gistream::Primitive primitive,
                          ReadPrimitive(model, prim, field, material_count));
      meshes[m].primitives.push_back(std::move(primitive));
    }
    // Default morph weights (glTF 2.0 3.7.2.2); CheckDeformers compares
    // every primitive's target count with them.
    const std::vector<double>& weights = model.meshes[m].weights;
    const size_t targets =
        model.meshes[m].primitives.empty() ? 0 : model.meshes[m].primitives[0].targets.size();
    const std::string weight_field = Item("meshes", m) + ".weights";
    if (!weights.empty() && weights.size() != targets) {
      return absl::InvalidArgumentError(absl::StrCat(weight_field, ": ", weights.size(),
                                                     " weights but the mesh has ", targets,
                                                     " morph targets"));
    }
    GS_RETURN_IF_ERROR(CheckFinite(weight_field, weights));
    meshes[m].weights.assign(targets, 0.0f);
    for (size_t k = 0; k < weights.size(); ++k) meshes[m].weights[k] = float(weights[k]);
  }
  return meshes;
}

}  // namespace gistream::gltf
