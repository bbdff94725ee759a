// Cooperative cancellation of a solver's background job (issue 30): the
// engine dropped the solver, or the server is stopping. The job runs under
// its stop token (CancellationScope, installed by BackgroundJob); long
// loops ask Cancelled() once per step (an iteration, a link task) and end
// early, leaving a result the job's owner discards. The pool's ParallelFor
// carries the caller's token to the workers that help it and starts no
// index once it is cancelled, so a loop of many small tasks stops within
// one task.
//
// Only for work whose result is thrown away when cancelled: a frame's
// cancellation is explicit (SolverContext::stop), since a ParallelFor that
// skipped indices of a shared solver's update would leave state other
// sessions go on to use.
//
// A thread-local token rather than a parameter through every solver
// function: the loops that must stop are deep (link recursion, transport
// steps), their callers many, and a token forgotten on one path would make
// that path uncancellable without a sign.
#pragma once

#include <stop_token>

namespace gistream {

// The token of the work running on this thread (none: never cancelled).
std::stop_token CurrentStopToken();

// Whether the work running on this thread was asked to stop (one atomic
// load: cheap enough for a recursion step).
bool Cancelled();

// Installs `token` as this thread's for its lifetime, then restores the
// previous one (scopes nest: a frame's work inside a job's keeps both in
// the sense that the innermost decides).
class CancellationScope {
 public:
  explicit CancellationScope(std::stop_token token);
  ~CancellationScope();
  CancellationScope(const CancellationScope&) = delete;
  CancellationScope& operator=(const CancellationScope&) = delete;

 private:
  std::stop_token previous_;
};

}  // namespace gistream
