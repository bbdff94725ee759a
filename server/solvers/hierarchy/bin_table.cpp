#include "solvers/hierarchy/bin_table.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "util/parallel_for.h"

namespace gistream::hierarchy {

void BinTable::Reset(int nodes, int bins) {
  nodes_ = nodes;
  bins_ = bins;
  const size_t size = size_t(nodes) * size_t(bins);
  if (size > capacity_) {
    link_ = std::make_unique<std::atomic<uint64_t>[]>(size);
    coverage_ = std::make_unique<std::atomic<uint32_t>[]>(size);
    capacity_ = size;
  }
  ParallelFor(size, 1 << 16, [&](size_t i) {
    link_[i].store(kEmpty, std::memory_order_relaxed);
    coverage_[i].store(0, std::memory_order_relaxed);
  });
}

void BinTable::Offer(int node, int bin, float distance, int other, float coverage) {
  uint32_t bits;
  std::memcpy(&bits, &distance, sizeof(bits));  // positive floats order like their bits
  const uint64_t entry = (uint64_t(bits) << 32) | uint32_t(other);
  std::atomic<uint64_t>& slot = link_[Index(node, bin)];
  uint64_t current = slot.load(std::memory_order_relaxed);
  while (entry < current &&
         !slot.compare_exchange_weak(current, entry, std::memory_order_relaxed)) {
  }
  if (!(coverage > 0.0f)) return;
  const uint32_t add = uint32_t(std::min(coverage, 1.0f) * float(kFullCoverage));
  std::atomic<uint32_t>& cov = coverage_[Index(node, bin)];
  uint32_t old = cov.load(std::memory_order_relaxed);
  while (old < kFullCoverage && !cov.compare_exchange_weak(old, std::min(old + add, kFullCoverage),
                                                           std::memory_order_relaxed)) {
  }
}

float BinTable::Distance(uint64_t entry) {
  const uint32_t bits = uint32_t(entry >> 32);
  float d;
  std::memcpy(&d, &bits, sizeof(d));
  return d;
}

uint64_t BinTable::CountLinks() const {
  const size_t size = size_t(nodes_) * size_t(bins_);
  std::atomic<uint64_t> total{0};
  const size_t chunk = 1 << 16;
  ParallelFor((size + chunk - 1) / chunk, 1, [&](size_t c) {
    uint64_t n = 0;
    for (size_t i = c * chunk; i < std::min(size, (c + 1) * chunk); ++i) {
      n += link_[i].load(std::memory_order_relaxed) != kEmpty ? 1 : 0;
    }
    total += n;
  });
  return total.load();
}

}  // namespace gistream::hierarchy
