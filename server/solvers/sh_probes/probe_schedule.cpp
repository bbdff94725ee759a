#include "solvers/sh_probes/probe_schedule.h"

#include <algorithm>
#include <numeric>
#include <tuple>

namespace gistream {

void ProbeSchedule::Reset(int probes) {
  order_.resize(size_t(probes));
  std::iota(order_.begin(), order_.end(), 0);
  raster_.assign(size_t(probes), 0);
  direct_.assign(size_t(probes), 0);
  next_ = 0;
  pending_ = false;
  sweeps_ = 0;
  change_ = last_change_ = 0.0;
  cap_reached_ = false;
}

void ProbeSchedule::Prioritize(const std::vector<int32_t>& seen,
                               const std::vector<glm::vec3>& positions, const glm::vec3& eye) {
  auto key = [&](int p) {
    const glm::vec3 d = positions[size_t(p)] - eye;
    return std::tuple(-int64_t(seen[size_t(p)]), glm::dot(d, d), p);
  };
  std::sort(order_.begin(), order_.end(), [&](int a, int b) { return key(a) < key(b); });
  next_ = 0;
  pending_ = true;
  sweeps_ = 0;
  change_ = 0.0;
  cap_reached_ = false;
}

void ProbeSchedule::NeedRaster(int probe) {
  raster_[size_t(probe)] = 1;
  direct_[size_t(probe)] = 1;
  pending_ = true;
}

void ProbeSchedule::NeedDirectAll() {
  std::fill(direct_.begin(), direct_.end(), uint8_t(1));
  pending_ = !order_.empty();
  sweeps_ = 0;
  cap_reached_ = false;
}

int ProbeSchedule::Units(int probe) const {
  return kBounceUnits + (raster_[size_t(probe)] ? kRasterUnits : 0) +
         (direct_[size_t(probe)] ? kDirectUnits : 0);
}

bool ProbeSchedule::raster_pending() const {
  return std::any_of(raster_.begin(), raster_.end(), [](uint8_t f) { return f != 0; });
}

bool ProbeSchedule::AnyFlag() const {
  return std::any_of(raster_.begin(), raster_.end(), [](uint8_t f) { return f != 0; }) ||
         std::any_of(direct_.begin(), direct_.end(), [](uint8_t f) { return f != 0; });
}

ProbeSchedule::Batch ProbeSchedule::Peek() const {
  Batch batch;
  if (!pending_) return batch;
  for (size_t i = next_; i < order_.size(); ++i) {
    const int p = order_[i];
    const int units = Units(p);
    if (!batch.probes.empty() && batch.units + units > kBatchUnits) break;
    batch.probes.push_back(p);
    if (raster_[size_t(p)]) batch.raster.push_back(p);
    if (direct_[size_t(p)]) batch.direct.push_back(p);
    batch.units += units;
  }
  return batch;
}

void ProbeSchedule::Done(const Batch& batch, double change, double total, double tolerance,
                         int max_sweeps) {
  for (int p : batch.probes) raster_[size_t(p)] = direct_[size_t(p)] = 0;
  next_ += batch.probes.size();
  change_ += change;
  if (next_ < order_.size()) return;
  // The end of a sweep.
  ++sweeps_;
  last_change_ = total > 0.0 ? change_ / total : 0.0;
  change_ = 0.0;
  next_ = 0;
  const bool settled = last_change_ < tolerance && !AnyFlag();
  cap_reached_ = !settled && sweeps_ >= max_sweeps && !AnyFlag();
  if (settled || cap_reached_) pending_ = false;
}

}  // namespace gistream
