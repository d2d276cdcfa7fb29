// Fuzzing preset loading and validation in-process (issue 16): thousands of mutated preset files
// and --set lines. Every case either resolves or throws pluvia::Error whose problems are one
// line each: never a crash, never another exception type.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include "fuzz_mutations.h"
#include "preset/preset.h"
#include "stages/registry.h"
#include "test_support.h"
#include "util/fs.h"

using namespace pluvia;
namespace stdfs = std::filesystem;

namespace {

constexpr uint32_t kSeed = 16;
constexpr int kFileCases = 3000;
constexpr int kSetCases = 3000;

// Runs one case: test::expectCleanOutcome, where a PresetError must also have its problems one
// line each.
void expectCleanPresetOutcome(const std::function<void()>& call, const std::string& which) {
  test::expectCleanOutcome(
      [&] {
        try {
          call();
        } catch (const PresetError& e) {
          EXPECT_FALSE(e.problems().empty()) << which;
          for (const std::string& problem : e.problems())
            EXPECT_EQ(problem.find('\n'), std::string::npos) << which << "\n" << problem;
        }
      },
      which);
}

std::vector<std::string> schemaKeys(const Schema& schema) {
  std::vector<std::string> keys{"extends",
                                "pluvia",
                                "description",
                                "depth.layers.0.distance_m",
                                "camera.path.0.frame",
                                "lighting.lights.0.radiance"};
  for (const SectionSpec& section : schema)
    for (const ParamSpec& param : section.params) keys.push_back(section.name + "." + param.key);
  return keys;
}

}  // namespace

TEST(FuzzPresets, MutatedPresetFiles) {
  const Schema schema = presetSchema();
  std::vector<std::string> originals;
  for (const auto& entry : stdfs::directory_iterator(test::sourceDir() / "presets"))
    originals.push_back(fs::readTextFile(entry.path()));
  originals.push_back(fs::readTextFile(test::sourceDir() / "examples/street/street.json"));
  const stdfs::path dir = test::freshTempDir("fuzz_presets");
  const stdfs::path file = dir / "case.json";
  test::Mutator mutator(kSeed);
  for (int i = 0; i < kFileCases; ++i) {
    const std::string text = mutator.mutateText(mutator.pick(originals));
    std::ofstream(file, std::ios::binary | std::ios::trunc) << text;
    expectCleanPresetOutcome([&] { Preset::resolve(file.string(), {}, schema); },
                             "file case " + std::to_string(i) + ":\n" + text.substr(0, 2000));
    if (HasFailure()) break;  // one reproducible case is enough
  }
}

TEST(FuzzPresets, MutatedSetLines) {
  const Schema schema = presetSchema();
  const std::vector<std::string> keys = schemaKeys(schema);
  const std::vector<std::string> keySuffixes{
      "", "", "", ".0", ".1", ".x", ".99999999999999999999", ".keys.0.1", ".", ".."};
  test::Mutator mutator(kSeed + 1);
  for (int i = 0; i < kSetCases; ++i) {
    std::vector<std::string> sets;
    const size_t count = 1 + mutator.below(3);
    for (size_t s = 0; s < count; ++s) {
      std::string value = mutator.hostileValue();
      if (mutator.below(3) == 0) value = mutator.mutateText(value);
      sets.push_back(mutator.pick(keys) + mutator.pick(keySuffixes) + "=" + value);
    }
    std::string which = "--set case " + std::to_string(i) + ":";
    for (const std::string& s : sets) which += " '" + s + "'";
    expectCleanPresetOutcome([&] { Preset::resolve("moderate", sets, schema); }, which);
    if (HasFailure()) break;
  }
}
