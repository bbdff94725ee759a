// External URIs: only names inside the scene directory, never "..", never
// absolute paths, never without a scene directory.
#include <filesystem>
#include <fstream>

#include "unit/gltf_test_util.h"

namespace gistream {
namespace external_uri_test {

using testing::TestGltf;

class ExternalUri : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("gistream_uri_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_ / "scene");
    g_.AddRoot({{"mesh", testing::AddQuadMesh(&g_)}});
    // The quad's buffer as an external file next to the scene, and a
    // "secret" outside the scene directory.
    WriteFile(dir_ / "scene" / "quad.bin", g_.bin);
    WriteFile(dir_ / "secret.bin", g_.bin);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  static void WriteFile(const std::filesystem::path& p, const std::vector<uint8_t>& bytes) {
    std::ofstream(p, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  }
  std::vector<uint8_t> WithUri(const std::string& uri) {
    nlohmann::json d = g_.doc;
    d["buffers"] = {{{"byteLength", g_.bin.size()}, {"uri", uri}}};
    return testing::Bytes(d.dump());
  }
  ImportOptions InScene() const {
    ImportOptions o;
    o.base_dir = dir_ / "scene";
    return o;
  }

  std::filesystem::path dir_;
  TestGltf g_;
};

TEST_F(ExternalUri, InsideSceneDirectoryIsAccepted) {
  auto scene = testing::Import(WithUri("quad.bin"), InScene());
  ASSERT_TRUE(scene.ok()) << scene.status();
  EXPECT_EQ(scene->triangle_count, 2u);
}

TEST_F(ExternalUri, ParentDirectoryIsRefused) {
  EXPECT_ERROR(testing::Import(WithUri("../secret.bin"), InScene()), kInvalidArgument, "buffers");
  EXPECT_ERROR(testing::Import(WithUri("../secret.bin"), InScene()), kInvalidArgument, "..");
}

TEST_F(ExternalUri, AbsolutePathIsRefused) {
  EXPECT_ERROR(testing::Import(WithUri("/etc/passwd"), InScene()), kInvalidArgument, "buffers");
  EXPECT_ERROR(testing::Import(WithUri((dir_ / "secret.bin").string()), InScene()),
               kInvalidArgument, "absolute");
}

TEST_F(ExternalUri, SymlinkLeavingTheDirectoryIsRefused) {
  std::filesystem::create_symlink(dir_ / "secret.bin", dir_ / "scene" / "link.bin");
  EXPECT_ERROR(testing::Import(WithUri("link.bin"), InScene()), kInvalidArgument, "buffers");
}

TEST_F(ExternalUri, UploadsMayNotNameFilesAtAll) {
  // An upload (no scene directory) must be self-contained.
  EXPECT_ERROR(testing::Import(WithUri("quad.bin")), kInvalidArgument, "buffers");
}

TEST(ResolveSceneUri, NamesTheField) {
  auto r = ResolveSceneUri("/tmp", "../x", "images[2].uri");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(std::string(r.status().message()).find("images[2].uri"), std::string::npos)
      << r.status();
}

}  // namespace external_uri_test
}  // namespace gistream
