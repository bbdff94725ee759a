#include "connection.h"

#include <chrono>

#include <absl/strings/cord.h>
#include <absl/strings/str_cat.h>

namespace gistream::client {
namespace {
constexpr absl::string_view kRpcPayload = "gistream.client/rpc";
}  // namespace

absl::Status FromGrpc(const grpc::Status& status, absl::string_view server) {
  if (status.ok()) return absl::OkStatus();
  const auto code = static_cast<absl::StatusCode>(status.error_code());
  std::string message = status.error_message();
  if (code == absl::StatusCode::kUnavailable || code == absl::StatusCode::kDeadlineExceeded) {
    message = absl::StrCat("gistreamd at ", server, ": ", message);
  }
  absl::Status result(code, message);
  result.SetPayload(kRpcPayload, absl::Cord("1"));
  return result;
}

bool IsRpcError(const absl::Status& status) { return status.GetPayload(kRpcPayload).has_value(); }

std::string DescribeStatus(const absl::Status& status) {
  return absl::StrCat(absl::StatusCodeToString(status.code()), ": ", status.message());
}

Connection::Connection(const ConnectionOptions& options) : options_(options) {
  grpc::ChannelArguments args;
  // Frames (EXR at high resolution) and uploaded scenes exceed gRPC's 4 MiB
  // default; the server enforces its own limits.
  args.SetMaxReceiveMessageSize(-1);
  args.SetMaxSendMessageSize(-1);
  if (options_.own_connection) args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
  channel_ = grpc::CreateCustomChannel(options_.server, grpc::InsecureChannelCredentials(), args);
  stub_ = v1::Gistream::NewStub(channel_);
}

void Connection::SetDeadline(grpc::ClientContext& context, double seconds) {
  context.set_deadline(std::chrono::system_clock::now() +
                       std::chrono::duration_cast<std::chrono::system_clock::duration>(
                           std::chrono::duration<double>(seconds)));
}

}  // namespace gistream::client
