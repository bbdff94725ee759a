// Every element's 6 x N x N cube-map bins (Section 4.2.2): each bin keeps
// only the shortest link seen so far, the implicit visibility. Links are
// offered concurrently by the linking threads, so a bin is one 64-bit
// atomic holding (distance bits << 32 | other node): an atomic minimum keeps
// the shortest link whatever the order (ties go to the lower node id), so
// the result is deterministic.
//
// Besides the paper's shortest link, each bin sums the projected solid
// angle of every element offered to it ("coverage", in 1/65536 of the bin,
// saturating at the whole bin): how much of the bin is filled by geometry.
// The gather uses it where Eq. 5's assumption that the closest element
// covers its bin does not hold (see ARCHITECTURE.md).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>

namespace gistream::hierarchy {

class BinTable {
 public:
  static constexpr uint64_t kEmpty = ~uint64_t(0);
  static constexpr uint32_t kFullCoverage = 65536;

  // Clears to `nodes` x `bins` empty bins (reuses the allocation).
  void Reset(int nodes, int bins);
  int bins() const { return bins_; }
  int nodes() const { return nodes_; }
  uint64_t bytes() const { return uint64_t(capacity_) * (sizeof(uint64_t) + sizeof(uint32_t)); }

  // Offers the link node -> other of length `distance` (> 0, finite) in
  // `bin`, covering `coverage` (fraction of the bin's solid angle).
  void Offer(int node, int bin, float distance, int other, float coverage);

  uint64_t Entry(int node, int bin) const {
    return link_[Index(node, bin)].load(std::memory_order_relaxed);
  }
  uint32_t Coverage(int node, int bin) const {
    return coverage_[Index(node, bin)].load(std::memory_order_relaxed);
  }
  static int Other(uint64_t entry) { return int(uint32_t(entry)); }
  static float Distance(uint64_t entry);

  // Non-empty bins (links stored before refinement).
  uint64_t CountLinks() const;

 private:
  size_t Index(int node, int bin) const { return size_t(node) * size_t(bins_) + size_t(bin); }

  std::unique_ptr<std::atomic<uint64_t>[]> link_;
  std::unique_ptr<std::atomic<uint32_t>[]> coverage_;
  size_t capacity_ = 0;
  int nodes_ = 0, bins_ = 0;
};

}  // namespace gistream::hierarchy
