// protobuf <-> domain translation: wire defaults and wire-form validation.
#include "service/translate.h"

#include <absl/strings/match.h>
#include <gtest/gtest.h>

namespace gistream::service {
namespace translate_test {

TEST(Translate, StatusCodesKeepTheirMeaning) {
  // absl and gRPC share google.rpc.Code numbering; the switch must agree.
  for (int code = 0; code <= 16; ++code) {
    EXPECT_EQ(static_cast<int>(ToGrpcCode(static_cast<absl::StatusCode>(code))), code);
  }
  EXPECT_EQ(ToGrpcCode(static_cast<absl::StatusCode>(99)), grpc::StatusCode::UNKNOWN);
  const grpc::Status s = ToGrpcStatus(absl::NotFoundError("scene_id: no scene 'x'"));
  EXPECT_EQ(s.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(s.error_message(), "scene_id: no scene 'x'");
  EXPECT_TRUE(ToGrpcStatus(absl::OkStatus()).ok());
}

TEST(Translate, ZeroQuatIsIdentityAndOthersKeepOrder) {
  const glm::quat id = FromProto(pb::Quat());
  EXPECT_EQ(id, glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
  pb::Quat q;
  q.set_x(0.1f);
  q.set_y(0.2f);
  q.set_z(0.3f);
  q.set_w(0.9f);
  const glm::quat g = FromProto(q);
  EXPECT_FLOAT_EQ(g.x, 0.1f);
  EXPECT_FLOAT_EQ(g.y, 0.2f);
  EXPECT_FLOAT_EQ(g.z, 0.3f);
  EXPECT_FLOAT_EQ(g.w, 0.9f);
  pb::Quat back;
  ToProto(g, &back);
  EXPECT_FLOAT_EQ(back.w(), 0.9f);
}

TEST(Translate, NodeTransformDefaultsAndMatrix) {
  pb::Update u;
  u.set_seq(7);
  u.mutable_node_transform()->set_node(2);
  absl::StatusOr<Update> out = UpdateFromProto(u, "update");
  ASSERT_TRUE(out.ok()) << out.status();
  EXPECT_EQ(out->seq, 7u);
  const auto& t = std::get<NodeTransformUpdate>(out->change);
  EXPECT_EQ(t.node, 2u);
  EXPECT_EQ(t.scale, glm::vec3(1.0f));  // unset scale
  EXPECT_EQ(t.rotation, glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
  EXPECT_FALSE(t.matrix.has_value());

  for (int i = 0; i < 16; ++i) u.mutable_node_transform()->add_matrix(static_cast<float>(i));
  out = UpdateFromProto(u, "update");
  ASSERT_TRUE(out.ok()) << out.status();
  const auto& m = std::get<NodeTransformUpdate>(out->change).matrix;
  ASSERT_TRUE(m.has_value());
  EXPECT_EQ((*m)[3][0], 12.0f);  // column major: column 3 holds elements 12..15
}

TEST(Translate, MatrixOfWrongLengthNamesTheField) {
  pb::Update u;
  for (int i = 0; i < 5; ++i) u.mutable_node_transform()->add_matrix(1.0f);
  const absl::StatusOr<Update> out = UpdateFromProto(u, "update");
  ASSERT_FALSE(out.ok());
  EXPECT_EQ(out.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(out.status().message(), "update.node_transform.matrix: expected 16 floats, got 5");
}

TEST(Translate, BaseColorTakesThreeOrFourFloats) {
  pb::Update u;
  pb::MaterialChange* m = u.mutable_material();
  m->add_base_color(0.1f);
  m->add_base_color(0.2f);
  m->add_base_color(0.3f);
  absl::StatusOr<Update> out = UpdateFromProto(u, "update");
  ASSERT_TRUE(out.ok());
  EXPECT_EQ(*std::get<MaterialUpdate>(out->change).base_color, glm::vec4(0.1f, 0.2f, 0.3f, 1.0f));
  m->add_base_color(0.5f);
  out = UpdateFromProto(u, "update");
  ASSERT_TRUE(out.ok());
  EXPECT_EQ(std::get<MaterialUpdate>(out->change).base_color->w, 0.5f);
  m->add_base_color(0.5f);
  out = UpdateFromProto(u, "update");
  ASSERT_FALSE(out.ok());
  EXPECT_EQ(out.status().message(), "update.material.base_color: expected 3 or 4 floats, got 5");
}

TEST(Translate, UpdateWithoutChangeIsInvalid) {
  pb::Update u;
  u.set_seq(3);
  const absl::StatusOr<Update> out = UpdateFromProto(u, "update");
  ASSERT_FALSE(out.ok());
  EXPECT_EQ(out.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_TRUE(absl::StartsWith(out.status().message(), "update.change: no change set (seq 3)"))
      << out.status();
}

TEST(Translate, LightChangeKeepsOnlyWhatIsSet) {
  pb::Update u;
  u.mutable_light()->set_light(0);
  u.mutable_light()->set_intensity(5.0f);
  const absl::StatusOr<Update> out = UpdateFromProto(u, "update");
  ASSERT_TRUE(out.ok());
  const auto& l = std::get<LightUpdate>(out->change);
  EXPECT_EQ(l.intensity, 5.0f);
  EXPECT_FALSE(l.color.has_value());
  EXPECT_FALSE(l.position.has_value());
}

TEST(Translate, CameraWidthWithoutHeightIsInvalid) {
  pb::CameraChange c;
  c.set_width(64);
  absl::StatusOr<CameraUpdate> out = CameraFromProto(c, "update.camera");
  ASSERT_FALSE(out.ok());
  EXPECT_TRUE(absl::StartsWith(out.status().message(),
                               "update.camera.width: set without update.camera.height"))
      << out.status();
  c.set_height(32);
  out = CameraFromProto(c, "update.camera");
  ASSERT_TRUE(out.ok());
  EXPECT_EQ(out->width, 64u);
  EXPECT_EQ(out->height, 32u);
}

TEST(Translate, LookAtWithZeroUpUsesPlusY) {
  pb::CameraChange c;
  c.mutable_look_at()->mutable_eye()->set_z(5.0f);
  const absl::StatusOr<CameraUpdate> out = CameraFromProto(c, "camera");
  ASSERT_TRUE(out.ok());
  ASSERT_TRUE(out->look_at.has_value());
  EXPECT_EQ(out->look_at->up, glm::vec3(0.0f, 1.0f, 0.0f));
  EXPECT_EQ(out->look_at->eye, glm::vec3(0.0f, 0.0f, 5.0f));
  EXPECT_FALSE(out->pose.has_value());
  EXPECT_FALSE(out->yfov_degrees.has_value());
}

TEST(Translate, SessionConfigDefaults) {
  pb::SessionConfig c;
  c.set_scene_id("s");
  const absl::StatusOr<SessionConfig> out = SessionConfigFromProto(c);
  ASSERT_TRUE(out.ok()) << out.status();
  EXPECT_EQ(out->solver, "direct");
  EXPECT_EQ(out->encoding.quality, 90);
  EXPECT_EQ(out->encoding.format, ImageFormat::kJpeg);
  EXPECT_EQ(out->width, SessionConfig().width);
  EXPECT_EQ(out->height, SessionConfig().height);
  EXPECT_EQ(out->pacing, Pacing::kContinuous);
  EXPECT_EQ(out->max_fps, 0.0f);
  EXPECT_FALSE(out->camera.has_value());
}

TEST(Translate, SessionConfigExplicitValues) {
  pb::SessionConfig c;
  c.set_scene_id("s");
  c.set_solver("sh_probes");
  (*c.mutable_params())["grid"] = "4";
  c.set_width(64);
  c.set_height(48);
  c.mutable_encoding()->set_format(pb::IMAGE_FORMAT_EXR);
  c.mutable_encoding()->set_quality(50);
  c.mutable_on_request();
  c.mutable_camera()->set_scene_camera(1);
  const absl::StatusOr<SessionConfig> out = SessionConfigFromProto(c);
  ASSERT_TRUE(out.ok()) << out.status();
  EXPECT_EQ(out->solver, "sh_probes");
  EXPECT_EQ(out->params.at("grid"), "4");
  EXPECT_EQ(out->width, 64u);
  EXPECT_EQ(out->height, 48u);
  EXPECT_EQ(out->encoding.format, ImageFormat::kExr);
  EXPECT_EQ(out->encoding.quality, 50);
  EXPECT_EQ(out->pacing, Pacing::kOnRequest);
  ASSERT_TRUE(out->camera.has_value());
  EXPECT_EQ(out->camera->scene_camera, 1u);
}

TEST(Translate, SessionConfigHalfAResolutionIsInvalid) {
  pb::SessionConfig c;
  c.set_height(48);
  const absl::StatusOr<SessionConfig> out = SessionConfigFromProto(c);
  ASSERT_FALSE(out.ok());
  EXPECT_TRUE(absl::StartsWith(out.status().message(), "config.height: set without config.width"))
      << out.status();
}

TEST(Translate, EncodingRejectsUnknownFormatAndQualityAbove100) {
  pb::Encoding e;
  e.set_format(static_cast<pb::ImageFormat>(9));
  EXPECT_EQ(EncodingFromProto(e, "encoding").status().code(), absl::StatusCode::kInvalidArgument);
  e.set_format(pb::IMAGE_FORMAT_PNG);
  e.set_quality(101);
  const auto out = EncodingFromProto(e, "encoding");
  ASSERT_FALSE(out.ok());
  EXPECT_TRUE(absl::StartsWith(out.status().message(), "encoding.quality")) << out.status();
}

TEST(Translate, RenderRequestNamesTheBadUpdate) {
  pb::RenderRequest r;
  r.set_scene_id("s");
  r.add_updates()->mutable_environment()->set_intensity(2.0f);
  r.add_updates()->mutable_node_transform()->add_matrix(1.0f);
  const absl::StatusOr<RenderRequest> out = RenderRequestFromProto(r);
  ASSERT_FALSE(out.ok());
  EXPECT_EQ(out.status().message(), "updates[1].node_transform.matrix: expected 16 floats, got 1");
}

TEST(Translate, RefineSamplesReachTheEngine) {
  pb::RenderRequest r;
  r.set_scene_id("s");
  r.set_refine_samples(7);
  const absl::StatusOr<RenderRequest> render = RenderRequestFromProto(r);
  ASSERT_TRUE(render.ok()) << render.status();
  EXPECT_EQ(render->refine_samples, 7u);
  pb::SessionConfig c;
  c.set_scene_id("s");
  c.set_refine_samples(3);
  const absl::StatusOr<SessionConfig> session = SessionConfigFromProto(c);
  ASSERT_TRUE(session.ok()) << session.status();
  EXPECT_EQ(session->refine_samples, 3u);
}

TEST(Translate, SceneSourceNeedsASource) {
  pb::LoadSceneRequest r;
  EXPECT_EQ(SceneSourceFromProto(r).status().code(), absl::StatusCode::kInvalidArgument);
  r.set_name("cornell_box");
  const absl::StatusOr<SceneSource> out = SceneSourceFromProto(r);
  ASSERT_TRUE(out.ok());
  EXPECT_EQ(out->name, "cornell_box");
  EXPECT_EQ(out->environment_intensity, 1.0f);  // 0 on the wire
}

TEST(Translate, FrameToProtoCopiesEverything) {
  EncodedFrame f;
  f.frame_number = 4;
  f.width = 8;
  f.height = 2;
  f.format = ImageFormat::kPng;
  f.image = "abc";
  f.scene_version = 9;
  f.last_update_seq = 11;
  f.timings = {{"shade", 1.0, 2.0, false, false}, {"encode", 0.5, 0.0, true, true}};
  f.stats = {{"vpls", 256.0}};
  f.solver = "direct";
  f.total_ms = 3.5;
  f.dropped_frames = 2;
  pb::Frame p;
  FrameToProto(f, &p);
  EXPECT_EQ(p.frame_number(), 4u);
  EXPECT_EQ(p.width(), 8u);
  EXPECT_EQ(p.height(), 2u);
  EXPECT_EQ(p.format(), pb::IMAGE_FORMAT_PNG);
  EXPECT_EQ(p.image(), "abc");
  EXPECT_EQ(p.scene_version(), 9u);
  EXPECT_EQ(p.last_update_seq(), 11u);
  ASSERT_EQ(p.timings_size(), 2);
  EXPECT_EQ(p.timings(1).name(), "encode");
  EXPECT_TRUE(p.timings(1).skipped());
  EXPECT_TRUE(p.timings(1).cpu_stage());
  EXPECT_EQ(p.stats().at("vpls"), 256.0);
  EXPECT_EQ(p.solver(), "direct");
  EXPECT_EQ(p.total_ms(), 3.5);
  EXPECT_EQ(p.dropped_frames(), 2u);
}

TEST(Translate, UpdateRejectedCarriesTheGrpcCode) {
  pb::UpdateRejected r;
  UpdateRejectedToProto(5, absl::NotFoundError("update.node_transform.node: no node 9"), &r);
  EXPECT_EQ(r.seq(), 5u);
  EXPECT_EQ(r.code(), static_cast<int>(grpc::StatusCode::NOT_FOUND));
  EXPECT_EQ(r.message(), "update.node_transform.node: no node 9");
}

}  // namespace translate_test
}  // namespace gistream::service
