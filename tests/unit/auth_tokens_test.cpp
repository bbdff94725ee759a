// The --auth-tokens file: tenants and quotas parsed, errors that name the
// line and never the token, unknown tokens not found.
#include <absl/strings/match.h>
#include <gtest/gtest.h>

#include "util/auth_tokens.h"

namespace gistream {
namespace auth_tokens_test {

TEST(AuthTokens, ParsesTenantsAndQuotas) {
  absl::StatusOr<AuthTokens> tokens = AuthTokens::Parse(
      "# comment\n\n"
      "aaaaaaaaaaaaaaaa1 alice scenes=4 sessions=8 upload_bytes=1000 gpu_bytes=2000\n"
      "bbbbbbbbbbbbbbbb2\tbob\r\n"
      "cccccccccccccccc3 alice\n");
  ASSERT_TRUE(tokens.ok()) << tokens.status();
  EXPECT_EQ(tokens->size(), 3u);
  EXPECT_EQ(tokens->TenantOf("aaaaaaaaaaaaaaaa1"), "alice");
  EXPECT_EQ(tokens->TenantOf("cccccccccccccccc3"), "alice");
  EXPECT_EQ(tokens->TenantOf("bbbbbbbbbbbbbbbb2"), "bob");
  EXPECT_EQ(tokens->TenantOf("aaaaaaaaaaaaaaaa"), std::nullopt);
  EXPECT_EQ(tokens->TenantOf(""), std::nullopt);
  const TenantQuota alice = tokens->quotas().at("alice");
  EXPECT_EQ(alice.scenes, 4u);
  EXPECT_EQ(alice.sessions, 8u);
  EXPECT_EQ(alice.upload_bytes, 1000u);
  EXPECT_EQ(alice.gpu_bytes, 2000u);
  EXPECT_EQ(tokens->quotas().at("bob").scenes, 0u);  // no limit of its own
}

TEST(AuthTokens, ErrorsNameTheLineNotTheToken) {
  struct Case {
    const char* text;
    const char* message;
  };
  const Case cases[] = {
      {"shortsecret alice\n", "line 1: a token is 16"},
      {"# x\nsecretsecretsecret1\n", "line 2: expected 'TOKEN TENANT"},
      {"secretsecretsecret1 al/ice\n", "line 1: a tenant is"},
      {"secretsecretsecret1 a scenes=x\n", "line 1: expected quota=N"},
      {"secretsecretsecret1 a frames=3\n", "line 1: unknown quota 'frames'"},
      {"secretsecretsecret1 a\nsecretsecretsecret1 b\n", "line 2: the token is listed twice"},
      {"secretsecretsecret1 a scenes=1\nsecretsecretsecret2 a scenes=2\n",
       "line 2: tenant's quota was already given on line 1"},
      {"# nothing\n", "lists no token"},
  };
  for (const Case& c : cases) {
    absl::StatusOr<AuthTokens> tokens = AuthTokens::Parse(c.text);
    ASSERT_FALSE(tokens.ok()) << c.text;
    EXPECT_TRUE(absl::StrContains(tokens.status().message(), c.message)) << tokens.status();
    EXPECT_FALSE(absl::StrContains(tokens.status().message(), "secretsecret")) << tokens.status();
  }
}

}  // namespace auth_tokens_test
}  // namespace gistream
