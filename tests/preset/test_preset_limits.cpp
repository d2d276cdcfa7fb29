// Presets that are hostile or impossible (issue 16): deep nesting, huge numbers, indexes past
// any list, files that are not presets; each is refused with a message naming the file or key,
// never a crash, never the bytes of a file.
#include <gtest/gtest.h>

#include <fstream>

#include "preset/preset.h"
#include "rain/stroke_library.h"
#include "stages/registry.h"
#include "test_support.h"

using namespace pluvia;

namespace {

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
  auto path = test::writeTextFile(dir, "deep.json",
                                  "{\"pluvia\": 1, \"description\": " + nested(60000) + "}");
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

TEST(PresetLimits, ImpossibleValuesAreRefusedByValidation) {
  // Drops nearer than they are far: nothing would be drawn.
  EXPECT_NE(errorOf("drizzle", {"rain.near_m=20", "rain.far_m=10"})
                .find("/rain/near_m (20) must be less than /rain/far_m (10)"),
            std::string::npos);
  EXPECT_NE(errorOf("moderate", {"rain.far_m=8", "rain.near_m=20"})
                .find("must be less than /rain/far_m (8)"),
            std::string::npos);
  // far_m 0 (the shipped presets') is resolved from the camera beyond near_m: no conflict.
  EXPECT_NO_THROW(Preset::resolve("moderate", {"rain.near_m=20"}, presetSchema()));
  // Used to pass validation and fail in render.
  EXPECT_NE(errorOf("drizzle", {"rain.min_diameter_mm=6"}).find("/rain/min_diameter_mm"),
            std::string::npos);
  // Keys spanning +-1e308 overflowed between them.
  EXPECT_NE(errorOf("drizzle", {"rain.rate_mm_h=[[-1e308,0],[1e308,1]]"})
                .find("expected a frame number between -1e+15 and 1e+15"),
            std::string::npos);
  // A colour a half float cannot hold.
  EXPECT_NE(errorOf("drizzle", {"fog.color=[1e6,1,1]"}).find("65504"), std::string::npos);
}

TEST(PresetLimits, BadTextNamesTheFileOrKey) {
  auto dir = test::freshTempDir("preset_text");
  auto huge =
      test::writeTextFile(dir, "huge.json", R"({"pluvia": 1, "rain": {"rate_mm_h": 1e400}})");
  const std::string file = errorOf(huge.string());
  EXPECT_NE(file.find("huge.json"), std::string::npos) << file;
  EXPECT_NE(file.find("too large for a double"), std::string::npos) << file;
  const std::string set = errorOf("drizzle", {"rain.rate_mm_h=1e400"});
  EXPECT_NE(set.find("rain.rate_mm_h: 1e400 is too large for a number"), std::string::npos) << set;
  const std::string index = errorOf("drizzle", {"depth.layers=[{\"type\": \"ground\"}]",
                                                "depth.layers.99999999999999999999999=1"});
  EXPECT_NE(index.find("index 99999999999999999999999 is past the end of a list of 1"),
            std::string::npos)
      << index;
  EXPECT_NE(errorOf("drizzle", {"extends=storm"}).find("extends cannot be set"), std::string::npos);
  auto broken = test::writeTextFile(dir, "broken.json", "{\"pluvia\": 1,\n  \"rain\": {oops}}");
  EXPECT_NE(errorOf(broken.string()).find("not valid JSON at line 2, column 12"), std::string::npos)
      << errorOf(broken.string());
}

TEST(PresetLimits, OtherFilesAreNamedNeverQuoted) {
  auto dir = test::freshTempDir("preset_quote");
  // The parser's own message would quote what it read of a number: "last read: '31415926x'".
  const std::string secret = "31415926xsecret-first-line";
  test::writeTextFile(dir, "secret.txt", secret + "\n");
  auto extending = test::writeTextFile(
      dir, "extends.json",
      R"({"pluvia": 1, "extends": ")" + (dir / "secret.txt").string() + R"("})");
  const std::string viaExtends = errorOf(extending.string());
  EXPECT_NE(viaExtends.find("secret.txt"), std::string::npos) << viaExtends;
  EXPECT_EQ(viaExtends.find("31415926"), std::string::npos) << viaExtends;
  try {
    rain::loadStrokeLibrary((dir / "secret.txt").string());
    ADD_FAILURE() << "a text file loaded as a stroke library";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("secret.txt"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("31415926"), std::string::npos) << e.what();
  }
}
