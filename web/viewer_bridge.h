// One browser's WebSocket bridged to one gistreamd Session (continuous
// pacing) on the gateway's scene. Browser -> server: JSON text messages
// (camera, light, material, key_frame) become Updates with the browser's
// sequence numbers, and `config` (solver + parameters from the picker)
// replaces the browser's session with a new one, `scene` (a name from the
// picker) loads that scene and moves the browser's session onto it;
// server -> browser: the scene description (text, again after `scene`),
// then every frame as a binary message: a 4-byte little-endian header
// length, a JSON header (frame number, last update seq, size, format,
// key_frame, unchanged, total_ms, stage timings) and the image bytes.
// A browser that reads slower than frames come loses frames: JPEG frames
// are replaced by newer ones; for H.264 the queued frames are dropped and
// a key frame is requested (delta frames would not decode).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/http.hpp>

#include "gistream/v1/gistream.grpc.pb.h"

#include "backend_health.h"
#include "util/auth_tokens.h"

namespace gistream::web {

struct ViewerOptions {
  std::shared_ptr<v1::Gistream::Stub> stub;
  v1::LoadSceneResponse scene;
  v1::ListSolversResponse solvers;  // for the page's solver picker
  v1::SessionConfig config;         // scene id, solver, params, size, pacing; encoding per browser
  // The scene names (in the server's scene directory) the page's scene
  // picker offers; `scene_name` is the one loaded first.
  std::vector<std::string> scene_names;
  std::string scene_name;
  // Origins whose pages may open /ws ("*": any). Empty: the gateway's own
  // origin alone (Origin equal to http:// or https:// + the Host header).
  // A request without Origin (not a browser) is let through.
  std::vector<std::string> allowed_origins;
  // Connections still sending their request (--max-connections): at the
  // limit a new one closes the oldest of them, so connections that never
  // finish a request cannot keep others (or /healthz) out.
  size_t max_pending_connections = 256;
  // Viewers (WebSocket sessions) at once (--max-viewers); beyond, an
  // upgrade is answered 503.
  size_t max_viewers = 64;
  // What a page may choose (issue 30): the solvers of `solvers` (filtered
  // by --solvers) and, when `page_params_limited`, only the parameters
  // named in `page_params` (--page-params); the rest keep the gateway's
  // --param values or the server's defaults. Anything else is refused.
  std::vector<std::string> page_params;
  bool page_params_limited = false;
  // Messages a page may send per second (a token bucket with twice that
  // as its burst): beyond, they are dropped and the page told once a second.
  double max_messages_per_second = 120.0;
  // The backend's health, polled (backend_health.h): /healthz answers 503
  // while it does not serve. Null: /healthz answers for the gateway alone.
  std::shared_ptr<const BackendHealth> backend;
  // Where /metrics is served (--metrics-listen HOST:PORT; empty: nowhere).
  std::string metrics_listen;
  // The viewers' tokens (--viewer-tokens FILE, gistreamd's token-file
  // format): when set, a WebSocket upgrade must carry one (ViewerToken),
  // else 401. Null: no viewer authentication (the Origin check alone).
  std::shared_ptr<const AuthTokens> viewer_tokens;
};

// The WebSocket subprotocol the page offers and the gateway selects, and
// the prefix of the one that carries a viewer token: browsers cannot set
// headers on a WebSocket, so the page offers "gistream" and
// "gistream.token.<base64url of the token>".
inline constexpr char kSubprotocol[] = "gistream";
inline constexpr char kTokenSubprotocolPrefix[] = "gistream.token.";

// The viewer token an upgrade request carries: `Authorization: Bearer T`
// (non-browser clients) or the token subprotocol; nullopt when neither.
std::optional<std::string> ViewerToken(
    const boost::beast::http::request<boost::beast::http::string_body>& request);

// Viewers running now (each holds a gistreamd session).
size_t LiveViewers();

// Takes over the socket of an HTTP upgrade request to /ws (query:
// format=jpeg|h264) and runs until either side closes. `who`: the viewer
// token's name, for log lines (empty without viewer tokens).
void StartViewer(boost::asio::ip::tcp::socket socket,
                 boost::beast::http::request<boost::beast::http::string_body> request,
                 const ViewerOptions& options, std::string who);

}  // namespace gistream::web
