#pragma once
#include <string>

namespace pluvia {

// `pluvia bench --lod 0,0.5,1,...`: the rain stage's time and picture error per rain.lod_px
// (see bench_lod.cpp).
void runLodBench(const std::string& lodList, const std::string& size, int frames,
                 double rateMmPerHour);

}  // namespace pluvia
