// The `gistream eval` spec (JSON): which scenes and views, which solvers
// over which grid of parameters, the reference's sample count, how many
// timed frames. Errors name the JSON path ("solvers[0].grid.vpls[1]: ...").
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "gistream/v1/gistream.pb.h"
#include "util/status.h"

namespace gistream::client {

struct EvalView {
  std::string name = "default";
  std::optional<v1::LookAt> look_at;  // none: the scene's camera
  std::optional<float> yfov_degrees;
};

// A scripted interaction (issue 27): the script's timeline played on the
// scene at `update_hz` into a session capped at `fps` for `duration_s`
// (after `warmup_s`), every frame compared with a path-traced reference
// of the state it shows (gistream bench --reference-spp, one session).
struct EvalAnimation {
  std::string script;  // a script .json (docs: README "Scripts"), relative to the spec's folder
  double duration_s = 3.0;
  double warmup_s = 2.0;
  double fps = 10.0;
  double update_hz = 10.0;
};

struct EvalScene {
  std::string name;  // a scene in the server's directory
  std::vector<EvalView> views;
  std::optional<EvalAnimation> animation;
  // Each pair alternates; the second must restore the loaded state.
  std::vector<v1::Update> geometry_change;  // 2 updates: forces every stage
  std::vector<v1::Update> light_change;     // 2 updates: light only
};

struct EvalSolver {
  std::string name;
  std::map<std::string, std::vector<std::string>> grid;  // param -> values
  // The cartesian product of the grid, in a stable order.
  std::vector<std::map<std::string, std::string>> Settings() const;
};

struct EvalSpec {
  uint32_t width = 64, height = 64;
  int reference_spp = 256;
  int timed_frames = 3;
  // Samples per pixel of the still picture whose error is measured (0: the
  // server's default; 1: pixel centres). Timed frames shade one sample.
  uint32_t refine_samples = 0;
  std::vector<double> pathtrace_budgets_ms = {10, 30, 100, 300, 1000};
  std::vector<EvalScene> scenes;
  std::vector<EvalSolver> solvers;
};

absl::StatusOr<EvalSpec> ParseEvalSpec(const std::string& json_text);

// FNV-1a 64: stable across runs and machines (std::hash is not).
uint64_t Fnv1a(const std::string& bytes, uint64_t seed = 14695981039346656037ull);

}  // namespace gistream::client
