#include "service/server.h"

#include <grpcpp/resource_quota.h>

#include <grpc/grpc.h>
#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>

#include <vector>

#include "util/log.h"

namespace gistream::service {

namespace {
constexpr const char* kServiceName = "gistream.v1.Gistream";

int Millis(std::chrono::milliseconds ms) { return static_cast<int>(ms.count()); }

// "host:0" -> "host:PORT"; IPv6 "[::]:0" keeps its brackets.
std::string WithPort(const std::string& listen, int port) {
  const size_t colon = listen.rfind(':');
  if (colon == std::string::npos) return absl::StrCat(listen, ":", port);
  return absl::StrCat(listen.substr(0, colon), ":", port);
}
}  // namespace

GistreamServer::GistreamServer(Engine& engine, const ServerOptions& options)
    : engine_(engine), service_(std::make_unique<GistreamService>(engine, options.service)) {}

void GistreamServer::ConfigureTransport(grpc::ServerBuilder& builder,
                                        const ServerOptions& options) {
  // gRPC sets SO_REUSEPORT by default: a second gistreamd on the same port
  // would silently share its traffic instead of failing to start.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  builder.SetMaxReceiveMessageSize(options.max_receive_message_bytes);
  if (options.transport_memory_bytes > 0) {
    // Uploads arrive whole before a handler sees them: this bounds what
    // concurrent ones hold while they are read (issue 30, item 4).
    grpc::ResourceQuota quota("gistreamd transport");
    quota.Resize(size_t(options.transport_memory_bytes));
    builder.SetResourceQuota(quota);
  }
  builder.SetMaxSendMessageSize(options.max_send_message_bytes);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIME_MS, Millis(options.keepalive_time));
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, Millis(options.keepalive_timeout));
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_PERMIT_WITHOUT_CALLS, 1);
  builder.AddChannelArgument(GRPC_ARG_HTTP2_MAX_PINGS_WITHOUT_DATA, 0);
  builder.AddChannelArgument(GRPC_ARG_HTTP2_MIN_RECV_PING_INTERVAL_WITHOUT_DATA_MS,
                             Millis(options.min_client_ping_interval));
  builder.AddChannelArgument(GRPC_ARG_HTTP2_MIN_SENT_PING_INTERVAL_WITHOUT_DATA_MS,
                             Millis(options.keepalive_time));
}

absl::Status GistreamServer::StartHealth(const std::string& listen) {
  if (listen.empty()) return absl::OkStatus();
  // Only the default health service: nothing else is registered here.
  grpc::ServerBuilder health_builder;
  health_builder.AddListeningPort(listen, grpc::InsecureServerCredentials(), &health_port_);
  health_builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  health_server_ = health_builder.BuildAndStart();
  if (health_server_ == nullptr || health_port_ == 0) {
    health_server_.reset();
    server_->Shutdown();
    return absl::UnavailableError(absl::StrCat("cannot listen on ", listen, " (--health-listen)"));
  }
  return absl::OkStatus();
}

void GistreamServer::ReportServing(Engine& engine) {
  for (grpc::Server* server : {server_.get(), health_server_.get()}) {
    grpc::HealthCheckServiceInterface* health =
        server != nullptr ? server->GetHealthCheckService() : nullptr;
    if (health != nullptr) {
      health->SetServingStatus("", true);
      health->SetServingStatus(kServiceName, true);
    }
  }
  // A GPU reset turns health NOT_SERVING until the engine has recovered.
  engine.SetServingListener(
      [servers = std::vector<grpc::Server*>{server_.get(), health_server_.get()}](bool serving) {
        for (grpc::Server* server : servers) {
          grpc::HealthCheckServiceInterface* h =
              server != nullptr ? server->GetHealthCheckService() : nullptr;
          if (h != nullptr) h->SetServingStatus(serving);
        }
      });
}

absl::StatusOr<std::unique_ptr<GistreamServer>> GistreamServer::Start(
    Engine& engine, const ServerOptions& options) {
  // Both are process-wide switches that apply to servers built afterwards.
  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();

  GS_ASSIGN_OR_RETURN(std::shared_ptr<grpc::ServerCredentials> credentials,
                      MakeServerCredentials(options.listen, options.tls, options.allow_insecure,
                                            options.service.tokens));
  std::unique_ptr<GistreamServer> self(new GistreamServer(engine, options));
  grpc::ServerBuilder builder;
  builder.AddListeningPort(options.listen, credentials, &self->port_);
  builder.RegisterService(self->service_.get());
  // Generic tools ask for grpc.reflection.v1 first; libgrpc++ 1.51 serves
  // only v1alpha (the plugin above), so v1 is ours.
  self->reflection_v1_ = std::make_unique<ReflectionV1>(std::vector<std::string>{
      kServiceName, "grpc.health.v1.Health", "grpc.reflection.v1.ServerReflection",
      "grpc.reflection.v1alpha.ServerReflection"});
  builder.RegisterService(self->reflection_v1_.get());
  ConfigureTransport(builder, options);
  self->server_ = builder.BuildAndStart();
  if (self->server_ == nullptr || self->port_ == 0) {
    self->server_.reset();
    return absl::UnavailableError(absl::StrCat("cannot listen on ", options.listen,
                                               " (address in use, not local, or malformed)"));
  }
  self->address_ = WithPort(options.listen, self->port_);

  GS_RETURN_IF_ERROR(self->StartHealth(options.health_listen));
  self->ReportServing(engine);
  return self;
}

GistreamServer::~GistreamServer() { Shutdown(std::chrono::milliseconds(0)); }

void GistreamServer::SetNotServing() {
  for (grpc::Server* server : {server_.get(), health_server_.get()}) {
    if (server == nullptr) continue;
    if (grpc::HealthCheckServiceInterface* health = server->GetHealthCheckService()) {
      health->SetServingStatus(false);  // every service, "" included
    }
  }
}

void GistreamServer::Shutdown(std::chrono::milliseconds deadline) {
  std::lock_guard lock(shutdown_mutex_);
  {
    std::lock_guard done_lock(done_mutex_);
    if (done_) return;
  }
  if (server_ != nullptr) {
    engine_.SetServingListener({});  // a recovery must not turn it back on
    SetNotServing();
    // Every session is told to move (a Draining event): its client loads
    // the scene on another server and replays its updates, then ends this
    // call, and Shutdown returns as soon as the last call has ended.
    engine_.BeginDrain(deadline);
    Log(LogLevel::kInfo,
        absl::StrCat("shutting down: calls have ", deadline.count(), " ms to finish"));
    server_->Shutdown(std::chrono::system_clock::now() + deadline);
    server_->Wait();
  }
  if (health_server_ != nullptr) health_server_->Shutdown(std::chrono::system_clock::now());
  service_->StopWorkers();  // drains: jobs that finish calls or close sessions
  engine_.Shutdown();
  Log(LogLevel::kInfo, "shut down");
  {
    std::lock_guard done_lock(done_mutex_);
    done_ = true;
  }
  done_cv_.notify_all();
}

void GistreamServer::Wait() {
  std::unique_lock lock(done_mutex_);
  done_cv_.wait(lock, [this] { return done_; });
}

}  // namespace gistream::service
