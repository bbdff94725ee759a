// The gRPC server around GistreamService: listening port, message size
// limits, keepalive, the standard health service (grpc.health.v1) and
// server reflection, and graceful shutdown:
//   health -> NOT_SERVING, grpc::Server::Shutdown(deadline) (running calls
//   get until the deadline, then are cancelled), worker pool drained,
//   Engine::Shutdown().
#pragma once

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>

#include <grpcpp/grpcpp.h>

#include "engine/engine.h"
#include "service/auth.h"
#include "service/gistream_service.h"
#include "service/reflection_v1.h"

namespace gistream::service {

struct ServerOptions {
  /// host:port to listen on; port 0 picks a free port (see GistreamServer::address).
  std::string listen = "127.0.0.1:50051";
  /// Largest request / response message (LoadScene carries whole .glb files).
  int max_receive_message_bytes = 272 << 20;
  int max_send_message_bytes = 272 << 20;
  /// Memory gRPC's transport may hold for all calls together (read buffers
  /// of uploads on their way in, above all): past it, new calls are refused
  /// with RESOURCE_EXHAUSTED (HTTP/2 ENHANCE_YOUR_CALM) instead of being
  /// read. 0: gRPC's default (unbounded).
  uint64_t transport_memory_bytes = 0;
  /// HTTP/2 keepalive pings on idle connections, so dead clients free their sessions.
  std::chrono::milliseconds keepalive_time{30'000};
  std::chrono::milliseconds keepalive_timeout{10'000};
  /// Shortest interval between client pings the server tolerates.
  std::chrono::milliseconds min_client_ping_interval{10'000};
  /// TLS (mutual with a client CA); empty: plaintext, which needs a loopback
  /// `listen` or `allow_insecure` (service/grpc/auth.h).
  TlsFiles tls;
  bool allow_insecure = false;
  /// host:port of a second, plaintext listener that serves grpc.health.v1
  /// only (kubelet's gRPC probes speak no TLS); empty: none.
  std::string health_listen;
  /// Bearer tokens and their tenants; set it in `service.tokens` (the
  /// server installs the matching auth processor).
  GistreamService::Options service;
};

class GistreamServer {
 public:
  // Binds and starts serving; health reports SERVING once this returns.
  // UNAVAILABLE when the address cannot be bound.
  static absl::StatusOr<std::unique_ptr<GistreamServer>> Start(Engine& engine,
                                                               const ServerOptions& options);
  // Shutdown(0) unless it ran.
  ~GistreamServer();
  GistreamServer(const GistreamServer&) = delete;
  GistreamServer& operator=(const GistreamServer&) = delete;

  // The listen address with the port actually bound ("127.0.0.1:43121").
  const std::string& address() const { return address_; }
  int port() const { return port_; }
  int health_port() const { return health_port_; }

  // First shutdown step, also on its own (e.g. a drain period for load
  // balancers): health answers NOT_SERVING for every service from now on.
  void SetNotServing();
  // Graceful shutdown (see the top of this file). Idempotent; blocks until
  // every call has finished and the engine has shut down.
  void Shutdown(std::chrono::milliseconds deadline);
  // Blocks until Shutdown has completed.
  void Wait();

 private:
  GistreamServer(Engine& engine, const ServerOptions& options);
  // Start's steps: message sizes, the transport's memory, keepalive; the
  // plaintext health-only server of --health-listen; health SERVING, and
  // NOT_SERVING while the engine recovers from a GPU reset.
  static void ConfigureTransport(grpc::ServerBuilder& builder, const ServerOptions& options);
  absl::Status StartHealth(const std::string& listen);
  void ReportServing(Engine& engine);

  // Configuration
  Engine& engine_;
  std::string address_;
  int port_ = 0;

  // Runtime data. service_ must outlive server_ (declared first).
  std::unique_ptr<GistreamService> service_;
  std::unique_ptr<ReflectionV1> reflection_v1_;  // grpc.reflection.v1 (v1alpha: libgrpc++)
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<grpc::Server> health_server_;  // --health-listen
  int health_port_ = 0;
  std::mutex shutdown_mutex_;  // held for the whole of Shutdown
  std::mutex done_mutex_;
  std::condition_variable done_cv_;
  bool done_ = false;  // Shutdown completed
};

}  // namespace gistream::service
