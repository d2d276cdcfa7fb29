#include "process_memory.h"

#include <malloc.h>

namespace pluvia {

void keepFreedBlocksForTheNextFrame() {
  constexpr int kMmapThresholdBytes = 32 << 20;  // glibc's largest on 64-bit
  constexpr int kTrimThresholdBytes = 512 << 20;
  mallopt(M_MMAP_THRESHOLD, kMmapThresholdBytes);
  mallopt(M_TRIM_THRESHOLD, kTrimThresholdBytes);
}

}  // namespace pluvia
