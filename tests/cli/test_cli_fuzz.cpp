// The binary under fuzzed input (issue 16), on a small sample: mutated presets and --set lines
// through `pluvia validate`, and mutated input images through `pluvia render`. The exit code is
// always 0, 1 or 2: never a signal, never an uncaught exception.
#include <gtest/gtest.h>

#include <fstream>

#include "fuzz_mutations.h"
#include "test_support.h"
#include "util/fs.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

constexpr uint32_t kSeed = 1616;

void expectCleanExit(const CommandResult& r, const std::string& which) {
  EXPECT_TRUE(r.exitCode == 0 || r.exitCode == 1 || r.exitCode == 2)
      << which << ": exit " << r.exitCode << "\n"
      << r.output.substr(0, 4000);
  EXPECT_EQ(r.output.find("terminate called"), std::string::npos) << which;
}

}  // namespace

TEST(CliFuzz, ValidateMutatedPresetsAndSetLines) {
  const stdfs::path dir = freshTempDir("cli_fuzz_presets");
  const std::string original = fs::readTextFile(sourceDir() / "presets/storm.json");
  const std::vector<std::string> keys{
      "rain.rate_mm_h", "rain.near_m",  "fog.color",    "depth.layers.0.distance_m", "camera.path",
      "extends",        "rain.strokes", "lighting.hdr", "rain.wind.speed_m_s"};
  Mutator mutator(kSeed);
  // 12 cases of each (24 runs of validate: about 15 s of the suite).
  for (int i = 0; i < 12; ++i) {
    const stdfs::path file = dir / ("case" + std::to_string(i) + ".json");
    std::ofstream(file, std::ios::binary) << mutator.mutateText(original);
    expectCleanExit(runPluvia({"validate", file.string()}), file.string());
    const std::string set = mutator.pick(keys) + "=" + mutator.hostileValue();
    expectCleanExit(runPluvia({"validate", "moderate", "--set", set}), "--set " + set);
  }
}

TEST(CliFuzz, RenderMutatedInputImages) {
  const stdfs::path dir = freshTempDir("cli_fuzz_images");
  Mutator mutator(kSeed + 1);
  Image image(32, 24);
  for (size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = float(i % 17) / 17.0f;
  for (const std::string extension : {"png", "exr"}) {
    const stdfs::path original = dir / ("original." + extension);
    writeImageFile(original, image);
    const std::string bytes = fs::readTextFile(original);
    for (int i = 0; i < 5; ++i) {
      const stdfs::path file = dir / ("case" + std::to_string(i) + "." + extension);
      std::ofstream(file, std::ios::binary) << mutator.mutateBytes(bytes, 512);
      expectCleanExit(runPluvia({"render", file.string(), "-p", "drizzle", "-o",
                                 (dir / ("out" + std::to_string(i) + ".####.exr")).string()}),
                      file.string());
    }
  }
}
