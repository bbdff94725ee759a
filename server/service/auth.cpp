#include "service/auth.h"

#include <absl/strings/match.h>
#include <absl/strings/str_cat.h>

#include <grpc/grpc.h>
#include <grpc/grpc_security.h>
#include <grpc/grpc_security_constants.h>
#include <grpc/slice.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>

#include "util/log.h"

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

// Failed authentications are logged, at most one line a second with the
// count since the last (a guesser must not flood the log; the token is
// never written). gRPC 1.51's auth filter does not tell the caller's
// address, so throttling per source is the balancer's (deploy/haproxy).
void LogFailedAuthentication(std::string_view path, const absl::Status& why) {
  static std::atomic<uint64_t> failures{0};
  static std::mutex mutex;
  static std::chrono::steady_clock::time_point last{};
  failures.fetch_add(1, std::memory_order_relaxed);
  const auto now = std::chrono::steady_clock::now();
  std::unique_lock lock(mutex, std::try_to_lock);
  if (!lock.owns_lock() || now - last < std::chrono::seconds(1)) return;
  last = now;
  const uint64_t count = failures.exchange(0, std::memory_order_relaxed);
  Log(LogLevel::kWarning,
      absl::StrCat("authentication failed: ", count, " call(s) since the last report (the last: ",
                   absl::string_view(path.data(), path.size()), ", ", why.message(), ")"));
}

// The check of both processors: open methods pass, every other call needs a
// listed bearer token.
absl::Status CheckCall(std::string_view path, const std::optional<std::string_view>& header,
                       const AuthTokens& tokens) {
  if (IsOpenMethod(path)) return absl::OkStatus();
  // The header stays in the call's metadata: CallerTenant reads the tenant
  // from it (an AuthContext property would be shared by the calls of one
  // connection, which may carry different tokens).
  absl::Status status = TenantOfHeader(header ? &*header : nullptr, tokens).status();
  if (!status.ok()) LogFailedAuthentication(path, status);
  return status;
}

std::string_view View(const grpc_slice& s) {
  return {reinterpret_cast<const char*>(GRPC_SLICE_START_PTR(s)), GRPC_SLICE_LENGTH(s)};
}

// TokenAuthProcessor's check as gRPC core's C processor, for the insecure
// credentials below (grpc_security.h: non-blocking, answered synchronously).
void ProcessInCore(void* state, grpc_auth_context* /*context*/, const grpc_metadata* md,
                   size_t num_md, grpc_process_auth_metadata_done_cb done, void* user_data) {
  const AuthTokens& tokens = **static_cast<std::shared_ptr<const AuthTokens>*>(state);
  std::optional<std::string_view> header;
  std::string_view path;
  for (size_t i = 0; i < num_md; ++i) {
    if (View(md[i].key) == "authorization") header = View(md[i].value);
    if (View(md[i].key) == ":path") path = View(md[i].value);
  }
  const absl::Status status = CheckCall(path, header, tokens);
  const std::string message(status.message());
  done(user_data, nullptr, 0, nullptr, 0, static_cast<grpc_status_code>(status.code()),
       status.ok() ? nullptr : message.c_str());
}

// Plaintext credentials (--insecure) that run the token check in gRPC's
// server auth filter, before any request message is read, as TLS and local
// credentials do. libgrpc++ 1.51's InsecureServerCredentials() refuses an
// AuthMetadataProcessor (it asserts), but core's insecure server
// credentials carry one: they install a security connector (no handshake),
// so the server auth filter is on the channel stack and calls the
// processor with each call's initial metadata.
class InsecureTokenCredentials final : public grpc::ServerCredentials {
 public:
  explicit InsecureTokenCredentials(std::shared_ptr<const AuthTokens> tokens)
      : tokens_(std::move(tokens)) {}

  // The token processor is built in (ProcessInCore); a C++ processor has no
  // place here, as on libgrpc++'s own insecure credentials.
  void SetAuthMetadataProcessor(
      const std::shared_ptr<grpc::AuthMetadataProcessor>& /*processor*/) override {
    GS_CHECK(false && "InsecureTokenCredentials has its token processor built in");
  }

 private:
  int AddPortToServer(const std::string& addr, grpc_server* server) override {
    grpc_server_credentials* credentials = grpc_insecure_server_credentials_create();
    grpc_auth_metadata_processor processor;
    processor.process = ProcessInCore;
    processor.destroy = [](void* state) {
      delete static_cast<std::shared_ptr<const AuthTokens>*>(state);
    };
    processor.state = new std::shared_ptr<const AuthTokens>(tokens_);
    grpc_server_credentials_set_auth_metadata_processor(credentials, processor);
    const int port = grpc_server_add_http2_port(server, addr.c_str(), credentials);
    grpc_server_credentials_release(credentials);
    return port;
  }

  std::shared_ptr<const AuthTokens> tokens_;
};

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
  return ToGrpc(CheckCall(path, header, *tokens_));
}

absl::StatusOr<TenantId> CallerTenant(const grpc::ServerContextBase& context,
                                      const AuthTokens* tokens) {
  if (tokens == nullptr) return TenantId(kDefaultTenant);
  // The auth filter has checked the header already (TokenAuthProcessor, or
  // ProcessInCore on an --insecure listener); this maps it to its tenant.
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
    if (tokens) return std::make_shared<InsecureTokenCredentials>(std::move(tokens));
    return grpc::InsecureServerCredentials();
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
