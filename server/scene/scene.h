// CPU-side scene model: what a glTF file describes after import and
// validation. Everything here is plain data; the GPU copy lives in
// gpu_scene.h and the mutable, versioned state in scene_state.h.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

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

struct Material {
  std::string name;
  glm::vec4 base_color_factor{1.0f};  // linear
  int base_color_texture = -1;        // index into Scene::images
  glm::vec3 emissive_factor{0.0f};    // linear
  float emissive_strength = 1.0f;     // KHR_materials_emissive_strength
  int emissive_texture = -1;
  float metallic_factor = 1.0f;  // kept for later solvers
  float roughness_factor = 1.0f;
  bool double_sided = false;

  // Emitted radiance (nits) of an untextured texel.
  glm::vec3 emission() const { return emissive_factor * emissive_strength; }
  bool emissive() const {
    const glm::vec3 e = emission();
    return e.x > 0.0f || e.y > 0.0f || e.z > 0.0f;
  }
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
};

struct Mesh {
  std::string name;
  std::vector<Primitive> primitives;
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
};

struct Environment {
  Image image;  // equirectangular, linear float RGBA
  float intensity = 1.0f;
  float rotation = 0.0f;  // radians about +Y
  float max_radiance = 0.0f;  // largest channel of `image`, for the magnitude limits
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
