// `antiradiance` (Dachsbacher et al. 2007) end to end on llvmpipe: a stiff
// white furnace stays finite and bounded, error against the path-traced
// reference on the indirect-only room, links and bytes in the stats, which
// stages each kind of change runs, and parameters that are refused.
#include <cmath>

#include <absl/strings/str_cat.h>
#include <gtest/gtest.h>

#include "support/measurement.h"
#include "support/render_helpers.h"

namespace gistream {
namespace antiradiance_test {

using testing::BundledCopy;
using testing::FloatImage;
using testing::FrameStage;
using testing::FrameStat;
using testing::GreyAlbedo;
using testing::ImageMean;
using testing::RelMse;
using testing::RenderRequestExr;
using testing::SolverRequest;

TEST(Antiradiance, StiffFurnaceIsFiniteAndNotBrighterThanTheFixedPoint) {
  // Emission 1: L = 1 / (1 - rho) at the fixed point; a few iterations stay
  // below it (3 %: the direct term's area-light estimate), never NaN.
  const BundledCopy scene("furnace.gltf");
  for (float rho : {0.5f, 0.9f, 0.99f}) {
    EncodedFrame frame;
    const FloatImage image =
        RenderRequestExr(SolverRequest(scene.id(), "antiradiance", {{"iterations", "8"}}, 16,
                                       {{1, GreyAlbedo(rho)}}),
                         &frame);
    ASSERT_EQ(image.width, 16);
    EXPECT_EQ(image.non_finite(), 0u) << rho;
    const double mean = ImageMean(image).g;
    EXPECT_LE(mean, 1.03 / (1.0 - rho)) << rho;
    EXPECT_GT(mean, 1.0) << rho;
    EXPECT_EQ(FrameStat(frame, "non_finite"), 0.0);
    if (rho == 0.5f) {
      EXPECT_NEAR(mean, 2.0, 0.2);  // 8 bounces of 0.5: within 1 %, plus discretization
    }
  }
}

TEST(Antiradiance, ExtremeScalesAndIntensitiesStayFiniteAndConserveEnergy) {
  // mm to km and 1e-3 to 1e6 nits: Eq. 17's 1 / r^2 and the intensities
  // scale, the answer L = E / (1 - rho) = 2 E does not. 10 %: 8 bounces of
  // 0.5 (0.4 %), the direct term's area samples and the elements'
  // collocation loss (see the furnace test above).
  testing::ExpectFurnaceScaleInvariant(
      "antiradiance", {{"iterations", "8"}}, 0.2,
      [](const EncodedFrame& frame) { EXPECT_EQ(FrameStat(frame, "fallback"), 0.0); });
}

TEST(Antiradiance, StatsReportLinksAndBytes) {
  const BundledCopy scene("cornell_box.gltf");
  EncodedFrame frame;
  const FloatImage image =
      RenderRequestExr(SolverRequest(scene.id(), "antiradiance", {}, 32), &frame);
  EXPECT_EQ(image.non_finite(), 0u);
  EXPECT_GT(FrameStat(frame, "links"), 1000.0);
  EXPECT_GT(FrameStat(frame, "link_bytes"), 0.0);
  EXPECT_EQ(FrameStat(frame, "table_bytes"), FrameStat(frame, "elements") * 128 * 2 * 12);
  EXPECT_EQ(FrameStat(frame, "bins"), 128.0);
  EXPECT_EQ(FrameStat(frame, "scheme_used"), 0.0);
  EXPECT_GE(FrameStat(frame, "residual_1"), FrameStat(frame, "residual_4"));
}

// relMSE against a path-traced reference, 64 x 64.
class AntiradianceAccuracy : public testing::ReferenceFixture {};

TEST_F(AntiradianceAccuracy, TriangleElementsAlsoBeatDirect) {
  // elements=triangles: this solver's own triangle/cluster builder.
  Reference("indirect_room.gltf", 1024);
  const double direct = ErrorOf("direct");
  const double ar = ErrorOf("antiradiance", {{"elements", "triangles"}});
  testing::RecordMeasurement("relmse_direct", direct);
  testing::RecordMeasurement("relmse_antiradiance_triangles", ar);
  // Measured 0.036 against 0.145.
  EXPECT_LT(ar, 0.3 * direct) << "direct " << direct << " antiradiance " << ar;
}

TEST(Antiradiance, StagePlanFollowsTheChange) {
  using testing::StageSkipped;
  const testing::ChangeKindFrames f =
      testing::RenderEachChangeKind("antiradiance", {{"bins", "64"}});
  const std::vector<std::string> gi = {"link", "global_pass", "local_pass", "push_pull"};
  EXPECT_EQ(f.first_image.non_finite(), 0u);
  for (const std::string& s : gi) EXPECT_FALSE(StageSkipped(f.first, s)) << "first frame " << s;
  EXPECT_TRUE(FrameStage(f.first, "link")->cpu_stage);
  // Light only: links reused.
  EXPECT_TRUE(StageSkipped(f.light_only, "link"));
  for (const char* s : {"global_pass", "local_pass", "push_pull", "display"}) {
    EXPECT_FALSE(StageSkipped(f.light_only, s)) << "light-only " << s;
  }
  // Camera only: only display runs.
  for (const std::string& s : gi)
    EXPECT_TRUE(StageSkipped(f.camera_only, s)) << "camera-only " << s;
  EXPECT_FALSE(StageSkipped(f.camera_only, "display"));
  // Geometry: relink.
  for (const std::string& s : gi) EXPECT_FALSE(StageSkipped(f.geometry, s)) << "geometry " << s;
}

TEST(Antiradiance, MovingAnObjectRelinksOnlyItsPairsAndMatchesAFullLink) {
  // Section 3.3: only links to and from the moved block are recomputed;
  // the result equals linking the moved scene from scratch.
  NodeTransformUpdate move;
  move.node = 2;  // block
  move.translation = {0.5f, 0.25f, 0.3f};
  // tolerance 0: every iteration runs, so the relinked update (which
  // iterates from the previous solution) and the fresh one (from the
  // sources) both reach the fixed point to float rounding.
  const std::map<std::string, std::string> params = {{"bins", "64"}, {"tolerance", "0"}};
  EncodedFrame frame;
  const BundledCopy scene("dynamic_block.gltf");
  RenderRequestExr(SolverRequest(scene.id(), "antiradiance", params, 32), &frame);
  const double pairs = FrameStat(frame, "root_pairs");
  EXPECT_EQ(FrameStat(frame, "relinked_root_pairs"), pairs);
  const FloatImage moved =
      RenderRequestExr(SolverRequest(scene.id(), "antiradiance", params, 32, {{1, move}}), &frame);
  EXPECT_GT(FrameStat(frame, "relinked_root_pairs"), 0.0);
  // The block is six of the eight charts (roots): the pairs among the
  // floor's charts are kept.
  EXPECT_LT(FrameStat(frame, "relinked_root_pairs"), pairs);
  const double links = FrameStat(frame, "links");

  const BundledCopy fresh("dynamic_block.gltf");
  const FloatImage full =
      RenderRequestExr(SolverRequest(fresh.id(), "antiradiance", params, 32, {{1, move}}), &frame);
  EXPECT_EQ(FrameStat(frame, "relinked_root_pairs"), pairs);
  EXPECT_EQ(FrameStat(frame, "links"), links);
  EXPECT_NEAR(ImageMean(moved).g, ImageMean(full).g, 1e-5 * ImageMean(full).g);
}

TEST(Antiradiance, OddBinCountIsRejectedNamingTheParameter) {
  const BundledCopy scene("furnace.gltf");
  auto frame = testing::SharedEngine().Render(
      SolverRequest(scene.id(), "antiradiance", {{"bins", "33"}}, 8));
  ASSERT_FALSE(frame.ok());
  EXPECT_EQ(frame.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(frame.status().message().find("params.bins"), std::string::npos) << frame.status();
}

}  // namespace antiradiance_test
}  // namespace gistream
