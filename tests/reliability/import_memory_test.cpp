// Issue 13, finding 2 (unbounded memory), import part: what an import reads
// and decodes is reserved from the server's memory budget before it is
// decoded (scene/gltf/import_memory.h): an image whose file is small but whose
// pixels are not is refused from its header, naming it, and nothing stays
// reserved.
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "encode/encode.h"
#include "reliability/reliability_fixture.h"
#include "support/render_helpers.h"

namespace gistream::reliability {
namespace import_memory_test {

using namespace std::chrono_literals;

TEST(ImportMemory, DecodedPixelsAreReservedBeforeDecoding) {
  EngineOptions options;
  options.scene_dir = SceneDir();
  options.max_memory_bytes = 2ull << 20;
  auto engine = Engine::Create(options);
  ASSERT_TRUE(engine.ok()) << engine.status();  // GL tests never skip
  Engine& e = **engine;

  // 512 x 512 float RGBA decodes to 4 MiB; the zip-compressed file of one
  // colour is a few KiB.
  const std::vector<float> rgba(512 * 512 * 4, 0.5f);
  auto exr = EncodeExr(rgba, 512, 512);
  ASSERT_TRUE(exr.ok()) << exr.status();
  ASSERT_LT(exr->size(), 256u << 10);
  SceneSource source = testing::SceneFromBytes(QuadScene().dump());
  source.environment_bytes = *exr;
  EXPECT_STATUS(StatusOf(e.LoadScene(source)), kResourceExhausted,
                "environment: 512x512 decoded pixels needs 4.0 MiB, more than the ");
  EXPECT_STATUS(StatusOf(e.LoadScene(source)), kResourceExhausted, "--max-memory-bytes 2.0 MiB");
  EXPECT_EQ(e.stats().memory_used_bytes, 0u) << "a refused import holds nothing";

  // The same scene without it fits, and gives its bytes back when unloaded.
  auto plain = e.LoadScene(testing::SceneFromBytes(QuadScene().dump()));
  ASSERT_TRUE(plain.ok()) << plain.status();
  EXPECT_GT(e.stats().memory_used_bytes, 0u);
  ASSERT_TRUE(e.UnloadScene(plain->id).ok());
  for (int i = 0; i < 1000 && e.stats().memory_used_bytes != 0; ++i) {
    std::this_thread::sleep_for(10ms);  // the GPU copy is freed on the render thread
  }
  EXPECT_EQ(e.stats().memory_used_bytes, 0u);
  e.Shutdown();
}

}  // namespace import_memory_test
}  // namespace gistream::reliability
