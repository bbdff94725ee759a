#include "reliability/reliability_fixture.h"

#include <sys/stat.h>

#include <cstdlib>
#include <fstream>

#include "support/gltf_builder.h"
#include "support/render_helpers.h"

namespace gistream::reliability {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

struct Fixture {
  fs::path dir;
  std::unique_ptr<Engine> engine;

  Fixture() {
    std::string pattern = (fs::temp_directory_path() / "gistream_reliability_XXXXXX").string();
    GS_CHECK(mkdtemp(pattern.data()) != nullptr);
    dir = pattern;
    std::ofstream(dir / "quad.gltf") << QuadScene().dump();
    for (const char* fifo : {"fifo_env.hdr", "fifo_scene.gltf", "fifo.bin"}) {
      GS_CHECK(mkfifo((dir / fifo).c_str(), 0600) == 0);
    }
    json external = QuadScene();
    external["buffers"][0]["uri"] = "fifo.bin";
    std::ofstream(dir / "external_fifo.gltf") << external.dump();
    EngineOptions options;
    options.scene_dir = dir;
    auto created = Engine::Create(options);
    GS_CHECK(created.ok());
    engine = *std::move(created);
  }
};

// Created on first use; its engine is shut down and its directory removed
// when the tests end (RemoveSceneDir), the Fixture itself never destroyed
// (GL teardown at static destruction time is not safe).
Fixture* g_fixture = nullptr;

Fixture& F() {
  if (g_fixture == nullptr) g_fixture = new Fixture();
  return *g_fixture;
}

// When the tests end (inside RUN_ALL_TESTS, before static destruction):
// the engine shuts down, its render thread joined, so no deferred scene
// drop runs while libraries' statics (Embree's, the GL driver's) are torn
// down at exit; then its scene directory goes.
class RemoveSceneDir : public ::testing::Environment {
 public:
  void TearDown() override {
    if (g_fixture == nullptr) return;
    g_fixture->engine.reset();
    std::error_code ec;
    fs::remove_all(g_fixture->dir, ec);
  }
};
[[maybe_unused]] ::testing::Environment* const kRemoveSceneDir =
    ::testing::AddGlobalTestEnvironment(new RemoveSceneDir);

}  // namespace

json QuadScene() {
  testing::GltfBuilder b;
  const int white = b.AddMaterial("white", {0.8f, 0.8f, 0.8f});
  const int lamp = b.AddMaterial("lamp", {0, 0, 0}, {1, 1, 1}, 5.0f);
  b.AddQuad("floor", {0, 0, 0}, {1, 0, 0}, {0, 0, -1}, white);
  b.AddQuad("lamp", {0, 1.5f, 0}, {0.2f, 0, 0}, {0, 0, 0.2f}, lamp);
  b.AddPointLight("bulb", {0, 1, 0}, {1, 1, 1}, 5.0f);
  b.AddCamera("cam", {0, 2, 2}, {0, -0.70710678f, -0.70710678f}, {0, 1, 0}, 0.8f);
  return json::parse(b.ToJson());
}

Engine& E() { return *F().engine; }
const fs::path& SceneDir() { return F().dir; }

QuadCopy::QuadCopy(const json& doc) {
  auto info = E().LoadScene(testing::SceneFromBytes(doc.dump()));
  EXPECT_TRUE(info.ok()) << info.status();
  if (info.ok()) id_ = info->id;
}

QuadCopy::~QuadCopy() {
  if (!id_.empty()) {
    EXPECT_TRUE(E().UnloadScene(id_).ok());
  }
}

RenderRequest Request(const std::string& scene, const std::string& solver,
                      std::vector<Update> updates, std::map<std::string, std::string> params) {
  RenderRequest r;
  r.scene = scene;
  r.solver = solver;
  r.params = std::move(params);
  r.width = 16;
  r.height = 16;
  r.encoding.format = ImageFormat::kExr;
  r.updates = std::move(updates);
  return r;
}

void ExpectRendersFinite(const std::string& scene, const std::string& solver) {
  auto frame = E().Render(Request(scene, solver));
  ASSERT_TRUE(frame.ok()) << frame.status();
  const testing::FloatImage image = testing::DecodeExr(*frame);
  EXPECT_EQ(image.non_finite(), 0u);
  EXPECT_GT(testing::ImageMean(image).x, 0.0) << "the lit floor renders black";
}

bool ResetPeakRss() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.flush();
  return bool(clear);
}

uint64_t StatusKiB(const std::string& key) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(key + ":", 0) == 0) return std::stoull(line.substr(key.size() + 1));
  }
  return 0;
}

}  // namespace gistream::reliability
