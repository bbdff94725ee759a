#include "solvers/direct/direct_solver.h"
#include "solvers/registry.h"

namespace gistream {

SolverDescription DirectSolver::Describe() {
  SolverDescription d;
  d.name = "direct";
  d.description = "Direct light only: shadow-mapped punctual lights and area lights";
  d.stages = {"shadow_maps", "gbuffer", "shade"};
  d.params = DirectLightingParams();
  return d;
}

const SolverDescription& DirectSolver::description() const {
  static const SolverDescription kDescription = Describe();
  return kDescription;
}

absl::StatusOr<std::unique_ptr<Solver>> DirectSolver::Create(const ParamSet& params) {
  auto solver = std::unique_ptr<DirectSolver>(new DirectSolver());
  solver->settings_ = DirectLightingFromParams(params);
  // The environment as directional lights (render/environment_lights.h).
  solver->settings_.environment_lights = true;
  GS_ASSIGN_OR_RETURN(solver->lighting_, DirectLighting::Create());
  GS_ASSIGN_OR_RETURN(solver->shade_,
                      gl::Program::Build({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                          {GL_FRAGMENT_SHADER, "direct/shade.frag.glsl"}}));
  return solver;
}

std::vector<std::string> DirectSolver::Plan(const SceneState& state, ChangeMask changes) const {
  changes = EnvironmentAsLights(changes, state);
  // Shadow maps depend on geometry, lights and emission; base colour and
  // camera changes only need the view-dependent stages.
  if ((changes & (kChangeShape | kChangeLights | kChangeEmission)) || lighting_.pending()) {
    return {"shadow_maps", "gbuffer", "shade"};
  }
  return {"gbuffer", "shade"};
}

absl::Status DirectSolver::Update(SolverContext& ctx, ChangeMask changes) {
  changes = EnvironmentAsLights(changes, ctx.state);
  if (!(changes & (kChangeShape | kChangeLights | kChangeEmission))) {
    if (!lighting_.pending()) {
      ctx.timer.Skip("shadow_maps");
      return absl::OkStatus();
    }
    // The next slice of a redraw after moved geometry.
    gl::StageTimer::Scope stage(ctx.timer, "shadow_maps");
    lighting_.Continue(ctx.gpu, ctx.state, ctx.budget_ms);
    return absl::OkStatus();
  }
  gl::StageTimer::Scope stage(ctx.timer, "shadow_maps");
  // Sliced by the frame budget: frames show the last shadows until the new
  // ones are all drawn (render/direct_lighting.h).
  return lighting_.Update(ctx.state, ctx.gpu, settings_, changes, ctx.budget_ms);
}

absl::Status DirectSolver::Shade(SolverContext& ctx, const ViewCamera& /*camera*/,
                                 const GBuffer& gbuffer) {
  gl::StageTimer::Scope stage(ctx.timer, "shade");
  gbuffer.BeginShadePass();
  lighting_.Bind(shade_);
  fullscreen_.Draw(shade_);
  return absl::OkStatus();
}

SolverStats DirectSolver::Stats() const {
  return {{"punctual_lights", double(lighting_.punctual_count())},
          {"area_samples", double(lighting_.area_samples().size())},
          {"emitter_triangles", double(lighting_.emitters().size())},
          {"emitter_polygons", double(lighting_.emitter_polygons())},
          {"shadow_map_bytes", double(lighting_.gpu_bytes())},
          {"shadow_maps_redrawn", double(lighting_.maps_redrawn())},
          {"shadow_maps_pending", lighting_.pending() ? 1.0 : 0.0},
          {"shadow_sets_shown", double(lighting_.sets_shown())}};
}

GISTREAM_REGISTER_SOLVER(DirectSolver, 10);

}  // namespace gistream
