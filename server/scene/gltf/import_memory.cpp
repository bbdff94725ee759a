#include "scene/gltf/import_memory.h"

#include <utility>

namespace gistream {

absl::Status ImportMemory::Reserve(uint64_t bytes, const std::string& what) {
  GS_ASSIGN_OR_RETURN(MemoryBudget::Reservation more, budget_.Reserve(bytes, what));
  held_.Merge(std::move(more));
  return absl::OkStatus();
}

}  // namespace gistream
