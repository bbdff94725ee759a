#include "util/memory_budget.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>

namespace gistream {

struct MemoryBudget::Reservation::Counter {
  std::atomic<uint64_t> used{0};
};

MemoryBudget::Reservation::Reservation(Reservation&& other) noexcept
    : counter_(std::move(other.counter_)), bytes_(std::exchange(other.bytes_, 0)) {}

MemoryBudget::Reservation& MemoryBudget::Reservation::operator=(Reservation&& other) noexcept {
  if (this != &other) {
    Release();
    counter_ = std::move(other.counter_);
    bytes_ = std::exchange(other.bytes_, 0);
  }
  return *this;
}

void MemoryBudget::Reservation::Release() {
  if (counter_ && bytes_ > 0) counter_->used.fetch_sub(bytes_);
  counter_.reset();
  bytes_ = 0;
}

void MemoryBudget::Reservation::Merge(Reservation&& other) {
  if (other.bytes_ == 0) return;
  GS_CHECK(!counter_ || bytes_ == 0 || counter_ == other.counter_);
  if (bytes_ == 0) counter_ = other.counter_;
  bytes_ += std::exchange(other.bytes_, 0);
  other.counter_.reset();
}

MemoryBudget::MemoryBudget(uint64_t limit_bytes, std::string name, std::string limit_name)
    : limit_(limit_bytes > 0 ? limit_bytes : DefaultMemoryLimit()),
      name_(std::move(name)),
      limit_name_(std::move(limit_name)),
      counter_(std::make_shared<Reservation::Counter>()) {}

uint64_t MemoryBudget::used() const { return counter_->used.load(); }

absl::StatusOr<MemoryBudget::Reservation> MemoryBudget::Reserve(uint64_t bytes,
                                                                const std::string& what) {
  uint64_t used = counter_->used.load();
  for (;;) {
    if (bytes > limit_ || used > limit_ - bytes) {
      const uint64_t left = used < limit_ ? limit_ - used : 0;
      return absl::ResourceExhaustedError(absl::StrCat(
          what, " needs ", FormatBytes(bytes), ", more than the ", FormatBytes(left), " left of ",
          name_, " (", limit_name_, " ", FormatBytes(limit_), ", ", FormatBytes(used), " in use)"));
    }
    if (counter_->used.compare_exchange_weak(used, used + bytes)) break;
  }
  return Reservation(counter_, bytes);
}

uint64_t CgroupMemoryLimit(const std::string& root) {
  for (const char* file : {"/memory.max", "/memory/memory.limit_in_bytes"}) {
    std::ifstream in(root + file);
    std::string value;
    if (!(in >> value)) continue;
    if (value == "max") return 0;
    char* end = nullptr;
    const unsigned long long bytes = std::strtoull(value.c_str(), &end, 10);
    return end != value.c_str() && *end == '\0' ? uint64_t(bytes) : 0;
  }
  return 0;
}

uint64_t MemoryLimitFor(uint64_t physical_bytes, uint64_t cgroup_bytes) {
  const uint64_t usable =
      cgroup_bytes > 0 ? std::min(physical_bytes, cgroup_bytes) : physical_bytes;
  return usable / 4 * 3;
}

uint64_t DefaultMemoryLimit() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  const uint64_t physical =
      pages > 0 && page_size > 0 ? uint64_t(pages) * uint64_t(page_size) : uint64_t(32) << 30;
  return MemoryLimitFor(physical, CgroupMemoryLimit());
}

std::string FormatBytes(uint64_t bytes) {
  if (bytes < 1024) return absl::StrCat(bytes, " B");
  static constexpr const char* kUnits[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  double value = double(bytes) / 1024.0;
  int unit = 0;
  while (value >= 1024.0 && unit + 1 < int(std::size(kUnits))) {
    value /= 1024.0;
    ++unit;
  }
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f %s", value, kUnits[unit]);
  return text;
}

}  // namespace gistream
