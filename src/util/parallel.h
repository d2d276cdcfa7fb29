#pragma once
// The one way pluvia runs a loop in parallel, as OpenImageIO routes every image op through one
// helper: over TBB's threads, under the process's cap (util/thread_limit.h). Each call returns
// when every item is done; items must not depend on each other's order.
#include <cstddef>
#include <functional>

namespace pluvia {

// block(begin, end) over blocks [begin, end) covering [0, count), each of at least `grain`
// items where there are that many (TBB's automatic partitioning).
void forEachBlock(size_t count, size_t grain, const std::function<void(size_t, size_t)>& block);

// item(i) for every i in [0, count), i of count's type.
template <class Index, class Item>
void forEachIndex(Index count, const Item& item) {
  forEachBlock(count > 0 ? size_t(count) : 0, 1, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) item(Index(i));
  });
}

// row(y) for every row y in [0, rows) of an image.
template <class Row>
void forEachRow(int rows, const Row& row) {
  forEachIndex(rows, row);
}

}  // namespace pluvia
