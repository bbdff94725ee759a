// Per-stage timings for one frame: CPU wall time from a steady clock and GPU
// time from GL timestamp queries (glQueryCounter, which unlike
// GL_TIME_ELAPSED allows back-to-back and nested stages). Results are read
// in Finish(), after the frame's readback has synchronised anyway.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "gl/handle.h"
#include "util/stage_timing.h"

namespace gistream::gl {

class StageTimer {
 public:
  StageTimer() = default;

  // Starts a frame: clears the previous frame's stages.
  void Reset();
  void Begin(const std::string& stage, bool cpu_stage = false);
  void End();
  // Records a stage the change did not need.
  void Skip(const std::string& stage);
  // Records a CPU stage that ran elsewhere (a background job on the CPU
  // pool) and took `cpu_ms`; it is reported in this frame.
  void Record(const std::string& stage, double cpu_ms);
  // Reads GPU results (blocks until the queries are available).
  std::vector<StageTiming> Finish();

  // RAII scope: Begin in the constructor, End in the destructor.
  class Scope {
   public:
    Scope(StageTimer& timer, const std::string& stage, bool cpu_stage = false) : timer_(timer) {
      timer_.Begin(stage, cpu_stage);
    }
    ~Scope() { timer_.End(); }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    StageTimer& timer_;
  };

 private:
  struct Entry {
    StageTiming timing;
    std::chrono::steady_clock::time_point cpu_start;
    int query_begin = -1;
    int query_end = -1;
  };
  int NextQuery();

  std::vector<Query> queries_;  // reused frame to frame
  int used_queries_ = 0;
  std::vector<Entry> entries_;
  int open_ = -1;
};

}  // namespace gistream::gl
