#include "bench_report.h"

#include <algorithm>
#include <fstream>

#include <absl/strings/str_cat.h>
#include <absl/strings/str_format.h>

#include "encode/encode.h"
#include "plot.h"
#include "text_table.h"

namespace gistream::client {
namespace {

std::string Ms(const std::optional<double>& v, int digits = 1) {
  return v ? FormatFixed(*v, digits) : "-";
}

nlohmann::json Number(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

nlohmann::json QuantilesJson(const Quantiles& q) {
  return {{"p50", Number(q.p50)},
          {"p95", Number(q.p95)},
          {"p99", Number(q.p99)},
          {"max", Number(q.max)}};
}

uint64_t MaxRss(const StepResult& step) {
  uint64_t rss = 0;
  for (const ServerSample& s : step.servers) rss = std::max(rss, s.max_rss_bytes);
  return rss;
}

double CpuPercent(const StepResult& step) {
  double cpu = 0.0;
  for (const ServerSample& s : step.servers) cpu += s.cpu_percent;
  return cpu;
}

bool ServersKnown(const StepResult& step) {
  return std::any_of(step.servers.begin(), step.servers.end(),
                     [](const ServerSample& s) { return s.available; });
}

std::string StepLabel(const StepResult& step) {
  return absl::StrCat(step.sessions, step.sessions == 1 ? " session" : " sessions");
}

absl::Status WritePlot(const std::filesystem::path& path, const std::vector<PlotSeries>& series,
                       const PlotStyle& style) {
  const Raster plot = PlotLines(series, style, 720, 480);
  GS_ASSIGN_OR_RETURN(std::string png, EncodePng(plot.rgba, plot.width, plot.height));
  std::ofstream(path, std::ios::binary) << png;
  return absl::OkStatus();
}

}  // namespace

std::string FormatBenchTable(const std::vector<StepResult>& steps) {
  TextTable table({{"sessions", TextTable::Align::kRight},
                   {"fps/session", TextTable::Align::kRight},
                   {"fps min", TextTable::Align::kRight},
                   {"fps total", TextTable::Align::kRight},
                   {"interval p50/p95/max ms", TextTable::Align::kRight},
                   {"latency p50/p95/p99/max ms", TextTable::Align::kRight},
                   {"settle p50/max ms", TextTable::Align::kRight},
                   {"updates", TextTable::Align::kRight},
                   {"dropped", TextTable::Align::kRight},
                   {"MB/s", TextTable::Align::kRight},
                   {"Jain", TextTable::Align::kRight},
                   {"RSS MB", TextTable::Align::kRight},
                   {"CPU %", TextTable::Align::kRight}});
  for (const StepResult& s : steps) {
    const bool known = ServersKnown(s);
    table.AddRow(
        {absl::StrCat(s.sessions,
                      s.failed_sessions ? absl::StrCat(" (", s.failed_sessions, " failed)") : ""),
         FormatFixed(s.fps_mean, 1), FormatFixed(s.fps_min, 1), FormatFixed(s.fps_total, 1),
         absl::StrCat(Ms(s.interval_ms.p50), " / ", Ms(s.interval_ms.p95), " / ",
                      Ms(s.interval_ms.max)),
         absl::StrCat(Ms(s.latency_ms.p50), " / ", Ms(s.latency_ms.p95), " / ",
                      Ms(s.latency_ms.p99), " / ", Ms(s.latency_ms.max)),
         absl::StrCat(Ms(s.settle_ms.p50, 0), " / ", Ms(s.settle_ms.max, 0),
                      s.unsettled ? absl::StrCat(" (", s.unsettled, " not)") : ""),
         absl::StrCat(s.updates_answered, "/", s.updates_sent), absl::StrCat(s.dropped),
         FormatFixed(s.bytes_per_s / 1e6, 2), FormatFixed(s.jain, 3),
         known ? FormatFixed(double(MaxRss(s)) / (1 << 20), 0) : "-",
         known ? FormatFixed(CpuPercent(s), 0) : "-"});
  }
  return table.Render();
}

std::string FormatStageMedians(const StatsSummary& stages) {
  std::string out;
  for (const StageSummary& s : stages.stages) {
    if (s.runs == 0) continue;
    const double ms = s.cpu_median.value_or(0.0) + (s.cpu_stage ? 0.0 : s.gpu_median.value_or(0.0));
    absl::StrAppend(&out, out.empty() ? "" : ", ", s.name, " ", FormatFixed(ms, 2));
  }
  return out.empty() ? "none" : out;
}

namespace {
// The moves of a step's sessions, pooled (sessions whose server drained or
// died and that went on elsewhere).
struct PooledMoves {
  int sessions_moved = 0, moves = 0, incomplete = 0;
  std::vector<double> gap_ms, to_acked_ms;
};
PooledMoves PoolMoves(const StepResult& step) {
  PooledMoves pooled;
  for (const SessionMeasurement& m : step.per_session) {
    pooled.sessions_moved += m.moves > 0 ? 1 : 0;
    pooled.moves += m.moves;
    pooled.incomplete += m.moves - static_cast<int>(m.move_to_acked_ms.size());
    pooled.gap_ms.insert(pooled.gap_ms.end(), m.move_gap_ms.begin(), m.move_gap_ms.end());
    pooled.to_acked_ms.insert(pooled.to_acked_ms.end(), m.move_to_acked_ms.begin(),
                              m.move_to_acked_ms.end());
  }
  return pooled;
}
nlohmann::json MovesJson(const StepResult& step) {
  const PooledMoves pooled = PoolMoves(step);
  return {{"sessions_moved", pooled.sessions_moved},
          {"moves", pooled.moves},
          {"incomplete", pooled.incomplete},
          {"gap_ms", QuantilesJson(Summarize(pooled.gap_ms))},
          {"to_acked_ms", QuantilesJson(Summarize(pooled.to_acked_ms))}};
}
}  // namespace

std::string FormatMoves(const StepResult& step) {
  const PooledMoves pooled = PoolMoves(step);
  if (pooled.moves == 0) return "";
  const Quantiles frame = Summarize(pooled.gap_ms), acked = Summarize(pooled.to_acked_ms);
  const auto ms = [](std::optional<double> v) {
    return v ? absl::StrFormat("%.0f", *v) : std::string("-");
  };
  return absl::StrCat("moves: ", pooled.sessions_moved, " of ", step.sessions,
                      " sessions moved to another server (", pooled.moves,
                      " moves); without frames p50/p95/max ", ms(frame.p50), "/", ms(frame.p95),
                      "/", ms(frame.max), " ms; every acknowledged update shown after ",
                      ms(acked.p50), "/", ms(acked.p95), "/", ms(acked.max), " ms; ",
                      pooled.incomplete, " incomplete");
}

nlohmann::json BenchJson(const std::vector<StepResult>& steps, const nlohmann::json& meta) {
  nlohmann::json doc = meta;
  nlohmann::json out = nlohmann::json::array();
  for (const StepResult& s : steps) {
    nlohmann::json sessions = nlohmann::json::array();
    for (const SessionMeasurement& m : s.per_session) {
      sessions.push_back({{"server", m.server},
                          {"frames", m.frames},
                          {"fps", m.fps()},
                          {"interval_ms", QuantilesJson(Summarize(m.intervals_ms))},
                          {"max_gap_ms", m.max_gap_ms},
                          {"latency_ms", QuantilesJson(Summarize(m.latencies_ms))},
                          {"updates_sent", m.updates_sent},
                          {"settle_ms", Number(m.settle_ms)},
                          {"updates_answered", m.latencies_ms.size()},
                          {"updates_rejected", m.updates_rejected},
                          {"updates_unanswered", m.updates_unanswered},
                          {"dropped_frames", m.dropped_frames},
                          {"bytes", m.bytes},
                          {"moves", m.moves},
                          {"move_gap_ms", m.move_gap_ms},
                          {"move_to_acked_ms", m.move_to_acked_ms},
                          {"error", m.error}});
    }
    nlohmann::json servers = nlohmann::json::array();
    for (const ServerSample& v : s.servers) {
      servers.push_back({{"server", v.server},
                         {"available", v.available},
                         {"max_rss_bytes", v.max_rss_bytes},
                         {"cpu_percent", v.cpu_percent}});
    }
    nlohmann::json step = {
        {"sessions", s.sessions},
        {"window_s", s.window_s},
        {"fps_mean", s.fps_mean},
        {"fps_min", s.fps_min},
        {"fps_total", s.fps_total},
        {"jain_fairness", s.jain},
        {"frames", s.frames},
        {"dropped_frames", s.dropped},
        {"updates_sent", s.updates_sent},
        {"updates_answered", s.updates_answered},
        {"updates_rejected", s.updates_rejected},
        {"updates_unanswered", s.updates_unanswered},
        {"bytes_per_s", s.bytes_per_s},
        {"failed_sessions", s.failed_sessions},
        {"latency_ms", QuantilesJson(s.latency_ms)},
        {"interval_ms", QuantilesJson(s.interval_ms)},
        {"settle_ms", QuantilesJson(s.settle_ms)},
        {"unsettled_sessions", s.unsettled},
        {"moves", MovesJson(s)},
        {"frame_total_ms",
         {{"median", Number(s.stages.total_median)}, {"p95", Number(s.stages.total_p95)}}},
        {"stages", StagesJson(s.stages.stages)},
        {"servers", servers},
        {"per_session", sessions}};
    if (!meta.value("interfere", std::string()).empty()) {
      step["interferer"] = {{"renders", s.interferer_renders},
                            {"median_ms", Number(s.interferer_median_ms)},
                            {"error", s.interferer_error}};
    }
    out.push_back(std::move(step));
  }
  doc["steps"] = std::move(out);
  return doc;
}

namespace {

// results.csv: a row per step.
absl::Status WriteBenchCsv(const std::filesystem::path& dir, const std::vector<StepResult>& steps) {
  std::ofstream csv(dir / "results.csv");
  csv << "sessions,window_s,fps_mean,fps_min,fps_total,jain,frames,dropped,interval_p50_ms,"
         "interval_p95_ms,interval_max_ms,latency_p50_ms,latency_p95_ms,latency_p99_ms,"
         "latency_max_ms,settle_p50_ms,settle_max_ms,unsettled_sessions,updates_sent,"
         "updates_answered,updates_rejected,updates_unanswered,"
         "bytes_per_s,max_rss_bytes,cpu_percent,failed_sessions,interferer_renders\n";
  auto cell = [](const std::optional<double>& v) { return v ? absl::StrCat(*v) : std::string(); };
  for (const StepResult& s : steps) {
    csv << s.sessions << ',' << s.window_s << ',' << s.fps_mean << ',' << s.fps_min << ','
        << s.fps_total << ',' << s.jain << ',' << s.frames << ',' << s.dropped << ','
        << cell(s.interval_ms.p50) << ',' << cell(s.interval_ms.p95) << ','
        << cell(s.interval_ms.max) << ',' << cell(s.latency_ms.p50) << ',' << cell(s.latency_ms.p95)
        << ',' << cell(s.latency_ms.p99) << ',' << cell(s.latency_ms.max) << ','
        << cell(s.settle_ms.p50) << ',' << cell(s.settle_ms.max) << ',' << s.unsettled << ','
        << s.updates_sent << ',' << s.updates_answered << ',' << s.updates_rejected << ','
        << s.updates_unanswered << ',' << s.bytes_per_s << ',' << MaxRss(s) << ',' << CpuPercent(s)
        << ',' << s.failed_sessions << ',' << s.interferer_renders << '\n';
  }
  if (!csv)
    return absl::UnavailableError(absl::StrCat("cannot write ", (dir / "results.csv").string()));
  return absl::OkStatus();
}

// latency_cdf.png, fps_vs_sessions.png, latency_vs_sessions.png.
absl::Status WriteBenchPlots(const std::filesystem::path& dir,
                             const std::vector<StepResult>& steps) {
  // Latency CDF, one curve per step: x latency (ms, log), y fraction.
  std::vector<PlotSeries> cdf;
  for (const StepResult& s : steps) {
    PlotSeries series{StepLabel(s), {}};
    const size_t n = s.all_latencies_ms.size();
    for (size_t i = 0; i < n; ++i) {
      series.points.emplace_back(std::max(s.all_latencies_ms[i], 0.01), double(i + 1) / double(n));
    }
    cdf.push_back(std::move(series));
  }
  GS_RETURN_IF_ERROR(WritePlot(dir / "latency_cdf.png", cdf,
                               {.x_title = "update-to-frame latency ms",
                                .y_title = "fraction of updates",
                                .x_scale = AxisScale::kLog,
                                .y_scale = AxisScale::kLinear,
                                .markers = false}));
  PlotSeries fps_mean{"fps per session (mean)", {}}, fps_min{"fps per session (min)", {}},
      fps_total{"fps total", {}};
  PlotSeries lat_p95{"latency p95 ms", {}}, lat_p50{"latency p50 ms", {}},
      interval_p95{"frame interval p95 ms", {}}, gap{"longest frame interval ms", {}};
  for (const StepResult& s : steps) {
    const double n = s.sessions;
    fps_mean.points.emplace_back(n, s.fps_mean);
    fps_min.points.emplace_back(n, s.fps_min);
    fps_total.points.emplace_back(n, s.fps_total);
    if (s.latency_ms.p95) lat_p95.points.emplace_back(n, *s.latency_ms.p95);
    if (s.latency_ms.p50) lat_p50.points.emplace_back(n, *s.latency_ms.p50);
    if (s.interval_ms.p95) interval_p95.points.emplace_back(n, *s.interval_ms.p95);
    if (s.interval_ms.max) gap.points.emplace_back(n, *s.interval_ms.max);
  }
  GS_RETURN_IF_ERROR(WritePlot(dir / "fps_vs_sessions.png", {fps_mean, fps_min, fps_total},
                               {.x_title = "sessions",
                                .y_title = "frames per second",
                                .x_scale = AxisScale::kLog,
                                .y_scale = AxisScale::kLinear}));
  GS_RETURN_IF_ERROR(WritePlot(dir / "latency_vs_sessions.png",
                               {lat_p50, lat_p95, interval_p95, gap},
                               {.x_title = "sessions",
                                .y_title = "ms",
                                .x_scale = AxisScale::kLog,
                                .y_scale = AxisScale::kLog}));

  return absl::OkStatus();
}

// results.md: what ran, a table row per step, the stage medians.
void WriteBenchMarkdown(const std::filesystem::path& dir, const std::vector<StepResult>& steps,
                        const nlohmann::json& meta) {
  std::ofstream md(dir / "results.md");
  md << "Measured " << meta.value("date", "") << " on " << meta.value("gl_renderer", "") << " (CPU "
     << meta.value("cpu", "") << ") with `" << meta.value("command", "")
     << "`: " << meta.value("scene", "") << ", " << meta.value("solver", "") << ", "
     << meta.value("size", "") << ", workload " << meta.value("workload", "") << " ("
     << meta.value("workload_description", "") << "), " << meta.value("pacing", "") << ", fps cap "
     << meta.value("fps_cap", "") << ".\n\n";
  for (const std::string& line :
       {std::string("| sessions | fps/session (min) | fps total | "
                    "interval p50 / p95 / max ms | latency p50 / p95 / "
                    "p99 / max ms | settle p50 / max ms | updates answered/sent | dropped | "
                    "MB/s | Jain | RSS MB | CPU % |"),
        std::string("|---|---|---|---|---|---|---|---|---|---|---|---|")}) {
    md << line << "\n";
  }
  for (const StepResult& s : steps) {
    const bool known = ServersKnown(s);
    md << "| " << s.sessions << " | " << FormatFixed(s.fps_mean, 1) << " ("
       << FormatFixed(s.fps_min, 1) << ") | " << FormatFixed(s.fps_total, 1) << " | "
       << Ms(s.interval_ms.p50) << " / " << Ms(s.interval_ms.p95) << " / " << Ms(s.interval_ms.max)
       << " | " << Ms(s.latency_ms.p50) << " / " << Ms(s.latency_ms.p95) << " / "
       << Ms(s.latency_ms.p99) << " / " << Ms(s.latency_ms.max) << " | " << Ms(s.settle_ms.p50, 0)
       << " / " << Ms(s.settle_ms.max, 0) << (s.unsettled ? " (some did not)" : "") << " | "
       << s.updates_answered << "/" << s.updates_sent << " | " << s.dropped << " | "
       << FormatFixed(s.bytes_per_s / 1e6, 2) << " | " << FormatFixed(s.jain, 3) << " | "
       << (known ? FormatFixed(double(MaxRss(s)) / (1 << 20), 0) : "-") << " | "
       << (known ? FormatFixed(CpuPercent(s), 0) : "-") << " |\n";
  }
  md << "\nServer stage medians (ms) per step:\n\n";
  for (const StepResult& s : steps) {
    md << "- " << StepLabel(s) << ": " << FormatStageMedians(s.stages);
    if (!meta.value("interfere", std::string()).empty()) {
      md << "; interferer: " << s.interferer_renders << " renders, median "
         << Ms(s.interferer_median_ms, 0) << " ms";
    }
    md << "\n";
  }
  md << "\nPlots: `latency_cdf.png` (fraction of updates answered within x ms, log x), "
        "`fps_vs_sessions.png`, `latency_vs_sessions.png` (log-log).\n";
}

}  // namespace

absl::Status WriteBenchOutputs(const std::filesystem::path& dir,
                               const std::vector<StepResult>& steps, const nlohmann::json& meta) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return absl::UnavailableError(absl::StrCat("--out ", dir.string(), ": ", ec.message()));
  GS_RETURN_IF_ERROR(WriteBenchCsv(dir, steps));
  std::ofstream(dir / "results.json") << BenchJson(steps, meta).dump(2) << '\n';
  GS_RETURN_IF_ERROR(WriteBenchPlots(dir, steps));
  WriteBenchMarkdown(dir, steps, meta);
  return absl::OkStatus();
}

}  // namespace gistream::client
