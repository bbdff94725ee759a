// What bounds a scene load's time (issue 19): the optional work (proxy
// levels and cluster trees, scene/proxies/proxy_levels.h) stops at a deadline and
// the scene loads without what is left; a caller that is gone stops the
// whole load between slices. The domain layer sees plain callables: the
// service translates the gRPC call's state into them.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

#include "util/status.h"

namespace gistream {

struct LoadControl {
  using Clock = std::chrono::steady_clock;
  // The proxy levels and cluster trees are built until this time; the
  // primitives left keep fewer (or no) proxies: the passes then draw their
  // coarsest levels or the full mesh, as for small primitives.
  Clock::time_point optional_deadline = Clock::time_point::max();
  // Polled between slices (a primitive's level, a cluster node): non-OK
  // (CANCELLED, DEADLINE_EXCEEDED) stops the load with that code; the
  // message is prefixed with the stage. Empty: never stops.
  std::function<absl::Status()> stop;

  bool OptionalTimeLeft() const { return Clock::now() < optional_deadline; }
  // OK, or `stop`'s status with "<stage>: " in front of its message.
  absl::Status Check(const std::string& stage) const;
};

// What the optional work got done.
struct ProxyReport {
  uint32_t primitives_with_levels = 0;
  uint32_t primitives_with_trees = 0;
  // Primitives that would have had levels / a tree but the optional
  // deadline came first.
  uint32_t levels_skipped = 0;
  uint32_t trees_skipped = 0;
  double seconds = 0.0;  // the levels and trees together
};

}  // namespace gistream
