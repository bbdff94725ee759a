#include "solvers/antiradiance/links.h"

#include <algorithm>
#include <atomic>
#include <array>
#include <cmath>
#include <span>
#include <tuple>

#include "util/cancellation.h"
#include "util/parallel_for.h"
#include "util/constants.h"

namespace gistream::antiradiance {
namespace {

// Leaf pairs closer than this many times the sum of their bounding radii
// take the exact point-to-polygon form factor of the sender's cell.
constexpr float kNearLink = 8.0f;
// Farther than this many times the sum of their radii, a link's kernel is
// averaged over both nodes' sigma points (SigmaPoints); closer (leaves
// without cells only), the disc kernel r^2 + a / pi keeps it finite.
constexpr float kSigmaLink = 2.0f;
// A near sender's cell quads are cut at most this many times per side
// (AddNearLinks).
constexpr int kMaxNearSplit = 16;

// A node's area as a few weighted points with its centroid and second
// moment (the sigma points of its area distribution): c +- sqrt(n) L_k for
// the n non-degenerate columns L_k of the moment's Cholesky factor, each of
// weight 1 / (2 n). Averaging the kernel over them is exact to second
// order in the node's extent (odd terms cancel), where one point at the
// centre (Eq. 17) is exact to zeroth order only.
struct SigmaPoints {
  std::array<glm::vec3, 6> p{};
  int count = 0;
};

// Per node: whether all its leaves share its normal (a leaf always), so one
// cosine holds for the whole node; per leaf: S(n) (CosineSum);
// sigma points of what it sends (the leaves' cells) and of where it
// receives (the leaves' centres, where the light is collocated).
struct NodeGeometry {
  std::vector<uint8_t> flat;
  std::vector<float> cosine_sum;
  std::vector<SigmaPoints> send, receive;
};

// Area, centroid and second moment about the origin of a set of points.
struct Moments {
  double area = 0.0;
  glm::dvec3 first{0.0};
  glm::dmat3 second{0.0};
  void Add(double a, const glm::dvec3& c, const glm::dmat3& m) {
    area += a;
    first += a * c;
    second += a * m;
  }
};

// The area moments of a leaf's cell (about the origin, per unit area):
// a triangle's E[x x^T] = (sum v_i v_i^T + s s^T) / 12 with s = sum v_i.
Moments CellMoments(std::span<const CellQuad> cell) {
  Moments m;
  for (const CellQuad& q : cell) {
    for (int t = 0; t < 2; ++t) {
      const glm::dvec3 a(q[0]), b(q[size_t(t + 1)]), c(q[size_t(t + 2)]);
      const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
      if (!(area > 0.0)) continue;
      const glm::dvec3 s = a + b + c;
      const glm::dmat3 e = (glm::outerProduct(a, a) + glm::outerProduct(b, b) +
                            glm::outerProduct(c, c) + glm::outerProduct(s, s)) /
                           12.0;
      m.Add(area, s / 3.0, e);
    }
  }
  return m;
}

SigmaPoints Sigma(const Moments& m) {
  SigmaPoints out;
  if (!(m.area > 0.0)) return out;
  const glm::dvec3 c = m.first / m.area;
  const glm::dmat3 cov = m.second / m.area - glm::outerProduct(c, c);
  // Cholesky, skipping pivots that vanish (a flat or linear node).
  const double scale = std::max(1e-30, cov[0][0] + cov[1][1] + cov[2][2]);
  std::array<glm::dvec3, 3> cols{};
  int n = 0;
  glm::dmat3 a = cov;
  for (int k = 0; k < 3; ++k) {
    if (!(a[k][k] > 1e-9 * scale)) continue;
    const glm::dvec3 col = a[k] / std::sqrt(a[k][k]);
    a -= glm::outerProduct(col, col);
    cols[size_t(n++)] = col;
  }
  if (n == 0) {
    out.p[0] = glm::vec3(c);
    out.count = 1;
    return out;
  }
  for (int k = 0; k < n; ++k) {
    const glm::dvec3 d = std::sqrt(double(n)) * cols[size_t(k)];
    out.p[size_t(out.count++)] = glm::vec3(c + d);
    out.p[size_t(out.count++)] = glm::vec3(c - d);
  }
  return out;
}

// S(n) = omega sum_j <n|omega_j>_+, the bins' cosine integral (~pi).
float CosineSum(const glm::vec3& n, const hierarchy::DirectionalBins& b) {
  double s = 0.0;
  for (int j = 0; j < b.count(); ++j) s += std::max(0.0f, glm::dot(n, b.direction(j)));
  return float(s * b.omega_bin());
}

NodeGeometry Geometry(const Patches& p, const hierarchy::DirectionalBins& b) {
  NodeGeometry g;
  g.flat.assign(size_t(p.size()), 1);
  g.cosine_sum.assign(size_t(p.size()), 0.0f);
  std::vector<Moments> send(size_t(p.size())), receive(size_t(p.size()));
  for (int i = p.size() - 1; i >= 0; --i) {  // children follow their parent
    const glm::vec3& n = p.normal[size_t(i)];
    if (p.is_leaf(i)) {
      g.cosine_sum[size_t(i)] = CosineSum(n, b);
      const glm::dvec3 x(p.position[size_t(i)]);
      const double a = p.area[size_t(i)];
      receive[size_t(i)].Add(a, x, glm::outerProduct(x, x));
      const Moments cell = CellMoments(p.Cell(i));
      send[size_t(i)] = cell.area > 0.0 ? cell : receive[size_t(i)];
      // Scaled to the leaf's area, so clusters weigh leaves as pull does.
      if (cell.area > 0.0) {
        const double k = a / cell.area;
        send[size_t(i)].area *= k, send[size_t(i)].first *= k, send[size_t(i)].second *= k;
      }
      continue;
    }
    for (int c : p.children[size_t(i)]) {
      if (c < 0) continue;
      if (!g.flat[size_t(c)] || glm::dot(p.normal[size_t(c)], n) < 0.99999f) g.flat[size_t(i)] = 0;
      for (auto* m : {&send, &receive}) {
        const Moments& mc = (*m)[size_t(c)];
        (*m)[size_t(i)].area += mc.area;
        (*m)[size_t(i)].first += mc.first;
        (*m)[size_t(i)].second += mc.second;
      }
    }
  }
  g.send.resize(size_t(p.size()));
  g.receive.resize(size_t(p.size()));
  for (size_t i = 0; i < size_t(p.size()); ++i) {
    g.send[i] = Sigma(send[i]);
    g.receive[i] = Sigma(receive[i]);
  }
  return g;
}

class Linker {
 public:
  Linker(const Patches& p, const hierarchy::DirectionalBins& b, const NodeGeometry& g,
         std::vector<Link>& out)
      : p_(p),
        bins_(b),
        geometry_(g),
        out_(out),
        bin_radius_(std::sqrt(b.omega_bin() / 3.14159265f)) {}

  void Refine(int recv, int send) {
    // The job's cancellation (util/cancellation.h), every 4096 pairs.
    if (stopped_ || ((++pairs_ & 4095) == 0 && (stopped_ = Cancelled()))) return;
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
    AddLink(recv, send, d / r, r, ts);
  }

  uint64_t pairs_ = 0, spread_ = 0, exact_ = 0;
  bool stopped_ = false;

 private:
  // The cosines a link between flat ends carries (AddLink).
  struct LinkEnds {
    bool flat_send = false, flat_recv = false;
    float sender_cos = 0.0f, sender_bin_cos = 0.0f;  // flat senders: |cosines|
    float receiver_cos = 1.0f, gathered = 1.0f;
  };

  // The link from `send` to `recv`, which see each other within a bin's
  // solid angle: w the unit direction from receiver to sender, r their
  // distance, ts the sender's half-angle.
  void AddLink(int recv, int send, const glm::vec3& w, float r, float ts) {
    if (NearLeaves(recv, send, r) && ts > bin_radius_) {
      AddNearLinks(recv, send, ts);
      return;
    }
    Link l;
    LinkEnds ends;
    if (!Oriented(recv, send, w, ts, l, ends)) return;
    if (l.cone > 0) ++spread_;
    bool exact = false;
    const double k = LinkFormFactor(recv, send, w, r, ends, &exact);
    if (!(k > 0.0) || !std::isfinite(k)) return;
    l.form_factor = float(k);
    if (exact) ++exact_;
    out_.push_back(l);
  }

  // A link from `send` to `recv` along w (receiver to sender) with the
  // bins toward each other and the cone of half-angle ts, oriented on both
  // ends; false: no link.
  bool Oriented(int recv, int send, const glm::vec3& w, float ts, Link& l, LinkEnds& ends) const {
    l.sender = uint32_t(send);
    l.receiver = uint32_t(recv);
    l.sender_bin = uint16_t(bins_.Find(-w));
    l.receiver_bin = uint16_t(bins_.Find(w));
    l.cone = uint16_t(bins_.ConeLevel(ts));
    return OrientSender(send, w, l, ends) && OrientReceiver(recv, w, l, ends);
  }

  // The bins' main directions stand for the true ones: their cosines
  // differ, and near a node's horizon the nearest bin can lie on the other
  // side (a sender's radiance read from its antiradiance bins, a
  // receiver's light put where it never gathers). For a node whose leaves
  // share one normal (`flat`), the link takes the nearest bin on the true
  // side and is scaled by true / bin cosine on both ends, so it carries
  // the cosines of Eq. 17 exactly. False: no link.
  bool OrientSender(int send, const glm::vec3& w, Link& l, LinkEnds& ends) const {
    ends.flat_send = geometry_.flat[size_t(send)] != 0;
    if (!ends.flat_send) return true;
    const glm::vec3& n = p_.normal[size_t(send)];
    const float c = glm::dot(n, -w);
    if (c == 0.0f) return false;  // in the sender's plane: nothing leaves that way
    l.sender_bin = uint16_t(BinOnSide(-w, n, c > 0.0f, l.sender_bin));
    ends.sender_cos = std::abs(c);
    ends.sender_bin_cos = std::abs(glm::dot(n, bins_.direction(l.sender_bin)));
    return ends.sender_bin_cos > 1e-6f;
  }

  // What the receiver's leaves gather of a unit L_in spread from
  // receiver_bin: sum of tap weight x cosine over the front taps.
  bool OrientReceiver(int recv, const glm::vec3& w, Link& l, LinkEnds& ends) const {
    ends.flat_recv = geometry_.flat[size_t(recv)] != 0;
    if (!ends.flat_recv) return true;
    const glm::vec3& n = p_.normal[size_t(recv)];
    ends.receiver_cos = glm::dot(n, w);
    if (ends.receiver_cos <= 0.0f) return false;  // behind every leaf of it
    if (l.cone == 0) l.receiver_bin = uint16_t(BinOnSide(w, n, true, l.receiver_bin));
    ends.gathered = 0.0f;
    const auto [begin, end] = bins_.Row(l.cone, l.receiver_bin);
    for (auto* t = begin; t != end; ++t)
      ends.gathered += t->weight * std::max(0.0f, glm::dot(n, bins_.direction(t->bin)));
    return ends.gathered > 1e-6f;
  }

  // Leaves close enough for the exact form factor of the sender's cell.
  bool NearLeaves(int recv, int send, float r) const {
    return p_.is_leaf(recv) && p_.is_leaf(send) && !p_.Cell(send).empty() &&
           r < kNearLink * (p_.radius[size_t(send)] + p_.radius[size_t(recv)]);
  }

  // A near sender wider than a bin, seen from the receiver (a ceiling leaf
  // a centimetre above a lamp spans most of its hemisphere): one link per
  // piece of its cell, each with its own bins toward that piece and its
  // exact form factor, so the light it sends and the antiradiance that
  // cancels it leave over the directions the sender covers, not along its
  // centre's bin alone (the pieces' form factors sum to the cell's). Each
  // cell quad is cut n x n, n from the sender's angular size in bins; links
  // that land in the same bins merge.
  void AddNearLinks(int recv, int send, float ts) {
    const int n = std::clamp(int(std::ceil(ts / bin_radius_)), 1, kMaxNearSplit);
    const glm::vec3 x = p_.position[size_t(recv)];
    const size_t first = out_.size();
    for (const CellQuad& q : p_.Cell(send)) {
      for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
          const CellQuad piece = SubQuad(q, n, i, j);
          const glm::vec3 c = 0.25f * (piece[0] + piece[1] + piece[2] + piece[3]);
          const float r = glm::length(c - x);
          if (!(r > 0.0f)) continue;
          float piece_radius = 0.0f;
          for (const glm::vec3& v : piece)
            piece_radius = std::max(piece_radius, glm::length(v - c));
          AddPieceLink(recv, send, (c - x) / r,
                       piece_radius >= r ? 1.5707963f : std::asin(piece_radius / r),
                       std::span<const CellQuad>(&piece, 1));
        }
      }
    }
    MergeSameBins(first);
  }

  // One piece's link: AddLink's exact branch with the piece's form factor.
  void AddPieceLink(int recv, int send, const glm::vec3& w, float ts,
                    std::span<const CellQuad> piece) {
    Link l;
    LinkEnds ends;
    if (!Oriented(recv, send, w, ts, l, ends)) return;
    const double f =
        PointToQuadsFormFactor(piece, p_.position[size_t(recv)], p_.normal[size_t(recv)]);
    const double k = ExactFactor(recv, send, w, f, ends);
    if (!(k > 0.0) || !std::isfinite(k)) return;
    l.form_factor = float(k);
    out_.push_back(l);
  }

  // Links out_[first...] with the same bins and cone carry the same ends'
  // cosines: one link with their summed factors. Counted once each.
  void MergeSameBins(size_t first) {
    auto begin = out_.begin() + std::ptrdiff_t(first);
    const auto key = [](const Link& l) { return std::tuple(l.sender_bin, l.receiver_bin, l.cone); };
    std::sort(begin, out_.end(), [&](const Link& a, const Link& b) { return key(a) < key(b); });
    size_t kept = first;
    for (size_t k = first; k < out_.size(); ++k) {
      if (kept > first && key(out_[kept - 1]) == key(out_[k])) {
        out_[kept - 1].form_factor += out_[k].form_factor;
      } else {
        out_[kept++] = out_[k];
      }
    }
    out_.resize(kept);
    if (kept > first) {
      ++exact_;
      if (std::any_of(out_.begin() + std::ptrdiff_t(first), out_.end(),
                      [](const Link& l) { return l.cone > 0; }))
        ++spread_;
    }
  }

  // Corner quad (i, j) of quad q cut n x n (bilinear; a planar convex quad
  // gives planar convex pieces).
  static CellQuad SubQuad(const CellQuad& q, int n, int i, int j) {
    const auto at = [&](int a, int b) {
      const float u = float(a) / float(n), v = float(b) / float(n);
      return (1 - u) * (1 - v) * q[0] + u * (1 - v) * q[1] + u * v * q[2] + (1 - u) * v * q[3];
    };
    return {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
  }

  // The exact branch's factor for form factor f of (part of) the sender's
  // cell: the receiver gathers E = pi L f. The global pass gives
  // E = (pi / S_r) omega_bin gathered F I_ex with I_ex = a |c_bin| B / S_s
  // (radiance, L = B / pi) or a |c_bin| L (antiradiance).
  double ExactFactor(int recv, int send, const glm::vec3& w, double f, const LinkEnds& ends) const {
    const bool radiance = glm::dot(p_.normal[size_t(send)], -w) > 0.0f;
    double k =
        f * geometry_.cosine_sum[size_t(recv)] /
        (double(bins_.omega_bin()) * ends.gathered * p_.area[size_t(send)] * ends.sender_bin_cos);
    if (radiance) k *= geometry_.cosine_sum[size_t(send)] / kPi;
    return k;
  }

  // The link's transfer factor; *exact when it is a near pair's exact
  // form factor.
  double LinkFormFactor(int recv, int send, const glm::vec3& w, float r, const LinkEnds& ends,
                        bool* exact) const {
    const float rs = p_.radius[size_t(send)], rr = p_.radius[size_t(recv)];
    const std::span<const CellQuad> cell = p_.Cell(send);
    if (NearLeaves(recv, send, r)) {
      // Near leaves: the exact form factor F_pt of the sender's cell.
      const double f =
          PointToQuadsFormFactor(cell, p_.position[size_t(recv)], p_.normal[size_t(recv)]);
      *exact = true;
      return ExactFactor(recv, send, w, f, ends);
    }
    double k;
    if (r > kSigmaLink * (rs + rr)) {
      // Eq. 17's kernel <n_k|-w> <n_i|w> / r^2 averaged over both nodes'
      // sigma points (the true cosines on a flat end; a curved end's bins
      // carry its cosines), exact to second order in the nodes' extent.
      k = SigmaKernel(send, recv, ends.flat_send, ends.flat_recv) / double(bins_.omega_bin());
      if (ends.flat_send) k /= ends.sender_bin_cos;
      if (ends.flat_recv) k /= ends.gathered;
    } else {
      // Eq. 17, with the sender as a disc of its area: r^2 + a_k / pi keeps
      // the exchange finite (point-to-disc form factor) where leaves almost
      // touch.
      k = 1.0 / ((double(r) * r + p_.area[size_t(send)] / kPi) * bins_.omega_bin());
      if (ends.flat_send) k *= ends.sender_cos / ends.sender_bin_cos;
      // A flat receiver gathers `gathered` where the true cosine is due; the
      // spread part behind it is lost (scaling by the front share, as before
      // for leaves, is the special case of equal cosines).
      if (ends.flat_recv) k *= ends.receiver_cos / ends.gathered;
    }
    // Not scaled by S_r S_s / pi^2 (the bins' cosine integrals, as the near
    // links are): that makes a uniform field gather exactly pi (1.00002 per
    // pass) but the iterated furnace then reads +7 % at rho = 0.99, since
    // the hierarchy's per-leaf errors (a cluster's light pushed to its
    // leaves unchanged, -8 ... +10 %) have a non-uniform mode that gathers
    // more than the uniform one (docs/ARCHITECTURE.md, antiradiance's Energy).
    return k;
  }

  // Find(d), or when that bin is not on the wanted side of normal n (or
  // in its plane), the nearest bin that is.
  int BinOnSide(const glm::vec3& d, const glm::vec3& n, bool front, int found) const {
    const float c = glm::dot(n, bins_.direction(found));
    if (front ? c > 0.0f : c < 0.0f) return found;
    int best = found;
    float best_dot = -2.0f;
    for (int j = 0; j < bins_.count(); ++j) {
      const float cj = glm::dot(n, bins_.direction(j));
      if (!(front ? cj > 0.0f : cj < 0.0f)) continue;
      const float dj = glm::dot(d, bins_.direction(j));
      if (dj > best_dot) best_dot = dj, best = j;
    }
    return best;
  }

  // The mean over sender x receiver sigma points of Eq. 17's kernel,
  // cos_s cos_r / d^2, with a flat end's true cosine (clamped at its
  // horizon) or 1 for a curved end.
  double SigmaKernel(int send, int recv, bool flat_send, bool flat_recv) const {
    const SigmaPoints& s = geometry_.send[size_t(send)];
    const SigmaPoints& q = geometry_.receive[size_t(recv)];
    // The sender's side that faces the receiver: its front for radiance,
    // its back for antiradiance (Eq. 19).
    glm::dvec3 ns(p_.normal[size_t(send)]);
    if (glm::dot(ns, glm::dvec3(p_.position[size_t(recv)] - p_.position[size_t(send)])) < 0.0)
      ns = -ns;
    const glm::dvec3 nr(p_.normal[size_t(recv)]);
    double sum = 0.0;
    for (int a = 0; a < s.count; ++a) {
      for (int b = 0; b < q.count; ++b) {
        const glm::dvec3 d = glm::dvec3(q.p[size_t(b)]) - glm::dvec3(s.p[size_t(a)]);
        const double d2 = glm::dot(d, d);
        if (!(d2 > 0.0)) continue;
        const double inv = 1.0 / std::sqrt(d2);
        const double cs = flat_send ? std::max(0.0, glm::dot(ns, d) * inv) : 1.0;
        const double cr = flat_recv ? std::max(0.0, -glm::dot(nr, d) * inv) : 1.0;
        sum += cs * cr / d2;
      }
    }
    return s.count > 0 && q.count > 0 ? sum / double(s.count * q.count) : 0.0;
  }

  // Whether any part of sender's bounding sphere is in front of leaf recv.
  bool SenderInFront(int recv, int send) const {
    const float h =
        glm::dot(p_.normal[size_t(recv)], p_.position[size_t(send)] - p_.position[size_t(recv)]);
    return h + p_.radius[size_t(send)] > 0.0f;
  }

  const Patches& p_;
  const hierarchy::DirectionalBins& bins_;
  const NodeGeometry& geometry_;
  std::vector<Link>& out_;
  float bin_radius_;
};

}  // namespace

void LinkSet::LinkPairs(const Patches& patches, const hierarchy::DirectionalBins& bins,
                        const std::vector<size_t>& pairs) {
  const NodeGeometry geometry = Geometry(patches, bins);
  // The links of the pairs kept, then each linked pair's as it ends.
  uint64_t kept = size();
  for (size_t pair : pairs) kept -= per_pair_[pair].size();
  std::atomic<uint64_t> total{kept};
  std::atomic<bool> over{kept > max_links_};
  ParallelFor(pairs.size(), 1, [&](size_t k) {
    const size_t pair = pairs[k];
    std::vector<Link>& out = per_pair_[pair];
    out.clear();
    pair_node_pairs_[pair] = pair_spread_[pair] = pair_exact_[pair] = 0;
    if (over.load(std::memory_order_relaxed)) return;  // refused anyway
    Linker linker(patches, bins, geometry, out);
    linker.Refine(patches.roots[pair / roots_], patches.roots[pair % roots_]);
    pair_node_pairs_[pair] = linker.pairs_;
    pair_spread_[pair] = linker.spread_;
    pair_exact_[pair] = linker.exact_;
    if (total.fetch_add(out.size()) + out.size() > max_links_) over = true;
  });
  exceeded_ = over;
  stats_ = {};
  for (size_t p = 0; p < per_pair_.size(); ++p) {
    stats_.node_pairs += pair_node_pairs_[p];
    stats_.spread += pair_spread_[p];
    stats_.exact += pair_exact_[p];
  }
  stats_.root_pairs = per_pair_.size();
  stats_.relinked_root_pairs = pairs.size();
}

void LinkSet::Build(const Patches& patches, const hierarchy::DirectionalBins& bins) {
  roots_ = patches.roots.size();
  per_pair_.assign(roots_ * roots_, {});
  pair_node_pairs_.assign(per_pair_.size(), 0);
  pair_spread_.assign(per_pair_.size(), 0);
  pair_exact_.assign(per_pair_.size(), 0);
  std::vector<size_t> all(per_pair_.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = i;
  LinkPairs(patches, bins, all);
}

void LinkSet::Relink(const Patches& patches, const hierarchy::DirectionalBins& bins,
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

std::vector<Link> CreateLinks(const Patches& patches, const hierarchy::DirectionalBins& bins,
                              LinkStats* stats) {
  LinkSet set;
  set.Build(patches, bins);
  if (stats != nullptr) *stats = set.stats();
  return set.Sorted();
}

}  // namespace gistream::antiradiance
