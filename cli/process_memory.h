#pragma once
// How the process's heap hands memory back, set once by each binary's main(): a library sets no
// process-wide state of its own.

namespace pluvia {

// llvmpipe mallocs and frees its vertex and binning buffers (megabytes) on every draw, and the
// rain planes of a frame are megabytes too. glibc gives a block above its mmap threshold back to
// the kernel when it is freed, so every frame faulted those pages in again: 20 ms of a 720x480
// frame of 80k streaks, and most of the fixed cost of a frame. Raising the thresholds keeps
// freed blocks in the heap for the next frame; the heap then holds its high-water mark, which a
// clip of steady rain reaches on its first frame (memory stays flat).
void keepFreedBlocksForTheNextFrame();

}  // namespace pluvia
