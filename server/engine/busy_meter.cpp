#include "engine/busy_meter.h"

#include <algorithm>

namespace gistream {

void BusyMeter::AddBusy(Clock::time_point start, Clock::time_point end) {
  if (end <= start) return;
  std::lock_guard lock(mutex_);
  if (!any_) {
    first_ = start;
    any_ = true;
  }
  busy_.emplace_back(start, end);
  // Keep one window (the oldest interval may straddle its start).
  while (!busy_.empty() && busy_.front().second < end - window_) busy_.pop_front();
}

double BusyMeter::Ratio(Clock::time_point now) const {
  std::lock_guard lock(mutex_);
  if (!any_) return 0.0;
  const Clock::time_point from = std::max(now - window_, first_);
  if (now <= from) return 0.0;
  Clock::duration busy{0};
  for (const auto& [start, end] : busy_) {
    const Clock::time_point a = std::max(start, from), b = std::min(end, now);
    if (b > a) busy += b - a;
  }
  return std::clamp(std::chrono::duration<double>(busy).count() /
                        std::chrono::duration<double>(now - from).count(),
                    0.0, 1.0);
}

}  // namespace gistream
