// Helpers for tests that render through a real Engine on EGL (llvmpipe
// when there is no GPU): one engine per test binary, float frames decoded,
// world points projected to pixels.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "encode/encode.h"
#include "render/camera.h"
#include "engine/engine.h"

namespace gistream::testing {

// The process-wide engine (created on first use; scene dir = scenes/).
Engine& SharedEngine();

struct FloatImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgba;  // rows top first
  glm::vec3 at(int x, int y) const {
    const size_t i = (size_t(y) * size_t(width) + size_t(x)) * 4;
    return {rgba[i], rgba[i + 1], rgba[i + 2]};
  }
  // Mean over a (2r+1)^2 window.
  glm::vec3 mean(int x, int y, int r) const;
  size_t non_finite() const;
};

FloatImage DecodeExr(const EncodedFrame& frame);

inline SceneSource SceneByName(const std::string& name) {
  SceneSource s;
  s.name = name;
  return s;
}
inline SceneSource SceneFromBytes(std::string bytes) {
  SceneSource s;
  s.bytes = std::move(bytes);
  return s;
}

// Pixel (x right, y down) where world point p lands for `camera`.
glm::ivec2 Project(const ViewCamera& camera, const glm::vec3& p);

// A scene loaded into the shared engine from `source` (a GltfBuilder's
// JSON through SceneFromBytes, with an environment or not), unloaded when
// it goes out of scope (a suite's static one after the engine is gone:
// nothing to do). id() is "" (and the test has failed) when loading did.
class TestScene {
 public:
  explicit TestScene(SceneSource source);
  ~TestScene();
  TestScene(const TestScene&) = delete;
  TestScene& operator=(const TestScene&) = delete;
  const std::string& id() const { return id_; }

 private:
  std::string id_;
};

// An EXR environment map of width x height texels, texel (x, y) (rows top
// first) of radiance `at(x, y)`; and one of uniform radiance.
std::string EnvironmentExr(int width, int height, const std::function<glm::vec3(int, int)>& at);
std::string UniformEnvironmentExr(float radiance, int width, int height);

// A private copy of a bundled scene (scenes/FILE uploaded as bytes), so
// updates do not leak into other tests; unloaded when it goes out of scope
// (the engine holds at most --max-scenes). id() is "" (and the test has
// failed) when loading did.
class BundledCopy : public TestScene {
 public:
  explicit BundledCopy(const std::string& file);
};

// A frame's stat / stage by name; a test failure (and -1 / nullptr) when
// the frame has none.
double FrameStat(const EncodedFrame& frame, const std::string& name);
const StageTiming* FrameStage(const EncodedFrame& frame, const std::string& name);

glm::dvec3 ImageMean(const FloatImage& image);
// Fails the test unless the images have the same size and every value
// agrees within `relative` x max(1, expected) (float rounding of the same
// computation done in another order or split over frames).
void ExpectSameImage(const FloatImage& got, const FloatImage& expected, float relative = 1e-4f);

// gistream eval's relMSE: mean over pixels and channels of
// (x - r)^2 / (r^2 + 0.01).
double RelMse(const FloatImage& image, const FloatImage& reference);

// The helpers below render pixel centres (refine_samples 1): their tests
// check a solver's solution at pixels (analytic values, equality of two
// ways to the same solution, a stream's frames against a Render), which a
// still view's refinement (tests/gl/refinement_test.cpp) would blur into
// box averages; ReferenceFixture::ErrorOf alone renders refined, as its
// box-filtered path-traced reference is.
// A Render request for `solver` on `scene` at size x size with `updates`.
RenderRequest SolverRequest(const std::string& scene, const std::string& solver,
                            std::map<std::string, std::string> params, uint32_t size,
                            std::vector<Update> updates = {});
// A stream session of size x size EXR frames, uncapped (240 fps), for
// tests that watch frames while an update runs on.
SessionConfig ExrStreamConfig(const std::string& scene, const std::string& solver,
                              std::map<std::string, std::string> params, uint32_t size);
// Sets material `material`'s base colour to grey `rho`.
MaterialUpdate GreyAlbedo(float rho, uint32_t material = 0);

// The white furnace (albedo 0.5: L = 2 x emission) scaled from 1e-4 to
// 1e5 and with emission 1e-6 to 1e6 nits: renders `solver` at 16 x 16 for
// each case and expects a finite image whose mean over the emission
// strength is `expected` (2; 1.5 for direct light alone: L_e plus one
// bounce of 0.5) within `tolerance`, and which over the strength is the
// image at scale 1 and emission 1 (relMSE at most tolerance^2); `check`
// sees every frame.
void ExpectFurnaceScaleInvariant(const std::string& solver,
                                 const std::map<std::string, std::string>& params, double tolerance,
                                 const std::function<void(const EncodedFrame&)>& check = {},
                                 double expected = 2.0);

// One frame per kind of change, on a private copy of dynamic_block and in
// this order: the first frame (everything runs), the point light dimmed
// (light-only), a camera-only move, the block moved (geometry).
struct ChangeKindFrames {
  FloatImage first_image;
  EncodedFrame first, light_only, camera_only, geometry;
};
ChangeKindFrames RenderEachChangeKind(const std::string& solver,
                                      const std::map<std::string, std::string>& params);
// True when `frame` reports `stage` as skipped (a test failure if absent).
bool StageSkipped(const EncodedFrame& frame, const std::string& stage);

// A fixture for error against the path-traced reference at 64 x 64:
// Reference() loads a private copy of a bundled scene and renders
// `pathtrace` at `spp`; ErrorOf() renders a solver on it, refined with the
// server's default samples (expecting a finite image), and returns its
// relMSE.
class ReferenceFixture : public ::testing::Test {
 protected:
  void Reference(const std::string& file, int spp);
  double ErrorOf(const std::string& solver, std::map<std::string, std::string> params = {});

  static constexpr uint32_t kSize = 64;
  std::unique_ptr<BundledCopy> copy_;
  std::string scene_;
  FloatImage reference_;
};

// Renders an EXR frame of `request` (format forced to EXR); fails the test
// on error.
FloatImage RenderRequestExr(RenderRequest request, EncodedFrame* frame_out = nullptr);

// Renders EXR through Engine::Render; fails the test on error.
FloatImage RenderExr(Engine& engine, const std::string& scene_id, const std::string& solver,
                     uint32_t width, uint32_t height,
                     const std::map<std::string, std::string>& params = {},
                     std::optional<CameraUpdate> camera = std::nullopt,
                     EncodedFrame* frame_out = nullptr);

// The mean green radiance of a size x size EXR render of `solver` on
// `scene_id` from `eye` looking at `target` (`up`, vertical fov
// `yfov_degrees`); -1 (and a test failure) when it did not render or has
// non-finite pixels.
double MeanGreenFrom(const std::string& scene_id, const std::string& solver,
                     const std::map<std::string, std::string>& params, glm::vec3 eye,
                     glm::vec3 target, glm::vec3 up, float yfov_degrees, uint32_t size);

}  // namespace gistream::testing
