// The command line, parsed into one options struct per command. Every
// error here is a usage error (main exits 2); nothing touches the network.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <variant>

#include <absl/strings/string_view.h>

#include "gistream/v1/gistream.pb.h"
#include "util/status.h"

namespace gistream::client {

inline constexpr absl::string_view kDefaultServer = "127.0.0.1:50051";

enum class Command { kSolvers, kRender, kStream, kScript, kStatus, kEval };

struct ConnectionOptions {
  std::string server{kDefaultServer};
  double timeout_seconds = 300.0;  // deadline of each unary call
};

// Where the scene comes from (LoadScene).
struct SceneOptions {
  std::string scene;                   // an existing local file is uploaded, else a name
  std::string environment;             // likewise; empty: none
  float environment_intensity = 0.0f;  // 0 means 1 (server default)
  bool keep_scene = false;             // do not UnloadScene when done
};

struct SolverOptions {
  std::string solver = "direct";
  std::map<std::string, std::string> params;
};

struct ViewOptions {
  uint32_t width = 320;
  uint32_t height = 240;
  v1::Encoding encoding;
  v1::CameraChange camera;  // empty: the server's default view
};

struct SolversOptions {
  bool json = false;  // print ListSolversResponse as protobuf JSON
};

struct RenderOptions {
  SceneOptions scene;
  SolverOptions solver;
  ViewOptions view;
  std::filesystem::path out;
};

struct StreamOptions {
  SceneOptions scene;
  SolverOptions solver;
  ViewOptions view;
  uint64_t frames = 30;  // 0: until interrupted
  float fps = 30.0f;     // continuous pacing cap; 0: the server's default
  std::filesystem::path out_dir = "out";
};

struct ScriptOptions {
  std::filesystem::path file;
  std::filesystem::path out_dir = "out";
  bool keep_scene = false;
};

struct StatusOptions {};

struct EvalOptions {
  std::filesystem::path file;
  std::filesystem::path out_dir = "out/eval";
  std::filesystem::path cache_dir = ".cache/reference";
};

struct CommandLine {
  ConnectionOptions connection;
  // --help / -h / `help [COMMAND]`: print the help of `command` (or the
  // overview when there is none) and exit 0.
  bool help = false;
  std::optional<Command> command;
  std::variant<std::monostate, SolversOptions, RenderOptions, StreamOptions, ScriptOptions,
               StatusOptions, EvalOptions>
      options;
};

// `args` excludes the program name. `default_server` is what --server
// defaults to (main passes $GISTREAM_SERVER or kDefaultServer).
absl::StatusOr<CommandLine> ParseCommandLine(std::span<const std::string> args,
                                             absl::string_view default_server);

absl::string_view CommandName(Command command);

// Value parsers, exposed for tests. Messages name the flag.
absl::StatusOr<std::pair<uint32_t, uint32_t>> ParseSize(absl::string_view flag,
                                                        absl::string_view text);
absl::StatusOr<v1::Vec3> ParseVec3(absl::string_view flag, absl::string_view text);
absl::StatusOr<std::pair<std::string, std::string>> ParseParam(absl::string_view text);

}  // namespace gistream::client
