// Who is calling: bearer tokens (util/auth_tokens.h) checked against the
// token file, and the server's transport credentials (TLS, mutual TLS,
// plaintext only on loopback or when asked for).
//
// On every listener (TLS, loopback plaintext through gRPC's local
// credentials, and --insecure plaintext through core's insecure credentials
// with a C processor, auth.cpp) the token check runs in gRPC's server auth
// filter on the call's metadata: a missing or unknown token fails the call
// with UNAUTHENTICATED before any request message is read. Health and
// reflection stay open (probes carry no token). CallerTenant() maps the
// call's token to its tenant, first thing in every handler. Tokens never
// reach a log line; tenants do.
#pragma once

#include <memory>
#include <string>

#include <grpcpp/grpcpp.h>
#include <grpcpp/security/auth_metadata_processor.h>

#include "util/auth_tokens.h"
#include "util/status.h"

namespace gistream::service {

struct TlsFiles {
  std::string cert_chain_pem;  // the server's certificate chain
  std::string private_key_pem;
  // Non-empty: mutual TLS, clients must present a certificate this CA signed.
  std::string client_ca_pem;
};

class TokenAuthProcessor final : public grpc::AuthMetadataProcessor {
 public:
  explicit TokenAuthProcessor(std::shared_ptr<const AuthTokens> tokens)
      : tokens_(std::move(tokens)) {}
  bool IsBlocking() const override { return false; }  // a map lookup
  grpc::Status Process(const InputMetadata& auth_metadata, grpc::AuthContext* context,
                       OutputMetadata* consumed_auth_metadata,
                       OutputMetadata* response_metadata) override;

 private:
  std::shared_ptr<const AuthTokens> tokens_;
};

// True for methods any caller may use without a token: grpc.health.v1 and
// server reflection ("/grpc.health.v1.Health/Check").
bool IsOpenMethod(std::string_view path);

// The caller's tenant: kDefaultTenant without `tokens`; else the tenant of
// the call's "authorization: Bearer TOKEN" header.
// UNAUTHENTICATED names what is wrong (missing, not Bearer, unknown token).
absl::StatusOr<TenantId> CallerTenant(const grpc::ServerContextBase& context,
                                      const AuthTokens* tokens);

// Transport credentials for `listen`: TLS when `tls` has a certificate,
// else gRPC's local credentials on a loopback address, else plaintext when
// `allow_insecure`; FAILED_PRECONDITION otherwise, saying what to pass.
// Checks `tokens` in the auth filter when set (TokenAuthProcessor; on
// plaintext with `allow_insecure`, the same check in core's processor).
absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> MakeServerCredentials(
    const std::string& listen, const TlsFiles& tls, bool allow_insecure,
    std::shared_ptr<const AuthTokens> tokens);

// "127.0.0.1:50051", "localhost:0", "[::1]:50051": only this machine can connect.
bool IsLoopbackAddress(std::string_view listen);

}  // namespace gistream::service
