// gistream-web's HTTP side (Boost.Beast, one I/O thread): GET / serves the
// embedded viewer page, /ws upgrades to a WebSocket bridged to a gistreamd
// session (viewer_bridge.h) when the page's Origin is allowed, else 403;
// /healthz answers "ok" while gistreamd serves (backend_health.h), else
// 503 naming why. A request's headers must come within 10 s.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "viewer_bridge.h"

namespace gistream::web {

// Whether a WebSocket upgrade with header `origin` (empty when absent) to
// a gateway reached as `host` (the Host header) may proceed:
// ViewerOptions::allowed_origins.
bool OriginAllowed(const std::string& origin, const std::string& host,
                   const std::vector<std::string>& allowed);

// Listens on `address` ("HOST:PORT"; port 0 picks one), calls `on_listening`
// with the bound address, then serves until the process ends.
int Serve(const std::string& address, const ViewerOptions& options,
          const std::function<void(const std::string&)>& on_listening);

}  // namespace gistream::web
