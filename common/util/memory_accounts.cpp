#include "util/memory_accounts.h"

#include <utility>

namespace gistream {

MemoryAccounts::MemoryAccounts(uint64_t limit_bytes, const std::map<TenantId, TenantQuota>& quotas)
    : server_(limit_bytes) {
  for (const auto& [tenant, quota] : quotas) {
    if (quota.gpu_bytes == 0) continue;
    tenant_gpu_[tenant] = std::make_unique<MemoryBudget>(
        quota.gpu_bytes, absl::StrCat("quota gpu_bytes of tenant '", tenant, "'"), "limit");
  }
}

absl::StatusOr<MemoryBudget::Reservation> MemoryAccounts::ReserveTenantGpu(
    const TenantId& tenant, uint64_t gpu_bytes, const std::string& what) {
  auto it = tenant_gpu_.find(tenant);
  if (it == tenant_gpu_.end() || gpu_bytes == 0) return MemoryBudget::Reservation();
  return it->second->Reserve(gpu_bytes, what);
}

absl::StatusOr<MemoryCharge> MemoryAccounts::Reserve(const TenantId& tenant, uint64_t cpu_bytes,
                                                     uint64_t gpu_bytes, const std::string& what) {
  MemoryCharge charge;
  GS_ASSIGN_OR_RETURN(charge.tenant_gpu, ReserveTenantGpu(tenant, gpu_bytes, what));
  GS_ASSIGN_OR_RETURN(charge.server, server_.Reserve(cpu_bytes + gpu_bytes, what));
  return charge;
}

MemoryReserver MemoryAccounts::ReserverFor(const TenantId& tenant) {
  return [this, tenant](uint64_t cpu_bytes, uint64_t gpu_bytes, const std::string& what) {
    return Reserve(tenant, cpu_bytes, gpu_bytes, what);
  };
}

uint64_t MemoryAccounts::tenant_gpu_used(const TenantId& tenant) const {
  auto it = tenant_gpu_.find(tenant);
  return it == tenant_gpu_.end() ? 0 : it->second->used();
}

}  // namespace gistream
