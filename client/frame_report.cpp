#include "frame_report.h"

#include <map>

#include <absl/strings/str_cat.h>
#include <absl/strings/str_join.h>

#include "image_format.h"
#include "text_table.h"

namespace gistream::client {

std::string FormatBytes(uint64_t bytes) {
  if (bytes < 1024) return absl::StrCat(bytes, " B");
  if (bytes < 1024 * 1024) return FormatFixed(static_cast<double>(bytes) / 1024.0, 1) + " KiB";
  return FormatFixed(static_cast<double>(bytes) / (1024.0 * 1024.0), 1) + " MiB";
}

std::string FormatSessionOpened(const v1::SessionOpened& opened) {
  const std::map<std::string, std::string> params(opened.params().begin(), opened.params().end());
  return absl::StrCat("session ", opened.session_id(), " on scene ", opened.scene_id(), ": solver ",
                      opened.solver(), " (", absl::StrJoin(params, ", ", absl::PairFormatter("=")),
                      ")");
}

std::string FormatFrameReport(const v1::Frame& frame, absl::string_view written_to) {
  std::string out = absl::StrCat(
      "wrote ", written_to, ": ", frame.width(), "x", frame.height(), " ",
      ImageFormatName(frame.format()), ", ", FormatBytes(frame.image().size()), ", solver ",
      frame.solver(), ", frame ", frame.frame_number(), ", scene version ", frame.scene_version(),
      ", ", FormatFixed(frame.total_ms()), " ms\n");

  using Align = TextTable::Align;
  TextTable table({{"stage"}, {"CPU ms", Align::kRight}, {"GPU ms", Align::kRight}});
  for (const v1::StageTiming& timing : frame.timings()) {
    if (timing.skipped()) {
      table.AddRow({timing.name(), "skipped", "skipped"});
    } else {
      table.AddRow({timing.name(), FormatFixed(timing.cpu_ms()),
                    timing.cpu_stage() ? "-" : FormatFixed(timing.gpu_ms())});
    }
  }
  out += table.Render("  ");
  if (!frame.stats().empty()) {
    std::map<std::string, double> sorted(frame.stats().begin(), frame.stats().end());
    out += "  stats: ";
    out += absl::StrJoin(sorted, " ", absl::PairFormatter("="));
    out += "\n";
  }
  return out;
}

}  // namespace gistream::client
