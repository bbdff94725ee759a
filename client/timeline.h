// A parsed script bound to a loaded scene: names resolved to ids, and the
// updates each frame needs. A track's update is sent on frame 0 and then
// only on frames where its value changes; a frame's events follow its
// track updates in file order.
#pragma once

#include <functional>
#include <vector>

#include "gistream/v1/gistream.pb.h"
#include "script.h"
#include "util/status.h"

namespace gistream::client {

class Timeline {
 public:
  // Resolves every node, light and material the script names (by name or
  // id) against `scene`; unknown or ambiguous names are errors here, before
  // a session opens. Errors name the JSON path.
  static absl::StatusOr<Timeline> Build(const Script& script, const v1::LoadSceneResponse& scene);

  int frames() const { return frames_; }

  // The updates for `frame` (0 <= frame < frames()); seq left 0.
  std::vector<v1::Update> UpdatesForFrame(int frame) const;

 private:
  using Channel = std::function<v1::Update(int frame)>;

  int frames_ = 0;
  std::vector<Channel> channels_;                // one per animated thing
  std::vector<std::vector<v1::Update>> events_;  // per frame
};

}  // namespace gistream::client
