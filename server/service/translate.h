// The one place protobuf meets the domain: gistream.v1 messages <-> the
// Engine's types (service/engine.h, scene/updates.h), and absl::Status ->
// grpc::Status. Translation checks only what the wire form can get wrong
// (repeated fields of the wrong length, a oneof left unset, half of a pair)
// and answers INVALID_ARGUMENT naming the field; ids, ranges and NaN/Inf are
// the Engine's to validate.
//
// Wire defaults resolved here: an all-zero Quat is the identity, an unset
// scale is (1,1,1), an empty solver is "direct", quality 0 is 90, format
// UNSPECIFIED is JPEG, width = height = 0 is the engine's default size,
// max_fps 0 stays 0 (the engine's default cap), environment_intensity 0 is 1.
#pragma once

#include <absl/strings/string_view.h>
#include <string_view>
#include <vector>

#include <grpcpp/support/status.h>

#include "gistream/v1/gistream.pb.h"
#include "engine/engine.h"
#include "util/process_stats.h"
#include "util/status.h"

namespace gistream::service {

namespace pb = ::gistream::v1;

// ---------------------------------------------------------------- status

grpc::StatusCode ToGrpcCode(absl::StatusCode code);
// The inverse; the codes and their names (absl::StatusCodeToString) are gRPC's.
absl::StatusCode FromGrpcCode(grpc::StatusCode code);
grpc::Status ToGrpcStatus(const absl::Status& status);

// ---------------------------------------------------------------- math

glm::vec3 FromProto(const pb::Vec3& v);
// All zeros (an unset field) is the identity; otherwise (x, y, z, w) as given.
glm::quat FromProto(const pb::Quat& q);
void ToProto(const glm::vec3& v, pb::Vec3* out);
void ToProto(const glm::quat& q, pb::Quat* out);

// ---------------------------------------------------------------- requests

// `field` prefixes error messages: "update", "updates[3]", ...
absl::StatusOr<Update> UpdateFromProto(const pb::Update& update, absl::string_view field);
absl::StatusOr<CameraUpdate> CameraFromProto(const pb::CameraChange& camera,
                                             absl::string_view field);
absl::StatusOr<EncodingOptions> EncodingFromProto(const pb::Encoding& encoding,
                                                  absl::string_view field);
absl::StatusOr<SceneSource> SceneSourceFromProto(const pb::LoadSceneRequest& request);
absl::StatusOr<SessionConfig> SessionConfigFromProto(const pb::SessionConfig& config);
absl::StatusOr<RenderRequest> RenderRequestFromProto(const pb::RenderRequest& request);

// ---------------------------------------------------------------- responses

pb::ImageFormat ToProto(ImageFormat format);
void SceneInfoToProto(const SceneInfo& info, pb::LoadSceneResponse* out);
void SolversToProto(const std::vector<SolverDescription>& solvers, pb::ListSolversResponse* out);
void FrameToProto(const EncodedFrame& frame, pb::Frame* out);
void SessionOpenedToProto(const SessionOpenInfo& info, pb::SessionOpened* out);
void UpdateRejectedToProto(uint64_t seq, const absl::Status& status, pb::UpdateRejected* out);
// `version` is util/version.h's Version(); `process` ReadProcessStats().
void ServerStatusToProto(const DeviceInfo& device, const EngineStats& stats,
                         const ProcessStats& process, std::string_view version,
                         pb::ServerStatus* out);

}  // namespace gistream::service
