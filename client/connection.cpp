#include "connection.h"

#include <chrono>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

#include <grpcpp/support/client_interceptor.h>

#include <absl/strings/cord.h>
#include <absl/strings/match.h>
#include <absl/strings/str_cat.h>

namespace gistream::client {
namespace {
constexpr absl::string_view kRpcPayload = "gistream.client/rpc";
constexpr absl::string_view kTransportRefusalPayload = "gistream.client/transport-refusal";

using Headers = std::vector<std::pair<std::string, std::string>>;

// Adds headers to every call of the channel: "authorization: Bearer TOKEN"
// (over TLS and loopback plaintext alike: gRPC's call credentials refuse
// plaintext) and "x-gistream-affinity: KEY" (what a balancer hashes).
class HeaderInterceptor final : public grpc::experimental::Interceptor {
 public:
  explicit HeaderInterceptor(const Headers& headers) : headers_(headers) {}
  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(
            grpc::experimental::InterceptionHookPoints::PRE_SEND_INITIAL_METADATA)) {
      for (const auto& [name, value] : headers_) {
        methods->GetSendInitialMetadata()->emplace(name, value);
      }
    }
    methods->Proceed();
  }

 private:
  const Headers headers_;  // a copy: a few short strings per call
};

class HeaderInterceptorFactory final
    : public grpc::experimental::ClientInterceptorFactoryInterface {
 public:
  explicit HeaderInterceptorFactory(Headers headers) : headers_(std::move(headers)) {}
  grpc::experimental::Interceptor* CreateClientInterceptor(
      grpc::experimental::ClientRpcInfo* /*info*/) override {
    return new HeaderInterceptor(headers_);
  }

 private:
  const Headers headers_;
};

std::shared_ptr<grpc::ChannelCredentials> Credentials(const ConnectionOptions& options) {
  if (!options.tls) return grpc::InsecureChannelCredentials();
  grpc::SslCredentialsOptions ssl;
  ssl.pem_root_certs = options.ca_pem;  // empty: the system's roots
  ssl.pem_cert_chain = options.cert_pem;
  ssl.pem_private_key = options.key_pem;
  return grpc::SslCredentials(ssl);
}
}  // namespace

bool IsTransportRefusal(absl::StatusCode code, absl::string_view message) {
  // HTTP/2 error code 11 is ENHANCE_YOUR_CALM: what gRPC's resource quota
  // answers (RST_STREAM) when a call would pass the server's
  // --max-transport-bytes.
  return code == absl::StatusCode::kResourceExhausted &&
         absl::StrContains(message, "RST_STREAM with error code 11");
}

absl::Status FromGrpc(const grpc::Status& status, absl::string_view server) {
  if (status.ok()) return absl::OkStatus();
  const auto code = static_cast<absl::StatusCode>(status.error_code());
  std::string message = status.error_message();
  if (code == absl::StatusCode::kUnavailable || code == absl::StatusCode::kDeadlineExceeded) {
    message = absl::StrCat("gistreamd at ", server, ": ", message);
  }
  if (IsTransportRefusal(code, message)) {
    // gRPC's own words name neither the cause nor the flag.
    message = absl::StrCat("gistreamd at ", server,
                           " refused the call before reading it (HTTP/2 ENHANCE_YOUR_CALM): the "
                           "requests it is receiving fill its transport memory "
                           "(--max-transport-bytes); retry in a few seconds or use another server "
                           "[",
                           message, "]");
  }
  absl::Status result(code, message);
  result.SetPayload(kRpcPayload, absl::Cord("1"));
  if (IsTransportRefusal(code, status.error_message())) {
    result.SetPayload(kTransportRefusalPayload, absl::Cord("1"));
  }
  return result;
}

absl::Status WithPrefix(const absl::Status& status, absl::string_view prefix) {
  absl::Status result(status.code(), absl::StrCat(prefix, status.message()));
  status.ForEachPayload(
      [&](absl::string_view key, const absl::Cord& value) { result.SetPayload(key, value); });
  return result;
}

bool IsTransportRefusal(const absl::Status& status) {
  return status.GetPayload(kTransportRefusalPayload).has_value();
}

bool IsRpcError(const absl::Status& status) { return status.GetPayload(kRpcPayload).has_value(); }

std::string DescribeStatus(const absl::Status& status) {
  return absl::StrCat(absl::StatusCodeToString(status.code()), ": ", status.message());
}

std::shared_ptr<grpc::Channel> MakeChannel(const ConnectionOptions& options,
                                           const grpc::ChannelArguments& args) {
  Headers headers;
  if (!options.token.empty()) headers.emplace_back("authorization", "Bearer " + options.token);
  if (!options.affinity.empty()) headers.emplace_back("x-gistream-affinity", options.affinity);
  if (headers.empty()) return grpc::CreateCustomChannel(options.server, Credentials(options), args);
  std::vector<std::unique_ptr<grpc::experimental::ClientInterceptorFactoryInterface>> factories;
  factories.push_back(std::make_unique<HeaderInterceptorFactory>(std::move(headers)));
  return grpc::experimental::CreateCustomChannelWithInterceptors(
      options.server, Credentials(options), args, std::move(factories));
}

absl::StatusOr<std::string> ReadPem(absl::string_view flag, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  if (in) text << in.rdbuf();
  if (!in || text.str().empty()) {
    return absl::InvalidArgumentError(absl::StrCat(flag, ": cannot read '", path, "'"));
  }
  return text.str();
}

Connection::Connection(const ConnectionOptions& options) : options_(options) {
  grpc::ChannelArguments args;
  // Frames (EXR at high resolution) and uploaded scenes exceed gRPC's 4 MiB
  // default; the server enforces its own limits.
  args.SetMaxReceiveMessageSize(-1);
  args.SetMaxSendMessageSize(-1);
  if (options_.own_connection) args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
  channel_ = MakeChannel(options_, args);
  stub_ = v1::Gistream::NewStub(channel_);
}

void Connection::SetDeadline(grpc::ClientContext& context, double seconds) {
  context.set_deadline(std::chrono::system_clock::now() +
                       std::chrono::duration_cast<std::chrono::system_clock::duration>(
                           std::chrono::duration<double>(seconds)));
}

}  // namespace gistream::client
