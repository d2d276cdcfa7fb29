// Two processes that need the same missing cache entry at once: one computes it, the other
// waits for the lock and then reads what the first stored (pipeline/cache_lock.h).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <thread>

#include "pipeline/cache.h"
#include "pipeline/cache_lock.h"
#include "test_support.h"

using namespace pluvia;
namespace stdfs = std::filesystem;

namespace {

// What a stage's prepare() does with its entry: read it, or compute it (slowly, noting each
// computation in `computations`) and store it. Returns 0 when the value read or computed is
// right, 1 when it is not, 2 when this process waited for another.
int prepareEntry(const stdfs::path& cacheDir, const stdfs::path& computations) {
  const ArtifactCache cache(cacheDir);
  const CacheEntryLock lock(cache, "lighting", "k1");
  std::optional<nlohmann::json> value = cache.load("lighting", "k1");
  if (!value) {
    std::ofstream(computations, std::ios::app) << getpid() << "\n";
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    value = nlohmann::json{{"average_rgb", {0.25, 0.5, 0.75}}};
    cache.store("lighting", "k1", *value);
  }
  if (value->at("average_rgb")[1].get<double>() != 0.5) return 1;
  return lock.waited() ? 2 : 0;
}

}  // namespace

TEST(CacheLock, TwoProcessesComputeAMissingEntryOnce) {
  const auto dir = test::freshTempDir("cache_lock_two");
  const stdfs::path cacheDir = dir / "cache";
  const stdfs::path computations = dir / "computations.txt";
  std::vector<pid_t> children;
  for (int i = 0; i < 2; ++i) {
    const pid_t pid = fork();
    if (pid == 0) _exit(prepareEntry(cacheDir, computations));
    children.push_back(pid);
  }
  std::vector<int> codes;
  for (pid_t pid : children) codes.push_back(test::waitForExit(pid));
  std::sort(codes.begin(), codes.end());
  // One computed (0), the other waited for it (2) and read its value: the computation takes
  // 400 ms, far longer than the two forks take to start.
  EXPECT_EQ(codes, (std::vector<int>{0, 2}));
  std::ifstream in(computations);
  int lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  EXPECT_EQ(lines, 1) << "the entry was computed more than once";
  EXPECT_TRUE(ArtifactCache(cacheDir).contains("lighting", "k1"));
  EXPECT_FALSE(stdfs::exists(cacheEntryLockPath(ArtifactCache(cacheDir), "lighting", "k1")))
      << "the last holder removes the lock file";
}
