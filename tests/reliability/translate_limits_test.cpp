// Issue 13, finding 3 ("accepted silently: a zero quaternion") and finding
// 7 (0x0 sizes, long names echoed), at the gRPC boundary: protobuf
// messages are translated, then validated by the engine, which names the
// field; status messages sent back are bounded.
#include <gtest/gtest.h>

#include "reliability/reliability_fixture.h"
#include "service/translate.h"

namespace gistream::reliability {
namespace translate_limits_test {

namespace pb = ::gistream::v1;
using service::SessionConfigFromProto;
using service::UpdateFromProto;

TEST(TranslateLimits, ExplicitZeroRotationIsRejectedUnsetIsIdentity) {
  const QuadCopy scene;
  pb::Update zero;
  zero.set_seq(1);
  zero.mutable_node_transform()->mutable_rotation();  // set, all zeros
  absl::StatusOr<Update> update = UpdateFromProto(zero, "update");
  ASSERT_TRUE(update.ok()) << update.status();
  EXPECT_STATUS(StatusOf(E().Render(Request(scene.id(), "direct", {*update}))), kInvalidArgument,
                "update.node_transform.rotation: zero-length quaternion");

  pb::Update pose;
  pose.set_seq(2);
  pose.mutable_camera()->mutable_pose()->mutable_position()->set_z(3.0f);
  pose.mutable_camera()->mutable_pose()->mutable_rotation()->set_w(2.0f);
  update = UpdateFromProto(pose, "update");
  ASSERT_TRUE(update.ok()) << update.status();
  EXPECT_STATUS(StatusOf(E().Render(Request(scene.id(), "direct", {*update}))), kInvalidArgument,
                "update.camera.pose.rotation: length 2 is not 1");

  // Unset: identity, as the proto says; the frame renders.
  pb::Update unset;
  unset.set_seq(3);
  unset.mutable_node_transform()->set_node(0);
  update = UpdateFromProto(unset, "update");
  ASSERT_TRUE(update.ok()) << update.status();
  EXPECT_EQ(std::get<NodeTransformUpdate>(update->change).rotation,
            glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
  ASSERT_TRUE(E().Render(Request(scene.id(), "direct", {*update})).ok());
  ExpectRendersFinite(scene.id(), "direct");
}

TEST(TranslateLimits, ZeroSizeMeansTheDocumentedDefaultOnlyWhenBothAreZero) {
  pb::SessionConfig config;
  config.set_scene_id("s");
  absl::StatusOr<SessionConfig> out = SessionConfigFromProto(config);
  ASSERT_TRUE(out.ok()) << out.status();
  EXPECT_EQ(out->width, 640u);  // proto: both 0 (unset) means 640 x 480
  EXPECT_EQ(out->height, 480u);
  config.set_height(5);
  EXPECT_STATUS(StatusOf(SessionConfigFromProto(config)), kInvalidArgument,
                "config.height: set without config.width");
}

TEST(TranslateLimits, StatusMessagesSentToClientsAreBounded) {
  const absl::Status huge = absl::InvalidArgumentError(std::string(100000, 'x'));
  const grpc::Status sent = service::ToGrpcStatus(huge);
  EXPECT_EQ(sent.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_LE(sent.error_message().size(), 4096u + 32u);
  EXPECT_NE(sent.error_message().find("\u2026 (100000 bytes)"), std::string::npos);
  pb::UpdateRejected rejected;
  service::UpdateRejectedToProto(7, huge, &rejected);
  EXPECT_LE(rejected.message().size(), 4096u + 32u);
  // Ordinary messages pass unchanged.
  EXPECT_EQ(service::ToGrpcStatus(absl::NotFoundError("scene_id: no scene 'x'")).error_message(),
            "scene_id: no scene 'x'");
}

}  // namespace translate_limits_test
}  // namespace gistream::reliability
