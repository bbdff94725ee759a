// CPU-side scene model: what a glTF file describes after import and
// validation. Everything here is plain data; the GPU copy lives in
// gpu_scene.h and the mutable, versioned state in scene_state.h.
#pragma once

#include <compare>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_precision.hpp>

namespace gistream {

// Axis-aligned box; empty() until a point is added.
struct Bounds {
  glm::vec3 min{std::numeric_limits<float>::max()};
  glm::vec3 max{std::numeric_limits<float>::lowest()};

  bool empty() const { return min.x > max.x; }
  void Extend(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void Extend(const Bounds& b) {
    if (b.empty()) return;
    Extend(b.min);
    Extend(b.max);
  }
  glm::vec3 center() const { return 0.5f * (min + max); }
  glm::vec3 extent() const { return max - min; }
  // The world box of this (local) box's eight corners under `m`; empty
  // stays empty.
  Bounds Transformed(const glm::mat4& m) const;
};

// Decoded texture. 8-bit textures keep their encoding (`srgb` says whether
// texels are sRGB-encoded); float images (environment maps) are linear.
struct Image {
  std::string name;
  int width = 0;
  int height = 0;
  int channels = 4;  // always 4 (RGBA) after import
  bool srgb = true;
  std::vector<uint8_t> pixels8;  // width*height*4, when !is_float
  std::vector<float> pixelsf;    // width*height*4, when is_float
  bool is_float = false;
};

// KHR_texture_transform of one texture reference: uv' = (dot(u, (uv, 1)),
// dot(v, (uv, 1))), the rows of the extension's offset x rotation x scale
// matrix. The identity when the file has none.
struct UvTransform {
  glm::vec3 u{1.0f, 0.0f, 0.0f};
  glm::vec3 v{0.0f, 1.0f, 0.0f};
  glm::vec2 Apply(const glm::vec2& uv) const {
    const glm::vec3 h(uv, 1.0f);
    return {glm::dot(u, h), glm::dot(v, h)};
  }
};

// A texture reference's sampler (glTF 2.0 5.26), in the file's values,
// which are GL's enums: wrap 10497 REPEAT (the default), 33071
// CLAMP_TO_EDGE, 33648 MIRRORED_REPEAT; magFilter 9728 NEAREST or 9729
// LINEAR; minFilter those or 9984-9987 (the four mipmap modes); 0: not
// given (the renderer's choice: linear, trilinear). Import accepts only
// these values.
struct TextureSampler {
  static constexpr int kRepeat = 10497, kClampToEdge = 33071, kMirroredRepeat = 33648;
  static constexpr int kNearest = 9728, kLinear = 9729;
  int wrap_s = kRepeat, wrap_t = kRepeat;
  int mag_filter = 0, min_filter = 0;
  auto operator<=>(const TextureSampler&) const = default;
};

struct Material {
  std::string name;
  glm::vec4 base_color_factor{1.0f};  // linear
  int base_color_texture = -1;        // index into Scene::images
  glm::vec3 emissive_factor{0.0f};    // linear
  float emissive_strength = 1.0f;     // KHR_materials_emissive_strength
  int emissive_texture = -1;
  // glTF metallic-roughness (the GGX BRDF, shaders/common/brdf.glsl and
  // solvers/shading/ggx.h). Import sets both from the file (absent: 1 and
  // 1, glTF 2.0 5.22); this default, metallic 0 and roughness 1, is the
  // Lambertian surface that the default material and scenes built in code
  // have always been.
  float metallic_factor = 0.0f;
  float roughness_factor = 1.0f;
  int metallic_roughness_texture = -1;  // linear; B: metallic, G: roughness
  // Each texture's KHR_texture_transform (identity without one) and
  // sampler (repeat, linear without one).
  UvTransform base_color_uv, emissive_uv, metallic_roughness_uv;
  TextureSampler base_color_sampler, emissive_sampler, metallic_roughness_sampler;
  // The dielectric part's Fresnel at normal and at grazing incidence
  // (solvers/shading/ggx.h): 0.04 and 1 (ior 1.5) unless the file's
  // KHR_materials_ior / KHR_materials_specular set them (gltf_materials).
  glm::vec3 specular_f0{0.04f};
  float specular_f90 = 1.0f;
  bool double_sided = false;

  // Emitted radiance (nits) of an untextured texel.
  glm::vec3 emission() const { return emissive_factor * emissive_strength; }
  bool emissive() const {
    const glm::vec3 e = emission();
    return e.x > 0.0f || e.y > 0.0f || e.z > 0.0f;
  }
};

// A simplified copy of a primitive's triangles for the view-independent GI
// passes (scene/proxies/proxy_levels.h): indices into the primitive's own vertices
// and an upper bound of its symmetric Hausdorff distance to the full mesh.
struct ProxyLevel {
  std::vector<uint32_t> indices;  // triangle list, a subset of the primitive's vertices
  float error = 0.0f;             // local units
};

// A node of a primitive's proxy cluster tree (scene/proxies/proxy_clusters.h): a
// k-d split of its triangles, each node with its local box, a simplified
// copy of its triangles with the node's border locked (so any cut through
// the tree is watertight) and that copy's error bound; leaves also hold
// their full triangles.
struct ProxyCluster {
  Bounds bounds;                  // local box of the node's full triangles
  std::vector<uint32_t> indices;  // leaves: their full triangles; inner nodes: empty
  ProxyLevel level;               // empty indices: no simplified copy (draw the children)
  int children[2] = {-1, -1};     // -1: a leaf
};

// One draw: triangles with one material. Attributes are in the mesh's
// local space; normals are always present after import (generated when the
// file has none), uvs may be empty.
struct Primitive {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  std::vector<uint32_t> indices;  // triangle list, always indexed after import
  int material = -1;              // -1: the default material
  Bounds bounds;
  // Skinning (glTF JOINTS_0 / WEIGHTS_0): both empty, or one entry per
  // vertex. Joints index the skin's `joints`; weights are >= 0 and sum to 1.
  std::vector<glm::u16vec4> joints;
  std::vector<glm::vec4> weights;
  // Morph targets: per target, POSITION and NORMAL deltas (each empty or
  // one per vertex). Every primitive of a mesh has the same target count.
  struct MorphTarget {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
  };
  std::vector<MorphTarget> targets;
  // Simplified levels, finest first (each at most half the triangles of
  // the one before); empty when the primitive is small or deforms.
  std::vector<ProxyLevel> proxies;
  // The cluster tree, root first; empty when `proxies` is (or the
  // primitive fits one cluster).
  std::vector<ProxyCluster> clusters;
};

struct Mesh {
  std::string name;
  std::vector<Primitive> primitives;
  std::vector<float> weights = {};  // default morph weights, one per target (zeros when not given)
};

// glTF skin: joints are node indices; inverse_bind_matrices has one matrix
// per joint (identity when the file gives none).
struct Skin {
  std::string name;
  std::vector<int> joints;
  std::vector<glm::mat4> inverse_bind_matrices;
  int skeleton = -1;  // the common root node, -1 when not given
};

// glTF animation data (see scene/state/animation.h for sampling).
enum class AnimationPath { kTranslation, kRotation, kScale, kWeights };
enum class Interpolation { kLinear, kStep, kCubicSpline };

struct AnimationSampler {
  std::vector<float> times;  // seconds, finite, strictly increasing, >= 0
  Interpolation interpolation = Interpolation::kLinear;
  // `components` floats per output element, elements in key order; for
  // CUBICSPLINE each key has three elements: in-tangent, value,
  // out-tangent. Rotations are x, y, z, w (glTF order), values unit length.
  // Empty when no channel uses the sampler.
  std::vector<float> values;
  int components = 0;
};

struct AnimationChannel {
  int sampler = -1;
  int node = -1;
  AnimationPath path = AnimationPath::kTranslation;
};

struct Animation {
  std::string name;
  std::vector<AnimationSampler> samplers;
  std::vector<AnimationChannel> channels;
  float start = 0.0f;  // earliest and latest key time over the samplers
  float end = 0.0f;
};

enum class LightType { kPoint, kSpot, kDirectional };

// KHR_lights_punctual light. Position and direction come from its node:
// the light shines down the node's -Z.
struct Light {
  std::string name;
  LightType type = LightType::kPoint;
  glm::vec3 color{1.0f};
  float intensity = 1.0f;  // candela (point/spot) or lux (directional)
  float range = 0.0f;      // 0: unlimited
  float inner_cone_angle = 0.0f;
  float outer_cone_angle = 0.78539816f;  // pi/4
};

struct Camera {
  std::string name;
  float yfov = 0.8f;  // radians
  float znear = 0.01f;
  float zfar = 0.0f;  // 0: infinite
};

struct Node {
  std::string name;
  int parent = -1;
  std::vector<int> children;
  int mesh = -1;
  int light = -1;   // index into Scene::lights
  int camera = -1;  // index into Scene::cameras
  // Local transform as TRS (a glTF matrix is decomposed on import).
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // w, x, y, z
  glm::vec3 scale{1.0f};
  int skin = -1;               // index into Scene::skins
  std::vector<float> weights;  // morph weights overriding the mesh's; empty: the mesh's
};

// One region of an environment map's median cut (scene/environment_cut.h)
// as a directional light.
struct EnvironmentRegionLight {
  glm::vec3 to_sky{0.0f, 1.0f, 0.0f};  // unit, from the scene towards the region
  glm::vec3 irradiance{0.0f};          // sum of L d(omega) over the region (lux)
};

struct Environment {
  Image image;  // equirectangular, linear float RGBA
  float intensity = 1.0f;
  float rotation = 0.0f;      // radians about +Y
  float max_radiance = 0.0f;  // largest channel of `image`, for the magnitude limits
  // The map cut into kEnvironmentLightCount lights at load (on the
  // loader's thread, not a render thread), unrotated, at intensity 1.
  std::vector<EnvironmentRegionLight> light_cut;
};

struct Scene {
  std::string name;
  std::vector<Node> nodes;
  std::vector<int> roots;  // nodes of the default scene without a parent
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Image> images;
  std::vector<Light> lights;
  std::vector<Camera> cameras;
  std::optional<Environment> environment;
  // Skins and animations: posed by SceneState::NodeMesh on the CPU and by
  // scene/gpu_deform on the GPU (docs/ARCHITECTURE.md, "Deformation at run
  // time").
  std::vector<Skin> skins;
  std::vector<Animation> animations;

  // glTF extensions the file uses that gistream renders without (sorted;
  // LoadScene's answer lists them): e.g. KHR_materials_ior, whose index of
  // refraction the BRDF does not read (README, "glTF support").
  std::vector<std::string> ignored_extensions;
  // What the file asks for that import renders otherwise, one line each
  // naming the field (a texture on TEXCOORD_1, ...): LoadScene lists them.
  std::vector<std::string> import_warnings;

  // Filled by import: totals over every node instance of every mesh.
  uint64_t triangle_count = 0;
  uint64_t vertex_count = 0;
  Bounds bounds;  // world space, at load time
};

// Light instances are the nodes that carry a KHR_lights_punctual light, in
// node order; a light instance's id is its position in this list.
std::vector<int> LightInstanceNodes(const Scene& scene);
// Camera instances likewise (nodes that carry a camera).
std::vector<int> CameraInstanceNodes(const Scene& scene);

// TRS -> matrix.
glm::mat4 LocalMatrix(const Node& node);
// World matrices of all nodes (parents before children; the graph is acyclic
// after import).
std::vector<glm::mat4> WorldMatrices(const Scene& scene, const std::vector<Node>& nodes);

}  // namespace gistream
