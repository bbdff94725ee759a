#include "solvers/avg/voxel_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "scene/proxies/proxy_levels.h"
#include "scene/proxies/surface_distance.h"
#include "scene/texture_lookup.h"
#include "solvers/brdf_albedo.h"
#include "solvers/avg/tri_box_overlap.h"

namespace gistream::avg {

glm::vec3 MeanTextureColor(const Scene& scene, int image) {
  if (image < 0 || size_t(image) >= scene.images.size()) return glm::vec3(1.0f);
  const Image& img = scene.images[size_t(image)];
  const size_t texels = size_t(img.width) * size_t(img.height);
  if (texels == 0 || (img.is_float ? img.pixelsf.size() : img.pixels8.size()) < 4 * texels) {
    return glm::vec3(1.0f);
  }
  glm::dvec3 sum(0.0);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) sum += glm::dvec3(ImageTexel(img, x, y));
  }
  return glm::clamp(glm::vec3(sum / double(texels)), 0.0f, 1.0f);
}

void VoxelGrid::Place(const SceneState& state, int resolution) {
  n_ = std::clamp(resolution, 4, 1024);
  const Scene& scene = state.scene();
  // Bounds of the current (moved) geometry.
  Bounds bounds;
  for (size_t n = 0; n < scene.nodes.size(); ++n) {
    if (scene.nodes[n].mesh < 0) continue;
    const glm::mat4& m = state.world()[n];
    for (const Primitive& p : state.NodeMesh(n).primitives) {  // posed when it deforms
      for (const glm::vec3& v : p.positions) bounds.Extend(glm::vec3(m * glm::vec4(v, 1.0f)));
    }
  }
  if (bounds.empty()) bounds.Extend(glm::vec3(-1.0f)), bounds.Extend(glm::vec3(1.0f));
  // One voxel of padding on each side, so a surface on the bounds lies
  // inside the grid; flat axes get a minimum thickness.
  const glm::vec3 ext = bounds.extent();
  const float largest = std::max({ext.x, ext.y, ext.z, 1e-20f});
  const glm::vec3 padded = glm::max(ext, glm::vec3(largest / float(n_)));
  size_ = padded / float(n_ - 2);
  origin_ = bounds.center() - 0.5f * padded - size_;
}

VoxelGrid VoxelGrid::Build(const SceneState& state, int resolution, bool full_detail) {
  VoxelGrid grid;
  grid.full_detail_ = full_detail;
  grid.Place(state, resolution);
  grid.voxels_.assign(size_t(grid.n_) * size_t(grid.n_) * size_t(grid.n_), Voxel{});
  grid.Rasterize(state, glm::ivec3(0), glm::ivec3(grid.n_ - 1), Pass::kBoth);
  for (const Voxel& v : grid.voxels_) grid.filled_ += v.count > 0 ? 1 : 0;
  if (grid.area_sum_ > 0.0) grid.mean_albedo_ = float(grid.albedo_area_sum_ / grid.area_sum_);
  return grid;
}

bool VoxelGrid::Revoxelize(const SceneState& state, const Bounds& moved) {
  VoxelGrid placed;
  placed.Place(state, n_);
  if (placed.n_ != n_ || placed.origin_ != origin_ || placed.size_ != size_) return false;
  rewritten_ = Bounds{};
  if (moved.empty()) return true;
  // One voxel of padding: a vertex transformed on its own may round
  // outside the transformed box corners.
  const glm::ivec3 lo = glm::clamp(VoxelOf(moved.min) - 1, glm::ivec3(0), glm::ivec3(n_ - 1));
  const glm::ivec3 hi = glm::clamp(VoxelOf(moved.max) + 1, glm::ivec3(0), glm::ivec3(n_ - 1));
  glm::ivec3 v;
  for (v.z = lo.z; v.z <= hi.z; ++v.z) {
    for (v.y = lo.y; v.y <= hi.y; ++v.y) {
      for (v.x = lo.x; v.x <= hi.x; ++v.x) {
        Voxel& voxel = voxels_[Index(v)];
        filled_ -= voxel.count > 0 ? 1 : 0;
        const uint32_t slot = voxel.sheets;
        voxel = Voxel{};
        voxel.sheets = slot;  // kept, emptied (see sheet_pool_)
        if (slot > 0) sheet_pool_[slot - 1] = VoxelSheets{};
      }
    }
  }
  Rasterize(state, lo, hi, Pass::kVoxels);
  // rho-bar over every triangle again, in Build's order (bitwise Build's):
  // a deformed or scaled node changes the areas, and a stale rho-bar gave
  // the split other path counts than a fresh solve of the same pose.
  area_sum_ = albedo_area_sum_ = 0.0;
  Rasterize(state, glm::ivec3(0), glm::ivec3(n_ - 1), Pass::kSums);
  if (area_sum_ > 0.0) mean_albedo_ = float(albedo_area_sum_ / area_sum_);
  for (v.z = lo.z; v.z <= hi.z; ++v.z) {
    for (v.y = lo.y; v.y <= hi.y; ++v.y) {
      for (v.x = lo.x; v.x <= hi.x; ++v.x) filled_ += voxels_[Index(v)].count > 0 ? 1 : 0;
    }
  }
  rewritten_.Extend(origin_ + glm::vec3(lo) * size_);
  rewritten_.Extend(origin_ + glm::vec3(hi + 1) * size_);
  return true;
}

void VoxelGrid::Rasterize(const SceneState& state, const glm::ivec3& lo, const glm::ivec3& hi,
                          Pass pass) {
  const Scene& scene = state.scene();
  // The voxels' world box, padded by a voxel, to skip primitives far away.
  const glm::vec3 box_min = origin_ + glm::vec3(lo - 1) * size_;
  const glm::vec3 box_max = origin_ + glm::vec3(hi + 2) * size_;
  const bool whole = lo == glm::ivec3(0) && hi == glm::ivec3(n_ - 1);
  // Textures' means, kept across Revoxelize (materials are unchanged).
  std::vector<glm::vec3>& texture_means = texture_means_;
  texture_means.resize(scene.images.size(), glm::vec3(-1.0f));
  // Proxies within half the smallest voxel side (issue 19): moving a
  // surface by less changes which voxels it touches by at most one voxel at
  // its edges, where the conservative test already reaches.
  const float tolerance = full_detail_ ? -1.0f : 0.5f * std::min({size_.x, size_.y, size_.z});
  for (size_t n = 0; n < scene.nodes.size(); ++n) {
    const int mesh = scene.nodes[n].mesh;
    if (mesh < 0) continue;
    const glm::mat4& m = state.world()[n];
    for (const Primitive& p : state.NodeMesh(n).primitives) {  // posed when it deforms
      if (!whole && !p.bounds.empty()) {
        Bounds world;
        for (int corner = 0; corner < 8; ++corner) {
          const glm::vec3 c((corner & 1) ? p.bounds.max.x : p.bounds.min.x,
                            (corner & 2) ? p.bounds.max.y : p.bounds.min.y,
                            (corner & 4) ? p.bounds.max.z : p.bounds.min.z);
          world.Extend(glm::vec3(m * glm::vec4(c, 1.0f)));
        }
        if (glm::any(glm::lessThan(world.max, box_min)) ||
            glm::any(glm::greaterThan(world.min, box_max))) {
          continue;
        }
      }
      TriangleMaterial material;
      glm::vec3& albedo = material.albedo;
      if (p.material >= 0) {
        const Material& mat = state.materials()[size_t(p.material)];
        albedo = glm::vec3(mat.base_color_factor);
        if (mat.base_color_texture >= 0) {
          glm::vec3& mean = texture_means[size_t(mat.base_color_texture)];
          if (mean.x < 0.0f) mean = MeanTextureColor(scene, mat.base_color_texture);
          albedo *= mean;
        }
        albedo = glm::clamp(albedo, 0.0f, 1.0f);  // as the G-buffer stores it
        float metallic = mat.metallic_factor, roughness = mat.roughness_factor;
        if (mat.metallic_roughness_texture >= 0) {  // B: metallic, G: roughness
          glm::vec3& mean = texture_means[size_t(mat.metallic_roughness_texture)];
          if (mean.x < 0.0f) mean = MeanTextureColor(scene, mat.metallic_roughness_texture);
          metallic *= mean.b, roughness *= mean.g;
        }
        material.brdf = {albedo, glm::clamp(metallic, 0.0f, 1.0f),
                         glm::clamp(roughness, 0.0f, 1.0f), mat.specular_f0, mat.specular_f90};
        // A VPL here reflects what the BRDF reflects of light from all
        // directions, averaged over the directions it leaves in (issue 18);
        // Lambertian materials keep their base colour bitwise.
        albedo = BrdfWhiteSkyAlbedo(material.brdf.base_color, material.brdf.metallic,
                                    material.brdf.roughness, material.brdf.specular_f0,
                                    material.brdf.specular_f90);
      }
      const int level = PickProxyLevel<ProxyLevel>(p.proxies, MaxScale(m), tolerance);
      const std::vector<uint32_t>& indices =
          level >= 0 ? p.proxies[size_t(level)].indices : p.indices;
      for (size_t i = 0; i + 2 < indices.size(); i += 3) {
        Add(glm::vec3(m * glm::vec4(p.positions[indices[i]], 1.0f)),
            glm::vec3(m * glm::vec4(p.positions[indices[i + 1]], 1.0f)),
            glm::vec3(m * glm::vec4(p.positions[indices[i + 2]], 1.0f)), material, lo, hi, pass);
      }
    }
  }
}

void VoxelGrid::Add(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                    const TriangleMaterial& material, const glm::ivec3& lo_clip,
                    const glm::ivec3& hi_clip, Pass pass) {
  const glm::vec3& albedo = material.albedo;
  const glm::vec3 cross = glm::cross(b - a, c - a);
  const float len = glm::length(cross);
  if (!(len > 0.0f) || !std::isfinite(len)) return;  // degenerate: no surface, no normal
  const glm::vec3 normal = cross / len;
  if (pass != Pass::kVoxels) {
    area_sum_ += 0.5 * double(len);
    albedo_area_sum_ += 0.5 * double(len) * double(std::max({albedo.r, albedo.g, albedo.b}));
    if (pass == Pass::kSums) return;
  }
  // A hair more than half a voxel, so a triangle on a voxel face marks the
  // voxels on both sides (conservative, never a gap from rounding).
  const glm::vec3 half = 0.5f * size_ * 1.0001f;
  // The triangle's voxel range as Build sees it, widened by that hair (a
  // triangle on a voxel face rounds into either voxel; without the hair
  // here the range held only that one and the test never saw the other:
  // issue 14's escapes at grid 16/32/128 and at scale 1e-3), then only the
  // part inside [lo_clip, hi_clip].
  const glm::vec3 hair = half - 0.5f * size_;
  const glm::ivec3 lo = glm::max(
      glm::clamp(VoxelOf(glm::min(a, glm::min(b, c)) - hair), glm::ivec3(0), glm::ivec3(n_ - 1)),
      lo_clip);
  const glm::ivec3 hi = glm::min(
      glm::clamp(VoxelOf(glm::max(a, glm::max(b, c)) + hair), glm::ivec3(0), glm::ivec3(n_ - 1)),
      hi_clip);
  if (glm::any(glm::greaterThan(lo, hi))) return;
  glm::ivec3 v;
  for (v.z = lo.z; v.z <= hi.z; ++v.z) {
    for (v.y = lo.y; v.y <= hi.y; ++v.y) {
      for (v.x = lo.x; v.x <= hi.x; ++v.x) {
        const glm::vec3 center = Center(v);
        if (!TriangleBoxOverlap(center, half, a, b, c)) continue;
        Voxel& voxel = voxels_[Index(v)];
        voxel.normal_sum += normal;
        voxel.albedo_sum += albedo;
        voxel.base_color_sum += material.brdf.base_color;
        voxel.metallic_roughness_sum += glm::vec2(material.brdf.metallic, material.brdf.roughness);
        voxel.specular_sum += glm::vec4(material.brdf.specular_f0, material.brdf.specular_f90);
        voxel.point_sum += ClosestPointOnTriangle(center, a, b, c);
        ++voxel.count;
        AddToSheets(voxel, normal, a, b, c, center, half);
      }
    }
  }
}

// Sheets: a triangle within ~8 degrees of a sheet's normal (either side)
// joins it where their extents along the normal meet (a curved or folded
// surface: its triangles share edges). Parallel surfaces apart, such as a
// lamp a centimetre under a ceiling in one voxel, stay two sheets: joined
// into one slab, a VPL in the gap lay "on" it (OnOwnSheet), so its next
// ray passed through the lamp into the room (23 % too much light on the
// floor, tests/gl/near_field_room_test.cpp). A full voxel joins the
// nearest sheet whatever it is.
constexpr float kSameSheet = 0.99f;

void VoxelGrid::AddToSheets(Voxel& voxel, const glm::vec3& normal, const glm::vec3& a,
                            const glm::vec3& b, const glm::vec3& c, const glm::vec3& center,
                            const glm::vec3& half) {
  if (voxel.sheets == 0) {
    sheet_pool_.emplace_back();
    voxel.sheets = uint32_t(sheet_pool_.size());
  }
  VoxelSheets& sheets = sheet_pool_[voxel.sheets - 1];
  int best = -1;
  float best_cos = -1.0f;
  for (int i = 0; i < int(sheets.count); ++i) {
    const float cos = std::abs(glm::dot(sheets.sheet[i].normal, normal));
    if (cos > best_cos) best = i, best_cos = cos;
  }
  // The triangle's extent along m, cut to the voxel's: a bound on the part
  // inside the voxel along any m (exact for a triangle of normal m).
  auto extent = [&](const glm::vec3& m) {
    const float box = glm::dot(glm::abs(m), half), mid = glm::dot(m, center);
    const float da = glm::dot(m, a), db = glm::dot(m, b), dc = glm::dot(m, c);
    const float hi = std::min(std::max({da, db, dc}), mid + box);
    return std::pair{std::min(std::max(std::min({da, db, dc}), mid - box), hi), hi};
  };
  bool join = sheets.count == VoxelSheets::kMaxSheets;
  if (best >= 0 && best_cos > kSameSheet) {
    const auto [lo, hi] = extent(sheets.sheet[best].normal);
    const float eps = SheetEpsilon();
    join = join || (lo <= sheets.sheet[best].hi + eps && hi >= sheets.sheet[best].lo - eps);
  }
  if (join) {
    Sheet& sheet = sheets.sheet[best];
    const auto [lo, hi] = extent(sheet.normal);
    sheet.lo = std::min(sheet.lo, lo), sheet.hi = std::max(sheet.hi, hi);
  } else {
    const auto [lo, hi] = extent(normal);
    sheets.sheet[sheets.count++] = Sheet{normal, lo, hi};
  }
}

std::span<const Sheet> VoxelGrid::sheets(const glm::ivec3& v) const {
  if (!Inside(v) || at(v).sheets == 0) return {};
  const VoxelSheets& s = sheet_pool_[at(v).sheets - 1];
  return {s.sheet, s.count};
}

glm::ivec3 VoxelGrid::VoxelOf(const glm::vec3& p) const {
  const glm::vec3 f = glm::floor((p - origin_) / size_);
  // Clamp in float first so far-away points cannot overflow the int cast.
  return glm::ivec3(glm::clamp(f, glm::vec3(-1.0f), glm::vec3(float(n_))));
}

glm::vec3 VoxelGrid::Normal(const glm::ivec3& v) const {
  const Voxel& voxel = at(v);
  const float len = glm::length(voxel.normal_sum);
  // Opposite sheets in one voxel (both faces of a thin wall) cancel: no
  // reliable normal.
  return len > 0.25f * float(voxel.count) ? voxel.normal_sum / len : glm::vec3(0.0f);
}

glm::vec3 VoxelGrid::Albedo(const glm::ivec3& v) const {
  const Voxel& voxel = at(v);
  return voxel.count > 0 ? voxel.albedo_sum / float(voxel.count) : glm::vec3(0.0f);
}

shading::Brdf VoxelGrid::Brdf(const glm::ivec3& v) const {
  const Voxel& voxel = at(v);
  if (voxel.count == 0) return {};
  // n ones sum to n exactly, so a voxel of Lambertian triangles (metallic
  // 0, roughness 1) stays exactly Lambertian.
  const float inv = 1.0f / float(voxel.count);
  const glm::vec2 mr = voxel.metallic_roughness_sum / float(voxel.count);
  const glm::vec4 specular = glm::clamp(voxel.specular_sum * inv, 0.0f, 1.0f);
  return {glm::clamp(voxel.base_color_sum * inv, 0.0f, 1.0f), std::clamp(mr.x, 0.0f, 1.0f),
          std::clamp(mr.y, 0.0f, 1.0f), glm::vec3(specular), specular.a};
}

glm::vec3 VoxelGrid::SurfacePoint(const glm::vec3& fallback, const glm::ivec3& v) const {
  const Voxel& voxel = at(v);
  return voxel.count > 0 ? voxel.point_sum / float(voxel.count) : fallback;
}

bool VoxelGrid::OnOwnSheet(const Sheet& s, const glm::vec3& o, const glm::vec3& own_normal) const {
  const float f = glm::dot(s.normal, o), eps = SheetEpsilon();
  return std::abs(glm::dot(s.normal, own_normal)) > kSameSheet && f >= s.lo - eps &&
         f <= s.hi + eps;
}

std::optional<GridHit> VoxelGrid::SheetAhead(const glm::ivec3& v, const glm::vec3& o,
                                             const glm::vec3& d, const glm::vec3& own_normal,
                                             float t_enter, float t_exit, bool own_voxel) const {
  const float eps = SheetEpsilon();
  std::optional<GridHit> first;
  auto take = [&](float t, const glm::vec3& n) {
    t = std::clamp(t, t_enter, std::max(t_exit, t_enter));
    if (!first || t < first->t_sheet) {
      first = GridHit{v, t_enter, std::max(t_exit, t_enter), t, n};
    }
  };
  for (const Sheet& s : sheets(v)) {
    // The ray's own surface (or one in its plane): left at t = 0, never
    // entered again.
    if (OnOwnSheet(s, o, own_normal)) continue;
    const float f = glm::dot(s.normal, o), fd = glm::dot(s.normal, d);
    if (f >= s.lo && f <= s.hi) {
      // o inside the slab: a thick one (a curved surface's triangles) may
      // be hit anywhere, at once, facing the ray, except in o's own voxels
      // (its own surface's other sheets); o on a thin one lies on an edge.
      if (!own_voxel && s.hi - s.lo > 2.0f * eps) take(t_enter, fd > 0.0f ? -s.normal : s.normal);
      continue;
    }
    // Moving towards the slab (o's side exactly: a ray from a wall a hair
    // off the next one's plane still meets that one): where it enters.
    const bool below = f < s.lo;
    if (below ? !(fd > 0.0f) : !(fd < 0.0f)) continue;
    const float t_in = ((below ? s.lo : s.hi) - f) / fd;
    const float t_out = ((below ? s.hi : s.lo) - f) / fd;
    // Entering it inside the voxel (a wall on the voxel's face meets it at
    // t_enter or t_exit: within eps); the VPL faces the side the ray comes
    // from.
    if (t_out < t_enter - eps || t_in > t_exit + eps) continue;
    take(t_in, below ? -s.normal : s.normal);
  }
  return first;
}

glm::vec3 VoxelGrid::KeepInFront(const glm::ivec3& v, const glm::vec3& p, const glm::vec3& from,
                                 const glm::vec3& from_normal, float gap) const {
  glm::vec3 q = p;
  for (const Sheet& s : sheets(v)) {
    const float f = glm::dot(s.normal, from);
    // In front: the side `from` lies on; of its own surface, the side its
    // normal faces.
    float side = f < s.lo ? -1.0f : f > s.hi ? 1.0f : 0.0f;
    if (OnOwnSheet(s, from, from_normal))
      side = glm::dot(s.normal, from_normal) > 0.0f ? 1.0f : -1.0f;
    const float g = glm::dot(s.normal, q);
    if (side < 0.0f && g > s.lo - gap) q -= s.normal * (g - (s.lo - gap));
    if (side > 0.0f && g < s.hi + gap) q += s.normal * ((s.hi + gap) - g);
  }
  return q;
}

bool VoxelGrid::ClipToBox(const glm::vec3& o, const glm::vec3& d, float* t0, float* t1) const {
  const glm::vec3 box_max = origin_ + extent();
  *t0 = 0.0f;
  *t1 = std::numeric_limits<float>::infinity();
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-30f) {
      if (o[i] < origin_[i] || o[i] > box_max[i]) return false;
      continue;
    }
    float a = (origin_[i] - o[i]) / d[i], b = (box_max[i] - o[i]) / d[i];
    if (a > b) std::swap(a, b);
    *t0 = std::max(*t0, a);
    *t1 = std::min(*t1, b);
  }
  return *t0 <= *t1;
}

VoxelGrid::Dda VoxelGrid::StartDda(const glm::vec3& o, const glm::vec3& d, float t0) const {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  Dda dda;
  dda.v = glm::clamp(VoxelOf(o + d * t0), glm::ivec3(0), glm::ivec3(n_ - 1));
  for (int i = 0; i < 3; ++i) {
    if (d[i] > 0.0f) {
      dda.step[i] = 1;
      dda.t_max[i] = (origin_[i] + float(dda.v[i] + 1) * size_[i] - o[i]) / d[i];
      dda.t_delta[i] = size_[i] / d[i];
    } else if (d[i] < 0.0f) {
      dda.step[i] = -1;
      dda.t_max[i] = (origin_[i] + float(dda.v[i]) * size_[i] - o[i]) / d[i];
      dda.t_delta[i] = -size_[i] / d[i];
    } else {
      dda.step[i] = 0;
      dda.t_max[i] = kInf;
      dda.t_delta[i] = kInf;
    }
  }
  return dda;
}

std::optional<GridHit> VoxelGrid::March(const glm::vec3& o, const glm::vec3& d,
                                        const glm::vec3& start_normal,
                                        bool starts_on_surface) const {
  float t0 = 0.0f, t1 = 0.0f;
  if (!ClipToBox(o, d, &t0, &t1)) return std::nullopt;
  Dda dda = StartDda(o, d, t0);
  glm::ivec3& v = dda.v;
  glm::vec3& t_max = dda.t_max;
  // A filled voxel stops the ray where it enters one of the voxel's sheets
  // inside the voxel (the sheets bound every triangle there, so a ray that
  // meets a triangle enters its sheet first; one that passes the voxel
  // outside them meets none). The sheet the ray starts on holds its origin
  // and is never entered. Self-intersection: a ray leaving a surface starts
  // inside that surface's voxels; in the start voxel, and further filled
  // voxels of the same sheet (normal within 60 degrees, or no normal) until
  // the ray has seen an empty voxel or gone one voxel diagonal, a thick
  // (curved) sheet holding the origin does not stop it either. Issue 14:
  // the march skipped those voxels outright, but an edge or corner voxel
  // also holds the perpendicular wall (mean normal 45 degrees off both),
  // and a ray into that wall passed it and left the closed furnace (0.2-
  // 0.8 % of rays after the first bounce, compounding over a stiff
  // furnace's hundreds of bounces); and a hit on such a voxel's mean plane,
  // its normal flipped to face the ray, put VPLs outside the box.
  const float skip_distance = glm::length(size_);
  bool skipping = starts_on_surface;
  const glm::vec3 own_normal = starts_on_surface ? start_normal : glm::vec3(0.0f);
  const glm::ivec3 start = v;
  float t_enter = t0;
  while (Inside(v)) {
    const float t_exit = std::min({t_max.x, t_max.y, t_max.z});
    const Voxel& voxel = at(v);
    if (voxel.count > 0) {
      bool skip = false;
      if (skipping) {
        if (v == start) {
          skip = true;
        } else if (t_enter < skip_distance) {
          const glm::vec3 n = Normal(v);
          const float cos_start = std::abs(glm::dot(n, start_normal));
          skip = n == glm::vec3(0.0f) || cos_start > 0.5f;
        }
      }
      if (auto hit = SheetAhead(v, o, d, own_normal, t_enter, t_exit, skip)) return hit;
    } else {
      skipping = false;
    }
    // Step to the next voxel along the axis whose boundary comes first.
    const int axis = t_max.x < t_max.y ? (t_max.x < t_max.z ? 0 : 2) : (t_max.y < t_max.z ? 1 : 2);
    t_enter = t_max[axis];
    v[axis] += dda.step[axis];
    t_max[axis] += dda.t_delta[axis];
    if (t_enter > t1) break;
  }
  return std::nullopt;
}

}  // namespace gistream::avg
