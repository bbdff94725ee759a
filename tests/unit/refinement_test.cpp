// Refinement of a still view (render/refinement.h): the jitter sequence is
// a stratified box filter over the pixel starting at its centre, the
// sample counter restarts on every change of what the samples show, and a
// change under the same view keeps the picture as history, or carries the
// anti-aliasing of the last complete one over.
#include "render/refinement.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include <gtest/gtest.h>

namespace gistream {
namespace refinement_test {

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
  return {scene_version,
          camera_version,
          &solver,
          32,
          32,
          /*solution_final=*/true,
          /*shown_changes=*/std::nullopt,
          /*shown_steps=*/0};
}

// Adds samples until Next says the picture is complete; returns how many.
int FillTo(Refinement& r, const Refinement::Key& key, uint32_t target) {
  int shaded = 0;
  for (auto sample = r.Next(key, target, 7); sample; sample = r.Next(key, target, 7)) {
    EXPECT_EQ(sample->index, r.samples());
    r.Added();
    if (++shaded > 1000) break;
  }
  return shaded;
}

TEST(Refinement, CountsToTheTargetThenShadesNothing) {
  Refinement r;
  EXPECT_EQ(FillTo(r, Key(), 8), 8);
  EXPECT_EQ(r.samples(), 8u);
  EXPECT_FALSE(r.Next(Key(), 8, 7));
  EXPECT_FALSE(r.Next(Key(), 8, 7));  // stays complete
  EXPECT_EQ(r.samples(), 8u);
  EXPECT_EQ(r.HistoryWeight(8), 0.0f);
}

// A change of the view (camera, size, solver) keeps nothing: the samples
// restart at the pixel centre, without history.
TEST(Refinement, AChangeOfTheViewRestartsWithoutHistory) {
  const int other_solver = 1;
  Refinement::Key moved_camera = Key(1, 1), resized = Key(), solver = Key();
  resized.width = 64;
  solver.solver = &other_solver;
  for (const Refinement::Key& change : {moved_camera, resized, solver}) {
    Refinement r;
    ASSERT_EQ(FillTo(r, Key(), 4), 4);
    const auto s = r.Next(change, 4, 7);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->index, 0u);
    EXPECT_EQ(s->jitter, 0u);
    EXPECT_FALSE(s->keep_history);
    r.Added();
    EXPECT_EQ(r.samples(), 1u);
    EXPECT_EQ(r.HistoryWeight(4), 0.0f);
  }
}

// A camera move with reprojection (weight 4 here) restarts at the pixel
// centre and asks for the picture shown to be kept and reprojected; its
// weight fades linearly to nothing at the target, and each further move
// asks again. A change of size or solver, a first picture, a change under
// the same camera or a weight of 0 reproject nothing.
TEST(Refinement, ACameraMoveReprojectsThePictureShownBeforeIt) {
  constexpr uint32_t kTarget = 4, kWeight = 4;
  Refinement r;
  const auto first = r.Next(Key(), kTarget, 0, true, kWeight);
  ASSERT_TRUE(first);
  EXPECT_FALSE(first->reproject) << "nothing shown yet";
  r.Added();
  const auto moved = r.Next(Key(1, 1), kTarget, 0, true, kWeight);
  ASSERT_TRUE(moved);
  EXPECT_TRUE(moved->reproject);
  EXPECT_FALSE(moved->keep_history);
  EXPECT_EQ(moved->jitter, 0u);
  r.Added();
  EXPECT_EQ(r.ReprojectWeight(kTarget), float(kWeight));
  const auto again = r.Next(Key(1, 2), kTarget, 0, true, kWeight);
  ASSERT_TRUE(again);
  EXPECT_TRUE(again->reproject) << "every frame of a move reprojects the one before";
  r.Added();
  for (uint32_t n = 2; n <= kTarget; ++n) {
    const auto still = r.Next(Key(1, 2), kTarget, 0, true, kWeight);
    ASSERT_TRUE(still);
    EXPECT_FALSE(still->reproject);
    r.Added();
    EXPECT_EQ(r.ReprojectWeight(kTarget), float(kWeight) * float(kTarget - n) / float(kTarget - 1));
  }
  EXPECT_EQ(r.ReprojectWeight(kTarget), 0.0f) << "a complete picture is its own mean";
  const int other_solver = 1;
  Refinement::Key resized = Key(1, 3), solver = Key(1, 3), scene = Key(2, 2);
  resized.width = 64;
  solver.solver = &other_solver;
  for (const Refinement::Key& change : {resized, solver, scene}) {
    Refinement c;
    ASSERT_EQ(FillTo(c, Key(1, 2), kTarget), int(kTarget));
    const auto s = c.Next(change, kTarget, 0, true, kWeight);
    ASSERT_TRUE(s);
    EXPECT_FALSE(s->reproject);
    c.Added();
    EXPECT_EQ(c.ReprojectWeight(kTarget), 0.0f);
  }
  Refinement off;
  ASSERT_EQ(FillTo(off, Key(), kTarget), int(kTarget));
  const auto s = off.Next(Key(1, 1), kTarget, 0, true, 0);
  ASSERT_TRUE(s);
  EXPECT_FALSE(s->reproject);
}

// A change of what the view shows (a new scene version, a solution being
// updated) under the same view restarts the samples but keeps the picture
// as history, at its weight (7 samples here), fading linearly to nothing
// at the target; the accumulations are counted. Without history (weight
// 0) it restarts like a change of the view.
TEST(Refinement, AChangeOfWhatTheViewShowsKeepsTheHistoryUntilItsSamplesAreIn) {
  Refinement::Key new_version = Key(2, 0), unsolved = Key();
  unsolved.solution_final = false;
  const float k = 8.0f;  // a history of 7 samples' weight
  for (const Refinement::Key& change : {new_version, unsolved}) {
    Refinement r;
    ASSERT_EQ(FillTo(r, Key(), 16), 16);
    const auto s = r.Next(change, 16, 7);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->index, 0u);
    EXPECT_EQ(s->jitter, 1u);
    EXPECT_TRUE(s->keep_history);
    r.Added();
    EXPECT_EQ(r.samples(), 1u);
    EXPECT_EQ(r.HistoryWeight(16), k - 1.0f);
    for (uint32_t n = 2; n <= 16; ++n) {
      const auto more = r.Continue(16);
      ASSERT_TRUE(more);
      EXPECT_FALSE(more->keep_history);
      EXPECT_EQ(more->index, n - 1u);
      EXPECT_EQ(more->jitter, n % 16u);  // (index + 1) mod 16
      r.Added();
      EXPECT_FLOAT_EQ(r.HistoryWeight(16), (k - 1.0f) * float(16 - n) / 15.0f);
    }
    EXPECT_EQ(r.HistoryWeight(16), 0.0f);
  }
  // A target below the history's weight: the history is gone at the
  // target, so a complete picture never holds it.
  Refinement r;
  ASSERT_EQ(FillTo(r, Key(), 4), 4);
  ASSERT_TRUE(r.Next(new_version, 4, 7));
  r.Added();
  EXPECT_EQ(r.HistoryWeight(4), k - 1.0f);
  ASSERT_EQ(FillTo(r, new_version, 4), 3);
  EXPECT_EQ(r.HistoryWeight(4), 0.0f);
}

// Every accumulation shades the same `target` offsets as a fresh view's,
// starting one further along each time: a complete picture does not depend
// on the changes before it.
TEST(Refinement, EveryAccumulationShadesTheFreshViewsOffsets) {
  for (int changes = 1; changes <= 6; ++changes) {
    Refinement r;
    ASSERT_EQ(FillTo(r, Key(), 4), 4);
    std::set<uint32_t> jitters;
    for (int c = 1; c < changes; ++c) {  // changes going on: a sample each
      ASSERT_TRUE(r.Next(Key(uint64_t(c) + 1), 4, 7));
      r.Added();
    }
    const Refinement::Key last = Key(uint64_t(changes) + 1);
    for (auto s = r.Next(last, 4, 7); s; s = r.Next(last, 4, 7)) {
      jitters.insert(s->jitter);
      r.Added();
    }
    EXPECT_EQ(jitters, (std::set<uint32_t>{0, 1, 2, 3})) << changes << " changes";
  }
}

// While the solution is not final every frame is a change: one sample a
// frame, each with the last picture as history (an exponential moving
// average); target 1 never accumulates nor keeps history.
TEST(Refinement, WithoutHistoryAChangeOfWhatTheViewShowsRestartsAtTheCentre) {
  Refinement r;
  ASSERT_EQ(FillTo(r, Key(), 4), 4);
  const auto s = r.Next(Key(2, 0), 4, /*history=*/0);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->index, 0u);
  EXPECT_EQ(s->jitter, 0u);
  EXPECT_FALSE(s->keep_history);
  r.Added();
  EXPECT_EQ(r.HistoryWeight(4), 0.0f);
}

// Carried anti-aliasing (the default without history): a picture that
// completed from the pixel centre is kept once (CaptureCarry); a later
// change of what the view shows restarts at the centre and carries it at
// target - n samples' weight; a change of the view, or carrying turned
// off, or no complete picture yet, carries nothing.
TEST(Refinement, ACompletePictureIsCarriedOverAChangeOfWhatTheViewShows) {
  constexpr uint32_t kTarget = 4;
  // Shades until complete as the engine does: CaptureCarry after each.
  const auto complete = [&](Refinement& r, const Refinement::Key& key, bool carry = true) {
    int captured = 0;
    for (auto s = r.Next(key, kTarget, 0, carry); s; s = r.Next(key, kTarget, 0, carry)) {
      r.Added();
      captured += r.CaptureCarry(kTarget) ? 1 : 0;
    }
    return captured;
  };
  Refinement r;
  const auto first = r.Next(Key(), kTarget, 0);
  ASSERT_TRUE(first);
  EXPECT_FALSE(first->carry) << "nothing to carry yet";
  EXPECT_TRUE(first->centre);
  r.Added();
  EXPECT_FALSE(r.CaptureCarry(kTarget)) << "incomplete";
  EXPECT_EQ(complete(r, Key()), 1);
  EXPECT_FALSE(r.CaptureCarry(kTarget)) << "kept once";
  EXPECT_TRUE(r.carry_valid());
  // A new scene version under the same view: carried, fading out.
  const auto change = r.Next(Key(2), kTarget, 0);
  ASSERT_TRUE(change);
  EXPECT_TRUE(change->carry);
  EXPECT_TRUE(change->centre);
  EXPECT_EQ(change->jitter, 0u);
  EXPECT_FALSE(change->keep_history);
  r.Added();
  EXPECT_EQ(r.CarryWeight(kTarget), 3.0f);
  EXPECT_EQ(r.HistoryWeight(kTarget), 0.0f);
  for (uint32_t n = 2; n <= kTarget; ++n) {
    const auto more = r.Continue(kTarget);
    ASSERT_TRUE(more);
    EXPECT_FALSE(more->carry);
    EXPECT_FALSE(more->centre);
    EXPECT_EQ(more->jitter, n - 1u);  // the fresh view's offsets
    r.Added();
    // target - n, not below n until complete; 0 once it is.
    EXPECT_EQ(r.CarryWeight(kTarget), n == kTarget ? 0.0f : float(std::max(kTarget - n, n)));
    EXPECT_EQ(r.CaptureCarry(kTarget), n == kTarget) << "the new complete picture is kept";
  }
  // Changes going on (a solution still coming in): each carries the pair.
  Refinement::Key unsolved = Key(3);
  unsolved.solution_final = false;
  for (int i = 0; i < 3; ++i) {
    const auto s = r.Next(unsolved, kTarget, 0);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->carry);
    r.Added();
    EXPECT_EQ(r.CarryWeight(kTarget), 3.0f);
    EXPECT_FALSE(r.CaptureCarry(kTarget));
  }
  // Turned off: the same change carries nothing and keeps no centre.
  const auto off = r.Next(Key(4), kTarget, 0, /*carry=*/false);
  ASSERT_TRUE(off);
  EXPECT_FALSE(off->carry);
  EXPECT_FALSE(off->centre);
  r.Added();
  EXPECT_EQ(r.CarryWeight(kTarget), 0.0f);
  // Nor is anything kept while it is off: on again, nothing to carry.
  EXPECT_EQ(complete(r, Key(4), /*carry=*/false), 0);
  EXPECT_FALSE(r.carry_valid());
  const auto on_again = r.Next(Key(5), kTarget, 0);
  ASSERT_TRUE(on_again);
  EXPECT_FALSE(on_again->carry);
  r.Added();
  // A change of the view drops the pair: nothing to carry until a picture
  // of the new view is complete.
  ASSERT_EQ(complete(r, Key(5)), 1);
  const auto moved = r.Next(Key(5, 1), kTarget, 0);
  ASSERT_TRUE(moved);
  EXPECT_FALSE(moved->carry);
  EXPECT_FALSE(r.carry_valid());
  r.Added();
  const auto next = r.Next(Key(6, 1), kTarget, 0);
  ASSERT_TRUE(next);
  EXPECT_FALSE(next->carry) << "the moved view's picture never completed";
  // With history (weight > 0) the history takes the carry's place.
  Refinement h;
  ASSERT_EQ(complete(h, Key()), 1);
  const auto kept = h.Next(Key(2), kTarget, 7);
  ASSERT_TRUE(kept);
  EXPECT_TRUE(kept->keep_history);
  EXPECT_FALSE(kept->carry);
  h.Added();
  EXPECT_EQ(h.CarryWeight(kTarget), 0.0f);
}

TEST(Refinement, AnUnfinishedSolutionBlendsFramesAndTargetOneNeverAccumulates) {
  Refinement::Key unsolved = Key();
  unsolved.solution_final = false;
  Refinement a, b;
  for (uint32_t i = 0; i < 5; ++i) {
    const auto sa = a.Next(unsolved, 16, 7);
    ASSERT_TRUE(sa);
    EXPECT_EQ(sa->index, 0u);
    EXPECT_EQ(sa->jitter, i);  // successive accumulations step on
    EXPECT_EQ(sa->keep_history, i > 0);
    a.Added();
    const auto sb = b.Next(Key(), 1, 7);
    ASSERT_TRUE(sb);
    EXPECT_EQ(sb->index, 0u);
    EXPECT_EQ(sb->jitter, 0u);
    EXPECT_FALSE(sb->keep_history);
    b.Added();
    EXPECT_EQ(a.samples(), 1u);
    EXPECT_EQ(b.samples(), 1u);
    EXPECT_EQ(b.HistoryWeight(1), 0.0f);
  }
}

// A solver that counts what it shows (Solver::Shown) is refined while its
// update is incomplete: its small steps go on with an incomplete picture, a
// step after a complete one and a change of its count restart (at the
// centre, carrying the complete picture's anti-aliasing over), and the end
// of the update restarts too, so the picture at rest is its own.
TEST(Refinement, AnUpdateThatCountsWhatItShowsIsRefinedAcrossItsSteps) {
  constexpr uint32_t kTarget = 4;
  auto step = [](uint64_t changes, uint64_t steps, bool final = false) {
    Refinement::Key k = Key();
    k.solution_final = final;
    k.shown_changes = changes;
    k.shown_steps = steps;
    return k;
  };
  Refinement r;
  ASSERT_TRUE(r.Next(step(1, 0), kTarget, 0));  // restarts: no picture yet
  r.Added();
  // The same count: the next samples of this picture.
  auto s = r.Next(step(1, 0), kTarget, 0);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->index, 1u);
  r.Added();
  // Steps: the picture goes on until it is complete.
  s = r.Next(step(1, 1), kTarget, 0);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->index, 2u);
  r.Added();
  s = r.Next(step(1, 2), kTarget, 0);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->index, 3u);
  r.Added();
  EXPECT_FALSE(r.Next(step(1, 2), kTarget, 0)) << "complete, and nothing changed";
  EXPECT_TRUE(r.CaptureCarry(kTarget));
  // A step after a complete picture: shaded again, carrying it over.
  s = r.Next(step(1, 3), kTarget, 0);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->index, 0u);
  EXPECT_EQ(s->jitter, 0u);
  EXPECT_TRUE(s->carry);
  r.Added();
  // A change of the count restarts an incomplete picture.
  s = r.Next(step(2, 3), kTarget, 0);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->index, 0u);
  r.Added();
  ASSERT_EQ(r.Next(step(2, 4), kTarget, 0)->index, 1u);
  r.Added();
  // The update's end: restarted, whatever the count.
  s = r.Next(step(2, 4, /*final=*/true), kTarget, 0);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->index, 0u);
  // A solver that does not count (nullopt) restarts every frame meanwhile.
  Refinement u;
  Refinement::Key unsolved = Key();
  unsolved.solution_final = false;
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(u.Next(unsolved, kTarget, 0)->index, 0u);
    u.Added();
  }
}

// The history is not used where something moved: the box a camera sees of
// the moved world box, two pixels wider; all of the view when the box
// reaches behind the eye.
TEST(Refinement, MovedPixelsIsTheScreenBoxOfWhatMoved) {
  ViewCamera camera;  // at the origin, looking down -Z
  camera.width = camera.height = 64;
  camera.yfov = 2.0f * std::atan(1.0f);  // tan(yfov / 2) = 1: x, y = -z at the edges
  camera.jitter = glm::vec2(0.3f);       // ignored
  Bounds b;
  b.Extend(glm::vec3(0.0f, 0.0f, -2.0f));
  b.Extend(glm::vec3(1.0f, 1.0f, -2.0f));  // ndc [0, 0.5]^2: pixels [32, 48)
  const Refinement::PixelBox box = MovedPixels(camera, b);
  EXPECT_EQ(box.min, glm::ivec2(30));
  EXPECT_EQ(box.max, glm::ivec2(50));
  EXPECT_EQ(MovedPixels(camera, Bounds{}).max, glm::ivec2(0));  // nothing moved
  Bounds behind = b;
  behind.Extend(glm::vec3(0.0f, 0.0f, 1.0f));
  const Refinement::PixelBox all = MovedPixels(camera, behind);
  EXPECT_EQ(all.min, glm::ivec2(0));
  EXPECT_EQ(all.max, glm::ivec2(64));
  Bounds aside;  // off screen to the right: clamped to the view's edge
  aside.Extend(glm::vec3(5.0f, 0.0f, -2.0f));
  aside.Extend(glm::vec3(6.0f, 0.5f, -2.0f));
  const Refinement::PixelBox edge = MovedPixels(camera, aside);
  EXPECT_EQ(edge.min.x, 64);
  EXPECT_EQ(edge.max.x, 64);
}

}  // namespace refinement_test
}  // namespace gistream
