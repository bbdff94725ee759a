// gistream.v1.Gistream on gRPC's callback API. A thin layer: translate the
// request (translate.h), call the Engine, translate the answer. Unary calls
// run their Engine call on a small bounded worker pool so gRPC's callback
// threads never block on scene loads or renders; a full pool answers
// RESOURCE_EXHAUSTED. Sessions are SessionReactors.
#pragma once

#include <grpcpp/grpcpp.h>

#include "gistream/v1/gistream.grpc.pb.h"
#include "engine/engine.h"
#include "util/auth_tokens.h"
#include "service/session_reactor.h"
#include "service/worker_pool.h"

namespace gistream::service {

class GistreamService final : public ::gistream::v1::Gistream::CallbackService {
 public:
  struct Options {
    WorkerPool::Options workers;
    SessionReactor::Options session;
    /// Told about failed calls, rejected updates and dropped frames (also
    /// passed on to every session); may be null.
    std::shared_ptr<ServerObserver> observer;
    /// Bearer tokens -> tenants (service/grpc/auth.h); null: every caller
    /// is the default tenant.
    std::shared_ptr<const AuthTokens> tokens;
  };

  GistreamService(Engine& engine, const Options& options);
  ~GistreamService() override;

  // Runs what the pool holds and joins it. Call after grpc::Server::Shutdown
  // returned (no call can submit work then) and before Engine::Shutdown.
  void StopWorkers();

  grpc::ServerUnaryReactor* LoadScene(grpc::CallbackServerContext* context,
                                      const ::gistream::v1::LoadSceneRequest* request,
                                      ::gistream::v1::LoadSceneResponse* response) override;
  grpc::ServerUnaryReactor* UnloadScene(grpc::CallbackServerContext* context,
                                        const ::gistream::v1::UnloadSceneRequest* request,
                                        ::gistream::v1::UnloadSceneResponse* response) override;
  grpc::ServerUnaryReactor* ListSolvers(grpc::CallbackServerContext* context,
                                        const ::gistream::v1::ListSolversRequest* request,
                                        ::gistream::v1::ListSolversResponse* response) override;
  grpc::ServerUnaryReactor* Render(grpc::CallbackServerContext* context,
                                   const ::gistream::v1::RenderRequest* request,
                                   ::gistream::v1::Frame* response) override;
  grpc::ServerBidiReactor<::gistream::v1::SessionRequest, ::gistream::v1::SessionEvent>* Session(
      grpc::CallbackServerContext* context) override;
  grpc::ServerUnaryReactor* GetServerStatus(grpc::CallbackServerContext* context,
                                            const ::gistream::v1::GetServerStatusRequest* request,
                                            ::gistream::v1::ServerStatus* response) override;

 private:
  // Runs `work` (returning grpc::Status) on the pool and finishes the call
  // with its result. `upload_bytes` of the request (a LoadScene's scene and
  // environment) are reserved from the memory budget first, once the caller
  // is authenticated, and held until `work` ends (Engine::ReserveUpload).
  template <typename Work>
  grpc::ServerUnaryReactor* RunOnPool(grpc::CallbackServerContext* context, const char* method,
                                      Work work, uint64_t upload_bytes = 0);

  // Counts and logs (at info, with the code's name) a call that failed.
  void NoteFailure(std::string_view method, grpc::CallbackServerContext* context,
                   const grpc::Status& status);

  // Configuration
  Engine& engine_;
  const Options options_;

  // Runtime data
  WorkerPool pool_;
};

}  // namespace gistream::service
