// Compiled by tests/thread_safety/check.sh with clang -Wthread-safety
// -Werror: once as written (must compile) and once with -DVIOLATE (must
// fail), so the annotations the engine relies on are proved to be checked.
#include "absl/base/thread_annotations.h"
#include "util/mutex.h"
#include "util/thread_role.h"

namespace {

class Engine {
 public:
  void FromAnyThread() ABSL_LOCKS_EXCLUDED(mutex_) {
    gistream::MutexLock lock(mutex_);
    ++sessions_;
  }
  void PostedJob() {
    render_role_.Assert();
    DrawOnRenderThread();
  }
#ifdef VIOLATE
  // A client thread touching render-thread state, and a guarded field
  // read without the mutex: both must be compile errors.
  int Wrong() {
    DrawOnRenderThread();
    return sessions_;
  }
#endif

 private:
  void DrawOnRenderThread() ABSL_EXCLUSIVE_LOCKS_REQUIRED(render_role_) { ++frames_; }

  gistream::Mutex mutex_;
  gistream::ThreadRole render_role_{"render thread"};
  int sessions_ ABSL_GUARDED_BY(mutex_) = 0;
  int frames_ ABSL_GUARDED_BY(render_role_) = 0;
};

}  // namespace

int main() {
  Engine engine;
  engine.FromAnyThread();
  engine.PostedJob();
  return 0;
}
