// What `gistream bench` prints and writes: the step table, results.csv,
// results.json, results.md and the plots (latency CDF per step; fps and
// p95 latency against the session count).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_stats.h"
#include "util/status.h"

namespace gistream::client {

// One row per step:
//   sessions | fps/session | fps min | total fps | interval p50/p95/max | latency ...
std::string FormatBenchTable(const std::vector<StepResult>& steps);
// "moves: 4 of 4 sessions moved to another server (4 moves); without
// frames p50/p95/max ... ms; every acknowledged update shown after ... ms;
// 0 incomplete"; empty when no session moved.
std::string FormatMoves(const StepResult& step);

// "shadow_maps 0.81, gbuffer 1.20, ..." (CPU + GPU median per stage that ran).
std::string FormatStageMedians(const StatsSummary& stages);

// The results document: `meta` (command, server, scene, solver, ...) plus
// one object per step with its per-session details.
nlohmann::json BenchJson(const std::vector<StepResult>& steps, const nlohmann::json& meta);

// Writes results.{csv,json,md}, latency_cdf.png, fps_vs_sessions.png and
// latency_vs_sessions.png into `dir` (created).
absl::Status WriteBenchOutputs(const std::filesystem::path& dir,
                               const std::vector<StepResult>& steps, const nlohmann::json& meta);

}  // namespace gistream::client
