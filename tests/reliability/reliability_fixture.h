// Shared by the reliability tests (issue 13, "Hostile input and faults"):
// each test reproduces one finding against a real Engine (EGL; llvmpipe
// without a GPU) and shows it fixed: the call answers a status naming the
// field, the engine stays up, and the next normal render works. Images are
// 16 x 16 to keep llvmpipe quick.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/engine.h"

namespace gistream::reliability {

#define EXPECT_STATUS(expr, expected_code, text)                               \
  do {                                                                         \
    const absl::Status _s = (expr);                                            \
    EXPECT_EQ(_s.code(), absl::StatusCode::expected_code) << _s;               \
    EXPECT_NE(std::string(_s.message()).find(text), std::string::npos)         \
        << "message: " << _s.message() << "\nexpected to contain: " << (text); \
  } while (0)

template <typename T>
absl::Status StatusOf(const absl::StatusOr<T>& s) {
  return s.status();
}
inline absl::Status StatusOf(const absl::Status& s) { return s; }

// A floor quad (node 0, material 0, white), an emissive quad above it
// (material 1), a point light and a camera looking down at the floor.
nlohmann::json QuadScene();

// The engine shared by the binary. Its scene directory (SceneDir()) holds
// quad.gltf and FIFOs: fifo_env.hdr, fifo_scene.gltf, fifo.bin (the buffer
// of external_fifo.gltf); it is removed when the tests end.
Engine& E();
const std::filesystem::path& SceneDir();

// A private copy of a scene (default: QuadScene()), loaded as bytes and
// unloaded at the end of the test.
class QuadCopy {
 public:
  explicit QuadCopy(const nlohmann::json& doc = QuadScene());
  ~QuadCopy();
  QuadCopy(const QuadCopy&) = delete;
  QuadCopy& operator=(const QuadCopy&) = delete;
  const std::string& id() const { return id_; }

 private:
  std::string id_;
};

// A 16 x 16 EXR Render request.
RenderRequest Request(const std::string& scene, const std::string& solver,
                      std::vector<Update> updates = {},
                      std::map<std::string, std::string> params = {});
inline Update U(Change change, uint64_t seq = 1) { return Update{seq, std::move(change)}; }

// The next normal render works: finite, and the lit floor is not black.
void ExpectRendersFinite(const std::string& scene, const std::string& solver);

// Resets this process's peak RSS (VmHWM, via /proc/self/clear_refs); false
// when the kernel does not allow it.
bool ResetPeakRss();
// A "Key:   N kB" line of /proc/self/status, in KiB (0 when absent).
uint64_t StatusKiB(const std::string& key);

}  // namespace gistream::reliability
