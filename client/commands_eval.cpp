// `gistream eval`: error against a path-traced reference and run time, per
// scene, view, solver and parameter setting (see eval_spec.h, README.md).
#include <algorithm>
#include <chrono>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <iterator>
#include <sstream>

#include <absl/strings/str_replace.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "connection.h"
#include "encode/encode.h"
#include "eval_spec.h"
#include "util/image_metrics.h"
#include "plot.h"
#include "progress_line.h"
#include "scene_loader.h"
#include "session_common.h"
#include "session_stream.h"
#include "stats_table.h"

namespace gistream::client {
namespace {

struct Timing {
  double median = 0.0, p95 = 0.0;
};

Timing Summarize(std::vector<double> v) {
  if (v.empty()) return {};
  std::sort(v.begin(), v.end());
  const auto pick = [&](double q) { return v[size_t(std::ceil(q * double(v.size())) - 1)]; };
  return {v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]),
          pick(0.95)};
}

struct EvalRow {
  std::string scene, view, solver, params;
  double first_ms = 0.0;
  Timing full, light, camera;
  ImageError error;
  // Per-stage timings of the timed frames of each kind of change.
  std::vector<StageSummary> full_stages, light_stages, camera_stages;
  double spp = 0.0;  // pathtrace rows
  bool equal_time = false;
  // Not measured: the server refused the setting ("RESOURCE_EXHAUSTED:
  // ..."); the other columns are empty.
  std::string failure;
};

// A refusal of one setting (too big for the server's budget, a bad
// parameter, a deadline) is a result of the run, written down and passed;
// anything else (the server gone, the credentials refused) ends it.
bool IsRefusal(const absl::Status& status) {
  switch (status.code()) {
    case absl::StatusCode::kResourceExhausted:
    case absl::StatusCode::kInvalidArgument:
    case absl::StatusCode::kFailedPrecondition:
    case absl::StatusCode::kOutOfRange:
    case absl::StatusCode::kDeadlineExceeded:
    case absl::StatusCode::kUnimplemented: return true;
    default: return false;
  }
}

absl::StatusOr<std::string> ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(absl::StrCat("cannot read ", path.string()));
  return std::string(std::istreambuf_iterator<char>(in), {});
}

absl::StatusOr<RgbaImage> DecodeFrame(const v1::Frame& frame) {
  const std::string& bytes = frame.image();
  GS_ASSIGN_OR_RETURN(
      DecodedImage d,
      DecodeImageBytes({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()}));
  return RgbaImage{d.width, d.height, std::move(d.rgba)};
}

std::string ParamsText(const std::map<std::string, std::string>& params) {
  std::string out;
  for (const auto& [k, v] : params) absl::StrAppend(&out, out.empty() ? "" : " ", k, "=", v);
  return out.empty() ? "(defaults)" : out;
}

v1::CameraChange ViewCamera(const EvalView& view) {
  v1::CameraChange c;
  if (view.look_at) *c.mutable_look_at() = *view.look_at;
  if (view.yfov_degrees) c.set_yfov_degrees(*view.yfov_degrees);
  return c;
}

class Evaluator {
 public:
  Evaluator(Connection& connection, const EvalSpec& spec) : conn_(connection), spec_(spec) {}

  // What the evaluation is waiting for (a terminal's stderr only).
  ProgressLine& progress() { return progress_; }

  absl::StatusOr<v1::Frame> RenderOnce(const std::string& scene, const std::string& solver,
                                       const std::map<std::string, std::string>& params,
                                       const v1::CameraChange& camera,
                                       uint32_t refine_samples = 0) {
    v1::RenderRequest request;
    request.set_refine_samples(refine_samples);
    request.set_scene_id(scene);
    request.set_solver(solver);
    for (const auto& [k, v] : params) (*request.mutable_params())[k] = v;
    request.set_width(spec_.width);
    request.set_height(spec_.height);
    request.mutable_encoding()->set_format(v1::IMAGE_FORMAT_EXR);
    *request.mutable_camera() = camera;
    v1::Frame frame;
    GS_RETURN_IF_ERROR(conn_.Call(&v1::Gistream::Stub::Render, request, &frame));
    return frame;
  }

  // The reference for one view: cached as EXR under `cache` by content key.
  absl::StatusOr<RgbaImage> Reference(const std::string& scene_id, const std::string& content_key,
                                      const EvalView& view, const std::filesystem::path& cache) {
    std::ostringstream key;
    key << content_key << '|' << view.name << '|'
        << (view.look_at ? view.look_at->ShortDebugString() : "scene camera") << '|'
        << (view.yfov_degrees ? *view.yfov_degrees : 0.0f) << '|' << spec_.width << 'x'
        << spec_.height << '|' << spec_.reference_spp;
    std::ostringstream name;
    name << std::hex << std::setw(16) << std::setfill('0') << Fnv1a(key.str()) << ".exr";
    const std::filesystem::path file = cache / name.str();
    if (auto cached = ReadText(file); cached.ok()) {
      progress_.Done();
      std::cerr << "reference " << file.string() << " (cached)\n";
      GS_ASSIGN_OR_RETURN(
          DecodedImage d,
          DecodeImageBytes({reinterpret_cast<const uint8_t*>(cached->data()), cached->size()}));
      return RgbaImage{d.width, d.height, std::move(d.rgba)};
    }
    // Progressive: same solver settings and view, so each call adds samples.
    const int chunk = std::min(spec_.reference_spp, 64);
    const std::map<std::string, std::string> params = {{"spp", std::to_string(chunk)},
                                                       {"seed", "1"}};
    v1::Frame frame;
    const auto start = std::chrono::steady_clock::now();
    double spp = 0.0;
    const std::string what = absl::StrCat("reference ", view.name, ": pathtrace ");
    progress_.Wait(absl::StrCat(what, "0/", spec_.reference_spp, " spp"));
    for (;;) {
      GS_ASSIGN_OR_RETURN(frame, RenderOnce(scene_id, "pathtrace", params, ViewCamera(view)));
      const double now = FrameStatValue(frame, "spp_total");
      progress_.Update(absl::StrCat(what, now, "/", spec_.reference_spp, " spp"),
                       now / spec_.reference_spp);
      if (now >= spec_.reference_spp) break;
      // The server keeps the solver between Render calls with the same
      // settings; if it did not accumulate, looping would never end.
      if (now <= spp) {
        return absl::FailedPreconditionError(
            absl::StrCat("reference: pathtrace reported spp_total ", now, " after ", spp,
                         "; the server did not accumulate samples across Render calls"));
      }
      spp = now;
    }
    std::filesystem::create_directories(cache);
    std::ofstream(file, std::ios::binary) << frame.image();
    progress_.Done();
    std::cerr << "reference " << file.string() << ": " << FrameStatValue(frame, "spp_total")
              << " spp in "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
              << " s\n";
    return DecodeFrame(frame);
  }

  absl::StatusOr<EvalRow> Measure(const std::string& scene_id, const EvalScene& scene,
                                  const EvalView& view, const std::string& solver,
                                  const std::map<std::string, std::string>& params,
                                  const RgbaImage& reference, float base_yfov) {
    v1::SessionConfig config;
    config.set_scene_id(scene_id);
    config.set_solver(solver);
    for (const auto& [k, v] : params) (*config.mutable_params())[k] = v;
    config.set_width(spec_.width);
    config.set_height(spec_.height);
    config.mutable_encoding()->set_format(v1::IMAGE_FORMAT_EXR);
    config.mutable_on_request();
    // Timed frames are the first frame after a change: one sample a pixel.
    config.set_refine_samples(1);
    *config.mutable_camera() = ViewCamera(view);
    GS_ASSIGN_OR_RETURN(std::unique_ptr<SessionStream> stream,
                        SessionStream::Open(conn_.stub(), config, conn_.server()));
    EvalRow row;
    row.scene = scene.name;
    row.view = view.name;
    row.solver = solver;
    row.params = ParamsText(params);
    uint64_t seq = 0;
    auto frame_after = [&](const v1::Update* update) -> absl::StatusOr<v1::Frame> {
      if (update) {
        v1::Update u = *update;
        u.set_seq(++seq);
        if (!stream->SendUpdate(u)) return absl::UnavailableError("session ended");
      }
      if (!stream->RequestFrame(1)) return absl::UnavailableError("session ended");
      v1::SessionEvent event;
      while (stream->Next(&event)) {
        if (event.has_rejected()) {
          return absl::InvalidArgumentError(
              absl::StrCat("update rejected: ", event.rejected().message()));
        }
        if (event.has_frame() && event.frame().last_update_seq() >= seq) return event.frame();
      }
      GS_RETURN_IF_ERROR(stream->Finish());
      return absl::UnavailableError("session ended before the frame");
    };
    GS_ASSIGN_OR_RETURN(v1::Frame first, frame_after(nullptr));
    row.first_ms = first.total_ms();
    row.spp = FrameStatValue(first, "spp_total");
    // The error of the still picture a viewer converges to: refined
    // (spec refine_samples) on the solution just solved; pathtrace
    // refines through its own spp.
    v1::Frame still = first;
    if (solver != "pathtrace" && spec_.refine_samples != 1) {
      GS_ASSIGN_OR_RETURN(
          still, RenderOnce(scene_id, solver, params, ViewCamera(view), spec_.refine_samples));
    }
    GS_ASSIGN_OR_RETURN(RgbaImage image, DecodeFrame(still));
    GS_ASSIGN_OR_RETURN(row.error, CompareImages(image, reference));

    auto timed = [&](const std::vector<v1::Update>& pair,
                     std::vector<StageSummary>& stages) -> absl::StatusOr<Timing> {
      std::vector<double> ms;
      StatsCollector collector;
      for (int k = 0; k < 2 * spec_.timed_frames; ++k) {  // even: ends restored
        GS_ASSIGN_OR_RETURN(v1::Frame f, frame_after(&pair[size_t(k % 2)]));
        ms.push_back(f.total_ms());
        collector.Add(f, StatsCollector::Clock::now());
      }
      stages = collector.Summarize().stages;
      return Summarize(ms);
    };
    GS_ASSIGN_OR_RETURN(row.full, timed(scene.geometry_change, row.full_stages));
    GS_ASSIGN_OR_RETURN(row.light, timed(scene.light_change, row.light_stages));
    std::vector<v1::Update> camera_pair(2);
    camera_pair[0].mutable_camera()->set_yfov_degrees(base_yfov + 1.0f);
    camera_pair[1].mutable_camera()->set_yfov_degrees(base_yfov);
    GS_ASSIGN_OR_RETURN(row.camera, timed(camera_pair, row.camera_stages));
    stream->CloseWrites();
    v1::SessionEvent drain;
    while (stream->Next(&drain)) {
    }
    (void)stream->Finish();
    return row;
  }

 private:
  Connection& conn_;
  const EvalSpec& spec_;
  ProgressLine progress_;
};

std::string Fixed(double v, int digits = 3) {
  std::ostringstream o;
  o << std::setprecision(digits) << std::fixed << v;
  return o.str();
}
std::string Sci(double v) {
  std::ostringstream o;
  o << std::setprecision(3) << std::scientific << v;
  return o.str();
}

std::string Markdown(const std::vector<EvalRow>& rows) {
  std::ostringstream md;
  md << "| scene | view | solver | params | full median/p95 ms | light-only median ms | "
        "camera-only median ms | relMSE | RMSE | SSIM | NaN/Inf |\n"
     << "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const EvalRow& r : rows) {
    md << "| " << r.scene << " | " << r.view << " | " << r.solver
       << (r.equal_time ? " (equal time)" : "") << " | " << r.params;
    if (!r.failure.empty()) {
      md << " | not measured: " << absl::StrReplaceAll(r.failure, {{"|", "/"}, {"\n", " "}})
         << " | | | | | | |\n";
      continue;
    }
    if (r.spp > 0) md << " (" << r.spp << " spp)";
    if (r.equal_time) {
      md << " | " << Fixed(r.full.median, 1) << " | - | - | ";
    } else {
      md << " | " << Fixed(r.full.median, 1) << " / " << Fixed(r.full.p95, 1) << " | "
         << Fixed(r.light.median, 1) << " | " << Fixed(r.camera.median, 1) << " | ";
    }
    md << Sci(r.error.rel_mse) << " | " << Sci(r.error.rmse) << " | " << Fixed(r.error.ssim)
       << " | " << r.error.nonfinite_fraction << " |\n";
  }
  return md.str();
}

std::string AnimationMarkdown(const nlohmann::json& rows);
absl::Status WritePlotAndMarkdown(const std::filesystem::path& dir,
                                  const std::vector<EvalRow>& rows, const nlohmann::json& meta,
                                  const nlohmann::json& animation_rows);

absl::Status WriteOutputs(const std::filesystem::path& dir, const std::vector<EvalRow>& rows,
                          const nlohmann::json& meta, const nlohmann::json& animation_rows) {
  std::filesystem::create_directories(dir);
  std::ofstream csv(dir / "results.csv");
  csv << "scene,view,solver,equal_time,params,spp,first_ms,full_median_ms,full_p95_ms,"
         "light_median_ms,light_p95_ms,camera_median_ms,camera_p95_ms,rel_mse,rmse,ssim,"
         "nonfinite_fraction,failure\n";
  nlohmann::json results = nlohmann::json::array();
  for (const EvalRow& r : rows) {
    if (!r.failure.empty()) {
      std::string quoted = r.failure;
      absl::StrReplaceAll({{"\"", "\"\""}, {"\n", " "}}, &quoted);
      csv << r.scene << ',' << r.view << ',' << r.solver << ",0,\"" << r.params
          << "\",,,,,,,,,,,,,\"" << quoted << "\"\n";
      results.push_back({{"scene", r.scene},
                         {"view", r.view},
                         {"solver", r.solver},
                         {"equal_time", false},
                         {"params", r.params},
                         {"failure", r.failure}});
      continue;
    }
    csv << r.scene << ',' << r.view << ',' << r.solver << ',' << (r.equal_time ? 1 : 0) << ",\""
        << r.params << "\"," << r.spp << ',' << r.first_ms << ',' << r.full.median << ','
        << r.full.p95 << ',' << r.light.median << ',' << r.light.p95 << ',' << r.camera.median
        << ',' << r.camera.p95 << ',' << r.error.rel_mse << ',' << r.error.rmse << ','
        << r.error.ssim << ',' << r.error.nonfinite_fraction << ",\n";
    results.push_back({{"scene", r.scene},
                       {"view", r.view},
                       {"solver", r.solver},
                       {"equal_time", r.equal_time},
                       {"params", r.params},
                       {"spp", r.spp},
                       {"first_ms", r.first_ms},
                       {"full_ms", {{"median", r.full.median}, {"p95", r.full.p95}}},
                       {"light_ms", {{"median", r.light.median}, {"p95", r.light.p95}}},
                       {"camera_ms", {{"median", r.camera.median}, {"p95", r.camera.p95}}},
                       {"rel_mse", r.error.rel_mse},
                       {"rmse", r.error.rmse},
                       {"ssim", r.error.ssim},
                       {"nonfinite_fraction", r.error.nonfinite_fraction},
                       {"stages",
                        {{"full", StagesJson(r.full_stages)},
                         {"light", StagesJson(r.light_stages)},
                         {"camera", StagesJson(r.camera_stages)}}}});
  }
  nlohmann::json doc = meta;
  doc["results"] = results;
  if (!animation_rows.empty()) doc["animation"] = animation_rows;
  std::ofstream(dir / "results.json") << doc.dump(2) << '\n';
  return WritePlotAndMarkdown(dir, rows, meta, animation_rows);
}

// error_vs_time.png (one series per solver and scene, log-log) and
// results.md (the tables, the plot's colours).
absl::Status WritePlotAndMarkdown(const std::filesystem::path& dir,
                                  const std::vector<EvalRow>& rows, const nlohmann::json& meta,
                                  const nlohmann::json& animation_rows) {
  std::vector<PlotSeries> series;
  auto series_for = [&](const std::string& name) -> PlotSeries& {
    for (PlotSeries& s : series) {
      if (s.name == name) return s;
    }
    series.push_back({name, {}});
    return series.back();
  };
  for (const EvalRow& r : rows) {
    if (!r.failure.empty()) continue;
    const std::string name =
        absl::StrCat(r.scene, "/", r.view, ": ", r.solver, r.equal_time ? " (equal time)" : "");
    series_for(name).points.emplace_back(r.full.median, r.error.rel_mse);
  }
  const Raster plot = PlotLogLog(series, 720, 480);
  GS_ASSIGN_OR_RETURN(std::string png, EncodePng(plot.rgba, plot.width, plot.height));
  std::ofstream(dir / "error_vs_time.png", std::ios::binary) << png;

  std::ofstream md(dir / "results.md");
  md << "Measured " << meta.value("date", "") << " on " << meta.value("gl_renderer", "") << " (CPU "
     << meta.value("cpu", "") << ")"
     << " with `" << meta.value("command", "") << "`.\n\n"
     << Markdown(rows) << "\nPlot `error_vs_time.png`: relMSE (y) against the median "
     << "full-update frame time in ms (x), log-log; tick labels are powers of ten. Colours:\n\n";
  for (size_t i = 0; i < series.size(); ++i) {
    md << "- " << SeriesColorName(i) << ": " << series[i].name << "\n";
  }
  if (!animation_rows.empty()) {
    md << "\nDuring each scene's animation, every frame against a reference of the state it "
          "shows (frames.csv under animation/):\n\n"
       << AnimationMarkdown(animation_rows);
  }
  return absl::OkStatus();
}

// A scene's content key for the reference cache: the scene file when it
// is readable here, else what the server reports about the scene (counts,
// bounds, materials, lights).
std::string ContentKey(const std::string& name, const LoadedScene& loaded) {
  std::string content;
  for (const char* ext : {".gltf", ".glb"}) {
    if (auto file = ReadText(std::filesystem::path("scenes") / (name + ext)); file.ok()) {
      content = *file;
    }
  }
  if (content.empty()) {
    v1::LoadSceneResponse info = loaded.info();
    info.clear_scene_id();
    info.clear_version();
    content = info.SerializeAsString();
  }
  return std::to_string(Fnv1a(content));
}

// Every solver setting of the spec in one view: a row each (a refused
// setting's row says why).
absl::Status MeasureSolvers(Evaluator& evaluator, const EvalSpec& spec, const LoadedScene& loaded,
                            const EvalScene& scene, const EvalView& view,
                            const RgbaImage& reference, float yfov, std::vector<EvalRow>& rows) {
  for (const EvalSolver& solver : spec.solvers) {
    for (const auto& params : solver.Settings()) {
      std::string setting;
      for (const auto& [k, v] : params) absl::StrAppend(&setting, " ", k, "=", v);
      evaluator.progress().Wait(
          absl::StrCat(scene.name, "/", view.name, " ", solver.name, setting));
      absl::StatusOr<EvalRow> row =
          evaluator.Measure(loaded.id(), scene, view, solver.name, params, reference, yfov);
      evaluator.progress().Done();
      if (!row.ok()) {
        if (!IsRefusal(row.status())) return row.status();
        EvalRow failed;
        failed.scene = scene.name;
        failed.view = view.name;
        failed.solver = solver.name;
        failed.params = ParamsText(params);
        failed.failure = row.status().ToString();
        std::cerr << scene.name << "/" << view.name << " " << solver.name << " " << failed.params
                  << ": not measured: " << failed.failure << "\n";
        rows.push_back(std::move(failed));
        continue;
      }
      std::cerr << scene.name << "/" << view.name << " " << solver.name << " " << row->params
                << ": relMSE " << row->error.rel_mse << ", full " << row->full.median << " ms\n";
      rows.push_back(*std::move(row));
    }
  }
  return absl::OkStatus();
}

// A scene's animation (issue 27): per solver setting, one session playing
// the script, every frame against a reference of the state it shows
// (RunInteraction). Returns a row per setting: scene, solver, params and
// bench's "converge" entry (or "failure").
absl::Status MeasureAnimation(const ConnectionOptions& connection, const EvalOptions& options,
                              const EvalSpec& spec, const EvalScene& scene, nlohmann::json& rows) {
  const EvalAnimation& animation = *scene.animation;
  std::filesystem::path script = animation.script;
  if (script.is_relative()) script = options.file.parent_path() / script;
  int k = 0;
  for (const EvalSolver& solver : spec.solvers) {
    for (const auto& params : solver.Settings()) {
      BenchOptions bench;
      bench.scene.scene = scene.name;
      bench.solver.solver = solver.name;
      bench.solver.params = params;
      bench.view.width = spec.width;
      bench.view.height = spec.height;
      bench.view.encoding.set_format(v1::IMAGE_FORMAT_EXR);
      bench.view.refine_samples = spec.refine_samples;
      bench.workload = script.string();
      bench.update_hz = animation.update_hz;
      bench.fps = float(animation.fps);
      bench.sessions = {1};
      bench.duration_s = animation.duration_s;
      bench.warmup_s = animation.warmup_s;
      bench.reference_spp = spec.reference_spp;
      bench.out_dir = options.out_dir / "animation" / absl::StrCat(scene.name, "_", k++);
      nlohmann::json row = {{"scene", scene.name},
                            {"solver", solver.name},
                            {"params", ParamsText(params)},
                            {"script", script.string()},
                            {"frames_csv", (bench.out_dir / "frames.csv").string()}};
      absl::StatusOr<std::string> converge = RunInteraction(connection, bench);
      if (converge.ok()) {
        row["converge"] = nlohmann::json::parse(*converge);
      } else if (IsRefusal(converge.status())) {
        row["failure"] = converge.status().ToString();
      } else {
        return converge.status();
      }
      rows.push_back(std::move(row));
    }
  }
  return absl::OkStatus();
}

// "x.xxe-yy (N.Nx)" of a relMSE against the full solve's.
std::string Versus(const nlohmann::json& over, const char* key, double full) {
  if (!over.contains(key) || !over[key].is_number()) return "-";
  const double v = over[key].get<double>();
  return absl::StrCat(Sci(v), " (", Fixed(v / full, 1), "x)");
}

std::string Within(const nlohmann::json& over, const char* key) {
  if (!over.contains(key) || !over[key].is_object()) return "never";
  return absl::StrCat(over[key].value("frames", 0), " / ", Fixed(over[key].value("ms", 0.0), 0));
}

// The animations' table: the error of the frames shown during the motion
// and after the stop, against the full solve's of the final state.
std::string AnimationMarkdown(const nlohmann::json& rows) {
  std::ostringstream md;
  md << "| scene | solver | params | full solve relMSE | motion mean (x full) | motion p95 | "
        "first frame after the stop (x full) | within 2x: frames / ms | within 1.05x: frames / "
        "ms |\n"
     << "| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const nlohmann::json& r : rows) {
    md << "| " << r.value("scene", "") << " | " << r.value("solver", "") << " | "
       << r.value("params", "") << " | ";
    const nlohmann::json converge = r.value("converge", nlohmann::json());
    const nlohmann::json over =
        converge.is_object() ? converge.value("over_time", nlohmann::json()) : nlohmann::json();
    if (!over.is_object() || !over.contains("full_solve_rel_mse")) {
      md << "not measured: "
         << absl::StrReplaceAll(r.value("failure", std::string("no frames after the stop")),
                                {{"|", "/"}, {"\n", " "}})
         << " | | | | | |\n";
      continue;
    }
    const double full = over["full_solve_rel_mse"].get<double>();
    md << Sci(full) << " | " << Versus(over, "motion_mean_rel_mse", full) << " | "
       << (over.contains("motion_p95_rel_mse") ? Sci(over["motion_p95_rel_mse"].get<double>())
                                               : std::string("-"))
       << " | " << Versus(over, "first_after_stop_rel_mse", full) << " | "
       << Within(over, "within_2x") << " | " << Within(over, "within_1_05x") << " |\n";
  }
  return md.str();
}

// The path tracer as the peer curve: its error at equal time budgets.
absl::Status MeasurePathtrace(Evaluator& evaluator, const EvalSpec& spec, const LoadedScene& loaded,
                              const EvalScene& scene, const EvalView& view,
                              const RgbaImage& reference, std::vector<EvalRow>& rows) {
  for (size_t i = 0; i < spec.pathtrace_budgets_ms.size(); ++i) {
    const double budget = spec.pathtrace_budgets_ms[i];
    std::ostringstream b;
    b << budget;
    evaluator.progress().Wait(
        absl::StrCat(scene.name, "/", view.name, " pathtrace ", b.str(), " ms"));
    GS_ASSIGN_OR_RETURN(v1::Frame frame, evaluator.RenderOnce(loaded.id(), "pathtrace",
                                                              {{"time_budget_ms", b.str()},
                                                               {"seed", std::to_string(1000 + i)}},
                                                              ViewCamera(view)));
    evaluator.progress().Done();
    GS_ASSIGN_OR_RETURN(RgbaImage image, DecodeFrame(frame));
    EvalRow row;
    row.scene = scene.name;
    row.view = view.name;
    row.solver = "pathtrace";
    row.equal_time = true;
    row.params = absl::StrCat("time_budget_ms=", b.str());
    row.spp = FrameStatValue(frame, "spp_total");
    row.full.median = row.full.p95 = frame.total_ms();
    StatsCollector stages;
    stages.Add(frame, StatsCollector::Clock::now());
    row.full_stages = stages.Summarize().stages;
    GS_ASSIGN_OR_RETURN(row.error, CompareImages(image, reference));
    rows.push_back(std::move(row));
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status RunEval(const ConnectionOptions& connection_options, const EvalOptions& options) {
  GS_ASSIGN_OR_RETURN(const std::string text, ReadText(options.file));
  GS_ASSIGN_OR_RETURN(const EvalSpec spec, ParseEvalSpec(text));
  Connection connection(connection_options);
  v1::ServerStatus status;
  GS_RETURN_IF_ERROR(
      connection.Call(&v1::Gistream::Stub::GetServerStatus, v1::GetServerStatusRequest(), &status));
  Evaluator evaluator(connection, spec);
  std::vector<EvalRow> rows;
  nlohmann::json animation_rows = nlohmann::json::array();
  for (const EvalScene& scene : spec.scenes) {
    v1::LoadSceneRequest load;
    load.set_name(scene.name);
    // Our own copy: another client's changes to the shared scene of that
    // name (a viewer's slider) cannot move what is measured.
    load.set_private_copy(true);
    GS_ASSIGN_OR_RETURN(std::unique_ptr<LoadedScene> loaded,
                        LoadedScene::Load(connection, load, /*keep=*/false));
    std::cerr << "eval: " << scene.name << " loaded as a private copy (" << loaded->id() << ")"
              << std::endl;
    const std::string content_key = ContentKey(scene.name, *loaded);
    const float base_yfov =
        loaded->info().cameras_size() > 0 ? loaded->info().cameras(0).yfov() * 57.29578f : 45.0f;
    for (const EvalView& view : scene.views) {
      GS_ASSIGN_OR_RETURN(RgbaImage reference,
                          evaluator.Reference(loaded->id(), content_key, view, options.cache_dir));
      const float yfov = view.yfov_degrees.value_or(base_yfov);
      GS_RETURN_IF_ERROR(
          MeasureSolvers(evaluator, spec, *loaded, scene, view, reference, yfov, rows));
      GS_RETURN_IF_ERROR(MeasurePathtrace(evaluator, spec, *loaded, scene, view, reference, rows));
    }
    if (scene.animation) {
      GS_RETURN_IF_ERROR(
          MeasureAnimation(connection_options, options, spec, scene, animation_rows));
    }
  }
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof(date), "%Y-%m-%d", std::gmtime(&now));
  const nlohmann::json meta = {
      {"date", date},
      {"gl_renderer", status.gl_renderer()},
      {"gl_version", status.gl_version()},
      {"cpu", absl::StrCat(status.cpu_model(), ", ", status.cpu_threads(), " threads")},
      {"command", absl::StrCat("gistream eval ", options.file.string())},
      {"size", {spec.width, spec.height}},
      {"reference_spp", spec.reference_spp}};
  GS_RETURN_IF_ERROR(WriteOutputs(options.out_dir, rows, meta, animation_rows));
  std::cout << "Measured " << date << " on " << status.gl_renderer() << " (CPU "
            << status.cpu_model() << ", " << status.cpu_threads() << " threads)\n\n"
            << Markdown(rows);
  if (!animation_rows.empty()) {
    std::cout << "\nDuring the animation (every frame against a reference of its state):\n\n"
              << AnimationMarkdown(animation_rows);
  }
  std::cout << "\nwrote " << (options.out_dir / "results.{csv,json,md}").string() << " and "
            << (options.out_dir / "error_vs_time.png").string() << "\n";
  return absl::OkStatus();
}

}  // namespace gistream::client
