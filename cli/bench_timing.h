#pragma once
// What every `pluvia bench` mode times with: the median of a run of measurements, and the
// process's CPU time.
#include <vector>

namespace pluvia {

// The middle value (the mean of the two middle values for an even count); 0 for none.
double median(std::vector<double> values);

// CPU time of the whole process (every thread, llvmpipe's rasteriser threads included), in ms:
// on a machine shared with other jobs it varies less than the wall time.
double processCpuMs();

}  // namespace pluvia
