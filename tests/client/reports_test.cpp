// What `solvers` and `render` print (client/solver_list.h,
// client/frame_report.h).
#include <string>

#include <gtest/gtest.h>

#include "frame_report.h"
#include "session_common.h"
#include "solver_list.h"

namespace gistream::client {
namespace reports_test {

TEST(SolverList, StagesAndParameterTable) {
  v1::ListSolversResponse response;
  v1::SolverInfo* solver = response.add_solvers();
  solver->set_name("direct");
  solver->set_description("Direct light only.");
  solver->add_stages("shadow_maps");
  solver->add_stages("shade");
  v1::ParamSpec* samples = solver->add_params();
  samples->set_name("area_samples");
  samples->set_type(v1::PARAM_TYPE_INT);
  samples->set_default_value("16");
  samples->set_min(1);
  samples->set_max(1024);
  samples->set_description("Samples per area light");
  v1::ParamSpec* filter = solver->add_params();
  filter->set_name("filter");
  filter->set_type(v1::PARAM_TYPE_ENUM);
  filter->set_default_value("box");
  filter->add_choices("box");
  filter->add_choices("tent");
  filter->set_description("Shadow filter");
  response.add_solvers()->set_name("pathtrace");

  EXPECT_EQ(FormatSolverList(response),
            "direct - Direct light only.\n"
            "  stages: shadow_maps, shade\n"
            "  parameters:\n"
            "    name         | type | default | range     | meaning\n"
            "    -------------+------+---------+-----------+-----------------------\n"
            "    area_samples | int  | 16      | [1, 1024] | Samples per area light\n"
            "    filter       | enum | box     | box|tent  | Shadow filter\n"
            "\n"
            "pathtrace\n"
            "  stages: none\n"
            "  parameters: none\n");
  EXPECT_EQ(FormatSolverList({}), "the server offers no solvers\n");
}

TEST(SolverList, FloatAndBoolRanges) {
  v1::ParamSpec param;
  param.set_type(v1::PARAM_TYPE_FLOAT);
  param.set_min(0.001);
  param.set_max(0.5);
  EXPECT_EQ(FormatParamRange(param), "[0.001, 0.5]");
  param.set_type(v1::PARAM_TYPE_BOOL);
  EXPECT_EQ(FormatParamRange(param), "true|false");
}

TEST(FrameReport, SummaryLineAndStages) {
  v1::Frame frame;
  frame.set_width(64);
  frame.set_height(48);
  frame.set_format(v1::IMAGE_FORMAT_PNG);
  frame.set_image(std::string(2048, 'x'));
  frame.set_solver("avg");
  frame.set_frame_number(3);
  frame.set_scene_version(2);
  frame.set_total_ms(12.345);
  v1::StageTiming* voxelize = frame.add_timings();
  voxelize->set_name("voxelize");
  voxelize->set_skipped(true);
  v1::StageTiming* trace = frame.add_timings();
  trace->set_name("trace_vpls");
  trace->set_cpu_ms(0.5);
  trace->set_gpu_ms(3.25);
  (*frame.mutable_stats())["vpls"] = 256;
  EXPECT_EQ(FormatFrameReport(frame, "out.png"),
            "wrote out.png: 64x48 png, 2.0 KiB, solver avg, frame 3, scene version 2, 12.35 ms\n"
            "  stage      |  CPU ms |  GPU ms\n"
            "  -----------+---------+--------\n"
            "  voxelize   | skipped | skipped\n"
            "  trace_vpls |    0.50 |    3.25\n"
            "  stats: vpls=256\n");
}

TEST(FrameReport, ConvergenceOfTheLastPicture) {
  // A frame of a camera move: one sample of 16, the picture before the
  // move reprojected, the GI still solving.
  v1::Frame moving;
  auto& stats = *moving.mutable_stats();
  stats["refine_target"] = 16;
  stats["refine_samples"] = 1;
  stats["refine_reproject"] = 4;
  stats["update_complete"] = 0;
  stats["ms_since_camera_change"] = 0;
  stats["ms_since_scene_change"] = 3200;
  EXPECT_EQ(FormatConvergence(moving),
            "last picture: refined 1/16 samples per pixel, last picture reprojected, GI still "
            "solving; 0.0 s since the camera moved, 3.2 s since the scene changed");
  // At rest: complete, nothing carried or reprojected; no refinement line
  // for a session that does not refine (target 1).
  v1::Frame still;
  (*still.mutable_stats())["refine_target"] = 1;
  (*still.mutable_stats())["update_complete"] = 1;
  (*still.mutable_stats())["at_rest"] = 1;
  EXPECT_EQ(FormatConvergence(still), "last picture: GI complete, at rest");
}

TEST(FrameReport, Bytes) {
  EXPECT_EQ(FormatBytes(512), "512 B");
  EXPECT_EQ(FormatBytes(1536), "1.5 KiB");
  EXPECT_EQ(FormatBytes(3 * 1024 * 1024), "3.0 MiB");
}

}  // namespace reports_test
}  // namespace gistream::client
