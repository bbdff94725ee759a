// What an import holds while it runs (issue 13): the file bytes it reads
// and the images it decodes, reserved from the server's memory budget
// (util/memory_budget.h) before they are decoded, and held until the import
// is done (the engine then reserves the scene itself, scene_memory.h).
// Decoded sizes come from the image header (DecodeImage), so a 500 KB PNG
// that decodes to 600 MB is refused before a pixel is allocated.
#pragma once

#include <cstdint>
#include <string>

#include "util/memory_budget.h"
#include "util/status.h"

namespace gistream {

class ImportMemory {
 public:
  explicit ImportMemory(MemoryBudget& budget) : budget_(budget) {}

  // RESOURCE_EXHAUSTED naming `what` when the budget cannot hold `bytes`
  // more.
  absl::Status Reserve(uint64_t bytes, const std::string& what);
  uint64_t bytes() const { return held_.bytes(); }
  void Release() { held_.Release(); }

 private:
  MemoryBudget& budget_;
  MemoryBudget::Reservation held_;
};

}  // namespace gistream
