#include "solvers/implicit_visibility/implicit_visibility_solver.h"
#include "solvers/registry.h"

#include <algorithm>
#include <chrono>
#include <utility>

#include "util/parallel_for.h"
#include "solvers/shading/env_light.h"
#include "solvers/tail_estimate.h"

namespace gistream {

SolverDescription ImplicitVisibilitySolver::Describe() {
  SolverDescription d;
  d.name = "implicit_visibility";
  d.description =
      "Dong et al. 2007: hierarchical radiosity over vertex discs, cube-map bins keep the shortest "
      "link (implicit visibility), multi-bounce";
  d.stages = {"create_surfels", "create_hierarchy", "update_elements", "create_links",
              "refine_push",    "shadow_maps",      "illumination",    "display"};
  // clang-format off
  d.params = {
      {"bins_per_face", ParamType::kInt, "12", 2, 32, {},
       "N: each element has 6 x N x N world-aligned cube-map bins (paper: 8, 12, 16)"},
      {"bounces", ParamType::kInt, "32", 1, 4096, {},
       "Most indirect bounces (gather + pull per bounce): a safety cap; tolerance stops first"},
      {"tolerance", ParamType::kFloat, "0.01", 0, 1, {},
       "Stop bouncing when a bounce changes the leaves' indirect light by less than this "
       "fraction (sum |dE| / sum |E|; 0: run every bounce)"},
      {"tail_estimate", ParamType::kBool, "true", 0, 0, {},
       "Add the geometric tail of the bounces not run (from the measured bounce ratios, at most "
       "the largest albedo), so a bright interior converges at the defaults"},
      {"glossy", ParamType::kBool, "true", 0, 0, {},
       "Glossy elements send their direct light through directional bins with the BRDF (Section "
       "4.3); false: every element reflects diffusely with its BRDF's white-sky albedo"},
      {"glossy_bins", ParamType::kInt, "128", 32, 512, {},
       "Directional bins of each glossy element (even): sharper lobes are blurred to what they "
       "resolve"},
      {"linking", ParamType::kEnum, "hierarchical", 0, 0, {"hierarchical", "brute_force"},
       "hierarchical (Section 4.2) or every pair of leaves (Section 3.1, for comparison)"},
  };
  // clang-format on
  for (ParamSpec& spec : DirectLightingParams()) d.params.push_back(std::move(spec));
  return d;
}

const SolverDescription& ImplicitVisibilitySolver::description() const {
  static const SolverDescription kDescription = Describe();
  return kDescription;
}

absl::StatusOr<std::unique_ptr<Solver>> ImplicitVisibilitySolver::Create(const ParamSet& params) {
  ImplicitVisibilitySettings s;
  s.bins_per_face = params.GetInt("bins_per_face");
  s.bounces = params.GetInt("bounces");
  s.tolerance = params.GetFloat("tolerance");
  s.tail_estimate = params.GetBool("tail_estimate");
  s.glossy_bins = params.GetBool("glossy") ? params.GetInt("glossy_bins") : 0;
  s.linking = params.GetString("linking") == "brute_force" ? hierarchy::Linking::kBruteForce
                                                           : hierarchy::Linking::kHierarchical;
  s.direct = DirectLightingFromParams(params);
  auto solver = std::unique_ptr<ImplicitVisibilitySolver>(new ImplicitVisibilitySolver(s));
  GS_ASSIGN_OR_RETURN(solver->lighting_, DirectLighting::Create());
  GS_ASSIGN_OR_RETURN(solver->illumination_, Illumination::Create(s.glossy_bins));
  GS_ASSIGN_OR_RETURN(solver->display_, Display::Create());
  return solver;
}

std::vector<std::string> ImplicitVisibilitySolver::Plan(const SceneState& state,
                                                        ChangeMask changes) const {
  // A dimmer (solvers/emission_scale.h) on a settled solution: the direct
  // light's buffers change (its shadow_maps stage), no bounce is gathered.
  if (scene_.built() && !(changes & (kChangeShape | kChangeMaterials)) && !relink_.running() &&
      !lighting_.pending() && !illumination_stale_ && emission_.Factor(state, changes)) {
    return {"shadow_maps", "display"};
  }
  std::vector<std::string> plan;
  if (!scene_.built()) plan = {"create_surfels", "create_hierarchy"};
  if (!scene_.built() || (changes & kChangeShape)) {
    // A moved node or a deformed mesh can hide or reveal any pair: every
    // link is rebuilt (in the background after the first solve); a
    // deformed mesh's elements follow its pose in update_elements.
    for (const char* s :
         {"update_elements", "create_links", "refine_push", "shadow_maps", "illumination"}) {
      plan.push_back(s);
    }
  } else {
    // Links reused; the shadow maps only for lights and emission.
    if (changes & (kChangeLights | kChangeEmission)) plan.push_back("shadow_maps");
    if (changes & (kChangeLights | kChangeEmission | kChangeMaterials | kChangeEnvironment)) {
      plan.push_back("illumination");
    }
  }
  if (relink_.running() || relink_.again() || illumination_stale_ || lighting_.pending()) {
    // A background relink may end this frame: its links are taken and the
    // light gathered.
    for (const char* s : {"create_links", "refine_push", "shadow_maps", "illumination"}) {
      if (std::find(plan.begin(), plan.end(), s) == plan.end()) plan.push_back(s);
    }
  }
  plan.push_back("display");
  return plan;
}

absl::Status ImplicitVisibilitySolver::CheckBinBytes() const {
  const hierarchy::Elements& e = scene_.elements();
  const uint64_t bin_bytes = uint64_t(e.node_count()) * uint64_t(bins_.count()) * 12;
  if (bin_bytes > kMaxBinBytes) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "params.bins_per_face: ", bins_.n(), " gives ", bins_.count(), " bins for each of ",
        e.node_count(), " elements, ", bin_bytes >> 20, " MiB; the limit is ", kMaxBinBytes >> 20,
        " MiB (use fewer bins or a coarser mesh)"));
  }
  return absl::OkStatus();
}

absl::Status ImplicitVisibilitySolver::StartRelink(SolverContext& ctx) {
  GS_RETURN_IF_ERROR(CheckBinBytes());
  if (relink_.running()) {
    relink_.Again();  // the running job links older geometry
    return absl::OkStatus();
  }
  auto job = std::make_shared<RelinkJob>();
  job->elements = scene_.elements();
  job->environment = ctx.state.scene().environment.has_value();
  job->version = ctx.state.version();
  const hierarchy::CubeBins* bins = &bins_;
  const hierarchy::Linking linking = settings_.linking;
  relink_.Start(std::move(job), [bins, linking](RelinkJob& j) {
    j.times.Time("create_links", [&] {
      j.link_stats = hierarchy::CreateLinks(j.elements, *bins, linking, j.table);
    });
    j.times.Time("refine_push", [&] {
      j.leaf_links =
          hierarchy::RefinePush(j.elements, *bins, j.table, j.environment, &j.refine_stats);
    });
  });
  return absl::OkStatus();
}

bool ImplicitVisibilitySolver::FinishRelink(SolverContext& ctx) {
  const std::shared_ptr<RelinkJob> job = relink_.TakeIfDone();
  if (!job) return false;
  table_ = std::move(job->table);
  link_stats_ = job->link_stats;
  refine_stats_ = job->refine_stats;
  leaf_links_ = std::move(job->leaf_links);
  links_version_ = job->version;
  // The job's CPU time is reported in the frame that takes its links.
  job->times.RecordInto(ctx.timer);
  illumination_.UploadLinks(leaf_links_, bins_);
  if (relink_.again()) {
    // The same element layout passed the bin-memory check already.
    StartRelink(ctx).IgnoreError();
  }
  return true;
}

void ImplicitVisibilitySolver::UpdateEnvironment(const SceneState& state) {
  const hierarchy::Elements& e = scene_.elements();
  std::vector<glm::vec3> e_env(size_t(e.leaf_count()), glm::vec3(0.0f));
  const Scene& scene = state.scene();
  if (scene.environment && !leaf_links_.env_offset.empty() &&
      state.environment_intensity() > 0.0f) {
    const shading::EnvironmentLight env(scene.environment->image);
    // Radiance per bin direction once, then each leaf's open bins (4.4).
    std::vector<glm::vec3> bin_radiance(size_t(bins_.count()));
    for (int b = 0; b < bins_.count(); ++b) {
      bin_radiance[size_t(b)] = env.Radiance(bins_.Direction(b), state.environment_rotation()) *
                                state.environment_intensity();
    }
    ParallelFor(e_env.size(), 64, [&](size_t i) {
      glm::vec3 sum(0.0f);
      for (uint32_t k = leaf_links_.env_offset[i]; k < leaf_links_.env_offset[i + 1]; ++k) {
        sum += leaf_links_.env_weight[k] * bin_radiance[leaf_links_.env_bin[k]];
      }
      e_env[i] = sum;
    });
  }
  illumination_.UploadEnvironment(e_env);
}

// Update's steps: the surfels and hierarchy once (BuildOnce), the elements
// and a background relink on a geometry change (UpdateElements), the
// relink's links when they are in (TakeLinks), the shadow maps while links
// or maps are pending (DrawWhilePending), a dimmer's rescale
// (ScaleForDimmer), else the shadow maps and the gather (Gather).
absl::Status ImplicitVisibilitySolver::Update(SolverContext& ctx, ChangeMask changes) {
  Changed changed;
  changed.first = !scene_.built();
  changed.geometry = changed.first || (changes & kChangeShape);
  changed.materials = changed.first || (changes & kChangeMaterials);
  changed.lights = changed.geometry || (changes & (kChangeLights | kChangeEmission));
  changed.environment = changed.geometry || (changes & kChangeEnvironment);
  BuildOnce(ctx, changed.first);
  latest_version_ = ctx.state.version();
  GS_RETURN_IF_ERROR(UpdateElements(ctx, changes, changed));
  const bool relinked = TakeLinks(ctx, changed);
  if (relink_.running() || lighting_.pending()) {
    GS_ASSIGN_OR_RETURN(const bool gather, DrawWhilePending(ctx, changes, changed, relinked));
    if (!gather) return absl::OkStatus();
    changed.lights = false;  // drawn above
  }
  GS_ASSIGN_OR_RETURN(const bool scaled, ScaleForDimmer(ctx, changes, changed));
  if (scaled) return absl::OkStatus();
  return Gather(ctx, changes, changed);
}

void ImplicitVisibilitySolver::BuildOnce(SolverContext& ctx, bool first) {
  if (first) {
    scene_.Build(ctx.state, ctx.gpu, ctx.timer, settings_.direct.full_detail);
    display_.UploadTriangles(scene_.triangles());
    display_.UploadTransfer(scene_.vertex_leaves(), scene_.vertex_weights());
  } else {
    ctx.timer.Skip("create_surfels");
    ctx.timer.Skip("create_hierarchy");
  }
}

absl::Status ImplicitVisibilitySolver::UpdateElements(SolverContext& ctx, ChangeMask changes,
                                                      const Changed& changed) {
  if (!changed.geometry) {
    ctx.timer.Skip("update_elements");
    return absl::OkStatus();
  }
  {
    gl::StageTimer::Scope stage(ctx.timer, "update_elements", /*cpu_stage=*/true);
    // A deformation moves the deforming meshes' discs to the pose; the
    // hierarchy stays (Section 4.2.1), so a relink running on the last
    // layout's copy stays valid and a new one follows it.
    if (!changed.first && (changes & kChangeDeformation)) scene_.UpdatePose(ctx.state);
    scene_.UpdateGeometry(ctx.state);
    if (changed.materials) scene_.UpdateAlbedo(ctx.state);
    illumination_.UploadElements(scene_.elements(), scene_.albedo(), scene_.brdf());
    display_.UploadVertices(scene_.vertex_world());
  }
  // The links are built by a background job on the CPU pool, the first
  // solve's too; until they are in, frames show the last solution on the
  // moved geometry (the display interpolates it at the new vertices), and
  // before the first one direct light alone.
  GS_RETURN_IF_ERROR(StartRelink(ctx));
  illumination_stale_ = true;
  return absl::OkStatus();
}

bool ImplicitVisibilitySolver::TakeLinks(SolverContext& ctx, const Changed& changed) {
  const bool relinked = FinishRelink(ctx);
  if (relinked) illumination_stale_ = links_ungathered_ = true;  // new links: gather them
  // The environment's share per leaf follows the links and the
  // environment; it is gathered with the next illumination, which may be
  // frames later (shadow maps still drawing).
  if (changed.environment || relinked) environment_stale_ = true;
  if (!relinked) {
    ctx.timer.Skip("create_links");
    ctx.timer.Skip("refine_push");
  }
  return relinked;
}

absl::StatusOr<bool> ImplicitVisibilitySolver::DrawWhilePending(SolverContext& ctx,
                                                                ChangeMask changes,
                                                                const Changed& changed,
                                                                bool relinked) {
  // The links or the shadow maps do not match the elements yet: keep the
  // last solution (and the last shadow maps, which the leaves' direct
  // light reads); the light is gathered once both are in. The maps are
  // redrawn in slices of the frame budget meanwhile.
  if (changed.lights) {
    gl::StageTimer::Scope stage(ctx.timer, "shadow_maps");
    GS_RETURN_IF_ERROR(
        lighting_.Update(ctx.state, ctx.gpu, settings_.direct, changes, ctx.budget_ms));
  } else if (lighting_.pending()) {
    gl::StageTimer::Scope stage(ctx.timer, "shadow_maps");
    lighting_.Continue(ctx.gpu, ctx.state, ctx.budget_ms);
  } else {
    ctx.timer.Skip("shadow_maps");
  }
  if (changed.materials && !changed.geometry) scene_.UpdateAlbedo(ctx.state);
  if (changed.materials || changed.environment || changed.lights) illumination_stale_ = true;
  // Links just taken are gathered even while a newer relink runs (the
  // geometry moved on while they were built): under continuous motion each
  // relink ends with the next one starting, and waiting for one with none
  // behind it showed direct light alone until the motion stopped (issue
  // 27: relMSE 17x the full solve's through the motion). They are gathered
  // on the current elements' direct light and albedo.
  // Likewise a set of maps shown since the last gather is gathered while
  // the next one is drawn (DirectLighting draws the newest change's set
  // after the one it is drawing): waiting for none to be pending waited,
  // under motion, until it stopped.
  const bool new_maps = lighting_.sets_shown() != gathered_sets_;
  if (new_maps) illumination_stale_ = true;
  const bool newer = relinked || links_ungathered_ || new_maps;
  if ((lighting_.pending() || relink_.running()) && !newer) {
    ctx.timer.Skip("illumination");
    return false;
  }
  return true;  // newer maps or links than the last gather's are in
}

absl::StatusOr<bool> ImplicitVisibilitySolver::ScaleForDimmer(SolverContext& ctx,
                                                              ChangeMask changes,
                                                              const Changed& changed) {
  const std::optional<float> k = (changed.geometry || changed.materials || illumination_stale_)
                                     ? std::nullopt
                                     : emission_.Factor(ctx.state, changes);
  if (!k) return false;
  // A dimmer: the gathered light scales with the lights (linear transport,
  // solvers/emission_scale.h); the direct light's buffers change, no
  // shadow map is redrawn and no bounce runs.
  {
    gl::StageTimer::Scope stage(ctx.timer, "shadow_maps");
    GS_RETURN_IF_ERROR(lighting_.Update(ctx.state, ctx.gpu, settings_.direct, changes));
  }
  ctx.timer.Skip("illumination");
  indirect_scale_ = *k;
  return true;
}

absl::Status ImplicitVisibilitySolver::Gather(SolverContext& ctx, ChangeMask changes,
                                              const Changed& changed) {
  if (changed.lights) {
    // The shared shadow maps, as `direct` draws them: the first bounce's
    // source at the leaves and the per-pixel direct light.
    gl::StageTimer::Scope stage(ctx.timer, "shadow_maps");
    GS_RETURN_IF_ERROR(lighting_.Update(ctx.state, ctx.gpu, settings_.direct, changes));
  } else {
    ctx.timer.Skip("shadow_maps");
  }
  if (!changed.geometry && !changed.materials && !changed.lights && !changed.environment &&
      !illumination_stale_) {
    ctx.timer.Skip("illumination");
    return absl::OkStatus();
  }
  gl::StageTimer::Scope stage(ctx.timer, "illumination");
  if ((changed.materials && !changed.geometry) || illumination_stale_) {
    scene_.UpdateAlbedo(ctx.state);
    illumination_.UploadElements(scene_.elements(), scene_.albedo(), scene_.brdf());
  }
  if (environment_stale_) UpdateEnvironment(ctx.state);
  environment_stale_ = false;
  // Issue 29, item 4: without the tail the tolerance stopped a rho = 0.9
  // furnace 6 % low and the cap a rho = 0.99 one 71 % low.
  const double tail_bound = settings_.tail_estimate ? LargestAlbedo(ctx.state) : 0.0;
  result_ =
      illumination_.Run(lighting_, settings_.bounces, settings_.tolerance, tail_bound, ctx.stop);
  if (result_.cancelled) {
    illumination_stale_ = true;  // solved again at the next frame that runs
    return absl::CancelledError(
        "implicit_visibility: illumination cancelled (the frame's client "
        "left, its deadline passed or the server is stopping)");
  }
  emission_.Solved(ctx.state);
  indirect_scale_ = 1.0f;
  illumination_stale_ = links_ungathered_ = false;
  gathered_sets_ = lighting_.sets_shown();
  // The links' geometry version while a newer relink runs (the solution
  // is that many versions behind in its visibility), else the latest.
  solved_version_ = relink_.running() ? links_version_ : latest_version_;
  return absl::OkStatus();
}

absl::Status ImplicitVisibilitySolver::Shade(SolverContext& ctx, const ViewCamera& camera,
                                             const GBuffer& gbuffer) {
  gl::StageTimer::Scope stage(ctx.timer, "display");
  // Display's irradiance (RGBA32F) and depth (32F) targets: 20 bytes a pixel.
  GS_RETURN_IF_ERROR(
      display_memory_.Fit(ctx, 0, uint64_t(gbuffer.width()) * gbuffer.height() * 20,
                          absl::StrCat("implicit_visibility: width x height ", gbuffer.width(), "x",
                                       gbuffer.height(), " (its display targets)")));
  // The G-buffer's clip planes (render/camera.h), so both depth tests agree.
  display_.Draw(WithDepthRange(camera, ctx.state, ctx.gpu.WorldBounds(ctx.state)), gbuffer,
                illumination_.indirect(), lighting_, indirect_scale_);
  return absl::OkStatus();
}

SolverStats ImplicitVisibilitySolver::Stats() const {
  const hierarchy::Elements& e = scene_.elements();
  return {
      {"elements", double(e.node_count())},
      {"links_pending", relink_.running() ? 1.0 : 0.0},
      {"gi_versions_behind", double(latest_version_ - std::min(solved_version_, latest_version_))},
      {"leaves", double(e.leaf_count())},
      {"proxy_leaves", double(scene_.proxy_leaves())},
      {"top_level_nodes", double(e.roots().size())},
      {"bins_per_element", double(bins_.count())},
      {"node_pairs", double(link_stats_.node_pairs)},
      {"links_offered", double(link_stats_.offered)},
      {"links_stored", double(link_stats_.stored)},
      {"splats", double(link_stats_.splats)},
      {"leaf_links", double(refine_stats_.leaf_links)},
      {"empty_bins", double(refine_stats_.empty_bins)},
      {"blocked_bins", double(refine_stats_.blocked_bins)},
      {"bin_bytes", double(table_.bytes())},
      {"glossy_leaves", double(illumination_.glossy_leaves())},
      {"glossy_slots", double(illumination_.glossy_slots())},
      {"glossy_capped", result_.glossy_capped ? 1.0 : 0.0},
      {"link_gpu_bytes", double(illumination_.gpu_bytes())},
      {"bounces_run", double(result_.bounces)},
      {"residual", result_.residual},
      {"cap_reached", result_.cap_reached ? 1.0 : 0.0},
      {"tail_stopped", result_.tail_stopped ? 1.0 : 0.0},
      {"monotone", result_.monotone ? 1.0 : 0.0},
      {"tail_applied", result_.tail_applied ? 1.0 : 0.0},
      {"tail_ratio", result_.tail_ratio},
      {"area_samples", double(lighting_.area_samples().size())},
      {"shadow_map_bytes", double(lighting_.gpu_bytes())}};
}

GISTREAM_REGISTER_SOLVER(ImplicitVisibilitySolver, 50);

}  // namespace gistream
