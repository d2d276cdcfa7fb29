// pluvia-bench-strokes, the stroke benchmark for a GPU node: it reads the atlas that
// `pluvia bench --strokes --save-atlas` writes (the built-in library's, value for value), times
// the renderer with it, and needs none of pluvia's image, video or SfM libraries.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "rain/stroke_library.h"
#include "test_support.h"
#include "util/fs.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

const stdfs::path benchBinary() {
  return pluviaBinary().parent_path() / "pluvia-bench-strokes";
}

TEST(CliBenchStrokes, SavedAtlasIsTheBuiltInOneAndRunsTheStandaloneBench) {
  const stdfs::path dir = freshTempDir("bench_strokes");
  const stdfs::path atlasPath = dir / "atlas.json";
  CommandResult r = runPluvia({"bench", "--strokes", "50", "--frames", "1", "--backend", "cpu",
                               "--save-atlas", atlasPath.string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;

  const rain::StrokeAtlas saved = rain::strokeAtlasFromJson(
      nlohmann::json::parse(fs::readTextFile(atlasPath)), atlasPath.string());
  const rain::StrokeAtlas builtin = rain::loadStrokeLibrary(rain::builtinStrokeLibraryPath()).atlas;
  EXPECT_EQ(saved.width, builtin.width);
  EXPECT_EQ(saved.height, builtin.height);
  EXPECT_EQ(saved.alpha, builtin.alpha);
  EXPECT_EQ(saved.rects, builtin.rects);

  // An existing file is never overwritten.
  const auto before = stdfs::last_write_time(atlasPath);
  r = runPluvia({"bench", "--strokes", "50", "--frames", "1", "--backend", "cpu", "--save-atlas",
                 atlasPath.string()});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  expectOutputHas(r.output, {"--save-atlas", atlasPath.string(), "exists"});
  EXPECT_EQ(stdfs::last_write_time(atlasPath), before);

  const ProcessResult bench = runProcess({benchBinary().string(), "--atlas", atlasPath.string(),
                                          "--strokes", "50", "--frames", "1", "--backend", "cpu"});
  ASSERT_EQ(bench.exitCode, 0) << bench.output;
  expectOutputHas(bench.output, {"atlas: " + std::to_string(builtin.rects.size()) + " strokes",
                                 "backend cpu", "synthetic stress test", "simulated rain"});

  const ProcessResult missing =
      runProcess({benchBinary().string(), "--atlas", (dir / "none.json").string()});
  EXPECT_EQ(missing.exitCode, 1) << missing.output;
  expectOutputHas(missing.output, {"none.json"});
}

// What lets it run where only a GPU driver is installed: its dynamic libraries.
TEST(CliBenchStrokes, LinksNoneOfPluviasIoLibraries) {
  const ProcessResult r = runProcess({"readelf", "-d", benchBinary().string()});
  if (r.exitCode != 0) GTEST_SKIP() << "readelf is not installed: " << r.output;
  for (const char* library :
       {"OpenImageIO", "OpenColorIO", "avcodec", "colmap", "imgcodecs", "videoio", "stitching"}) {
    EXPECT_EQ(r.output.find(library), std::string::npos) << library << " in:\n" << r.output;
  }
  EXPECT_NE(r.output.find("libepoxy"), std::string::npos) << r.output;
}

}  // namespace
