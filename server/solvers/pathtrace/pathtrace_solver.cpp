#include "solvers/pathtrace/pathtrace_solver.h"
#include "solvers/registry.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "util/parallel_for.h"

namespace gistream {

using pathtrace::Integrator;
using pathtrace::PathStats;
using shading::Rng;

SolverDescription PathtraceSolver::Describe() {
  SolverDescription d;
  d.name = "pathtrace";
  d.description = "Unbiased progressive reference path tracer (CPU, Embree 3)";
  d.stages = {"build_bvh", "trace", "accumulate"};
  // clang-format off
  d.params = {
      {"spp", ParamType::kInt, "1", 1, 4096, {}, "Samples per pixel added each frame"},
      {"max_depth", ParamType::kInt, "0", 0, 65536, {},
       "Maximum bounces; 0 = none (unbiased: Russian roulette ends paths; a cap biases low)"},
      {"seed", ParamType::kInt, "0", 0, 2147483647, {}, "Random seed; same seed, same image"},
      {"time_budget_ms", ParamType::kFloat, "0", 0, 600000, {},
       "When > 0: add 1-spp rounds until this much trace time is spent (at least one)"},
  };
  // clang-format on
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

std::vector<std::string> PathtraceSolver::Plan(const SceneState&, ChangeMask changes) const {
  if (changes & kChangeShape) return {"build_bvh", "trace", "accumulate"};
  return {"trace", "accumulate"};
}

absl::Status PathtraceSolver::Update(SolverContext& ctx, ChangeMask changes) {
  if (!bvh_ || (changes & kChangeShape)) {
    gl::StageTimer::Scope stage(ctx.timer, "build_bvh", /*cpu_stage=*/true);
    // A deformation alone refits the deforming meshes' BVH when its
    // topology and quality allow (scene_bvh.h); anything else rebuilds.
    const bool deformation_only = bvh_ && (changes & kChangeShape) == kChangeDeformation;
    const pathtrace::RefitResult refit =
        deformation_only ? bvh_->Refit(ctx.state) : pathtrace::RefitResult::kNothingDeforms;
    if (refit == pathtrace::RefitResult::kRefit) {
      ++bvh_refits_;
    } else {
      // Declined for the topology or the quality (refit_quality.h).
      if (refit != pathtrace::RefitResult::kNothingDeforms) ++bvh_refits_declined_;
      GS_ASSIGN_OR_RETURN(bvh_, pathtrace::SceneBvh::Build(ctx.state));
      ++bvh_rebuilds_;
    }
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
  if (changes != kChangeNone) {  // any scene change restarts every view
    views_.clear();
    current_ = nullptr;
  }
  return absl::OkStatus();
}

bool PathtraceSolver::SameView(const ViewCamera& a, const ViewCamera& b) {
  return a.position == b.position && a.rotation == b.rotation && a.yfov == b.yfov &&
         a.width == b.width && a.height == b.height;
}

absl::StatusOr<PathtraceSolver::Accumulation*> PathtraceSolver::ViewFor(const SolverContext& ctx,
                                                                        const ViewCamera& camera) {
  Accumulation* pick = nullptr;
  for (Accumulation& acc : views_) {
    if (SameView(acc.view, camera)) pick = &acc;
  }
  if (!pick) {
    // Room for the new view: the least recently used views go while they
    // would pass kMaxViews or kMaxAccumulationBytes together.
    const size_t need = size_t(camera.width) * size_t(camera.height) * 3 * sizeof(double);
    auto held = [&] {
      size_t bytes = 0;
      for (const Accumulation& acc : views_) bytes += acc.accum.size() * sizeof(double);
      return bytes;
    };
    while (!views_.empty() &&
           (views_.size() >= kMaxViews || held() + need > kMaxAccumulationBytes)) {
      views_.erase(std::min_element(views_.begin(), views_.end(), [](const auto& a, const auto& b) {
        return a.last_used < b.last_used;
      }));
    }
    current_ = nullptr;  // it may have pointed at a view just dropped or moved
    GS_ASSIGN_OR_RETURN(
        MemoryCharge memory,
        ReserveViewMemory(ctx, need, 0,
                          absl::StrCat("pathtrace: width x height ", camera.width, "x",
                                       camera.height, " (its accumulation buffer)")));
    pick = &views_.emplace_back();
    pick->view = camera;
    pick->accum.assign(size_t(camera.width) * size_t(camera.height) * 3, 0.0);
    pick->memory = std::move(memory);
  }
  pick->last_used = ++clock_;
  return pick;
}

void PathtraceSolver::TraceRows(const SceneState& state, Accumulation& acc, int row_begin,
                                int row_end) {
  const ViewCamera& camera = acc.view;
  const int w = int(camera.width);
  const Integrator integrator(state, *bvh_, env_.get(), settings_);
  const uint64_t sample = uint64_t(acc.spp_total);
  std::atomic<uint64_t> rays{0}, nonfinite{0};
  ParallelFor(size_t(row_end - row_begin), 1, [&](size_t row) {
    const int y = row_begin + int(row);
    PathStats stats;
    uint64_t bad = 0;
    for (int x = 0; x < w; ++x) {
      Rng rng(shading::Mix64(seed_ ^ shading::Mix64(sample)),
              uint64_t(y) * uint64_t(w) + uint64_t(x));
      // Pixel (x, y) counts rows from the bottom, as GL does.
      const glm::vec2 ndc((float(x) + rng.Uniform()) / float(w) * 2.0f - 1.0f,
                          (float(y) + rng.Uniform()) / float(camera.height) * 2.0f - 1.0f);
      // From the camera basis and tan(yfov / 2), not an inverted
      // projection matrix (which lost precision at large scales).
      const glm::vec3 dir = camera.RayDirection(ndc);
      const glm::vec3 li = integrator.Li(camera.position, dir, rng, stats);
      if (!(std::isfinite(li.r) && std::isfinite(li.g) && std::isfinite(li.b))) {
        ++bad;  // dropped and counted: never averaged into the image
        continue;
      }
      double* a = &acc.accum[(size_t(y) * size_t(w) + size_t(x)) * 3];
      a[0] += double(li.r);
      a[1] += double(li.g);
      a[2] += double(li.b);
    }
    rays += stats.rays;
    nonfinite += bad;
  });
  acc.rays += rays;
  acc.nonfinite += nonfinite;
}

absl::Status PathtraceSolver::Shade(SolverContext& ctx, const ViewCamera& camera,
                                    const GBuffer& gbuffer) {
  const size_t pixels = size_t(camera.width) * size_t(camera.height);
  const int h = int(camera.height);
  GS_RETURN_IF_ERROR(image_memory_.Fit(ctx, pixels * 4 * sizeof(float), 0,
                                       absl::StrCat("pathtrace: width x height ", camera.width, "x",
                                                    camera.height, " (its image upload buffer)")));
  GS_ASSIGN_OR_RETURN(Accumulation * view, ViewFor(ctx, camera));
  Accumulation& acc = *view;
  current_ = &acc;
  if (acc.frame_complete) {  // a new frame: what it owes
    acc.frame_complete = false;
    acc.owed_passes = time_budget_ms_ > 0.0 ? 0 : spp_per_frame_;
    acc.frame_trace_ms = 0.0;
    acc.frame_passes = 0;
    acc.frame_rays = 0;
    acc.frame_slices = 0;
  }
  ++acc.frame_slices;
  {
    gl::StageTimer::Scope stage(ctx.timer, "trace", /*cpu_stage=*/true);
    const auto start = std::chrono::steady_clock::now();
    const uint64_t rays_before = acc.rays;
    auto elapsed_ms = [&] {
      return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
          .count();
    };
    const double traced_before = acc.frame_trace_ms;  // by the frame's earlier slices
    auto frame_done = [&] {
      if (time_budget_ms_ > 0.0) {
        // Whole passes until the trace time is spent (at least one).
        return acc.pass_row == 0 && acc.frame_passes > 0 &&
               traced_before + elapsed_ms() >= time_budget_ms_;
      }
      return acc.owed_passes <= 0;
    };
    while (!frame_done()) {
      int rows = h - acc.pass_row;
      if (ctx.budget_ms > 0.0) {
        const double left = ctx.budget_ms - elapsed_ms();
        if (left <= 0.0) break;  // the rest in the next slice
        if (ms_per_row_ > 0.0) {
          rows = std::clamp(int(left / ms_per_row_), std::min(rows, int(WorkerCount())), rows);
        }
      }
      const auto slice_start = std::chrono::steady_clock::now();
      TraceRows(ctx.state, acc, acc.pass_row, acc.pass_row + rows);
      const double per_row =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - slice_start)
              .count() /
          double(rows);
      ms_per_row_ = ms_per_row_ > 0.0 ? 0.5 * (ms_per_row_ + per_row) : per_row;
      acc.pass_row += rows;
      if (acc.pass_row >= h) {  // a pass is complete: every pixel has one more sample
        acc.pass_row = 0;
        ++acc.spp_total;
        ++acc.frame_passes;
        --acc.owed_passes;
      }
    }
    acc.frame_complete = frame_done();
    acc.frame_trace_ms = traced_before + elapsed_ms();
    acc.frame_rays += acc.rays - rays_before;
  }
  gl::StageTimer::Scope stage(ctx.timer, "accumulate");
  image_.resize(pixels * 4);
  // Rows below pass_row hold one sample more than the others.
  for (size_t i = 0; i < pixels; ++i) {
    const int row = int(i / camera.width);
    const int samples = acc.spp_total + (row < acc.pass_row ? 1 : 0);
    const double inv = samples > 0 ? 1.0 / double(samples) : 0.0;
    image_[i * 4 + 0] = float(acc.accum[i * 3 + 0] * inv);
    image_[i * 4 + 1] = float(acc.accum[i * 3 + 1] * inv);
    image_[i * 4 + 2] = float(acc.accum[i * 3 + 2] * inv);
    image_[i * 4 + 3] = 1.0f;
  }
  glTextureSubImage2D(gbuffer.hdr(), 0, 0, 0, GLsizei(camera.width), GLsizei(camera.height),
                      GL_RGBA, GL_FLOAT, image_.data());
  return absl::OkStatus();
}

SolverStats PathtraceSolver::Stats() const {
  // The frame's figures are over all its slices.
  const Accumulation empty;
  const Accumulation& acc = current_ ? *current_ : empty;
  const double seconds = acc.frame_trace_ms * 1e-3;
  return {{"spp_total", double(acc.spp_total)},
          {"spp_frame", double(acc.frame_passes)},
          {"trace_ms", acc.frame_trace_ms},
          {"rays", double(acc.frame_rays)},
          {"rays_total", double(acc.rays)},
          {"mrays_per_s", seconds > 0.0 ? double(acc.frame_rays) * 1e-6 / seconds : 0.0},
          {"nonfinite_samples", double(acc.nonfinite)},
          {"triangles", bvh_ ? double(bvh_->triangles().size()) : 0.0},
          {"emitter_triangles", bvh_ ? double(bvh_->emitters().size()) : 0.0},
          {"bvh_rebuilds", double(bvh_rebuilds_)},
          {"bvh_refits", double(bvh_refits_)},
          {"bvh_refit_growth", bvh_ ? bvh_->refit_growth() : 1.0},
          {"bvh_refits_declined", double(bvh_refits_declined_)},
          {"pass_rows", double(acc.pass_row)},
          {"slices", double(acc.frame_slices)},
          {"views", double(views_.size())},
          {"frame_complete", acc.frame_complete ? 1.0 : 0.0},
          {"threads", double(WorkerCount())}};
}

GISTREAM_REGISTER_SOLVER(PathtraceSolver, 20);

}  // namespace gistream
