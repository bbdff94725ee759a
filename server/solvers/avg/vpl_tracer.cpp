#include "solvers/avg/vpl_tracer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/constants.hpp>

#include "solvers/avg/quasi_random.h"
#include "solvers/brdf_albedo.h"
#include "solvers/tail_estimate.h"
#include "util/parallel_for.h"

namespace gistream::avg {
namespace {

float Luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

// Orthonormal basis around unit n (Duff et al. 2017).
void Basis(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = glm::vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  b = glm::vec3(c, sign + n.y * n.y * a, -n.y);
}

// Quasi-random dimensions of one path: 0 light, 1-2 point, 3-4 direction,
// then 3 per bounce (2 direction, 1 unused since paths end by index).
constexpr int kDimLight = 0, kDimPoint = 1, kDimDir = 3, kDimBounce = 5, kDimsPerBounce = 3;

// A hash of (path i, dimension dim) in [0, 1) (SplitMix64): the same every
// frame, independent between dimensions.
float HashSample(uint64_t i, int dim) {
  uint64_t z = i * 0x9E3779B97F4A7C15ull + uint64_t(dim) * 0xD1B54A32D192ED03ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return float(z >> 40) * (1.0f / 16777216.0f);
}

// Dimension `dim` of path i: the scrambled Halton point where it has that
// many dimensions (the first 14 bounces), else the hash.
float PathSample(uint64_t i, int dim) {
  if (dim < ScrambledHalton::kMaxDimensions) return ScrambledHalton::Instance().Get(i, dim);
  return HashSample(i, dim);
}

struct LightTable {
  std::vector<double> cdf;  // by luminous power
  double total = 0.0;
};

struct PathStart {
  glm::vec3 origin, dir, normal, flux;  // flux: power / (light pdf), still to divide by N
  bool on_surface = false;
};

PathStart StartPath(const VplLight& l, double pdf, uint64_t i) {
  const ScrambledHalton& h = ScrambledHalton::Instance();
  const float u1 = h.Get(i, kDimPoint), u2 = h.Get(i, kDimPoint + 1);
  const float v1 = h.Get(i, kDimDir), v2 = h.Get(i, kDimDir + 1);
  PathStart s{};
  const float inv_pdf = float(1.0 / pdf);
  switch (l.kind) {
    case VplLightKind::kArea: {
      // Uniform point on the triangle, cosine-distributed direction: each
      // ray then carries power pi L A (the cosine and the pdf cancel).
      const float su = std::sqrt(u1);
      s.origin = (1.0f - su) * l.p0 + su * (1.0f - u2) * l.p1 + su * u2 * l.p2;
      s.normal = l.normal;
      s.dir = SampleCosine(l.normal, v1, v2);
      s.flux = l.power * inv_pdf;
      s.on_surface = true;
      break;
    }
    case VplLightKind::kPoint: {
      // Uniform direction on the sphere: power 4 pi I per ray.
      const float z = 1.0f - 2.0f * v1, r = std::sqrt(std::max(0.0f, 1.0f - z * z));
      const float phi = 2.0f * glm::pi<float>() * v2;
      s.origin = l.position;
      s.dir = glm::vec3(r * std::cos(phi), r * std::sin(phi), z);
      s.normal = s.dir;
      s.flux = l.power * inv_pdf;
      break;
    }
    case VplLightKind::kSpot: {
      // Uniform direction inside the outer cone (solid angle
      // 2 pi (1 - cos_outer)), weighted by the falloff: I f(theta) Omega.
      const float c = 1.0f - v1 * (1.0f - l.cos_outer);
      const float r = std::sqrt(std::max(0.0f, 1.0f - c * c));
      const float phi = 2.0f * glm::pi<float>() * v2;
      glm::vec3 t, b;
      Basis(l.normal, t, b);
      s.origin = l.position;
      s.dir = glm::normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + l.normal * c);
      s.normal = s.dir;
      const float f = std::clamp(c * l.cone_scale + l.cone_offset, 0.0f, 1.0f);
      const float omega = 2.0f * glm::pi<float>() * (1.0f - l.cos_outer);
      s.flux = l.radiance * (f * f * omega) * inv_pdf;
      break;
    }
    case VplLightKind::kDirectional: {
      // Parallel rays through a uniform point of the disc covering the
      // grid: power E pi R^2 per ray.
      glm::vec3 t, b;
      Basis(l.normal, t, b);
      const float r = l.disc_radius * std::sqrt(u1), phi = 2.0f * glm::pi<float>() * u2;
      s.origin = l.position - l.normal * (2.0f * l.disc_radius) + t * (r * std::cos(phi)) +
                 b * (r * std::sin(phi));
      s.dir = l.normal;
      s.normal = l.normal;
      s.flux = l.power * inv_pdf;
      break;
    }
  }
  return s;
}

// A glossy VPL's next direction, drawn from its BRDF (ggx.h Sample, the
// path tracer's lobes) for light arriving from vpl.incident; `flux` (the
// VPL's) is weighted by f cos / (pdf a(v)), a(v) the directional albedo,
// which is 1 on average, so the flux a path carries on is the VPL's as
// for a Lambertian one (Keller's split stays exact on average). None for
// light at or behind the plane.
std::optional<glm::vec3> SampleBrdf(const Vpl& vpl, const glm::vec3& u, glm::vec3& flux) {
  glm::vec3 t, b;
  Basis(vpl.normal, t, b);
  const glm::vec3 wo(glm::dot(vpl.incident, t), glm::dot(vpl.incident, b),
                     glm::dot(vpl.incident, vpl.normal));
  if (!(wo.z > 0.0f)) return std::nullopt;
  const shading::BrdfSample s = shading::Sample(vpl.brdf, wo, glm::vec3(u.z, u.x, u.y));
  if (!(s.pdf > 0.0f)) return std::nullopt;
  const glm::vec3 albedo =
      BrdfDirectionalAlbedo(vpl.brdf.base_color, vpl.brdf.metallic, vpl.brdf.roughness, wo.z,
                            vpl.brdf.specular_f0, vpl.brdf.specular_f90);
  flux *= s.weight / glm::max(albedo, glm::vec3(1e-4f));
  return glm::normalize(t * s.wi.x + b * s.wi.y + vpl.normal * s.wi.z);
}

// Path i has a VPL at bounce b + 1 iff i < counts[b] (see SplitCounts); its
// VPLs' flux is the start flux x the albedos hit, not yet divided by counts.
// Its quasi-random numbers are point i + sample_offset's of the sequence.
VplPath TracePath(const VoxelGrid& grid, const std::vector<VplLight>& lights,
                  const LightTable& table, const std::vector<uint64_t>& counts, uint64_t i,
                  uint64_t sample_offset) {
  const ScrambledHalton& h = ScrambledHalton::Instance();
  const uint64_t q = i + sample_offset;
  VplPath result;
  // Pick a light by power (dimension 0 is van der Corput, so any prefix of
  // paths splits between the lights in proportion to their power).
  const double u = double(h.Get(q, kDimLight)) * table.total;
  const size_t k = std::min(
      size_t(std::upper_bound(table.cdf.begin(), table.cdf.end(), u) - table.cdf.begin()) - 1,
      lights.size() - 1);
  const double pdf = (table.cdf[k + 1] - table.cdf[k]) / table.total;
  if (!(pdf > 0.0)) return result;
  PathStart s = StartPath(lights[k], pdf, q);
  glm::vec3 origin = s.origin, dir = s.dir, normal = s.normal, flux = s.flux;
  bool on_surface = s.on_surface;
  const float nudge = 0.05f * glm::length(grid.voxel_size());
  for (size_t bounce = 0; bounce < counts.size() && i < counts[bounce]; ++bounce) {
    const std::optional<GridHit> hit = grid.March(origin, dir, normal, on_surface);
    result.rays.push_back(
        {origin, dir, hit ? hit->t_exit : std::numeric_limits<float>::infinity()});
    if (!hit) {
      result.escaped = bounce == 0;
      break;
    }
    // The hit surface: the sheet the ray entered (VoxelGrid::March), its
    // normal on the ray's side, and the voxel's albedo; the VPL sits where
    // the ray entered it (see ARCHITECTURE.md: the paper pushes VPLs a
    // random depth into the voxel instead), nudged in front of every sheet
    // of the voxel (at an edge or corner, of both walls).
    const glm::vec3 n = hit->sheet_normal;
    const glm::vec3 albedo = grid.Albedo(hit->voxel);
    const glm::vec3 p = origin + dir * hit->t_sheet;

    Vpl vpl;
    vpl.position = grid.KeepInFront(hit->voxel, p + n * nudge, origin,
                                    on_surface ? normal : glm::vec3(0.0f), nudge);
    vpl.normal = n;
    vpl.flux = flux * albedo;
    vpl.bounce = int(bounce) + 1;
    vpl.incident = -dir;
    vpl.brdf = grid.Brdf(hit->voxel);
    result.vpls.push_back(vpl);

    const int dim = kDimBounce + kDimsPerBounce * int(bounce);
    const glm::vec3 next = vpl.flux;
    if (!(std::max({next.r, next.g, next.b}) > 0.0f)) break;
    flux = next;
    // From the VPL, i.e. off the surface on the side the ray came from:
    // from p itself, rounding put some origins a hair behind the plane,
    // and a grazing ray from there hit its own sheet from behind and
    // left the closed furnace facing out (0.2 % of rays, compounding over
    // a stiff scene's hundreds of bounces: issue 14).
    origin = vpl.position;
    normal = n;
    const glm::vec3 uv(PathSample(q, dim), PathSample(q, dim + 1), PathSample(q, dim + 2));
    if (vpl.brdf.Lambertian()) {
      dir = SampleCosine(n, uv.x, uv.y);
    } else {
      const std::optional<glm::vec3> reflected = SampleBrdf(vpl, uv, flux);
      if (!reflected) break;
      dir = *reflected;
    }
    on_surface = true;
  }
  return result;
}

}  // namespace

glm::vec3 SampleCosine(const glm::vec3& n, float u1, float u2) {
  // Malley's method: a uniform disc point lifted to the hemisphere,
  // cos(theta) = sqrt(1 - u1), phi = 2 pi u2 (the paper's Sec. III-B map).
  const float r = std::sqrt(u1), phi = 2.0f * glm::pi<float>() * u2;
  const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
  glm::vec3 t, b;
  Basis(n, t, b);
  return glm::normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * z);
}

namespace {

bool SameLights(const std::vector<VplLight>& a, const std::vector<VplLight>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const VplLight &x = a[i], &y = b[i];
    if (x.kind != y.kind || x.p0 != y.p0 || x.p1 != y.p1 || x.p2 != y.p2 ||
        x.position != y.position || x.normal != y.normal || x.radiance != y.radiance ||
        x.cone_scale != y.cone_scale || x.cone_offset != y.cone_offset ||
        x.cos_outer != y.cos_outer || x.disc_radius != y.disc_radius || x.power != y.power) {
      return false;
    }
  }
  return true;
}

LightTable MakeTable(const std::vector<VplLight>& lights) {
  LightTable table;
  table.cdf.push_back(0.0);
  for (const VplLight& l : lights) {
    table.cdf.push_back(table.cdf.back() + double(std::max(Luminance(l.power), 0.0f)));
  }
  table.total = table.cdf.back();
  return table;
}

// Traces the paths `indices` into `out` (in parallel when many;
// each path depends on its index only, so not on the split).
void TraceRange(const VoxelGrid& grid, const std::vector<VplLight>& lights, const LightTable& table,
                const VplTraceSettings& settings, const std::vector<uint64_t>& counts,
                const std::vector<uint64_t>& indices, std::vector<VplPath>& out) {
  auto trace = [&](size_t j) {
    out[j] = TracePath(grid, lights, table, counts, indices[j], settings.sample_offset);
  };
  if (indices.size() < 64 || settings.threads == 1) {
    for (size_t j = 0; j < indices.size(); ++j) trace(j);
  } else {
    ParallelFor(indices.size(), 16, trace);
  }
}

// The generations the cap left out (issue 29, item 4: at the default 8
// bounces a rho = 0.9 furnace read 0.65 of its value, 0.99 0.10): when
// the split still had paths at the last generation, the last generations'
// VPLs carry f times the last one's flux more, f = r / (1 - r) from the measured
// flux per generation (the split makes it exactly P rho^b in a closed
// scene of one albedo) by MonotoneTailFactor. They stand for the later
// bounces' light where it is after the cap's bounce (the last bounces'
// distribution, to which a stiff scene's converges).
void AddTail(const VplTraceSettings& settings, const std::vector<uint64_t>& counts,
             VplTraceResult& result) {
  const size_t cap = size_t(std::clamp(settings.bounces, 1, VplTraceSettings::kMaxBounces));
  if (!(settings.tail_bound > 0.0) || counts.size() < cap || counts.back() == 0) return;
  std::vector<double> deltas(counts.size(), 0.0), totals(counts.size(), 0.0);
  for (const Vpl& v : result.vpls) deltas[size_t(v.bounce - 1)] += double(Luminance(v.flux));
  for (size_t b = 0; b < deltas.size(); ++b) totals[b] = (b > 0 ? totals[b - 1] : 0.0) + deltas[b];
  const TailEstimate tail = EstimateTail(deltas, settings.tail_bound);
  if (!tail.applied) return;
  // The tail, f x the last generation's flux, is spread over the last
  // generations (up to kTailGenerations, in proportion to their flux): a
  // bright interior's tail is most of its light, and on the last
  // generation's few VPLs alone it showed as bright blotches.
  constexpr size_t kTailGenerations = 4;
  const size_t first = counts.size() > kTailGenerations ? counts.size() - kTailGenerations : 0;
  double carriers = 0.0;
  for (size_t b = first; b < deltas.size(); ++b) carriers += deltas[b];
  if (!(carriers > 0.0)) return;
  const double f = MonotoneTailFactor(deltas, totals, settings.tail_bound);
  const float scale = float(1.0 + f * deltas.back() / carriers);
  for (Vpl& v : result.vpls) {
    if (size_t(v.bounce) > first) v.flux *= scale;
  }
  result.tail_ratio = tail.ratio;
}

// Packs the paths counts[0] of `counts` asks for, in index order: those in
// `paths` are used as they are, the rest traced. Each VPL of bounce b + 1
// gets its flux / counts[b]: the paths that reach bounce b + 1 carry the
// light's power x the albedos on the way between them (Keller 1997,
// Sec. 3: the survivors of a reflection carry f_r / rho-bar each; with
// integer counts exactly counts[b - 1] / counts[b]), so in a closed scene
// of one albedo rho the VPLs of bounce b hold exactly power x rho^b, for
// any N. At most `vpls` VPLs (shadow-map layers), whatever escapes.
VplTraceResult Pack(const VoxelGrid& grid, const std::vector<VplLight>& lights,
                    const VplTraceSettings& settings, const std::vector<uint64_t>& counts,
                    std::vector<VplPath>& paths, const std::vector<uint8_t>& retraced) {
  VplTraceResult result;
  for (const VplLight& l : lights) result.light_power += l.power;
  const LightTable table = MakeTable(lights);
  if (lights.empty() || !(table.total > 0.0) || counts.empty()) {
    paths.clear();
    return result;
  }
  const uint64_t n = counts[0];
  const size_t cached = std::min<size_t>(paths.size(), size_t(n));
  paths.resize(size_t(n));
  std::vector<uint64_t> indices;
  for (uint64_t i = cached; i < n; ++i) indices.push_back(i);
  std::vector<VplPath> traced(indices.size());
  TraceRange(grid, lights, table, settings, counts, indices, traced);
  for (size_t j = 0; j < indices.size(); ++j) paths[size_t(indices[j])] = std::move(traced[j]);
  for (uint64_t i = 0; i < n; ++i) {
    const VplPath& p = paths[size_t(i)];
    result.path_first.push_back(uint32_t(result.vpls.size()));
    if (i >= cached) {
      ++result.new_paths;
    } else if (i < retraced.size() && retraced[size_t(i)]) {
      ++result.retraced_paths;
      result.retraced_vpls += p.vpls.size();
    } else {
      ++result.kept_paths;
      result.kept_vpls += p.vpls.size();
    }
    result.escaped += p.escaped ? 1 : 0;
    for (Vpl v : p.vpls) {
      v.flux /= float(counts[size_t(v.bounce - 1)]);
      result.vpls.push_back(v);
    }
  }
  result.paths = n;
  AddTail(settings, counts, result);
  return result;
}

}  // namespace

VplTraceResult JoinTraces(const VplTraceResult& a, const VplTraceResult& b) {
  VplTraceResult out;
  const uint64_t paths = a.paths + b.paths;
  if (paths == 0) return a;
  const float wa = float(double(a.paths) / double(paths));
  const float wb = float(double(b.paths) / double(paths));
  out.vpls.reserve(a.vpls.size() + b.vpls.size());
  for (Vpl v : a.vpls) {
    v.flux *= wa;
    out.vpls.push_back(v);
  }
  for (Vpl v : b.vpls) {
    v.flux *= wb;
    out.vpls.push_back(v);
  }
  out.path_first = a.path_first;
  for (uint32_t first : b.path_first) out.path_first.push_back(first + uint32_t(a.vpls.size()));
  out.paths = paths;
  out.escaped = a.escaped + b.escaped;
  out.light_power = a.light_power;
  out.kept_paths = a.paths;
  out.kept_vpls = a.vpls.size();
  out.new_paths = b.paths;
  out.tail_ratio = a.tail_ratio;
  return out;
}

VplTraceResult TraceSecondSet(const VoxelGrid& grid, const std::vector<VplLight>& lights,
                              VplTraceSettings second, const VplTraceResult& first) {
  second.sample_offset = first.paths;
  return JoinTraces(first, TraceVpls(grid, lights, second));
}

bool PathTouches(const VplPath& path, const Bounds& box, const glm::vec3& pad) {
  if (box.empty()) return false;
  const glm::vec3 lo = box.min - pad, hi = box.max + pad;
  for (const VplRay& r : path.rays) {
    // Slab test of the segment [0, t_end].
    float t0 = 0.0f, t1 = r.t_end;
    bool miss = false;
    for (int i = 0; i < 3 && !miss; ++i) {
      if (std::abs(r.dir[i]) < 1e-30f) {
        miss = r.origin[i] < lo[i] || r.origin[i] > hi[i];
        continue;
      }
      float a = (lo[i] - r.origin[i]) / r.dir[i], b = (hi[i] - r.origin[i]) / r.dir[i];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
      miss = !(t0 <= t1);
    }
    if (!miss) return true;
  }
  return false;
}

std::vector<uint64_t> SplitCounts(int vpls, int bounces, float mean_albedo) {
  const int cap = std::clamp(bounces, 1, VplTraceSettings::kMaxBounces);
  const double rho = std::clamp(double(mean_albedo), 0.0, 1.0);
  auto counts_for = [&](uint64_t n) {
    // M_b = round(N rho^b) (Keller 1997, Sec. 3: the particles left after
    // b reflections), while positive, at most `bounces` generations.
    std::vector<uint64_t> m;
    double expected = double(n);
    for (int b = 0; b < cap; ++b, expected *= rho) {
      const uint64_t mb = b == 0 ? n : std::min(m.back(), uint64_t(std::llround(expected)));
      if (mb == 0) break;
      m.push_back(mb);
    }
    return m;
  };
  auto total = [](const std::vector<uint64_t>& m) {
    uint64_t sum = 0;
    for (uint64_t x : m) sum += x;
    return sum;
  };
  // The largest N whose VPLs fit (the total grows with N).
  uint64_t lo = 0, hi = uint64_t(std::max(vpls, 0));
  while (lo < hi) {
    const uint64_t mid = (lo + hi + 1) / 2;
    if (total(counts_for(mid)) <= uint64_t(std::max(vpls, 0))) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  return lo > 0 ? counts_for(lo) : std::vector<uint64_t>{};
}

namespace {

std::vector<uint64_t> CountsFor(const VoxelGrid& grid, const VplTraceSettings& settings) {
  // Without `roulette` every path runs `bounces` generations (rho-bar 1).
  return SplitCounts(settings.vpls, settings.bounces,
                     settings.roulette ? grid.mean_albedo() : 1.0f);
}

}  // namespace

VplTraceResult TraceVpls(const VoxelGrid& grid, const std::vector<VplLight>& lights,
                         const VplTraceSettings& settings, VplPathCache* cache) {
  std::vector<VplPath> paths;
  const std::vector<uint64_t> counts = CountsFor(grid, settings);
  VplTraceResult result = Pack(grid, lights, settings, counts, paths, {});
  if (cache) {
    cache->paths = std::move(paths);
    cache->lights = lights;
    cache->counts = counts;
  }
  return result;
}

VplTraceResult RetraceVpls(const VoxelGrid& grid, const std::vector<VplLight>& lights,
                           const VplTraceSettings& settings, const Bounds& changed,
                           VplPathCache& cache) {
  const std::vector<uint64_t> counts = CountsFor(grid, settings);
  if (!SameLights(lights, cache.lights) || counts != cache.counts) {
    return TraceVpls(grid, lights, settings, &cache);
  }
  // A voxel of padding: the DDA's steps may round into a voxel the segment
  // only grazes.
  const glm::vec3 pad = grid.voxel_size();
  std::vector<uint64_t> invalid;
  for (size_t i = 0; i < cache.paths.size(); ++i) {
    if (PathTouches(cache.paths[i], changed, pad)) invalid.push_back(i);
  }
  std::vector<VplPath> traced(invalid.size());
  TraceRange(grid, lights, MakeTable(lights), settings, counts, invalid, traced);
  std::vector<uint8_t> retraced(cache.paths.size(), 0);
  for (size_t j = 0; j < invalid.size(); ++j) {
    cache.paths[invalid[j]] = std::move(traced[j]);
    retraced[invalid[j]] = 1;
  }
  return Pack(grid, lights, settings, counts, cache.paths, retraced);
}

}  // namespace gistream::avg
