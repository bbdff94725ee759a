#include "scene/gltf/load_control.h"

namespace gistream {

absl::Status LoadControl::Check(const std::string& stage) const {
  if (!stop) return absl::OkStatus();
  const absl::Status status = stop();
  if (status.ok()) return status;
  return absl::Status(status.code(), absl::StrCat(stage, ": ", status.message()));
}

}  // namespace gistream
