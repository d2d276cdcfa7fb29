// pluvia-bench-strokes: `pluvia bench --strokes` without pluvia's image, video and SfM
// libraries, for a GPU machine that has only its driver: the stroke atlas comes from a JSON
// file (`pluvia bench --strokes N --save-atlas FILE` writes it).
#include <iostream>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench_strokes.h"
#include "process_memory.h"
#include "process_variables.h"
#include "rain/stroke_atlas.h"
#include "util/error.h"
#include "util/fs.h"

int main(int argc, char** argv) {
  using namespace pluvia;
  keepFreedBlocksForTheNextFrame();
  CLI::App app{"pluvia-bench-strokes: frames per second of the rain insertion alone.",
               "pluvia-bench-strokes"};
  std::string atlasPath, strokes = "10000,20000,40000,80000", size = "720x480", backend = "both";
  int frames = 30;
  bool depthPlane = false;
  app.add_option("--atlas", atlasPath, "stroke atlas JSON (pluvia bench --save-atlas)")->required();
  app.add_option("--strokes", strokes, "streak counts (10000,20000,40000,80000)");
  app.add_option("--size", size, "frame size WIDTHxHEIGHT (720x480)");
  app.add_option("--frames", frames, "timed frames per count (30)")->check(CLI::Range(1, 100000));
  app.add_option("--backend", backend, "egl, cpu, auto or both (both)")
      ->check(CLI::IsMember({"egl", "cpu", "auto", "both"}));
  app.add_flag("--depth-plane", depthPlane, "give the frame a scene depth plane (3-50 m)");
  CLI11_PARSE(app, argc, argv);
  try {
    applyRainBackendVariable();
    nlohmann::json json;
    try {
      json = nlohmann::json::parse(fs::readTextFile(atlasPath));
    } catch (const nlohmann::json::parse_error& e) {
      throw Error(fmt::format("{}: not valid JSON (at byte {})", atlasPath, e.byte));
    }
    runStrokeBench(rain::strokeAtlasFromJson(json, atlasPath), strokes, size, frames, depthPlane,
                   backend);
  } catch (const UsageError& e) {
    std::cerr << "pluvia-bench-strokes: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "pluvia-bench-strokes: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
