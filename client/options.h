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
#include <vector>

#include <absl/strings/string_view.h>

#include "gistream/v1/gistream.pb.h"
#include "util/status.h"

namespace gistream::client {

inline constexpr absl::string_view kDefaultServer = "127.0.0.1:50051";

enum class Command { kSolvers, kRender, kStream, kScript, kStatus, kEval, kBench, kHealth };

struct ConnectionOptions {
  std::string server{kDefaultServer};
  double timeout_seconds = 300.0;  // deadline of each unary call
  // A TCP connection of this channel's own instead of one shared with other
  // channels to the same address (bench --channels per-session).
  bool own_connection = false;
  // TLS (--tls; implied by --ca/--cert/--key): PEM contents, read while
  // parsing. Empty ca_pem: the system's roots. cert/key: mutual TLS.
  bool tls = false;
  std::string ca_pem, cert_pem, key_pem;
  // Sent as "authorization: Bearer TOKEN" on every call (--token, else
  // $GISTREAM_TOKEN); empty: none.
  std::string token;
  // Sent as "x-gistream-affinity: KEY" on every call (--affinity, else
  // $GISTREAM_AFFINITY): what a balancer hashes to pick the server.
  std::string affinity;
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
  v1::CameraChange camera;      // empty: the server's default view
  uint32_t refine_samples = 0;  // still-view samples per pixel; 0: the server's default
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
  float resume_for_s = 15.0f;  // a move's time to reconnect (0: no moves)
};

struct ScriptOptions {
  std::filesystem::path file;
  std::filesystem::path out_dir = "out";
  bool keep_scene = false;
  float resume_for_s = 15.0f;  // a move's time to reconnect (0: no moves)
};

struct StatusOptions {};

// grpc.health.v1 Check; exit 0 only when SERVING (container probes).
struct HealthOptions {
  std::string service;  // "" (the whole server) or "gistream.v1.Gistream"
};

struct EvalOptions {
  std::filesystem::path file;
  std::filesystem::path out_dir = "out/eval";
  std::filesystem::path cache_dir = ".cache/reference";
};

struct BenchOptions {
  SceneOptions scene;  // default cornell_box
  SolverOptions solver;
  ViewOptions view;                // default 128x128 JPEG
  std::string workload = "orbit";  // orbit | light | object | mixed | FILE.json
  std::string node;                // object/mixed: the node to move (name or id)
  double update_hz = 0.0;          // open loop at this rate; 0: one per received frame
  std::vector<int> sessions = {1, 2, 4};
  double duration_s = 10.0;
  double warmup_s = 2.0;
  bool channel_per_session = false;  // else one channel per server
  float fps = 30.0f;                 // session frame cap; 0: the server's default
  float resume_for_s = 15.0f;        // a session's move to reconnect (0: none)
  std::string interfere;             // a `render ...` command line run in a loop
  int reference_spp = 0;             // > 0: time to converge against a pathtrace reference
  bool keep_frames = false;          // with reference_spp: write each measured frame
  std::filesystem::path out_dir = "out/bench";
};

struct CommandLine {
  ConnectionOptions connection;
  // --help / -h / `help [COMMAND]`: print the help of `command` (or the
  // overview when there is none) and exit 0.
  bool help = false;
  std::optional<Command> command;
  std::variant<std::monostate, SolversOptions, RenderOptions, StreamOptions, ScriptOptions,
               StatusOptions, EvalOptions, BenchOptions, HealthOptions>
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
// "10s", "500ms", "2m" or plain seconds ("10", "0.5").
absl::StatusOr<double> ParseDuration(absl::string_view flag, absl::string_view text);
// "1,2,4,8": positive integers.
absl::StatusOr<std::vector<int>> ParseIntList(absl::string_view flag, absl::string_view text);
// The highest frame cap the server accepts: what `--fps uncapped` asks for.
inline constexpr float kUncappedFps = 240.0f;

}  // namespace gistream::client
