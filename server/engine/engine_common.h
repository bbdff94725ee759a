// What EngineImpl's files (engine_impl.cpp and engine_*.cpp) share: the
// statuses its calls answer with, session and scene ids, and the clock.
// Internal to server/engine/.
#pragma once

#include <absl/status/status.h>
#include <absl/strings/str_cat.h>

#include <algorithm>
#include <random>
#include <string>
#include <string_view>

#include "engine/render_thread.h"
#include "scene/state/scene_state.h"

namespace gistream::engine_internal {

using Clock = RenderThread::Clock;

inline absl::Status Unavailable() { return absl::UnavailableError("server is shutting down"); }
inline absl::Status Draining() {
  return absl::UnavailableError(
      "server is draining: load the scene and open the session on another");
}
inline absl::Status GpuLost() {
  return absl::UnavailableError(
      "GPU reset: the render context was lost; the server is recovering, try again");
}

// "prefix-" and 128 random bits in hex: ids nobody can guess or enumerate.
inline std::string RandomId(std::string_view prefix) {
  std::random_device random;  // the kernel's CSPRNG (getrandom) on Linux
  std::string id = absl::StrCat(absl::string_view(prefix.data(), prefix.size()), "-");
  for (int i = 0; i < 4; ++i) absl::StrAppend(&id, absl::Hex(random(), absl::kZeroPad8));
  return id;
}

// How far a quota would be exceeded, as the message of RESOURCE_EXHAUSTED.
inline absl::Status QuotaExceeded(std::string_view tenant, std::string_view quota, uint64_t used,
                                  uint64_t adding, uint64_t limit) {
  return absl::ResourceExhaustedError(
      absl::StrCat("quota ", absl::string_view(quota.data(), quota.size()), " of tenant '",
                   absl::string_view(tenant.data(), tenant.size()), "': ", used, " held + ", adding,
                   " exceeds its limit of ", limit));
}

inline bool AnyAnimationPlaying(const SceneState& state) {
  return std::any_of(state.animations().begin(), state.animations().end(),
                     [](const AnimationPlayback& a) { return a.playing; });
}

}  // namespace gistream::engine_internal
