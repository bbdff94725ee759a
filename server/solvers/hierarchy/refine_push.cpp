#include "solvers/hierarchy/refine_push.h"

#include <algorithm>

#include "util/parallel_for.h"

namespace gistream::hierarchy {
namespace {

constexpr float kPi = 3.14159265358979f;
// A bin covered at least this much counts as fully covered.
constexpr float kSnapCoverage = 0.5f;

}  // namespace

LeafLinks RefinePush(const Elements& elements, const CubeBins& bins, const BinTable& table,
                     bool environment, RefineStats* stats) {
  const size_t leaves = size_t(elements.leaf_count());
  struct Row {
    std::vector<uint32_t> source;
    std::vector<float> weight;
    std::vector<uint16_t> env_bin;
    std::vector<float> env_weight;
    uint64_t blocked = 0, empty = 0;
  };
  std::vector<Row> rows(leaves);
  ParallelFor(leaves, 32, [&](size_t leaf) {
    Row& row = rows[leaf];
    const glm::vec3 n = elements.normal[leaf];
    const glm::vec3 p = elements.position[leaf];
    const float cosine_sum = bins.CosineSum(n);
    const float norm = cosine_sum > 0.0f ? kPi / cosine_sum : 0.0f;
    int chain[64];
    int depth = 0;
    for (int node = int(leaf); node >= 0 && depth < 64; node = elements.parent[size_t(node)]) {
      chain[depth++] = node;
    }
    for (int b = 0; b < bins.count(); ++b) {
      const float c = glm::dot(n, bins.Direction(b));
      if (!(c > 0.0f)) continue;
      // Refinement: the shortest link of this bin along the ancestor chain
      // wins; coverage adds up over the levels the links were made at.
      uint64_t best = BinTable::kEmpty;
      uint32_t covered = 0;
      for (int k = 0; k < depth; ++k) {
        best = std::min(best, table.Entry(chain[k], b));
        covered = std::min(covered + table.Coverage(chain[k], b), BinTable::kFullCoverage);
      }
      // Eq. 5 assumes the closest element covers its bin. We hold to it
      // where the bin is mostly covered (the measured sum scatters around 1
      // on a closed surface, and each bin's shortfall would be light lost),
      // and weigh by the measured coverage where it is not (small or
      // distant elements, silhouettes).
      const float measured = float(covered) / float(BinTable::kFullCoverage);
      const float cover = measured >= kSnapCoverage ? 1.0f : measured;
      const float quadrature = norm * c * bins.SolidAngle(b);
      if (best == BinTable::kEmpty) {
        ++row.empty;
      } else {
        const int src = BinTable::Other(best);
        // The source sends light only from its front (a back face blocks).
        if (glm::dot(elements.normal[size_t(src)], p - elements.position[size_t(src)]) > 0.0f) {
          const float w = quadrature * cover;
          if (w > 0.0f) {
            row.source.push_back(uint32_t(src));
            row.weight.push_back(w);
          }
        } else {
          ++row.blocked;
        }
      }
      if (environment && cover < 1.0f) {
        row.env_bin.push_back(uint16_t(b));
        row.env_weight.push_back(quadrature * (1.0f - cover));
      }
    }
  });
  LeafLinks out;
  out.offset.assign(leaves + 1, 0);
  out.env_offset.assign(environment ? leaves + 1 : 0, 0);
  RefineStats s;
  for (size_t i = 0; i < leaves; ++i) {
    out.offset[i + 1] = out.offset[i] + uint32_t(rows[i].source.size());
    if (environment) out.env_offset[i + 1] = out.env_offset[i] + uint32_t(rows[i].env_bin.size());
    s.blocked_bins += rows[i].blocked;
    s.empty_bins += rows[i].empty;
  }
  out.source.resize(out.offset.back());
  out.weight.resize(out.offset.back());
  if (environment) {
    out.env_bin.resize(out.env_offset.back());
    out.env_weight.resize(out.env_offset.back());
  }
  ParallelFor(leaves, 64, [&](size_t i) {
    std::copy(rows[i].source.begin(), rows[i].source.end(), out.source.begin() + out.offset[i]);
    std::copy(rows[i].weight.begin(), rows[i].weight.end(), out.weight.begin() + out.offset[i]);
    if (environment) {
      std::copy(rows[i].env_bin.begin(), rows[i].env_bin.end(), out.env_bin.begin() + out.env_offset[i]);
      std::copy(rows[i].env_weight.begin(), rows[i].env_weight.end(),
                out.env_weight.begin() + out.env_offset[i]);
    }
  });
  s.leaf_links = out.source.size();
  if (stats) *stats = s;
  return out;
}

}  // namespace gistream::hierarchy
