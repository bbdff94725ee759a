// gistream script: a timeline played in a session paced on request, one
// saved frame per timeline step, with the update seq echo checked.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <iostream>
#include <map>

#include <absl/strings/str_cat.h>

#include "commands.h"
#include "connection.h"
#include "frame_report.h"
#include "frame_writer.h"
#include "interrupt.h"
#include "progress_line.h"
#include "resumable_session.h"
#include "scene_loader.h"
#include "script.h"
#include "session_common.h"
#include "session_stream.h"
#include "stats_table.h"
#include "timeline.h"
#include "util/log.h"

namespace gistream::client {
namespace {

using Clock = StatsCollector::Clock;

// How often a frame that does not include the last update yet is asked
// for again before the server is taken to ignore the update order.
constexpr int kMaxStaleFrames = 3;

// Checks the seq numbers frames echo and waits for the frame that includes
// every update sent so far.
class EchoChecker {
 public:
  // Called when a frame arrives. OK(true): the frame we wait for; OK(false):
  // an earlier frame, keep waiting; an error when the echo is out of order.
  absl::StatusOr<bool> Accept(const v1::Frame& frame, uint64_t last_sent) {
    const uint64_t seq = frame.last_update_seq();
    if (seq < last_echo_) {
      return absl::DataLossError(
          absl::StrCat("frame ", frame.frame_number(), " reports update seq ", seq,
                       " after a frame that reported ", last_echo_, ": updates out of order"));
    }
    if (seq > last_sent) {
      return absl::DataLossError(absl::StrCat("frame ", frame.frame_number(),
                                              " reports update seq ", seq,
                                              " but the client has sent only up to ", last_sent));
    }
    last_echo_ = seq;
    return seq == last_sent;
  }

 private:
  uint64_t last_echo_ = 0;
};

v1::SessionConfig MakeConfig(const Script& script, const std::string& scene_id) {
  v1::SessionConfig config;
  config.set_scene_id(scene_id);
  config.set_solver(script.solver);
  config.mutable_params()->insert(script.params.begin(), script.params.end());
  config.set_width(script.width);
  config.set_height(script.height);
  *config.mutable_encoding() = script.encoding;
  config.mutable_on_request();
  return config;
}

}  // namespace

absl::Status RunScript(const ConnectionOptions& connection_options, const ScriptOptions& options) {
  GS_ASSIGN_OR_RETURN(Script script, LoadScriptFile(options.file));
  SceneOptions scene_options{.scene = script.scene,
                             .environment = script.environment,
                             .environment_intensity = script.environment_intensity,
                             .keep_scene = options.keep_scene};
  // A scene or environment file in the script is relative to the script.
  GS_ASSIGN_OR_RETURN(v1::LoadSceneRequest load,
                      BuildLoadSceneRequest(scene_options, options.file.parent_path()));
  GS_ASSIGN_OR_RETURN(FrameWriter writer,
                      FrameWriter::Create(options.out_dir, script.encoding.format()));
  Connection connection(connection_options);
  ProgressLine progress;
  progress.Wait(absl::StrCat("loading scene ", script.scene));
  GS_ASSIGN_OR_RETURN(std::unique_ptr<LoadedScene> scene,
                      LoadedScene::Load(connection, load, options.keep_scene));
  progress.Done();
  std::cout << DescribeScene(script.scene, scene->info()) << std::endl;

  // Every name in the script is resolved before the session opens.
  auto timeline = Timeline::Build(script, scene->info());
  if (!timeline.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat(options.file.string(), ": ", timeline.status().message()));
  }

  ResumeOptions resume{.connection = connection_options,
                       .load = load,
                       .give_up_after_s = options.resume_for_s,
                       .group = nullptr};
  GS_ASSIGN_OR_RETURN(std::unique_ptr<ResumableSession> stream,
                      ResumableSession::Open(connection.stub(), MakeConfig(script, scene->id()),
                                             connection.server(), std::move(resume)));
  std::cout << FormatSessionOpened(stream->opened()) << std::endl;
  // Frame by frame, with a bar and an ETA from the frames so far.
  progress.Wait(absl::StrCat("frame 1/", timeline->frames()));

  std::atomic<bool> interrupted{false};
  ScopedInterruptHandler on_interrupt([&](int count) {
    if (count == 1) {
      std::cerr << "\ninterrupt: stopping after this frame (Ctrl-C again to cancel)" << std::endl;
      interrupted = true;
    } else {
      stream->Cancel();
    }
  });

  StatsCollector stats;
  EchoChecker echo;
  uint64_t seq = 0;
  int saved = 0;
  int outstanding = 0;      // frames requested and not yet received
  bool call_ended = false;  // the server ended the call early; EndSession says why
  for (int i = 0; i < timeline->frames() && !interrupted && !call_ended; ++i) {
    std::map<uint64_t, std::string> sent;  // this frame's updates, for rejections
    for (v1::Update& update : timeline->UpdatesForFrame(i)) {
      update.set_seq(++seq);
      sent[seq] = DescribeUpdate(update);
      if (!stream->SendUpdate(update)) call_ended = true;
    }
    const Clock::time_point requested = Clock::now();
    if (call_ended || !stream->RequestFrame(1)) {
      call_ended = true;
      break;
    }
    ++outstanding;

    int stale = 0;
    bool got_frame = false;
    v1::SessionEvent event;
    while (!got_frame && stream->Next(&event)) {
      if (event.has_rejected()) {
        const v1::UpdateRejected& rejected = event.rejected();
        auto it = sent.find(rejected.seq());
        return absl::InvalidArgumentError(absl::StrCat(
            "frame ", i, ": update seq ", rejected.seq(),
            it == sent.end() ? "" : absl::StrCat(" (", it->second, ")"),
            " rejected: ", absl::StatusCodeToString(static_cast<absl::StatusCode>(rejected.code())),
            ": ", rejected.message()));
      }
      if (!event.has_frame()) continue;
      const v1::Frame& frame = event.frame();
      outstanding = std::max(0, outstanding - 1);
      GS_ASSIGN_OR_RETURN(got_frame, echo.Accept(frame, seq));
      if (!got_frame) {
        // A frame rendered before our updates. Wait for the one we asked
        // for; when none is pending, ask again, a few times.
        LogOnce(LogLevel::kWarning, "script-stale-frame",
                absl::StrCat("frame ", i, ": got a frame with update seq ", frame.last_update_seq(),
                             ", waiting for ", seq));
        if (outstanding > 0) continue;
        if (++stale > kMaxStaleFrames) {
          return absl::DataLossError(absl::StrCat(
              "frame ", i, ": the server keeps sending frames without update seq ", seq));
        }
        if (!stream->RequestFrame(1)) break;
        ++outstanding;
        continue;
      }
      const Clock::time_point arrived = Clock::now();
      stats.Add(frame, arrived,
                std::chrono::duration<double, std::milli>(arrived - requested).count());
      GS_RETURN_IF_ERROR(writer.Write(static_cast<uint64_t>(i), frame));
      ++saved;
      progress.Update(
          absl::StrCat("frame ", std::min(saved + 1, timeline->frames()), "/", timeline->frames()),
          double(saved) / double(timeline->frames()));
    }
    if (!got_frame) call_ended = true;
  }
  const absl::Status ended = EndSession(*stream);
  progress.Done();

  std::cout << FormatStatsTable(stats.Summarize())
            << FormatWrittenFrames(writer, static_cast<uint64_t>(saved), script.encoding.format())
            << std::endl;
  for (const ResumableSession::Move& move : stream->moves()) {
    std::cout << FormatMove(move) << std::endl;
  }
  if (!ended.ok()) return ended;
  if (!interrupted && saved < timeline->frames()) {
    return absl::AbortedError(absl::StrCat("the server ended the session after ", saved, " of ",
                                           timeline->frames(), " frames"));
  }
  return absl::OkStatus();
}

}  // namespace gistream::client
