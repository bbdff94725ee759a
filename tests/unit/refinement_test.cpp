// Refinement of a still view (render/refinement.h): the jitter sequence is
// a stratified box filter over the pixel starting at its centre, and the
// sample counter restarts on every change of what the samples show.
#include "render/refinement.h"

#include <cmath>
#include <set>

#include <gtest/gtest.h>

namespace gistream {
namespace {

TEST(RefinementJitter, StartsAtThePixelCentreAndStratifiesThePixel) {
  EXPECT_EQ(Refinement::Jitter(0), glm::vec2(0.0f));
  // Halton (2, 3): the first 2^k x-offsets fall one in each of 2^k equal
  // columns, the first 3^k y-offsets one in each of 3^k rows.
  std::set<int> columns, rows;
  for (uint32_t k = 0; k < 256; ++k) {
    const glm::vec2 j = Refinement::Jitter(k);
    ASSERT_GE(j.x, -0.5f);
    ASSERT_LT(j.x, 0.5f);
    ASSERT_GE(j.y, -0.5f);
    ASSERT_LT(j.y, 0.5f);
    // Undo the half-pixel rotation: the Halton points, multiples of 1/16
    // and 1/27 there (rounded to their index).
    const glm::vec2 h = glm::fract(j + 1.0f);
    if (k < 16) columns.insert(int(std::lround(h.x * 16.0f)) % 16);
    if (k < 27) rows.insert(int(std::lround(h.y * 27.0f)) % 27);
  }
  EXPECT_EQ(columns.size(), 16u);
  EXPECT_EQ(rows.size(), 27u);
  // The mean offset of a full stratum is the pixel centre: a box filter.
  glm::dvec2 mean(0.0);
  for (uint32_t k = 0; k < 64; ++k) mean += glm::dvec2(Refinement::Jitter(k));
  EXPECT_NEAR(mean.x / 64.0, 0.0, 1.0 / 64.0);
  EXPECT_NEAR(mean.y / 64.0, 0.0, 1.0 / 27.0);
}

Refinement::Key Key(uint64_t scene_version = 1, uint64_t camera_version = 0) {
  static const int solver = 0;
  return {scene_version, camera_version, &solver, 32, 32, /*solution_final=*/true};
}

// Adds samples until Next says the picture is complete; returns how many.
int FillTo(Refinement& r, const Refinement::Key& key, uint32_t target) {
  int shaded = 0;
  for (int sample = r.Next(key, target); sample >= 0; sample = r.Next(key, target)) {
    EXPECT_EQ(sample, int(r.samples()));
    r.Added();
    if (++shaded > 1000) break;
  }
  return shaded;
}

TEST(Refinement, CountsToTheTargetThenShadesNothing) {
  Refinement r;
  EXPECT_EQ(FillTo(r, Key(), 8), 8);
  EXPECT_EQ(r.samples(), 8u);
  EXPECT_EQ(r.Next(Key(), 8), -1);
  EXPECT_EQ(r.Next(Key(), 8), -1);  // stays complete
  EXPECT_EQ(r.samples(), 8u);
}

TEST(Refinement, EachChangeOfWhatTheSamplesShowRestarts) {
  const int other_solver = 1;
  Refinement::Key moved_camera = Key(1, 1), new_version = Key(2, 0), resized = Key(),
                  solver = Key(), unsolved = Key();
  resized.width = 64;
  solver.solver = &other_solver;
  unsolved.solution_final = false;
  for (const Refinement::Key& change : {moved_camera, new_version, resized, solver, unsolved}) {
    Refinement r;
    ASSERT_EQ(FillTo(r, Key(), 4), 4);
    EXPECT_EQ(r.Next(change, 4), 0);
    r.Added();
    EXPECT_EQ(r.samples(), 1u);
  }
}

TEST(Refinement, AnUnfinishedSolutionOrTargetOneNeverAccumulates) {
  Refinement::Key unsolved = Key();
  unsolved.solution_final = false;
  Refinement a, b;
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(a.Next(unsolved, 16), 0);
    a.Added();
    EXPECT_EQ(b.Next(Key(), 1), 0);
    b.Added();
    EXPECT_EQ(a.samples(), 1u);
    EXPECT_EQ(b.samples(), 1u);
  }
}

}  // namespace
}  // namespace gistream
