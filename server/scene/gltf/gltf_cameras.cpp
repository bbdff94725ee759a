#include <numbers>
#include <string>

#include "scene/gltf/gltf_stages.h"
#include "scene/gltf/gltf_util.h"
#include "scene/magnitude_limits.h"
#include "util/log.h"

namespace gistream::gltf {

absl::StatusOr<std::vector<Camera>> ImportCameras(const tinygltf::Model& model,
                                                  std::vector<int>* camera_map) {
  std::vector<Camera> cameras;
  camera_map->assign(model.cameras.size(), -1);
  for (size_t i = 0; i < model.cameras.size(); ++i) {
    const tinygltf::Camera& in = model.cameras[i];
    const std::string field = Item("cameras", i);
    if (in.type == "orthographic") {
      LogOnce(LogLevel::kWarning, "gltf-orthographic-camera",
              absl::StrCat(field, ": orthographic cameras are not supported; skipped"));
      continue;
    }
    if (in.type != "perspective") {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ".type: '", in.type, "' is not perspective or orthographic"));
    }
    const tinygltf::PerspectiveCamera& p = in.perspective;
    const double min_yfov = kMinYfovDegrees * std::numbers::pi / 180.0;
    const double max_yfov = kMaxYfovDegrees * std::numbers::pi / 180.0;
    if (!(p.yfov >= min_yfov && p.yfov <= max_yfov)) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".perspective.yfov: ", p.yfov,
                                                     " is out of range [", min_yfov, ", ", max_yfov,
                                                     "] radians"));
    }
    // Clip distances are positions along the view ray: within the world
    // extent limit (and its diagonal for zfar) like every other distance.
    const double max_far = 4.0 * double(kMaxCoordinate);
    if (!(p.znear > 0.0 && p.znear <= double(kMaxCoordinate))) {
      return absl::InvalidArgumentError(absl::StrCat(
          field, ".perspective.znear: ", p.znear, " is out of range (0, ", kMaxCoordinate, "] m"));
    }
    if (!(p.zfar == 0.0 || (p.zfar > p.znear && p.zfar <= max_far))) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".perspective.zfar: ", p.zfar,
                                                     " must be 0 (infinite) or beyond znear ",
                                                     p.znear, " and at most ", max_far, " m"));
    }
    Camera camera;
    camera.name = in.name;
    camera.yfov = static_cast<float>(p.yfov);
    camera.znear = static_cast<float>(p.znear);
    camera.zfar = static_cast<float>(p.zfar);
    (*camera_map)[i] = static_cast<int>(cameras.size());
    cameras.push_back(std::move(camera));
  }
  return cameras;
}

}  // namespace gistream::gltf
