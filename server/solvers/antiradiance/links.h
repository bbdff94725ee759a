// `link`: the refinement oracle of Dachsbacher et al. 2007, Section 3.2.
// Starting from every pair of roots (a root with itself is a self-link,
// always subdivided into all pairs of children), a link is subdivided
// (the larger of sender and receiver) while the sender or receiver covers
// more than one bin's solid angle as seen from the other, and stored once
// both are small enough or both are leaves. Links are directed sender ->
// receiver; a pair facing each other gets one in each direction (the
// paper's bidirectional link between positive-hemisphere bins, Fig. 7a),
// a sender behind the receiver's plane none (the receiver only gathers
// over its positive hemisphere, Fig. 7b). Runs on the CPU, as in the paper.
#pragma once

#include <cstdint>
#include <vector>

#include "solvers/hierarchy/directional_bins.h"
#include "solvers/antiradiance/patches.h"

namespace gistream::antiradiance {

struct Link {
  uint32_t sender = 0;
  uint32_t receiver = 0;
  uint16_t sender_bin = 0;    // omega_l: direction receiver - sender
  uint16_t receiver_bin = 0;  // omega_j: direction sender - receiver (incident, "from")
  uint16_t cone = 0;          // spreading level (hierarchy::DirectionalBins::Row)
  // Eq. 17: 1 / (|x_i - x_k|^2 omega_bin), times the true / bin cosines;
  // near leaves: from the sender cell's exact form factor (links.cpp).
  float form_factor = 0.0f;
};

struct LinkStats {
  uint64_t node_pairs = 0;           // oracle calls
  uint64_t spread = 0;               // links with cone level > 0
  uint64_t exact = 0;                // near leaf links with the cell's exact form factor
  uint64_t root_pairs = 0;           // (receiver root, sender root) pairs
  uint64_t relinked_root_pairs = 0;  // of those, linked by the last call
};

// Sorted by receiver. Multi-threaded over pairs of roots.
std::vector<Link> CreateLinks(const Patches& patches, const hierarchy::DirectionalBins& bins,
                              LinkStats* stats);

// The links kept per pair of roots, so that moving objects relink only the
// pairs that touch a moved root (Section 3.3: "we only have to update
// links to and from moving objects"). The hierarchy's layout must stay the
// same between calls (same roots, same node ids), only positions change.
class LinkSet {
 public:
  // Links every pair.
  void Build(const Patches& patches, const hierarchy::DirectionalBins& bins);
  // Relinks the pairs whose receiver or sender root has moved[root index].
  void Relink(const Patches& patches, const hierarchy::DirectionalBins& bins,
              const std::vector<bool>& moved);
  // All links, sorted by receiver then sender.
  std::vector<Link> Sorted() const;
  const LinkStats& stats() const { return stats_; }
  uint64_t size() const;
  // At most this many links: once the pairs linked so far hold more, the
  // pairs not started are left empty and exceeded() is true (the caller
  // refuses the set), so a scene whose links would not fit stops within a
  // pair of the limit instead of building them all first (the 2-cylinder
  // engine of Khronos' samples built 2.8 GiB of links for a minute before
  // it was refused). Default: no limit.
  void set_max_links(uint64_t max_links) { max_links_ = max_links; }
  bool exceeded() const { return exceeded_; }

 private:
  void LinkPairs(const Patches& patches, const hierarchy::DirectionalBins& bins,
                 const std::vector<size_t>& pairs);

  size_t roots_ = 0;
  std::vector<std::vector<Link>> per_pair_;  // receiver root x roots + sender root
  std::vector<uint64_t> pair_node_pairs_, pair_spread_, pair_exact_;
  LinkStats stats_;
  uint64_t max_links_ = ~uint64_t(0);
  bool exceeded_ = false;
};

}  // namespace gistream::antiradiance
