#include "service/gistream_service.h"

#include <unistd.h>

#include <chrono>
#include <utility>

#include <absl/strings/str_cat.h>

#include "service/auth.h"
#include "service/translate.h"
#include "util/log.h"
#include "util/process_stats.h"
#include "util/version.h"

namespace gistream::service {
namespace {

// "HOSTNAME/PID": which server answered (behind a balancer, a pod's name).
const std::string& Instance() {
  static const std::string instance = [] {
    char host[256] = {};
    if (gethostname(host, sizeof(host) - 1) != 0) host[0] = '\0';
    return absl::StrCat(host[0] != '\0' ? host : "unknown", "/", getpid());
  }();
  return instance;
}

}  // namespace

namespace pb = ::gistream::v1;

namespace {
// Sessions report to the service's observer unless given their own.
GistreamService::Options WithSessionObserver(GistreamService::Options options) {
  if (options.session.observer == nullptr) options.session.observer = options.observer;
  return options;
}
// A Session call refused before it starts (no valid token).
class RejectedSession final : public grpc::ServerBidiReactor<pb::SessionRequest, pb::SessionEvent> {
 public:
  explicit RejectedSession(const grpc::Status& status) { Finish(status); }
  void OnDone() override { delete this; }
};

// `stats` with the scenes and sessions of other tenants left out, and the
// server-wide figures (frames of every session, memory, GPU, retiring
// solvers) replaced by the tenant's own or 0: one tenant's status says
// nothing of another's load (issue 30). Operators read those on /metrics.
EngineStats OnlyTenant(EngineStats stats, const TenantId& tenant) {
  EngineStats out;
  out.scene_ids.clear();
  out.scene_tenants.clear();
  for (size_t i = 0; i < stats.scene_ids.size() && i < stats.scene_tenants.size(); ++i) {
    if (stats.scene_tenants[i] != tenant) continue;
    out.scene_ids.push_back(stats.scene_ids[i]);
    out.scene_tenants.push_back(tenant);
  }
  out.session_status = std::move(stats.session_status);
  std::erase_if(out.session_status, [&](const SessionStatus& s) { return s.tenant != tenant; });
  out.scenes = uint32_t(out.scene_ids.size());
  out.sessions = uint32_t(out.session_status.size());
  for (const SessionStatus& s : out.session_status) out.frames_rendered += s.frames;
  return out;
}
}  // namespace

GistreamService::GistreamService(Engine& engine, const Options& options)
    : engine_(engine), options_(WithSessionObserver(options)), pool_(options.workers) {}

void GistreamService::NoteFailure(std::string_view method, grpc::CallbackServerContext* context,
                                  const grpc::Status& status) {
  const absl::StatusCode code = FromGrpcCode(status.error_code());
  if (options_.observer) options_.observer->OnRpcFailed(method, code);
  // The code's name and the message (which names the field); never the request.
  Log(LogLevel::kInfo,
      absl::StrCat(absl::string_view(method.data(), method.size()), " from ", context->peer(),
                   " failed: ", absl::StatusCodeToString(code), ": ", status.error_message()));
}

GistreamService::~GistreamService() { StopWorkers(); }

void GistreamService::StopWorkers() { pool_.Stop(); }

template <typename Work>
grpc::ServerUnaryReactor* GistreamService::RunOnPool(grpc::CallbackServerContext* context,
                                                     const char* method, Work work,
                                                     uint64_t upload_bytes) {
  grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
  // Before anything of the request is looked at (TokenAuthProcessor has
  // usually rejected an unknown caller already).
  absl::StatusOr<TenantId> tenant = CallerTenant(*context, options_.tokens.get());
  if (!tenant.ok()) {
    const grpc::Status status = ToGrpcStatus(tenant.status());
    NoteFailure(method, context, status);
    if (options_.observer) options_.observer->OnRpcFinished(method, tenant.status().code());
    reactor->Finish(status);
    return reactor;
  }
  // The request's upload, held by gRPC until the call finishes: counted
  // while it waits for a worker, not only once its load parses it.
  std::shared_ptr<MemoryBudget::Reservation> upload;
  if (upload_bytes > 0) {
    absl::StatusOr<MemoryBudget::Reservation> held = engine_.ReserveUpload(
        upload_bytes, absl::StrCat(method, ": ", upload_bytes, " bytes uploaded"));
    if (!held.ok()) {
      const grpc::Status status = ToGrpcStatus(held.status());
      NoteFailure(method, context, status);
      if (options_.observer) options_.observer->OnRpcFinished(method, held.status().code());
      reactor->Finish(status);
      return reactor;
    }
    upload = std::make_shared<MemoryBudget::Reservation>(*std::move(held));
  }
  absl::Status submitted = pool_.Submit(
      [this, reactor, context, method, work, upload, tenant = *std::move(tenant)]() mutable {
        grpc::Status status;
        if (context->IsCancelled()) {
          status = grpc::Status(grpc::StatusCode::CANCELLED, "cancelled before it ran");
        } else {
          status = work(tenant);
        }
        if (!status.ok()) NoteFailure(method, context, status);
        if (options_.observer) {
          options_.observer->OnRpcFinished(method, FromGrpcCode(status.error_code()));
        }
        reactor->Finish(status);  // the last use of context/request/response
        upload.reset();           // the request goes with the call
      });
  if (!submitted.ok()) {
    const grpc::Status status = ToGrpcStatus(submitted);
    NoteFailure(method, context, status);
    if (options_.observer) options_.observer->OnRpcFinished(method, submitted.code());
    reactor->Finish(status);
  }
  return reactor;
}

grpc::ServerUnaryReactor* GistreamService::LoadScene(grpc::CallbackServerContext* context,
                                                     const pb::LoadSceneRequest* request,
                                                     pb::LoadSceneResponse* response) {
  return RunOnPool(
      context, "LoadScene",
      [this, context, request, response](const TenantId& tenant) {
        absl::StatusOr<SceneSource> source = SceneSourceFromProto(*request);
        if (!source.ok()) return ToGrpcStatus(source.status());
        source->tenant = tenant;
        // A client that leaves or whose deadline passes stops the load between
        // its slices (scene/gltf/load_control.h), naming the stage.
        source->stop = [context]() -> absl::Status {
          if (!context->IsCancelled()) return absl::OkStatus();
          if (context->deadline() <= std::chrono::system_clock::now()) {
            return absl::DeadlineExceededError("the client's deadline passed");
          }
          return absl::CancelledError("the client cancelled the call");
        };
        absl::StatusOr<SceneInfo> info = engine_.LoadScene(*source);
        if (!info.ok()) return ToGrpcStatus(info.status());
        Log(LogLevel::kInfo, {"", info->id},
            absl::StrCat(
                "loaded by tenant ", tenant, " (", info->triangle_count, " triangles, ",
                info->lights.size(), " lights",
                info->proxy_trees_skipped + info->proxy_levels_skipped > 0
                    ? absl::StrCat("; past --max-load-seconds: ", info->proxy_trees_skipped,
                                   " primitive(s) without proxy trees, ",
                                   info->proxy_levels_skipped, " with fewer levels")
                    : "",
                ")"));
        SceneInfoToProto(*info, response);
        return grpc::Status::OK;
      },
      uint64_t(request->gltf().size()) + request->environment_image().size());
}

grpc::ServerUnaryReactor* GistreamService::UnloadScene(grpc::CallbackServerContext* context,
                                                       const pb::UnloadSceneRequest* request,
                                                       pb::UnloadSceneResponse* /*response*/) {
  return RunOnPool(context, "UnloadScene", [this, request](const TenantId& tenant) {
    if (request->scene_id().empty()) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "scene_id: empty");
    }
    return ToGrpcStatus(engine_.UnloadScene(request->scene_id(), tenant));
  });
}

grpc::ServerUnaryReactor* GistreamService::ListSolvers(grpc::CallbackServerContext* context,
                                                       const pb::ListSolversRequest* /*request*/,
                                                       pb::ListSolversResponse* response) {
  return RunOnPool(context, "ListSolvers", [this, response](const TenantId&) {
    SolversToProto(engine_.ListSolvers(), response);
    return grpc::Status::OK;
  });
}

grpc::ServerUnaryReactor* GistreamService::Render(grpc::CallbackServerContext* context,
                                                  const pb::RenderRequest* request,
                                                  pb::Frame* response) {
  return RunOnPool(context, "Render", [this, context, request, response](const TenantId& tenant) {
    absl::StatusOr<RenderRequest> render = RenderRequestFromProto(*request);
    if (!render.ok()) return ToGrpcStatus(render.status());
    render->tenant = tenant;
    // A client that leaves (or whose deadline passes, or a server shutdown
    // past its deadline) cancels the call: the engine stops the work.
    render->cancelled = [context] { return context->IsCancelled(); };
    absl::StatusOr<EncodedFrame> frame = engine_.Render(*render);
    if (!frame.ok()) return ToGrpcStatus(frame.status());
    if (options_.observer) options_.observer->OnFrameSent(frame->image.size());
    FrameToProto(*frame, response);
    return grpc::Status::OK;
  });
}

grpc::ServerBidiReactor<pb::SessionRequest, pb::SessionEvent>* GistreamService::Session(
    grpc::CallbackServerContext* context) {
  absl::StatusOr<TenantId> tenant = CallerTenant(*context, options_.tokens.get());
  if (!tenant.ok()) {
    const grpc::Status status = ToGrpcStatus(tenant.status());
    NoteFailure("Session", context, status);
    return new RejectedSession(status);
  }
  return new SessionReactor(engine_, pool_, context, options_.session, *std::move(tenant));
}

grpc::ServerUnaryReactor* GistreamService::GetServerStatus(
    grpc::CallbackServerContext* context, const pb::GetServerStatusRequest* /*request*/,
    pb::ServerStatus* response) {
  return RunOnPool(context, "GetServerStatus", [this, response](const TenantId& tenant) {
    // With tokens a tenant sees its own scenes and sessions only (without,
    // there is one tenant).
    EngineStats stats = engine_.stats();
    ProcessStats process = ReadProcessStats();
    if (options_.tokens) {
      stats = OnlyTenant(std::move(stats), tenant);
      // The process's memory and CPU are every tenant's together.
      process.rss_bytes = process.peak_rss_bytes = 0;
      process.cpu_seconds = 0.0;
    }
    ServerStatusToProto(engine_.device_info(), stats, process, Version(), response);
    response->set_instance(Instance());
    return grpc::Status::OK;
  });
}

}  // namespace gistream::service
