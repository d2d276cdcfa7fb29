#pragma once
// The stroke benchmark: RainRenderer::render alone, end to end (streak upload, draw, read-back,
// the CPU-side planes), for each streak count on a synthetic stress test and on simulated
// rain, with each backend asked for in one run.
#include <string>

#include "rain/streak_types.h"

namespace pluvia {

// `strokeList`: comma-separated streak counts; `size`: WIDTHxHEIGHT; `frames`: timed renders
// per count (the median after 3 warm-up renders); `backends`: egl, cpu, auto, or both (egl
// then cpu and their ratio).
void runStrokeBench(const rain::StrokeAtlas& atlas, const std::string& strokeList,
                    const std::string& size, int frames, bool depthPlane,
                    const std::string& backends);

}  // namespace pluvia
