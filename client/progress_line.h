// What a command is waiting for, on one erasable stderr line: shown once a
// wait has lasted a second (loading a scene, the first frame, a reference
// rendering with a bar and an ETA), redrawn by a ticker thread while the
// command blocks in a call, erased when the wait ends or the object goes.
// Only on a terminal (isatty(stderr)); elsewhere it prints nothing, so
// logs and pipes stay clean.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace gistream::client {

// The line for `what` after `elapsed`: "loading scene x… 3s", or with a
// fraction in [0, 1] "[#####.....] 50% reference 2048/4096 spp, ETA 12s"
// (ETA from the elapsed time and the fraction done). At most `width`
// columns.
std::string FormatProgressLine(const std::string& what, std::chrono::duration<double> elapsed,
                               std::optional<double> fraction, int width = 79);

class ProgressLine {
 public:
  using Clock = std::chrono::steady_clock;

  // Draws on `out` when `enabled` (default: stderr is a terminal); a wait
  // shows after `delay`.
  ProgressLine();
  ProgressLine(std::FILE* out, bool enabled, std::chrono::milliseconds delay);
  ~ProgressLine();  // erases the line
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  // A new wait: its clock starts now.
  void Wait(std::string what);
  // The current wait's progress (fraction in [0, 1]) and text; the ETA
  // counts from the last Wait().
  void Update(std::string what, double fraction);
  // The wait ended: the line is erased.
  void Done();

  bool enabled() const { return enabled_; }

 private:
  void Run();
  void DrawLocked();
  void EraseLocked();

  std::FILE* out_;
  const bool enabled_;
  const std::chrono::milliseconds delay_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool active_ = false;
  bool drawn_ = false;
  bool stop_ = false;
  std::string what_;
  std::optional<double> fraction_;
  Clock::time_point started_;
  std::thread ticker_;
};

}  // namespace gistream::client
