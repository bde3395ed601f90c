// The BLAS thread count for a scope (blas_threads.hpp): OpenBLAS's setters found with
// dlsym, a process-wide nesting depth under a mutex.

#include "ncp/blas_threads.hpp"

#include <dlfcn.h>

#include <mutex>
#include <stdexcept>
#include <string>

namespace ncp {
namespace {

struct OpenBlasThreadApi {
  int (*get)() = nullptr;
  void (*set)(int) = nullptr;
  bool found() const { return get != nullptr && set != nullptr; }
};

const OpenBlasThreadApi& OpenBlas() {
  static const OpenBlasThreadApi api = [] {
    OpenBlasThreadApi a;
    a.get = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
    a.set =
        reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    return a;
  }();
  return api;
}

// The process-wide state of the guards: how many are alive, and the count to restore.
struct GuardState {
  std::mutex mutex;
  int depth = 0;
  int saved_threads = 0;
};

GuardState& Guards() {
  static GuardState state;
  return state;
}

}  // namespace

bool BlasThreadsAdjustable() { return OpenBlas().found(); }

int BlasThreads() { return OpenBlas().found() ? OpenBlas().get() : -1; }

ScopedBlasThreads::ScopedBlasThreads(int threads) {
  if (threads < 0)
    throw std::invalid_argument("ncp::ScopedBlasThreads: threads must be >= 0, got " +
                                std::to_string(threads));
  const OpenBlasThreadApi& api = OpenBlas();
  if (threads == 0 || !api.found()) return;
  GuardState& state = Guards();
  std::lock_guard<std::mutex> lock(state.mutex);
  if (state.depth == 0) state.saved_threads = api.get();
  ++state.depth;
  engaged_ = true;
  if (api.get() > threads) api.set(threads);
}

ScopedBlasThreads::~ScopedBlasThreads() {
  if (!engaged_) return;
  GuardState& state = Guards();
  std::lock_guard<std::mutex> lock(state.mutex);
  if (--state.depth == 0 && OpenBlas().get() != state.saved_threads)
    OpenBlas().set(state.saved_threads);
}

}  // namespace ncp
