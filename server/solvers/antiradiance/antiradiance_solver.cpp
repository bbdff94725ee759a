#include "solvers/antiradiance/antiradiance_solver.h"
#include "solvers/registry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "antiradiance/bindings.glsl"  // shaders/: the slots its passes declare
#include "gl/buffers.h"
#include "gl/compute.h"
#include "solvers/antiradiance/scene_patches.h"
#include "solvers/antiradiance/shared_elements.h"
#include "solvers/tail_estimate.h"

namespace gistream {
namespace {

using antiradiance::Scheme;

constexpr int kMaxGridDim = 64;
constexpr size_t kMaxResidualStats = 32;
// Memory limits per solver instance (the paper's Table 2 scenes need
// < 140 MB in all).
constexpr uint64_t kMaxTableBytes = uint64_t(1) << 30;
constexpr uint64_t kMaxLinkBytes = uint64_t(1) << 30;

struct ElementGpu {
  glm::vec4 position_radius;
  glm::vec4 normal;
  glm::vec4 irradiance;
};
GS_STD430_MIRROR(ElementGpu, 48);

}  // namespace

SolverDescription AntiradianceSolver::Describe() {
  SolverDescription d;
  d.name = "antiradiance";
  d.description =
      "Dachsbacher et al. 2007: implicit visibility through antiradiance, hierarchical links, "
      "directional bins";
  d.stages = {"link", "global_pass", "local_pass", "push_pull", "display"};
  // clang-format off
  d.params = {
      // Even: the bins come in opposite pairs (directional_bins.h).
      {"bins", ParamType::kInt, "128", 32, 512, {}, "Directional bins per element (even)", 2},
      {"iterations", ParamType::kInt, "32", 1, 4096, {},
       "Most iterations per update (asymmetric: radiance steps, each after converged "
       "antiradiance): a safety cap; tolerance stops first"},
      {"tolerance", ParamType::kFloat, "0.01", 0, 1, {},
       "Stop iterating when an iteration changes the exitant intensities by less than this "
       "fraction of the direct-light source (|dI_ex|_1 / |I_ex^(0)|_1; 0: run every iteration)"},
      {"scheme", ParamType::kEnum, "symmetric", 0, 0, {"symmetric", "asymmetric"},
       "Iteration scheme (Section 2.2); symmetric falls back to asymmetric when it diverges"},
      {"antiradiance_steps", ParamType::kInt, "16", 1, 64, {},
       "Asymmetric: most antiradiance steps (Eq. 14) per radiance step; stop earlier once converged"},
      {"tail_estimate", ParamType::kBool, "true", 0, 0, {},
       "Add the geometric tail of the iterations not run (from the measured ratios, at most the "
       "largest albedo), so a bright interior converges at the defaults"},
      {"elements", ParamType::kEnum, "surfels", 0, 0, {"surfels", "triangles"},
       "Leaf elements: the shared hierarchy's vertex discs, or scene triangles split to patch_size"},
      {"patch_size", ParamType::kFloat, "0", 0, 1e9, {},
       "elements=triangles: longest leaf edge in metres, larger triangles are split (0: diagonal / 24)"},
      {"glossy", ParamType::kBool, "true", 0, 0, {},
       "Glossy leaves reflect through the GGX BRDF per bin (glossy_transfer.h); false: every leaf "
       "diffuse, glossy pixels shade the irradiance with the BRDF's albedo"},
  };
  // clang-format on
  for (ParamSpec& spec : DirectLightingParams()) d.params.push_back(std::move(spec));
  return d;
}

const SolverDescription& AntiradianceSolver::description() const {
  static const SolverDescription kDescription = Describe();
  return kDescription;
}

absl::StatusOr<std::unique_ptr<Solver>> AntiradianceSolver::Create(const ParamSet& params) {
  auto solver = std::unique_ptr<AntiradianceSolver>(new AntiradianceSolver());
  AntiradianceSettings& s = solver->settings_;
  s.bins = params.GetInt("bins");
  s.patch_size = float(params.GetFloat("patch_size"));
  s.surfels = params.GetString("elements") == "surfels";
  s.glossy = params.GetBool("glossy");
  s.transport.iterations = params.GetInt("iterations");
  s.transport.tolerance = params.GetFloat("tolerance");
  s.transport.scheme =
      params.GetString("scheme") == "asymmetric" ? Scheme::kAsymmetric : Scheme::kSymmetric;
  s.transport.antiradiance_steps = params.GetInt("antiradiance_steps");
  s.tail_estimate = params.GetBool("tail_estimate");
  s.direct = DirectLightingFromParams(params);
  // The environment as directional lights (render/environment_lights.h):
  // the elements' direct light, so it bounces, and the display's.
  s.direct.environment_lights = true;
  GS_ASSIGN_OR_RETURN(solver->bins_, hierarchy::DirectionalBins::Create(s.bins));
  GS_ASSIGN_OR_RETURN(solver->lighting_, DirectLighting::Create());
  GS_ASSIGN_OR_RETURN(
      solver->direct_program_,
      gl::Program::Build({{GL_COMPUTE_SHADER, "antiradiance/element_direct.comp.glsl"}}));
  GS_ASSIGN_OR_RETURN(solver->glossy_direct_, GlossyBinDirect::Create());
  {
    std::vector<glm::vec4> directions;
    for (int j = 0; j < solver->bins_.count(); ++j)
      directions.push_back(glm::vec4(solver->bins_.direction(j), 0.0f));
    solver->bin_directions_ = gl::StorageBuffer(directions);
  }
  GS_ASSIGN_OR_RETURN(solver->display_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                          {GL_FRAGMENT_SHADER, "antiradiance/display.frag.glsl"}}));
  return solver;
}

std::vector<std::string> AntiradianceSolver::Plan(const SceneState& state,
                                                  ChangeMask changes) const {
  changes = EnvironmentAsLights(changes, state);
  // A dimmer (solvers/emission_scale.h) on a settled solution: no link,
  // pass or push-pull; the direct light's buffers in local_pass.
  if (started_ && !(changes & kChangeShape) && !solve_.running() && !lighting_.pending() &&
      !stale_ && emission_.Factor(state, changes)) {
    return {"local_pass", "display"};
  }
  // Geometry relinks; anything that changes the light (lights, emission,
  // albedo, environment) reuses the links (Section 3.3); the camera only
  // redisplays.
  // A solve under way (a background job, shadow-map slices) may end or
  // start in any frame: its stages may run (link when it relinks).
  if ((changes & kChangeShape) || relink_due_ || (solve_.running() && relinking_)) {
    return {"link", "global_pass", "local_pass", "push_pull", "display"};
  }
  if (!UpdateComplete()) return {"global_pass", "local_pass", "push_pull", "display"};
  if (changes & (kChangeLights | kChangeEmission | kChangeMaterials | kChangeEnvironment)) {
    return {"global_pass", "local_pass", "push_pull", "display"};
  }
  return {"display"};
}

absl::StatusOr<std::unique_ptr<antiradiance::Patches>> AntiradianceSolver::PatchesNow(
    const SolverContext& ctx) {
  const Bounds bounds = ctx.gpu.WorldBounds(ctx.state);
  const float diagonal = bounds.empty() ? 1.0f : glm::length(bounds.extent());
  const float max_edge = settings_.patch_size > 0.0f ? settings_.patch_size : diagonal / 24.0f;
  auto patches = std::make_unique<antiradiance::Patches>();
  if (settings_.surfels) {
    *patches = antiradiance::SurfelPatches(ctx.state, ctx.gpu, surfel_cache_,
                                           settings_.direct.full_detail);
  } else {
    const auto triangles = antiradiance::SceneTriangles(ctx.state);
    // Refuse before splitting: a tiny patch_size makes up to 4^12 leaves per
    // triangle (it used to pass 5 GB before any check ran). Each leaf needs
    // its own I_ex/L_in tables, so this bound is never above the real need.
    const uint64_t leaves = antiradiance::CountLeaves(triangles, max_edge);
    const uint64_t leaf_table_bytes = leaves * uint64_t(bins_.count()) * 2 * sizeof(glm::vec3);
    if (leaves > kMaxTableBytes || leaf_table_bytes > kMaxTableBytes) {
      return absl::ResourceExhaustedError(absl::StrCat(
          "params.patch_size: ", max_edge, " m splits the scene's triangles into ", leaves,
          " leaves, whose I_ex/L_in tables need at least ", leaf_table_bytes >> 20, " MiB (limit ",
          kMaxTableBytes >> 20, " MiB); use a larger patch_size or fewer bins"));
    }
    *patches = antiradiance::BuildPatches(triangles, max_edge);
  }
  // doubleSided materials: both faces gather, reflect and block (patches.h).
  const std::vector<Material>& materials = ctx.state.materials();
  antiradiance::AddBackFaces(*patches, [&materials](int tag) {
    return tag >= 0 && size_t(tag) < materials.size() && materials[size_t(tag)].double_sided;
  });
  // I_ex and L_in: elements x bins x 2 x RGB floats.
  const uint64_t table_bytes =
      uint64_t(patches->size()) * uint64_t(bins_.count()) * 2 * sizeof(glm::vec3);
  if (table_bytes > kMaxTableBytes) {
    return absl::ResourceExhaustedError(
        absl::StrCat("params.bins: ", bins_.count(), " bins x ", patches->size(), " elements need ",
                     table_bytes >> 20, " MiB of I_ex/L_in tables (limit ", kMaxTableBytes >> 20,
                     " MiB); use fewer bins"));
  }
  return patches;
}

absl::Status AntiradianceSolver::StartSolve(const SolverContext& ctx, bool relink) {
  auto job = std::make_shared<SolveJob>();
  if (relink || !patches_) {
    GS_ASSIGN_OR_RETURN(job->patches, PatchesNow(ctx));
    FindMovedRoots(*job);
    job->relink = true;
  } else {
    // Same elements and links (lights, emission, albedo, environment, or
    // the new shadow maps): only the transport runs.
    job->patches = std::make_unique<antiradiance::Patches>(*patches_);
  }
  job->leaves = job->patches->Leaves();
  SetLeafMaterials(ctx, *job);
  if (!job->relink || job->same_layout) job->link_set = link_set_;  // (relinked in the job)
  {
    // Section 3.3: direct light initializes the elements through the
    // shadow maps shown now; it creates no antiradiance.
    gl::StageTimer::Scope stage(ctx.timer, "local_pass", /*cpu_stage=*/true);
    job->direct = DirectAtLeaves(*job->patches, job->leaves);
    job->glossy_direct = GlossyDirectAtLeaves(
        *job->patches, job->brdf, antiradiance::GlossyTransfer::Slots(*job->patches, job->brdf));
  }
  const hierarchy::DirectionalBins* bins = &bins_;
  antiradiance::TransportSettings settings = settings_.transport;
  // Issue 29, item 4: without the tail the cap stopped a rho = 0.99
  // furnace 71 % low (the tolerance a rho = 0.9 one 4 % low).
  settings.tail_bound = settings_.tail_estimate ? LargestAlbedo(ctx.state) : 0.0;
  // Section 3.3: iterate from the shown solution (same nodes; Solve checks
  // the layout). The render thread does not change it before the job ends.
  const antiradiance::Transport* warm = transport_.get();
  solve_.Start(job, [bins, settings, warm](SolveJob& j) { RunSolveJob(*bins, settings, warm, j); });
  return absl::OkStatus();
}

void AntiradianceSolver::FindMovedRoots(SolveJob& job) const {
  const antiradiance::Patches& p = *job.patches;
  // Section 3.3: relink only the pairs of roots (charts / mesh instances)
  // that touch a moved one; the layout is the same as long as the scene's
  // meshes are (only transforms change), which same_layout checks.
  job.same_layout =
      transport_ && patches_ && p.roots == patches_->roots && p.size() == patches_->size();
  job.moved.assign(p.roots.size(), true);
  if (!job.same_layout) return;
  for (size_t r = 0; r < p.roots.size(); ++r) {
    const int end = r + 1 < p.roots.size() ? p.roots[r + 1] : p.size();
    job.moved[r] = false;
    for (int i = p.roots[r]; i < end && !job.moved[r]; ++i) {
      job.moved[r] = p.position[size_t(i)] != patches_->position[size_t(i)] ||
                     p.normal[size_t(i)] != patches_->normal[size_t(i)] ||
                     p.area[size_t(i)] != patches_->area[size_t(i)];
    }
  }
}

void AntiradianceSolver::SetLeafMaterials(const SolverContext& ctx, SolveJob& job) const {
  for (int i : job.leaves) {
    job.patches->albedo[size_t(i)] =
        antiradiance::MaterialAlbedo(ctx.state, job.patches->tag[size_t(i)]);
  }
  // Glossy leaves (glossy_transfer.h): the material's metallic-roughness
  // factors (textures are not sampled per leaf, as the albedo above).
  job.brdf.assign(size_t(job.patches->size()), shading::Brdf());
  for (int i : job.leaves) {
    const int material = settings_.glossy ? job.patches->tag[size_t(i)] : -1;
    if (material < 0 || size_t(material) >= ctx.state.materials().size()) continue;
    const Material& m = ctx.state.materials()[size_t(material)];
    shading::Brdf& b = job.brdf[size_t(i)];
    b.base_color = job.patches->albedo[size_t(i)];
    b.metallic = m.metallic_factor;
    b.roughness = m.roughness_factor;
    b.specular_f0 = m.specular_f0;
    b.specular_f90 = m.specular_f90;
  }
}

void AntiradianceSolver::RunSolveJob(const hierarchy::DirectionalBins& bins,
                                     const antiradiance::TransportSettings& settings,
                                     const antiradiance::Transport* warm, SolveJob& j) {
  if (j.relink) {
    j.link_set.set_max_links(kMaxLinkBytes / sizeof(antiradiance::Link));
    j.times.Time("link", [&] {
      if (j.same_layout) {
        j.link_set.Relink(*j.patches, bins, j.moved);
      } else {
        j.link_set.Build(*j.patches, bins);
      }
    });
  }
  const uint64_t links = j.link_set.size();
  if (j.link_set.exceeded() || links * sizeof(antiradiance::Link) > kMaxLinkBytes) {
    // Linking stopped once the links passed the limit: `links` is a floor.
    j.status = absl::ResourceExhaustedError(absl::StrCat(
        "params.bins: more than ", kMaxLinkBytes / sizeof(antiradiance::Link), " links (",
        kMaxLinkBytes >> 20, " MiB, the limit; ", links, " when linking stopped); use fewer bins"));
    return;
  }
  j.transport = std::make_unique<antiradiance::Transport>(*j.patches, bins, j.link_set.Sorted());
  // The glossy leaves' BRDF matrices (glossy_transfer.h).
  absl::StatusOr<antiradiance::GlossyTransfer> glossy;
  j.times.Time("local_pass", [&] {
    glossy = antiradiance::GlossyTransfer::Build(*j.patches, bins, j.brdf, kMaxTableBytes);
  });
  if (!glossy.ok()) {
    j.status = glossy.status();
    return;
  }
  j.glossy = std::make_unique<antiradiance::GlossyTransfer>(*std::move(glossy));
  j.transport->SetGlossy(j.glossy.get(), std::move(j.glossy_direct));
  // Emission is the direct term's (area-light samples), not transported again.
  j.result = j.transport->Solve(
      j.direct, {}, settings,
      [&](const char* stage, bool begin) {
        if (begin) {
          j.times.Begin();
        } else {
          j.times.End(stage);
        }
      },
      warm);
}

absl::Status AntiradianceSolver::TakeSolve(SolverContext& ctx, SolveJob& job) {
  // The job's CPU time is reported in the frame that takes its solution.
  job.times.RecordInto(ctx.timer);
  GS_RETURN_IF_ERROR(job.status);
  patches_ = std::move(job.patches);
  leaves_ = std::move(job.leaves);
  link_set_ = std::move(job.link_set);
  link_stats_ = link_set_.stats();
  transport_ = std::move(job.transport);
  glossy_ = std::move(job.glossy);
  result_ = job.result;
  BuildDisplay();
  UploadIrradiance();
  indirect_scale_ = 1.0f;
  return absl::OkStatus();
}

void AntiradianceSolver::BuildDisplay() {
  const antiradiance::Patches& patches = *patches_;
  // Display data: the leaves as splats (radius 1.5 x the leaf's bounding
  // radius, so neighbours overlap) in a uniform grid (below).
  std::vector<ElementGpu> elements(leaves_.size());
  Bounds box;
  float largest = 0.0f;
  leaf_area_ = 0.0;
  for (size_t k = 0; k < leaves_.size(); ++k) {
    const size_t i = size_t(leaves_[k]);
    // Unless full_detail (the splats of before proxies): twice the
    // distance to its cell's farthest corner, as a leaf made from a proxy's
    // sliver (hierarchy/element_source.h) reaches beyond 1.5 disc radii,
    // and a splat that barely covers its cell makes each pixel's light
    // nearly its nearest leaf's (neighbours that differ show as tiles;
    // README, Display).
    float r = 1.5f * patches.radius[i];
    if (!settings_.direct.full_detail) {
      for (const antiradiance::CellQuad& q : patches.Cell(int(i)))
        for (const glm::vec3& c : q) r = std::max(r, 2.0f * glm::length(c - patches.position[i]));
    }
    elements[k].position_radius = glm::vec4(patches.position[i], r);
    // w: the glossy slot, -1 for a Lambertian leaf (antiradiance/elements.glsl).
    elements[k].normal = glm::vec4(patches.normal[i], float(glossy_ ? glossy_->slot(int(i)) : -1));
    elements[k].irradiance = glm::vec4(0.0f);
    box.Extend(patches.position[i]);
    largest = std::max(largest, r);
    leaf_area_ += patches.area[i];
  }
  if (box.empty()) box.Extend(glm::vec3(0.0f));
  const glm::vec3 extent = box.extent();
  const float widest = std::max({extent.x, extent.y, extent.z});
  // Cells of half the largest splat: a pixel scans the cells within that
  // splat's reach of it (4-5 per axis), 2.5 splats wide instead of the 3
  // of a 3 x 3 x 3 block of splat-sized cells (the leaves a pixel reads
  // lie on surfaces: about 0.7 as many).
  grid_cell_ = std::max({0.5f * largest, widest / float(kMaxGridDim - 1), 1e-6f});
  grid_reach_ = largest;
  grid_min_ = box.min;
  grid_dims_ = glm::clamp(glm::ivec3(glm::floor(extent / grid_cell_)) + 1, glm::ivec3(1),
                          glm::ivec3(kMaxGridDim));
  const size_t cells = size_t(grid_dims_.x) * size_t(grid_dims_.y) * size_t(grid_dims_.z);
  std::vector<uint32_t> grid(cells + 1 + leaves_.size(), 0);
  auto cell_of = [&](const glm::vec3& p) {
    const glm::ivec3 c =
        glm::clamp(glm::ivec3((p - grid_min_) / grid_cell_), glm::ivec3(0), grid_dims_ - 1);
    return size_t((c.z * grid_dims_.y + c.y) * grid_dims_.x + c.x);
  };
  for (const ElementGpu& e : elements) ++grid[cell_of(glm::vec3(e.position_radius)) + 1];
  for (size_t c = 0; c < cells; ++c) grid[c + 1] += grid[c];
  std::vector<uint32_t> fill(grid.begin(), grid.begin() + long(cells));
  for (size_t k = 0; k < elements.size(); ++k) {
    grid[cells + 1 + fill[cell_of(glm::vec3(elements[k].position_radius))]++] = uint32_t(k);
  }
  elements_ = gl::StorageBuffer(elements, GL_DYNAMIC_STORAGE_BIT);
  element_data_.resize(elements.size() * 3);
  std::memcpy(element_data_.data(), elements.data(), elements.size() * sizeof(ElementGpu));
  grid_ = gl::StorageBuffer(grid);
}

std::vector<glm::vec3> AntiradianceSolver::DirectAtLeaves(const antiradiance::Patches& patches,
                                                          const std::vector<int>& leaves) {
  std::vector<glm::vec3> direct(size_t(patches.size()), glm::vec3(0.0f));
  if (leaves.empty()) return direct;
  // The leaves' centres and normals (the element layout the shader reads).
  std::vector<ElementGpu> elements(leaves.size());
  for (size_t k = 0; k < leaves.size(); ++k) {
    const size_t i = size_t(leaves[k]);
    elements[k].position_radius = glm::vec4(patches.position[i], patches.radius[i]);
    elements[k].normal = glm::vec4(patches.normal[i], 0.0f);
    elements[k].irradiance = glm::vec4(0.0f);
  }
  const gl::Buffer input = gl::StorageBuffer(elements);
  const gl::Buffer output = gl::ZeroedBuffer(leaves.size() * sizeof(glm::vec4));
  lighting_.Bind(direct_program_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, AR_BINDING_ELEMENTS, input.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, AR_BINDING_ELEMENT_DIRECT, output.id());
  direct_program_.Set("uCount", int(leaves.size()));
  direct_program_.Use();
  glDispatchCompute(gl::GroupCount(leaves.size(), 64), 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
  std::vector<glm::vec4> e(leaves.size());
  glGetNamedBufferSubData(output.id(), 0, GLsizeiptr(e.size() * sizeof(glm::vec4)), e.data());
  for (size_t k = 0; k < leaves.size(); ++k) direct[size_t(leaves[k])] = glm::vec3(e[k]);
  return direct;
}

std::vector<glm::vec3> AntiradianceSolver::GlossyDirectAtLeaves(
    const antiradiance::Patches& patches, const std::vector<shading::Brdf>& brdf,
    const std::vector<int>& slots) {
  // The glossy leaves in slot order, roughness raised to the bins' as the
  // transfer matrices (glossy_transfer.h).
  std::vector<GlossyBinElement> input;
  const float min_roughness = bins_.ResolvedRoughness();
  for (int i = 0; i < patches.size(); ++i) {
    if (slots[size_t(i)] < 0) continue;
    const shading::Brdf& b = brdf[size_t(i)];
    input.push_back({glm::vec4(patches.position[size_t(i)], 0.0f),
                     glm::vec4(patches.normal[size_t(i)], std::max(b.roughness, min_roughness)),
                     glm::vec4(b.base_color, b.metallic),
                     glm::vec4(b.specular_f0, b.specular_f90)});
  }
  const int count = int(input.size());
  const size_t cells = size_t(count) * size_t(bins_.count());
  if (count == 0) return {};
  const gl::Buffer elements = gl::StorageBuffer(input);
  const gl::Buffer output = gl::ZeroedBuffer(cells * sizeof(glm::vec4));
  glossy_direct_.Run(lighting_, elements.id(), count, bin_directions_.id(), bins_.count(),
                     output.id());
  std::vector<glm::vec4> l(cells);
  glGetNamedBufferSubData(output.id(), 0, GLsizeiptr(cells * sizeof(glm::vec4)), l.data());
  std::vector<glm::vec3> out(cells);
  for (size_t c = 0; c < cells; ++c) out[c] = glm::vec3(l[c]);
  return out;
}

void AntiradianceSolver::UploadIrradiance() {
  // Negative irradiance (antiradiance over-cancelling, see ARCHITECTURE)
  // is displayed as zero and its area reported in the stats.
  negative_area_ = 0.0;
  for (size_t k = 0; k < leaves_.size(); ++k) {
    const glm::vec3 v = transport_->indirect_irradiance()[size_t(leaves_[k])];
    if (v.r < 0.0f || v.g < 0.0f || v.b < 0.0f)
      negative_area_ += patches_->area[size_t(leaves_[k])];
    element_data_[3 * k + 2] = glm::vec4(glm::max(v, glm::vec3(0.0f)), 0.0f);
  }
  if (!element_data_.empty()) {
    glNamedBufferSubData(elements_.id(), 0, GLsizeiptr(element_data_.size() * sizeof(glm::vec4)),
                         element_data_.data());
  }
  // The glossy leaves' reflected indirect radiance per bin, signed: bins
  // can be negative where antiradiance over-cancels; the display clamps
  // after interpolating (clamping each bin would bias it upward).
  const int glossy = glossy_ ? glossy_->count() : 0;
  glossy_data_.assign(size_t(std::max(glossy, 1)) * size_t(bins_.count()), glm::vec4(0.0f));
  for (int g = 0; g < glossy; ++g) {
    const glm::vec3* l = transport_->glossy_indirect(g);
    for (int j = 0; j < bins_.count(); ++j) {
      glossy_data_[size_t(g) * size_t(bins_.count()) + size_t(j)] = glm::vec4(l[j], 0.0f);
    }
  }
  glossy_radiance_ = gl::StorageBuffer(glossy_data_);
}

absl::Status AntiradianceSolver::Update(SolverContext& ctx, ChangeMask changes) {
  changes = EnvironmentAsLights(changes, ctx.state);
  const bool first = !started_;  // (the first solve's job may still run)
  started_ = true;
  const bool geometry = (changes & kChangeShape) || first;
  const bool light =
      geometry ||
      (changes & (kChangeLights | kChangeEmission | kChangeMaterials | kChangeEnvironment));
  const bool busy = solve_.running() || lighting_.pending() || stale_;
  if (!light && !busy) {
    for (const char* stage : {"link", "global_pass", "local_pass", "push_pull"})
      ctx.timer.Skip(stage);
    return absl::OkStatus();
  }
  if (const std::optional<float> k =
          (geometry || busy) ? std::nullopt : emission_.Factor(ctx.state, changes)) {
    // A dimmer: the transported light scales with the lights (linear
    // transport, solvers/emission_scale.h); no link, pass or push-pull.
    for (const char* stage : {"link", "global_pass", "push_pull"}) ctx.timer.Skip(stage);
    gl::StageTimer::Scope stage(ctx.timer, "local_pass", /*cpu_stage=*/true);
    GS_RETURN_IF_ERROR(lighting_.Update(ctx.state, ctx.gpu, settings_.direct, changes));
    indirect_scale_ = *k;
    return absl::OkStatus();
  }
  {
    // The shadow maps, in slices of the frame budget while the shown set
    // stays bound (render/direct_lighting.h).
    gl::StageTimer::Scope stage(ctx.timer, "local_pass", /*cpu_stage=*/true);
    const uint64_t shown = lighting_.sets_shown();
    if (light) {
      GS_RETURN_IF_ERROR(
          lighting_.Update(ctx.state, ctx.gpu, settings_.direct, changes, ctx.budget_ms));
    } else if (lighting_.pending()) {
      lighting_.Continue(ctx.gpu, ctx.state, ctx.budget_ms);
    }
    // New light, or new maps are shown (the newest set may be drawn next):
    // the elements' direct light changed, a new solve is due.
    if (light || lighting_.sets_shown() != shown) stale_ = true;
  }
  if (geometry) relink_due_ = true;
  if (std::shared_ptr<SolveJob> done = solve_.TakeIfDone())
    GS_RETURN_IF_ERROR(TakeSolve(ctx, *done));
  // The first solve waits for its shadow maps (its elements' direct light
  // reads them); later ones start with the maps shown and follow the new.
  if (stale_ && !solve_.running() && (transport_ || !lighting_.pending())) {
    // Link and transport run on the CPU pool on copies (links of the moved
    // roots only, Section 3.3); frames show the last solution meanwhile,
    // before the first one direct light alone (the render thread never
    // waits for the job). A change during the job makes the next one, with
    // the newest data.
    GS_RETURN_IF_ERROR(StartSolve(ctx, relink_due_));
    relinking_ = relink_due_;
    stale_ = relink_due_ = false;
  }
  if (!stale_ && !solve_.running() && !lighting_.pending()) emission_.Solved(ctx.state);
  return absl::OkStatus();
}

absl::Status AntiradianceSolver::Shade(SolverContext& ctx, const ViewCamera& /*camera*/,
                                       const GBuffer& gbuffer) {
  gl::StageTimer::Scope stage(ctx.timer, "display");
  if (!elements_) {
    // No solution yet: an empty grid (one cell, no leaf), direct light only.
    elements_ = gl::StorageBuffer(std::vector<ElementGpu>(1), GL_DYNAMIC_STORAGE_BIT);
    grid_ = gl::StorageBuffer(std::vector<uint32_t>{0, 0});
  }
  gbuffer.BeginShadePass();
  lighting_.Bind(display_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, AR_BINDING_ELEMENTS, elements_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, AR_BINDING_GRID, grid_.id());
  if (!glossy_radiance_) glossy_radiance_ = gl::StorageBuffer(std::vector<glm::vec4>(1));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, AR_BINDING_GLOSSY_RADIANCE, glossy_radiance_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, AR_BINDING_BIN_DIRECTIONS, bin_directions_.id());
  display_.Set("uBins", bins_.count());
  display_.Set("uBinSpacing", bins_.spacing());
  display_.Set("uGridMin", grid_min_);
  display_.Set("uGridDims", grid_dims_);
  display_.Set("uGridCell", grid_cell_);
  display_.Set("uGridReach", grid_reach_);
  display_.Set("uIndirectScale", indirect_scale_);
  fullscreen_.Draw(display_);
  return absl::OkStatus();
}

SolverStats AntiradianceSolver::Stats() const {
  const uint64_t links = transport_ ? transport_->links().size() : 0;
  SolverStats s = {
      {"bins", double(bins_.count())},
      {"elements", patches_ ? double(patches_->size()) : 0.0},
      {"leaves", double(leaves_.size())},
      {"links", double(links)},
      {"links_spread", double(link_stats_.spread)},
      {"link_node_pairs", double(link_stats_.node_pairs)},
      {"root_pairs", double(link_stats_.root_pairs)},
      {"relinked_root_pairs", double(link_stats_.relinked_root_pairs)},
      {"link_bytes", transport_ ? double(transport_->link_bytes()) : 0.0},
      {"table_bytes", transport_ ? double(transport_->table_bytes()) : 0.0},
      {"spreading_table_bytes", double(bins_.table_bytes())},
      {"glossy_leaves", glossy_ ? double(glossy_->count()) : 0.0},
      {"glossy_matrices", glossy_ ? double(glossy_->matrices()) : 0.0},
      {"glossy_transfer_bytes", glossy_ ? double(glossy_->bytes()) : 0.0},
      {"element_gpu_bytes", double(leaves_.size() * sizeof(ElementGpu))},
      {"iterations", double(result_.iterations)},
      {"max_iterations", double(settings_.transport.iterations)},
      {"cap_reached", result_.cap_reached ? 1.0 : 0.0},
      {"tail_applied", result_.tail_applied ? 1.0 : 0.0},
      {"tail_ratio", result_.tail_ratio},
      {"global_passes", double(result_.global_passes)},
      {"scheme_used", double(int(result_.scheme_used))},
      {"fallback", result_.fallback ? 1.0 : 0.0},
      {"non_finite", result_.non_finite ? 1.0 : 0.0},
      {"residual", result_.residual.empty() ? 0.0 : result_.residual.back()},
      {"negative_irradiance_area", leaf_area_ > 0.0 ? negative_area_ / leaf_area_ : 0.0},
      {"area_samples", double(lighting_.area_samples().size())},
      {"shadow_map_bytes", double(lighting_.gpu_bytes())},
      {"links_pending", solve_.running() ? 1.0 : 0.0},
      {"shadow_maps_pending", lighting_.pending() ? 1.0 : 0.0},
  };
  for (size_t i = 0; i < result_.residual.size() && i < kMaxResidualStats; ++i) {
    s.push_back({absl::StrCat("residual_", i + 1), result_.residual[i]});
  }
  return s;
}

GISTREAM_REGISTER_SOLVER(AntiradianceSolver, 60);

}  // namespace gistream
