#include "service/grpc/auth.h"

#include <absl/strings/match.h>
#include <absl/strings/str_cat.h>

#include <grpc/grpc_security_constants.h>

namespace gistream::service {
namespace {

constexpr std::string_view kBearer = "Bearer ";

std::string_view View(const grpc::string_ref& s) { return {s.data(), s.size()}; }

// The token of an "authorization: Bearer TOKEN" header, or why there is none.
absl::StatusOr<std::string_view> BearerToken(const std::string_view* header) {
  if (header == nullptr) {
    return absl::UnauthenticatedError(
        "authorization: missing; send 'authorization: Bearer TOKEN' (gistream --token)");
  }
  if (header->size() <= kBearer.size() ||
      !absl::EqualsIgnoreCase(absl::string_view(header->data(), kBearer.size()),
                              absl::string_view(kBearer.data(), kBearer.size()))) {
    return absl::UnauthenticatedError("authorization: expected 'Bearer TOKEN'");
  }
  return header->substr(kBearer.size());
}

absl::StatusOr<TenantId> TenantOfHeader(const std::string_view* header, const AuthTokens& tokens) {
  GS_ASSIGN_OR_RETURN(std::string_view token, BearerToken(header));
  std::optional<TenantId> tenant = tokens.TenantOf(token);
  if (!tenant) return absl::UnauthenticatedError("authorization: unknown token");
  return *tenant;
}

grpc::Status ToGrpc(const absl::Status& status) {
  return grpc::Status(static_cast<grpc::StatusCode>(status.code()), std::string(status.message()));
}

}  // namespace

bool IsOpenMethod(std::string_view path) {
  return path.starts_with("/grpc.health.v1.Health/") ||
         path.starts_with("/grpc.reflection.v1.ServerReflection/") ||
         path.starts_with("/grpc.reflection.v1alpha.ServerReflection/");
}

grpc::Status TokenAuthProcessor::Process(const InputMetadata& auth_metadata,
                                         grpc::AuthContext* /*context*/,
                                         OutputMetadata* /*consumed_auth_metadata*/,
                                         OutputMetadata* /*response_metadata*/) {
  std::optional<std::string_view> header;
  std::string_view path;
  for (const auto& [key, value] : auth_metadata) {
    if (View(key) == "authorization") header = View(value);
    if (View(key) == ":path") path = View(value);
  }
  if (IsOpenMethod(path)) return grpc::Status::OK;
  // The header stays in the call's metadata: CallerTenant reads the tenant
  // from it (an AuthContext property would be shared by the calls of one
  // connection, which may carry different tokens).
  return ToGrpc(TenantOfHeader(header ? &*header : nullptr, *tokens_).status());
}

absl::StatusOr<TenantId> CallerTenant(const grpc::ServerContextBase& context,
                                      const AuthTokens* tokens) {
  if (tokens == nullptr) return TenantId(kDefaultTenant);
  // TokenAuthProcessor has checked the header already where an auth filter
  // runs; on an --insecure listener this is the check.
  const auto& metadata = context.client_metadata();
  const auto it = metadata.find("authorization");
  std::string_view header;
  if (it != metadata.end()) header = View(it->second);
  return TenantOfHeader(it != metadata.end() ? &header : nullptr, *tokens);
}

bool IsLoopbackAddress(std::string_view listen) {
  const size_t colon = listen.rfind(':');
  std::string_view host = colon == std::string_view::npos ? listen : listen.substr(0, colon);
  if (host.starts_with("[") && host.ends_with("]")) host = host.substr(1, host.size() - 2);
  return host == "localhost" || host == "::1" || host.starts_with("127.");
}

absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> MakeServerCredentials(
    const std::string& listen, const TlsFiles& tls, bool allow_insecure,
    std::shared_ptr<const AuthTokens> tokens) {
  std::shared_ptr<grpc::ServerCredentials> credentials;
  if (!tls.cert_chain_pem.empty()) {
    grpc::SslServerCredentialsOptions ssl(
        tls.client_ca_pem.empty() ? GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE
                                  : GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY);
    ssl.pem_root_certs = tls.client_ca_pem;
    ssl.pem_key_cert_pairs.push_back({tls.private_key_pem, tls.cert_chain_pem});
    credentials = grpc::SslServerCredentials(ssl);
  } else if (IsLoopbackAddress(listen) && !allow_insecure) {
    // Plaintext that only this machine can reach; unlike
    // InsecureServerCredentials it runs the auth filter (tokens).
    credentials = grpc::experimental::LocalServerCredentials(LOCAL_TCP);
  } else if (allow_insecure) {
    return grpc::InsecureServerCredentials();  // CallerTenant checks tokens
  } else {
    return absl::FailedPreconditionError(absl::StrCat(
        "refusing to serve plaintext on ", listen,
        ", which is not a loopback address: give --tls-cert and --tls-key (and --tls-client-ca "
        "for mutual TLS), or --insecure if something in front of gistreamd encrypts the traffic"));
  }
  if (tokens) credentials->SetAuthMetadataProcessor(std::make_shared<TokenAuthProcessor>(tokens));
  return credentials;
}

}  // namespace gistream::service
