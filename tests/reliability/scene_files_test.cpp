// Issue 13, finding 4 (wedged): a FIFO named as environment_name blocked a
// worker forever. Only regular files are opened from the scene directory,
// without blocking.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <future>

#include "reliability/reliability_fixture.h"
#include "support/render_helpers.h"

namespace gistream::reliability {
namespace scene_files_test {

// Runs `load` on another thread; a load that blocks longer than a minute is
// a failure, and writing to the FIFO then unblocks it so the binary exits.
void ExpectRefusedWithoutBlocking(const SceneSource& source, const std::string& fifo,
                                  const std::string& expected) {
  auto result = std::async(std::launch::async, [source] { return E().LoadScene(source); });
  if (result.wait_for(std::chrono::seconds(60)) != std::future_status::ready) {
    ADD_FAILURE() << "LoadScene blocked on FIFO " << fifo;
    const int fd = ::open((SceneDir() / fifo).c_str(), O_WRONLY | O_NONBLOCK);
    if (fd >= 0) ::close(fd);
  }
  EXPECT_STATUS(StatusOf(result.get()), kInvalidArgument, expected);
}

TEST(SceneFiles, FifoEnvironmentIsRefusedWithoutBlocking) {
  SceneSource source;
  source.name = "quad";
  source.environment_name = "fifo_env.hdr";
  ExpectRefusedWithoutBlocking(source, "fifo_env.hdr",
                               "environment_name: 'fifo_env.hdr' is not a regular file");
}

TEST(SceneFiles, FifoSceneAndFifoBufferAreRefusedWithoutBlocking) {
  ExpectRefusedWithoutBlocking(testing::SceneByName("fifo_scene"), "fifo_scene.gltf",
                               "name: 'fifo_scene.gltf' is not a regular file");
  ExpectRefusedWithoutBlocking(testing::SceneByName("external_fifo"), "fifo.bin",
                               "buffers[0].uri: 'fifo.bin'");
  // The server still loads and renders a regular scene from the directory.
  auto info = E().LoadScene(testing::SceneByName("quad"));
  ASSERT_TRUE(info.ok()) << info.status();
  ExpectRendersFinite(info->id, "direct");
  EXPECT_TRUE(E().UnloadScene(info->id).ok());
}

}  // namespace scene_files_test
}  // namespace gistream::reliability
