// LoadScene from a command-line argument: an existing local file is
// uploaded as bytes, anything else is a scene name in the server's scene
// directory. The loaded scene is unloaded again when the command is done.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <absl/strings/string_view.h>

#include "connection.h"
#include "gistream/v1/gistream.pb.h"
#include "options.h"
#include "util/status.h"

namespace gistream::client {

// `argument` as a local file: as given, else relative to `base_dir` (a
// script's folder) when that is set; nullopt when it names no local file.
std::optional<std::filesystem::path> FindLocalFile(absl::string_view argument,
                                                   const std::filesystem::path& base_dir = {});

// Builds the request without touching the network. A .gltf's buffers and
// images that refer to files beside it are inlined as data: URIs (the
// server accepts only self-contained glTF).
absl::StatusOr<v1::LoadSceneRequest> BuildLoadSceneRequest(
    const SceneOptions& scene, const std::filesystem::path& base_dir = {});

// Rewrites the glTF JSON `text` so that every buffers[].uri and images[].uri
// that names a file (relative to `dir`) becomes a base64 data: URI. `label`
// names the file in errors. Text without such URIs comes back unchanged.
absl::StatusOr<std::string> InlineGltfResources(absl::string_view text,
                                                const std::filesystem::path& dir,
                                                absl::string_view label);

// A scene held on the server for the lifetime of this object.
class LoadedScene {
 public:
  static absl::StatusOr<std::unique_ptr<LoadedScene>> Load(Connection& connection,
                                                           const v1::LoadSceneRequest& request,
                                                           bool keep);
  // UnloadScene unless kept. FAILED_PRECONDITION (another session still
  // uses the shared scene) is expected and quiet; other failures are logged.
  ~LoadedScene();
  LoadedScene(const LoadedScene&) = delete;
  LoadedScene& operator=(const LoadedScene&) = delete;

  const v1::LoadSceneResponse& info() const { return info_; }
  // Not unloaded at the end: its server went away (the session moved).
  void Abandon() { keep_ = true; }
  const std::string& id() const { return info_.scene_id(); }

 private:
  LoadedScene(Connection& connection, v1::LoadSceneResponse info, bool keep)
      : connection_(connection), info_(std::move(info)), keep_(keep) {}

  Connection& connection_;
  v1::LoadSceneResponse info_;
  bool keep_;
};

// A connection and the scene loaded through it (the scene is unloaded
// first: it is declared last).
struct ConnectedScene {
  std::unique_ptr<Connection> connection;
  std::unique_ptr<LoadedScene> scene;
};

// Connects to `options.server` and loads `request` there. A server that
// answers that it drains (UNAVAILABLE, "draining": a balancer still routes
// this connection to it) is asked again, on a connection of its own which
// the balancer routes anew, with a backoff of 0.1-1 s, for up to
// `give_up_after_s` (0: not again), as a moving session is; other errors
// end it at once.
// `render`'s give_up_after_s (it has no --resume-for; a stream's default).
inline constexpr double kLoadRetryForS = 15.0;
absl::StatusOr<ConnectedScene> ConnectAndLoad(ConnectionOptions options,
                                              const v1::LoadSceneRequest& request, bool keep,
                                              double give_up_after_s);

// What a user should know before looking at the frames: the glTF
// extensions the server ignored, and a scene with no light at all (no
// KHR_lights_punctual light, no emissive surface, no environment: many
// sample models are made for viewers that add their own), which every
// solver renders black. One line each; none for a scene without either.
std::vector<std::string> SceneWarnings(const v1::LoadSceneResponse& info);

// "scene cornell_box (id 3): 36 triangles, 9 nodes, 0 lights, 4 materials",
// then SceneWarnings, a line each.
std::string DescribeScene(absl::string_view label, const v1::LoadSceneResponse& info);

}  // namespace gistream::client
