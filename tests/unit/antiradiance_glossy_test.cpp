// antiradiance's glossy local pass (solvers/antiradiance/glossy_transfer.h)
// without GL: a glossy white furnace reflects the BRDF's albedo and no
// more, a glossy floor's exitant bins peak at the mirror direction of the
// light, a mirror-like metal stays finite, and Lambertian leaves are
// untouched (bitwise).
#include <algorithm>
#include <cmath>

#include <absl/strings/str_cat.h>
#include <gtest/gtest.h>

#include "support/measurement.h"

#include "solvers/hierarchy/directional_bins.h"
#include "solvers/antiradiance/glossy_transfer.h"
#include "solvers/antiradiance/links.h"
#include "solvers/antiradiance/patches.h"
#include "solvers/antiradiance/transport.h"
#include "solvers/brdf_albedo.h"

namespace gistream::antiradiance {
namespace antiradiance_glossy_test {

constexpr float kPi = 3.14159265358979f;
const glm::vec3 kX(1, 0, 0), kY(0, 1, 0), kZ(0, 0, 1);

// A w x h rectangle centred at c spanned by unit u, v; it faces u x v.
std::vector<SourceTriangle> Quad(glm::vec3 c, glm::vec3 u, glm::vec3 v, float w, float h) {
  const glm::vec3 a = c - 0.5f * w * u - 0.5f * h * v, b = a + w * u, d = a + h * v, e = b + h * v;
  const glm::vec3 n = glm::normalize(glm::cross(u, v));
  return {{{a, b, e}, n, glm::vec3(1.0f)}, {{a, e, d}, n, glm::vec3(1.0f)}};
}

// A closed unit box, walls facing in.
std::vector<std::vector<SourceTriangle>> Box() {
  return {Quad({0, -0.5f, 0}, kX, -kZ, 1, 1), Quad({0, 0.5f, 0}, kX, kZ, 1, 1),
          Quad({-0.5f, 0, 0}, kY, kZ, 1, 1),  Quad({0.5f, 0, 0}, kY, -kZ, 1, 1),
          Quad({0, 0, -0.5f}, kX, kY, 1, 1),  Quad({0, 0, 0.5f}, kX, -kY, 1, 1)};
}

double Luminance(const glm::vec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

struct GlossyScene {
  GlossyScene(const std::vector<std::vector<SourceTriangle>>& groups, float max_edge, int m,
              const std::vector<shading::Brdf>& per_root) {
    patches = BuildPatches(groups, max_edge);
    bins = *hierarchy::DirectionalBins::Create(m);
    brdf.assign(size_t(patches.size()), shading::Brdf());
    for (size_t r = 0; r < patches.roots.size(); ++r) {
      const int end = r + 1 < patches.roots.size() ? patches.roots[r + 1] : patches.size();
      for (int i = patches.roots[r]; i < end; ++i) brdf[size_t(i)] = per_root[r];
    }
    transfer = *GlossyTransfer::Build(patches, bins, brdf, uint64_t(1) << 30);
    transport = std::make_unique<Transport>(patches, bins, CreateLinks(patches, bins, nullptr));
    transport->SetGlossy(&transfer, {});
  }
  std::vector<glm::vec3> Emission(size_t root, float l) const {
    std::vector<glm::vec3> e(size_t(patches.size()), glm::vec3(0.0f));
    const int end = root + 1 < patches.roots.size() ? patches.roots[root + 1] : patches.size();
    for (int i = patches.roots[root]; i < end; ++i) {
      if (patches.is_leaf(i)) e[size_t(i)] = glm::vec3(l);
    }
    return e;
  }
  Patches patches;
  hierarchy::DirectionalBins bins;
  std::vector<shading::Brdf> brdf;
  GlossyTransfer transfer;
  std::unique_ptr<Transport> transport;
};

shading::Brdf Material(float metallic, float roughness) {
  shading::Brdf b;
  b.base_color = glm::vec3(1.0f);
  b.metallic = metallic;
  b.roughness = roughness;
  return b;
}

TEST(AntiradianceGlossy, TransferReflectsTheDirectionalAlbedo) {
  // The matrix alone: uniform incident radiance 1 in every bin reflects
  // albedo(omega_o) pi / S(n) toward every bin (the rows), and each
  // incident bin sends out albedo(omega_j) of its flux (the columns), for
  // a rough and a shiny metal, a glossy dielectric and a coloured metal.
  const hierarchy::DirectionalBins bins = *hierarchy::DirectionalBins::Create(128);
  Patches p = BuildPatches({Quad({0, 0, 0}, kX, -kZ, 1, 1)}, 2.0f);
  shading::Brdf gold = Material(1, 0.3f);
  gold.base_color = {1.0f, 0.78f, 0.34f};
  for (const shading::Brdf& b : {Material(1, 0.5f), Material(1, 0.2f), Material(0, 0.3f), gold}) {
    const std::string name = absl::StrCat("m", b.metallic, "_r", b.roughness, "_b", b.base_color.b);
    const GlossyTransfer t =
        *GlossyTransfer::Build(p, bins, std::vector<shading::Brdf>(size_t(p.size()), b), 1 << 30);
    const int leaf = p.Leaves()[0];
    const glm::vec3& n = p.normal[size_t(leaf)];
    double s = 0.0;
    for (int j = 0; j < bins.count(); ++j) s += std::max(0.0f, glm::dot(n, bins.direction(j)));
    const float pi_over_s = kPi / float(s * bins.omega_bin());
    const std::vector<glm::vec3> ones(size_t(bins.count()), glm::vec3(1.0f));
    std::vector<glm::vec3> out(size_t(bins.count()));
    t.Reflect(t.slot(leaf), ones.data(), out.data());
    double row_error = 0.0, column_error = 0.0;
    glm::dvec3 exitance(0.0);
    for (int o = 0; o < bins.count(); ++o) {
      const float c = glm::dot(n, bins.direction(o));
      if (c <= 0.0f) continue;
      const glm::vec3 albedo = BrdfDirectionalAlbedo(b.base_color, b.metallic, b.roughness, c);
      const glm::vec3 e = glm::abs(out[size_t(o)] / (albedo * pi_over_s) - 1.0f);
      row_error = std::max(row_error, double(std::max({e.r, e.g, e.b})));
      exitance += glm::dvec3(out[size_t(o)]) * double(c * bins.omega_bin());
      // Column o: one incident bin's light.
      std::vector<glm::vec3> one(size_t(bins.count()), glm::vec3(0.0f));
      one[size_t(o)] = glm::vec3(1.0f);
      t.Reflect(t.slot(leaf), one.data(), out.data());
      glm::dvec3 sent(0.0);
      for (int q = 0; q < bins.count(); ++q) {
        sent += glm::dvec3(out[size_t(q)]) *
                double(std::max(0.0f, glm::dot(n, bins.direction(q))) * bins.omega_bin());
      }
      const glm::dvec3 expected = glm::dvec3(albedo) * double(c * bins.omega_bin() * pi_over_s);
      const glm::dvec3 ce = glm::abs(sent / expected - 1.0);
      column_error = std::max(column_error, std::max({ce.r, ce.g, ce.b}));
      t.Reflect(t.slot(leaf), ones.data(), out.data());
    }
    const glm::dvec3 ws(BrdfWhiteSkyAlbedo(b.base_color, b.metallic, b.roughness));
    const glm::dvec3 ratio = exitance / (ws * double(kPi));
    testing::RecordMeasurement(absl::StrCat("row_error_", name), row_error);
    testing::RecordMeasurement(absl::StrCat("column_error_", name), column_error);
    testing::RecordMeasurement(absl::StrCat("exitance_over_white_sky_", name), ratio.g);
    EXPECT_LE(row_error, 1e-3) << name;
    EXPECT_LE(column_error, 1e-3) << name;
    // The bins' discrete cosine-weighted mean of the albedo is the white-sky
    // albedo (brdf_albedo.h) within 1 %.
    EXPECT_NEAR(ratio.r, 1.0, 0.01) << name;
    EXPECT_NEAR(ratio.g, 1.0, 0.01) << name;
    EXPECT_NEAR(ratio.b, 1.0, 0.01) << name;
  }
}

TEST(AntiradianceGlossy, WhiteFurnaceReflectsTheBrdfAlbedo) {
  // Every wall emits L_e = 1 and is a white GGX material. After one global
  // pass the incident radiance is ~1 (the box gathers 99.9 % per pass;
  // per bin it varies with the links' spreading), so the reflected
  // exitance is pi times the white-sky albedo.
  for (const shading::Brdf& b : {Material(1, 0.5f), Material(0, 0.3f), Material(1, 0.2f)}) {
    const std::string name = absl::StrCat("m", b.metallic, "_r", b.roughness);
    GlossyScene s(Box(), 0.25f, 128, std::vector<shading::Brdf>(6, b));
    ASSERT_EQ(s.transfer.matrices(), 6);  // one per wall normal
    std::vector<glm::vec3> emit(size_t(s.patches.size()), glm::vec3(1.0f));
    TransportSettings settings;
    settings.iterations = 1;
    const TransportResult r = s.transport->Solve({}, emit, settings);
    ASSERT_FALSE(r.non_finite);
    const float white_sky = BrdfWhiteSkyAlbedo(b.base_color, b.metallic, b.roughness).g;
    double exitance = 0.0, area = 0.0;
    for (int i : s.patches.Leaves()) {
      const int g = s.transfer.slot(i);
      ASSERT_GE(g, 0);
      const glm::vec3* l_r = s.transport->glossy_indirect(g);
      const glm::vec3& n = s.patches.normal[size_t(i)];
      double e = 0.0, cs = 0.0;
      for (int o = 0; o < s.bins.count(); ++o) {
        const float c = glm::dot(n, s.bins.direction(o));
        if (c <= 0.0f) continue;
        e += double(c) * l_r[o].g;
        cs += c;
      }
      exitance += double(s.patches.area[size_t(i)]) * e / cs;  // pi E / S = e / cs
      area += s.patches.area[size_t(i)];
    }
    const double ratio = exitance / area / white_sky;
    testing::RecordMeasurement(absl::StrCat("exitance_over_white_sky_", name), ratio);
    // Energy: the white-sky albedo of the ~1 incident radiance (within the
    // bins' 0.3 % discrete cosine-weighted mean of the albedo), not above.
    EXPECT_LE(ratio, 1.0 + 3e-3) << name;
    EXPECT_GE(ratio, 0.98) << name;
  }
}

TEST(AntiradianceGlossy, IteratedFurnaceStaysBelowTheAlbedoBound) {
  // Emission 1 iterated to convergence: L = L_e / (1 - albedo) at most
  // with the largest directional albedo, never more.
  const shading::Brdf b = Material(1, 0.4f);
  GlossyScene s(Box(), 0.25f, 128, std::vector<shading::Brdf>(6, b));
  std::vector<glm::vec3> emit(size_t(s.patches.size()), glm::vec3(1.0f));
  TransportSettings settings;
  settings.iterations = 400;
  settings.tolerance = 1e-6;
  const TransportResult r = s.transport->Solve({}, emit, settings);
  EXPECT_FALSE(r.non_finite);
  EXPECT_FALSE(r.cap_reached);
  float max_albedo = 0.0f;
  for (int k = 1; k <= 100; ++k) {
    max_albedo = std::max(
        max_albedo, BrdfDirectionalAlbedo(b.base_color, b.metallic, b.roughness, k / 100.0f).g);
  }
  const double bound = 1.0 / (1.0 - max_albedo);
  double exitance = 0.0, area = 0.0, highest = 0.0;
  for (int i : s.patches.Leaves()) {
    const glm::vec3* l_r = s.transport->glossy_indirect(s.transfer.slot(i));
    const glm::vec3& n = s.patches.normal[size_t(i)];
    double e = 0.0, cs = 0.0;
    for (int o = 0; o < s.bins.count(); ++o) {
      ASSERT_TRUE(std::isfinite(l_r[o].g));
      const float c = glm::dot(n, s.bins.direction(o));
      if (c <= 0.0f) continue;
      e += double(c) * (1.0 + l_r[o].g);  // + L_e
      cs += c;
      highest = std::max(highest, 1.0 + double(l_r[o].g));
    }
    exitance += double(s.patches.area[size_t(i)]) * e / cs;
    area += s.patches.area[size_t(i)];
  }
  // The white-sky albedo's fixed point L_e / (1 - rho_ws): what a uniform
  // incident field would settle at.
  const double ws = 1.0 / (1.0 - BrdfWhiteSkyAlbedo(b.base_color, b.metallic, b.roughness).g);
  testing::RecordMeasurement("exitance_over_bound", exitance / area / bound);
  testing::RecordMeasurement("exitance_over_white_sky_fixed_point", exitance / area / ws);
  testing::RecordMeasurement("highest_bin_over_bound", highest / bound);
  // The cosine-weighted mean stays below L_e / (1 - albedo) with the
  // largest directional albedo (measured 0.57 of it) and within 5 % of the
  // white-sky fixed point (measured +0.9 %); single bins follow the links'
  // uneven spreading (measured 1.05 of the bound, not asserted).
  EXPECT_LE(exitance / area, bound);
  EXPECT_NEAR(exitance / area / ws, 1.0, 0.05);
}

TEST(AntiradianceGlossy, HighlightLeavesAtTheMirrorDirection) {
  // A small emitter 45 degrees above a glossy floor: the floor's reflected
  // radiance peaks in the bin nearest the mirror direction of the light,
  // and is far brighter there than back toward the light.
  const glm::vec3 light_dir = glm::normalize(glm::vec3(-1, 1, 0));
  const glm::vec3 c = 2.0f * light_dir;
  std::vector<std::vector<SourceTriangle>> g = {
      Quad({0, 0, 0}, kX, -kZ, 1, 1),
      Quad(c, glm::normalize(glm::cross(-light_dir, kZ)), -kZ, 0.3f, 0.3f)};
  ASSERT_LT(glm::dot(g[1][0].normal, light_dir), -0.99f);  // the emitter faces the floor
  GlossyScene s(g, 0.5f, 256, {Material(1, 0.45f), shading::Brdf()});
  TransportSettings settings;
  settings.iterations = 1;
  s.transport->Solve({}, s.Emission(1, 1.0f), settings);
  int leaf = -1;  // the floor's leaf nearest its centre
  for (int i : s.patches.Leaves()) {
    if (s.transfer.slot(i) >= 0 && (leaf < 0 || glm::length(s.patches.position[size_t(i)]) <
                                                    glm::length(s.patches.position[size_t(leaf)])))
      leaf = i;
  }
  ASSERT_GE(leaf, 0);
  const glm::vec3 to_light = glm::normalize(c - s.patches.position[size_t(leaf)]);
  const glm::vec3 mirror = glm::reflect(-to_light, kY);
  const glm::vec3* l_r = s.transport->glossy_indirect(s.transfer.slot(leaf));
  int peak = 0;
  for (int o = 0; o < s.bins.count(); ++o) {
    if (Luminance(l_r[o]) > Luminance(l_r[peak])) peak = o;
  }
  const float off = std::acos(std::clamp(glm::dot(s.bins.direction(peak), mirror), -1.0f, 1.0f));
  const double toward_mirror = Luminance(l_r[s.bins.Find(mirror)]);
  const double toward_light = Luminance(l_r[s.bins.Find(to_light)]);
  testing::RecordMeasurement("peak_off_mirror_over_spacing", off / s.bins.spacing());
  testing::RecordMeasurement("mirror_over_back", toward_mirror / toward_light);
  EXPECT_GT(Luminance(l_r[peak]), 0.0);
  EXPECT_LE(off, 1.0f * s.bins.spacing());  // within a bin of the mirror direction
  EXPECT_GT(toward_mirror, 10.0 * toward_light);
}

TEST(AntiradianceGlossy, MirrorMetalStaysFinite) {
  // Roughness 0.03 (the clamp) in a closed box with a blocker: every
  // intensity finite, nothing negative in the reflected bins beyond the
  // antiradiance's own over-cancellation.
  std::vector<std::vector<SourceTriangle>> g = Box();
  g.push_back(Quad({0, 0, 0}, kX, kZ, 0.4f, 0.4f));
  GlossyScene s(g, 0.25f, 128, std::vector<shading::Brdf>(7, Material(1, 0.03f)));
  std::vector<glm::vec3> emit = s.Emission(0, 1.0f);
  TransportSettings settings;
  settings.iterations = 32;
  const TransportResult r = s.transport->Solve({}, emit, settings);
  EXPECT_FALSE(r.non_finite);
  for (int i : s.patches.Leaves()) {
    const glm::vec3* l_r = s.transport->glossy_indirect(s.transfer.slot(i));
    for (int o = 0; o < s.bins.count(); ++o) {
      ASSERT_TRUE(std::isfinite(l_r[o].r) && std::isfinite(l_r[o].g) && std::isfinite(l_r[o].b));
      const glm::vec3& v = s.transport->I_ex(i, o);
      ASSERT_TRUE(std::isfinite(v.r) && std::isfinite(v.g) && std::isfinite(v.b));
    }
  }
}

TEST(AntiradianceGlossy, LambertianLeavesAreUnchanged) {
  // Lambertian leaves get no slot: a transport with the (empty) glossy
  // transfer is bitwise the diffuse one.
  GlossyScene s(Box(), 0.25f, 128, std::vector<shading::Brdf>(6, shading::Brdf()));
  EXPECT_EQ(s.transfer.count(), 0);
  for (int i = 0; i < s.patches.size(); ++i) s.patches.albedo[size_t(i)] = glm::vec3(0.7f);
  Transport plain(s.patches, s.bins, CreateLinks(s.patches, s.bins, nullptr));
  Transport glossy(s.patches, s.bins, CreateLinks(s.patches, s.bins, nullptr));
  glossy.SetGlossy(&s.transfer, {});
  const std::vector<glm::vec3> emit = s.Emission(2, 1.0f);
  TransportSettings settings;
  settings.iterations = 6;
  plain.Solve({}, emit, settings);
  glossy.Solve({}, emit, settings);
  for (int i = 0; i < s.patches.size(); ++i) {
    for (int j = 0; j < s.bins.count(); ++j) {
      ASSERT_EQ(plain.I_ex(i, j), glossy.I_ex(i, j)) << i << " " << j;
    }
    ASSERT_EQ(plain.indirect_irradiance()[size_t(i)], glossy.indirect_irradiance()[size_t(i)]);
  }
}

}  // namespace antiradiance_glossy_test
}  // namespace gistream::antiradiance

namespace gistream::antiradiance {
namespace antiradiance_glossy_test {

// The link limit (LinkSet::set_max_links): linking a closed box of six
// roots (36 root pairs) stops once the pairs linked hold more than the
// limit; the pairs not started stay empty, so what was built is at most
// the limit and the last pairs that ran (here: well under the full set).
TEST(AntiradianceLinks, LinkingStopsOnceTheLinksPassTheLimit) {
  const Patches patches = BuildPatches(Box(), 0.25f);
  const hierarchy::DirectionalBins bins = *hierarchy::DirectionalBins::Create(32);
  LinkSet all;
  all.Build(patches, bins);
  const uint64_t full = all.size();
  ASSERT_GT(full, 1000u);
  EXPECT_FALSE(all.exceeded());

  LinkSet capped;
  capped.set_max_links(full / 10);
  capped.Build(patches, bins);
  EXPECT_TRUE(capped.exceeded());
  EXPECT_LT(capped.size(), full / 2);
  testing::RecordMeasurement("links_full", double(full));
  testing::RecordMeasurement("links_when_stopped", double(capped.size()));

  LinkSet roomy;
  roomy.set_max_links(full);
  roomy.Build(patches, bins);
  EXPECT_FALSE(roomy.exceeded());
  EXPECT_EQ(roomy.size(), full);
}

}  // namespace antiradiance_glossy_test
}  // namespace gistream::antiradiance
