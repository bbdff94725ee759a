// The channel to gistreamd and the translation of gRPC statuses into
// absl::Status, so the rest of the client speaks one error type.
#pragma once

#include <memory>
#include <string>

#include <absl/strings/string_view.h>
#include <grpcpp/grpcpp.h>

#include "gistream/v1/gistream.grpc.pb.h"
#include "options.h"
#include "util/status.h"

namespace gistream::client {

// Same code, same message; UNAVAILABLE and DEADLINE_EXCEEDED also name the
// server, since they usually mean it is not where the user thinks. The result
// is marked as coming from the server (IsRpcError), so that main prints its
// code name: "error: INVALID_ARGUMENT: params.area_samples: ...".
// A call the server's transport refused unread (its --max-transport-bytes
// full) is explained as such, naming the flag.
absl::Status FromGrpc(const grpc::Status& status, absl::string_view server);
// Whether `code` and gRPC's `message` are that transport refusal.
bool IsTransportRefusal(absl::StatusCode code, absl::string_view message);
// Whether a status from FromGrpc is that refusal.
bool IsTransportRefusal(const absl::Status& status);
bool IsRpcError(const absl::Status& status);
// `status` with `prefix` before its message, its code and marks kept.
absl::Status WithPrefix(const absl::Status& status, absl::string_view prefix);
// "CODE: message", without the payloads absl::Status::ToString appends.
std::string DescribeStatus(const absl::Status& status);

// A channel to `options.server` with its TLS credentials and bearer token
// (on every call); gistream-web's upstream channel too.
std::shared_ptr<grpc::Channel> MakeChannel(const ConnectionOptions& options,
                                           const grpc::ChannelArguments& args);
// The contents of the PEM file `path`, or a usage error naming `flag`.
absl::StatusOr<std::string> ReadPem(absl::string_view flag, const std::string& path);

class Connection {
 public:
  // Does not connect yet: the first call does, and fails fast with
  // UNAVAILABLE when nothing listens at the address.
  explicit Connection(const ConnectionOptions& options);

  const std::string& server() const { return options_.server; }
  v1::Gistream::Stub& stub() { return *stub_; }

  // One unary call with the configured deadline:
  //   conn.Call(&v1::Gistream::Stub::ListSolvers, request, &response)
  template <typename Request, typename Response>
  absl::Status Call(grpc::Status (v1::Gistream::Stub::*method)(grpc::ClientContext*, const Request&,
                                                               Response*),
                    const Request& request, Response* response, double timeout_seconds = 0.0) {
    grpc::ClientContext context;
    SetDeadline(context, timeout_seconds > 0.0 ? timeout_seconds : options_.timeout_seconds);
    return FromGrpc(((*stub_).*method)(&context, request, response), options_.server);
  }

 private:
  static void SetDeadline(grpc::ClientContext& context, double seconds);

  ConnectionOptions options_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::Gistream::Stub> stub_;
};

}  // namespace gistream::client
