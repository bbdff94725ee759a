// gistream bench: load and latency. For each concurrency step, opens N
// continuous sessions (round-robin over the servers), waits for their
// first frames, warms up, measures for the duration while each session
// sends its workload's updates, then drains and closes. An optional
// interferer loops a Render on its own channel meanwhile.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <ctime>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <thread>

#include <absl/strings/match.h>
#include <absl/strings/str_cat.h>
#include <absl/strings/str_join.h>
#include <absl/strings/str_split.h>
#include <google/protobuf/util/json_util.h>

#include "bench_report.h"
#include "bench_session.h"
#include "bench_stats.h"
#include "bench_workload.h"
#include "commands.h"
#include "connection.h"
#include "encode/encode.h"
#include "file_io.h"
#include "interrupt.h"
#include "scene_loader.h"
#include "session_common.h"
#include "text_table.h"
#include "util/image_metrics.h"
#include "util/log.h"

namespace gistream::client {
namespace {

using Clock = BenchClock;

constexpr auto kFirstFrameTimeout = std::chrono::minutes(5);
constexpr auto kDrainTimeout = std::chrono::seconds(30);
constexpr auto kPollPeriod = std::chrono::milliseconds(500);

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }
Clock::duration FromSeconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

// One server of the run: its channel(s), its copy of the scene, and the
// GetServerStatus samples of the current step.
struct BenchServer {
  std::string address;
  std::unique_ptr<Connection> connection;  // shared by its sessions unless per-session
  std::unique_ptr<LoadedScene> scene;
  v1::ServerStatus first, last;
  ServerSample sample;
};

// The `--interfere "render ..."` client: Render in a loop on a channel of
// its own until stopped; Stop cancels the call in flight.
class Interferer {
 public:
  Interferer(const ConnectionOptions& connection, v1::RenderRequest request)
      : connection_([&] {
          ConnectionOptions own = connection;
          own.own_connection = true;
          return own;
        }()),
        request_(std::move(request)) {}
  ~Interferer() { Stop(); }

  void Start() {
    stop_ = false;
    thread_ = std::thread([this] { Loop(); });
  }
  void Stop() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
      if (context_) context_->TryCancel();
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
  }
  // Renders finished since the last call, their times, and the last error.
  void Take(int& renders, std::optional<double>& median_ms, std::string& error) {
    std::lock_guard lock(mutex_);
    renders = int(times_ms_.size());
    median_ms = Percentile(times_ms_, 50);
    error = error_;
    times_ms_.clear();
    error_.clear();
  }

 private:
  void Loop() {
    while (true) {
      grpc::ClientContext context;
      {
        std::lock_guard lock(mutex_);
        if (stop_) return;
        context_ = &context;
      }
      v1::Frame frame;
      const Clock::time_point start = Clock::now();
      const grpc::Status status = connection_.stub().Render(&context, request_, &frame);
      std::unique_lock lock(mutex_);
      context_ = nullptr;
      if (stop_) return;
      if (status.ok()) {
        times_ms_.push_back(Seconds(Clock::now() - start) * 1e3);
      } else {
        error_ = DescribeStatus(FromGrpc(status, connection_.server()));
        cv_.wait_for(lock, std::chrono::seconds(1), [this] { return stop_; });  // no busy loop
      }
    }
  }

  Connection connection_;
  v1::RenderRequest request_;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
  grpc::ClientContext* context_ = nullptr;
  std::vector<double> times_ms_;
  std::string error_;
};

// Parses `--interfere` as a `render` command line; the scene defaults to
// the bench's, and no file is written.
absl::StatusOr<RenderOptions> ParseInterferer(const std::string& text, const std::string& scene,
                                              const std::string& server) {
  std::vector<std::string> args = absl::StrSplit(text, ' ', absl::SkipWhitespace());
  if (args.empty() || args.front() != "render") {
    return absl::InvalidArgumentError(
        absl::StrCat("--interfere: \"", text, "\" is not a `render ...` command line"));
  }
  if (std::find(args.begin(), args.end(), "--scene") == args.end()) {
    args.insert(args.end(), {"--scene", scene});
  }
  if (std::find(args.begin(), args.end(), "--out") == args.end()) {
    args.insert(args.end(), {"--out", "/dev/null"});
  }
  absl::StatusOr<CommandLine> line = ParseCommandLine(args, server);
  if (!line.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("--interfere: ", line.status().message()));
  }
  return std::get<RenderOptions>(line->options);
}

bool StderrIsTty() { return ::isatty(STDERR_FILENO) == 1; }

// The live progress line (on a terminal only), rewritten in place.
class Progress {
 public:
  explicit Progress(bool enabled) : enabled_(enabled) {}
  void Show(const std::string& text) {
    if (!enabled_) return;
    std::cerr << "\r\033[K" << text << std::flush;
    shown_ = true;
  }
  void Clear() {
    if (enabled_ && shown_) std::cerr << "\r\033[K" << std::flush;
    shown_ = false;
  }

 private:
  bool enabled_;
  bool shown_ = false;
};

std::string Canonical(const BenchOptions& o, const std::string& servers) {
  std::string cmd = absl::StrCat("gistream --server ", servers, " bench --scene ", o.scene.scene,
                                 " --solver ", o.solver.solver);
  for (const auto& [k, v] : o.solver.params) absl::StrAppend(&cmd, " --param ", k, "=", v);
  absl::StrAppend(&cmd, " --size ", o.view.width, "x", o.view.height, " --workload ", o.workload);
  if (!o.node.empty()) absl::StrAppend(&cmd, " --node ", o.node);
  absl::StrAppend(&cmd, " --update-hz ", o.update_hz, " --sessions ",
                  absl::StrJoin(o.sessions, ","), " --duration ", o.duration_s, "s --warmup ",
                  o.warmup_s, "s --channels ", o.channel_per_session ? "per-session" : "shared",
                  " --fps ", o.fps);
  if (!o.interfere.empty()) absl::StrAppend(&cmd, " --interfere \"", o.interfere, "\"");
  if (o.reference_spp > 0) absl::StrAppend(&cmd, " --reference-spp ", o.reference_spp);
  return cmd;
}

void PollStatus(BenchServer& server, bool first) {
  v1::ServerStatus status;
  if (!server.connection
           ->Call(&v1::Gistream::Stub::GetServerStatus, v1::GetServerStatusRequest(), &status, 5.0)
           .ok()) {
    return;
  }
  if (first) server.first = status;
  server.last = status;
  server.sample.max_rss_bytes = std::max<uint64_t>(server.sample.max_rss_bytes, status.rss_bytes());
}

void FinishSample(BenchServer& server) {
  ServerSample& s = server.sample;
  s.server = server.address;
  // A server that reports no RSS predates these fields.
  s.available = server.last.rss_bytes() > 0;
  const double wall = server.last.uptime_s() - server.first.uptime_s();
  s.cpu_percent =
      wall > 0.0 ? 100.0 * (server.last.cpu_seconds() - server.first.cpu_seconds()) / wall : 0.0;
}

// What the first session showed after the updates stopped (--reference-spp).
struct SettleTrace {
  std::vector<BenchSession::SettleFrame> frames;
  std::vector<v1::Update> last_state;  // every update sent
  // Every frame from the window's start, and the state of each sequence
  // number they show (frames.csv).
  std::vector<BenchSession::TracedFrame> traced;
  std::map<uint64_t, std::vector<v1::Update>> state_of_seq;
};

// A state (updates replayed on the scene as loaded) as a Render request
// carries it: the camera's changes merged into the request's camera, which
// every call of a progressive reference repeats (a camera is a session's,
// and each Render is its own session), the rest as updates (a scene's:
// they stay on the private copy).
void SetState(const std::vector<v1::Update>& state, const v1::CameraChange& view_camera,
              bool with_updates, v1::RenderRequest& r) {
  v1::CameraChange camera = view_camera;
  for (const v1::Update& u : state) {
    if (u.has_camera()) {
      camera.MergeFrom(u.camera());
    } else if (with_updates) {
      *r.add_updates() = u;
    }
  }
  if (camera.ByteSizeLong() > 0) *r.mutable_camera() = camera;
}

absl::StatusOr<RgbaImage> DecodeRgba(const std::string& bytes) {
  GS_ASSIGN_OR_RETURN(
      DecodedImage d,
      DecodeImageBytes({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()}));
  return RgbaImage{d.width, d.height, std::move(d.rgba)};
}

// The time to converge (issue 12's figure of merit): on a fresh copy of the
// scene in the final state, a full solve of the solver and a pathtrace
// reference of `reference_spp`; the first frame after the stop from which
// on every frame's relMSE stays within 5 % of the full solve's.
absl::StatusOr<nlohmann::json> TimeToConverge(Connection& connection,
                                              const v1::LoadSceneRequest& load,
                                              const BenchOptions& options,
                                              const SettleTrace& trace) {
  if (trace.frames.empty()) return absl::FailedPreconditionError("no frame after the stop");
  GS_ASSIGN_OR_RETURN(std::unique_ptr<LoadedScene> copy,
                      LoadedScene::Load(connection, load, false));
  auto request = [&](const std::string& solver, const std::map<std::string, std::string>& params,
                     bool updates) {
    v1::RenderRequest r;
    r.set_scene_id(copy->id());
    r.set_solver(solver);
    for (const auto& [k, v] : params) (*r.mutable_params())[k] = v;
    r.set_width(options.view.width);
    r.set_height(options.view.height);
    r.set_refine_samples(options.view.refine_samples);
    r.mutable_encoding()->set_format(v1::IMAGE_FORMAT_EXR);
    SetState(trace.last_state, options.view.camera, updates, r);
    return r;
  };
  v1::Frame full_frame;
  GS_RETURN_IF_ERROR(connection.Call(&v1::Gistream::Stub::Render,
                                     request(options.solver.solver, options.solver.params, true),
                                     &full_frame, 600.0));
  // Progressive: the server keeps the pathtrace accumulation between calls.
  const int chunk = std::min(options.reference_spp, 64);
  v1::Frame reference_frame;
  for (int spp = 0; spp < options.reference_spp; spp += chunk) {
    GS_RETURN_IF_ERROR(connection.Call(
        &v1::Gistream::Stub::Render,
        request("pathtrace", {{"spp", std::to_string(chunk)}, {"seed", "1"}}, false),
        &reference_frame, 600.0));
  }
  GS_ASSIGN_OR_RETURN(const RgbaImage reference, DecodeRgba(reference_frame.image()));
  GS_ASSIGN_OR_RETURN(const RgbaImage full, DecodeRgba(full_frame.image()));
  GS_ASSIGN_OR_RETURN(const ImageError full_error, CompareImages(full, reference));
  std::vector<double> errors;  // per frame after the stop
  for (const BenchSession::SettleFrame& f : trace.frames) {
    if (f.image.empty()) return absl::FailedPreconditionError("a frame without an image");
    GS_ASSIGN_OR_RETURN(const RgbaImage image, DecodeRgba(f.image));
    GS_ASSIGN_OR_RETURN(const ImageError e, CompareImages(image, reference));
    errors.push_back(e.rel_mse);
  }
  const double bound = 1.05 * full_error.rel_mse;
  std::optional<size_t> first;
  for (size_t i = errors.size(); i-- > 0;) {
    if (!(errors[i] <= bound)) break;
    first = i;
  }
  nlohmann::json out = {{"reference_spp", options.reference_spp},
                        {"full_solve_rel_mse", full_error.rel_mse},
                        {"first_frame_rel_mse", errors.front()},
                        {"last_frame_rel_mse", errors.back()},
                        {"frames_after_stop", errors.size()}};
  if (first) {
    out["frames"] = *first + 1;
    out["ms"] = trace.frames[*first].ms;
  } else {
    out["frames"] = nullptr;
    out["ms"] = nullptr;
  }
  return out;
}

// A path-traced reference of `reference_spp` of the scene as `updates`
// leave it, on a fresh private copy (progressive: the server keeps the
// accumulation between the calls of one copy): the EXR bytes.
absl::StatusOr<std::string> RenderReference(Connection& connection,
                                            const v1::LoadSceneRequest& load,
                                            const BenchOptions& options,
                                            const std::vector<v1::Update>& updates) {
  v1::LoadSceneRequest own = load;
  own.set_private_copy(true);
  GS_ASSIGN_OR_RETURN(std::unique_ptr<LoadedScene> copy, LoadedScene::Load(connection, own, false));
  const int chunk = std::min(options.reference_spp, 64);
  v1::Frame frame;
  for (int spp = 0; spp < options.reference_spp; spp += chunk) {
    v1::RenderRequest r;
    r.set_scene_id(copy->id());
    r.set_solver("pathtrace");
    // (std::string values: GCC 12 warns, falsely, on assigning a literal)
    const std::map<std::string, std::string> params = {{"spp", std::to_string(chunk)},
                                                       {"seed", "1"}};
    for (const auto& [k, v] : params) (*r.mutable_params())[k] = v;
    r.set_width(options.view.width);
    r.set_height(options.view.height);
    r.mutable_encoding()->set_format(v1::IMAGE_FORMAT_EXR);
    SetState(updates, options.view.camera, /*with_updates=*/spp == 0, r);
    GS_RETURN_IF_ERROR(connection.Call(&v1::Gistream::Stub::Render, r, &frame, 600.0));
  }
  return std::move(*frame.mutable_image());
}

// The updates a reference applied, as a JSON array of protobuf-JSON Update
// messages (references/, for checking them against a fresh render).
std::string UpdatesJson(const std::vector<v1::Update>& updates) {
  nlohmann::json out = nlohmann::json::array();
  for (const v1::Update& u : updates) {
    std::string text;
    if (google::protobuf::util::MessageToJsonString(u, &text).ok()) {
      out.push_back(nlohmann::json::parse(text));
    }
  }
  return out.dump(1);
}

// Issue 27's error over time: every frame of the first session from the
// window's start, against a reference of the state it shows (the updates
// up to its sequence number; one reference per number, rendered after the
// run, written to references/step<k>_seq<n>.exr with the updates it
// applied in .json). Appends its rows to `csv` and returns the step's summary: relMSE
// mean and p95 during the motion, the first frame after the stop, and the
// time from the stop until every later frame stays within 2x and 1.05x of
// the full solve's error.
absl::StatusOr<nlohmann::json> ErrorOverTime(Connection& connection,
                                             const v1::LoadSceneRequest& load,
                                             const BenchOptions& options, const SettleTrace& trace,
                                             double full_solve_rel_mse, int step,
                                             std::string& csv) {
  std::map<uint64_t, RgbaImage> references;
  const std::filesystem::path dir = options.out_dir / "references";
  for (const auto& [seq, updates] : trace.state_of_seq) {
    GS_ASSIGN_OR_RETURN(const std::string exr, RenderReference(connection, load, options, updates));
    GS_ASSIGN_OR_RETURN(references[seq], DecodeRgba(exr));
    // Kept beside frames.csv: the reference and the updates it applied.
    const std::string stem = absl::StrCat("step", step, "_seq", seq);
    GS_RETURN_IF_ERROR(WriteFile(dir / (stem + ".exr"), exr));
    GS_RETURN_IF_ERROR(WriteFile(dir / (stem + ".json"), UpdatesJson(updates)));
  }
  std::vector<double> motion;
  std::optional<double> first_after_stop, stop_ms;
  std::vector<std::pair<double, double>> settle;  // (ms after the stop, relMSE)
  for (const BenchSession::TracedFrame& f : trace.traced) {
    if (f.image.empty()) continue;  // before the first picture
    GS_ASSIGN_OR_RETURN(const RgbaImage image, DecodeRgba(f.image));
    GS_ASSIGN_OR_RETURN(const ImageError e, CompareImages(image, references.at(f.seq)));
    // --keep-frames: to look at what each row measured (a float EXR each,
    // 190 KiB at 128x128, so not by default).
    if (options.keep_frames) {
      GS_RETURN_IF_ERROR(WriteFile(
          options.out_dir / "frames" / absl::StrCat("step", step, "_frame", f.frame_number, ".exr"),
          f.image));
    }
    absl::StrAppend(&csv, step, ",1,", f.frame_number, ",", f.seq, ",", FormatFixed(f.t_ms, 1), ",",
                    f.settle ? "settle" : "motion", ",", e.rel_mse, ",", f.update_complete, ",",
                    f.at_rest, ",", f.frames_since_scene_change, ",", f.refine_samples, "\n");
    if (!f.settle) {
      motion.push_back(e.rel_mse);
    } else {
      if (!stop_ms) {
        stop_ms = f.t_ms;
        first_after_stop = e.rel_mse;
      }
      settle.emplace_back(f.t_ms - *stop_ms, e.rel_mse);
    }
  }
  nlohmann::json out = {{"full_solve_rel_mse", full_solve_rel_mse},
                        {"motion_frames", motion.size()},
                        {"settle_frames", settle.size()}};
  if (!motion.empty()) {
    double sum = 0.0;
    for (double v : motion) sum += v;
    std::vector<double> sorted = motion;
    std::sort(sorted.begin(), sorted.end());
    out["motion_mean_rel_mse"] = sum / double(motion.size());
    out["motion_p95_rel_mse"] =
        sorted[std::min(sorted.size() - 1, size_t(0.95 * double(sorted.size())))];
    out["motion_mean_vs_full"] = out["motion_mean_rel_mse"].get<double>() / full_solve_rel_mse;
  }
  if (first_after_stop) {
    out["first_after_stop_rel_mse"] = *first_after_stop;
    out["first_after_stop_vs_full"] = *first_after_stop / full_solve_rel_mse;
  }
  // From which frame on every later one stays within the bound.
  const auto within = [&](double factor) -> nlohmann::json {
    std::optional<size_t> first;
    for (size_t i = settle.size(); i-- > 0;) {
      if (!(settle[i].second <= factor * full_solve_rel_mse)) break;
      first = i;
    }
    if (!first) return nullptr;
    return {{"frames", *first + 1}, {"ms", settle[*first].first}};
  };
  out["within_2x"] = within(2.0);
  out["within_1_05x"] = within(1.05);
  return out;
}

// A step's sessions, spread over the servers, and the channels of their
// own (--channel-per-session).
struct StepSessions {
  std::map<std::string, std::shared_ptr<MoveGroup>> move_groups;
  std::vector<std::unique_ptr<Connection>> own_connections;
  std::vector<std::unique_ptr<BenchSession>> sessions;
};

StepSessions OpenSessions(const BenchOptions& options, const ConnectionOptions& connection,
                          const v1::LoadSceneRequest& load, std::vector<BenchServer>& servers,
                          const Workload& workload, int count, const std::string& label,
                          Progress& progress, const std::atomic<bool>& interrupted,
                          bool keep_settle_frames, SharedStages& stages) {
  StepSessions out;
  for (int i = 0; i < count && !interrupted; ++i) {
    BenchServer& server = servers[size_t(i) % servers.size()];
    Connection* channel = server.connection.get();
    if (options.channel_per_session) {
      ConnectionOptions own = connection;
      own.server = server.address;
      own.own_connection = true;
      out.own_connections.push_back(std::make_unique<Connection>(own));
      channel = out.own_connections.back().get();
    }
    const v1::SessionConfig config =
        ContinuousConfig(server.scene->id(), options.solver, options.view, options.fps);
    auto session =
        std::make_unique<BenchSession>(server.address, workload, options.update_hz, stages);
    progress.Show(absl::StrCat(label, " opening session ", i + 1, "/", count));
    if (keep_settle_frames && i == 0) session->KeepSettleFrames();
    // The sessions of one server move together: one load where they land.
    std::shared_ptr<MoveGroup>& group = out.move_groups[server.address];
    if (!group) group = std::make_shared<MoveGroup>();
    ResumeOptions resume{.connection = connection,
                         .load = load,
                         .give_up_after_s = options.resume_for_s,
                         .group = group};
    resume.connection.server = server.address;
    const absl::Status opened = session->Open(channel->stub(), config, std::move(resume));
    if (!opened.ok())
      Log(LogLevel::kWarning, absl::StrCat("session ", i + 1, ": ", DescribeStatus(opened)));
    out.sessions.push_back(std::move(session));
  }
  return out;
}

// Every live session's first frame (a GI solver's first full solve can
// take a while), at most kFirstFrameTimeout.
void WaitForFirstFrames(const std::vector<std::unique_ptr<BenchSession>>& sessions,
                        const std::string& label, Progress& progress,
                        const std::atomic<bool>& interrupted) {
  const Clock::time_point wait_start = Clock::now();
  while (!interrupted) {
    int ready = 0, live = 0;
    for (const auto& s : sessions) {
      if (s->failed()) continue;
      ++live;
      ready += s->has_first_frame() ? 1 : 0;
    }
    if (ready == live) return;
    if (Clock::now() - wait_start > kFirstFrameTimeout) {
      Log(LogLevel::kWarning,
          absl::StrCat(label, " ", live - ready,
                       " session(s) sent no frame in 5 minutes; measuring anyway"));
      return;
    }
    progress.Show(absl::StrCat(label, " waiting for first frames ", ready, "/", live, " (",
                               int(Seconds(Clock::now() - wait_start)), " s)"));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

// The warm-up, then the measured window [start, end): the servers' status
// polled, the live figures shown; the servers' samples finished.
void MeasureWindow(const BenchOptions& options,
                   const std::vector<std::unique_ptr<BenchSession>>& sessions,
                   std::vector<BenchServer>& servers, Clock::time_point start,
                   Clock::time_point end, const std::string& label, Progress& progress,
                   const std::atomic<bool>& interrupted) {
  for (BenchServer& server : servers) server.sample = ServerSample{};
  bool polled_first = false;
  while (!interrupted) {
    const Clock::time_point now = Clock::now();
    if (now >= end) break;
    if (now < start) {
      const double warmed = options.warmup_s - Seconds(start - now);
      progress.Show(absl::StrCat(label, " warming up ", FormatFixed(warmed, 1), "/",
                                 FormatFixed(options.warmup_s, 1), " s"));
    } else {
      for (BenchServer& server : servers) PollStatus(server, !polled_first);
      polled_first = true;
      int frames = 0;
      std::vector<double> latencies;
      for (const auto& s : sessions) {
        frames += s->LiveFrames();
        s->AppendLatencies(latencies);
      }
      const double elapsed = std::max(Seconds(Clock::now() - start), 1e-3);
      const std::optional<double> p95 = Percentile(latencies, 95);
      progress.Show(absl::StrCat(
          label, " measuring ", FormatFixed(elapsed, 1), "/", FormatFixed(options.duration_s, 1),
          " s  fps ", FormatFixed(frames / elapsed / std::max<size_t>(sessions.size(), 1), 1),
          "/session  p95 latency ", p95 ? absl::StrCat(FormatFixed(*p95, 1), " ms") : "-"));
    }
    std::this_thread::sleep_until(std::min(Clock::now() + kPollPeriod, now < start ? start : end));
  }
  for (BenchServer& server : servers) {
    PollStatus(server, !polled_first);
    FinishSample(server);
  }
}

// Lets the frames that answer the last measured updates arrive, and the GI
// catch up with the last update (the time to converge), at most
// kDrainTimeout.
void DrainSessions(const std::vector<std::unique_ptr<BenchSession>>& sessions,
                   const std::string& label, Progress& progress,
                   const std::atomic<bool>& interrupted) {
  const Clock::time_point drain_end = Clock::now() + kDrainTimeout;
  while (!interrupted && Clock::now() < drain_end) {
    size_t pending = 0, unsettled = 0;
    for (const auto& s : sessions) {
      pending += s->Unanswered();
      unsettled += s->Settled() ? 0 : 1;
    }
    if (pending == 0 && unsettled == 0) return;
    progress.Show(absl::StrCat(
        label, " waiting for ", pending > 0 ? absl::StrCat(pending, " update(s) to show") : "",
        pending > 0 && unsettled > 0 ? " and " : "",
        unsettled > 0 ? absl::StrCat(unsettled, " session(s) to converge") : ""));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

// The first session's frames and updates, for --reference-spp.
void KeepTrace(const BenchSession& session, SettleTrace* trace) {
  trace->frames = session.SettleFrames();
  trace->last_state = session.LastState();
  trace->traced = session.TracedFrames();
  for (const BenchSession::TracedFrame& f : trace->traced) {
    if (!trace->state_of_seq.count(f.seq)) trace->state_of_seq[f.seq] = session.StateOfSeq(f.seq);
  }
}

// Runs one step with `count` sessions.
absl::StatusOr<StepResult> RunStep(const BenchOptions& options, const ConnectionOptions& connection,
                                   const v1::LoadSceneRequest& load,
                                   std::vector<BenchServer>& servers, const Workload& workload,
                                   Interferer* interferer, int count, const std::string& label,
                                   Progress& progress, const std::atomic<bool>& interrupted,
                                   SettleTrace* trace) {
  SharedStages stages;
  StepSessions step_sessions =
      OpenSessions(options, connection, load, servers, workload, count, label, progress,
                   interrupted, /*keep_settle_frames=*/trace != nullptr, stages);
  std::vector<std::unique_ptr<BenchSession>>& sessions = step_sessions.sessions;
  // The warm-up starts after every session's first frame.
  WaitForFirstFrames(sessions, label, progress, interrupted);
  if (interferer) interferer->Start();
  const Clock::time_point start = Clock::now() + FromSeconds(options.warmup_s);
  const Clock::time_point end = start + FromSeconds(options.duration_s);
  for (auto& s : sessions) s->SetWindow(start, end);
  MeasureWindow(options, sessions, servers, start, end, label, progress, interrupted);
  for (auto& s : sessions) s->StopUpdates();
  StepResult partial;
  if (interferer) {
    interferer->Stop();
    interferer->Take(partial.interferer_renders, partial.interferer_median_ms,
                     partial.interferer_error);
  }
  DrainSessions(sessions, label, progress, interrupted);
  progress.Show(absl::StrCat(label, " closing ", sessions.size(), " session(s)"));
  std::vector<SessionMeasurement> measured;
  for (auto& s : sessions) s->StopUpdates();
  for (auto& s : sessions) s->Close();
  for (auto& s : sessions) measured.push_back(s->Result());
  if (trace && !sessions.empty()) KeepTrace(*sessions[0], trace);
  progress.Clear();

  StatsSummary stage_summary;
  {
    std::lock_guard lock(stages.mutex);
    stage_summary = stages.collector.Summarize();
  }
  StepResult step =
      AggregateStep(std::move(measured), std::move(stage_summary), options.duration_s);
  step.interferer_renders = partial.interferer_renders;
  step.interferer_median_ms = partial.interferer_median_ms;
  step.interferer_error = partial.interferer_error;
  for (BenchServer& server : servers) step.servers.push_back(server.sample);
  return step;
}

// --reference-spp's preconditions: linear frames, fresh copies for the
// references (any workload: a reference replays every update sent up to
// the frame it is for).
absl::Status CheckReferenceOptions(const BenchOptions& options, const v1::LoadSceneRequest& load) {
  if (options.reference_spp <= 0) return absl::OkStatus();
  if (options.view.encoding.format() != v1::IMAGE_FORMAT_EXR) {
    return absl::InvalidArgumentError("--reference-spp: needs --format exr (linear frames)");
  }
  if (load.has_name() && !load.private_copy()) {
    return absl::InvalidArgumentError(
        absl::StrCat("--reference-spp: --scene \"", options.scene.scene,
                     "\" with --keep-scene is the shared scene; its references need fresh copies"));
  }
  return absl::OkStatus();
}

// One connection per address, each with the scene loaded (ConnectAndLoad:
// a server that answers it drains is asked again on a connection of its
// own for up to 30 s, as a moving session is).
absl::StatusOr<std::vector<BenchServer>> ConnectServers(const ConnectionOptions& connection,
                                                        const std::vector<std::string>& addresses,
                                                        const v1::LoadSceneRequest& load,
                                                        bool keep_scene) {
  constexpr double kGiveUpAfterS = 30.0;
  std::vector<BenchServer> servers;
  for (const std::string& address : addresses) {
    BenchServer server;
    server.address = address;
    ConnectionOptions one = connection;
    one.server = address;
    GS_ASSIGN_OR_RETURN(ConnectedScene loaded,
                        ConnectAndLoad(one, load, keep_scene, kGiveUpAfterS));
    server.connection = std::move(loaded.connection);
    server.scene = std::move(loaded.scene);
    servers.push_back(std::move(server));
  }
  return servers;
}

// --interfere's client on the first server, with its own scene when it
// names another one.
struct InterfererSetup {
  std::unique_ptr<LoadedScene> scene;
  std::unique_ptr<Interferer> interferer;
};
absl::StatusOr<InterfererSetup> StartInterferer(const RenderOptions& interferer_options,
                                                const BenchOptions& options,
                                                const ConnectionOptions& connection,
                                                BenchServer& first_server) {
  InterfererSetup setup;
  v1::RenderRequest request;
  std::string scene_id = first_server.scene->id();
  if (interferer_options.scene.scene != options.scene.scene) {
    GS_ASSIGN_OR_RETURN(v1::LoadSceneRequest other,
                        BuildLoadSceneRequest(interferer_options.scene));
    GS_ASSIGN_OR_RETURN(setup.scene, LoadedScene::Load(*first_server.connection, other, false));
    scene_id = setup.scene->id();
  }
  request.set_scene_id(scene_id);
  request.set_solver(interferer_options.solver.solver);
  request.mutable_params()->insert(interferer_options.solver.params.begin(),
                                   interferer_options.solver.params.end());
  request.set_width(interferer_options.view.width);
  request.set_height(interferer_options.view.height);
  *request.mutable_encoding() = interferer_options.view.encoding;
  if (interferer_options.view.camera.ByteSizeLong() > 0) {
    *request.mutable_camera() = interferer_options.view.camera;
  }
  ConnectionOptions first = connection;
  first.server = first_server.address;
  setup.interferer = std::make_unique<Interferer>(first, request);
  return setup;
}

// --reference-spp after a step: the time to converge and the error of each
// frame shown (appended to frames_csv); null when it could not be measured.
nlohmann::json MeasureConvergence(Connection& connection, const v1::LoadSceneRequest& load,
                                  const BenchOptions& options, const SettleTrace& trace,
                                  const std::string& label, int step_number,
                                  std::string& frames_csv) {
  absl::StatusOr<nlohmann::json> figure = TimeToConverge(connection, load, options, trace);
  if (!figure.ok()) {
    Log(LogLevel::kWarning, absl::StrCat("time to converge: ", figure.status().message()));
    return nullptr;
  }
  std::cout << label << " converge: " << figure->dump() << std::endl;
  absl::StatusOr<nlohmann::json> over_time =
      ErrorOverTime(connection, load, options, trace,
                    figure->at("full_solve_rel_mse").get<double>(), step_number, frames_csv);
  if (over_time.ok()) {
    std::cout << label << " error over time: " << over_time->dump() << std::endl;
    (*figure)["over_time"] = *over_time;
  } else {
    Log(LogLevel::kWarning, absl::StrCat("error over time: ", over_time.status().message()));
  }
  return *figure;
}

// A step's line while the bench runs, and its sessions' and the
// interferer's errors.
void PrintStep(const std::string& label, const StepResult& step) {
  std::cout << label << " " << FormatFixed(step.fps_mean, 1) << " fps/session, latency p95 "
            << (step.latency_ms.p95 ? FormatFixed(*step.latency_ms.p95, 1) : "-")
            << " ms, longest frame interval "
            << (step.interval_ms.max ? FormatFixed(*step.interval_ms.max, 0) : "-") << " ms"
            << (step.failed_sessions ? absl::StrCat(", ", step.failed_sessions, " failed") : "")
            << std::endl;
  if (const std::string moves = FormatMoves(step); !moves.empty()) {
    std::cout << label << " " << moves << std::endl;
  }
  for (const SessionMeasurement& m : step.per_session) {
    if (!m.error.empty())
      Log(LogLevel::kWarning, absl::StrCat("session on ", m.server, ": ", m.error));
  }
  if (!step.interferer_error.empty()) {
    Log(LogLevel::kWarning, absl::StrCat("interferer: ", step.interferer_error));
  }
}

// results.json's "meta": what ran, where and how.
nlohmann::json BenchMeta(const BenchOptions& options, const ConnectionOptions& connection,
                         const std::vector<std::string>& addresses, const v1::ServerStatus& status,
                         const WorkloadSpec& spec, const Workload& workload,
                         const std::string& pacing, const nlohmann::json& converge) {
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof(date), "%Y-%m-%d", std::gmtime(&now));
  return {
      {"date", date},
      {"command", Canonical(options, connection.server)},
      {"servers", addresses},
      {"server_version", status.version()},
      {"gl_renderer", status.gl_renderer()},
      {"cpu", absl::StrCat(status.cpu_model(), ", ", status.cpu_threads(), " threads")},
      {"scene", options.scene.scene},
      {"solver", options.solver.solver},
      {"params", options.solver.params},
      {"size", absl::StrCat(options.view.width, "x", options.view.height)},
      {"format", v1::ImageFormat_Name(options.view.encoding.format())},
      {"workload", WorkloadName(spec)},
      {"workload_description", workload.description()},
      {"pacing", pacing},
      {"update_hz", options.update_hz},
      {"fps_cap", options.fps > 0.0f ? FormatFixed(options.fps, 0) : std::string("server default")},
      {"duration_s", options.duration_s},
      {"warmup_s", options.warmup_s},
      {"channels", options.channel_per_session ? "per-session" : "shared"},
      {"interfere", options.interfere},
      {"reference_spp", options.reference_spp},
      {"converge", converge}};
}

// The table and stage medians, then results.{csv,json,md}, the plots and
// (--reference-spp) frames.csv.
absl::Status ReportBench(const BenchOptions& options, const std::vector<StepResult>& steps,
                         const nlohmann::json& meta, const std::string& frames_csv) {
  std::cout << "\n" << FormatBenchTable(steps);
  for (const StepResult& s : steps) {
    std::cout << "stages (" << s.sessions << "): " << FormatStageMedians(s.stages) << "\n";
  }
  GS_RETURN_IF_ERROR(WriteBenchOutputs(options.out_dir, steps, meta));
  if (options.reference_spp > 0) {
    GS_RETURN_IF_ERROR(WriteFile(options.out_dir / "frames.csv", frames_csv));
    std::cout << "wrote " << (options.out_dir / "frames.csv").string()
              << " (every frame of the first session against a reference of its state)"
              << std::endl;
  }
  std::cout << "wrote " << (options.out_dir / "results.{csv,json,md}").string() << ", "
            << (options.out_dir / "latency_cdf.png").string() << ", fps_vs_sessions.png and "
            << "latency_vs_sessions.png" << std::endl;
  return absl::OkStatus();
}

constexpr char kFramesCsvHeader[] =
    "step,session,frame,seq,t_ms,phase,relmse,update_complete,at_rest,"
    "frames_since_scene_change,refine_samples\n";

}  // namespace

absl::StatusOr<std::string> RunInteraction(const ConnectionOptions& connection,
                                           const BenchOptions& options) {
  if (options.reference_spp <= 0) {
    return absl::InvalidArgumentError("an interaction needs a reference sample count");
  }
  GS_ASSIGN_OR_RETURN(WorkloadSpec spec, ParseWorkload(options.workload));
  spec.node = options.node;
  GS_ASSIGN_OR_RETURN(v1::LoadSceneRequest load, BuildLoadSceneRequest(options.scene));
  load.set_private_copy(true);
  GS_RETURN_IF_ERROR(CheckReferenceOptions(options, load));
  GS_ASSIGN_OR_RETURN(std::vector<BenchServer> servers,
                      ConnectServers(connection, {connection.server}, load, false));
  GS_ASSIGN_OR_RETURN(Workload workload, Workload::Create(spec, servers[0].scene->info()));
  std::atomic<bool> interrupted{false};
  Progress progress(StderrIsTty());
  const std::string label = absl::StrCat("[", options.solver.solver, " ", WorkloadName(spec), "]");
  SettleTrace trace;
  GS_ASSIGN_OR_RETURN(const StepResult step,
                      RunStep(options, connection, load, servers, workload, nullptr, 1, label,
                              progress, interrupted, &trace));
  if (step.failed_sessions > 0) {
    // The server refused or ended the session (a bad parameter, a limit).
    return absl::FailedPreconditionError(absl::StrCat("the session failed: ", step.first_error));
  }
  std::string frames_csv = kFramesCsvHeader;
  const nlohmann::json converge =
      MeasureConvergence(*servers[0].connection, load, options, trace, label, 1, frames_csv);
  GS_RETURN_IF_ERROR(WriteFile(options.out_dir / "frames.csv", frames_csv));
  return converge.dump();
}

absl::Status RunBench(const ConnectionOptions& connection, const BenchOptions& options) {
  GS_ASSIGN_OR_RETURN(WorkloadSpec spec, ParseWorkload(options.workload));
  spec.node = options.node;
  const std::vector<std::string> addresses =
      absl::StrSplit(connection.server, ',', absl::SkipWhitespace());
  if (addresses.empty()) return absl::InvalidArgumentError("--server: no address");
  std::optional<RenderOptions> interferer_options;
  if (!options.interfere.empty()) {
    GS_ASSIGN_OR_RETURN(interferer_options,
                        ParseInterferer(options.interfere, options.scene.scene, addresses[0]));
  }
  GS_ASSIGN_OR_RETURN(v1::LoadSceneRequest load, BuildLoadSceneRequest(options.scene));
  // The sessions measure on their own copy of a named scene (another
  // client's changes to the shared one cannot move the figures), and the
  // time-to-converge reference on a fresh one; --keep-scene shares it.
  if (!options.scene.keep_scene) load.set_private_copy(true);
  GS_RETURN_IF_ERROR(CheckReferenceOptions(options, load));
  GS_ASSIGN_OR_RETURN(std::vector<BenchServer> servers,
                      ConnectServers(connection, addresses, load, options.scene.keep_scene));
  std::cout << DescribeScene(options.scene.scene, servers[0].scene->info())
            << (load.private_copy() ? " (a private copy)" : "") << std::endl;
  GS_ASSIGN_OR_RETURN(Workload workload, Workload::Create(spec, servers[0].scene->info()));
  InterfererSetup interferer;
  if (interferer_options) {
    GS_ASSIGN_OR_RETURN(interferer,
                        StartInterferer(*interferer_options, options, connection, servers[0]));
  }

  const std::string pacing = options.update_hz > 0.0
                                 ? absl::StrCat("open loop at ", options.update_hz, " Hz")
                                 : "closed loop (one update per frame)";
  std::cout << "workload " << WorkloadName(spec) << ": " << workload.description() << "; " << pacing
            << "; " << options.solver.solver << " at " << options.view.width << "x"
            << options.view.height << ", fps cap "
            << (options.fps > 0.0f ? FormatFixed(options.fps, 0) : std::string("server default"))
            << std::endl;

  std::atomic<bool> interrupted{false};
  ScopedInterruptHandler on_interrupt([&](int) { interrupted = true; });
  Progress progress(StderrIsTty());
  std::vector<StepResult> steps;
  nlohmann::json converge = nlohmann::json::array();  // per step, with --reference-spp
  // One row per frame of each step's first session (--reference-spp).
  std::string frames_csv = kFramesCsvHeader;
  for (size_t i = 0; i < options.sessions.size() && !interrupted; ++i) {
    const int count = options.sessions[i];
    const std::string label = absl::StrCat("[step ", i + 1, "/", options.sessions.size(), ": ",
                                           count, count == 1 ? " session]" : " sessions]");
    if (!StderrIsTty()) std::cout << label << " running" << std::endl;
    SettleTrace trace;
    GS_ASSIGN_OR_RETURN(
        StepResult step,
        RunStep(options, connection, load, servers, workload, interferer.interferer.get(), count,
                label, progress, interrupted, options.reference_spp > 0 ? &trace : nullptr));
    if (options.reference_spp > 0 && !interrupted) {
      converge.push_back(MeasureConvergence(*servers[0].connection, load, options, trace, label,
                                            int(i + 1), frames_csv));
    }
    PrintStep(label, step);
    steps.push_back(std::move(step));
  }
  if (steps.empty()) return absl::CancelledError("interrupted before the first step ended");
  GS_RETURN_IF_ERROR(ReportBench(
      options, steps,
      BenchMeta(options, connection, addresses, servers[0].last, spec, workload, pacing, converge),
      frames_csv));
  if (interrupted) return InterruptedError();
  return absl::OkStatus();
}

}  // namespace gistream::client
