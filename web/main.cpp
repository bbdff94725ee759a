// gistream-web: the browser viewer's gateway. Loads a scene on a gistreamd
// over gRPC, serves the embedded viewer page, and bridges each browser's
// WebSocket to its own continuous Session on that scene (so browsers see
// each other's light and material changes).
//
//   gistream-web [--server ADDR] [--listen HOST:PORT] [--scene NAME]
//                [--solver NAME] [--param K=V]... [--size WxH] [--fps F]
//                [--tls] [--ca FILE] [--cert FILE --key FILE] [--token TOKEN]
//                [--allow-origin ORIGIN]... [--max-connections N]
//                [--max-viewers N] [--solvers NAME,...] [--page-params NAME,...|none]
//                [--max-messages N] [--metrics-listen HOST:PORT]
//                [--viewer-tokens FILE] [--version]
// The upstream channel to gistreamd takes the CLI's TLS and token options
// (client/connection.h); the token defaults to $GISTREAM_TOKEN.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <sys/resource.h>

#include <grpcpp/grpcpp.h>

#include "connection.h"
#include "http_server.h"
#include "util/log.h"
#include "util/version.h"

namespace {

// "a,b,,c" -> {"a", "b", "c"}.
std::vector<std::string> Split(const std::string& list) {
  std::vector<std::string> out;
  for (size_t begin = 0; begin <= list.size();) {
    const size_t end = std::min(list.find(',', begin), list.size());
    if (end > begin) out.push_back(list.substr(begin, end - begin));
    begin = end + 1;
  }
  return out;
}

int Usage() {
  std::cerr
      << "usage: gistream-web [--server ADDR] [--listen HOST:PORT] [--scene NAME]\n"
         "                    [--scenes NAME,NAME,...] [--solver NAME] [--param K=V]...\n"
         "                    [--size WxH] [--fps F] [--tls] [--ca FILE]\n"
         "                    [--cert FILE --key FILE] [--token TOKEN] [--allow-origin ORIGIN]...\n"
         "                    [--max-connections N] [--max-viewers N] [--solvers NAME,...]\n"
         "                    [--page-params NAME,...|none] [--max-messages N]\n"
         "                    [--metrics-listen HOST:PORT] [--viewer-tokens FILE]\n"
         "--tls/--ca/--cert/--key/--token: the channel to gistreamd, as in gistream\n"
         "(token default $GISTREAM_TOKEN).\n"
         "--scenes: the page's scene picker (default: the bundled scenes).\n"
         "--solver NAME: the solver a page opens on (default antiradiance).\n"
         "--solvers NAME,NAME,...: the solvers a page may pick (default: all the server's);\n"
         "--page-params NAME,...|none: the parameters a page may set (default: all; the\n"
         "gateway's --param values stay for the rest); --max-messages N: messages a\n"
         "page may send a second (default 120; beyond, dropped and the page told).\n"
         "--allow-origin ORIGIN: a site whose pages may open the viewer's WebSocket\n"
         "(repeatable; '*' any; default: this gateway's own origin only).\n"
         "--fps F: 0 (the server's cap) to 240; --size WxH: 1x1 to 8192x8192.\n"
         "--max-connections N: connections still sending their request (default 256;\n"
         "at the limit a new one closes the oldest); --max-viewers N: WebSocket\n"
         "viewers at once (default 64; beyond: 503). Both 1 to 100000.\n"
         "--metrics-listen HOST:PORT: serve Prometheus metrics on http://HOST:PORT/metrics\n"
         "(a port of its own, not the viewers'; default off).\n"
         "--viewer-tokens FILE: viewers must present a token of FILE (gistreamd's\n"
         "--auth-tokens format): the page is opened as http://HOST:PORT/#token=TOKEN\n"
         "(default: no viewer tokens; the Origin check alone).\n"
         "--version: print the version and exit.\n"
         "Serves the viewer on http://HOST:PORT/ (default 127.0.0.1:8080), bridged to\n"
         "gistreamd at --server (default $GISTREAM_SERVER, else 127.0.0.1:50051).\n";
  return 2;
}

// What the command line says.
struct WebFlags {
  std::string server;
  gistream::client::ConnectionOptions upstream;
  // A GI solver by default: the page shows what the product is for
  // (colour bleeding, soft indirect light), not direct light alone.
  std::string listen = "127.0.0.1:8080", scene = "cornell_box", solver = "antiradiance";
  std::vector<std::string> allowed_solvers;  // empty: every solver the server lists
  // The scene picker's choices: the bundled scenes unless --scenes says.
  std::string scenes = "cornell_box,cornell_box_coarse,indirect_room,dynamic_block,furnace";
  unsigned width = 640, height = 480;
  float fps = 30.0f;
  gistream::v1::SessionConfig config;
  gistream::web::ViewerOptions options;
};

// A number flag's value in [min, max], else an error naming the flag.
std::optional<double> ParseNumber(const std::string& flag, const std::string& value, double min,
                                  double max) {
  char* end = nullptr;
  const double n = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !(n >= min && n <= max)) {
    std::cerr << "gistream-web: " << flag << ": '" << value << "' is not a number from " << min
              << " to " << max << "\n";
    return std::nullopt;
  }
  return n;
}

// One flag with its value; an exit code when it is wrong.
std::optional<int> ApplyFlag(const std::string& flag, const std::string& value, WebFlags& f) {
  using namespace gistream;
  if (flag == "--server") {
    f.server = value;
  } else if (flag == "--listen") {
    f.listen = value;
  } else if (flag == "--scene") {
    f.scene = value;
  } else if (flag == "--scenes") {
    f.scenes = value;
  } else if (flag == "--solver") {
    f.solver = value;
  } else if (flag == "--fps") {
    const std::optional<double> n = ParseNumber(flag, value, 0.0, 240.0);
    if (!n) return Usage();
    f.fps = float(*n);
  } else if (flag == "--size") {
    char tail = 0;
    if (std::sscanf(value.c_str(), "%ux%u%c", &f.width, &f.height, &tail) != 2 || f.width == 0 ||
        f.height == 0 || f.width > 8192 || f.height > 8192) {
      std::cerr << "gistream-web: --size: '" << value << "' is not WxH from 1x1 to 8192x8192\n";
      return Usage();
    }
  } else if (flag == "--max-connections" || flag == "--max-viewers") {
    const std::optional<double> n = ParseNumber(flag, value, 1.0, 100000.0);
    if (!n) return Usage();
    if (*n != std::floor(*n)) {
      std::cerr << "gistream-web: " << flag << ": '" << value << "' is not a whole number\n";
      return Usage();
    }
    (flag == "--max-viewers" ? f.options.max_viewers : f.options.max_pending_connections) =
        size_t(*n);
  } else if (flag == "--solvers") {
    f.allowed_solvers = Split(value);
    if (f.allowed_solvers.empty()) return Usage();
  } else if (flag == "--page-params") {
    f.options.page_params_limited = true;
    if (value != "none") f.options.page_params = Split(value);
  } else if (flag == "--max-messages") {
    const std::optional<double> n = ParseNumber(flag, value, 1.0, 10000.0);
    if (!n) return Usage();
    f.options.max_messages_per_second = *n;
  } else if (flag == "--viewer-tokens") {
    absl::StatusOr<AuthTokens> tokens = AuthTokens::Load(value);
    if (!tokens.ok()) {
      std::cerr << "gistream-web: --viewer-tokens: " << tokens.status().message() << "\n";
      return 2;
    }
    f.options.viewer_tokens = std::make_shared<const AuthTokens>(*std::move(tokens));
  } else if (flag == "--metrics-listen") {
    f.options.metrics_listen = value;
  } else if (flag == "--allow-origin") {
    f.options.allowed_origins.push_back(value);
  } else if (flag == "--ca" || flag == "--cert" || flag == "--key") {
    absl::StatusOr<std::string> pem = client::ReadPem(flag, value);
    if (!pem.ok()) {
      std::cerr << "gistream-web: " << pem.status().message() << "\n";
      return 2;
    }
    (flag == "--ca"     ? f.upstream.ca_pem
     : flag == "--cert" ? f.upstream.cert_pem
                        : f.upstream.key_pem) = *pem;
    f.upstream.tls = true;
  } else if (flag == "--token") {
    f.upstream.token = value;
  } else if (flag == "--param") {
    const size_t eq = value.find('=');
    if (eq == std::string::npos) return Usage();
    (*f.config.mutable_params())[value.substr(0, eq)] = value.substr(eq + 1);
  } else {
    return Usage();
  }
  return std::nullopt;
}

// The command line (and $GISTREAM_SERVER, $GISTREAM_TOKEN); an exit code
// when it asks to exit (--help, --version) or is wrong.
std::optional<int> ParseFlags(int argc, char** argv, WebFlags& f) {
  const char* env = std::getenv("GISTREAM_SERVER");
  f.server = env && *env ? env : "127.0.0.1:50051";
  if (const char* token = std::getenv("GISTREAM_TOKEN"); token != nullptr) {
    f.upstream.token = token;
  }
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--help" || flag == "-h") return Usage(), 0;
    if (flag == "--version") {
      std::cout << "gistream-web " << gistream::Version() << std::endl;
      return 0;
    }
    if (flag == "--tls") {
      f.upstream.tls = true;
      continue;
    }
    if (i + 1 >= argc) return Usage();
    if (std::optional<int> exit = ApplyFlag(flag, argv[++i], f)) return exit;
  }
  return std::nullopt;
}

// The backend: its channel, the page's scene loaded, its solvers (only
// --solvers' when given); an exit code when it cannot serve.
std::optional<int> ConnectBackend(WebFlags& f) {
  using namespace gistream;
  web::ViewerOptions& options = f.options;
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(256 << 20);
  // A restarted backend is found within 2 s (gRPC's default back-off
  // grows to 120 s), for /healthz and the viewers' reconnection.
  args.SetInt(GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS, 500);
  args.SetInt(GRPC_ARG_MIN_RECONNECT_BACKOFF_MS, 500);
  args.SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS, 2000);
  f.upstream.server = f.server;
  auto channel = client::MakeChannel(f.upstream, args);
  options.stub = v1::Gistream::NewStub(channel);
  options.backend = std::make_shared<web::BackendHealth>(channel, f.server);
  v1::LoadSceneRequest load;
  load.set_name(f.scene);
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(120));
  if (grpc::Status s = options.stub->LoadScene(&context, load, &options.scene); !s.ok()) {
    std::cerr << "error: LoadScene " << f.scene << " on " << f.server << ": " << s.error_message()
              << "\n";
    return 1;
  }
  grpc::ClientContext list_context;
  list_context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
  if (grpc::Status s =
          options.stub->ListSolvers(&list_context, v1::ListSolversRequest(), &options.solvers);
      !s.ok()) {
    std::cerr << "error: ListSolvers on " << f.server << ": " << s.error_message() << "\n";
    return 1;
  }
  if (!f.allowed_solvers.empty()) {
    // The page's picker offers these alone, and a page asking for another
    // is refused (viewer_bridge.h).
    v1::ListSolversResponse offered;
    for (const std::string& name : f.allowed_solvers) {
      const auto& all = options.solvers.solvers();
      const auto it = std::find_if(all.begin(), all.end(),
                                   [&](const v1::SolverInfo& s) { return s.name() == name; });
      if (it == all.end()) {
        std::cerr << "gistream-web: --solvers: the server has no solver '" << name << "'\n";
        return 2;
      }
      *offered.add_solvers() = *it;
    }
    options.solvers = std::move(offered);
  }
  if (std::none_of(options.solvers.solvers().begin(), options.solvers.solvers().end(),
                   [&](const v1::SolverInfo& s) { return s.name() == f.solver; })) {
    std::cerr << "gistream-web: --solver " << f.solver << " is not among the offered solvers\n";
    return 2;
  }
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace gistream;
  // Every descriptor the hard limit allows (connections are bounded by
  // --max-connections and --max-viewers; running out is handled too).
  if (rlimit files{}; getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur < files.rlim_max) {
    files.rlim_cur = files.rlim_max;
    setrlimit(RLIMIT_NOFILE, &files);
  }
  WebFlags f;
  if (std::optional<int> exit = ParseFlags(argc, argv, f)) return *exit;
  if (std::optional<int> exit = ConnectBackend(f)) return *exit;
  web::ViewerOptions& options = f.options;
  f.config.set_scene_id(options.scene.scene_id());
  options.scene_name = f.scene;
  options.scene_names = Split(f.scenes);
  if (std::find(options.scene_names.begin(), options.scene_names.end(), f.scene) ==
      options.scene_names.end()) {
    options.scene_names.insert(options.scene_names.begin(), f.scene);
  }
  f.config.set_solver(f.solver);
  f.config.set_width(f.width);
  f.config.set_height(f.height);
  f.config.mutable_continuous()->set_max_fps(f.fps);
  options.config = f.config;
  return web::Serve(f.listen, options, [&](const std::string& bound) {
    std::cout << "serving http://" << bound << "/ (scene " << options.scene.scene_id() << " on "
              << f.server << ")" << std::endl;
    Log(LogLevel::kInfo, "gistream-web " + std::string(Version()) + " serving http://" + bound +
                             "/ for gistreamd " + f.server);
  });
}
