#include "util/process_stats.h"

#include <sys/resource.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>

namespace gistream {
namespace {

// Taken during static initialisation, i.e. before main().
const auto kStartSteady = std::chrono::steady_clock::now();
const auto kStartSystem = std::chrono::system_clock::now();

// "VmRSS:	  123456 kB" -> bytes.
uint64_t KibField(const std::string& line) {
  std::istringstream in(line.substr(line.find(':') + 1));
  uint64_t kib = 0;
  in >> kib;
  return kib * 1024;
}

double Seconds(const timeval& t) { return double(t.tv_sec) + double(t.tv_usec) * 1e-6; }

}  // namespace

ProcessStats ReadProcessStats() {
  ProcessStats out;
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) out.rss_bytes = KibField(line);
    if (line.rfind("VmHWM:", 0) == 0) out.peak_rss_bytes = KibField(line);
  }
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) == 0) {
    out.cpu_seconds = Seconds(usage.ru_utime) + Seconds(usage.ru_stime);
    if (out.peak_rss_bytes == 0) out.peak_rss_bytes = uint64_t(usage.ru_maxrss) * 1024;
  }
  out.uptime_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - kStartSteady).count();
  out.start_time_unix_s = std::chrono::duration<double>(kStartSystem.time_since_epoch()).count();
  return out;
}

}  // namespace gistream
