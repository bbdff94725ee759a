// Validation of client updates before they reach the render thread: ids in
// range, every number finite, values in their ranges and within the
// magnitude limits of scene/magnitude_limits.h (limits that depend on the
// scene's current state are SceneState::CheckApply's). Messages name the
// field ("update.node_transform.translation.y: nan is not finite").
#pragma once

#include <cstdint>

#include "scene/scene.h"
#include "scene/updates.h"
#include "util/status.h"

namespace gistream {

// INVALID_ARGUMENT when `update` cannot be applied to `scene`; a resize
// must fit in max_width x max_height.
absl::Status ValidateUpdate(const Scene& scene, const Update& update, uint32_t max_width,
                            uint32_t max_height);

}  // namespace gistream
