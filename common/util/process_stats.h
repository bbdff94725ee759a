// This process's resource use, for status reports and metrics: resident and
// peak resident memory (/proc/self/status VmRSS, VmHWM), user + system CPU
// time (getrusage), and time since start. Linux only; fields it cannot read
// stay 0.
#pragma once

#include <cstdint>

namespace gistream {

struct ProcessStats {
  uint64_t rss_bytes = 0;
  uint64_t peak_rss_bytes = 0;
  double cpu_seconds = 0.0;
  double uptime_s = 0.0;           // since the process started (steady clock)
  double start_time_unix_s = 0.0;  // when it started, seconds since the epoch
};

ProcessStats ReadProcessStats();

}  // namespace gistream
