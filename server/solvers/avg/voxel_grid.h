// The approximate visibility grid (AVG, paper Sec. III-A): a coarse N^3
// voxelization of the scene fitted to its bounds, each voxel holding the
// summed normal, reflectance and surface point of the triangles that touch it
// plus their count (additive accumulation, normalized on use), and the
// slabs that bound its triangles of each orientation (Sheet): the tracer's
// rays stop where they enter one, so VPLs lie on the walls of an edge or
// corner voxel rather than on its mean plane (issue 14).
//
// Voxelization is conservative (every voxel a triangle touches, exact
// triangle/box test) instead of the paper's rasterization with nudged
// vertices: a conservative voxelization is watertight by construction,
// for thin walls and for triangles parallel to any axis alike.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "scene/state/scene_state.h"
#include "solvers/shading/ggx.h"

namespace gistream::avg {

struct Voxel {
  glm::vec3 normal_sum{0.0f};  // sum of unit triangle normals (authored side)
  glm::vec3 albedo_sum{0.0f};  // sum of linear albedos (white-sky, BrdfWhiteSkyAlbedo)
  // Sums of the BRDF's parameters: a glossy VPL reflects through their mean.
  glm::vec3 base_color_sum{0.0f};
  glm::vec2 metallic_roughness_sum{0.0f};
  glm::vec4 specular_sum{0.0f};  // rgb dielectric F0, a F90 (KHR_materials_ior/_specular)
  glm::vec3 point_sum{0.0f};     // sum of the triangles' points closest to the voxel centre
  uint32_t count = 0;            // triangles touching the voxel
  uint32_t sheets = 0;           // 1 + its slot of VoxelGrid's sheet pool; 0: none yet
};

// The triangles of one orientation inside a voxel, as a slab: every point
// of them inside the voxel has dot(normal, p) in [lo, hi]. Triangles within
// ~8 degrees of a sheet's normal (either side) join it; a voxel keeps up to
// kMaxSheets (a box's corner: three walls), and a triangle beyond that
// widens the most parallel one, so the slabs always hold every triangle.
struct Sheet {
  glm::vec3 normal{0.0f};  // unit, the first triangle's (authored side)
  float lo = 0.0f, hi = 0.0f;
};
struct VoxelSheets {
  static constexpr int kMaxSheets = 3;
  Sheet sheet[kMaxSheets];
  uint32_t count = 0;
};

// What a ray marched through the grid hit.
struct GridHit {
  glm::ivec3 voxel{0};
  float t_enter = 0.0f;  // ray parameter where it entered the voxel
  float t_exit = 0.0f;   // ... and would leave it
  // The sheet hit (see March): where the ray enters it and its unit
  // normal on the side the ray came from.
  float t_sheet = 0.0f;
  glm::vec3 sheet_normal{0.0f};
};

class VoxelGrid {
 public:
  // Voxelizes every mesh instance of `state` (current transforms and
  // materials) into a `resolution`^3 grid over the scene's bounds padded by
  // one voxel. Resolution 1..1024.
  // Each primitive is drawn from its coarsest proxy level within half a
  // voxel (scene/proxies/proxy_levels.h), or in full with `full_detail`.
  static VoxelGrid Build(const SceneState& state, int resolution, bool full_detail = false);

  // Voxelizes only what moved (materials unchanged): `moved` is a world box
  // holding every moved triangle's old and new place (solvers/moved_bounds.h).
  // The voxels it touches, padded by one, are cleared and every triangle
  // that overlaps them is rasterized again into them alone, in Build's
  // order, so each voxel ends bitwise equal to Build's. Returns false and
  // changes nothing when the grid fitted to the current geometry lies
  // elsewhere (the scene's bounds changed): then Build.
  bool Revoxelize(const SceneState& state, const Bounds& moved);
  // The voxels the last Revoxelize rewrote, as a world box (empty after
  // Build); a ray that misses it marches as it did before.
  const Bounds& rewritten() const { return rewritten_; }

  int resolution() const { return n_; }
  const glm::vec3& origin() const { return origin_; }    // world min corner
  const glm::vec3& voxel_size() const { return size_; }  // per axis
  glm::vec3 extent() const { return size_ * float(n_); }
  size_t filled() const { return filled_; }
  // The scene's area-weighted mean reflectance (max over the albedo's
  // channels): instant radiosity's rho-bar (Keller 1997). Revoxelize sums
  // it again over every triangle (a deformed or scaled node changes the
  // areas), so it equals Build's bitwise.
  float mean_albedo() const { return mean_albedo_; }
  uint64_t bytes() const {
    return voxels_.size() * sizeof(Voxel) + sheet_pool_.size() * sizeof(VoxelSheets);
  }

  bool Inside(const glm::ivec3& v) const {
    return v.x >= 0 && v.y >= 0 && v.z >= 0 && v.x < n_ && v.y < n_ && v.z < n_;
  }
  const Voxel& at(const glm::ivec3& v) const { return voxels_[Index(v)]; }
  bool Filled(const glm::ivec3& v) const { return Inside(v) && at(v).count > 0; }
  glm::ivec3 VoxelOf(const glm::vec3& p) const;
  glm::vec3 Center(const glm::ivec3& v) const { return origin_ + (glm::vec3(v) + 0.5f) * size_; }

  // Normalized voxel data (only for filled voxels). The normal is unit, or
  // zero when opposite sheets cancel inside the voxel.
  glm::vec3 Normal(const glm::ivec3& v) const;
  glm::vec3 Albedo(const glm::ivec3& v) const;
  // The mean of its triangles' BRDF parameters; Lambertian exactly when
  // every triangle's is.
  shading::Brdf Brdf(const glm::ivec3& v) const;
  glm::vec3 SurfacePoint(const glm::vec3& fallback, const glm::ivec3& v) const;
  // The voxel's sheets (none for an empty voxel).
  std::span<const Sheet> sheets(const glm::ivec3& v) const;
  // p moved, where needed, to lie at least `gap` in front of each sheet of
  // voxel v, in front meaning on the side `from` lies (of the surface
  // `from` lies on with normal `from_normal`, zero: none, the side that
  // normal faces): a VPL at an edge or corner stays inside it.
  glm::vec3 KeepInFront(const glm::ivec3& v, const glm::vec3& p, const glm::vec3& from,
                        const glm::vec3& from_normal, float gap) const;

  // Marches the ray (o, d unit) through the grid with a 3D DDA (Amanatides
  // & Woo) and returns the first filled voxel where it enters one of the
  // voxel's sheets, not the surface it starts on (see the .cpp). Empty
  // when the ray leaves the grid.
  std::optional<GridHit> March(const glm::vec3& o, const glm::vec3& d,
                               const glm::vec3& start_normal, bool starts_on_surface) const;

 private:
  // The ray's (o, d) span [*t0, *t1] inside the grid box (slab test);
  // false when it misses the box.
  bool ClipToBox(const glm::vec3& o, const glm::vec3& d, float* t0, float* t1) const;
  // A 3D DDA's state (Amanatides & Woo 1987): the voxel, the step per axis,
  // the ray parameter of the next boundary per axis and between two.
  struct Dda {
    glm::ivec3 v;
    glm::ivec3 step;
    glm::vec3 t_max;
    glm::vec3 t_delta;
  };
  // The DDA at the ray's point o + d t0 in the box.
  Dda StartDda(const glm::vec3& o, const glm::vec3& d, float t0) const;
  size_t Index(const glm::ivec3& v) const {
    return (size_t(v.z) * size_t(n_) + size_t(v.y)) * size_t(n_) + size_t(v.x);
  }
  // The first sheet of voxel v the ray (o, d) enters inside the voxel
  // (t in [t_enter, t_exit]), as a hit on it: where it enters and its
  // normal on the side the ray comes from. Not the ray's own surface
  // (OnOwnSheet); a thick sheet holding o is hit at t_enter unless
  // `own_voxel` (o's surface's voxels). None when it meets no sheet there.
  std::optional<GridHit> SheetAhead(const glm::ivec3& v, const glm::vec3& o, const glm::vec3& d,
                                    const glm::vec3& own_normal, float t_enter, float t_exit,
                                    bool own_voxel) const;
  // Whether sheet s is the surface a ray starts on at o with normal
  // `own_normal` (zero: none): parallel to it within ~8 degrees, o on it
  // within SheetEpsilon.
  bool OnOwnSheet(const Sheet& s, const glm::vec3& o, const glm::vec3& own_normal) const;
  // A point within this of a sheet's slab lies on it.
  float SheetEpsilon() const { return 1e-3f * glm::length(size_); }
  // Adds the part of triangle (a, b, c) with unit `normal` inside the voxel
  // (centre, half size) to the voxel's sheets.
  void AddToSheets(Voxel& voxel, const glm::vec3& normal, const glm::vec3& a, const glm::vec3& b,
                   const glm::vec3& c, const glm::vec3& center, const glm::vec3& half);
  // Origin and voxel size of a `resolution`^3 grid over the current geometry.
  void Place(const SceneState& state, int resolution);
  // Rasterizes every triangle of `state` (Build's order) into the voxels
  // [lo, hi]; primitives whose world box misses them are skipped.
  // kVoxels: into the voxels; kSums: only rho-bar's area sums; kBoth.
  enum class Pass { kVoxels, kSums, kBoth };
  void Rasterize(const SceneState& state, const glm::ivec3& lo, const glm::ivec3& hi, Pass pass);
  // A triangle's material: its white-sky albedo and its BRDF.
  struct TriangleMaterial {
    glm::vec3 albedo{1.0f};
    shading::Brdf brdf;
  };
  void Add(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
           const TriangleMaterial& material, const glm::ivec3& lo, const glm::ivec3& hi, Pass pass);

  int n_ = 0;
  glm::vec3 origin_{0.0f};
  glm::vec3 size_{1.0f};
  std::vector<Voxel> voxels_;
  // Per filled voxel its sheets (Voxel::sheets). Revoxelize empties a
  // cleared voxel's slot and keeps it for the voxel, so the pool holds one
  // slot per voxel ever filled.
  std::vector<VoxelSheets> sheet_pool_;
  size_t filled_ = 0;
  float mean_albedo_ = 0.0f;
  double area_sum_ = 0.0, albedo_area_sum_ = 0.0;  // rho-bar's accumulation
  std::vector<glm::vec3> texture_means_;           // per image; -1: not yet
  bool full_detail_ = false;
  Bounds rewritten_;
};

// The mean linear colour of a base-colour texture (the paper uses the
// lowest mip level, i.e. the same mean); 1 when there is none.
glm::vec3 MeanTextureColor(const Scene& scene, int image);

}  // namespace gistream::avg
