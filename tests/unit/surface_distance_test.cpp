// The proxy levels' distance measure (scene/proxies/surface_distance.h, issue 19):
// the early-stopping query is an upper bound within its threshold, and the
// one-sided bound holds for slivers (sampled in pieces) against a brute-force
// measurement.
#include "scene/proxies/surface_distance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace gistream {
namespace surface_distance_test {

// A wavy strip of n x n quads over [0, 1]^2 (height 0.05 sin).
struct Surface {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
};

Surface WavySurface(int n) {
  Surface s;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const float x = float(i) / float(n), z = float(j) / float(n);
      s.positions.push_back({x, 0.05f * std::sin(9.0f * x + 4.0f * z), z});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
      s.indices.insert(s.indices.end(), {a, c, d, a, d, b});
    }
  }
  return s;
}

float BruteDistance(const Surface& s, const glm::vec3& p) {
  float nearest = INFINITY;
  for (size_t t = 0; t + 2 < s.indices.size(); t += 3) {
    const glm::vec3 q = ClosestPointOnTriangle(
        p, s.positions[s.indices[t]], s.positions[s.indices[t + 1]], s.positions[s.indices[t + 2]]);
    nearest = std::min(nearest, glm::length(q - p));
  }
  return nearest;
}

TEST(SurfaceDistance, EarlyStopIsAnUpperBoundWithinItsThreshold) {
  const Surface s = WavySurface(24);
  const TriangleGrid grid(s.positions, s.indices, 0.02f);
  for (int i = 0; i < 200; ++i) {
    const glm::vec3 p(0.005f * float(i % 200), 0.1f * std::sin(float(i)), 0.37f + 0.002f * i);
    const float exact = BruteDistance(s, p);
    EXPECT_NEAR(grid.Distance(p, 1.0f), exact, 1e-5f);
    for (const float enough : {0.0f, 0.01f, 0.05f, 0.2f}) {
      const float d = grid.Distance(p, 1.0f, enough);
      EXPECT_GE(d, exact - 1e-5f) << i << " " << enough;
      if (exact > enough) {
        EXPECT_NEAR(d, exact, 1e-5f) << i << " " << enough;  // nothing within: exact
      } else {
        EXPECT_LE(d, enough + 1e-6f) << i << " " << enough;
      }
    }
  }
}

// Slivers (a long edge, a tiny height) are split lengthwise before they
// are sampled; the bound still holds against dense brute-force samples and
// stays within the sample spacing of them.
TEST(SurfaceDistance, SliverBoundHoldsAgainstBruteForce) {
  const Surface to = WavySurface(16);
  Surface from;
  from.positions = {{0.02f, 0.08f, 0.1f}, {0.97f, -0.03f, 0.9f}, {0.5f, 0.03f, 0.52f},
                    {0.1f, 0.0f, 0.95f},  {0.9f, 0.02f, 0.05f},  {0.5f, 0.0f, 0.501f}};
  from.indices = {0, 1, 2, 3, 4, 5};
  std::vector<glm::vec3> positions = to.positions;
  std::vector<uint32_t> from_indices;
  for (uint32_t i : from.indices) from_indices.push_back(uint32_t(positions.size()) + i);
  positions.insert(positions.end(), from.positions.begin(), from.positions.end());
  const TriangleGrid joint(positions, to.indices, 0.02f);
  const float spacing = 0.01f;
  const float bound = HausdorffBound(positions, from_indices, joint, spacing, 1.0f);
  float measured = 0.0f;
  constexpr int k = 400;
  for (size_t t = 0; t < from.indices.size(); t += 3) {
    const glm::vec3 a = from.positions[from.indices[t]], b = from.positions[from.indices[t + 1]],
                    c = from.positions[from.indices[t + 2]];
    for (int i = 0; i <= k; ++i) {
      for (int j = 0; i + j <= k; j += 8) {
        const glm::vec3 p = a + (b - a) * (float(i) / k) + (c - a) * (float(j) / k);
        measured = std::max(measured, BruteDistance(to, p));
      }
    }
  }
  EXPECT_GE(bound, measured);
  EXPECT_LE(bound, measured + spacing);
}

// A passed deadline (a load's budget) gives up: `cap`, which every caller
// reads as "no bound" and so keeps no level.
TEST(SurfaceDistance, PassedDeadlineAnswersCap) {
  const Surface s = WavySurface(24);
  const TriangleGrid grid(s.positions, s.indices, 0.02f);
  const float bound = HausdorffBound(s.positions, s.indices, grid, 0.01f, 1.0f);
  EXPECT_LT(bound, 0.01f);
  EXPECT_EQ(
      HausdorffBound(s.positions, s.indices, grid, 0.01f, 1.0f, std::chrono::steady_clock::now()),
      1.0f);
}

}  // namespace surface_distance_test
}  // namespace gistream
