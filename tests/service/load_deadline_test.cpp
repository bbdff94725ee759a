// A LoadScene whose client deadline passes while the server builds the
// scene's proxies (issue 19, scene/gltf/load_control.h): the gRPC handler turns
// the cancelled call into a stop, and the load ends with DEADLINE_EXCEEDED
// at its next slice instead of running to the end; the engine keeps
// nothing. Real engine (EGL; llvmpipe without a GPU).
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "test_server.h"

namespace gistream::testing {
namespace load_deadline_test {

using namespace std::chrono_literals;

class FailedCalls final : public ServerObserver {
 public:
  void OnRpcFailed(std::string_view method, absl::StatusCode code) override {
    std::lock_guard lock(mutex_);
    failed_.emplace_back(std::string(method), code);
  }
  std::vector<std::pair<std::string, absl::StatusCode>> failed() const {
    std::lock_guard lock(mutex_);
    return failed_;
  }

 private:
  mutable std::mutex mutex_;
  std::vector<std::pair<std::string, absl::StatusCode>> failed_;
};

// A flat floor of n x n quads (2 n^2 triangles) as floor.gltf + floor.bin in
// `dir`: its proxy levels and cluster tree take seconds to build at n = 400.
void WriteFloor(const std::filesystem::path& dir, int n) {
  std::vector<float> positions;
  std::vector<uint32_t> indices;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      positions.insert(positions.end(), {float(i) / float(n), 0.0f, float(j) / float(n)});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
      indices.insert(indices.end(), {a, c, d, a, d, b});
    }
  }
  const size_t pos_bytes = positions.size() * 4, idx_bytes = indices.size() * 4;
  std::ofstream bin(dir / "floor.bin", std::ios::binary);
  bin.write(reinterpret_cast<const char*>(positions.data()), std::streamsize(pos_bytes));
  bin.write(reinterpret_cast<const char*>(indices.data()), std::streamsize(idx_bytes));
  bin.close();
  std::ofstream(dir / "floor.gltf") << absl::StrCat(
      R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)",
      R"("nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)",
      R"("buffers":[{"uri":"floor.bin","byteLength":)", pos_bytes + idx_bytes, "}],",
      R"("bufferViews":[{"buffer":0,"byteLength":)", pos_bytes, R"(},{"buffer":0,"byteOffset":)",
      pos_bytes, R"(,"byteLength":)", idx_bytes, "}],",
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":)", positions.size() / 3,
      R"(,"type":"VEC3","min":[0,0,0],"max":[1,0,1]},)",
      R"({"bufferView":1,"componentType":5125,"count":)", indices.size(), R"(,"type":"SCALAR"}]})");
}

TEST(LoadDeadline, PassedClientDeadlineStopsTheLoad) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / absl::StrCat("load_deadline_", getpid());
  std::filesystem::create_directories(dir);
  WriteFloor(dir, 400);  // 320,000 triangles
  EngineOptions options;
  options.scene_dir = dir;
  absl::StatusOr<std::unique_ptr<Engine>> engine = Engine::Create(options);
  ASSERT_TRUE(engine.ok()) << engine.status();  // GL tests never skip
  auto failed = std::make_shared<FailedCalls>();
  service::ServerOptions server_options;
  server_options.service.observer = failed;
  {
    TestServer server(**engine, server_options);
    grpc::ClientContext context;
    SetDeadline(&context, 300ms);
    pb::LoadSceneRequest request;
    request.set_name("floor");
    pb::LoadSceneResponse response;
    const grpc::Status status = server.stub().LoadScene(&context, request, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::DEADLINE_EXCEEDED) << status.error_message();
    // The server's own answer: the load stopped at a slice with the
    // deadline's code (a load run to its end would have answered OK).
    EXPECT_TRUE(WaitFor([&] { return !failed->failed().empty(); }, 60s));
    const auto calls = failed->failed();
    ASSERT_EQ(calls.size(), 1u);
    EXPECT_EQ(calls[0].first, "LoadScene");
    EXPECT_EQ(calls[0].second, absl::StatusCode::kDeadlineExceeded);
    EXPECT_EQ((*engine)->stats().scenes, 0u);
    EXPECT_EQ((*engine)->stats().memory_used_bytes, 0u);
  }  // the server shuts the engine down
  std::filesystem::remove_all(dir);
}

}  // namespace load_deadline_test
}  // namespace gistream::testing
