#include "engine/scene_import.h"

#include <span>
#include <string>
#include <vector>

#include <absl/strings/str_cat.h>

#include "scene/environment_cut.h"
#include "scene/gltf/gltf_import.h"
#include "scene/gltf/image_decode.h"
#include "scene/magnitude_limits.h"
#include "scene/gltf/scene_files.h"
#include "util/log.h"

namespace gistream {
namespace {

std::span<const uint8_t> Bytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

// The environment map: a file in the scene directory or uploaded bytes,
// decoded and bounded (its brightest pixel times the intensity).
absl::StatusOr<Environment> ImportEnvironment(const SceneSource& source,
                                              const std::filesystem::path& scene_dir,
                                              const ImportLimits& limits, ImportMemory& transient) {
  std::vector<uint8_t> env_file;
  std::span<const uint8_t> env_bytes = Bytes(source.environment_bytes);
  if (!source.environment_name.empty()) {
    GS_ASSIGN_OR_RETURN(std::filesystem::path path,
                        ResolveSceneUri(scene_dir, source.environment_name, "environment_name"));
    // A regular file only, opened without blocking (a FIFO would wedge
    // this thread), and no larger than a scene may be.
    GS_ASSIGN_OR_RETURN(env_file,
                        ReadFileLimited(path, limits.max_scene_bytes, "environment_name"));
    GS_RETURN_IF_ERROR(transient.Reserve(
        env_file.size(), absl::StrCat("environment_name: ", env_file.size(), " bytes read")));
    env_bytes = env_file;
  }
  Environment env;
  GS_ASSIGN_OR_RETURN(env.image, DecodeImage(env_bytes, ImageKind::kEnvironment, limits,
                                             "environment", &transient));
  env.intensity = source.environment_intensity > 0.0f ? source.environment_intensity : 1.0f;
  env.max_radiance = MaxPixel(env.image);
  env.light_cut = MedianCutEnvironment(env.image, kEnvironmentLightCount);
  if (env.intensity * env.max_radiance > kMaxRadiance) {
    return absl::InvalidArgumentError(
        absl::StrCat("environment_intensity: ", env.intensity, " x the map's brightest pixel ",
                     env.max_radiance, " exceeds the limit of ", kMaxRadiance, " nits"));
  }
  return env;
}

}  // namespace

absl::StatusOr<ImportedScene> ImportSceneSource(const SceneSource& source,
                                                const std::filesystem::path& scene_dir,
                                                const ImportLimits& limits,
                                                std::chrono::milliseconds max_load_time,
                                                ImportMemory& transient) {
  LoadControl control;
  control.optional_deadline = LoadControl::Clock::now() + max_load_time;
  control.stop = source.stop;
  ImportedScene out;
  if (!source.name.empty()) {
    GS_ASSIGN_OR_RETURN(out.scene, ImportSceneByName(scene_dir, source.name, limits, &transient,
                                                     &control, &out.proxies));
  } else {
    ImportOptions import;
    import.limits = limits;
    import.name = "upload";
    import.memory = &transient;
    import.control = &control;
    import.proxy_report = &out.proxies;
    GS_ASSIGN_OR_RETURN(out.scene, ImportGltf(Bytes(source.bytes), import));
  }
  if (out.proxies.trees_skipped + out.proxies.levels_skipped > 0) {
    Log(LogLevel::kInfo,
        absl::StrCat("load: the proxies ran past --max-load-seconds (",
                     max_load_time.count() / 1000.0, " s): ", out.proxies.trees_skipped,
                     " primitive(s) without their cluster trees, ", out.proxies.levels_skipped,
                     " with levels cut short; they draw coarser levels or the full mesh"));
  }
  if (!source.environment_name.empty() || !source.environment_bytes.empty()) {
    GS_ASSIGN_OR_RETURN(out.scene.environment,
                        ImportEnvironment(source, scene_dir, limits, transient));
  }
  GS_RETURN_IF_ERROR(control.Check("load: before the upload"));
  return out;
}

}  // namespace gistream
