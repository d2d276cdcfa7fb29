#pragma once
#include <cstdint>

namespace pluvia {

// Prints the CPU time per frame of the drop simulation for `drops` drops (see bench_drops.cpp).
void runDropBench(int64_t drops, int frames);

}  // namespace pluvia
