// Where a reservation is counted: the server-wide memory budget
// (util/memory_budget.h, --max-memory-bytes) and, for the GPU bytes, the
// gpu_bytes quota of the tenant that owns the scene (util/tenancy.h,
// --auth-tokens). Scene uploads, solver estimates, per-view G-buffers and
// encoders, and the lazily allocated per-view state of solvers (a path
// tracer's accumulation, view-sized render targets) all reserve here before
// they allocate, and give the bytes back when freed (MemoryCharge is RAII).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "util/memory_budget.h"
#include "util/status.h"
#include "util/tenancy.h"

namespace gistream {

// One allocation's bytes in the server's budget (CPU + GPU) and its GPU
// bytes in its tenant's gpu_bytes quota. Move-only; empty holds nothing.
struct MemoryCharge {
  MemoryBudget::Reservation server;
  MemoryBudget::Reservation tenant_gpu;  // empty for a tenant without the quota
  uint64_t bytes() const { return server.bytes(); }
  void Release() {
    server.Release();
    tenant_gpu.Release();
  }
  void Merge(MemoryCharge&& other) {
    server.Merge(std::move(other.server));
    tenant_gpu.Merge(std::move(other.tenant_gpu));
  }
};

// How domain code (solvers) reserves without knowing the accounts: the
// engine binds the owning tenant. Empty: nothing is counted (unit tests).
using MemoryReserver = std::function<absl::StatusOr<MemoryCharge>(
    uint64_t cpu_bytes, uint64_t gpu_bytes, const std::string& what)>;

class MemoryAccounts {
 public:
  // `limit_bytes` as MemoryBudget's; a tenant of `quotas` with gpu_bytes > 0
  // gets its own count.
  MemoryAccounts(uint64_t limit_bytes, const std::map<TenantId, TenantQuota>& quotas);

  // RESOURCE_EXHAUSTED naming `what` and the quota ("... more than the 1.0
  // MiB left of quota gpu_bytes of tenant 'alice' (limit 4.0 MiB, ...)") or
  // the server's budget; the tenant's quota is checked first.
  absl::StatusOr<MemoryCharge> Reserve(const TenantId& tenant, uint64_t cpu_bytes,
                                       uint64_t gpu_bytes, const std::string& what);
  // GPU bytes of `tenant` alone (an upload measured after the fact); an
  // empty reservation for a tenant without the quota.
  absl::StatusOr<MemoryBudget::Reservation> ReserveTenantGpu(const TenantId& tenant,
                                                             uint64_t gpu_bytes,
                                                             const std::string& what);
  // Binds `tenant`.
  MemoryReserver ReserverFor(const TenantId& tenant);

  const MemoryBudget& server() const { return server_; }
  MemoryBudget& server() { return server_; }
  // GPU bytes `tenant` holds (0 without a gpu_bytes quota).
  uint64_t tenant_gpu_used(const TenantId& tenant) const;

 private:
  MemoryBudget server_;
  std::map<TenantId, std::unique_ptr<MemoryBudget>> tenant_gpu_;  // fixed after construction
};

}  // namespace gistream
