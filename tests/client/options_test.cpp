// Command-line parsing (client/options.h): the contract scripts and
// benchmarks depend on.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "connection.h"
#include "options.h"

namespace gistream::client {
namespace options_test {

absl::StatusOr<CommandLine> Parse(std::vector<std::string> args) {
  return ParseCommandLine(args, kDefaultServer);
}

std::string UsageError(std::vector<std::string> args) {
  auto line = Parse(std::move(args));
  EXPECT_FALSE(line.ok());
  return line.ok() ? "" : std::string(line.status().message());
}

TEST(CommandLine, RenderWithEverything) {
  auto line = Parse({"--server",
                     "10.0.0.1:1234",
                     "render",
                     "--scene",
                     "cornell_box",
                     "--solver",
                     "sh_probes",
                     "--param",
                     "probes=8",
                     "--param=order=3",
                     "--size",
                     "64x48",
                     "--format",
                     "exr",
                     "--out",
                     "x.bin",
                     "--exposure",
                     "-1",
                     "--quality",
                     "95",
                     "--camera-eye",
                     "0,1,2",
                     "--camera-target",
                     "0.5, 0.5, 0.5",
                     "--yfov",
                     "40",
                     "--refine-samples",
                     "4"});
  ASSERT_TRUE(line.ok()) << line.status();
  EXPECT_EQ(line->connection.server, "10.0.0.1:1234");
  ASSERT_EQ(line->command, Command::kRender);
  const auto& render = std::get<RenderOptions>(line->options);
  EXPECT_EQ(render.scene.scene, "cornell_box");
  EXPECT_EQ(render.solver.solver, "sh_probes");
  EXPECT_EQ(render.solver.params.at("probes"), "8");
  EXPECT_EQ(render.solver.params.at("order"), "3");
  EXPECT_EQ(render.view.width, 64u);
  EXPECT_EQ(render.view.height, 48u);
  EXPECT_EQ(render.view.encoding.format(), v1::IMAGE_FORMAT_EXR);
  EXPECT_FLOAT_EQ(render.view.encoding.exposure(), -1.0f);
  EXPECT_EQ(render.view.encoding.quality(), 95u);
  EXPECT_EQ(render.out, "x.bin");
  ASSERT_TRUE(render.view.camera.has_look_at());
  EXPECT_FLOAT_EQ(render.view.camera.look_at().eye().z(), 2.0f);
  EXPECT_FLOAT_EQ(render.view.camera.look_at().target().x(), 0.5f);
  EXPECT_FLOAT_EQ(render.view.camera.look_at().up().y(), 1.0f);
  EXPECT_FLOAT_EQ(render.view.camera.yfov_degrees(), 40.0f);
  EXPECT_EQ(render.view.refine_samples, 4u);
}

TEST(CommandLine, RefineSamplesAreBounded) {
  EXPECT_EQ(UsageError({"render", "--scene", "a", "--out", "b", "--refine-samples", "0"})
                .find("--refine-samples"),
            0u);
  EXPECT_EQ(UsageError({"stream", "--refine-samples", "1025"}).find("--refine-samples"), 0u);
}

TEST(CommandLine, RenderFormatFromOutputExtension) {
  auto line = Parse({"render", "--scene", "a.glb", "--out", "shot.PNG"});
  ASSERT_TRUE(line.ok()) << line.status();
  const auto& render = std::get<RenderOptions>(line->options);
  EXPECT_EQ(render.view.encoding.format(), v1::IMAGE_FORMAT_PNG);
  EXPECT_EQ(render.solver.solver, "direct");
  EXPECT_FALSE(render.view.camera.has_look_at());
  EXPECT_EQ(line->connection.server, kDefaultServer);
}

TEST(CommandLine, StreamDefaults) {
  auto line = ParseCommandLine(std::vector<std::string>{"stream"}, "from-env:1");
  ASSERT_TRUE(line.ok()) << line.status();
  EXPECT_EQ(line->connection.server, "from-env:1");
  const auto& stream = std::get<StreamOptions>(line->options);
  EXPECT_EQ(stream.scene.scene, "cornell_box");
  EXPECT_EQ(stream.solver.solver, "direct");
  EXPECT_EQ(stream.view.width, 320u);
  EXPECT_EQ(stream.view.height, 240u);
  EXPECT_EQ(stream.view.encoding.format(), v1::IMAGE_FORMAT_JPEG);
  EXPECT_EQ(stream.frames, 30u);
  EXPECT_FLOAT_EQ(stream.fps, 30.0f);
  EXPECT_EQ(stream.out_dir, "out");
}

TEST(CommandLine, BenchKeepsFramesOnlyWhenAsked) {
  auto plain = Parse({"bench", "--format", "exr", "--reference-spp", "64"});
  ASSERT_TRUE(plain.ok()) << plain.status();
  EXPECT_EQ(std::get<BenchOptions>(plain->options).reference_spp, 64);
  EXPECT_FALSE(std::get<BenchOptions>(plain->options).keep_frames);
  auto kept = Parse({"bench", "--format", "exr", "--reference-spp", "64", "--keep-frames"});
  ASSERT_TRUE(kept.ok()) << kept.status();
  EXPECT_TRUE(std::get<BenchOptions>(kept->options).keep_frames);
}

TEST(CommandLine, ServerAfterTheCommandWins) {
  auto line =
      Parse({"--server", "a:1", "script", "timeline.json", "--server", "b:2", "--out", "frames"});
  ASSERT_TRUE(line.ok()) << line.status();
  EXPECT_EQ(line->connection.server, "b:2");
  const auto& script = std::get<ScriptOptions>(line->options);
  EXPECT_EQ(script.file, "timeline.json");
  EXPECT_EQ(script.out_dir, "frames");
}

TEST(CommandLine, StreamFramesZeroMeansUntilInterrupted) {
  auto line = Parse({"stream", "--frames", "0", "--fps", "60"});
  ASSERT_TRUE(line.ok()) << line.status();
  EXPECT_EQ(std::get<StreamOptions>(line->options).frames, 0u);
  EXPECT_FLOAT_EQ(std::get<StreamOptions>(line->options).fps, 60.0f);
}

TEST(CommandLine, Help) {
  for (auto args : std::vector<std::vector<std::string>>{{"--help"},
                                                         {"-h"},
                                                         {"help"},
                                                         {"render", "--help"},
                                                         {"help", "render"},
                                                         {"render", "--scene", "x", "-h"}}) {
    auto line = Parse(args);
    ASSERT_TRUE(line.ok()) << line.status();
    EXPECT_TRUE(line->help);
  }
  EXPECT_EQ(Parse({"render", "--help"})->command, Command::kRender);
  EXPECT_FALSE(Parse({"--help"})->command.has_value());
}

TEST(CommandLine, UsageErrors) {
  EXPECT_EQ(UsageError({}), "no command given");
  EXPECT_EQ(UsageError({"draw"}), "unknown command \"draw\"");
  EXPECT_EQ(UsageError({"-x", "solvers"}), "unknown option -x");
  EXPECT_EQ(UsageError({"render", "--out", "a.jpg"}), "--scene is required");
  EXPECT_EQ(UsageError({"render", "--scene", "a"}), "--out FILE is required");
  EXPECT_EQ(UsageError({"render", "--scene", "a", "--out", "b", "--sise", "1x1"}),
            "unknown option --sise");
  EXPECT_EQ(UsageError({"render", "--scene", "a", "--scene", "b", "--out", "c"}),
            "--scene given twice");
  EXPECT_EQ(UsageError({"render", "--scene", "a", "--out", "b", "--size", "320"}),
            "--size: \"320\" is not WIDTHxHEIGHT (e.g. 320x240)");
  EXPECT_EQ(UsageError({"render", "--scene", "a", "--out", "b", "--size", "0x10"}),
            "--size: 0x10 is out of range [1, 16384] per side");
  EXPECT_EQ(UsageError({"render", "--scene", "a", "--out", "b", "--format", "gif"}),
            "--format: unknown image format \"gif\" (expected jpeg, png, exr, h264, hevc or av1)");
  EXPECT_EQ(UsageError({"render", "--scene", "a", "--out", "b", "--param", "noequals"}),
            "--param: \"noequals\" is not key=value");
  EXPECT_EQ(
      UsageError({"render", "--scene", "a", "--out", "b", "--param", "k=1", "--param", "k=2"}),
      "--param k given twice");
  EXPECT_EQ(UsageError({"render", "--scene", "a", "--out", "b", "--camera-eye", "1,2,3"}),
            "--camera-eye and --camera-target go together");
  EXPECT_EQ(UsageError({"render", "--scene", "a", "--out", "b", "--camera-eye", "1,2",
                        "--camera-target", "0,0,0"}),
            "--camera-eye: \"1,2\" is not three numbers x,y,z");
  EXPECT_EQ(UsageError({"render", "--scene", "a", "--out", "b", "--quality", "0"}),
            "--quality: 0 is out of range [1, 100]");
  EXPECT_EQ(UsageError({"render", "--scene", "a", "--out", "b", "--exposure", "nan"}),
            "--exposure: \"nan\" is not a finite number");
  EXPECT_EQ(UsageError({"render", "--scene", "a", "--out", "b", "--yfov", "180"}),
            "--yfov: 180 degrees is out of range (0, 180)");
  EXPECT_EQ(UsageError({"stream", "--frames", "-1"}),
            "--frames: -1 is out of range [0, 9223372036854775807]");
  EXPECT_EQ(UsageError({"stream", "--fps"}), "--fps needs a value");
  EXPECT_EQ(UsageError({"script"}), "script FILE is required");
  EXPECT_EQ(UsageError({"script", "a.json", "b.json"}), "script takes exactly one FILE");
  EXPECT_EQ(UsageError({"solvers", "extra"}), "unexpected argument \"extra\"");
  EXPECT_EQ(UsageError({"solvers", "--json=yes"}), "--json takes no value");
  EXPECT_EQ(UsageError({"status", "--timeout", "0"}), "--timeout: must be positive seconds");
}

}  // namespace options_test
}  // namespace gistream::client

namespace gistream::client {
namespace options_test {

TEST(CommandLine, TlsAndTokenOptions) {
  const std::string ca = GISTREAM_SOURCE_DIR "/scripts/dev_certs.sh";  // any readable file
  auto line = Parse({"--tls", "--token", "t0ken-0123456789abcdef", "health", "--service",
                     "gistream.v1.Gistream"});
  ASSERT_TRUE(line.ok()) << line.status();
  EXPECT_TRUE(line->connection.tls);
  EXPECT_EQ(line->connection.token, "t0ken-0123456789abcdef");
  EXPECT_EQ(std::get<HealthOptions>(line->options).service, "gistream.v1.Gistream");
  auto with_ca = Parse({"status", "--ca", ca});
  ASSERT_TRUE(with_ca.ok()) << with_ca.status();
  EXPECT_TRUE(with_ca->connection.tls);  // implied by --ca
  EXPECT_FALSE(with_ca->connection.ca_pem.empty());
  EXPECT_NE(UsageError({"status", "--ca", "/nonexistent/ca.crt"}).find("--ca: cannot read"),
            std::string::npos);
  EXPECT_NE(UsageError({"status", "--cert", ca}).find("--cert and --key"), std::string::npos);
}

}  // namespace options_test
}  // namespace gistream::client

namespace gistream::client {
namespace options_test {

// gRPC's resource quota refuses a call unread with RST_STREAM code 11
// (ENHANCE_YOUR_CALM) and those words alone: the client names the cause
// and the server's flag, keeps the code and the mark of a server error.
TEST(TransportRefusal, IsExplainedNamingTheFlag) {
  const absl::Status status = FromGrpc(
      grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED, "Received RST_STREAM with error code 11"),
      "127.0.0.1:50051");
  EXPECT_EQ(status.code(), absl::StatusCode::kResourceExhausted);
  EXPECT_TRUE(IsRpcError(status));
  EXPECT_TRUE(IsTransportRefusal(status));
  EXPECT_NE(status.message().find("--max-transport-bytes"), std::string::npos) << status;
  EXPECT_NE(status.message().find("ENHANCE_YOUR_CALM"), std::string::npos) << status;
  EXPECT_NE(status.message().find("127.0.0.1:50051"), std::string::npos) << status;
  // The upload's field in front, the rest kept.
  const absl::Status named = WithPrefix(status, "gltf: the 8.0 MiB upload was not read: ");
  EXPECT_TRUE(IsRpcError(named));
  EXPECT_EQ(named.code(), absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(named.message().substr(0, 5), "gltf:");
  // Other RESOURCE_EXHAUSTED answers are left as the server wrote them.
  const absl::Status quota = FromGrpc(
      grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED, "scenes: the server holds 8 scenes"),
      "127.0.0.1:50051");
  EXPECT_EQ(quota.message(), "scenes: the server holds 8 scenes");
  EXPECT_FALSE(IsTransportRefusal(quota));
}

}  // namespace options_test
}  // namespace gistream::client
