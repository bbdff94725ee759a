// Scene arguments: local file (uploaded, .gltf resources inlined) or a
// name on the server (client/scene_loader.h). No network.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "scene_loader.h"

namespace gistream::client {
namespace scene_loader_test {

namespace fs = std::filesystem;

class SceneLoaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("gistream_scene_loader_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_ / "textures");
  }
  void TearDown() override { fs::remove_all(dir_); }

  void Write(const fs::path& relative, const std::string& bytes) {
    std::ofstream(dir_ / relative, std::ios::binary) << bytes;
  }

  fs::path dir_;
};

TEST_F(SceneLoaderTest, NameWhenNoSuchFile) {
  auto request = BuildLoadSceneRequest({.scene = "cornell_box",
                                        .environment = "sky.hdr",
                                        .environment_intensity = 2.0f,
                                        .keep_scene = false});
  ASSERT_TRUE(request.ok()) << request.status();
  EXPECT_EQ(request->name(), "cornell_box");
  EXPECT_EQ(request->environment_name(), "sky.hdr");
  EXPECT_FLOAT_EQ(request->environment_intensity(), 2.0f);
}

TEST_F(SceneLoaderTest, GlbFileIsUploadedAsIs) {
  Write("box.glb", std::string("glTF\x02\0\0\0", 8));
  SceneOptions scene;
  scene.scene = (dir_ / "box.glb").string();
  auto request = BuildLoadSceneRequest(scene);
  ASSERT_TRUE(request.ok()) << request.status();
  EXPECT_EQ(request->gltf(), std::string("glTF\x02\0\0\0", 8));
  EXPECT_EQ(request->environment_case(), v1::LoadSceneRequest::ENVIRONMENT_NOT_SET);
}

TEST_F(SceneLoaderTest, RelativeToBaseDir) {
  Write("env.hdr", "#?RADIANCE");
  Write("scene.glb", "glTF");
  SceneOptions scene;
  scene.scene = "scene.glb";
  scene.environment = "env.hdr";
  auto request = BuildLoadSceneRequest(scene, dir_);
  ASSERT_TRUE(request.ok()) << request.status();
  EXPECT_EQ(request->gltf(), "glTF");
  EXPECT_EQ(request->environment_image(), "#?RADIANCE");
}

TEST_F(SceneLoaderTest, GltfExternalResourcesAreInlined) {
  Write("mesh.bin", "abc");
  Write("textures/my tex.png", "PNG!");
  Write("scene.gltf", R"({"asset": {"version": "2.0"},
      "buffers": [{"uri": "mesh.bin", "byteLength": 3},
                  {"uri": "data:application/octet-stream;base64,AAAA", "byteLength": 3}],
      "images": [{"uri": "textures/my%20tex.png"}]})");
  SceneOptions scene;
  scene.scene = (dir_ / "scene.gltf").string();
  auto request = BuildLoadSceneRequest(scene);
  ASSERT_TRUE(request.ok()) << request.status();
  const auto gltf = nlohmann::json::parse(request->gltf());
  EXPECT_EQ(gltf["buffers"][0]["uri"], "data:application/octet-stream;base64,YWJj");
  EXPECT_EQ(gltf["buffers"][1]["uri"], "data:application/octet-stream;base64,AAAA");
  EXPECT_EQ(gltf["images"][0]["uri"], "data:image/png;base64,UE5HIQ==");
  EXPECT_EQ(gltf["asset"]["version"], "2.0");
}

TEST_F(SceneLoaderTest, SelfContainedGltfIsUnchanged) {
  const std::string text = R"({"buffers": [{"uri": "data:application/octet-stream;base64,AA"}]})";
  auto inlined = InlineGltfResources(text, dir_, "x.gltf");
  ASSERT_TRUE(inlined.ok()) << inlined.status();
  EXPECT_EQ(*inlined, text);
}

TEST_F(SceneLoaderTest, InlineErrorsNameTheUri) {
  auto missing = InlineGltfResources(R"({"buffers": [{"uri": "gone.bin"}]})", dir_, "x.gltf");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(std::string(missing.status().message()).find("x.gltf: buffers[0].uri \"gone.bin\""),
            std::string::npos);
  auto remote =
      InlineGltfResources(R"({"images": [{"uri": "https://example.com/a.png"}]})", dir_, "x.gltf");
  ASSERT_FALSE(remote.ok());
  EXPECT_EQ(remote.status().message(),
            "x.gltf: images[0].uri \"https://example.com/a.png\": only files relative to the "
            "glTF can be inlined");
  auto not_json = InlineGltfResources("glTF binary?", dir_, "x.gltf");
  ASSERT_FALSE(not_json.ok());
  EXPECT_EQ(not_json.status().message(), "x.gltf: not a glTF JSON document");
}

// A load the server's --max-load-seconds cut says so (issue 19); a full
// one says nothing of it.
TEST(DescribeScene, SaysWhenTheServerSkippedProxies) {
  v1::LoadSceneResponse info;
  info.set_scene_id("x64-1");
  info.set_triangle_count(414728);
  EXPECT_EQ(DescribeScene("x64", info).find("max-load-seconds"), std::string::npos);
  info.set_proxy_trees_skipped(7);
  info.set_proxy_levels_skipped(2);
  EXPECT_NE(DescribeScene("x64", info)
                .find("past the server's --max-load-seconds: 7 primitive(s) without proxy "
                      "trees, 2 with fewer levels"),
            std::string::npos)
      << DescribeScene("x64", info);
}

// The glTF extensions the server rendered without are named (issue 29).
TEST(DescribeScene, NamesTheIgnoredExtensions) {
  v1::LoadSceneResponse info;
  info.set_scene_id("box-1");
  EXPECT_EQ(DescribeScene("box", info).find("ignored"), std::string::npos);
  info.add_ignored_extensions("KHR_materials_ior");
  info.add_ignored_extensions("KHR_materials_specular");
  EXPECT_NE(DescribeScene("box", info)
                .find("\nignored glTF extensions (rendered without them): KHR_materials_ior, "
                      "KHR_materials_specular"),
            std::string::npos)
      << DescribeScene("box", info);
  // The import's warnings, one line each, after the extensions.
  info.add_lights()->set_name("sun");
  info.add_import_warnings("materials[0].emissiveTexture.texCoord: 1: only TEXCOORD_0 is read");
  const std::vector<std::string> warnings = SceneWarnings(info);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[1], "materials[0].emissiveTexture.texCoord: 1: only TEXCOORD_0 is read");
}

// A scene with no light at all renders black in every solver: the user
// is told so (issue 29: never a silent black frame), and not when any of
// a punctual light, an emissive surface or an environment is there.
TEST(DescribeScene, SaysWhenTheSceneHasNoLight) {
  v1::LoadSceneResponse info;
  info.set_scene_id("box-1");
  ASSERT_EQ(SceneWarnings(info).size(), 1u);
  EXPECT_NE(SceneWarnings(info)[0].find("no light"), std::string::npos);
  EXPECT_NE(DescribeScene("box", info).find("\nno light: "), std::string::npos);
  v1::LoadSceneResponse lit = info;
  lit.add_lights()->set_name("sun");
  EXPECT_TRUE(SceneWarnings(lit).empty());
  v1::LoadSceneResponse emissive = info;
  emissive.set_emissive_triangle_count(2);
  EXPECT_TRUE(SceneWarnings(emissive).empty());
  v1::LoadSceneResponse sky = info;
  sky.set_has_environment(true);
  EXPECT_TRUE(SceneWarnings(sky).empty());
}

}  // namespace scene_loader_test
}  // namespace gistream::client
