#include "solvers/antiradiance/links.h"

#include <algorithm>
#include <cmath>

#include "util/parallel_for.h"

namespace gistream::antiradiance {
namespace {

class Linker {
 public:
  Linker(const Patches& p, const DirectionalBins& b, std::vector<Link>& out)
      : p_(p), bins_(b), out_(out), bin_radius_(std::sqrt(b.omega_bin() / 3.14159265f)) {}

  void Refine(int recv, int send) {
    ++pairs_;
    if (recv == send) {
      // Self-links are always subdivided (Section 3.2).
      if (p_.is_leaf(recv)) return;
      const auto& c = p_.children[size_t(recv)];
      for (int a : c) {
        for (int b : c) {
          if (a >= 0 && b >= 0) Refine(a, b);
        }
      }
      return;
    }
    const glm::vec3 d = p_.position[size_t(send)] - p_.position[size_t(recv)];
    const float r = glm::length(d);
    const float rs = p_.radius[size_t(send)], rr = p_.radius[size_t(recv)];
    // A leaf receiver gathers over its positive hemisphere only (Fig. 7).
    if (p_.is_leaf(recv) && !SenderInFront(recv, send)) return;
    // Half-angles of sender and receiver seen from each other's centre.
    auto half_angle = [&](float rad) { return rad >= r ? 1.5707963f : std::asin(rad / r); };
    const float ts = half_angle(rs), tr = half_angle(rr);
    const bool split_send = !p_.is_leaf(send) && ts > bin_radius_;
    const bool split_recv = !p_.is_leaf(recv) && tr > bin_radius_;
    if (split_send || split_recv) {
      // Subdivide the larger one.
      if (split_send && (!split_recv || rs >= rr)) {
        for (int c : p_.children[size_t(send)]) {
          if (c >= 0) Refine(recv, c);
        }
      } else {
        for (int c : p_.children[size_t(recv)]) {
          if (c >= 0) Refine(c, send);
        }
      }
      return;
    }
    if (p_.is_leaf(recv) && glm::dot(p_.normal[size_t(recv)], d) <= 0.0f) return;
    if (r <= 0.0f) return;
    const glm::vec3 w = d / r;  // from receiver towards sender
    Link l;
    l.sender = uint32_t(send);
    l.receiver = uint32_t(recv);
    l.sender_bin = uint16_t(bins_.Find(-w));
    l.receiver_bin = uint16_t(bins_.Find(w));
    l.cone = uint16_t(bins_.ConeLevel(ts));
    // Eq. 17, with the sender as a disc of its area: r^2 + a_k / pi keeps the
    // exchange finite (point-to-disc form factor) where leaves almost touch.
    l.form_factor = 1.0f / ((r * r + p_.area[size_t(send)] / 3.14159265f) * bins_.omega_bin());
    if (l.cone > 0) {
      ++spread_;
      // A leaf gathers only over its positive hemisphere: scale the link so
      // that the part of the spread that lands there carries all the flux.
      if (p_.is_leaf(recv)) {
        float front = 0.0f;
        const auto [begin, end] = bins_.Row(l.cone, l.receiver_bin);
        for (auto* t = begin; t != end; ++t) {
          if (glm::dot(p_.normal[size_t(recv)], bins_.direction(t->bin)) > 0.0f) front += t->weight;
        }
        if (front <= 0.0f) return;
        l.form_factor /= front;
      }
    }
    out_.push_back(l);
  }

  uint64_t pairs_ = 0, spread_ = 0;

 private:
  // Whether any part of sender's bounding sphere is in front of leaf recv.
  bool SenderInFront(int recv, int send) const {
    const float h =
        glm::dot(p_.normal[size_t(recv)], p_.position[size_t(send)] - p_.position[size_t(recv)]);
    return h + p_.radius[size_t(send)] > 0.0f;
  }

  const Patches& p_;
  const DirectionalBins& bins_;
  std::vector<Link>& out_;
  float bin_radius_;
};

}  // namespace

void LinkSet::LinkPairs(const Patches& patches, const DirectionalBins& bins,
                        const std::vector<size_t>& pairs) {
  ParallelFor(pairs.size(), 1, [&](size_t k) {
    const size_t pair = pairs[k];
    std::vector<Link>& out = per_pair_[pair];
    out.clear();
    Linker linker(patches, bins, out);
    linker.Refine(patches.roots[pair / roots_], patches.roots[pair % roots_]);
    pair_node_pairs_[pair] = linker.pairs_;
    pair_spread_[pair] = linker.spread_;
  });
  stats_ = {};
  for (size_t p = 0; p < per_pair_.size(); ++p) {
    stats_.node_pairs += pair_node_pairs_[p];
    stats_.spread += pair_spread_[p];
  }
  stats_.root_pairs = per_pair_.size();
  stats_.relinked_root_pairs = pairs.size();
}

void LinkSet::Build(const Patches& patches, const DirectionalBins& bins) {
  roots_ = patches.roots.size();
  per_pair_.assign(roots_ * roots_, {});
  pair_node_pairs_.assign(per_pair_.size(), 0);
  pair_spread_.assign(per_pair_.size(), 0);
  std::vector<size_t> all(per_pair_.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = i;
  LinkPairs(patches, bins, all);
}

void LinkSet::Relink(const Patches& patches, const DirectionalBins& bins,
                     const std::vector<bool>& moved) {
  if (patches.roots.size() != roots_ || moved.size() != roots_) {
    Build(patches, bins);
    return;
  }
  std::vector<size_t> pairs;
  for (size_t r = 0; r < roots_; ++r) {
    for (size_t s = 0; s < roots_; ++s) {
      if (moved[r] || moved[s]) pairs.push_back(r * roots_ + s);
    }
  }
  LinkPairs(patches, bins, pairs);
}

uint64_t LinkSet::size() const {
  uint64_t total = 0;
  for (const auto& v : per_pair_) total += v.size();
  return total;
}

std::vector<Link> LinkSet::Sorted() const {
  size_t total = 0;
  for (const auto& v : per_pair_) total += v.size();
  std::vector<Link> links;
  links.reserve(total);
  for (const auto& v : per_pair_) links.insert(links.end(), v.begin(), v.end());
  std::sort(links.begin(), links.end(), [](const Link& a, const Link& b) {
    return a.receiver != b.receiver ? a.receiver < b.receiver : a.sender < b.sender;
  });
  return links;
}

std::vector<Link> CreateLinks(const Patches& patches, const DirectionalBins& bins,
                              LinkStats* stats) {
  LinkSet set;
  set.Build(patches, bins);
  if (stats != nullptr) *stats = set.stats();
  return set.Sorted();
}

}  // namespace gistream::antiradiance
