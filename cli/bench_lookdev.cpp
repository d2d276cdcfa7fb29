#include "bench_lookdev.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <vector>

#include <fmt/format.h>

#include "bench_floors.h"
#include "bench_timing.h"
#include "io/clip_reader.h"
#include "temporary_folder.h"

namespace pluvia::cli {
namespace stdfs = std::filesystem;
namespace {

constexpr double kGoalSeconds = 2.0;  // issue 31: a look change at proxy 0.5, warm cache

// The look changes timed warm: each touches only per-frame stages.
const std::vector<std::string> kLookChanges = {"rain.rate_mm_h=20", "rain.wind.speed_m_s=4",
                                               "rain.opacity=0.7", "fog.density=0.003",
                                               "darken.amount=0.3"};

}  // namespace

LookdevTimes runLookdevBench(const std::string& input, const std::string& preset) {
  const TemporaryFolder temporary("pluvia-bench-lookdev");
  const stdfs::path& folder = temporary.path();
  const std::string plate = input.empty() ? exampleSequence(folder, 24, 1001, "png") : input;
  const std::string cache = (folder / "cache").string();
  // The plate's middle frame (a render from there pays no pre-roll: rain at any frame costs
  // the same).
  const std::vector<int64_t> frames = openClip(plate)->info().frames;
  const std::string frame = std::to_string(frames[frames.size() / 2]);
  int run = 0;
  auto render = [&](const std::string& set) {
    std::vector<std::string> args = {"--proxy", "0.5",      "--cache",
                                     cache,     "--frames", frame + "-" + frame};
    if (!set.empty()) args.insert(args.end(), {"--set", set});
    const stdfs::path out = folder / fmt::format("run{}", ++run);
    stdfs::create_directories(out);
    return timedRender(exrOutputIn(out), plate, preset, args);
  };
  std::cout << fmt::format("bench lookdev: {} with preset {}, one frame at --proxy 0.5\n",
                           input.empty() ? "a 1080p PNG sequence of the bundled example" : plate,
                           preset);
  std::cout << fmt::format("{:<28} {:>9}\n", "render", "seconds");
  const double cold = render("");
  std::cout << fmt::format("{:<28} {:>9.2f}\n", "cold (fresh --cache)", cold);
  std::vector<double> warm;
  for (const std::string& change : kLookChanges) {
    warm.push_back(render(change));
    std::cout << fmt::format("{:<28} {:>9.2f}\n", "--set " + change, warm.back());
  }
  const double typical = median(warm);
  std::cout << fmt::format(
      "warm look change: median {:.2f} s (goal <= {:g} s: {}); warm / cold: {:.2f}\n", typical,
      kGoalSeconds, typical <= kGoalSeconds ? "met" : "not met", typical / cold);
  return {cold, typical};
}

}  // namespace pluvia::cli
