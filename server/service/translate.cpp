#include "service/translate.h"

#include <limits>
#include <string>
#include <utility>

#include <glm/gtc/type_ptr.hpp>

namespace gistream::service {

// ---------------------------------------------------------------- status

grpc::StatusCode ToGrpcCode(absl::StatusCode code) {
  switch (code) {
    case absl::StatusCode::kOk: return grpc::StatusCode::OK;
    case absl::StatusCode::kCancelled: return grpc::StatusCode::CANCELLED;
    case absl::StatusCode::kUnknown: return grpc::StatusCode::UNKNOWN;
    case absl::StatusCode::kInvalidArgument: return grpc::StatusCode::INVALID_ARGUMENT;
    case absl::StatusCode::kDeadlineExceeded: return grpc::StatusCode::DEADLINE_EXCEEDED;
    case absl::StatusCode::kNotFound: return grpc::StatusCode::NOT_FOUND;
    case absl::StatusCode::kAlreadyExists: return grpc::StatusCode::ALREADY_EXISTS;
    case absl::StatusCode::kPermissionDenied: return grpc::StatusCode::PERMISSION_DENIED;
    case absl::StatusCode::kResourceExhausted: return grpc::StatusCode::RESOURCE_EXHAUSTED;
    case absl::StatusCode::kFailedPrecondition: return grpc::StatusCode::FAILED_PRECONDITION;
    case absl::StatusCode::kAborted: return grpc::StatusCode::ABORTED;
    case absl::StatusCode::kOutOfRange: return grpc::StatusCode::OUT_OF_RANGE;
    case absl::StatusCode::kUnimplemented: return grpc::StatusCode::UNIMPLEMENTED;
    case absl::StatusCode::kInternal: return grpc::StatusCode::INTERNAL;
    case absl::StatusCode::kUnavailable: return grpc::StatusCode::UNAVAILABLE;
    case absl::StatusCode::kDataLoss: return grpc::StatusCode::DATA_LOSS;
    case absl::StatusCode::kUnauthenticated: return grpc::StatusCode::UNAUTHENTICATED;
    default: return grpc::StatusCode::UNKNOWN;
  }
}

absl::StatusCode FromGrpcCode(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK: return absl::StatusCode::kOk;
    case grpc::StatusCode::CANCELLED: return absl::StatusCode::kCancelled;
    case grpc::StatusCode::UNKNOWN: return absl::StatusCode::kUnknown;
    case grpc::StatusCode::INVALID_ARGUMENT: return absl::StatusCode::kInvalidArgument;
    case grpc::StatusCode::DEADLINE_EXCEEDED: return absl::StatusCode::kDeadlineExceeded;
    case grpc::StatusCode::NOT_FOUND: return absl::StatusCode::kNotFound;
    case grpc::StatusCode::ALREADY_EXISTS: return absl::StatusCode::kAlreadyExists;
    case grpc::StatusCode::PERMISSION_DENIED: return absl::StatusCode::kPermissionDenied;
    case grpc::StatusCode::RESOURCE_EXHAUSTED: return absl::StatusCode::kResourceExhausted;
    case grpc::StatusCode::FAILED_PRECONDITION: return absl::StatusCode::kFailedPrecondition;
    case grpc::StatusCode::ABORTED: return absl::StatusCode::kAborted;
    case grpc::StatusCode::OUT_OF_RANGE: return absl::StatusCode::kOutOfRange;
    case grpc::StatusCode::UNIMPLEMENTED: return absl::StatusCode::kUnimplemented;
    case grpc::StatusCode::INTERNAL: return absl::StatusCode::kInternal;
    case grpc::StatusCode::UNAVAILABLE: return absl::StatusCode::kUnavailable;
    case grpc::StatusCode::DATA_LOSS: return absl::StatusCode::kDataLoss;
    case grpc::StatusCode::UNAUTHENTICATED: return absl::StatusCode::kUnauthenticated;
    default: return absl::StatusCode::kUnknown;
  }
}

namespace {

// A status message sent to a client is at most this long: messages echo
// user strings cut to 64 bytes (util/user_string.h), and this bounds
// whatever else (a library's error text quoting input) gets through.
constexpr size_t kMaxStatusMessageBytes = 4096;

std::string BoundedMessage(absl::string_view message) {
  if (message.size() <= kMaxStatusMessageBytes) return std::string(message);
  size_t cut = kMaxStatusMessageBytes;
  while (cut > 0 && (static_cast<unsigned char>(message[cut]) & 0xC0) == 0x80) --cut;
  return absl::StrCat(message.substr(0, cut), "\u2026 (", message.size(), " bytes)");
}

}  // namespace

grpc::Status ToGrpcStatus(const absl::Status& status) {
  if (status.ok()) return grpc::Status::OK;
  return grpc::Status(ToGrpcCode(status.code()), BoundedMessage(status.message()));
}

// ---------------------------------------------------------------- math

glm::vec3 FromProto(const pb::Vec3& v) { return {v.x(), v.y(), v.z()}; }

glm::quat FromProto(const pb::Quat& q) {
  if (q.x() == 0.0f && q.y() == 0.0f && q.z() == 0.0f && q.w() == 0.0f) {
    return glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  }
  return glm::quat(q.w(), q.x(), q.y(), q.z());  // glm: (w, x, y, z)
}

void ToProto(const glm::vec3& v, pb::Vec3* out) {
  out->set_x(v.x);
  out->set_y(v.y);
  out->set_z(v.z);
}

void ToProto(const glm::quat& q, pb::Quat* out) {
  out->set_x(q.x);
  out->set_y(q.y);
  out->set_z(q.z);
  out->set_w(q.w);
}

// ---------------------------------------------------------------- requests

namespace {

absl::Status FieldError(absl::string_view field, absl::string_view what) {
  return absl::InvalidArgumentError(absl::StrCat(field, ": ", what));
}

// proto3 uint32/bool scalars have no presence: a pair is "set" when non-zero.
absl::Status CheckPair(absl::string_view field, absl::string_view a_name, bool a_set,
                       absl::string_view b_name, bool b_set) {
  if (a_set == b_set) return absl::OkStatus();
  const absl::string_view set = a_set ? a_name : b_name;
  const absl::string_view unset = a_set ? b_name : a_name;
  return FieldError(absl::StrCat(field, field.empty() ? "" : ".", set),
                    absl::StrCat("set without ", field, field.empty() ? "" : ".", unset,
                                 "; give both or neither"));
}

// A rotation field: unset means identity (proto3 message presence); a set
// one is taken as given, so that update validation rejects an explicit
// zero or non-unit quaternion naming the field instead of it silently
// becoming the identity.
glm::quat RotationFromProto(bool set, const pb::Quat& q) {
  return set ? glm::quat(q.w(), q.x(), q.y(), q.z()) : glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
}

absl::StatusOr<NodeTransformUpdate> NodeTransformFromProto(const pb::NodeTransform& t,
                                                           absl::string_view field) {
  NodeTransformUpdate out;
  out.node = t.node();
  out.translation = FromProto(t.translation());
  out.rotation = RotationFromProto(t.has_rotation(), t.rotation());
  out.scale = t.has_scale() ? FromProto(t.scale()) : glm::vec3(1.0f);
  if (t.matrix_size() != 0) {
    if (t.matrix_size() != 16) {
      return FieldError(absl::StrCat(field, ".matrix"),
                        absl::StrCat("expected 16 floats, got ", t.matrix_size()));
    }
    out.matrix = glm::make_mat4(t.matrix().data());  // column major, as glTF
  }
  return out;
}

LightUpdate LightFromProto(const pb::LightChange& l) {
  LightUpdate out;
  out.light = l.light();
  if (l.has_color()) out.color = FromProto(l.color());
  if (l.has_intensity()) out.intensity = l.intensity();
  if (l.has_position()) out.position = FromProto(l.position());
  if (l.has_direction()) out.direction = FromProto(l.direction());
  if (l.has_inner_cone_angle()) out.inner_cone_angle = l.inner_cone_angle();
  if (l.has_outer_cone_angle()) out.outer_cone_angle = l.outer_cone_angle();
  return out;
}

absl::StatusOr<MaterialUpdate> MaterialFromProto(const pb::MaterialChange& m,
                                                 absl::string_view field) {
  MaterialUpdate out;
  out.material = m.material();
  const auto& c = m.base_color();
  switch (c.size()) {
    case 0: break;
    case 3: out.base_color = glm::vec4(c[0], c[1], c[2], 1.0f); break;
    case 4: out.base_color = glm::vec4(c[0], c[1], c[2], c[3]); break;
    default:
      return FieldError(absl::StrCat(field, ".base_color"),
                        absl::StrCat("expected 3 or 4 floats, got ", c.size()));
  }
  if (m.has_emissive()) out.emissive = FromProto(m.emissive());
  if (m.has_emissive_strength()) out.emissive_strength = m.emissive_strength();
  if (m.has_metallic()) out.metallic = m.metallic();
  if (m.has_roughness()) out.roughness = m.roughness();
  return out;
}

EnvironmentUpdate EnvironmentFromProto(const pb::EnvironmentChange& e) {
  EnvironmentUpdate out;
  if (e.has_rotation()) out.rotation = e.rotation();
  if (e.has_intensity()) out.intensity = e.intensity();
  return out;
}

AnimationUpdate AnimationFromProto(const pb::AnimationChange& a) {
  AnimationUpdate out;
  if (a.which_case() == pb::AnimationChange::kAnimation) out.animation = a.animation();
  if (a.which_case() == pb::AnimationChange::kName) out.name = a.name();
  if (a.has_playing()) out.playing = a.playing();
  if (a.has_time()) out.time = a.time();
  if (a.has_speed()) out.speed = a.speed();
  if (a.has_loop()) out.loop = a.loop();
  return out;
}

MorphWeightsUpdate MorphWeightsFromProto(const pb::MorphWeightsChange& m) {
  return {m.node(), std::vector<float>(m.weights().begin(), m.weights().end())};
}

absl::Status ResolutionFromProto(absl::string_view field, uint32_t width, uint32_t height,
                                 uint32_t* out_width, uint32_t* out_height) {
  GS_RETURN_IF_ERROR(CheckPair(field, "width", width != 0, "height", height != 0));
  if (width != 0) {
    *out_width = width;
    *out_height = height;
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<Update> UpdateFromProto(const pb::Update& update, absl::string_view field) {
  Update out;
  out.seq = update.seq();
  switch (update.change_case()) {
    case pb::Update::kNodeTransform: {
      GS_ASSIGN_OR_RETURN(
          out.change,
          NodeTransformFromProto(update.node_transform(), absl::StrCat(field, ".node_transform")));
      break;
    }
    case pb::Update::kLight: out.change = LightFromProto(update.light()); break;
    case pb::Update::kCamera: {
      GS_ASSIGN_OR_RETURN(out.change,
                          CameraFromProto(update.camera(), absl::StrCat(field, ".camera")));
      break;
    }
    case pb::Update::kMaterial: {
      GS_ASSIGN_OR_RETURN(out.change,
                          MaterialFromProto(update.material(), absl::StrCat(field, ".material")));
      break;
    }
    case pb::Update::kEnvironment: out.change = EnvironmentFromProto(update.environment()); break;
    case pb::Update::kAnimation: out.change = AnimationFromProto(update.animation()); break;
    case pb::Update::kMorphWeights:
      out.change = MorphWeightsFromProto(update.morph_weights());
      break;
    case pb::Update::CHANGE_NOT_SET:
    default:
      return FieldError(
          absl::StrCat(field, ".change"),
          absl::StrCat("no change set (seq ", update.seq(),
                       "); expected one of node_transform, light, camera, material, environment, "
                       "animation, morph_weights"));
  }
  return out;
}

absl::StatusOr<CameraUpdate> CameraFromProto(const pb::CameraChange& camera,
                                             absl::string_view field) {
  CameraUpdate out;
  switch (camera.view_case()) {
    case pb::CameraChange::kLookAt: {
      const pb::LookAt& l = camera.look_at();
      LookAt look;
      look.eye = FromProto(l.eye());
      look.target = FromProto(l.target());
      const glm::vec3 up = FromProto(l.up());
      look.up = (up == glm::vec3(0.0f)) ? glm::vec3(0.0f, 1.0f, 0.0f) : up;
      out.look_at = look;
      break;
    }
    case pb::CameraChange::kPose: {
      CameraPose pose;
      pose.position = FromProto(camera.pose().position());
      pose.rotation = RotationFromProto(camera.pose().has_rotation(), camera.pose().rotation());
      out.pose = pose;
      break;
    }
    case pb::CameraChange::kSceneCamera: out.scene_camera = camera.scene_camera(); break;
    case pb::CameraChange::VIEW_NOT_SET:
    default: break;
  }
  if (camera.has_yfov_degrees()) out.yfov_degrees = camera.yfov_degrees();
  GS_RETURN_IF_ERROR(CheckPair(field, "width", camera.has_width(), "height", camera.has_height()));
  if (camera.has_width()) {
    out.width = camera.width();
    out.height = camera.height();
  }
  return out;
}

absl::StatusOr<EncodingOptions> EncodingFromProto(const pb::Encoding& encoding,
                                                  absl::string_view field) {
  EncodingOptions out;
  switch (encoding.format()) {
    case pb::IMAGE_FORMAT_UNSPECIFIED:
    case pb::IMAGE_FORMAT_JPEG: out.format = ImageFormat::kJpeg; break;
    case pb::IMAGE_FORMAT_PNG: out.format = ImageFormat::kPng; break;
    case pb::IMAGE_FORMAT_EXR: out.format = ImageFormat::kExr; break;
    case pb::IMAGE_FORMAT_H264: out.format = ImageFormat::kH264; break;
    case pb::IMAGE_FORMAT_HEVC: out.format = ImageFormat::kHevc; break;
    case pb::IMAGE_FORMAT_AV1: out.format = ImageFormat::kAv1; break;
    default:
      return FieldError(absl::StrCat(field, ".format"),
                        absl::StrCat("unknown image format ", static_cast<int>(encoding.format())));
  }
  if (encoding.quality() > 100) {
    return FieldError(absl::StrCat(field, ".quality"),
                      absl::StrCat("expected 1..100 (0 means 90), got ", encoding.quality()));
  }
  out.quality = encoding.quality() == 0 ? 90 : static_cast<int>(encoding.quality());
  out.exposure = encoding.exposure();
  if (encoding.crf() > 51) {
    return FieldError(absl::StrCat(field, ".crf"),
                      absl::StrCat("expected 1..51 (0 means 23), got ", encoding.crf()));
  }
  out.crf = encoding.crf() == 0 ? 23 : static_cast<int>(encoding.crf());
  out.bitrate_kbps = encoding.bitrate_kbps();
  out.key_frame_interval = encoding.key_frame_interval() == 0 ? 120 : encoding.key_frame_interval();
  out.send_unchanged = encoding.send_unchanged();
  return out;
}

absl::StatusOr<SceneSource> SceneSourceFromProto(const pb::LoadSceneRequest& request) {
  SceneSource out;
  switch (request.source_case()) {
    case pb::LoadSceneRequest::kName:
      if (request.name().empty()) return FieldError("name", "empty scene name");
      out.name = request.name();
      break;
    case pb::LoadSceneRequest::kGltf:
      if (request.gltf().empty()) return FieldError("gltf", "empty");
      out.bytes = request.gltf();
      break;
    case pb::LoadSceneRequest::SOURCE_NOT_SET:
    default: return FieldError("source", "set one of name or gltf");
  }
  switch (request.environment_case()) {
    case pb::LoadSceneRequest::kEnvironmentName:
      out.environment_name = request.environment_name();
      break;
    case pb::LoadSceneRequest::kEnvironmentImage:
      out.environment_bytes = request.environment_image();
      break;
    case pb::LoadSceneRequest::ENVIRONMENT_NOT_SET:
    default: break;
  }
  out.environment_intensity =
      request.environment_intensity() == 0.0f ? 1.0f : request.environment_intensity();
  out.private_copy = request.private_copy();
  return out;
}

absl::StatusOr<SessionConfig> SessionConfigFromProto(const pb::SessionConfig& config) {
  SessionConfig out;
  out.scene = config.scene_id();
  if (!config.solver().empty()) out.solver = config.solver();
  out.params.insert(config.params().begin(), config.params().end());
  GS_RETURN_IF_ERROR(
      ResolutionFromProto("config", config.width(), config.height(), &out.width, &out.height));
  GS_ASSIGN_OR_RETURN(out.encoding, EncodingFromProto(config.encoding(), "config.encoding"));
  switch (config.pacing_case()) {
    case pb::SessionConfig::kOnRequest: out.pacing = Pacing::kOnRequest; break;
    case pb::SessionConfig::kContinuous:
      out.pacing = Pacing::kContinuous;
      out.max_fps = config.continuous().max_fps();
      break;
    case pb::SessionConfig::PACING_NOT_SET:
    default: out.pacing = Pacing::kContinuous; break;
  }
  out.frame_budget_ms = config.frame_budget_ms();
  out.refine_samples = config.refine_samples();
  if (config.has_camera()) {
    GS_ASSIGN_OR_RETURN(out.camera, CameraFromProto(config.camera(), "config.camera"));
  }
  return out;
}

absl::StatusOr<RenderRequest> RenderRequestFromProto(const pb::RenderRequest& request) {
  RenderRequest out;
  out.scene = request.scene_id();
  if (!request.solver().empty()) out.solver = request.solver();
  out.params.insert(request.params().begin(), request.params().end());
  GS_RETURN_IF_ERROR(
      ResolutionFromProto("", request.width(), request.height(), &out.width, &out.height));
  GS_ASSIGN_OR_RETURN(out.encoding, EncodingFromProto(request.encoding(), "encoding"));
  if (request.has_camera()) {
    GS_ASSIGN_OR_RETURN(out.camera, CameraFromProto(request.camera(), "camera"));
  }
  out.updates.reserve(request.updates_size());
  for (int i = 0; i < request.updates_size(); ++i) {
    GS_ASSIGN_OR_RETURN(Update u,
                        UpdateFromProto(request.updates(i), absl::StrCat("updates[", i, "]")));
    out.updates.push_back(std::move(u));
  }
  out.frame_budget_ms = request.frame_budget_ms();
  out.refine_samples = request.refine_samples();
  return out;
}

// ---------------------------------------------------------------- responses

namespace {

pb::LightType ToProto(LightType type) {
  switch (type) {
    case LightType::kPoint: return pb::LIGHT_TYPE_POINT;
    case LightType::kSpot: return pb::LIGHT_TYPE_SPOT;
    case LightType::kDirectional: return pb::LIGHT_TYPE_DIRECTIONAL;
  }
  return pb::LIGHT_TYPE_UNSPECIFIED;
}

pb::ParamType ToProto(ParamType type) {
  switch (type) {
    case ParamType::kInt: return pb::PARAM_TYPE_INT;
    case ParamType::kFloat: return pb::PARAM_TYPE_FLOAT;
    case ParamType::kBool: return pb::PARAM_TYPE_BOOL;
    case ParamType::kEnum: return pb::PARAM_TYPE_ENUM;
  }
  return pb::PARAM_TYPE_UNSPECIFIED;
}

}  // namespace

pb::ImageFormat ToProto(ImageFormat format) {
  switch (format) {
    case ImageFormat::kJpeg: return pb::IMAGE_FORMAT_JPEG;
    case ImageFormat::kPng: return pb::IMAGE_FORMAT_PNG;
    case ImageFormat::kExr: return pb::IMAGE_FORMAT_EXR;
    case ImageFormat::kH264: return pb::IMAGE_FORMAT_H264;
    case ImageFormat::kHevc: return pb::IMAGE_FORMAT_HEVC;
    case ImageFormat::kAv1: return pb::IMAGE_FORMAT_AV1;
  }
  return pb::IMAGE_FORMAT_UNSPECIFIED;
}

void SceneInfoToProto(const SceneInfo& info, pb::LoadSceneResponse* out) {
  out->set_scene_id(info.id);
  for (const NodeSummary& n : info.nodes) {
    pb::NodeInfo* p = out->add_nodes();
    p->set_id(n.id);
    p->set_name(n.name);
    p->set_parent(n.parent);
    p->set_mesh(n.mesh);
    ToProto(n.translation, p->mutable_translation());
    ToProto(n.rotation, p->mutable_rotation());
    ToProto(n.scale, p->mutable_scale());
  }
  for (const LightSummary& l : info.lights) {
    pb::LightInfo* p = out->add_lights();
    p->set_id(l.id);
    p->set_name(l.name);
    p->set_type(ToProto(l.type));
    p->set_node(l.node);
    ToProto(l.color, p->mutable_color());
    p->set_intensity(l.intensity);
    ToProto(l.position, p->mutable_position());
    ToProto(l.direction, p->mutable_direction());
    p->set_inner_cone_angle(l.inner_cone_angle);
    p->set_outer_cone_angle(l.outer_cone_angle);
  }
  for (const CameraSummary& c : info.cameras) {
    pb::CameraInfo* p = out->add_cameras();
    p->set_id(c.id);
    p->set_name(c.name);
    p->set_node(c.node);
    p->set_yfov(c.yfov);
    ToProto(c.position, p->mutable_position());
    ToProto(c.rotation, p->mutable_rotation());
  }
  for (const MaterialSummary& m : info.materials) {
    pb::MaterialInfo* p = out->add_materials();
    p->set_id(m.id);
    p->set_name(m.name);
    for (int i = 0; i < 4; ++i) p->add_base_color(m.base_color[i]);
    ToProto(m.emissive, p->mutable_emissive());
    ToProto(m.emissive_factor, p->mutable_emissive_factor());
    p->set_emissive_strength(m.emissive_strength);
  }
  if (!info.bounds.empty()) {
    ToProto(info.bounds.min, out->mutable_bounds()->mutable_min());
    ToProto(info.bounds.max, out->mutable_bounds()->mutable_max());
  }
  out->set_triangle_count(info.triangle_count);
  out->set_vertex_count(info.vertex_count);
  out->set_emissive_triangle_count(info.emissive_triangle_count);
  out->set_proxy_trees_skipped(info.proxy_trees_skipped);
  out->set_proxy_levels_skipped(info.proxy_levels_skipped);
  out->set_has_environment(info.has_environment);
  for (const std::string& name : info.ignored_extensions) out->add_ignored_extensions(name);
  for (const std::string& line : info.import_warnings) out->add_import_warnings(line);
  for (const AnimationSummary& a : info.animations) {
    pb::AnimationInfo* p = out->add_animations();
    p->set_id(a.id);
    p->set_name(a.name);
    p->set_start(a.start);
    p->set_end(a.end);
  }
  out->set_version(info.version);
}

void SolversToProto(const std::vector<SolverDescription>& solvers, pb::ListSolversResponse* out) {
  for (const SolverDescription& s : solvers) {
    pb::SolverInfo* p = out->add_solvers();
    p->set_name(s.name);
    p->set_description(s.description);
    for (const std::string& stage : s.stages) p->add_stages(stage);
    for (const ParamSpec& spec : s.params) {
      pb::ParamSpec* ps = p->add_params();
      ps->set_name(spec.name);
      ps->set_type(ToProto(spec.type));
      ps->set_default_value(spec.default_value);
      ps->set_min(spec.min);
      ps->set_max(spec.max);
      for (const std::string& c : spec.choices) ps->add_choices(c);
      ps->set_description(spec.description);
    }
  }
}

void FrameToProto(const EncodedFrame& frame, pb::Frame* out) {
  out->set_frame_number(frame.frame_number);
  out->set_width(frame.width);
  out->set_height(frame.height);
  out->set_format(ToProto(frame.format));
  out->set_image(frame.image);
  out->set_scene_version(frame.scene_version);
  out->set_last_update_seq(frame.last_update_seq);
  for (const StageTiming& t : frame.timings) {
    pb::StageTiming* p = out->add_timings();
    p->set_name(t.name);
    p->set_cpu_ms(t.cpu_ms);
    p->set_gpu_ms(t.gpu_ms);
    p->set_skipped(t.skipped);
    p->set_cpu_stage(t.cpu_stage);
  }
  auto* stats = out->mutable_stats();
  for (const auto& [key, value] : frame.stats) (*stats)[key] = value;
  out->set_dropped_frames(frame.dropped_frames);
  out->set_solver(frame.solver);
  out->set_total_ms(frame.total_ms);
  out->set_key_frame(frame.key_frame);
  out->set_unchanged(frame.unchanged);
}

void SessionOpenedToProto(const SessionOpenInfo& info, pb::SessionOpened* out) {
  out->set_session_id(info.id);
  out->set_scene_id(info.scene);
  out->set_solver(info.solver);
  out->mutable_params()->insert(info.params.begin(), info.params.end());
}

void UpdateRejectedToProto(uint64_t seq, const absl::Status& status, pb::UpdateRejected* out) {
  out->set_seq(seq);
  out->set_code(static_cast<int32_t>(ToGrpcCode(status.code())));  // google.rpc.Code
  out->set_message(BoundedMessage(status.message()));
}

void ServerStatusToProto(const DeviceInfo& device, const EngineStats& stats,
                         const ProcessStats& process, std::string_view version,
                         pb::ServerStatus* out) {
  out->set_gl_vendor(device.vendor);
  out->set_gl_renderer(device.renderer);
  out->set_gl_version(device.version);
  out->set_cpu_model(device.cpu_model);
  out->set_cpu_threads(device.cpu_threads);
  out->set_sessions(stats.sessions);
  out->set_scenes(stats.scenes);
  out->set_frames_rendered(stats.frames_rendered);
  out->set_keep_alives_at_rest(stats.keep_alives_at_rest);
  for (const SceneId& id : stats.scene_ids) out->add_scene_ids(id);
  out->set_version(std::string(version));
  out->set_uptime_s(process.uptime_s);
  out->set_rss_bytes(process.rss_bytes);
  out->set_peak_rss_bytes(process.peak_rss_bytes);
  out->set_cpu_seconds(process.cpu_seconds);
  for (const SessionStatus& s : stats.session_status) {
    pb::SessionStatus* session = out->add_session_status();
    session->set_session_id(s.id);
    session->set_scene_id(s.scene);
    session->set_solver(s.solver);
    session->set_width(s.width);
    session->set_height(s.height);
    session->set_frames(s.frames);
    session->set_fps(s.fps);
    session->set_dropped_frames(s.dropped_frames);
    session->set_pending_updates(s.pending_updates);
    session->set_last_update_seq(s.last_update_seq);
  }
  out->set_gl_object_bytes(stats.gl_object_bytes);
  out->set_gpu_memory_total_bytes(stats.gpu_memory_total_bytes);
  out->set_gpu_memory_available_bytes(stats.gpu_memory_available_bytes);
  out->set_memory_budget_used_bytes(stats.memory_used_bytes);
  out->set_memory_budget_limit_bytes(stats.memory_limit_bytes);
}

}  // namespace gistream::service
