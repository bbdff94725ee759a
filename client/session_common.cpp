#include "session_common.h"

#include <absl/strings/cord.h>
#include <absl/strings/str_cat.h>
#include <absl/strings/str_format.h>
#include <absl/strings/str_join.h>

#include "commands.h"
#include "image_format.h"
#include "util/log.h"

namespace gistream::client {
namespace {
constexpr absl::string_view kInterruptedPayload = "gistream.client/interrupted";
}  // namespace

absl::Status InterruptedError() {
  absl::Status status = absl::CancelledError("interrupted: the session was cancelled");
  status.SetPayload(kInterruptedPayload, absl::Cord("1"));
  return status;
}

bool IsInterrupted(const absl::Status& status) {
  return status.GetPayload(kInterruptedPayload).has_value();
}

v1::SessionConfig ContinuousConfig(const std::string& scene_id, const SolverOptions& solver,
                                   const ViewOptions& view, float max_fps) {
  v1::SessionConfig config;
  config.set_scene_id(scene_id);
  config.set_solver(solver.solver);
  config.mutable_params()->insert(solver.params.begin(), solver.params.end());
  config.set_width(view.width);
  config.set_height(view.height);
  *config.mutable_encoding() = view.encoding;
  config.set_refine_samples(view.refine_samples);
  config.mutable_continuous()->set_max_fps(max_fps);
  if (view.camera.ByteSizeLong() > 0) *config.mutable_camera() = view.camera;
  return config;
}

double FrameStatValue(const v1::Frame& frame, const std::string& name) {
  const auto it = frame.stats().find(name);
  return it == frame.stats().end() ? 0.0 : it->second;
}

std::string FormatConvergence(const v1::Frame& last) {
  std::vector<std::string> parts;
  const auto has = [&](const char* name) { return last.stats().contains(name); };
  if (has("refine_target") && FrameStatValue(last, "refine_target") > 1.0) {
    parts.push_back(absl::StrCat("refined ", FrameStatValue(last, "refine_samples"), "/",
                                 FrameStatValue(last, "refine_target"), " samples per pixel"));
  }
  if (FrameStatValue(last, "refine_carry") > 0.0) parts.push_back("anti-aliasing carried");
  if (FrameStatValue(last, "refine_reproject") > 0.0) parts.push_back("last picture reprojected");
  if (has("spp_total")) parts.push_back(absl::StrCat(FrameStatValue(last, "spp_total"), " spp"));
  if (has("update_complete")) {
    parts.push_back(FrameStatValue(last, "update_complete") == 1.0 ? "GI complete"
                                                                   : "GI still solving");
  }
  if (FrameStatValue(last, "at_rest") == 1.0) parts.push_back("at rest");
  std::string line =
      absl::StrCat("last picture: ", parts.empty() ? "-" : absl::StrJoin(parts, ", "));
  const auto seconds = [&](const char* name) {
    return absl::StrFormat("%.1f", FrameStatValue(last, name) / 1000.0);
  };
  if (has("ms_since_camera_change") && has("ms_since_scene_change")) {
    absl::StrAppend(&line, "; ", seconds("ms_since_camera_change"), " s since the camera moved, ",
                    seconds("ms_since_scene_change"), " s since the scene changed");
  }
  return line;
}

std::string FormatWrittenFrames(const FrameWriter& writer, uint64_t count, v1::ImageFormat format,
                                std::optional<uint64_t> pictures) {
  if (count == 0) return absl::StrCat("wrote no frames to ", writer.dir().string());
  if (IsVideoFormat(format)) {
    // A video stream holds the frames that carried a picture; the others
    // (unchanged, keep-alives) are the decoder's last picture shown on.
    const uint64_t encoded = pictures.value_or(count);
    return absl::StrCat("wrote ", encoded, encoded == 1 ? " picture" : " pictures", " to ",
                        writer.PathFor(0, format).string(), " (", count,
                        count == 1 ? " frame" : " frames", " received)");
  }
  return absl::StrCat(
      "wrote ", count, count == 1 ? " frame" : " frames", " to ", writer.dir().string(), " (",
      writer.PathFor(0, format).filename().string(),
      count > 1 ? absl::StrCat(" .. ", writer.PathFor(count - 1, format).filename().string()) : "",
      ")");
}

std::string DescribeUpdate(const v1::Update& update) {
  switch (update.change_case()) {
    case v1::Update::kNodeTransform:
      return absl::StrCat("node_transform (node ", update.node_transform().node(), ")");
    case v1::Update::kLight: return absl::StrCat("light (light ", update.light().light(), ")");
    case v1::Update::kCamera: return "camera";
    case v1::Update::kMaterial:
      return absl::StrCat("material (material ", update.material().material(), ")");
    case v1::Update::kEnvironment: return "environment";
    case v1::Update::kAnimation:
      return update.animation().which_case() == v1::AnimationChange::kName
                 ? absl::StrCat("animation (", update.animation().name(), ")")
                 : absl::StrCat("animation (animation ", update.animation().animation(), ")");
    case v1::Update::kMorphWeights:
      return absl::StrCat("morph_weights (node ", update.morph_weights().node(), ")");
    case v1::Update::CHANGE_NOT_SET: break;
  }
  return "empty update";
}

}  // namespace gistream::client
