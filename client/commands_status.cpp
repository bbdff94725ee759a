// gistream status
#include <iostream>

#include <absl/strings/str_cat.h>
#include <absl/strings/str_join.h>

#include "commands.h"
#include "connection.h"

namespace gistream::client {

absl::Status RunStatus(const ConnectionOptions& connection_options, const StatusOptions&) {
  Connection connection(connection_options);
  v1::ServerStatus status;
  GS_RETURN_IF_ERROR(
      connection.Call(&v1::Gistream::Stub::GetServerStatus, v1::GetServerStatusRequest(), &status));
  std::cout << "server           " << connection.server() << "\n"
            << "GL vendor        " << status.gl_vendor() << "\n"
            << "GL renderer      " << status.gl_renderer() << "\n"
            << "GL version       " << status.gl_version() << "\n"
            << "CPU              " << status.cpu_model() << " (" << status.cpu_threads()
            << " threads)\n"
            << "sessions         " << status.sessions() << "\n"
            << "scenes           " << status.scenes()
            << (status.scene_ids().empty()
                    ? std::string()
                    : absl::StrCat(" (", absl::StrJoin(status.scene_ids(), ", "), ")"))
            << "\n"
            << "frames rendered  " << status.frames_rendered() << "\n";
  return absl::OkStatus();
}

}  // namespace gistream::client
