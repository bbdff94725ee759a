// gistream status: the server's device, version, resources and sessions.
#include <iostream>

#include <absl/strings/str_cat.h>
#include <absl/strings/str_join.h>

#include "commands.h"
#include "connection.h"
#include "text_table.h"

namespace gistream::client {
namespace {

std::string Mib(uint64_t bytes) {
  return absl::StrCat(FormatFixed(double(bytes) / (1 << 20), 1), " MiB");
}

std::string Uptime(double seconds) {
  const uint64_t s = uint64_t(seconds);
  return absl::StrCat(s / 3600, "h ", (s / 60) % 60, "m ", s % 60, "s");
}

}  // namespace

absl::Status RunStatus(const ConnectionOptions& connection_options, const StatusOptions&) {
  Connection connection(connection_options);
  v1::ServerStatus status;
  GS_RETURN_IF_ERROR(
      connection.Call(&v1::Gistream::Stub::GetServerStatus, v1::GetServerStatusRequest(), &status));
  std::cout << "server           " << connection.server()
            << (status.instance().empty() ? ""
                                          : absl::StrCat(" (instance ", status.instance(), ")"))
            << "\n"
            << "version          " << (status.version().empty() ? "-" : status.version()) << "\n"
            << "uptime           " << Uptime(status.uptime_s()) << "\n"
            << "GL vendor        " << status.gl_vendor() << "\n"
            << "GL renderer      " << status.gl_renderer() << "\n"
            << "GL version       " << status.gl_version() << "\n"
            << "CPU              " << status.cpu_model() << " (" << status.cpu_threads()
            << " threads), " << FormatFixed(status.cpu_seconds(), 1) << " s used\n"
            << "memory           RSS " << Mib(status.rss_bytes()) << " (peak "
            << Mib(status.peak_rss_bytes()) << "), GL objects " << Mib(status.gl_object_bytes())
            << ", budget " << Mib(status.memory_budget_used_bytes()) << " of "
            << Mib(status.memory_budget_limit_bytes());
  if (status.gpu_memory_total_bytes() > 0 || status.gpu_memory_available_bytes() > 0) {
    std::cout << ", GPU " << Mib(status.gpu_memory_available_bytes()) << " free of "
              << Mib(status.gpu_memory_total_bytes());
  }
  std::cout << "\n"
            << "scenes           " << status.scenes()
            << (status.scene_ids().empty()
                    ? std::string()
                    : absl::StrCat(" (", absl::StrJoin(status.scene_ids(), ", "), ")"))
            << "\n"
            << "frames rendered  " << status.frames_rendered() << "\n"
            << "sessions         " << status.sessions() << "\n";
  if (status.session_status_size() > 0) {
    TextTable table({{"session"},
                     {"scene"},
                     {"solver"},
                     {"size"},
                     {"frames", TextTable::Align::kRight},
                     {"fps", TextTable::Align::kRight},
                     {"dropped", TextTable::Align::kRight},
                     {"pending", TextTable::Align::kRight},
                     {"last seq", TextTable::Align::kRight}});
    for (const v1::SessionStatus& s : status.session_status()) {
      table.AddRow({s.session_id(), s.scene_id(), s.solver(),
                    absl::StrCat(s.width(), "x", s.height()), absl::StrCat(s.frames()),
                    FormatFixed(s.fps(), 1), absl::StrCat(s.dropped_frames()),
                    absl::StrCat(s.pending_updates()), absl::StrCat(s.last_update_seq())});
    }
    std::cout << "\n" << table.Render("  ");
  }
  return absl::OkStatus();
}

}  // namespace gistream::client
