#include "support/render_helpers.h"

#include <cmath>
#include <fstream>
#include <iterator>
#include <mutex>

#include <gtest/gtest.h>

#include "encode/encode.h"
#include "util/image_metrics.h"

namespace gistream::testing {

namespace {

// The shared engine is destroyed when the test program ends, before static
// destruction: its render thread must not run (dropping scenes, releasing
// Embree devices) while libraries' own statics are being torn down.
std::unique_ptr<Engine>& SharedEngineSlot() {
  static std::unique_ptr<Engine> engine;
  return engine;
}

class ShutDownSharedEngine : public ::testing::EmptyTestEventListener {
  void OnTestProgramEnd(const ::testing::UnitTest& /*unit_test*/) override {
    SharedEngineSlot().reset();
  }
};

}  // namespace

Engine& SharedEngine() {
  std::unique_ptr<Engine>& engine = SharedEngineSlot();
  static std::once_flag created_once;
  std::call_once(created_once, [&engine] {
    EngineOptions options;
    options.scene_dir = std::string(GISTREAM_SOURCE_DIR "/scenes");
    // No solve-time limit: the GL suites drive the solvers themselves, up
    // to the extreme in-range parameters a server without the limit
    // accepts (cancellation_test.cpp), and the solvers' own limits
    // (sh_probes_test.cpp); the limit has its own tests
    // (reliability/solve_estimate_test.cpp).
    options.max_solve_seconds = 0.0;
    auto created = Engine::Create(options);
    if (!created.ok()) {
      ADD_FAILURE() << "Engine::Create: " << created.status();
      std::abort();
    }
    engine = std::move(created).value();
    ::testing::UnitTest::GetInstance()->listeners().Append(new ShutDownSharedEngine);
  });
  return *engine;
}

glm::vec3 FloatImage::mean(int x, int y, int r) const {
  glm::vec3 sum(0.0f);
  int n = 0;
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      const int px = x + dx, py = y + dy;
      if (px < 0 || py < 0 || px >= width || py >= height) continue;
      sum += at(px, py);
      ++n;
    }
  }
  return n ? sum / float(n) : sum;
}

size_t FloatImage::non_finite() const {
  size_t n = 0;
  for (float v : rgba) n += std::isfinite(v) ? 0 : 1;
  return n;
}

FloatImage DecodeExr(const EncodedFrame& frame) {
  auto decoded =
      DecodeImageBytes({reinterpret_cast<const uint8_t*>(frame.image.data()), frame.image.size()});
  EXPECT_TRUE(decoded.ok()) << decoded.status();
  FloatImage image;
  if (!decoded.ok()) return image;
  image.width = decoded->width;
  image.height = decoded->height;
  image.rgba = std::move(decoded->rgba);
  return image;
}

glm::ivec2 Project(const ViewCamera& camera, const glm::vec3& p) {
  const glm::vec4 clip = camera.Projection() * camera.View() * glm::vec4(p, 1.0f);
  const glm::vec2 ndc = glm::vec2(clip) / clip.w;
  const float x = (ndc.x * 0.5f + 0.5f) * float(camera.width);
  const float y = (1.0f - (ndc.y * 0.5f + 0.5f)) * float(camera.height);
  return {int(std::floor(x)), int(std::floor(y))};
}

FloatImage RenderExr(Engine& engine, const std::string& scene_id, const std::string& solver,
                     uint32_t width, uint32_t height,
                     const std::map<std::string, std::string>& params,
                     std::optional<CameraUpdate> camera, EncodedFrame* frame_out) {
  RenderRequest request;
  request.scene = scene_id;
  request.solver = solver;
  request.params = params;
  request.width = width;
  request.height = height;
  request.encoding.format = ImageFormat::kExr;
  request.camera = camera;
  request.refine_samples = 1;  // pixel centres (see render_helpers.h)
  auto frame = engine.Render(request);
  EXPECT_TRUE(frame.ok()) << frame.status();
  if (!frame.ok()) return {};
  if (frame_out) *frame_out = *frame;
  return DecodeExr(*frame);
}

TestScene::TestScene(SceneSource source) {
  auto info = SharedEngine().LoadScene(std::move(source));
  EXPECT_TRUE(info.ok()) << info.status();
  if (info.ok()) id_ = info->id;
}

TestScene::~TestScene() {
  if (id_.empty() || !SharedEngineSlot()) return;
  const absl::Status status = SharedEngine().UnloadScene(id_);
  EXPECT_TRUE(status.ok()) << status;
}

std::string EnvironmentExr(int width, int height, const std::function<glm::vec3(int, int)>& at) {
  std::vector<float> rgba;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const glm::vec3 c = at(x, y);
      rgba.insert(rgba.end(), {c.r, c.g, c.b, 1.0f});
    }
  }
  auto exr = EncodeExr(rgba, width, height);
  EXPECT_TRUE(exr.ok()) << exr.status();
  return exr.ok() ? *exr : std::string();
}

std::string UniformEnvironmentExr(float radiance, int width, int height) {
  return EnvironmentExr(width, height, [radiance](int, int) { return glm::vec3(radiance); });
}

namespace {
std::string BundledBytes(const std::string& file) {
  std::ifstream in(std::string(GISTREAM_SOURCE_DIR "/scenes/") + file, std::ios::binary);
  std::string bytes(std::istreambuf_iterator<char>(in), {});
  EXPECT_FALSE(bytes.empty()) << file;
  return bytes;
}
}  // namespace

BundledCopy::BundledCopy(const std::string& file) : TestScene(SceneFromBytes(BundledBytes(file))) {}

double FrameStat(const EncodedFrame& frame, const std::string& name) {
  for (const auto& [k, v] : frame.stats) {
    if (k == name) return v;
  }
  ADD_FAILURE() << "no stat " << name;
  return -1.0;
}

const StageTiming* FrameStage(const EncodedFrame& frame, const std::string& name) {
  for (const StageTiming& t : frame.timings) {
    if (t.name == name) return &t;
  }
  ADD_FAILURE() << "no stage " << name;
  return nullptr;
}

glm::dvec3 ImageMean(const FloatImage& image) {
  glm::dvec3 sum(0.0);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) sum += glm::dvec3(image.at(x, y));
  }
  return image.width > 0 ? sum / double(image.width * image.height) : sum;
}

void ExpectSameImage(const FloatImage& got, const FloatImage& expected, float relative) {
  ASSERT_EQ(got.width, expected.width);
  ASSERT_EQ(got.height, expected.height);
  ASSERT_EQ(got.rgba.size(), expected.rgba.size());
  for (size_t i = 0; i < got.rgba.size(); ++i) {
    ASSERT_NEAR(got.rgba[i], expected.rgba[i], relative * std::max(1.0f, expected.rgba[i]))
        << "value " << i << " (pixel " << i / 4 << ")";
  }
}

double RelMse(const FloatImage& image, const FloatImage& reference) {
  // The same relMSE as gistream eval (util/image_metrics.h); a size
  // mismatch or a non-finite pixel fails the test and reads as huge.
  const absl::StatusOr<ImageError> error = CompareImages(
      {image.width, image.height, image.rgba}, {reference.width, reference.height, reference.rgba});
  EXPECT_TRUE(error.ok()) << error.status();
  if (!error.ok()) return 1e30;
  EXPECT_EQ(error->nonfinite_fraction, 0.0);
  return error->nonfinite_fraction > 0.0 ? 1e30 : error->rel_mse;
}

RenderRequest SolverRequest(const std::string& scene, const std::string& solver,
                            std::map<std::string, std::string> params, uint32_t size,
                            std::vector<Update> updates) {
  RenderRequest r;
  r.scene = scene;
  r.solver = solver;
  r.params = std::move(params);
  r.width = r.height = size;
  r.updates = std::move(updates);
  r.refine_samples = 1;  // pixel centres (see render_helpers.h)
  return r;
}

SessionConfig ExrStreamConfig(const std::string& scene, const std::string& solver,
                              std::map<std::string, std::string> params, uint32_t size) {
  SessionConfig config;
  config.scene = scene;
  config.solver = solver;
  config.params = std::move(params);
  config.width = config.height = size;
  config.encoding.format = ImageFormat::kExr;
  config.max_fps = 240.0f;
  config.refine_samples = 1;  // pixel centres (see render_helpers.h)
  return config;
}

MaterialUpdate GreyAlbedo(float rho, uint32_t material) {
  MaterialUpdate m;
  m.material = material;
  m.base_color = glm::vec4(rho, rho, rho, 1.0f);
  return m;
}

FloatImage RenderRequestExr(RenderRequest request, EncodedFrame* frame_out) {
  request.encoding.format = ImageFormat::kExr;
  auto frame = SharedEngine().Render(request);
  EXPECT_TRUE(frame.ok()) << frame.status();
  if (!frame.ok()) return {};
  if (frame_out) *frame_out = *frame;
  return DecodeExr(*frame);
}

void ExpectFurnaceScaleInvariant(const std::string& solver,
                                 const std::map<std::string, std::string>& params, double tolerance,
                                 const std::function<void(const EncodedFrame&)>& check,
                                 double expected) {
  struct Case {
    float scale, strength;
  };
  auto render = [&](const Case& c, EncodedFrame* frame) {
    const BundledCopy scene("furnace.gltf");
    NodeTransformUpdate scale;
    scale.node = 0;
    scale.scale = glm::vec3(c.scale);
    MaterialUpdate emission;
    emission.material = 0;
    emission.emissive_strength = c.strength;
    return RenderRequestExr(
        SolverRequest(scene.id(), solver, params, 16, {{1, scale}, {2, emission}}), frame);
  };
  EncodedFrame reference_frame;
  const FloatImage reference = render({1.0f, 1.0f}, &reference_frame);
  ASSERT_EQ(reference.width, 16);
  for (const Case c : {Case{1e-4f, 1.0f}, Case{1e-3f, 1.0f}, Case{1e3f, 1.0f}, Case{1e5f, 1.0f},
                       Case{1.0f, 1e6f}, Case{1.0f, 1e-3f}, Case{1.0f, 1e-6f}}) {
    SCOPED_TRACE(::testing::Message()
                 << solver << " scale " << c.scale << " emission " << c.strength);
    EncodedFrame frame;
    FloatImage image = render(c, &frame);
    ASSERT_EQ(image.width, 16);
    EXPECT_EQ(image.non_finite(), 0u);
    EXPECT_NEAR(ImageMean(image).g / c.strength, expected, tolerance);
    // The same image as at scale 1 and emission 1: per pixel (RMS,
    // relative) within the same tolerance as the mean.
    for (float& v : image.rgba) v /= c.strength;
    EXPECT_LE(RelMse(image, reference), tolerance * tolerance);
    if (check) check(frame);
  }
}

ChangeKindFrames RenderEachChangeKind(const std::string& solver,
                                      const std::map<std::string, std::string>& params) {
  const BundledCopy scene("dynamic_block.gltf");
  const std::string& id = scene.id();
  ChangeKindFrames out;
  out.first_image = RenderRequestExr(SolverRequest(id, solver, params, 16), &out.first);
  LightUpdate dim;
  dim.light = 0;  // point_light
  dim.intensity = 10.0f;
  RenderRequestExr(SolverRequest(id, solver, params, 16, {{1, dim}}), &out.light_only);
  RenderRequest camera_only = SolverRequest(id, solver, params, 16);
  CameraUpdate camera;
  camera.look_at = LookAt{{1.0f, 2.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  camera_only.camera = camera;
  RenderRequestExr(camera_only, &out.camera_only);
  NodeTransformUpdate move;
  move.node = 2;  // block
  move.translation = {0.5f, 0.25f, 0.3f};
  RenderRequestExr(SolverRequest(id, solver, params, 16, {{2, move}}), &out.geometry);
  return out;
}

bool StageSkipped(const EncodedFrame& frame, const std::string& stage) {
  const StageTiming* t = FrameStage(frame, stage);
  return t != nullptr && t->skipped;
}

void ReferenceFixture::Reference(const std::string& file, int spp) {
  copy_ = std::make_unique<BundledCopy>(file);
  scene_ = copy_->id();
  reference_ =
      RenderRequestExr(SolverRequest(scene_, "pathtrace", {{"spp", std::to_string(spp)}}, kSize));
}

double ReferenceFixture::ErrorOf(const std::string& solver,
                                 std::map<std::string, std::string> params) {
  // Refined (the server's default samples), as the box-filtered reference.
  RenderRequest request = SolverRequest(scene_, solver, std::move(params), kSize);
  request.refine_samples = 0;
  const FloatImage image = RenderRequestExr(request);
  EXPECT_EQ(image.non_finite(), 0u) << solver;
  return RelMse(image, reference_);
}

double MeanGreenFrom(const std::string& scene_id, const std::string& solver,
                     const std::map<std::string, std::string>& params, glm::vec3 eye,
                     glm::vec3 target, glm::vec3 up, float yfov_degrees, uint32_t size) {
  CameraUpdate camera;
  camera.look_at = LookAt{eye, target, up};
  camera.yfov_degrees = yfov_degrees;
  const FloatImage image = RenderExr(SharedEngine(), scene_id, solver, size, size, params, camera);
  EXPECT_EQ(image.width, int(size)) << solver;
  EXPECT_EQ(image.non_finite(), 0u) << solver;
  if (image.width != int(size) || image.non_finite() > 0) return -1.0;
  return ImageMean(image).g;
}

}  // namespace gistream::testing
