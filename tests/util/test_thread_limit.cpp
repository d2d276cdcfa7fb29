// --threads: one cap for pluvia's own bands and TBB's pool, restored afterwards.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <thread>

#include "util/thread_limit.h"

namespace pluvia {
namespace {

size_t tbbParallelism() {
  return tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
}

TEST(ThreadLimit, CapsTbbAndOurOwnPoolsAndRestoresThem) {
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  EXPECT_EQ(threadLimit(), hardware);
  const size_t tbbBefore = tbbParallelism();
  {
    const ThreadLimit cap(1);
    EXPECT_EQ(threadLimit(), 1);
    EXPECT_EQ(tbbParallelism(), 1u);
  }
  EXPECT_EQ(threadLimit(), hardware);
  EXPECT_EQ(tbbParallelism(), tbbBefore);
}

}  // namespace
}  // namespace pluvia
