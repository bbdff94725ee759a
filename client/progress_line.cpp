#include "progress_line.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

#include <absl/strings/str_cat.h>

namespace gistream::client {
namespace {

std::string Duration(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  if (s < 60) return absl::StrCat(s, "s");
  if (s < 3600) return absl::StrCat(s / 60, "m", s % 60 < 10 ? "0" : "", s % 60, "s");
  return absl::StrCat(s / 3600, "h", (s % 3600) / 60 < 10 ? "0" : "", (s % 3600) / 60, "m");
}

}  // namespace

std::string FormatProgressLine(const std::string& what, std::chrono::duration<double> elapsed,
                               std::optional<double> fraction, int width) {
  std::string line;
  if (fraction) {
    const double f = std::clamp(*fraction, 0.0, 1.0);
    constexpr int kBar = 20;
    const int filled = int(std::floor(f * kBar));
    line =
        absl::StrCat("[", std::string(size_t(filled), '#'), std::string(size_t(kBar - filled), '.'),
                     "] ", int(std::floor(f * 100.0)), "% ", what);
    absl::StrAppend(&line, f > 0.0
                               ? absl::StrCat(", ETA ", Duration(elapsed.count() * (1.0 - f) / f))
                               : ", ETA ?");
  } else {
    line = absl::StrCat(what, "... ", Duration(elapsed.count()));
  }
  if (width > 3 && int(line.size()) > width) line = line.substr(0, size_t(width - 3)) + "...";
  return line;
}

ProgressLine::ProgressLine()
    : ProgressLine(stderr, isatty(fileno(stderr)) != 0, std::chrono::milliseconds(1000)) {}

ProgressLine::ProgressLine(std::FILE* out, bool enabled, std::chrono::milliseconds delay)
    : out_(out), enabled_(enabled), delay_(delay) {
  if (enabled_) ticker_ = std::thread([this] { Run(); });
}

ProgressLine::~ProgressLine() {
  if (!enabled_) return;
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    EraseLocked();
  }
  cv_.notify_all();
  ticker_.join();
}

void ProgressLine::Wait(std::string what) {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  what_ = std::move(what);
  fraction_.reset();
  started_ = Clock::now();
  active_ = true;
  if (drawn_) DrawLocked();  // an earlier wait was showing: replace its text now
}

void ProgressLine::Update(std::string what, double fraction) {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  if (!active_) started_ = Clock::now();
  what_ = std::move(what);
  fraction_ = fraction;
  active_ = true;
  if (drawn_) DrawLocked();
}

void ProgressLine::Done() {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  active_ = false;
  EraseLocked();
}

void ProgressLine::Run() {
  std::unique_lock lock(mutex_);
  while (!stop_) {
    cv_.wait_for(lock, std::chrono::milliseconds(250));
    if (stop_) break;
    if (active_ && Clock::now() - started_ >= delay_) DrawLocked();
  }
}

void ProgressLine::DrawLocked() {
  const std::string line = FormatProgressLine(what_, Clock::now() - started_, fraction_);
  // Carriage return, the line, then clear to the end of the line.
  std::fprintf(out_, "\r%s\033[K", line.c_str());
  std::fflush(out_);
  drawn_ = true;
}

void ProgressLine::EraseLocked() {
  if (!drawn_) return;
  std::fprintf(out_, "\r\033[K");
  std::fflush(out_);
  drawn_ = false;
}

}  // namespace gistream::client
