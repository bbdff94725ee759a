// A double-sided lamp a centimetre under a ceiling, in a closed room
// (issue 29, item 3): the GI solvers must light the room as the reference
// does. The lamp's back face lights the ceiling above it a centimetre
// away, very brightly; physically most of that light stays in the gap
// (ceiling and lamp back reflect it to each other) and what escapes at the
// edges adds to the room. A solver that lets the bright ceiling above the
// lamp shine through the lamp over-lights the room. Before the fixes:
// antiradiance 1.66x the reference here (its leaves gathered, reflected
// and blocked over their front hemisphere only, the paper's solid
// objects; now a doubleSided sheet has mirrored back-face leaves,
// antiradiance/patches.h), avg 1.23x (lamp and ceiling shared one voxel
// sheet, so rays from VPLs in the gap passed through the lamp; now two
// sheets, avg/voxel_grid.cpp).
//
// The room: a closed 1 m cube of albedo 0.7 (grey, facing in), a 30 cm x
// 30 cm double-sided lamp (emission 1, base colour 0.78, as exporters
// write lamps) 1 cm under the ceiling's centre. A camera 30 cm above the
// floor's centre looks straight down (yfov 90 degrees: the floor's middle
// 60 cm); the mean of that view is held to pathtrace's (all bounces).
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/gltf_builder.h"
#include "support/measurement.h"
#include "support/registered_solvers.h"
#include "support/render_helpers.h"

namespace gistream {
namespace near_field_room_test {

using testing::GltfBuilder;

constexpr float kGap = 0.01f;
constexpr uint32_t kSize = 16;

// kWalls x kWalls quads per wall, kLamp x kLamp on the lamp.
template <int kWalls, int kLamp>
class NearFieldRoomOf : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    GltfBuilder b;
    const int lamp = b.AddMaterial("lamp", {0.78f, 0.78f, 0.78f}, {1, 1, 1});
    b.SetDoubleSided(lamp);
    const int grey = b.AddMaterial("grey", {0.7f, 0.7f, 0.7f});
    // Faces cross(u, v), all towards the inside.
    b.AddQuad("floor", {0, -0.5f, 0}, {0, 0, 0.5f}, {0.5f, 0, 0}, grey, kWalls);
    b.AddQuad("ceiling", {0, 0.5f, 0}, {0.5f, 0, 0}, {0, 0, 0.5f}, grey, kWalls);
    b.AddQuad("left", {-0.5f, 0, 0}, {0, 0.5f, 0}, {0, 0, 0.5f}, grey, kWalls);
    b.AddQuad("right", {0.5f, 0, 0}, {0, 0, 0.5f}, {0, 0.5f, 0}, grey, kWalls);
    b.AddQuad("back", {0, 0, -0.5f}, {0.5f, 0, 0}, {0, 0.5f, 0}, grey, kWalls);
    b.AddQuad("front", {0, 0, 0.5f}, {0, 0.5f, 0}, {0.5f, 0, 0}, grey, kWalls);
    b.AddQuad("lamp", {0, 0.5f - kGap, 0}, {0.15f, 0, 0}, {0, 0, 0.15f}, lamp, kLamp);  // faces -Y
    b.AddCamera("camera", {0, -0.2f, 0}, {0, -1, 0}, {0, 0, 1}, 1.5708f);
    auto info = testing::SharedEngine().LoadScene(testing::SceneFromBytes(b.ToJson()));
    ASSERT_TRUE(info.ok()) << info.status();
    scene_ = new std::string(info->id);
    // 16 x 16 pixels x 1024 spp: the floor's mean to well under 1 %.
    reference_ = Floor("pathtrace", {{"spp", "1024"}});
    testing::RecordMeasurement("pathtrace", reference_);
  }
  static void TearDownTestSuite() {
    if (scene_) (void)testing::SharedEngine().UnloadScene(*scene_);
    delete scene_;
    scene_ = nullptr;
  }

  // Mean green radiance of the floor's middle, seen from above.
  static double Floor(const std::string& solver, const std::map<std::string, std::string>& params) {
    return testing::MeanGreenFrom(*scene_, solver, params, {0.0f, -0.2f, 0.0f}, {0.0f, -1.0f, 0.0f},
                                  {0.0f, 0.0f, 1.0f}, 90.0f, kSize);
  }

  // The floor at `solver`'s defaults within 10 % of the reference.
  static void ExpectFloorNearTheReference(const std::string& solver) {
    const double got = Floor(solver, {});
    testing::RecordMeasurement(solver, got);
    testing::RecordMeasurement("ratio", got / reference_);
    EXPECT_NEAR(got, reference_, 0.10 * reference_) << solver << ": " << got / reference_ << "x";
  }

  static std::string* scene_;
  static double reference_;
};
template <int kWalls, int kLamp>
std::string* NearFieldRoomOf<kWalls, kLamp>::scene_ = nullptr;
template <int kWalls, int kLamp>
double NearFieldRoomOf<kWalls, kLamp>::reference_ = 0.0;

// Coarse: leaves 6-15 times the gap.
class NearFieldRoomGi : public NearFieldRoomOf<8, 2>,
                        public ::testing::WithParamInterface<const char*> {};
// Finely tessellated: the lamp's quads 1.9 cm, the walls' 4.2 cm.
class NearFieldFineRoomGi : public NearFieldRoomOf<24, 16>,
                            public ::testing::WithParamInterface<const char*> {};

// At each solver's defaults. The floor's light is about half direct
// (exact in every solver: `direct`'s area samples, the same shadow maps)
// and half indirect; the solvers' indirect light in this room is within
// 10 % of the reference without the lamp's gap (their usual
// discretization error), so 10 % of the total is a wide bound for it and
// far below the +23 % and +66 % of light through the lamp. Measured:
// sh_probes 0.97x, avg 0.99x, implicit_visibility 1.05x, antiradiance
// 0.99x (with its near links per piece alone 1.21x: its elements are
// refined near double-sided emitters, antiradiance/near_field.h).
TEST_P(NearFieldRoomGi, FloorMatchesTheReferenceAtTheDefaults) {
  ExpectFloorNearTheReference(GetParam());
}

// The same room finely tessellated, where antiradiance's near links used
// to put a ceiling leaf's light into the one bin towards its centre
// (1.26x the reference; each now a link per piece of the sender's cell,
// antiradiance/links.cpp). Measured: sh_probes 0.98x, avg 1.01x,
// implicit_visibility 1.02x, antiradiance 0.95x.
TEST_P(NearFieldFineRoomGi, FloorMatchesTheReferenceAtTheDefaults) {
  ExpectFloorNearTheReference(GetParam());
}

const std::vector<const char*> kNearFieldSolvers = {"sh_probes", "avg", "implicit_visibility",
                                                    "antiradiance"};

INSTANTIATE_TEST_SUITE_P(Solvers, NearFieldRoomGi, ::testing::ValuesIn(kNearFieldSolvers));
INSTANTIATE_TEST_SUITE_P(Solvers, NearFieldFineRoomGi, ::testing::ValuesIn(kNearFieldSolvers));

TEST(NearFieldRoomGi, CoversEveryRegisteredSolver) {
  testing::ExpectCoversEveryRegisteredSolver(
      {kNearFieldSolvers.begin(), kNearFieldSolvers.end()},
      {{"direct", "no indirect light: the room's floor is half indirect"},
       {"pathtrace", "the reference (its near field: NearFieldEmitter)"}});
}

}  // namespace near_field_room_test
}  // namespace gistream
