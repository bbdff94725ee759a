// The solver contract. A solver brings its view-independent GI state up to
// the scene's current version (Update, running only the stages the change
// set needs and reporting the others as skipped), then shades a view from
// the G-buffer into linear HDR radiance (Shade). One solver instance is
// shared by every session on the same scene with the same parameters.
// Long work is sliced to SolverContext::budget_ms where the solver can
// (FrameComplete() says whether the frame's work is done).
#pragma once

#include <cstdint>
#include <memory>
#include <stop_token>
#include <string>
#include <utility>
#include <vector>

#include "gl/stage_timer.h"
#include "render/camera.h"
#include "render/gbuffer.h"
#include "scene/gpu/gpu_scene.h"
#include "scene/state/scene_state.h"
#include "solvers/solver_params.h"
#include "util/memory_accounts.h"

namespace gistream {

struct SolverContext {
  const SceneState& state;
  GpuScene& gpu;
  gl::StageTimer& timer;
  // The frame's time budget for solver work in ms (0: none). A solver that
  // can slice its work stops near it and reports FrameComplete() false;
  // the engine then runs the rest in later slices, other sessions' frames
  // in between.
  double budget_ms = 0.0;
  // Reserves view-dependent state before a solver allocates it (its
  // estimate covers the rest): the server's memory budget and the scene's
  // tenant's gpu_bytes quota (solvers/view_memory.h). Empty: not counted.
  MemoryReserver reserve{};
  // The frame's cancellation: its session closed (client gone, a Render's
  // deadline passed) or the server is stopping. A loop on the render
  // thread that can run long checks it per step and returns CANCELLED,
  // leaving shared state consistent (other sessions may use the solver).
  // Explicit rather than the thread's token (util/cancellation.h, for
  // background jobs whose results are discarded): a ParallelFor under it
  // would skip indices of work another session goes on to use.
  std::stop_token stop{};
};

using SolverStats = std::vector<std::pair<std::string, double>>;

class Solver {
 public:
  virtual ~Solver() = default;

  virtual const SolverDescription& description() const = 0;
  // The stages of description().stages that Update and Shade will run for
  // `changes` on `state` (the frame reports the others skipped). It sees
  // what Update sees (the state, not only the mask: a dimmer is a light
  // change that runs no solve), and tests/gl/stage_plan_test.cpp holds the
  // two equal for every registered solver and every change kind.
  virtual std::vector<std::string> Plan(const SceneState& state, ChangeMask changes) const = 0;
  // View-independent work for the current scene version.
  virtual absl::Status Update(SolverContext& ctx, ChangeMask changes) = 0;
  // View-dependent: writes radiance into gbuffer.hdr() (bound hdr_fbo).
  virtual absl::Status Shade(SolverContext& ctx, const ViewCamera& camera,
                             const GBuffer& gbuffer) = 0;
  virtual SolverStats Stats() const = 0;
  // False when Shade does not read the G-buffer (the engine then skips it).
  virtual bool NeedsGBuffer() const { return true; }
  // Whether the last Update + Shade finished what this frame owes (e.g. the
  // `spp` samples of a path-traced frame). A frame requested on its own (a
  // Render) is only delivered complete; a continuous stream shows partial
  // frames as they come (progressive).
  virtual bool FrameComplete() const { return true; }
  // Whether the view-independent work of the changes seen so far is done
  // (false while a background job runs or a sliced update has slices to
  // go; Shade then shows the last consistent solution). A frame requested
  // on its own skips Shade until it is.
  virtual bool UpdateComplete() const { return true; }
  // What Shade shows, counted, also while an update is incomplete, so a
  // still view refines meanwhile (render/refinement.h): `changes` changes
  // whenever it changed by more than the solver's tolerance, `steps` on
  // smaller steps toward the solution in between (each within the
  // tolerance). nullopt (the default): not counted, every frame of an
  // incomplete update may show a newer solution.
  struct ShownCount {
    uint64_t changes = 0;
    uint64_t steps = 0;
  };
  virtual std::optional<ShownCount> Shown() const { return std::nullopt; }
  // Whether a background job of it still runs on the CPU pool: its
  // destructor would wait for it, so the engine keeps a solver it drops
  // until this is false (the render thread never waits for a job).
  virtual bool BackgroundBusy() const { return false; }
  // Asks its background job to stop (util/cancellation.h): the engine
  // dropped the solver, and what the job would deliver is not wanted.
  virtual void CancelBackground() {}
  // Bytes its main GL buffers and textures hold (shadow maps, probe atlas,
  // element and link buffers), for status reports; 0 when it holds none.
  virtual uint64_t gpu_bytes() const { return 0; }
};

}  // namespace gistream
