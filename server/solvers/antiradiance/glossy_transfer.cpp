#include "solvers/antiradiance/glossy_transfer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "absl/strings/str_cat.h"
#include "solvers/brdf_albedo.h"
#include "util/parallel_for.h"
#include "util/constants.h"

namespace gistream::antiradiance {
namespace {

constexpr int kSubSamples = 7;  // a bin's centre and six around it
constexpr int kScalingIterations = 64;

// Two unit vectors completing unit n to an orthonormal frame.
void Frame(const glm::vec3& n, glm::vec3* u, glm::vec3* v) {
  const glm::vec3 a = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  *u = glm::normalize(glm::cross(a, n));
  *v = glm::cross(n, *u);
}

using Key = std::array<float, 8>;  // base colour, metallic, roughness, normal

}  // namespace

std::vector<int> GlossyTransfer::Slots(const Patches& patches,
                                       const std::vector<shading::Brdf>& brdf) {
  std::vector<int> slot(size_t(patches.size()), -1);
  int next = 0;
  for (int i : patches.Leaves()) {
    if (size_t(i) < brdf.size() && !brdf[size_t(i)].Lambertian()) slot[size_t(i)] = next++;
  }
  return slot;
}

absl::StatusOr<GlossyTransfer> GlossyTransfer::Build(const Patches& patches,
                                                     const hierarchy::DirectionalBins& bins,
                                                     const std::vector<shading::Brdf>& brdf,
                                                     uint64_t max_bytes) {
  GlossyTransfer g;
  g.m_ = bins.count();
  g.slot_ = Slots(patches, brdf);
  // One matrix per distinct (material, normal).
  std::map<Key, uint32_t> index;
  std::vector<int> first_node;  // per matrix, a node that has it
  for (int i = 0; i < patches.size(); ++i) {
    if (g.slot_[size_t(i)] < 0) continue;
    const shading::Brdf& b = brdf[size_t(i)];
    const glm::vec3& n = patches.normal[size_t(i)];
    const Key key = {
        b.base_color.r, b.base_color.g, b.base_color.b, b.metallic, b.roughness, n.x, n.y, n.z};
    auto [it, inserted] = index.try_emplace(key, uint32_t(first_node.size()));
    if (inserted) first_node.push_back(i);
    g.matrix_of_slot_.push_back(it->second);
  }
  const uint64_t half = uint64_t(g.m_ / 2 + 1);
  const uint64_t bound = uint64_t(first_node.size()) * half * half * sizeof(glm::vec3);
  if (bound > max_bytes) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "params.bins: ", first_node.size(), " glossy (material, normal) pairs x ", g.m_,
        " bins need about ", bound >> 20, " MiB of BRDF transfer matrices (limit ", max_bytes >> 20,
        " MiB); use fewer bins"));
  }
  g.matrices_.resize(first_node.size());
  const float min_roughness = bins.ResolvedRoughness();
  ParallelFor(first_node.size(), 1, [&](size_t mi) {
    const int node = first_node[mi];
    g.matrices_[mi] =
        BuildMatrix(bins, patches.normal[size_t(node)], brdf[size_t(node)], min_roughness);
  });
  return g;
}

GlossyTransfer::Matrix GlossyTransfer::BuildMatrix(const hierarchy::DirectionalBins& bins,
                                                   const glm::vec3& n,
                                                   const shading::Brdf& material,
                                                   float min_roughness) {
  const float omega = bins.omega_bin();
  shading::Brdf blurred = material;
  blurred.roughness = std::max(material.roughness, min_roughness);
  Matrix mat;
  double s = 0.0;  // S(n), transport.h
  for (int j = 0; j < bins.count(); ++j) {
    const float c = glm::dot(n, bins.direction(j));
    if (c > 0.0f) mat.hemisphere.push_back(uint16_t(j)), s += c;
  }
  const float pi_over_s = kPi / float(s * omega);
  const size_t h = mat.hemisphere.size();
  const std::vector<glm::vec3> wo = SubSampleDirections(bins, n, mat.hemisphere);
  std::vector<glm::vec3> kernel = BlurredKernel(blurred, wo, h);
  // Symmetric scaling K' = D K D (Sinkhorn-Knopp, damped by the square
  // root) so that every row reflects the true directional albedo under
  // uniform light: sum_j K'[o][j] <n|omega_j> omega_bin = albedo(omega_o).
  // K' stays symmetric, so each column (what one incident bin sends out)
  // carries the same albedo: uniform light gives albedo(omega_o) per bin
  // and no incident bin leaves with more than albedo(omega_j) of its flux.
  std::vector<glm::vec3> albedo(h), d(h, glm::vec3(1.0f));
  std::vector<float> cw(h);
  for (size_t o = 0; o < h; ++o) {
    const float c = wo[o * kSubSamples].z;
    cw[o] = c * omega;
    albedo[o] = BrdfDirectionalAlbedo(material.base_color, material.metallic, material.roughness, c,
                                      material.specular_f0, material.specular_f90);
  }
  for (int it = 0; it < kScalingIterations; ++it) {
    for (size_t o = 0; o < h; ++o) {
      glm::vec3 row(0.0f);
      for (size_t j = 0; j < h; ++j) row += kernel[o * h + j] * d[j] * cw[j];
      for (int ch = 0; ch < 3; ++ch) {
        const float r = d[o][ch] * row[ch];
        d[o][ch] = r > 0.0f ? d[o][ch] * std::sqrt(albedo[o][ch] / r) : 0.0f;
      }
    }
  }
  // T[o][j] = K'[o][j] <n|omega_j> omega_bin pi / S(n) (the bins' cosine
  // correction, as the diffuse K: uniform L_in = 1 gives albedo pi / S).
  mat.t.resize(h * h);
  for (size_t o = 0; o < h; ++o) {
    for (size_t j = 0; j < h; ++j) {
      mat.t[o * h + j] = d[o] * kernel[o * h + j] * d[j] * (cw[j] * pi_over_s);
    }
  }
  return mat;
}

std::vector<glm::vec3> GlossyTransfer::SubSampleDirections(
    const hierarchy::DirectionalBins& bins, const glm::vec3& n,
    const std::vector<uint16_t>& hemisphere) {
  const float sub_radius = 0.5f * std::sqrt(bins.omega_bin() / kPi);  // half the bin's radius
  glm::vec3 tu, tv;
  Frame(n, &tu, &tv);
  auto local = [&](const glm::vec3& d) {
    return glm::vec3(glm::dot(d, tu), glm::dot(d, tv), glm::dot(d, n));
  };
  // The exitant bins' sub-sample directions, local frame.
  std::vector<glm::vec3> wo(hemisphere.size() * kSubSamples);
  for (size_t o = 0; o < hemisphere.size(); ++o) {
    const glm::vec3 d = bins.direction(hemisphere[o]);
    glm::vec3 du, dv;
    Frame(d, &du, &dv);
    wo[o * kSubSamples] = local(d);
    for (int q = 1; q < kSubSamples; ++q) {
      const float phi = 2.0f * kPi * float(q) / float(kSubSamples - 1);
      const glm::vec3 e =
          glm::normalize(d + sub_radius * (std::cos(phi) * du + std::sin(phi) * dv));
      wo[o * kSubSamples + size_t(q)] = local(e);
    }
  }
  return wo;
}

std::vector<glm::vec3> GlossyTransfer::BlurredKernel(const shading::Brdf& blurred,
                                                     const std::vector<glm::vec3>& wo, size_t h) {
  // K[o][j]: the blurred BRDF averaged over the sub-samples of one end,
  // then symmetrized (f is reciprocal, so K = (A + A^T) / 2 is the mean
  // over both ends' sub-samples).
  std::vector<glm::vec3> kernel(h * h, glm::vec3(0.0f));
  for (size_t o = 0; o < h; ++o) {
    for (size_t j = 0; j < h; ++j) {
      glm::vec3 f(0.0f);
      for (int q = 0; q < kSubSamples; ++q) {
        f += shading::Eval(blurred, wo[o * kSubSamples + size_t(q)], wo[j * kSubSamples]);
      }
      kernel[o * h + j] = f / float(kSubSamples);
    }
  }
  for (size_t o = 0; o < h; ++o) {
    for (size_t j = 0; j < o; ++j) {
      const glm::vec3 mean = 0.5f * (kernel[o * h + j] + kernel[j * h + o]);
      kernel[o * h + j] = kernel[j * h + o] = mean;
    }
  }
  return kernel;
}

void GlossyTransfer::Reflect(int s, const glm::vec3* l_in, glm::vec3* out) const {
  const Matrix& mat = matrices_[matrix_of_slot_[size_t(s)]];
  std::fill(out, out + m_, glm::vec3(0.0f));
  const size_t h = mat.hemisphere.size();
  for (size_t o = 0; o < h; ++o) {
    const glm::vec3* row = &mat.t[o * h];
    glm::vec3 sum(0.0f);
    for (size_t j = 0; j < h; ++j) sum += row[j] * l_in[mat.hemisphere[j]];
    out[mat.hemisphere[o]] = sum;
  }
}

uint64_t GlossyTransfer::bytes() const {
  uint64_t b = slot_.size() * sizeof(int) + matrix_of_slot_.size() * sizeof(uint32_t);
  for (const Matrix& mat : matrices_) {
    b += mat.hemisphere.size() * sizeof(uint16_t) + mat.t.size() * sizeof(glm::vec3);
  }
  return b;
}

}  // namespace gistream::antiradiance
