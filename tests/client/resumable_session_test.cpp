// What a moving session keeps (client/resumable_session.h): the update
// log's compaction key and which ended calls it resumes. The moves
// themselves run in the fleet test (tests/deploy/fleet_test.py: three
// gistreamd behind HAProxy, drained and killed).
#include "resumable_session.h"

#include <gtest/gtest.h>

namespace gistream::client {
namespace resumable_session_test {

v1::Update Translate(uint32_t node, float x) {
  v1::Update update;
  update.mutable_node_transform()->set_node(node);
  update.mutable_node_transform()->mutable_translation()->set_x(x);
  return update;
}

TEST(ResumableSession, UpdatesOfOneTargetAndFieldsShareAKey) {
  EXPECT_EQ(UpdateTargetKey(Translate(3, 1.0f)), UpdateTargetKey(Translate(3, 2.0f)));
  EXPECT_NE(UpdateTargetKey(Translate(3, 1.0f)), UpdateTargetKey(Translate(4, 1.0f)));
  // Node 0 (proto3 leaves the default out) is a target of its own too.
  EXPECT_NE(UpdateTargetKey(Translate(0, 1.0f)), UpdateTargetKey(Translate(1, 1.0f)));
  // More fields set: not made redundant by one that sets fewer.
  v1::Update moved_and_turned = Translate(3, 1.0f);
  moved_and_turned.mutable_node_transform()->mutable_rotation()->set_w(1.0f);
  EXPECT_NE(UpdateTargetKey(moved_and_turned), UpdateTargetKey(Translate(3, 1.0f)));

  v1::Update dim, tint;
  dim.mutable_light()->set_light(2);
  dim.mutable_light()->set_intensity(0.5f);
  tint.mutable_light()->set_light(2);
  tint.mutable_light()->mutable_color()->set_x(1.0f);
  EXPECT_NE(UpdateTargetKey(dim), UpdateTargetKey(tint));
  v1::Update dimmer = dim;
  dimmer.mutable_light()->set_intensity(0.25f);
  EXPECT_EQ(UpdateTargetKey(dim), UpdateTargetKey(dimmer));
  EXPECT_NE(UpdateTargetKey(dim), UpdateTargetKey(Translate(2, 1.0f)));
}

TEST(ResumableSession, AnimationPlaybackIsNeverCompacted) {
  v1::Update play;
  play.mutable_animation();
  EXPECT_EQ(UpdateTargetKey(play), "");
  EXPECT_EQ(UpdateTargetKey(v1::Update()), "");
}

TEST(ResumableSession, OnlyAServerGoneAwayIsResumed) {
  EXPECT_TRUE(ResumableStatus(absl::UnavailableError("connection refused")));
  EXPECT_TRUE(ResumableStatus(absl::CancelledError("server shutting down")));
  EXPECT_TRUE(ResumableStatus(absl::InternalError("RST_STREAM")));
  EXPECT_TRUE(ResumableStatus(absl::UnknownError("No status received")));
  EXPECT_FALSE(ResumableStatus(absl::OkStatus()));
  EXPECT_FALSE(ResumableStatus(absl::InvalidArgumentError("params.spp")));
  EXPECT_FALSE(ResumableStatus(absl::NotFoundError("scene_id")));
  EXPECT_FALSE(ResumableStatus(absl::ResourceExhaustedError("max sessions")));
  EXPECT_FALSE(ResumableStatus(absl::PermissionDeniedError("tenant")));
}

}  // namespace resumable_session_test
}  // namespace gistream::client
