// The server-wide memory budget (gistreamd --max-memory-bytes): decoded
// images and scenes (their CPU copy and their GPU upload) and solver state
// (estimated from the parameters and the scene before it is built) reserve
// their bytes here before they are allocated, and give them back when they
// are freed. A reservation is an RAII token: dropping it (unloading the
// scene, closing the last session of a solver, evicting it) returns the
// bytes. One count for CPU and GPU bytes together: on llvmpipe and on
// unified-memory machines both are the same RAM, and a discrete GPU's
// memory is checked separately by the driver's GL_OUT_OF_MEMORY.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "util/status.h"

namespace gistream {

class MemoryBudget {
 public:
  // Bytes held until destroyed or Release()d. Move-only; an empty one holds
  // nothing.
  class Reservation {
   public:
    Reservation() = default;
    ~Reservation() { Release(); }
    Reservation(Reservation&& other) noexcept;
    Reservation& operator=(Reservation&& other) noexcept;
    Reservation(const Reservation&) = delete;
    Reservation& operator=(const Reservation&) = delete;

    uint64_t bytes() const { return bytes_; }
    void Release();
    // Takes `other`'s bytes into this one (both of one budget, or this one
    // empty).
    void Merge(Reservation&& other);

   private:
    friend class MemoryBudget;
    struct Counter;
    Reservation(std::shared_ptr<Counter> counter, uint64_t bytes)
        : counter_(std::move(counter)), bytes_(bytes) {}
    std::shared_ptr<Counter> counter_;
    uint64_t bytes_ = 0;
  };

  // limit_bytes 0: DefaultMemoryLimit(). `name` and `limit_name` word the
  // refusal; the defaults are the server's budget's.
  explicit MemoryBudget(uint64_t limit_bytes, std::string name = "the server's memory budget",
                        std::string limit_name = "--max-memory-bytes");

  // RESOURCE_EXHAUSTED when `bytes` do not fit in what is left:
  // "<what> needs 5.1 GiB, more than the 3.0 GiB left of the server's memory
  // budget (--max-memory-bytes 12.0 GiB, 9.0 GiB in use)".
  absl::StatusOr<Reservation> Reserve(uint64_t bytes, const std::string& what);

  uint64_t limit() const { return limit_; }
  uint64_t used() const;

 private:
  uint64_t limit_;
  std::string name_;
  std::string limit_name_;
  std::shared_ptr<Reservation::Counter> counter_;
};

// Three quarters of the memory this process may use: the machine's
// physical memory (sysconf), or the cgroup's memory limit when lower (a
// container's or pod's limit: beyond it the kernel kills the process
// instead of a load being refused with RESOURCE_EXHAUSTED). The rest is
// left to the process's code, encoders, gRPC buffers and transient work.
uint64_t DefaultMemoryLimit();
// The same from given figures (cgroup_bytes 0: no cgroup limit).
uint64_t MemoryLimitFor(uint64_t physical_bytes, uint64_t cgroup_bytes);
// The cgroup memory limit under `cgroup_root`: v2's memory.max, else v1's
// memory/memory.limit_in_bytes; 0 when there is none ("max", no files).
uint64_t CgroupMemoryLimit(const std::string& cgroup_root = "/sys/fs/cgroup");

// "512 B", "12.0 KiB", "5.1 GiB".
std::string FormatBytes(uint64_t bytes);

}  // namespace gistream
