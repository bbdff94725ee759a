// gistream health: grpc.health.v1 Check, for container health checks.
#include <chrono>
#include <iostream>

#include <absl/strings/str_cat.h>

#include "commands.h"
#include "connection.h"
#include "grpc/health/v1/health.grpc.pb.h"

namespace gistream::client {

absl::Status RunHealth(const ConnectionOptions& connection, const HealthOptions& options) {
  grpc::ChannelArguments args;
  auto stub = ::grpc::health::v1::Health::NewStub(MakeChannel(connection, args));
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() +
                       std::chrono::duration_cast<std::chrono::system_clock::duration>(
                           std::chrono::duration<double>(connection.timeout_seconds)));
  ::grpc::health::v1::HealthCheckRequest request;
  request.set_service(options.service);
  ::grpc::health::v1::HealthCheckResponse response;
  GS_RETURN_IF_ERROR(FromGrpc(stub->Check(&context, request, &response), connection.server));
  const std::string& name =
      ::grpc::health::v1::HealthCheckResponse::ServingStatus_Name(response.status());
  std::cout << name << "\n";
  if (response.status() != ::grpc::health::v1::HealthCheckResponse::SERVING) {
    return absl::UnavailableError(absl::StrCat("gistreamd at ", connection.server, ": ", name));
  }
  return absl::OkStatus();
}

}  // namespace gistream::client
