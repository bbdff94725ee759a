#include "eval_spec.h"

#include <google/protobuf/util/json_util.h>
#include <nlohmann/json.hpp>

#include <set>

namespace gistream::client {
namespace {

using json = nlohmann::json;

absl::Status Bad(const std::string& path, const std::string& what) {
  return absl::InvalidArgumentError(absl::StrCat(path, ": ", what));
}

absl::StatusOr<v1::Vec3> Vec3At(const json& j, const std::string& path) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() ||
      !j[2].is_number()) {
    return Bad(path, "expected 3 numbers");
  }
  v1::Vec3 v;
  v.set_x(j[0].get<float>());
  v.set_y(j[1].get<float>());
  v.set_z(j[2].get<float>());
  return v;
}

absl::StatusOr<std::vector<v1::Update>> UpdatePair(const json& j, const std::string& path) {
  if (!j.is_array() || j.size() != 2) {
    return Bad(path, "expected two updates (change, then restore), as protobuf JSON");
  }
  std::vector<v1::Update> out;
  for (size_t i = 0; i < 2; ++i) {
    v1::Update u;
    const auto st = google::protobuf::util::JsonStringToMessage(j[i].dump(), &u);
    if (!st.ok()) return Bad(absl::StrCat(path, "[", i, "]"), std::string(st.message()));
    if (u.change_case() == v1::Update::CHANGE_NOT_SET) {
      return Bad(absl::StrCat(path, "[", i, "]"), "sets no change");
    }
    out.push_back(u);
  }
  return out;
}

absl::StatusOr<int> PositiveInt(const json& j, const std::string& path, int max) {
  if (!j.is_number_integer() || j.get<int64_t>() < 1 || j.get<int64_t>() > max) {
    return Bad(path, absl::StrCat(j.dump(), " is not an integer in [1, ", max, "]"));
  }
  return int(j.get<int64_t>());
}

}  // namespace

uint64_t Fnv1a(const std::string& bytes, uint64_t seed) {
  uint64_t h = seed;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::vector<std::map<std::string, std::string>> EvalSolver::Settings() const {
  std::vector<std::map<std::string, std::string>> out{{}};
  for (const auto& [name, values] : grid) {
    std::vector<std::map<std::string, std::string>> next;
    for (const auto& partial : out) {
      for (const std::string& v : values) {
        auto s = partial;
        s[name] = v;
        next.push_back(std::move(s));
      }
    }
    out = std::move(next);
  }
  return out;
}

namespace {

// The spec's settings (size, reference, timed_frames, refine_samples,
// pathtrace_budgets_ms) into `spec`.
absl::Status ParseSettings(const json& doc, EvalSpec& spec) {
  if (doc.contains("size")) {
    const json& s = doc["size"];
    if (!s.is_array() || s.size() != 2) return Bad("size", "expected [width, height]");
    GS_ASSIGN_OR_RETURN(const int w, PositiveInt(s[0], "size[0]", 4096));
    GS_ASSIGN_OR_RETURN(const int h, PositiveInt(s[1], "size[1]", 4096));
    spec.width = uint32_t(w);
    spec.height = uint32_t(h);
  }
  if (doc.contains("reference")) {
    const json& r = doc["reference"];
    if (!r.is_object() || !r.contains("spp")) return Bad("reference", "expected {\"spp\": N}");
    GS_ASSIGN_OR_RETURN(spec.reference_spp, PositiveInt(r["spp"], "reference.spp", 1 << 20));
  }
  if (doc.contains("timed_frames")) {
    GS_ASSIGN_OR_RETURN(spec.timed_frames, PositiveInt(doc["timed_frames"], "timed_frames", 1000));
  }
  if (doc.contains("refine_samples")) {
    GS_ASSIGN_OR_RETURN(const int n, PositiveInt(doc["refine_samples"], "refine_samples", 1024));
    spec.refine_samples = uint32_t(n);
  }
  if (doc.contains("pathtrace_budgets_ms")) {
    const json& b = doc["pathtrace_budgets_ms"];
    if (!b.is_array()) return Bad("pathtrace_budgets_ms", "expected an array of milliseconds");
    spec.pathtrace_budgets_ms.clear();
    for (size_t i = 0; i < b.size(); ++i) {
      if (!b[i].is_number() || b[i].get<double>() <= 0 || b[i].get<double>() > 600000) {
        return Bad(absl::StrCat("pathtrace_budgets_ms[", i, "]"), "expected ms in (0, 600000]");
      }
      spec.pathtrace_budgets_ms.push_back(b[i].get<double>());
    }
  }
  return absl::OkStatus();
}

// The "name" string of the object at `path`.
absl::StatusOr<std::string> NameAt(const json& s, const std::string& path, const char* expected) {
  if (!s.is_object() || !s.contains("name") || !s["name"].is_string()) {
    return Bad(path + ".name", expected);
  }
  return s["name"].get<std::string>();
}

// scenes[i].views[v] at `path`.
absl::StatusOr<EvalView> ParseView(const json& jv, size_t v, const std::string& path) {
  EvalView view;
  view.name = jv.value("name", absl::StrCat("view", v));
  if (jv.contains("eye") || jv.contains("target")) {
    v1::LookAt look;
    GS_ASSIGN_OR_RETURN(*look.mutable_eye(), Vec3At(jv.value("eye", json()), path + ".eye"));
    GS_ASSIGN_OR_RETURN(*look.mutable_target(),
                        Vec3At(jv.value("target", json()), path + ".target"));
    view.look_at = look;
  }
  if (jv.contains("yfov")) {
    if (!jv["yfov"].is_number()) return Bad(path + ".yfov", "expected degrees");
    view.yfov_degrees = jv["yfov"].get<float>();
  }
  return view;
}

// scenes[i].animation at `path`.
absl::StatusOr<EvalAnimation> ParseAnimation(const json& a, const std::string& path) {
  EvalAnimation animation;
  if (!a.is_object() || !a.contains("script") || !a["script"].is_string()) {
    return Bad(path + ".script", "expected the path of a script .json");
  }
  animation.script = a["script"].get<std::string>();
  struct Number {
    const char* key;
    double* value;
    double min, max;
  };
  const Number numbers[] = {{"duration_s", &animation.duration_s, 0.1, 600.0},
                            {"warmup_s", &animation.warmup_s, 0.0, 600.0},
                            {"fps", &animation.fps, 0.1, 240.0},
                            {"update_hz", &animation.update_hz, 0.1, 240.0}};
  for (const Number& n : numbers) {
    if (!a.contains(n.key)) continue;
    const json& v = a[n.key];
    if (!v.is_number() || !(v.get<double>() >= n.min) || !(v.get<double>() <= n.max)) {
      return Bad(absl::StrCat(path, ".", n.key),
                 absl::StrCat(v.dump(), " is not a number in [", n.min, ", ", n.max, "]"));
    }
    *n.value = v.get<double>();
  }
  return animation;
}

// scenes[i] at `path`: its name, its two changes, its views (one default
// view when it lists none) and its animation, if any.
absl::StatusOr<EvalScene> ParseScene(const json& s, const std::string& path) {
  EvalScene scene;
  GS_ASSIGN_OR_RETURN(scene.name, NameAt(s, path, "expected a scene name"));
  if (!s.contains("geometry_change")) return Bad(path + ".geometry_change", "missing");
  if (!s.contains("light_change")) return Bad(path + ".light_change", "missing");
  GS_ASSIGN_OR_RETURN(scene.geometry_change,
                      UpdatePair(s["geometry_change"], path + ".geometry_change"));
  GS_ASSIGN_OR_RETURN(scene.light_change, UpdatePair(s["light_change"], path + ".light_change"));
  if (s.contains("views")) {
    for (size_t v = 0; v < s["views"].size(); ++v) {
      GS_ASSIGN_OR_RETURN(EvalView view,
                          ParseView(s["views"][v], v, absl::StrCat(path, ".views[", v, "]")));
      scene.views.push_back(std::move(view));
    }
  }
  if (scene.views.empty()) scene.views.push_back(EvalView{});
  if (s.contains("animation")) {
    GS_ASSIGN_OR_RETURN(scene.animation, ParseAnimation(s["animation"], path + ".animation"));
  }
  return scene;
}

// solvers[i] at `path`: its name and its parameter grid.
absl::StatusOr<EvalSolver> ParseSolver(const json& s, const std::string& path) {
  EvalSolver solver;
  GS_ASSIGN_OR_RETURN(solver.name, NameAt(s, path, "expected a solver name"));
  if (!s.contains("grid")) return solver;
  if (!s["grid"].is_object()) return Bad(path + ".grid", "expected {param: [values]}");
  for (const auto& [param, values] : s["grid"].items()) {
    const std::string gpath = absl::StrCat(path, ".grid.", param);
    if (!values.is_array() || values.empty()) return Bad(gpath, "expected a non-empty array");
    for (size_t k = 0; k < values.size(); ++k) {
      const json& v = values[k];
      if (v.is_string()) {
        solver.grid[param].push_back(v.get<std::string>());
      } else if (v.is_number() || v.is_boolean()) {
        solver.grid[param].push_back(v.dump());
      } else {
        return Bad(absl::StrCat(gpath, "[", k, "]"), "expected a string or number");
      }
    }
  }
  return solver;
}

}  // namespace

absl::StatusOr<EvalSpec> ParseEvalSpec(const std::string& text) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {
    return Bad("spec", absl::StrCat("malformed JSON: ", e.what()));
  }
  if (!doc.is_object()) return Bad("spec", "expected an object");
  EvalSpec spec;
  static const std::set<std::string> kKeys = {
      "size",           "reference", "timed_frames", "pathtrace_budgets_ms",
      "refine_samples", "scenes",    "solvers"};
  for (const auto& [key, value] : doc.items()) {
    if (!kKeys.count(key)) return Bad(key, "unknown key");
  }
  GS_RETURN_IF_ERROR(ParseSettings(doc, spec));
  if (!doc.contains("scenes") || !doc["scenes"].is_array() || doc["scenes"].empty()) {
    return Bad("scenes", "expected a non-empty array");
  }
  for (size_t i = 0; i < doc["scenes"].size(); ++i) {
    GS_ASSIGN_OR_RETURN(EvalScene scene,
                        ParseScene(doc["scenes"][i], absl::StrCat("scenes[", i, "]")));
    spec.scenes.push_back(std::move(scene));
  }
  if (!doc.contains("solvers") || !doc["solvers"].is_array()) {
    return Bad("solvers", "expected an array");
  }
  for (size_t i = 0; i < doc["solvers"].size(); ++i) {
    GS_ASSIGN_OR_RETURN(EvalSolver solver,
                        ParseSolver(doc["solvers"][i], absl::StrCat("solvers[", i, "]")));
    spec.solvers.push_back(std::move(solver));
  }
  return spec;
}

}  // namespace gistream::client
