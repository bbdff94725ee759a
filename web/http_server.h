// gistream-web's HTTP side (Boost.Beast, one I/O thread): GET / serves the
// embedded viewer page, /ws upgrades to a WebSocket bridged to a gistreamd
// session (viewer_bridge.h), /healthz answers "ok".
#pragma once

#include <functional>
#include <string>

#include "viewer_bridge.h"

namespace gistream::web {

// Listens on `address` ("HOST:PORT"; port 0 picks one), calls `on_listening`
// with the bound address, then serves until the process ends.
int Serve(const std::string& address, const ViewerOptions& options,
          const std::function<void(const std::string&)>& on_listening);

}  // namespace gistream::web
