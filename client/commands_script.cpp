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

// Plays a timeline's frames in an open session: each frame's updates,
// then a request for the frame that includes them, saved.
class ScriptPlayer {
 public:
  ScriptPlayer(ResumableSession& stream, Timeline& timeline, FrameWriter& writer,
               ProgressLine& progress)
      : stream_(stream), timeline_(timeline), writer_(writer), progress_(progress) {}

  // Frame i: OK(true) when it was saved, OK(false) when the server ended
  // the call (EndSession says why); an error for a rejected update or a
  // broken echo.
  absl::StatusOr<bool> Play(int i) {
    std::map<uint64_t, std::string> sent;  // this frame's updates, for rejections
    for (v1::Update& update : timeline_.UpdatesForFrame(i)) {
      update.set_seq(++seq_);
      sent[seq_] = DescribeUpdate(update);
      if (!stream_.SendUpdate(update)) return false;
    }
    const Clock::time_point requested = Clock::now();
    if (!stream_.RequestFrame(1)) return false;
    ++outstanding_;
    return WaitForFrame(i, sent, requested);
  }

  const StatsCollector& stats() const { return stats_; }
  int saved() const { return saved_; }

 private:
  // Reads events until the frame with every update sent so far.
  absl::StatusOr<bool> WaitForFrame(int i, const std::map<uint64_t, std::string>& sent,
                                    Clock::time_point requested) {
    int stale = 0;
    v1::SessionEvent event;
    while (stream_.Next(&event)) {
      if (event.has_rejected()) return Rejected(i, event.rejected(), sent);
      if (!event.has_frame()) continue;
      const v1::Frame& frame = event.frame();
      outstanding_ = std::max(0, outstanding_ - 1);
      GS_ASSIGN_OR_RETURN(const bool ours, echo_.Accept(frame, seq_));
      if (!ours) {
        // A frame rendered before our updates. Wait for the one we asked
        // for; when none is pending, ask again, a few times.
        LogOnce(LogLevel::kWarning, "script-stale-frame",
                absl::StrCat("frame ", i, ": got a frame with update seq ", frame.last_update_seq(),
                             ", waiting for ", seq_));
        if (outstanding_ > 0) continue;
        if (++stale > kMaxStaleFrames) {
          return absl::DataLossError(absl::StrCat(
              "frame ", i, ": the server keeps sending frames without update seq ", seq_));
        }
        if (!stream_.RequestFrame(1)) return false;
        ++outstanding_;
        continue;
      }
      const Clock::time_point arrived = Clock::now();
      stats_.Add(frame, arrived,
                 std::chrono::duration<double, std::milli>(arrived - requested).count());
      GS_RETURN_IF_ERROR(writer_.Write(static_cast<uint64_t>(i), frame));
      ++saved_;
      progress_.Update(
          absl::StrCat("frame ", std::min(saved_ + 1, timeline_.frames()), "/", timeline_.frames()),
          double(saved_) / double(timeline_.frames()));
      return true;
    }
    return false;
  }

  static absl::Status Rejected(int i, const v1::UpdateRejected& rejected,
                               const std::map<uint64_t, std::string>& sent) {
    auto it = sent.find(rejected.seq());
    return absl::InvalidArgumentError(absl::StrCat(
        "frame ", i, ": update seq ", rejected.seq(),
        it == sent.end() ? "" : absl::StrCat(" (", it->second, ")"),
        " rejected: ", absl::StatusCodeToString(static_cast<absl::StatusCode>(rejected.code())),
        ": ", rejected.message()));
  }

  ResumableSession& stream_;
  Timeline& timeline_;
  FrameWriter& writer_;
  ProgressLine& progress_;
  StatsCollector stats_;
  EchoChecker echo_;
  uint64_t seq_ = 0;
  int saved_ = 0;
  int outstanding_ = 0;  // frames requested and not yet received
};

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
  ProgressLine progress;
  progress.Wait(absl::StrCat("loading scene ", script.scene));
  // A draining server's refusal is tried again for --resume-for.
  GS_ASSIGN_OR_RETURN(
      ConnectedScene loaded,
      ConnectAndLoad(connection_options, load, options.keep_scene, options.resume_for_s));
  Connection& connection = *loaded.connection;
  const std::unique_ptr<LoadedScene>& scene = loaded.scene;
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

  ScriptPlayer player(*stream, *timeline, writer, progress);
  for (int i = 0; i < timeline->frames() && !interrupted; ++i) {
    GS_ASSIGN_OR_RETURN(const bool saved, player.Play(i));
    if (!saved) break;  // the server ended the call early; EndSession says why
  }
  const absl::Status ended = EndSession(*stream);
  progress.Done();

  std::cout << FormatStatsTable(player.stats().Summarize())
            << FormatWrittenFrames(writer, static_cast<uint64_t>(player.saved()),
                                   script.encoding.format())
            << std::endl;
  for (const ResumableSession::Move& move : stream->moves()) {
    std::cout << FormatMove(move) << std::endl;
  }
  if (!ended.ok()) return ended;
  if (!interrupted && player.saved() < timeline->frames()) {
    return absl::AbortedError(absl::StrCat("the server ended the session after ", player.saved(),
                                           " of ", timeline->frames(), " frames"));
  }
  return absl::OkStatus();
}

}  // namespace gistream::client
