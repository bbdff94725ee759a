#include "util/auth_tokens.h"

#include <absl/strings/numbers.h>
#include <absl/strings/str_cat.h>
#include <absl/strings/str_split.h>

#include <fstream>
#include <sstream>
#include <vector>

namespace gistream {
namespace {

constexpr size_t kMinTokenChars = 16;
constexpr size_t kMaxTokenChars = 4096;
constexpr size_t kMaxTenantChars = 64;

bool IsTokenChar(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' ||
         c == '_' || c == '~' || c == '+' || c == '/' || c == '=' || c == '-';
}

bool IsTenantChar(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' ||
         c == '_' || c == '-';
}

template <typename Pred>
bool All(std::string_view s, Pred pred) {
  for (char c : s) {
    if (!pred(c)) return false;
  }
  return true;
}

// Equal length and bytes, in time that depends only on the lengths.
bool SameBytes(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

absl::Status ParseQuota(std::string_view item, size_t line, TenantQuota& quota) {
  const size_t eq = item.find('=');
  const std::string_view key = item.substr(0, eq);
  uint64_t value = 0;
  if (eq == std::string_view::npos ||
      !absl::SimpleAtoi(absl::string_view(item.data() + eq + 1, item.size() - eq - 1), &value)) {
    return absl::InvalidArgumentError(
        absl::StrCat("auth tokens line ", line,
                     ": expected quota=N (scenes, sessions, upload_bytes, gpu_bytes)"));
  }
  if (key == "scenes" || key == "sessions") {
    if (value > UINT32_MAX) {
      return absl::InvalidArgumentError(absl::StrCat("auth tokens line ", line, ": ",
                                                     absl::string_view(key.data(), key.size()),
                                                     " = ", value, " is out of range"));
    }
    (key == "scenes" ? quota.scenes : quota.sessions) = static_cast<uint32_t>(value);
  } else if (key == "upload_bytes") {
    quota.upload_bytes = value;
  } else if (key == "gpu_bytes") {
    quota.gpu_bytes = value;
  } else {
    const absl::string_view shown(key.data(), std::min<size_t>(key.size(), 32));
    return absl::InvalidArgumentError(
        absl::StrCat("auth tokens line ", line, ": unknown quota '", shown,
                     "' (scenes, sessions, upload_bytes, gpu_bytes)"));
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<AuthTokens> AuthTokens::Parse(std::string_view text) {
  AuthTokens out;
  std::map<TenantId, size_t> quota_line;  // where a tenant's quota was given
  size_t line_number = 0;
  for (absl::string_view raw : absl::StrSplit(absl::string_view(text.data(), text.size()), '\n')) {
    ++line_number;
    std::vector<absl::string_view> fields =
        absl::StrSplit(raw, absl::ByAnyChar(" \t\r"), absl::SkipEmpty());
    if (fields.empty() || fields[0].front() == '#') continue;
    if (fields.size() < 2) {
      return absl::InvalidArgumentError(absl::StrCat("auth tokens line ", line_number,
                                                     ": expected 'TOKEN TENANT [quota=N ...]'"));
    }
    const std::string_view token(fields[0].data(), fields[0].size());
    const std::string_view tenant(fields[1].data(), fields[1].size());
    if (token.size() < kMinTokenChars || token.size() > kMaxTokenChars ||
        !All(token, IsTokenChar)) {
      return absl::InvalidArgumentError(
          absl::StrCat("auth tokens line ", line_number, ": a token is ", kMinTokenChars, " to ",
                       kMaxTokenChars, " characters of A-Z a-z 0-9 . _ ~ + / = -"));
    }
    if (tenant.empty() || tenant.size() > kMaxTenantChars || !All(tenant, IsTenantChar)) {
      return absl::InvalidArgumentError(absl::StrCat("auth tokens line ", line_number,
                                                     ": a tenant is 1 to ", kMaxTenantChars,
                                                     " characters of A-Z a-z 0-9 . _ -"));
    }
    if (out.tokens_.count(std::string(token)) > 0) {
      return absl::InvalidArgumentError(
          absl::StrCat("auth tokens line ", line_number, ": the token is listed twice"));
    }
    out.tokens_[std::string(token)] = TenantId(tenant);
    TenantQuota& quota = out.quotas_[TenantId(tenant)];
    if (fields.size() > 2) {
      auto [it, first] = quota_line.emplace(TenantId(tenant), line_number);
      if (!first) {
        return absl::InvalidArgumentError(
            absl::StrCat("auth tokens line ", line_number,
                         ": tenant's quota was already given on line ", it->second));
      }
      for (size_t i = 2; i < fields.size(); ++i) {
        GS_RETURN_IF_ERROR(
            ParseQuota(std::string_view(fields[i].data(), fields[i].size()), line_number, quota));
      }
    }
  }
  if (out.tokens_.empty()) {
    return absl::InvalidArgumentError("auth tokens: the file lists no token");
  }
  return out;
}

absl::StatusOr<AuthTokens> AuthTokens::Load(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return absl::NotFoundError(absl::StrCat("--auth-tokens: cannot read ", path.string()));
  }
  std::ostringstream text;
  text << in.rdbuf();
  absl::StatusOr<AuthTokens> tokens = Parse(text.str());
  if (!tokens.ok()) {
    return absl::Status(tokens.status().code(),
                        absl::StrCat(path.string(), ": ", tokens.status().message()));
  }
  return tokens;
}

std::optional<TenantId> AuthTokens::TenantOf(std::string_view token) const {
  // Every entry is compared, so the time says nothing about which matched.
  std::optional<TenantId> found;
  for (const auto& [known, tenant] : tokens_) {
    if (SameBytes(known, token)) found = tenant;
  }
  return found;
}

}  // namespace gistream
