// What LoadScene reports about a scene in its current state.
#pragma once

#include "scene/state/scene_state.h"
#include "engine/engine.h"

namespace gistream {

SceneInfo DescribeScene(const SceneId& id, const SceneState& state);

}  // namespace gistream
