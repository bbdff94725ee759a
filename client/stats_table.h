// Per-stage timing statistics over the frames of a session, and the table
// `stream` and `script` print at the end:
//
//   stage       | runs | skipped | CPU median | CPU p95 | GPU median | GPU p95
//   shadow_maps |   30 |       0 |       0.04 |    0.06 |       0.81 |    0.90
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gistream/v1/gistream.pb.h"

namespace gistream::client {

// The p-th percentile (p in [0, 100]) with linear interpolation between
// closest ranks (numpy's default): p=50 is the median, and the average of
// the middle two for an even count. nullopt for no values.
std::optional<double> Percentile(std::vector<double> values, double p);

struct StageSummary {
  std::string name;
  int runs = 0;            // frames in which the stage ran
  int skipped = 0;         // frames that reported it skipped
  bool cpu_stage = false;  // every run said cpu_stage: GPU columns print "-"
  // Over the runs only; nullopt when the stage never ran.
  std::optional<double> cpu_median, cpu_p95, gpu_median, gpu_p95;
};

struct StatsSummary {
  int frames = 0;
  std::vector<StageSummary> stages;               // in order of first appearance
  std::optional<double> total_median, total_p95;  // Frame.total_ms
  // Frames per second between the first and the last frame's arrival.
  std::optional<double> fps;
  uint64_t dropped = 0;  // sum of Frame.dropped_frames
  // Client-side request-to-frame time, when the caller measured it.
  std::optional<double> round_trip_median, round_trip_p95;
  std::map<std::string, double> last_stats;  // the last frame's solver stats
};

class StatsCollector {
 public:
  using Clock = std::chrono::steady_clock;

  // `round_trip_ms`: from the frame request to the frame's arrival.
  void Add(const v1::Frame& frame, Clock::time_point arrival,
           std::optional<double> round_trip_ms = std::nullopt);
  int frames() const { return frames_; }
  StatsSummary Summarize() const;

 private:
  struct Stage {
    std::string name;
    int skipped = 0;
    bool all_cpu = true;
    std::vector<double> cpu_ms, gpu_ms;
  };

  int frames_ = 0;
  std::vector<Stage> stages_;
  std::vector<double> total_ms_, round_trip_ms_;
  std::optional<Clock::time_point> first_arrival_, last_arrival_;
  uint64_t dropped_ = 0;
  std::map<std::string, double> last_stats_;
};

// The table, then the frame-time, fps, dropped and solver-stats lines.
std::string FormatStatsTable(const StatsSummary& summary);

// The stages as JSON objects (name, runs, skipped, cpu_stage, CPU/GPU
// median and p95 in ms; null where a stage never ran), for results files.
nlohmann::json StagesJson(const std::vector<StageSummary>& stages);

}  // namespace gistream::client
