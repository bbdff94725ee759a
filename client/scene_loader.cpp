#include "scene_loader.h"

#include <algorithm>
#include <chrono>
#include <system_error>
#include <thread>

#include <absl/strings/ascii.h>
#include <absl/strings/escaping.h>
#include <absl/strings/match.h>
#include <absl/strings/str_cat.h>
#include <absl/strings/str_join.h>
#include <nlohmann/json.hpp>

#include "file_io.h"
#include "util/log.h"
#include "util/memory_budget.h"

namespace gistream::client {
namespace {

using nlohmann::json;

constexpr double kUnloadTimeoutSeconds = 10.0;

// glTF URIs are RFC 3986 references: "my%20texture.png" names
// "my texture.png". Malformed escapes are kept as written.
std::string PercentDecode(absl::string_view uri) {
  auto digit = [](char c) { return absl::ascii_isdigit(c) ? c - '0' : (c | 0x20) - 'a' + 10; };
  std::string out;
  out.reserve(uri.size());
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && absl::ascii_isxdigit(uri[i + 1]) &&
        absl::ascii_isxdigit(uri[i + 2])) {
      out += static_cast<char>(digit(uri[i + 1]) * 16 + digit(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

absl::string_view MimeType(const std::filesystem::path& file, bool image) {
  if (!image) return "application/octet-stream";
  const std::string ext = absl::AsciiStrToLower(file.extension().string());
  if (ext == ".png") return "image/png";
  if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
  return "application/octet-stream";
}

// Inlines `array[i].uri` for one of "buffers" / "images". Returns whether
// anything changed.
absl::StatusOr<bool> InlineArray(json& gltf, const char* array_name,
                                 const std::filesystem::path& dir, absl::string_view label) {
  auto array = gltf.find(array_name);
  if (array == gltf.end() || !array->is_array()) return false;
  bool changed = false;
  for (size_t i = 0; i < array->size(); ++i) {
    json& entry = (*array)[i];
    if (!entry.is_object() || !entry.contains("uri") || !entry["uri"].is_string()) continue;
    const std::string uri = entry["uri"].get<std::string>();
    if (absl::StartsWith(uri, "data:")) continue;
    const std::string where = absl::StrCat(label, ": ", array_name, "[", i, "].uri \"", uri, "\"");
    const std::filesystem::path relative = PercentDecode(uri);
    if (uri.find("://") != std::string::npos || relative.is_absolute()) {
      return absl::InvalidArgumentError(
          absl::StrCat(where, ": only files relative to the glTF can be inlined"));
    }
    auto bytes = ReadFile(dir / relative);
    if (!bytes.ok()) {
      return absl::Status(bytes.status().code(),
                          absl::StrCat(where, ": ", bytes.status().message()));
    }
    entry["uri"] =
        absl::StrCat("data:", MimeType(relative, array_name == absl::string_view("images")),
                     ";base64,", absl::Base64Escape(*bytes));
    changed = true;
  }
  return changed;
}

}  // namespace

std::optional<std::filesystem::path> FindLocalFile(absl::string_view argument,
                                                   const std::filesystem::path& base_dir) {
  if (argument.empty()) return std::nullopt;
  std::error_code ec;
  const std::filesystem::path path{std::string(argument)};
  if (std::filesystem::is_regular_file(path, ec)) return path;
  if (!base_dir.empty() && path.is_relative() &&
      std::filesystem::is_regular_file(base_dir / path, ec)) {
    return base_dir / path;
  }
  return std::nullopt;
}

absl::StatusOr<std::string> InlineGltfResources(absl::string_view text,
                                                const std::filesystem::path& dir,
                                                absl::string_view label) {
  json gltf = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (gltf.is_discarded() || !gltf.is_object()) {
    return absl::InvalidArgumentError(absl::StrCat(label, ": not a glTF JSON document"));
  }
  GS_ASSIGN_OR_RETURN(bool buffers, InlineArray(gltf, "buffers", dir, label));
  GS_ASSIGN_OR_RETURN(bool images, InlineArray(gltf, "images", dir, label));
  if (!buffers && !images) return std::string(text);
  return gltf.dump();
}

absl::StatusOr<v1::LoadSceneRequest> BuildLoadSceneRequest(const SceneOptions& scene,
                                                           const std::filesystem::path& base_dir) {
  v1::LoadSceneRequest request;
  if (scene.scene.empty()) return absl::InvalidArgumentError("no scene given");
  if (auto file = FindLocalFile(scene.scene, base_dir)) {
    GS_ASSIGN_OR_RETURN(std::string bytes, ReadFile(*file));
    if (absl::AsciiStrToLower(file->extension().string()) == ".gltf") {
      GS_ASSIGN_OR_RETURN(bytes, InlineGltfResources(bytes, file->parent_path(), file->string()));
    }
    request.set_gltf(std::move(bytes));
  } else {
    request.set_name(scene.scene);
  }
  if (!scene.environment.empty()) {
    if (auto file = FindLocalFile(scene.environment, base_dir)) {
      GS_ASSIGN_OR_RETURN(*request.mutable_environment_image(), ReadFile(*file));
    } else {
      request.set_environment_name(scene.environment);
    }
  }
  request.set_environment_intensity(scene.environment_intensity);
  return request;
}

absl::StatusOr<std::unique_ptr<LoadedScene>> LoadedScene::Load(Connection& connection,
                                                               const v1::LoadSceneRequest& request,
                                                               bool keep) {
  v1::LoadSceneResponse response;
  absl::Status loaded = connection.Call(&v1::Gistream::Stub::LoadScene, request, &response);
  if (IsTransportRefusal(loaded)) {
    // The field that made the request large: the upload.
    const size_t bytes = request.gltf().size() + request.environment_image().size();
    return WithPrefix(loaded, absl::StrCat(request.gltf().empty() ? "environment_image" : "gltf",
                                           ": the ", FormatBytes(bytes), " upload was not read: "));
  }
  GS_RETURN_IF_ERROR(loaded);
  return std::unique_ptr<LoadedScene>(new LoadedScene(connection, std::move(response), keep));
}

absl::StatusOr<ConnectedScene> ConnectAndLoad(ConnectionOptions options,
                                              const v1::LoadSceneRequest& request, bool keep,
                                              double give_up_after_s) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point give_up =
      Clock::now() + std::chrono::milliseconds(int64_t(std::max(give_up_after_s, 0.0) * 1e3));
  auto backoff = std::chrono::milliseconds(100);
  for (;;) {
    ConnectedScene out;
    out.connection = std::make_unique<Connection>(options);
    absl::StatusOr<std::unique_ptr<LoadedScene>> scene =
        LoadedScene::Load(*out.connection, request, keep);
    if (scene.ok()) {
      out.scene = *std::move(scene);
      return out;
    }
    const bool draining = absl::IsUnavailable(scene.status()) &&
                          absl::StrContains(scene.status().message(), "draining");
    if (!draining || Clock::now() + backoff > give_up) return scene.status();
    Log(LogLevel::kWarning, absl::StrCat(DescribeStatus(scene.status()), "; trying again"));
    options.own_connection = true;
    std::this_thread::sleep_for(backoff);
    backoff = std::min(backoff * 2, std::chrono::milliseconds(1000));
  }
}

LoadedScene::~LoadedScene() {
  if (keep_ || info_.scene_id().empty()) return;
  v1::UnloadSceneRequest request;
  request.set_scene_id(info_.scene_id());
  v1::UnloadSceneResponse response;
  const absl::Status status =
      connection_.Call(&v1::Gistream::Stub::UnloadScene, request, &response, kUnloadTimeoutSeconds);
  if (!status.ok() && !absl::IsFailedPrecondition(status) && !absl::IsNotFound(status)) {
    Log(LogLevel::kWarning,
        absl::StrCat("could not unload scene ", info_.scene_id(), ": ", DescribeStatus(status)));
  }
}

std::vector<std::string> SceneWarnings(const v1::LoadSceneResponse& info) {
  std::vector<std::string> warnings;
  if (info.ignored_extensions_size() > 0) {
    warnings.push_back(absl::StrCat("ignored glTF extensions (rendered without them): ",
                                    absl::StrJoin(info.ignored_extensions(), ", ")));
  }
  for (const std::string& line : info.import_warnings()) warnings.push_back(line);
  if (info.lights_size() == 0 && info.emissive_triangle_count() == 0 && !info.has_environment()) {
    warnings.push_back(
        "no light: the scene has no KHR_lights_punctual light, no emissive surface and no "
        "environment, so every solver renders it black (load it with --environment FILE, or "
        "make a material emissive)");
  }
  return warnings;
}

std::string DescribeScene(absl::string_view label, const v1::LoadSceneResponse& info) {
  std::string out = absl::StrCat(
      "scene ", label, " (id ", info.scene_id(), "): ", info.triangle_count(), " triangles, ",
      info.nodes_size(), " nodes, ", info.lights_size(), " lights, ", info.materials_size(),
      " materials", info.has_environment() ? ", environment" : "",
      info.proxy_trees_skipped() + info.proxy_levels_skipped() > 0
          ? absl::StrCat("; past the server's --max-load-seconds: ", info.proxy_trees_skipped(),
                         " primitive(s) without proxy trees, ", info.proxy_levels_skipped(),
                         " with fewer levels")
          : "");
  for (const std::string& warning : SceneWarnings(info)) absl::StrAppend(&out, "\n", warning);
  return out;
}

}  // namespace gistream::client
