// The `avg` solver through the shared Engine on EGL (llvmpipe): error
// against the path-traced reference falls as VPLs are added, it beats
// `direct` on the indirect-only room, conserves energy in the furnace,
// keeps light from leaking through a thin wall, and a camera-only change
// skips the view-independent stages (the glossy cube: glossy_light_test.cpp). Images are 32 px
// (llvmpipe-sized); references are rendered here by `pathtrace`.
#include <cmath>

#include <absl/strings/str_cat.h>
#include <gtest/gtest.h>

#include "support/gltf_builder.h"
#include "support/measurement.h"
#include "support/render_helpers.h"

namespace gistream {
namespace avg_test {

using testing::BundledCopy;
using testing::FloatImage;
using testing::FrameStage;
using testing::RelMse;
glm::dvec3 Mean(const FloatImage& image) { return testing::ImageMean(image); }

FloatImage Render(const std::string& scene, const std::string& solver,
                  std::map<std::string, std::string> params, uint32_t size,
                  std::vector<Update> updates = {}, EncodedFrame* frame = nullptr) {
  RenderRequest request;
  request.scene = scene;
  request.solver = solver;
  request.params = std::move(params);
  request.width = request.height = size;
  request.updates = std::move(updates);
  return testing::RenderRequestExr(std::move(request), frame);
}

// Small settings for llvmpipe: 16 area samples and 32^2 VPL maps.
std::map<std::string, std::string> Small(std::map<std::string, std::string> more = {}) {
  std::map<std::string, std::string> p = {
      {"area_samples", "16"}, {"shadow_res", "32"}, {"direct_shadow_res", "128"}};
  for (auto& [k, v] : more) p[k] = v;
  return p;
}

constexpr uint32_t kSize = 32;

// The still picture's VPLs (`still_vpls`, default 2048: a second set of
// 1024 joined to the first once nothing changes) take the error further
// down; the frame says how many it shows.
TEST(AvgRender, CornellErrorFallsAsVplsGrow) {
  const BundledCopy scene("cornell_box.gltf");
  const std::string& id = scene.id();
  const FloatImage reference = Render(id, "pathtrace", {{"spp", "1024"}}, kSize);
  const FloatImage few = Render(id, "avg", Small({{"vpls", "64"}, {"still_vpls", "0"}}), kSize);
  const FloatImage many = Render(id, "avg", Small({{"vpls", "1024"}, {"still_vpls", "0"}}), kSize);
  EncodedFrame still_frame;
  const FloatImage still = Render(id, "avg", Small(), kSize, {}, &still_frame);
  const FloatImage direct = Render(id, "direct", {{"area_samples", "16"}}, kSize);
  ASSERT_EQ(many.width, int(kSize));
  EXPECT_EQ(few.non_finite(), 0u);
  EXPECT_EQ(many.non_finite(), 0u);
  EXPECT_EQ(still.non_finite(), 0u);
  const double e_few = RelMse(few, reference), e_many = RelMse(many, reference);
  const double e_still = RelMse(still, reference);
  const double e_direct = RelMse(direct, reference);
  testing::RecordMeasurement("relmse_direct", e_direct);
  testing::RecordMeasurement("relmse_64_vpls", e_few);
  testing::RecordMeasurement("relmse_1024_vpls", e_many);
  testing::RecordMeasurement("relmse_still_2048_vpls", e_still);
  EXPECT_LT(e_many, 0.7 * e_few);
  EXPECT_LT(e_many, 0.5 * e_direct);
  // 5.87e-3 against 6.83e-3 (0.86x; the 1024-spp reference's own noise
  // is part of both at 32 px).
  EXPECT_LT(e_still, 0.93 * e_many);
  EXPECT_GT(testing::FrameStat(still_frame, "still_vpls"), 500.0);
  EXPECT_EQ(testing::FrameStat(still_frame, "still_pending"), 0.0);
  EXPECT_EQ(testing::FrameStat(still_frame, "update_complete"), 1.0);
}

TEST(AvgRender, BeatsDirectOnTheIndirectOnlyRoom) {
  const BundledCopy scene("indirect_room.gltf");
  const std::string& id = scene.id();
  const FloatImage reference = Render(id, "pathtrace", {{"spp", "1024"}}, kSize);
  // 64^2 VPL maps: at 32^2 the shadow bias (a texel at the receiver's
  // distance) is too coarse for the 25 cm door reveals (relMSE 0.084).
  const FloatImage avg = Render(id, "avg", Small({{"vpls", "512"}, {"shadow_res", "64"}}), kSize);
  const FloatImage direct = Render(id, "direct", {{"area_samples", "16"}}, kSize);
  ASSERT_EQ(avg.width, int(kSize));
  EXPECT_EQ(avg.non_finite(), 0u);
  const double e_avg = RelMse(avg, reference), e_direct = RelMse(direct, reference);
  testing::RecordMeasurement("relmse_direct", e_direct);
  testing::RecordMeasurement("relmse_avg", e_avg);
  // `direct` renders room B black; avg must at least halve its error.
  EXPECT_LT(e_avg, 0.5 * e_direct);
}

TEST(AvgRender, ThinWallDoesNotLeak) {
  // A closed 2 m box split by a single zero-thickness sheet at x = 0 (far
  // thinner than a voxel), a point light on the left. Nothing reaches the
  // right half: the reference is black there. The grid never lets a path
  // through the sheet; with VPL visibility the right half stays nearly
  // dark, without it VPLs on the left shine through.
  testing::GltfBuilder b;
  const int white = b.AddMaterial("white", {0.7f, 0.7f, 0.7f});
  b.AddQuad("left", {-1, 0, 0}, {0, 0, 1}, {0, 1, 0}, white, 8);
  b.AddQuad("right", {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, white, 8);
  b.AddQuad("floor", {0, -1, 0}, {1, 0, 0}, {0, 0, 1}, white, 8);
  b.AddQuad("ceiling", {0, 1, 0}, {0, 0, 1}, {1, 0, 0}, white, 8);
  b.AddQuad("back", {0, 0, -1}, {0, 1, 0}, {1, 0, 0}, white, 8);
  b.AddQuad("front", {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, white, 8);
  b.AddQuad("divider", {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, white, 8);
  b.AddPointLight("lamp", {-0.5f, 0.5f, 0.0f}, {1, 1, 1}, 5.0f);
  b.AddCamera("camera", {0.95f, 0.0f, 0.0f}, {-1, 0, 0}, {0, 1, 0}, 1.4f);
  auto info = testing::SharedEngine().LoadScene(testing::SceneFromBytes(b.ToJson()));
  ASSERT_TRUE(info.ok()) << info.status();
  CameraUpdate lit_view, dark_view;
  lit_view.look_at = LookAt{{-0.95f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  lit_view.yfov_degrees = 80.0f;
  // The right half's floor, back wall and divider (the divider alone would
  // face away from every VPL, dark even without visibility).
  dark_view.look_at = LookAt{{0.95f, 0.9f, 0.9f}, {0.2f, -1.0f, -0.6f}, {0.0f, 1.0f, 0.0f}};
  dark_view.yfov_degrees = 80.0f;
  const auto params = Small({{"vpls", "256"}});
  const FloatImage dark = Render(info->id, "avg", params, kSize, {{1, dark_view}});
  const FloatImage lit = Render(info->id, "avg", params, kSize, {{2, lit_view}});
  auto unshadowed = params;
  unshadowed["visibility"] = "false";
  const FloatImage leaky = Render(info->id, "avg", unshadowed, kSize, {{3, dark_view}});
  ASSERT_EQ(dark.width, int(kSize));
  const double lit_mean = Mean(lit).g, dark_mean = Mean(dark).g, leak_nv = Mean(leaky).g;
  testing::RecordMeasurement("lit_side", lit_mean);
  testing::RecordMeasurement("dark_side", dark_mean);
  testing::RecordMeasurement("dark_side_without_visibility", leak_nv);
  // Measured: dark / lit = 1.7 % with visibility, 12 % without. What is
  // left comes from VPLs in the voxels the sheet shares with the ceiling
  // and floor, whose mean plane can lie on the dark side (server/solvers/avg/README.md).
  EXPECT_GT(lit_mean, 0.01);
  EXPECT_LT(dark_mean, 0.03 * lit_mean);
  EXPECT_LT(dark_mean, 0.25 * leak_nv);
  EXPECT_TRUE(testing::SharedEngine().UnloadScene(info->id).ok());
}

TEST(AvgRender, CameraOnlyChangeSkipsViewIndependentStages) {
  const BundledCopy scene("dynamic_block.gltf");
  const std::string& id = scene.id();
  const auto params = Small({{"vpls", "64"}});
  EncodedFrame first, camera_only, light_only, geometry;
  Render(id, "avg", params, kSize, {}, &first);
  for (const char* stage :
       {"voxelize", "trace_vpls", "vpl_shadow_maps", "gbuffer", "illuminate", "filter"}) {
    const StageTiming* t = FrameStage(first, stage);
    ASSERT_NE(t, nullptr) << stage;
    EXPECT_FALSE(t->skipped) << stage;
  }
  EXPECT_TRUE(FrameStage(first, "voxelize")->cpu_stage);
  EXPECT_TRUE(FrameStage(first, "trace_vpls")->cpu_stage);

  CameraUpdate cam;
  cam.look_at = LookAt{{1.0f, 2.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  Render(id, "avg", params, kSize, {{1, cam}}, &camera_only);
  for (const char* stage : {"voxelize", "trace_vpls", "vpl_shadow_maps"}) {
    EXPECT_TRUE(FrameStage(camera_only, stage)->skipped) << stage;
  }
  for (const char* stage : {"gbuffer", "illuminate", "filter"}) {
    EXPECT_FALSE(FrameStage(camera_only, stage)->skipped) << stage;
  }

  LightUpdate dim;
  dim.light = 0;
  dim.intensity = 20.0f;
  Render(id, "avg", params, kSize, {{2, dim}}, &light_only);
  EXPECT_TRUE(FrameStage(light_only, "voxelize")->skipped);
  EXPECT_FALSE(FrameStage(light_only, "trace_vpls")->skipped);
  EXPECT_FALSE(FrameStage(light_only, "vpl_shadow_maps")->skipped);

  NodeTransformUpdate move;
  move.node = 2;  // block
  move.translation = {0.5f, 0.25f, 0.3f};
  const FloatImage moved = Render(id, "avg", params, kSize, {{3, move}}, &geometry);
  for (const char* stage : {"voxelize", "trace_vpls", "vpl_shadow_maps", "illuminate", "filter"}) {
    EXPECT_FALSE(FrameStage(geometry, stage)->skipped) << stage;
  }
  EXPECT_EQ(moved.non_finite(), 0u);
}

}  // namespace avg_test
}  // namespace gistream
