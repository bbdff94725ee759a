#include "usage.h"

namespace gistream::client {
namespace {

constexpr absl::string_view kOverview =
    R"(usage: gistream [--server ADDR] [--timeout SEC] [--tls --ca FILE] [--token TOKEN]
                COMMAND [OPTIONS]

Thin client of gistreamd, the remote global-illumination render server.

commands:
  solvers   list the solvers, their stages and parameters
  render    render one frame and write it to a file
  stream    open a session and save the frames it streams
  script    play a JSON timeline of updates, one saved frame per step
  eval      error against a path-traced reference and run time, per solver
  bench     load and latency: sessions, update-to-frame latency, fps, stalls
  status    show the server's device, sessions, scenes and frame count
  health    ask grpc.health.v1 whether the server serves (exit 0 if it does)

global options (also accepted after the command):
  --server ADDR   server address (default $GISTREAM_SERVER, else 127.0.0.1:50051)
  --timeout SEC   deadline of each single request (default 300)
  --tls           connect with TLS (the system's root CAs unless --ca)
  --ca FILE       PEM CA that signed the server's certificate (implies --tls)
  --cert FILE     PEM client certificate for mutual TLS, with --key FILE
  --token TOKEN   bearer token (default $GISTREAM_TOKEN; prefer the variable:
                  the command line is visible to other users)
  --affinity KEY  sent as x-gistream-affinity on every call (default
                  $GISTREAM_AFFINITY): a balancer routes calls with one key
                  to one server (deploy/README.md), else it hashes the token
  -h, --help      show help; `gistream COMMAND --help` for a command
  --version       print "gistream VERSION" and exit (on its own)

exit status: 0 on success, 1 on an error (printed as "error: CODE: message"),
2 on a usage error, 130 when interrupted twice.
)";

constexpr absl::string_view kSolvers = R"(usage: gistream [--server ADDR] solvers [--json]

Lists the server's GI solvers: description, stages (in the order they run)
and the parameter schema (name, type, default, range or choices, meaning).

  --json   print the ListSolvers response as protobuf JSON
)";

constexpr absl::string_view kRender =
    R"(usage: gistream [--server ADDR] render --scene NAME_OR_FILE --out FILE
                [--solver NAME] [--param KEY=VALUE]... [--size WxH]
                [--format jpeg|png|exr|h264|hevc|av1] [--quality Q] [--exposure EV]
                [--camera-eye X,Y,Z --camera-target X,Y,Z] [--yfov DEG]
                [--refine-samples N]
                [--environment NAME_OR_FILE] [--environment-intensity X]
                [--keep-scene]

Loads a scene, renders one frame, writes the image bytes to FILE, and prints
a one-line summary and the per-stage timings.

  --scene NAME_OR_FILE   an existing local .glb/.gltf file is uploaded (a
                         .gltf's external buffers and images are inlined);
                         anything else is a scene name on the server
  --solver NAME          GI solver (default direct; see `gistream solvers`)
  --param KEY=VALUE      solver parameter; repeatable
  --size WxH             image size (default 320x240)
  --format F             jpeg, png, exr (linear HDR), or video: h264, hevc,
                         av1 (one key frame; a raw stream ffmpeg reads);
                         default: from the --out extension, else jpeg
  --quality Q            JPEG quality 1..100 (server default 90)
  --exposure EV          stops added before tone mapping (8-bit formats)
  --crf N                video quality 1..51, x264 scale (server default 23)
  --bitrate KBPS         video target bitrate in kbit/s (instead of --crf)
  --key-interval N       video key frame at least every N frames (default 120)
  --send-unchanged       re-send frames whose picture did not change (by
                         default they come without an image; continuous
                         sessions send them only once a second)
  --refine-samples N     samples per pixel of a still view, 1..1024 (server
                         default 16): sub-pixel jittered frames averaged
                         (anti-aliased edges); 1: pixel centres only
  --camera-eye X,Y,Z     camera position; needs --camera-target
  --camera-target X,Y,Z  point the camera looks at (up is +Y)
  --yfov DEG             vertical field of view in degrees
  --environment N_OR_F   equirectangular HDR/EXR environment: a local file
                         is uploaded, else a file name on the server
  --environment-intensity X  environment scale (default 1)
  --keep-scene           leave the scene loaded on the server afterwards
  --out FILE             where to write the image
)";

constexpr absl::string_view kStream =
    R"(usage: gistream [--server ADDR] stream [--scene NAME_OR_FILE] [--solver NAME]
                [--param KEY=VALUE]... [--size WxH] [--format F]
                [--frames N] [--fps F] [--out DIR] [--resume-for SEC]
                [view and scene options]

Opens an interactive session with continuous pacing and saves every frame it
receives as DIR/frame_00000.jpg, frame_00001.jpg, ... (extension by format;
video formats: one raw stream DIR/stream.h264, .hevc or .obu). A still
picture is not re-sent: the server sends a keep-alive frame about once a
second instead, saved as a copy of the last picture (--send-unchanged
turns this off).
At the end prints a per-stage timing table (runs, skipped, CPU and GPU
median/p95 in ms), the frame time median/p95, the achieved frame rate and the
frames the server dropped. Ctrl-C ends the session cleanly and prints the
table; a second Ctrl-C cancels it.
When the server drains (it is shutting down) or goes away, the session
moves: the scene is loaded again through the same address (a balancer
routes it to another server), the session reopened with the same settings,
and frames go on; each move is printed with its time.

  --scene NAME_OR_FILE   default cornell_box (file or name, as for render)
  --solver NAME          default direct
  --param KEY=VALUE      solver parameter; repeatable
  --size WxH             default 320x240
  --format F             jpeg (default), png, exr, h264, hevc or av1
  --frames N             frames to save, keep-alives included (default 30;
                         0: until Ctrl-C); ends sooner when the server
                         says the view is at rest (a finished picture)
  --fps F                frame-rate cap asked of the server (default 30;
                         0: the server's default cap)
  --out DIR              output directory (default out/)
  --resume-for SEC       how long one move may keep trying before the
                         session fails (default 15; 0: never move)
  also: --quality, --exposure, --crf, --bitrate, --key-interval,
        --send-unchanged, --camera-eye, --camera-target, --yfov,
        --refine-samples, --environment, --environment-intensity,
        --keep-scene (see render)
)";

constexpr absl::string_view kScript =
    R"(usage: gistream [--server ADDR] script FILE [--out DIR] [--keep-scene]
                [--resume-for SEC]

Plays the JSON timeline FILE in a session paced on request: for each frame
it sends that frame's updates (increasing seq numbers), asks for one frame,
waits for the frame that includes the last update, and saves it as
DIR/frame_00000.jpg, ... Frames must echo the update seq numbers in order.
At the end prints the same timing table as `stream`. When the server
drains or goes away, the session moves as `stream`'s does (the scene loaded
again through the same address, the updates sent so far replayed, the
frame asked for asked of the new server) and the script goes on.

  --out DIR          output directory (default out/)
  --keep-scene       leave the scene loaded on the server afterwards
  --resume-for SEC   how long one move may keep trying before the script
                     fails (default 15; 0: never move)

The script format is described in README.md (see scenes/cornell_orbit.json):
scene, solver, params, size, format, frames, tracks (camera_orbit,
camera_path, node_path, node_spin, light, material, environment) and events
(protobuf-JSON Update messages at given frames).
)";

constexpr absl::string_view kEval =
    R"(usage: gistream [--server ADDR] eval SPEC [--out DIR] [--cache DIR]

Measures solvers through the running server: for every scene, view, solver
and parameter setting in the JSON SPEC, the error of its float image against
a path-traced reference (relMSE, RMSE, SSIM of tone-mapped luminance, the
fraction of NaN/Inf pixels) and the median/p95 frame time of a full update,
a light-only and a camera-only change; plus the path tracer's own error at
equal time budgets. Writes results.csv, results.json, results.md and
error_vs_time.png (log-log) into DIR and prints the markdown table. A
setting the server refuses (over its memory budget, a bad parameter) is
written down as "not measured" with the server's status, and the run goes
on; losing the server ends it. A scene with an "animation" (a script)
also plays it into one session per setting and compares every frame with
a reference of the state it shows: a second table of the error during
the motion and after it (frames.csv per setting under DIR/animation/).

  --out DIR     output directory (default out/eval)
  --cache DIR   reference images, keyed by scene content, view, size and
                sample count, computed once (default .cache/reference)

See scenes/eval_default.json and README.md for the spec format.
)";

constexpr absl::string_view kBench =
    R"(usage: gistream [--server ADDR[,ADDR...]] bench [--sessions N,N,...]
                [--duration T] [--warmup T]
                [--workload orbit|light|object|mixed|animation|FILE.json]
                [--node NAME_OR_ID] [--update-hz HZ] [--channels shared|per-session]
                [--fps F|uncapped] [--interfere "render ..."] [--out DIR]
                [--reference-spp N [--keep-frames]] [--resume-for SEC]
                [--scene NAME_OR_FILE] [--solver NAME] [--param KEY=VALUE]...
                [--size WxH] [--format jpeg|png|exr] [--quality Q]

Load and latency benchmark. For each session count in --sessions (a step),
opens that many continuous sessions, waits for every first frame, runs
--warmup, then measures for --duration while each session sends the
workload's updates. Per step: update-to-frame latency (send of update seq
to the first frame whose last applied seq is >= seq) p50/p95/p99/max, frame
interval p50/p95 and the longest gap, fps per session and in total, Jain's
fairness index of fps, dropped frames, bytes/s, the server's stage medians,
and the server's RSS and CPU use (GetServerStatus). Prints a table and
writes results.csv, results.json, results.md, latency_cdf.png,
fps_vs_sessions.png and latency_vs_sessions.png into DIR.

  --sessions N,N,...   concurrency steps (default 1,2,4)
  --duration T         measured time per step: 10s, 500ms, 2m (default 10s)
  --warmup T           unmeasured time after the first frames (default 2s)
  --workload W         orbit (camera only), light (a light's intensity and
                       position, or an emitter's strength), object (a mesh
                       node moves), mixed (the three in turn), animation
                       (the scene's own glTF animation, 1/30 s a tick), or
                       a script JSON file whose tracks and events loop
                       (default orbit)
  --node NAME_OR_ID    the node object/mixed move (default: a "block"/"box"
                       node, else the last mesh node)
  --update-hz HZ       open loop: updates at this rate; 0 (default): closed
                       loop, one update per received frame
  --channels C         shared: one gRPC channel per server (default);
                       per-session: a channel and TCP connection each
  --fps F              frame cap per session (default 30; 0: the server's
                       default; uncapped: 240, the highest the server takes)
  --interfere "CMD"    a `render ...` command line (e.g. "render --solver
                       pathtrace --param spp=256 --size 256x256") run in a
                       loop by an extra client during warmup and measurement,
                       on the first server, to measure isolation
  --out DIR            output directory (default out/bench)
  --reference-spp N    any workload, --format exr: after each step, the
                       time to converge of the first session: the frames
                       and ms after the updates stop until relMSE against
                       a pathtrace reference of N spp stays within 5 % of a
                       full solve's (both rendered on a fresh copy of the
                       scene in the final state); in the output as converge.
                       Also every frame of the first session from the
                       window's start against a reference of the state it
                       shows (one per update seq, after the run): DIR/
                       frames.csv (step,session,frame,seq,t_ms,phase,relmse
                       and the convergence stats), and per step relMSE
                       during the motion, the first frame after the stop
                       and the time to within 2x and 1.05x of a full solve;
                       each reference and the updates it applied in DIR/
                       references/step<k>_seq<n>.exr and .json (with
                       --keep-frames each frame too, in DIR/frames/
                       step<k>_frame<n>.exr: a float EXR each). The first
                       session's updates wait for a complete picture (GI
                       done and the still view refined)
  --resume-for SEC     a session whose server drains or dies moves (as in
                       stream) for up to SEC (default 15; 0: it fails);
                       each step then prints the sessions moved and the
                       time without frames and from the failure to the
                       first frame showing every acknowledged update
  --scene, --solver, --param, --size, --format, --quality, --exposure as
  for stream (defaults: cornell_box, direct, 128x128, jpeg).
With several servers (--server a,b) sessions are placed round-robin and
each server loads the scene.
)";

constexpr absl::string_view kStatus = R"(usage: gistream [--server ADDR] status

Prints the server's version and uptime, GL vendor, renderer and version,
CPU and memory use (RSS, GL objects, GPU memory where the driver tells),
the scenes, the frames rendered, and a table of the open sessions (scene,
solver, size, frames, fps, dropped frames, pending updates, last seq).
)";

constexpr absl::string_view kHealth = R"(usage: gistream [--server ADDR] health [--service NAME]

Asks the server's grpc.health.v1 service whether it serves (for container
health checks): prints SERVING and exits 0, or prints the status and exits 1.
No token is needed; over TLS give --tls/--ca as for any command. gistreamd
--health-listen serves this alone in plaintext on a port of its own.

  --service NAME   "" (the whole server, default) or gistream.v1.Gistream
)";

}  // namespace

absl::string_view HelpText(std::optional<Command> command) {
  if (!command) return kOverview;
  switch (*command) {
    case Command::kSolvers: return kSolvers;
    case Command::kRender: return kRender;
    case Command::kStream: return kStream;
    case Command::kScript: return kScript;
    case Command::kStatus: return kStatus;
    case Command::kEval: return kEval;
    case Command::kBench: return kBench;
    case Command::kHealth: return kHealth;
  }
  return kOverview;
}

}  // namespace gistream::client
