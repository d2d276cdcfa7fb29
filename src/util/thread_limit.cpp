#include "util/thread_limit.h"

#include <algorithm>
#include <atomic>
#include <thread>

#include <tbb/global_control.h>

namespace pluvia {
namespace {
std::atomic<int> gLimit{0};  // 0: none set
}  // namespace

int threadLimit() {
  const int limit = gLimit.load();
  return limit > 0 ? limit : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

struct ThreadLimit::Impl {
  int previous = 0;
  tbb::global_control tbbCap;
  Impl(int threads, int previousLimit)
      : previous(previousLimit),
        tbbCap(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads)) {}
};

ThreadLimit::ThreadLimit(int threads) {
  threads = std::max(1, threads);
  impl_ = std::make_unique<Impl>(threads, gLimit.exchange(threads));
}

ThreadLimit::~ThreadLimit() {
  gLimit = impl_->previous;
}

}  // namespace pluvia
