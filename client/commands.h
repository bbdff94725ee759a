// One function per subcommand. Results go to stdout, warnings to stderr;
// errors come back as a Status (main prints them and picks the exit code).
#pragma once

#include "options.h"
#include "util/status.h"

namespace gistream::client {

absl::Status RunSolvers(const ConnectionOptions& connection, const SolversOptions& options);
absl::Status RunStatus(const ConnectionOptions& connection, const StatusOptions& options);
absl::Status RunHealth(const ConnectionOptions& connection, const HealthOptions& options);
absl::Status RunRender(const ConnectionOptions& connection, const RenderOptions& options);
absl::Status RunStream(const ConnectionOptions& connection, const StreamOptions& options);
absl::Status RunScript(const ConnectionOptions& connection, const ScriptOptions& options);
absl::Status RunEval(const ConnectionOptions& connection, const EvalOptions& options);
// `connection.server` may list several servers, comma separated: sessions
// are placed on them round-robin.
absl::Status RunBench(const ConnectionOptions& connection, const BenchOptions& options);
// One session of `options`' workload, solver and view on a private copy of
// its scene, with --reference-spp (> 0): bench's "converge" entry for it
// (the time to converge and "over_time", the error of every frame shown
// during the motion and after it) as JSON text, null when it could not be
// measured; frames.csv goes to options.out_dir. `gistream eval` runs its
// spec's animations through it.
absl::StatusOr<std::string> RunInteraction(const ConnectionOptions& connection,
                                           const BenchOptions& options);

// What RunStream/RunScript return when a second interrupt cancelled the
// session (main exits 130).
absl::Status InterruptedError();
bool IsInterrupted(const absl::Status& status);

}  // namespace gistream::client
