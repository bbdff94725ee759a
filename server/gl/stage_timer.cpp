#include "gl/stage_timer.h"
#include "gl/driver_quirks.h"

#include <algorithm>

#include "util/status.h"

namespace gistream::gl {

void StageTimer::Reset() {
  entries_.clear();
  used_queries_ = 0;
  open_ = -1;
}

int StageTimer::NextQuery() {
  if (used_queries_ == int(queries_.size())) queries_.push_back(Query::Create(GL_TIMESTAMP));
  return used_queries_++;
}

void StageTimer::Begin(const std::string& stage, bool cpu_stage) {
  GS_CHECK(open_ < 0);  // stages do not nest
  Entry entry;
  entry.timing.name = stage;
  entry.timing.cpu_stage = cpu_stage;
  if (!cpu_stage) {
    entry.query_begin = NextQuery();
    glQueryCounter(queries_[size_t(entry.query_begin)].id(), GL_TIMESTAMP);
  }
  entry.cpu_start = std::chrono::steady_clock::now();
  entries_.push_back(std::move(entry));
  open_ = int(entries_.size()) - 1;
}

void StageTimer::End() {
  GS_CHECK(open_ >= 0);
  Entry& entry = entries_[size_t(open_)];
  if (!entry.timing.cpu_stage) {
    entry.query_end = NextQuery();
    glQueryCounter(queries_[size_t(entry.query_end)].id(), GL_TIMESTAMP);
    // Submit now on a deferred driver (DriverQuirks::flush_after_gpu_stage),
    // so this stage runs before a following CPU stage and its time stays
    // its own.
    if (CurrentQuirks().flush_after_gpu_stage) glFlush();
  }
  entry.timing.cpu_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - entry.cpu_start)
          .count();
  open_ = -1;
}

void StageTimer::Skip(const std::string& stage) {
  Entry entry;
  entry.timing.name = stage;
  entry.timing.skipped = true;
  entries_.push_back(std::move(entry));
}

void StageTimer::Record(const std::string& stage, double cpu_ms) {
  Entry entry;
  entry.timing.name = stage;
  entry.timing.cpu_ms = cpu_ms;
  entry.timing.cpu_stage = true;
  entries_.push_back(std::move(entry));
}

std::vector<StageTiming> StageTimer::Finish() {
  GS_CHECK(open_ < 0);
  std::vector<StageTiming> out;
  out.reserve(entries_.size());
  for (Entry& entry : entries_) {
    if (entry.query_begin >= 0 && entry.query_end >= 0) {
      GLuint64 t0 = 0, t1 = 0;
      glGetQueryObjectui64v(queries_[size_t(entry.query_begin)].id(), GL_QUERY_RESULT, &t0);
      glGetQueryObjectui64v(queries_[size_t(entry.query_end)].id(), GL_QUERY_RESULT, &t1);
      entry.timing.gpu_ms = t1 > t0 ? double(t1 - t0) * 1e-6 : 0.0;
    }
    // A stage that ran several times (one per bounce of an iterative
    // solver) is reported once, with its times summed; it counts as
    // skipped only when every occurrence was.
    auto same = std::find_if(out.begin(), out.end(),
                             [&](const StageTiming& t) { return t.name == entry.timing.name; });
    if (same == out.end()) {
      out.push_back(entry.timing);
    } else if (same->skipped) {
      *same = entry.timing;
    } else if (!entry.timing.skipped) {
      same->cpu_ms += entry.timing.cpu_ms;
      same->gpu_ms += entry.timing.gpu_ms;
    }
  }
  return out;
}

}  // namespace gistream::gl
