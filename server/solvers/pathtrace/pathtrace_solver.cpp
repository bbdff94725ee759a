#include "solvers/pathtrace/pathtrace_solver.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

namespace gistream {

using pathtrace::Integrator;
using pathtrace::PathStats;
using pathtrace::Rng;

SolverDescription PathtraceSolver::Describe() {
  SolverDescription d;
  d.name = "pathtrace";
  d.description = "Unbiased progressive reference path tracer (CPU, Embree 3)";
  d.stages = {"build_bvh", "trace", "accumulate"};
  d.params = {
      {"spp", ParamType::kInt, "1", 1, 4096, {}, "Samples per pixel added each frame"},
      {"max_depth", ParamType::kInt, "64", 1, 64, {},
       "Maximum bounces (Russian roulette ends most paths earlier)"},
      {"seed", ParamType::kInt, "0", 0, 2147483647, {}, "Random seed; same seed, same image"},
      {"time_budget_ms", ParamType::kFloat, "0", 0, 600000, {},
       "When > 0: add 1-spp rounds until this much trace time is spent (at least one)"},
  };
  return d;
}

const SolverDescription& PathtraceSolver::description() const {
  static const SolverDescription kDescription = Describe();
  return kDescription;
}

absl::StatusOr<std::unique_ptr<Solver>> PathtraceSolver::Create(const ParamSet& params) {
  auto solver = std::unique_ptr<PathtraceSolver>(new PathtraceSolver());
  solver->spp_per_frame_ = params.GetInt("spp");
  solver->settings_.max_depth = params.GetInt("max_depth");
  solver->seed_ = uint64_t(params.GetInt("seed"));
  solver->time_budget_ms_ = params.GetFloat("time_budget_ms");
  return solver;
}

std::vector<std::string> PathtraceSolver::Plan(ChangeMask changes) const {
  if (changes & kChangeGeometry) return {"build_bvh", "trace", "accumulate"};
  return {"trace", "accumulate"};
}

absl::Status PathtraceSolver::Update(SolverContext& ctx, ChangeMask changes) {
  if (!bvh_ || (changes & kChangeGeometry)) {
    gl::StageTimer::Scope stage(ctx.timer, "build_bvh", /*cpu_stage=*/true);
    GS_ASSIGN_OR_RETURN(bvh_, pathtrace::SceneBvh::Build(ctx.state));
    // The environment map never changes after load (only its rotation and
    // intensity do), so its sampling distribution is built once.
    if (!env_ && ctx.state.scene().environment) {
      env_ = std::make_unique<pathtrace::EnvironmentLight>(ctx.state.scene().environment->image);
    }
  } else {
    ctx.timer.Skip("build_bvh");
    // Which triangles emit, and how much, is the light distribution: a
    // cheap pass over the triangles, no BVH rebuild.
    if (changes & kChangeEmission) bvh_->UpdateEmitters(ctx.state);
  }
  if (changes != kChangeNone) spp_total_ = 0;  // any scene change restarts
  return absl::OkStatus();
}

bool PathtraceSolver::SameView(const ViewCamera& c) const {
  return has_view_ && c.position == view_.position && c.rotation == view_.rotation &&
         c.yfov == view_.yfov && c.width == view_.width && c.height == view_.height;
}

void PathtraceSolver::TraceRound(const SceneState& state, const ViewCamera& camera, int spp) {
  const int w = int(camera.width), h = int(camera.height);
  const glm::mat4 inv = glm::inverse(camera.Projection() * camera.View());
  const Integrator integrator(state, *bvh_, env_.get(), settings_);
  const int first_sample = spp_total_;
  std::atomic<int> next_row{0};
  std::atomic<uint64_t> rays{0}, nonfinite{0};
  auto worker = [&] {
    PathStats stats;
    uint64_t bad = 0;
    for (int y = next_row++; y < h; y = next_row++) {
      for (int x = 0; x < w; ++x) {
        glm::dvec3 sum(0.0);
        for (int s = 0; s < spp; ++s) {
          const uint64_t sample = uint64_t(first_sample + s);
          Rng rng(pathtrace::Mix64(seed_ ^ pathtrace::Mix64(sample)),
                  uint64_t(y) * uint64_t(w) + uint64_t(x));
          // Pixel (x, y) counts rows from the bottom, as GL does.
          const glm::vec2 ndc((float(x) + rng.Uniform()) / float(w) * 2.0f - 1.0f,
                              (float(y) + rng.Uniform()) / float(h) * 2.0f - 1.0f);
          const glm::vec4 far = inv * glm::vec4(ndc, 0.5f, 1.0f);
          const glm::vec3 dir = glm::normalize(glm::vec3(far) / far.w - camera.position);
          const glm::vec3 li = integrator.Li(camera.position, dir, rng, stats);
          if (std::isfinite(li.r) && std::isfinite(li.g) && std::isfinite(li.b)) {
            sum += glm::dvec3(li);
          } else {
            ++bad;  // dropped and counted: never averaged into the image
          }
        }
        double* a = &accum_[(size_t(y) * size_t(w) + size_t(x)) * 3];
        a[0] += sum.x;
        a[1] += sum.y;
        a[2] += sum.z;
      }
    }
    rays += stats.rays;
    nonfinite += bad;
  };
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  spp_total_ += spp;
  rays_ += rays;
  nonfinite_ += nonfinite;
}

absl::Status PathtraceSolver::Shade(SolverContext& ctx, const ViewCamera& camera,
                                    const GBuffer& gbuffer) {
  const size_t pixels = size_t(camera.width) * size_t(camera.height);
  if (!SameView(camera) || spp_total_ == 0) {
    view_ = camera;
    has_view_ = true;
    spp_total_ = 0;
    accum_.assign(pixels * 3, 0.0);
    rays_ = 0;
    nonfinite_ = 0;
  }
  {
    gl::StageTimer::Scope stage(ctx.timer, "trace", /*cpu_stage=*/true);
    const auto start = std::chrono::steady_clock::now();
    const int before = spp_total_;
    const uint64_t rays_before = rays_;
    auto elapsed_ms = [&] {
      return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
          .count();
    };
    if (time_budget_ms_ > 0.0) {
      do {
        TraceRound(ctx.state, camera, 1);
      } while (elapsed_ms() < time_budget_ms_);
    } else {
      TraceRound(ctx.state, camera, spp_per_frame_);
    }
    last_trace_ms_ = elapsed_ms();
    last_spp_ = spp_total_ - before;
    last_rays_ = rays_ - rays_before;
  }
  gl::StageTimer::Scope stage(ctx.timer, "accumulate");
  image_.resize(pixels * 4);
  const double inv = 1.0 / double(std::max(spp_total_, 1));
  for (size_t i = 0; i < pixels; ++i) {
    image_[i * 4 + 0] = float(accum_[i * 3 + 0] * inv);
    image_[i * 4 + 1] = float(accum_[i * 3 + 1] * inv);
    image_[i * 4 + 2] = float(accum_[i * 3 + 2] * inv);
    image_[i * 4 + 3] = 1.0f;
  }
  glTextureSubImage2D(gbuffer.hdr(), 0, 0, 0, GLsizei(camera.width), GLsizei(camera.height),
                      GL_RGBA, GL_FLOAT, image_.data());
  return absl::OkStatus();
}

SolverStats PathtraceSolver::Stats() const {
  const double seconds = last_trace_ms_ * 1e-3;
  return {{"spp_total", double(spp_total_)},
          {"spp_frame", double(last_spp_)},
          {"trace_ms", last_trace_ms_},
          {"rays", double(last_rays_)},
          {"rays_total", double(rays_)},
          {"mrays_per_s", seconds > 0.0 ? double(last_rays_) * 1e-6 / seconds : 0.0},
          {"nonfinite_samples", double(nonfinite_)},
          {"triangles", bvh_ ? double(bvh_->triangles().size()) : 0.0},
          {"emitter_triangles", bvh_ ? double(bvh_->emitters().size()) : 0.0},
          {"threads", double(std::max(1u, std::thread::hardware_concurrency()))}};
}

}  // namespace gistream
