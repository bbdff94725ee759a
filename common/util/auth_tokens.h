// The bearer-token file of `gistreamd --auth-tokens FILE`: which token
// belongs to which tenant, and that tenant's quota. One token per line:
//
//   # token                            tenant  [quota=value ...]
//   9c1f0e6b2a7d4e58b3f1c0a9d8e7f6a5   alice   scenes=4 sessions=8 upload_bytes=268435456
//   gpu_bytes=2147483648 3b8e5a7c9d1f2e4a6b8c0d2e4f6a8b0c   bob
//
// Blank lines and lines starting with '#' are ignored. A token is at least
// 16 characters of [A-Za-z0-9._~+/=-] (RFC 6750's b64token); a tenant name
// is 1 to 64 characters of [A-Za-z0-9._-]. Quotas: scenes, sessions,
// upload_bytes, gpu_bytes (see tenancy.h; 0 or absent: no limit of the
// tenant's own). Several tokens may name one tenant; its quota is then given
// on at most one of them. Errors name the line, never the token.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "util/status.h"
#include "util/tenancy.h"

namespace gistream {

class AuthTokens {
 public:
  static absl::StatusOr<AuthTokens> Parse(std::string_view text);
  static absl::StatusOr<AuthTokens> Load(const std::filesystem::path& path);

  // The tenant a token belongs to; nullopt for an unknown token. Compares
  // in time independent of where a wrong token differs.
  std::optional<TenantId> TenantOf(std::string_view token) const;
  const std::map<TenantId, TenantQuota>& quotas() const { return quotas_; }
  size_t size() const { return tokens_.size(); }

 private:
  std::map<std::string, TenantId> tokens_;
  std::map<TenantId, TenantQuota> quotas_;
};

}  // namespace gistream
