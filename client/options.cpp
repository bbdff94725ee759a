#include "options.h"

#include <cmath>
#include <limits>
#include <vector>

#include <absl/strings/numbers.h>
#include <absl/strings/str_cat.h>
#include <absl/strings/str_split.h>
#include <absl/strings/strip.h>

#include "cli_args.h"
#include "connection.h"
#include "image_format.h"

namespace gistream::client {
namespace {

constexpr uint32_t kMaxImageSide = 16384;

absl::Status Usage(absl::string_view message) {
  return absl::InvalidArgumentError(std::string(message));
}

absl::StatusOr<int64_t> ParseInt(absl::string_view flag, absl::string_view text, int64_t min,
                                 int64_t max) {
  int64_t value = 0;
  if (!absl::SimpleAtoi(text, &value)) {
    return Usage(absl::StrCat(flag, ": \"", text, "\" is not an integer"));
  }
  if (value < min || value > max) {
    return Usage(absl::StrCat(flag, ": ", value, " is out of range [", min, ", ", max, "]"));
  }
  return value;
}

absl::StatusOr<float> ParseFloat(absl::string_view flag, absl::string_view text) {
  float value = 0.0f;
  if (!absl::SimpleAtof(text, &value) || !std::isfinite(value)) {
    return Usage(absl::StrCat(flag, ": \"", text, "\" is not a finite number"));
  }
  return value;
}

std::optional<Command> CommandFromName(absl::string_view name) {
  if (name == "solvers") return Command::kSolvers;
  if (name == "render") return Command::kRender;
  if (name == "stream") return Command::kStream;
  if (name == "script") return Command::kScript;
  if (name == "status") return Command::kStatus;
  if (name == "eval") return Command::kEval;
  if (name == "bench") return Command::kBench;
  if (name == "health") return Command::kHealth;
  return std::nullopt;
}

// Flags every command accepts, so `--server` may come after the command too.
const std::vector<FlagSpec> kConnectionFlags = {
    {"server"}, {"timeout"}, {"tls", false}, {"ca"}, {"cert"}, {"key"}, {"token"}, {"affinity"}};
const std::vector<FlagSpec> kSceneFlags = {
    {"scene"}, {"environment"}, {"environment-intensity"}, {"keep-scene", false}};
const std::vector<FlagSpec> kSolverFlags = {{"solver"}, {"param", true, true}};
const std::vector<FlagSpec> kViewFlags = {{"size"},
                                          {"format"},
                                          {"quality"},
                                          {"exposure"},
                                          {"camera-eye"},
                                          {"camera-target"},
                                          {"yfov"},
                                          {"bitrate"},
                                          {"crf"},
                                          {"key-interval"},
                                          {"send-unchanged", false},
                                          {"refine-samples"}};

std::vector<FlagSpec> Concat(std::initializer_list<const std::vector<FlagSpec>*> groups) {
  std::vector<FlagSpec> all;
  for (const auto* group : groups) all.insert(all.end(), group->begin(), group->end());
  return all;
}

absl::Status ApplyConnection(const ParsedFlags& flags, ConnectionOptions& connection) {
  if (auto server = flags.Get("server")) {
    if (server->empty()) return Usage("--server: empty address");
    connection.server = *server;
  }
  if (auto timeout = flags.Get("timeout")) {
    GS_ASSIGN_OR_RETURN(float seconds, ParseFloat("--timeout", *timeout));
    if (seconds <= 0.0f) return Usage("--timeout: must be positive seconds");
    connection.timeout_seconds = seconds;
  }
  if (flags.Has("tls")) connection.tls = true;
  for (auto [flag, pem] :
       {std::pair{"ca", &connection.ca_pem}, std::pair{"cert", &connection.cert_pem},
        std::pair{"key", &connection.key_pem}}) {
    if (auto path = flags.Get(flag)) {
      GS_ASSIGN_OR_RETURN(*pem, ReadPem(absl::StrCat("--", flag), *path));
      connection.tls = true;
    }
  }
  if (connection.cert_pem.empty() != connection.key_pem.empty() &&
      (flags.Has("cert") || flags.Has("key"))) {
    return Usage("--cert and --key: give both or neither");
  }
  if (auto token = flags.Get("token")) {
    if (token->empty()) return Usage("--token: empty");
    connection.token = *token;
  }
  if (auto affinity = flags.Get("affinity")) {
    if (affinity->empty()) return Usage("--affinity: empty");
    connection.affinity = *affinity;
  }
  return absl::OkStatus();
}

// --resume-for SEC (stream, bench): how long a session's move may try.
absl::Status ApplyResumeFor(const ParsedFlags& flags, float& seconds) {
  if (auto value = flags.Get("resume-for")) {
    GS_ASSIGN_OR_RETURN(seconds, ParseFloat("--resume-for", *value));
    if (!(seconds >= 0.0f && seconds <= 3600.0f)) {
      return Usage("--resume-for: seconds from 0 to 3600");
    }
  }
  return absl::OkStatus();
}

absl::Status ApplyScene(const ParsedFlags& flags, SceneOptions& scene) {
  if (auto value = flags.Get("scene")) scene.scene = *value;
  if (auto value = flags.Get("environment")) scene.environment = *value;
  if (auto value = flags.Get("environment-intensity")) {
    GS_ASSIGN_OR_RETURN(scene.environment_intensity, ParseFloat("--environment-intensity", *value));
    if (scene.environment_intensity < 0.0f) return Usage("--environment-intensity: negative");
  }
  scene.keep_scene = flags.Has("keep-scene");
  return absl::OkStatus();
}

absl::Status ApplySolver(const ParsedFlags& flags, SolverOptions& solver) {
  if (auto value = flags.Get("solver")) solver.solver = *value;
  for (const std::string& text : flags.GetAll("param")) {
    GS_ASSIGN_OR_RETURN(auto param, ParseParam(text));
    if (!solver.params.emplace(param).second) {
      return Usage(absl::StrCat("--param ", param.first, " given twice"));
    }
  }
  return absl::OkStatus();
}

absl::Status ApplyView(const ParsedFlags& flags, ViewOptions& view) {
  if (auto value = flags.Get("size")) {
    GS_ASSIGN_OR_RETURN(auto size, ParseSize("--size", *value));
    view.width = size.first;
    view.height = size.second;
  }
  if (auto value = flags.Get("format")) {
    auto format = ParseImageFormat(*value);
    if (!format.ok()) return Usage(absl::StrCat("--format: ", format.status().message()));
    view.encoding.set_format(*format);
  }
  if (auto value = flags.Get("quality")) {
    GS_ASSIGN_OR_RETURN(int64_t quality, ParseInt("--quality", *value, 1, 100));
    view.encoding.set_quality(static_cast<uint32_t>(quality));
  }
  if (auto value = flags.Get("exposure")) {
    GS_ASSIGN_OR_RETURN(float exposure, ParseFloat("--exposure", *value));
    view.encoding.set_exposure(exposure);
  }
  if (auto value = flags.Get("bitrate")) {
    GS_ASSIGN_OR_RETURN(int64_t kbps, ParseInt("--bitrate", *value, 1, 1'000'000));
    view.encoding.set_bitrate_kbps(static_cast<uint32_t>(kbps));
  }
  if (auto value = flags.Get("crf")) {
    GS_ASSIGN_OR_RETURN(int64_t crf, ParseInt("--crf", *value, 1, 51));
    view.encoding.set_crf(static_cast<uint32_t>(crf));
  }
  if (auto value = flags.Get("key-interval")) {
    GS_ASSIGN_OR_RETURN(int64_t interval, ParseInt("--key-interval", *value, 1, 100'000));
    view.encoding.set_key_frame_interval(static_cast<uint32_t>(interval));
  }
  if (flags.Has("send-unchanged")) view.encoding.set_send_unchanged(true);
  if (auto value = flags.Get("refine-samples")) {
    GS_ASSIGN_OR_RETURN(int64_t samples, ParseInt("--refine-samples", *value, 1, 1024));
    view.refine_samples = static_cast<uint32_t>(samples);
  }
  const auto eye = flags.Get("camera-eye");
  const auto target = flags.Get("camera-target");
  if (eye.has_value() != target.has_value()) {
    return Usage("--camera-eye and --camera-target go together");
  }
  if (eye) {
    v1::LookAt* look_at = view.camera.mutable_look_at();
    GS_ASSIGN_OR_RETURN(*look_at->mutable_eye(), ParseVec3("--camera-eye", *eye));
    GS_ASSIGN_OR_RETURN(*look_at->mutable_target(), ParseVec3("--camera-target", *target));
    look_at->mutable_up()->set_y(1.0f);
  }
  if (auto value = flags.Get("yfov")) {
    GS_ASSIGN_OR_RETURN(float yfov, ParseFloat("--yfov", *value));
    if (yfov <= 0.0f || yfov >= 180.0f) {
      return Usage(absl::StrCat("--yfov: ", *value, " degrees is out of range (0, 180)"));
    }
    view.camera.set_yfov_degrees(yfov);
  }
  return absl::OkStatus();
}

absl::Status NoPositional(const ParsedFlags& flags) {
  if (!flags.positional().empty()) {
    return Usage(absl::StrCat("unexpected argument \"", flags.positional().front(), "\""));
  }
  return absl::OkStatus();
}

absl::StatusOr<RenderOptions> ParseRender(const ParsedFlags& flags) {
  RenderOptions options;
  GS_RETURN_IF_ERROR(NoPositional(flags));
  GS_RETURN_IF_ERROR(ApplyScene(flags, options.scene));
  GS_RETURN_IF_ERROR(ApplySolver(flags, options.solver));
  GS_RETURN_IF_ERROR(ApplyView(flags, options.view));
  if (options.scene.scene.empty()) return Usage("--scene is required");
  auto out = flags.Get("out");
  if (!out || out->empty()) return Usage("--out FILE is required");
  options.out = *out;
  if (!flags.Has("format")) {
    // No --format: the output file's extension decides, else JPEG.
    options.view.encoding.set_format(
        ImageFormatFromPath(options.out).value_or(v1::IMAGE_FORMAT_JPEG));
  }
  return options;
}

absl::StatusOr<StreamOptions> ParseStream(const ParsedFlags& flags) {
  StreamOptions options;
  options.scene.scene = "cornell_box";
  options.view.encoding.set_format(v1::IMAGE_FORMAT_JPEG);
  GS_RETURN_IF_ERROR(NoPositional(flags));
  GS_RETURN_IF_ERROR(ApplyScene(flags, options.scene));
  GS_RETURN_IF_ERROR(ApplySolver(flags, options.solver));
  GS_RETURN_IF_ERROR(ApplyView(flags, options.view));
  if (auto value = flags.Get("frames")) {
    GS_ASSIGN_OR_RETURN(int64_t frames,
                        ParseInt("--frames", *value, 0, std::numeric_limits<int64_t>::max()));
    options.frames = static_cast<uint64_t>(frames);
  }
  if (auto value = flags.Get("fps")) {
    GS_ASSIGN_OR_RETURN(options.fps, ParseFloat("--fps", *value));
    if (options.fps < 0.0f) return Usage("--fps: negative");
  }
  if (auto value = flags.Get("out")) {
    if (value->empty()) return Usage("--out: empty directory name");
    options.out_dir = *value;
  }
  GS_RETURN_IF_ERROR(ApplyResumeFor(flags, options.resume_for_s));
  return options;
}

absl::StatusOr<ScriptOptions> ParseScript(const ParsedFlags& flags) {
  ScriptOptions options;
  if (flags.positional().size() != 1) {
    return Usage(flags.positional().empty() ? "script FILE is required"
                                            : "script takes exactly one FILE");
  }
  options.file = flags.positional().front();
  if (auto value = flags.Get("out")) {
    if (value->empty()) return Usage("--out: empty directory name");
    options.out_dir = *value;
  }
  options.keep_scene = flags.Has("keep-scene");
  GS_RETURN_IF_ERROR(ApplyResumeFor(flags, options.resume_for_s));
  return options;
}

absl::StatusOr<EvalOptions> ParseEval(const ParsedFlags& flags) {
  EvalOptions options;
  if (flags.positional().size() != 1) {
    return Usage(flags.positional().empty() ? "eval SPEC is required"
                                            : "eval takes exactly one SPEC");
  }
  options.file = flags.positional().front();
  if (auto value = flags.Get("out")) {
    if (value->empty()) return Usage("--out: empty directory name");
    options.out_dir = *value;
  }
  if (auto value = flags.Get("cache")) {
    if (value->empty()) return Usage("--cache: empty directory name");
    options.cache_dir = *value;
  }
  return options;
}

absl::StatusOr<BenchOptions> ParseBench(const ParsedFlags& flags) {
  BenchOptions options;
  options.scene.scene = "cornell_box";
  options.view.width = 128;
  options.view.height = 128;
  options.view.encoding.set_format(v1::IMAGE_FORMAT_JPEG);
  GS_RETURN_IF_ERROR(NoPositional(flags));
  GS_RETURN_IF_ERROR(ApplyScene(flags, options.scene));
  GS_RETURN_IF_ERROR(ApplySolver(flags, options.solver));
  GS_RETURN_IF_ERROR(ApplyView(flags, options.view));
  GS_RETURN_IF_ERROR(ApplyResumeFor(flags, options.resume_for_s));
  if (auto value = flags.Get("workload")) {
    if (value->empty()) return Usage("--workload: empty");
    options.workload = *value;
  }
  if (auto value = flags.Get("node")) options.node = *value;
  if (auto value = flags.Get("update-hz")) {
    GS_ASSIGN_OR_RETURN(float hz, ParseFloat("--update-hz", *value));
    if (hz < 0.0f || hz > 1000.0f) {
      return Usage(absl::StrCat("--update-hz: ", *value, " is out of range [0, 1000]"));
    }
    options.update_hz = hz;
  }
  if (auto value = flags.Get("sessions")) {
    GS_ASSIGN_OR_RETURN(options.sessions, ParseIntList("--sessions", *value));
  }
  if (auto value = flags.Get("duration")) {
    GS_ASSIGN_OR_RETURN(options.duration_s, ParseDuration("--duration", *value));
    if (options.duration_s <= 0.0) return Usage("--duration: must be positive");
  }
  if (auto value = flags.Get("warmup")) {
    GS_ASSIGN_OR_RETURN(options.warmup_s, ParseDuration("--warmup", *value));
  }
  if (auto value = flags.Get("channels")) {
    if (*value == "shared")
      options.channel_per_session = false;
    else if (*value == "per-session")
      options.channel_per_session = true;
    else
      return Usage(absl::StrCat("--channels: \"", *value, "\" is not shared or per-session"));
  }
  if (auto value = flags.Get("fps")) {
    if (*value == "uncapped") {
      options.fps = kUncappedFps;
    } else {
      GS_ASSIGN_OR_RETURN(options.fps, ParseFloat("--fps", *value));
      if (options.fps < 0.0f || options.fps > kUncappedFps) {
        return Usage(absl::StrCat("--fps: ", *value, " is out of range [0, ", kUncappedFps,
                                  "] (or \"uncapped\")"));
      }
    }
  }
  if (auto value = flags.Get("interfere")) options.interfere = *value;
  if (auto value = flags.Get("reference-spp")) {
    GS_ASSIGN_OR_RETURN(int64_t spp, ParseInt("--reference-spp", *value, 0, 1 << 20));
    options.reference_spp = int(spp);
  }
  options.keep_frames = flags.Has("keep-frames");
  if (auto value = flags.Get("out")) {
    if (value->empty()) return Usage("--out: empty directory name");
    options.out_dir = *value;
  }
  return options;
}

// Leading options before the command word: --server, --timeout, --help.
absl::StatusOr<size_t> ParseGlobalOptions(std::span<const std::string> args, CommandLine& line) {
  size_t i = 0;
  while (i < args.size() && args[i].size() > 1 && args[i][0] == '-') {
    const std::string& arg = args[i];
    if (arg == "--help" || arg == "-h") {
      line.help = true;
      ++i;
      continue;
    }
    if (arg.rfind("--", 0) != 0) return Usage(absl::StrCat("unknown option ", arg));
    // Hand the flag (and its value) to the common scanner.
    const bool joined = arg.find('=') != std::string::npos;
    const size_t count = joined || arg == "--tls" ? 1 : 2;
    GS_ASSIGN_OR_RETURN(
        ParsedFlags flags,
        ParseFlags(args.subspan(i, std::min(count, args.size() - i)), kConnectionFlags));
    GS_RETURN_IF_ERROR(ApplyConnection(flags, line.connection));
    i += count;
  }
  return i;
}

bool WantsHelp(std::span<const std::string> args) {
  for (const std::string& arg : args) {
    if (arg == "--") return false;
    if (arg == "--help" || arg == "-h") return true;
  }
  return false;
}

// The flags `command` takes.
std::vector<FlagSpec> CommandFlags(Command command) {
  std::vector<FlagSpec> specs;
  switch (command) {
    case Command::kSolvers:
      specs = Concat({&kConnectionFlags});
      specs.push_back({"json", false});
      break;
    case Command::kStatus: specs = Concat({&kConnectionFlags}); break;
    case Command::kHealth:
      specs = Concat({&kConnectionFlags});
      specs.push_back({"service"});
      break;
    case Command::kRender:
      specs = Concat({&kConnectionFlags, &kSceneFlags, &kSolverFlags, &kViewFlags});
      specs.push_back({"out"});
      break;
    case Command::kStream:
      specs = Concat({&kConnectionFlags, &kSceneFlags, &kSolverFlags, &kViewFlags});
      specs.insert(specs.end(), {{"frames"}, {"fps"}, {"out"}, {"resume-for"}});
      break;
    case Command::kScript:
      specs = Concat({&kConnectionFlags});
      specs.insert(specs.end(), {{"out"}, {"keep-scene", false}, {"resume-for"}});
      break;
    case Command::kEval:
      specs = Concat({&kConnectionFlags});
      specs.insert(specs.end(), {{"out"}, {"cache"}});
      break;
    case Command::kBench:
      specs = Concat({&kConnectionFlags, &kSceneFlags, &kSolverFlags, &kViewFlags});
      specs.insert(specs.end(), {{"workload"},
                                 {"node"},
                                 {"update-hz"},
                                 {"sessions"},
                                 {"duration"},
                                 {"warmup"},
                                 {"channels"},
                                 {"fps"},
                                 {"interfere"},
                                 {"reference-spp"},
                                 {"keep-frames", false},
                                 {"resume-for"},
                                 {"out"}});
      break;
  }
  return specs;
}

// `command`'s options from its parsed flags.
absl::StatusOr<decltype(CommandLine::options)> CommandOptions(Command command,
                                                              const ParsedFlags& flags) {
  decltype(CommandLine::options) options;
  switch (command) {
    case Command::kSolvers: {
      GS_RETURN_IF_ERROR(NoPositional(flags));
      options = SolversOptions{.json = flags.Has("json")};
      break;
    }
    case Command::kStatus: {
      GS_RETURN_IF_ERROR(NoPositional(flags));
      options = StatusOptions{};
      break;
    }
    case Command::kHealth: {
      GS_RETURN_IF_ERROR(NoPositional(flags));
      options = HealthOptions{.service = flags.Get("service").value_or("")};
      break;
    }
    case Command::kRender: {
      GS_ASSIGN_OR_RETURN(options, ParseRender(flags));
      break;
    }
    case Command::kStream: {
      GS_ASSIGN_OR_RETURN(options, ParseStream(flags));
      break;
    }
    case Command::kScript: {
      GS_ASSIGN_OR_RETURN(options, ParseScript(flags));
      break;
    }
    case Command::kEval: {
      GS_ASSIGN_OR_RETURN(options, ParseEval(flags));
      break;
    }
    case Command::kBench: {
      GS_ASSIGN_OR_RETURN(options, ParseBench(flags));
      break;
    }
  }
  return options;
}

}  // namespace

absl::string_view CommandName(Command command) {
  switch (command) {
    case Command::kSolvers: return "solvers";
    case Command::kRender: return "render";
    case Command::kStream: return "stream";
    case Command::kScript: return "script";
    case Command::kStatus: return "status";
    case Command::kEval: return "eval";
    case Command::kBench: return "bench";
    case Command::kHealth: return "health";
  }
  return "?";
}

absl::StatusOr<std::pair<uint32_t, uint32_t>> ParseSize(absl::string_view flag,
                                                        absl::string_view text) {
  std::vector<absl::string_view> parts = absl::StrSplit(text, absl::ByAnyChar("xX"));
  uint32_t width = 0;
  uint32_t height = 0;
  if (parts.size() != 2 || !absl::SimpleAtoi(parts[0], &width) ||
      !absl::SimpleAtoi(parts[1], &height)) {
    return Usage(absl::StrCat(flag, ": \"", text, "\" is not WIDTHxHEIGHT (e.g. 320x240)"));
  }
  if (width == 0 || height == 0 || width > kMaxImageSide || height > kMaxImageSide) {
    return Usage(absl::StrCat(flag, ": ", width, "x", height, " is out of range [1, ",
                              kMaxImageSide, "] per side"));
  }
  return std::make_pair(width, height);
}

absl::StatusOr<v1::Vec3> ParseVec3(absl::string_view flag, absl::string_view text) {
  std::vector<absl::string_view> parts = absl::StrSplit(text, ',');
  float xyz[3];
  bool ok = parts.size() == 3;
  for (size_t i = 0; ok && i < 3; ++i) {
    ok = absl::SimpleAtof(absl::StripAsciiWhitespace(parts[i]), &xyz[i]) && std::isfinite(xyz[i]);
  }
  if (!ok) return Usage(absl::StrCat(flag, ": \"", text, "\" is not three numbers x,y,z"));
  v1::Vec3 v;
  v.set_x(xyz[0]);
  v.set_y(xyz[1]);
  v.set_z(xyz[2]);
  return v;
}

absl::StatusOr<std::pair<std::string, std::string>> ParseParam(absl::string_view text) {
  const size_t eq = text.find('=');
  if (eq == absl::string_view::npos || eq == 0) {
    return Usage(absl::StrCat("--param: \"", text, "\" is not key=value"));
  }
  return std::make_pair(std::string(text.substr(0, eq)), std::string(text.substr(eq + 1)));
}

absl::StatusOr<double> ParseDuration(absl::string_view flag, absl::string_view text) {
  double scale = 1.0;
  absl::string_view number = text;
  if (absl::ConsumeSuffix(&number, "ms"))
    scale = 1e-3;
  else if (absl::ConsumeSuffix(&number, "s"))
    scale = 1.0;
  else if (absl::ConsumeSuffix(&number, "m"))
    scale = 60.0;
  double value = 0.0;
  if (!absl::SimpleAtod(number, &value) || !std::isfinite(value) || value < 0.0 ||
      value * scale > 86400.0) {
    return Usage(absl::StrCat(flag, ": \"", text,
                              "\" is not a duration (e.g. 10s, 500ms, 2m; at most a day)"));
  }
  return value * scale;
}

absl::StatusOr<std::vector<int>> ParseIntList(absl::string_view flag, absl::string_view text) {
  std::vector<int> out;
  for (absl::string_view part : absl::StrSplit(text, ',')) {
    GS_ASSIGN_OR_RETURN(int64_t value, ParseInt(flag, absl::StripAsciiWhitespace(part), 1, 1024));
    out.push_back(int(value));
  }
  return out;
}

absl::StatusOr<CommandLine> ParseCommandLine(std::span<const std::string> args,
                                             absl::string_view default_server) {
  CommandLine line;
  line.connection.server = std::string(default_server);
  GS_ASSIGN_OR_RETURN(size_t i, ParseGlobalOptions(args, line));
  if (i == args.size()) {
    if (line.help) return line;
    return Usage("no command given");
  }

  absl::string_view word = args[i++];
  if (word == "help") {
    line.help = true;
    if (i == args.size()) return line;
    word = args[i++];
    if (i != args.size()) return Usage("help takes at most one COMMAND");
  }
  line.command = CommandFromName(word);
  if (!line.command) return Usage(absl::StrCat("unknown command \"", word, "\""));
  const std::span<const std::string> rest = args.subspan(i);
  if (line.help || WantsHelp(rest)) {
    line.help = true;
    return line;
  }

  GS_ASSIGN_OR_RETURN(ParsedFlags flags, ParseFlags(rest, CommandFlags(*line.command)));
  GS_RETURN_IF_ERROR(ApplyConnection(flags, line.connection));
  GS_ASSIGN_OR_RETURN(line.options, CommandOptions(*line.command, flags));
  return line;
}

}  // namespace gistream::client
