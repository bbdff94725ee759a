// gistreamd: the render server. Parses flags, creates the Engine (EGL device,
// render thread), serves gistream.v1 over gRPC (and, with --metrics-listen,
// Prometheus metrics over HTTP), prints `listening on ADDR` once serving, and
// shuts down gracefully on SIGTERM/SIGINT.
#include <pthread.h>
#include <signal.h>

#include <algorithm>
#include <optional>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <climits>
#include <condition_variable>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <type_traits>
#include <string_view>
#include <thread>

#include "metrics/metrics.h"
#include "engine/engine.h"
#include "service/server.h"
#include "solvers/registry.h"
#include "util/auth_tokens.h"
#include "util/cpu_pool.h"
#include "util/log.h"
#include "util/memory_budget.h"
#include "util/status.h"
#include "util/version.h"

namespace gistream {
namespace {

constexpr int kExitUsage = 2;

// Debian's Abseil keeps its own string_view type; StrCat needs it.
absl::string_view AV(std::string_view s) { return absl::string_view(s.data(), s.size()); }

struct Flags {
  std::string listen = "127.0.0.1:50051";
  std::string metrics_listen;  // empty: no metrics endpoint
  std::string metrics_token;   // path of a file holding it; empty: open
  std::string health_listen;   // empty: health on --listen only
  EngineOptions engine;
  uint64_t max_message_bytes = 0;               // 0: max_scene_bytes + 16 MiB
  std::optional<uint64_t> max_transport_bytes;  // unset: a quarter of the budget, >= 256 MiB
  double shutdown_deadline_s = 10.0;
  LogLevel log_level = LogLevel::kInfo;
  unsigned cpu_threads = 0;                      // 0: DefaultCpuThreads()
  std::string tls_cert, tls_key, tls_client_ca;  // PEM file paths
  bool insecure = false;
  std::string auth_tokens;  // token file path; empty: one default tenant
  double idle_timeout_s = 900.0;
};

constexpr const char* kUsage = R"(usage: gistreamd [flags]

  --listen ADDR              host:port to serve on (default 127.0.0.1:50051;
                             port 0 picks a free one)
  --metrics-listen ADDR      also serve Prometheus metrics on http://ADDR/metrics
                             (host:port; default off)
  --metrics-token-file FILE  scrapes must send the token in FILE as the password
                             of HTTP Basic authentication (any user), else 401
                             (default: no token; logged as a warning with
                             --auth-tokens or a non-loopback --metrics-listen)
  --scenes DIR               scene directory for LoadScene by name (default scenes)
  --egl-device N             EGL device index; -1 picks the first hardware
                             device, else Mesa's software one (default -1)
  --health-listen ADDR       also serve grpc.health.v1 alone, in plaintext, on
                             ADDR (host:port), for probes that speak no TLS
                             (kubelet's gRPC probes); default off
  --tls-cert FILE            serve TLS with this PEM certificate chain ...
  --tls-key FILE             ... and its PEM private key
  --tls-client-ca FILE       mutual TLS: clients must present a certificate
                             signed by this PEM CA
  --insecure                 allow plaintext on a non-loopback --listen (only
                             behind something that encrypts, e.g. a mesh
                             sidecar); without TLS, gistreamd otherwise
                             refuses any address but loopback
  --auth-tokens FILE         bearer tokens, one per line: TOKEN TENANT
                             [scenes=N sessions=N upload_bytes=N gpu_bytes=N];
                             calls without a listed token get UNAUTHENTICATED
                             (health stays open). Default: no tokens, one tenant
  --idle-timeout-s F         end sessions without a client request and free
                             scenes nobody uses for this long; 0: never
                             (default 900)
  --max-sessions N           concurrent sessions (default 32)
  --max-render-busy F        admission by measured GPU time: a new session is
                             refused (RESOURCE_EXHAUSTED, retry later or on
                             another server) when the render thread's busy
                             share over the last 5 s plus one more active
                             session's share would pass F (0..1; default 0:
                             only --max-sessions limits); deployments use 0.85
  --max-scenes N             scenes held at once (default 16)
  --max-memory-bytes N       memory budget for scenes (decoded images
                             included), solver state and G-buffers, CPU and
                             GPU bytes together; over it is RESOURCE_EXHAUSTED
                             (default: 3/4 of physical memory, or
                             of the cgroup's memory limit when lower)
  --max-solvers-per-scene N  GI solutions cached per scene, one per solver and
                             parameter set; the least recently used idle
                             one is dropped beyond N (default 8)
  --max-solve-seconds F      a session's solver whose complete solve (every
                             bounce or iteration up to its cap) is estimated
                             over F seconds is refused (RESOURCE_EXHAUSTED
                             naming the parameters) before it is built; the
                             estimate is for the reference machine (2 cores,
                             llvmpipe) divided by --solve-speed; 0: no limit
                             (default 300)
  --solve-speed F            how many times faster than the reference machine
                             this server solves (default 1)
  --max-width N              largest frame width (default 4096)
  --max-height N             largest frame height (default 4096)
  --max-scene-bytes N        largest glb/gltf, buffers included (default 268435456)
  --max-triangles N          triangles over all mesh instances (default 4000000)
  --max-draw-items N         primitives drawn: each mesh's primitives x the nodes
                             instancing it (default 262144)
  --max-materials N          materials of a scene (default 65536)
  --max-load-seconds F       a scene load's proxy levels and cluster trees stop
                             this long after it began; the scene loads without
                             the rest (LoadScene's proxy_trees_skipped; its GI
                             passes draw coarser proxies). Default 60
  --max-image-pixels N       pixels per texture/environment image (default 67108864)
  --max-message-bytes N      largest gRPC message (default max-scene-bytes + 16 MiB)
  --max-transport-bytes N    memory gRPC's transport may hold for all calls
                             (uploads being read); past it new calls get
                             RESOURCE_EXHAUSTED (default a quarter of the
                             memory budget, at least 256 MiB; 0: unbounded)
  --default-fps F            frame cap for continuous sessions that give none (default 30)
  --shutdown-deadline-s F    on SIGTERM/SIGINT, seconds running calls get before
                             they are cancelled (default 10)
  --log-level L              debug | info | warning | error (default info)
  --cpu-threads N            threads of the CPU pool that runs every CPU stage
                             (default: the CPUs of the affinity mask, capped by
                             the cgroup CPU quota)
  --frame-budget-ms F        solver work per frame before the render thread
                             serves other sessions; sliceable work (pathtrace)
                             continues in later slices (default 30)
  --refine-samples N         samples per pixel a still view accumulates (sub-
                             pixel jitter, box filter) before it rests; 1:
                             pixel centres only (default 16, at most 1024)
  --refine-history N         weight, in samples, of the picture kept when the
                             scene changes under a still camera (clipped to
                             the new picture's colours, faded out by the last
                             sample); 0: a change restarts the picture
                             (default 0, at most 64)
  --refine-carry 0|1         carry a complete picture's anti-aliasing over a
                             change under a still camera, scaled by the
                             change of light at each pixel centre and dropped
                             where geometry moved (default 1)
  --refine-reproject N       weight, in samples, of the picture shown before a
                             camera move, reprojected into the new view
                             where it saw the same surfaces (clipped to the
                             new picture's colours, faded out by the last
                             sample); 0: a move restarts at the pixel
                             centres (default 4, at most 64)
  --version                  print "gistreamd VERSION" and exit
  --list-solvers             print the registered solvers, one name per line,
                             and exit
  --help                     this text
Flags take their value as the next argument or after '=' (--listen=:50051).
)";

[[noreturn]] void UsageError(std::string_view message) {
  std::fprintf(stderr, "gistreamd: %.*s\n(see gistreamd --help)\n",
               static_cast<int>(message.size()), message.data());
  std::exit(kExitUsage);
}

template <typename T>
T ParseUnsigned(std::string_view flag, std::string_view value, T min, T max) {
  uint64_t v = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
  if (ec != std::errc() || end != value.data() + value.size() || v < min || v > max) {
    UsageError(absl::StrCat(AV(flag), ": expected an integer in ", min, "..", max, ", got '",
                            AV(value), "'"));
  }
  return static_cast<T>(v);
}

int ParseInt(std::string_view flag, std::string_view value, int min, int max) {
  int v = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
  if (ec != std::errc() || end != value.data() + value.size() || v < min || v > max) {
    UsageError(absl::StrCat(AV(flag), ": expected an integer in ", min, "..", max, ", got '",
                            AV(value), "'"));
  }
  return v;
}

double ParseDouble(std::string_view flag, std::string_view value, double min, double max) {
  // std::from_chars for double is in libstdc++ 11+; strtod keeps this portable.
  const std::string s(value);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || errno != 0 || !std::isfinite(v) || v < min ||
      v > max) {
    UsageError(absl::StrCat(AV(flag), ": expected a number in ", min, "..", max, ", got '",
                            AV(value), "'"));
  }
  return v;
}

LogLevel ParseLogLevel(std::string_view flag, std::string_view value) {
  if (value == "debug") return LogLevel::kDebug;
  if (value == "info") return LogLevel::kInfo;
  if (value == "warning") return LogLevel::kWarning;
  if (value == "error") return LogLevel::kError;
  UsageError(
      absl::StrCat(AV(flag), ": expected debug, info, warning or error, got '", AV(value), "'"));
}

using Setter = std::function<void(std::string_view flag, std::string_view value)>;
using Setters = std::map<std::string_view, Setter>;

// A flag that sets `field` to an integer in [min, max].
template <typename T>
Setter Unsigned(T& field, std::type_identity_t<T> min, std::type_identity_t<T> max) {
  return [&field, min, max](std::string_view flag, std::string_view v) {
    field = ParseUnsigned<T>(flag, v, min, max);
  };
}
// A flag that sets `field` to a number in [min, max].
Setter Number(double& field, double min, double max) {
  return [&field, min, max](std::string_view flag, std::string_view v) {
    field = ParseDouble(flag, v, min, max);
  };
}

// The process's own flags: addresses, TLS and tokens, the gRPC transport,
// shutdown, logging, threads.
void AddServerFlags(Flags& f, Setters& setters) {
  setters.insert({
      {"--listen",
       [&](auto flag, auto v) {
         if (v.empty()) UsageError(absl::StrCat(AV(flag), ": empty address"));
         f.listen = std::string(v);
       }},
      {"--metrics-listen",
       [&](auto flag, auto v) {
         if (v.empty()) UsageError(absl::StrCat(AV(flag), ": empty address"));
         f.metrics_listen = std::string(v);
       }},
      {"--metrics-token-file", [&](auto, auto v) { f.metrics_token = std::string(v); }},
      {"--health-listen",
       [&](auto flag, auto v) {
         if (v.empty()) UsageError(absl::StrCat(AV(flag), ": empty address"));
         f.health_listen = std::string(v);
       }},
      {"--tls-cert", [&](auto, auto v) { f.tls_cert = std::string(v); }},
      {"--tls-key", [&](auto, auto v) { f.tls_key = std::string(v); }},
      {"--tls-client-ca", [&](auto, auto v) { f.tls_client_ca = std::string(v); }},
      {"--auth-tokens", [&](auto, auto v) { f.auth_tokens = std::string(v); }},
      {"--max-transport-bytes",
       [&](auto flag, auto v) {
         f.max_transport_bytes = ParseUnsigned<uint64_t>(flag, v, 0, UINT64_MAX);
       }},
      {"--max-message-bytes", Unsigned<uint64_t>(f.max_message_bytes, 1024, INT_MAX)},
      {"--shutdown-deadline-s", Number(f.shutdown_deadline_s, 0.0, 3600.0)},
      {"--idle-timeout-s", Number(f.idle_timeout_s, 0.0, 30.0 * 86400.0)},
      {"--log-level", [&](auto flag, auto v) { f.log_level = ParseLogLevel(flag, v); }},
      {"--cpu-threads", Unsigned<unsigned>(f.cpu_threads, 1, 1024)},
  });
}

// What a client or a scene may take: import limits, the memory budget,
// sessions, scenes, solvers and frame sizes (see --help).
void AddLimitFlags(Flags& f, Setters& setters) {
  setters.insert({
      {"--max-scene-bytes",
       Unsigned<uint64_t>(f.engine.import_limits.max_scene_bytes, 1024, uint64_t{2} << 30)},
      {"--max-triangles",
       Unsigned<uint64_t>(f.engine.import_limits.max_triangles, 1, uint64_t{1} << 32)},
      {"--max-draw-items",
       Unsigned<uint64_t>(f.engine.import_limits.max_draw_items, 1, uint64_t{1} << 32)},
      {"--max-materials",
       Unsigned<uint32_t>(f.engine.import_limits.max_materials, 1, uint32_t{1} << 24)},
      {"--max-image-pixels",
       Unsigned<uint64_t>(f.engine.import_limits.max_image_pixels, 1, uint64_t{1} << 32)},
      {"--max-load-seconds",
       [&](auto flag, auto v) {
         f.engine.max_load_time =
             std::chrono::milliseconds(int64_t(1000.0 * ParseDouble(flag, v, 0.0, 86400.0)));
       }},
      {"--max-memory-bytes",
       Unsigned<uint64_t>(f.engine.max_memory_bytes, uint64_t{1} << 20, UINT64_MAX)},
      {"--max-scenes", Unsigned<uint32_t>(f.engine.max_scenes, 1, 100'000)},
      {"--max-sessions", Unsigned<uint32_t>(f.engine.max_sessions, 1, 100'000)},
      {"--max-render-busy", Number(f.engine.max_render_busy, 0.0, 1.0)},
      {"--max-solvers-per-scene", Unsigned<uint32_t>(f.engine.max_solvers_per_scene, 1, 1'000)},
      {"--max-solve-seconds", Number(f.engine.max_solve_seconds, 0.0, 1e9)},
      {"--solve-speed", Number(f.engine.solve_speed, 1e-3, 1e6)},
      {"--max-width", Unsigned<uint32_t>(f.engine.max_width, 1, 65'536)},
      {"--max-height", Unsigned<uint32_t>(f.engine.max_height, 1, 65'536)},
  });
}

// How the engine renders: the scene directory, the EGL device, frame
// pacing, slices and refinement.
void AddEngineFlags(Flags& f, Setters& setters) {
  setters.insert({
      {"--scenes", [&](auto, auto v) { f.engine.scene_dir = std::string(v); }},
      {"--egl-device",
       [&](auto flag, auto v) { f.engine.egl_device = ParseInt(flag, v, -1, 1024); }},
      {"--default-fps",
       [&](auto flag, auto v) {
         f.engine.default_max_fps = static_cast<float>(ParseDouble(flag, v, 0.1, f.engine.max_fps));
       }},
      {"--frame-budget-ms", Number(f.engine.frame_budget_ms, 1.0, 10'000.0)},
      {"--refine-samples",
       Unsigned<uint32_t>(f.engine.refine_samples, 1, EngineOptions::kMaxRefineSamples)},
      {"--refine-history",
       Unsigned<uint32_t>(f.engine.refine_history, 0, EngineOptions::kMaxRefineHistory)},
      {"--refine-carry",
       [&](auto flag, auto v) { f.engine.refine_carry = ParseInt(flag, v, 0, 1) != 0; }},
      {"--refine-reproject",
       Unsigned<uint32_t>(f.engine.refine_reproject, 0, EngineOptions::kMaxRefineHistory)},
  });
}

// --help, --version and --list-solvers print and exit.
void HandleExitingFlag(std::string_view arg) {
  if (arg == "--help" || arg == "-h") {
    std::fputs(kUsage, stdout);
    std::exit(0);
  }
  if (arg == "--version") {
    const std::string_view version = Version();
    std::printf("gistreamd %.*s\n", static_cast<int>(version.size()), version.data());
    std::exit(0);
  }
  if (arg == "--list-solvers") {
    for (const SolverDescription& d : AllSolverDescriptions()) std::printf("%s\n", d.name.c_str());
    std::exit(0);
  }
}

// What depends on several flags: TLS pairs, the idle timeout, the default
// message size.
void FinishFlags(Flags& f) {
  if (f.tls_cert.empty() != f.tls_key.empty()) {
    UsageError("--tls-cert and --tls-key: give both or neither");
  }
  if (!f.tls_client_ca.empty() && f.tls_cert.empty()) {
    UsageError("--tls-client-ca: needs --tls-cert and --tls-key");
  }
  f.engine.idle_timeout =
      std::chrono::milliseconds(static_cast<int64_t>(f.idle_timeout_s * 1000.0));
  if (f.max_message_bytes == 0) {
    f.max_message_bytes =
        std::min<uint64_t>(f.engine.import_limits.max_scene_bytes + (16u << 20), INT_MAX);
  }
}

Flags ParseFlags(int argc, char** argv) {
  Flags f;
  Setters setters;
  AddServerFlags(f, setters);
  AddLimitFlags(f, setters);
  AddEngineFlags(f, setters);
  for (int i = 1; i < argc; ++i) {
    std::string_view arg = argv[i];
    HandleExitingFlag(arg);
    if (arg == "--insecure") {
      f.insecure = true;
      continue;
    }
    std::string_view name = arg;
    std::string_view value;
    bool has_value = false;
    if (const size_t eq = arg.find('='); arg.starts_with("--") && eq != std::string_view::npos) {
      name = arg.substr(0, eq);
      value = arg.substr(eq + 1);
      has_value = true;
    }
    const auto it = setters.find(name);
    if (it == setters.end()) {
      UsageError(arg.starts_with("-") ? absl::StrCat("unknown flag ", AV(name))
                                      : absl::StrCat("unexpected argument '", AV(arg), "'"));
    }
    if (!has_value) {
      if (i + 1 >= argc) UsageError(absl::StrCat(AV(name), ": missing value"));
      value = argv[++i];
    }
    it->second(name, value);
  }
  FinishFlags(f);
  return f;
}

// Blocks SIGINT/SIGTERM in the calling thread (and so in every thread it
// starts afterwards: gRPC's, the render thread) so that only SignalWaiter's
// sigwait sees them.
sigset_t BlockShutdownSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  return set;
}

// A dedicated thread waiting for SIGINT/SIGTERM. The first one calls
// `on_first`; a second one while shutdown runs exits at once.
class SignalWaiter {
 public:
  SignalWaiter(sigset_t set, std::function<void(int)> on_first)
      : thread_([set, on_first = std::move(on_first)](std::stop_token stop) {
          bool first = true;
          while (!stop.stop_requested()) {
            timespec timeout{0, 200'000'000};  // wake to see stop requests
            const int sig = sigtimedwait(&set, nullptr, &timeout);
            if (sig < 0) continue;  // EAGAIN (timeout) or EINTR
            if (first) {
              first = false;
              on_first(sig);
            } else {
              Log(LogLevel::kWarning, "second signal during shutdown: exiting now");
              std::_Exit(1);
            }
          }
        }) {}

 private:
  std::jthread thread_;  // stop requested and joined on destruction
};

// A PEM file named by `flag`; exits with a usage error when unreadable.
std::string ReadPem(std::string_view flag, const std::string& path) {
  if (path.empty()) return "";
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  if (in) text << in.rdbuf();
  if (!in || text.str().empty()) {
    UsageError(absl::StrCat(AV(flag), ": cannot read '", path, "'"));
  }
  return text.str();
}

// Read before the engine starts, so a bad path fails fast; the tenants'
// quotas go to the engine.
std::shared_ptr<const AuthTokens> LoadTokens(Flags& flags) {
  if (flags.auth_tokens.empty()) return nullptr;
  absl::StatusOr<AuthTokens> loaded = AuthTokens::Load(flags.auth_tokens);
  if (!loaded.ok()) UsageError(std::string(loaded.status().message()));
  flags.engine.quotas = loaded->quotas();
  auto tokens = std::make_shared<const AuthTokens>(*std::move(loaded));
  Log(LogLevel::kInfo,
      absl::StrCat("auth: ", tokens->size(), " tokens for ", tokens->quotas().size(), " tenants"));
  return tokens;
}

std::string LoadMetricsToken(const Flags& flags) {
  std::string token = ReadPem("--metrics-token-file", flags.metrics_token);
  token.erase(token.find_last_not_of(" \t\r\n") + 1);  // a trailing newline
  if (!flags.metrics_token.empty() && token.empty()) {
    UsageError(absl::StrCat("--metrics-token-file: '", flags.metrics_token, "' holds no token"));
  }
  return token;
}

service::TlsFiles LoadTls(const Flags& flags) {
  service::TlsFiles tls{ReadPem("--tls-cert", flags.tls_cert), ReadPem("--tls-key", flags.tls_key),
                        ReadPem("--tls-client-ca", flags.tls_client_ca)};
  if (tls.cert_chain_pem.empty() && !flags.insecure && !service::IsLoopbackAddress(flags.listen)) {
    UsageError(absl::StrCat("refusing to serve plaintext on ", flags.listen,
                            ", which is not a loopback address: give --tls-cert and --tls-key, "
                            "or --insecure if something in front of gistreamd encrypts"));
  }
  return tls;
}

uint64_t MemoryBudgetBytes(const Flags& flags) {
  return flags.engine.max_memory_bytes > 0 ? flags.engine.max_memory_bytes : DefaultMemoryLimit();
}

// The CPU pool sized, and the process's limits logged, before the engine.
void ConfigureProcess(const Flags& flags) {
  CpuPool::Configure(flags.cpu_threads);
  Log(LogLevel::kInfo,
      absl::StrCat("CPU pool: ", CpuPool::Get().threads(), " threads",
                   flags.cpu_threads > 0 ? " (--cpu-threads)" : " (affinity and cgroup quota)"));
  const uint64_t cgroup = CgroupMemoryLimit();
  Log(LogLevel::kInfo,
      absl::StrCat("memory budget: ", FormatBytes(MemoryBudgetBytes(flags)),
                   flags.engine.max_memory_bytes > 0 ? " (--max-memory-bytes)"
                   : cgroup > 0 ? absl::StrCat(" (3/4 of the lower of physical memory and the "
                                               "cgroup limit ",
                                               FormatBytes(cgroup), ")")
                                : std::string(" (3/4 of physical memory)")));
}

// Serves --metrics-listen over `engine`; false (logged) when it cannot.
bool ServeMetrics(metrics::Metrics& metrics, const Flags& flags, Engine& engine,
                  const std::string& token, bool with_tokens) {
  if (absl::Status serving = metrics.Serve(flags.metrics_listen, engine, token); !serving.ok()) {
    std::fprintf(stderr, "gistreamd: %s\n", serving.ToString().c_str());
    return false;
  }
  const std::string host = flags.metrics_listen.substr(0, flags.metrics_listen.rfind(':'));
  Log(LogLevel::kInfo, absl::StrCat("metrics on http://", host, ":", metrics.port(), "/metrics",
                                    token.empty() ? "" : " (token required)"));
  if (token.empty() && (with_tokens || !service::IsLoopbackAddress(flags.metrics_listen))) {
    // Server-wide figures (every tenant's frames, memory, sessions).
    Log(LogLevel::kWarning,
        "metrics are served without a token: anyone who reaches the port reads every tenant's "
        "figures (--metrics-token-file)");
  }
  return true;
}

service::ServerOptions MakeServerOptions(const Flags& flags, service::TlsFiles tls) {
  service::ServerOptions options;
  options.listen = flags.listen;
  options.max_receive_message_bytes = static_cast<int>(flags.max_message_bytes);
  options.max_send_message_bytes = static_cast<int>(flags.max_message_bytes);
  options.transport_memory_bytes =
      flags.max_transport_bytes
          ? *flags.max_transport_bytes
          : std::max<uint64_t>(MemoryBudgetBytes(flags) / 4, uint64_t(256) << 20);
  Log(LogLevel::kInfo,
      absl::StrCat("transport memory: ",
                   options.transport_memory_bytes > 0 ? FormatBytes(options.transport_memory_bytes)
                                                      : std::string("unbounded"),
                   flags.max_transport_bytes ? " (--max-transport-bytes)"
                                             : " (a quarter of the memory budget)"));
  options.tls = std::move(tls);
  options.allow_insecure = flags.insecure;
  options.health_listen = flags.health_listen;
  return options;
}

// The first SIGINT or SIGTERM, waited for; while this lives a second one
// exits at once (SignalWaiter), so it outlives the shutdown it starts.
class ShutdownSignal {
 public:
  explicit ShutdownSignal(const sigset_t& signals)
      : waiter_(signals, [this](int sig) {
          {
            std::lock_guard lock(mutex_);
            received_ = sig;
          }
          cv_.notify_all();
        }) {}
  // Blocks until the first signal; returns it.
  int Wait() {
    std::unique_lock lock(mutex_);
    cv_.wait(lock, [&] { return received_ != 0; });
    return received_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  int received_ = 0;
  SignalWaiter waiter_;  // last: its thread stops before the fields it uses go
};

int Main(int argc, char** argv) {
  Flags flags = ParseFlags(argc, argv);
  SetLogLevel(flags.log_level);
  const sigset_t signals = BlockShutdownSignals();
  Log(LogLevel::kInfo, absl::StrCat("gistreamd ", AV(Version())));
  const std::shared_ptr<const AuthTokens> tokens = LoadTokens(flags);
  const std::string metrics_token = LoadMetricsToken(flags);
  service::TlsFiles tls = LoadTls(flags);

  // Declared before the engine and server, which report to it.
  std::shared_ptr<metrics::Metrics> metrics;
  if (!flags.metrics_listen.empty()) {
    metrics = std::make_shared<metrics::Metrics>();
    flags.engine.observer = metrics;
  }
  ConfigureProcess(flags);
  // Test-only GPU fault injection (gl/fault_injection.h), never a flag.
  if (const char* faults = std::getenv("GISTREAM_TEST_FAULT_DIR"); faults && *faults) {
    flags.engine.test_fault_dir = faults;
  }
  absl::StatusOr<std::unique_ptr<Engine>> engine = Engine::Create(flags.engine);
  if (!engine.ok()) {
    std::fprintf(stderr, "gistreamd: cannot start the engine: %s\n",
                 engine.status().ToString().c_str());
    return 1;
  }
  const DeviceInfo device = (*engine)->device_info();
  Log(LogLevel::kInfo,
      absl::StrCat("GL: ", device.vendor, " / ", device.renderer, " / ", device.version));
  Log(LogLevel::kInfo, absl::StrCat("EGL device: ", device.egl_device));
  if (metrics && !ServeMetrics(*metrics, flags, **engine, metrics_token, tokens != nullptr)) {
    (*engine)->Shutdown();
    return 1;
  }

  service::ServerOptions options = MakeServerOptions(flags, std::move(tls));
  options.service.observer = metrics;
  options.service.tokens = tokens;
  absl::StatusOr<std::unique_ptr<service::GistreamServer>> server =
      service::GistreamServer::Start(**engine, options);
  if (!server.ok()) {
    std::fprintf(stderr, "gistreamd: %s\n", server.status().ToString().c_str());
    if (metrics) metrics->StopServing();
    (*engine)->Shutdown();
    return 1;
  }
  ShutdownSignal shutdown(signals);
  Log(LogLevel::kInfo,
      absl::StrCat("transport: ",
                   !options.tls.cert_chain_pem.empty()
                       ? (options.tls.client_ca_pem.empty() ? "TLS" : "mutual TLS")
                       : (flags.insecure ? "plaintext (--insecure)" : "plaintext on loopback"),
                   tokens ? "; bearer tokens required" : "; no tokens (one default tenant)"));
  std::printf("listening on %s\n", (*server)->address().c_str());
  std::fflush(stdout);

  const int signal_received = shutdown.Wait();
  Log(LogLevel::kInfo, absl::StrCat("received ", strsignal(signal_received)));
  const auto deadline = std::chrono::duration_cast<std::chrono::milliseconds>(
      std::chrono::duration<double>(flags.shutdown_deadline_s));
  (*server)->Shutdown(deadline);        // health NOT_SERVING, drain calls, Engine::Shutdown
  if (metrics) metrics->StopServing();  // scrapes read the engine: stop them first
  server->reset();
  engine->reset();
  return 0;
}

}  // namespace
}  // namespace gistream

int main(int argc, char** argv) { return gistream::Main(argc, argv); }
