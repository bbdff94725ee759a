#include "support/render_helpers.h"

#include <cmath>

#include <gtest/gtest.h>

namespace gistream::testing {

Engine& SharedEngine() {
  static std::unique_ptr<Engine> engine = [] {
    EngineOptions options;
    options.scene_dir = std::string(GISTREAM_SOURCE_DIR) + "/scenes";
    auto created = Engine::Create(options);
    if (!created.ok()) {
      ADD_FAILURE() << "Engine::Create: " << created.status();
      std::abort();
    }
    return std::move(created).value();
  }();
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
  auto decoded = DecodeImageBytes(
      {reinterpret_cast<const uint8_t*>(frame.image.data()), frame.image.size()});
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
  auto frame = engine.Render(request);
  EXPECT_TRUE(frame.ok()) << frame.status();
  if (!frame.ok()) return {};
  if (frame_out) *frame_out = *frame;
  return DecodeExr(*frame);
}

}  // namespace gistream::testing
