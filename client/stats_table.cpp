#include "stats_table.h"

#include <algorithm>
#include <cmath>

#include <absl/strings/str_cat.h>
#include <absl/strings/str_join.h>

#include "text_table.h"

namespace gistream::client {
namespace {

std::string Ms(const std::optional<double>& value) { return value ? FormatFixed(*value) : "-"; }

// Solver stats print as integers when they are whole numbers (counts).
std::string StatValue(double value) {
  if (std::isfinite(value) && value == std::floor(value) && std::fabs(value) < 1e15) {
    return absl::StrCat(static_cast<int64_t>(value));
  }
  return absl::StrCat(value);
}

}  // namespace

std::optional<double> Percentile(std::vector<double> values, double p) {
  if (values.empty()) return std::nullopt;
  std::sort(values.begin(), values.end());
  const double rank = std::clamp(p, 0.0, 100.0) / 100.0 * static_cast<double>(values.size() - 1);
  const size_t lower = static_cast<size_t>(std::floor(rank));
  const size_t upper = std::min(lower + 1, values.size() - 1);
  const double t = rank - static_cast<double>(lower);
  return values[lower] + (values[upper] - values[lower]) * t;
}

void StatsCollector::Add(const v1::Frame& frame, Clock::time_point arrival,
                         std::optional<double> round_trip_ms) {
  ++frames_;
  for (const v1::StageTiming& timing : frame.timings()) {
    auto it = std::find_if(stages_.begin(), stages_.end(),
                           [&](const Stage& stage) { return stage.name == timing.name(); });
    if (it == stages_.end()) {
      it = stages_.insert(stages_.end(), Stage());
      it->name = timing.name();
    }
    if (timing.skipped()) {
      ++it->skipped;
      continue;
    }
    it->cpu_ms.push_back(timing.cpu_ms());
    it->gpu_ms.push_back(timing.gpu_ms());
    it->all_cpu = it->all_cpu && timing.cpu_stage();
  }
  total_ms_.push_back(frame.total_ms());
  if (round_trip_ms) round_trip_ms_.push_back(*round_trip_ms);
  if (!first_arrival_) first_arrival_ = arrival;
  last_arrival_ = arrival;
  dropped_ += frame.dropped_frames();
  last_stats_.clear();
  last_stats_.insert(frame.stats().begin(), frame.stats().end());
}

StatsSummary StatsCollector::Summarize() const {
  StatsSummary summary;
  summary.frames = frames_;
  for (const Stage& stage : stages_) {
    StageSummary& out = summary.stages.emplace_back();
    out.name = stage.name;
    out.runs = static_cast<int>(stage.cpu_ms.size());
    out.skipped = stage.skipped;
    out.cpu_stage = out.runs > 0 && stage.all_cpu;
    out.cpu_median = Percentile(stage.cpu_ms, 50);
    out.cpu_p95 = Percentile(stage.cpu_ms, 95);
    if (!out.cpu_stage) {
      out.gpu_median = Percentile(stage.gpu_ms, 50);
      out.gpu_p95 = Percentile(stage.gpu_ms, 95);
    }
  }
  summary.total_median = Percentile(total_ms_, 50);
  summary.total_p95 = Percentile(total_ms_, 95);
  summary.round_trip_median = Percentile(round_trip_ms_, 50);
  summary.round_trip_p95 = Percentile(round_trip_ms_, 95);
  if (frames_ >= 2) {
    const double seconds = std::chrono::duration<double>(*last_arrival_ - *first_arrival_).count();
    if (seconds > 0.0) summary.fps = (frames_ - 1) / seconds;
  }
  summary.dropped = dropped_;
  summary.last_stats = last_stats_;
  return summary;
}

std::string FormatStatsTable(const StatsSummary& summary) {
  using Align = TextTable::Align;
  TextTable table({{"stage"},
                   {"runs", Align::kRight},
                   {"skipped", Align::kRight},
                   {"CPU median", Align::kRight},
                   {"CPU p95", Align::kRight},
                   {"GPU median", Align::kRight},
                   {"GPU p95", Align::kRight}});
  for (const StageSummary& stage : summary.stages) {
    table.AddRow({stage.name, absl::StrCat(stage.runs), absl::StrCat(stage.skipped),
                  Ms(stage.cpu_median), Ms(stage.cpu_p95), Ms(stage.gpu_median),
                  Ms(stage.gpu_p95)});
  }
  std::string out = absl::StrCat("per-stage timings over ", summary.frames, " frames (ms):\n");
  out += table.Render();
  out += absl::StrCat("frame total (server): median ", Ms(summary.total_median), " ms, p95 ",
                      Ms(summary.total_p95), " ms\n");
  if (summary.round_trip_median) {
    out += absl::StrCat("round trip (client): median ", Ms(summary.round_trip_median), " ms, p95 ",
                        Ms(summary.round_trip_p95), " ms\n");
  }
  out += absl::StrCat("achieved: ", summary.fps ? FormatFixed(*summary.fps, 1) : "-",
                      " fps, dropped frames: ", summary.dropped, "\n");
  if (!summary.last_stats.empty()) {
    out += "solver stats (last frame): ";
    out += absl::StrJoin(summary.last_stats, " ", [](std::string* s, const auto& entry) {
      absl::StrAppend(s, entry.first, "=", StatValue(entry.second));
    });
    out += "\n";
  }
  return out;
}

nlohmann::json StagesJson(const std::vector<StageSummary>& stages) {
  nlohmann::json out = nlohmann::json::array();
  auto number = [](const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
  };
  for (const StageSummary& s : stages) {
    out.push_back({{"name", s.name},
                   {"runs", s.runs},
                   {"skipped", s.skipped},
                   {"cpu_stage", s.cpu_stage},
                   {"cpu_median_ms", number(s.cpu_median)},
                   {"cpu_p95_ms", number(s.cpu_p95)},
                   {"gpu_median_ms", number(s.gpu_median)},
                   {"gpu_p95_ms", number(s.gpu_p95)}});
  }
  return out;
}

}  // namespace gistream::client
