// External URIs resolve only inside the scene directory; scenes load by name.
#include <gtest/gtest.h>

#include <fstream>

#include "encode/encode.h"
#include "gltf_test_util.h"
#include "scene/gltf/gltf_import.h"

namespace gistream {
namespace scene_uri_test {

namespace fs = std::filesystem;
using testing::AddQuadMesh;
using testing::Import;
using testing::TestGltf;

class SceneDir : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "gistream-uri-XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    root_ = pattern;
    dir_ = root_ / "scenes";
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(root_); }

  void Write(const fs::path& path, const std::vector<uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  }

  // The quad with its buffer in an external file named `uri`.
  std::vector<uint8_t> QuadWithBufferUri(const std::string& uri, TestGltf* g) {
    g->AddRoot({{"mesh", AddQuadMesh(g)}});
    nlohmann::json d = g->doc;
    d["buffers"] = {{{"byteLength", g->bin.size()}, {"uri", uri}}};
    return testing::Bytes(d.dump());
  }

  ImportOptions Options() const {
    ImportOptions options;
    options.base_dir = dir_;
    return options;
  }

  fs::path root_;
  fs::path dir_;
};

TEST_F(SceneDir, ExternalBufferInsideBaseDirIsAccepted) {
  TestGltf g;
  const std::vector<uint8_t> gltf = QuadWithBufferUri("data/quad%20buffer.bin", &g);
  fs::create_directories(dir_ / "data");
  Write(dir_ / "data" / "quad buffer.bin", g.bin);
  const absl::StatusOr<Scene> scene = Import(gltf, Options());
  ASSERT_TRUE(scene.ok()) << scene.status();
  EXPECT_EQ(scene->triangle_count, 2u);
}

TEST_F(SceneDir, ExternalFilesCountAgainstTheSceneBudget) {
  TestGltf g;
  const std::vector<uint8_t> gltf = QuadWithBufferUri("quad.bin", &g);
  Write(dir_ / "quad.bin", g.bin);
  ImportOptions options = Options();
  options.limits.max_scene_bytes = gltf.size() + g.bin.size() - 1;
  EXPECT_ERROR(Import(gltf, options), kResourceExhausted, "over the remaining scene budget");
}

TEST_F(SceneDir, ExternalUriWithoutBaseDirIsRefused) {
  TestGltf g;
  EXPECT_ERROR(Import(QuadWithBufferUri("quad.bin", &g)), kInvalidArgument,
               "buffers[0].uri: external file 'quad.bin' refused");
}

TEST_F(SceneDir, ParentDirectoryIsRefused) {
  Write(root_ / "secret.bin", std::vector<uint8_t>(96, 0));
  TestGltf g;
  EXPECT_ERROR(Import(QuadWithBufferUri("../secret.bin", &g), Options()), kInvalidArgument,
               "buffers[0].uri: '../secret.bin' refused");
  TestGltf h;
  EXPECT_ERROR(Import(QuadWithBufferUri("data/../../secret.bin", &h), Options()), kInvalidArgument,
               "'..' is not allowed");
  TestGltf e;  // "..", percent-encoded
  EXPECT_ERROR(Import(QuadWithBufferUri("%2e%2e/secret.bin", &e), Options()), kInvalidArgument,
               "'..' is not allowed");
}

TEST_F(SceneDir, AbsolutePathIsRefused) {
  TestGltf g;
  EXPECT_ERROR(Import(QuadWithBufferUri("/etc/passwd", &g), Options()), kInvalidArgument,
               "buffers[0].uri: absolute path '/etc/passwd' refused");
  TestGltf h;
  EXPECT_ERROR(Import(QuadWithBufferUri("file:///etc/passwd", &h), Options()), kInvalidArgument,
               "URI scheme 'file' is not supported");
}

TEST_F(SceneDir, SymlinkOutOfBaseDirIsRefused) {
  TestGltf g;
  const std::vector<uint8_t> gltf = QuadWithBufferUri("link.bin", &g);
  Write(root_ / "outside.bin", g.bin);
  fs::create_symlink(root_ / "outside.bin", dir_ / "link.bin");
  EXPECT_ERROR(Import(gltf, Options()), kInvalidArgument,
               "buffers[0].uri: 'link.bin' resolves outside the scene directory");
}

TEST_F(SceneDir, MissingExternalBuffer) {
  TestGltf g;
  EXPECT_ERROR(Import(QuadWithBufferUri("nowhere.bin", &g), Options()), kInvalidArgument,
               "buffers[0].uri: 'nowhere.bin' does not exist");
}

TEST_F(SceneDir, ExternalImages) {
  const std::vector<uint8_t> rgba(4 * 4 * 4, 99);
  const absl::StatusOr<std::string> png = EncodePng(rgba, 4, 4);
  ASSERT_TRUE(png.ok());
  Write(dir_ / "tex.png", std::vector<uint8_t>(png->begin(), png->end()));
  Write(root_ / "outside.png", std::vector<uint8_t>(png->begin(), png->end()));
  TestGltf g;
  g.doc["images"] = {{{"uri", "tex.png"}}};
  g.doc["textures"] = {{{"source", 0}}};
  const int mat = g.AddMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  g.AddRoot({{"mesh", AddQuadMesh(&g, true, mat)}});
  const absl::StatusOr<Scene> scene = Import(g.ToGltf(), Options());
  ASSERT_TRUE(scene.ok()) << scene.status();
  EXPECT_EQ(scene->images.at(0).pixels8, rgba);

  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "images[0].uri: external file 'tex.png' refused");
  g.doc["images"][0]["uri"] = "../outside.png";
  EXPECT_ERROR(Import(g.ToGltf(), Options()), kInvalidArgument,
               "images[0].uri: '../outside.png' refused");
  g.doc["images"][0]["uri"] = "/etc/passwd";
  EXPECT_ERROR(Import(g.ToGltf(), Options()), kInvalidArgument, "images[0].uri: absolute path");
}

TEST_F(SceneDir, ImportSceneByName) {
  TestGltf g;
  g.AddRoot({{"mesh", AddQuadMesh(&g)}});
  Write(dir_ / "quad.gltf", g.ToGltf());
  Write(dir_ / "box.glb", g.ToGlb());
  for (const char* name : {"quad", "quad.gltf", "box", "box.glb"}) {
    const absl::StatusOr<Scene> scene = ImportSceneByName(dir_, name, {});
    ASSERT_TRUE(scene.ok()) << name << ": " << scene.status();
    EXPECT_EQ(scene->triangle_count, 2u);
  }
  EXPECT_EQ(ImportSceneByName(dir_, "quad", {})->name, "quad");
  EXPECT_ERROR(ImportSceneByName(dir_, "missing", {}), kNotFound,
               "name: no scene 'missing' (tried missing.glb, missing.gltf)");
  EXPECT_ERROR(ImportSceneByName(dir_, "box.gltf", {}), kNotFound, "tried box.gltf");
  for (const char* bad : {"", "../quad", "a/b", "/etc/passwd", "..", ".hidden", "quad gltf"}) {
    SCOPED_TRACE(bad);
    EXPECT_ERROR(ImportSceneByName(dir_, bad, {}), kInvalidArgument, "is not a scene name");
  }
}

TEST_F(SceneDir, ImportSceneByNameRespectsTheSizeLimit) {
  TestGltf g;
  g.AddRoot({{"mesh", AddQuadMesh(&g)}});
  Write(dir_ / "quad.gltf", g.ToGltf());
  ImportLimits limits;
  limits.max_scene_bytes = 64;
  EXPECT_ERROR(ImportSceneByName(dir_, "quad", limits), kResourceExhausted,
               "name: 'quad.gltf' has");
}

}  // namespace scene_uri_test
}  // namespace gistream
