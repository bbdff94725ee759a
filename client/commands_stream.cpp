// gistream stream: a continuous session; every frame is saved and timed.
#include <atomic>
#include <iostream>

#include <absl/strings/str_cat.h>

#include "commands.h"
#include "connection.h"
#include "frame_report.h"
#include "frame_writer.h"
#include "interrupt.h"
#include "progress_line.h"
#include "resumable_session.h"
#include "scene_loader.h"
#include "session_common.h"
#include "stats_table.h"
#include "util/log.h"

namespace gistream::client {

namespace {

// What a stream received.
struct StreamTally {
  StatsCollector stats;
  uint64_t saved = 0;
  uint64_t pictures = 0;  // frames that carried an image
  bool at_rest = false;   // stopped early: the server said the view rests
  v1::Frame last;         // its header: the convergence line
};

// Saves every frame until the stream ends; half-closes it after
// options.frames, or at rest.
absl::Status ReceiveFrames(ResumableSession& stream, FrameWriter& writer,
                           const StreamOptions& options, std::atomic<bool>& closing,
                           ProgressLine& progress, StreamTally& tally) {
  v1::SessionEvent event;
  while (stream.Next(&event)) {
    if (event.has_rejected()) {
      Log(LogLevel::kWarning, absl::StrCat("update seq ", event.rejected().seq(),
                                           " rejected: ", event.rejected().message()));
      continue;
    }
    if (!event.has_frame() || closing) continue;  // frames after the half-close are not kept
    const v1::Frame& frame = event.frame();
    if (tally.saved == 0) progress.Done();
    tally.stats.Add(frame, StatsCollector::Clock::now());
    GS_RETURN_IF_ERROR(writer.Write(tally.saved, frame));
    ++tally.saved;
    tally.pictures += frame.image().empty() ? 0 : 1;
    tally.last = frame;
    tally.last.clear_image();
    if (options.frames != 0 && tally.saved >= options.frames) {
      closing = true;
      stream.CloseWrites();
    } else if (options.frames != 0 && FrameStatValue(frame, "at_rest") == 1.0) {
      // The server says the picture is finished and nothing changes: more
      // frames would be keep-alives of the same picture, a second apart.
      tally.at_rest = true;
      closing = true;
      stream.CloseWrites();
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status RunStream(const ConnectionOptions& connection_options, const StreamOptions& options) {
  GS_ASSIGN_OR_RETURN(v1::LoadSceneRequest load, BuildLoadSceneRequest(options.scene));
  GS_ASSIGN_OR_RETURN(FrameWriter writer,
                      FrameWriter::Create(options.out_dir, options.view.encoding.format()));
  ProgressLine progress;
  progress.Wait(absl::StrCat("loading scene ", options.scene.scene));
  // A draining server's refusal is tried again for --resume-for.
  GS_ASSIGN_OR_RETURN(
      ConnectedScene loaded,
      ConnectAndLoad(connection_options, load, options.scene.keep_scene, options.resume_for_s));
  Connection& connection = *loaded.connection;
  const std::unique_ptr<LoadedScene>& scene = loaded.scene;
  progress.Done();
  std::cout << DescribeScene(options.scene.scene, scene->info()) << std::endl;

  const v1::SessionConfig config =
      ContinuousConfig(scene->id(), options.solver, options.view, options.fps);

  ResumeOptions resume{.connection = connection_options,
                       .load = load,
                       .give_up_after_s = options.resume_for_s,
                       .group = nullptr};
  GS_ASSIGN_OR_RETURN(
      std::unique_ptr<ResumableSession> stream,
      ResumableSession::Open(connection.stub(), config, connection.server(), std::move(resume)));
  std::cout << FormatSessionOpened(stream->opened()) << std::endl;
  progress.Wait("waiting for the first frame");

  // Declared after `stream`, so it is gone before the stream is.
  std::atomic<bool> closing{false};
  std::atomic<bool> interrupted{false};
  ScopedInterruptHandler on_interrupt([&](int count) {
    if (count == 1) {
      std::cerr << "\ninterrupt: closing the session (Ctrl-C again to cancel it)" << std::endl;
      interrupted = true;
      closing = true;
      stream->CloseWrites();
    } else {
      stream->Cancel();
    }
  });

  StreamTally tally;
  GS_RETURN_IF_ERROR(ReceiveFrames(*stream, writer, options, closing, progress, tally));
  const absl::Status ended = EndSession(*stream);
  progress.Done();
  const std::vector<ResumableSession::Move> moves = stream->moves();
  if (!moves.empty()) scene->Abandon();  // its server went away
  for (const ResumableSession::Move& move : moves) std::cout << FormatMove(move) << std::endl;

  std::cout << FormatStatsTable(tally.stats.Summarize())
            << FormatWrittenFrames(writer, tally.saved, options.view.encoding.format(),
                                   tally.pictures)
            << std::endl;
  if (tally.saved > 0) std::cout << FormatConvergence(tally.last) << std::endl;
  if (tally.at_rest) {
    std::cout << "the view is at rest after " << tally.saved << " of " << options.frames
              << " frames (its picture is finished and nothing changes): stopped early"
              << std::endl;
  }
  if (ended.ok() && !interrupted && !tally.at_rest && options.frames != 0 &&
      tally.saved < options.frames) {
    return absl::AbortedError(absl::StrCat("the server ended the session after ", tally.saved,
                                           " of ", options.frames, " frames"));
  }
  return ended;
}

}  // namespace gistream::client
