// Tenants: who owns a scene or a session, and what each may hold at once.
// Without --auth-tokens every caller is kDefaultTenant with no quota beyond
// the server's own limits (--max-scenes, --max-sessions).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace gistream {

using TenantId = std::string;

inline constexpr std::string_view kDefaultTenant = "default";

// What one tenant may hold at once; 0 means no limit of the tenant's own.
struct TenantQuota {
  /// Scenes loaded (a named scene shared by the tenant's sessions counts once).
  uint32_t scenes = 0;
  /// Open sessions (Render calls are not counted).
  uint32_t sessions = 0;
  /// Bytes of uploaded glTF and environment images held.
  uint64_t upload_bytes = 0;
  /// GPU bytes of the tenant's scenes (GpuScene::gpu_bytes at upload).
  uint64_t gpu_bytes = 0;
};

}  // namespace gistream
