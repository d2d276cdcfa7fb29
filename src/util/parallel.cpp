#include "util/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace pluvia {

void forEachBlock(size_t count, size_t grain, const std::function<void(size_t, size_t)>& block) {
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, count, grain),
      [&](const tbb::blocked_range<size_t>& range) { block(range.begin(), range.end()); });
}

}  // namespace pluvia
