// Presets that are hostile or impossible (issue 16): deep nesting, huge numbers, indexes past
// any list, files that are not presets; each is refused with a message naming the file or key,
// never a crash, never the bytes of a file.
#include <gtest/gtest.h>

#include <fstream>

#include "preset/preset.h"
#include "stages/registry.h"
#include "test_support.h"

using namespace pluvia;

namespace {

std::filesystem::path writePreset(const std::filesystem::path& dir, const std::string& name,
                                  const std::string& text) {
  auto path = dir / name;
  std::ofstream(path) << text;
  return path;
}

// The message of the PresetError that resolving gives; fails the test when there is none.
std::string errorOf(const std::string& preset, const std::vector<std::string>& sets = {}) {
  try {
    Preset::resolve(preset, sets, presetSchema());
  } catch (const PresetError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for " << preset;
  return "";
}

std::string nested(int levels) {
  return std::string(levels, '[') + std::string(levels, ']');
}

}  // namespace

TEST(PresetLimits, DeepNestingIsRefusedNamingTheFile) {
  auto dir = test::freshTempDir("preset_deep");
  auto path =
      writePreset(dir, "deep.json", "{\"pluvia\": 1, \"description\": " + nested(60000) + "}");
  const std::string message = errorOf(path.string());
  EXPECT_NE(message.find("deep.json"), std::string::npos) << message;
  EXPECT_NE(message.find("nest deeper than 64 levels at line 1"), std::string::npos) << message;
  // Through --set too.
  const std::string set = errorOf("drizzle", {"rain.seed=" + nested(60000)});
  EXPECT_NE(set.find("--set rain.seed"), std::string::npos) << set;
  // 64 levels are fine as far as nesting goes (the key is still the wrong type).
  EXPECT_EQ(errorOf("drizzle", {"description=" + nested(64)}).find("nest deeper"),
            std::string::npos);
}
