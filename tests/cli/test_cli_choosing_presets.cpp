// Choosing a preset and finding one's way: `pluvia presets`, `preview --presets`, the man page,
// the bash completion, and the ocio:// message on an OpenColorIO that has no built-in configs.
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "test_support.h"
#include "util/subprocess.h"

using namespace pluvia::test;
namespace stdfs = std::filesystem;

TEST(CliChoosingPresets, PresetsListsEveryShippedPresetWithWhatItSets) {
  const auto table = runPluvia({"presets"});
  ASSERT_EQ(table.exitCode, 0) << table.output;
  const auto listed = runPluvia({"presets", "--json"});
  ASSERT_EQ(listed.exitCode, 0) << listed.output;
  const nlohmann::json presets = nlohmann::json::parse(listed.output);
  std::vector<std::string> names;
  for (const auto& preset : presets) names.push_back(preset["name"]);
  EXPECT_EQ(names, (std::vector<std::string>{"drizzle", "gentle", "moderate", "hard", "heavy",
                                             "storm", "base"}))
      << "lightest rain first, base (what the others extend) last";
  // The values are the presets' own: heavy.json says 40 mm/h, 2 m/s of wind, fog 0.0037.
  const nlohmann::json& heavy = presets[4];
  EXPECT_EQ(heavy["rate_mm_h"], 40);
  EXPECT_EQ(heavy["wind_speed_m_s"], 2.0);
  EXPECT_EQ(heavy["fog_density_per_m"], 0.0037);
  EXPECT_EQ(heavy["exposure_s"], 0.0);
  EXPECT_NE(heavy["description"].get<std::string>().find("'heavy' rain: 40 mm/h"),
            std::string::npos);
  EXPECT_NE(table.output.find("heavy             40        2   0.0037"), std::string::npos)
      << table.output;
  EXPECT_NE(table.output.find("    Mizukami et al. Table 1 'heavy' rain"), std::string::npos);
  // A preset folder of one's own is listed with the shipped ones.
  const stdfs::path dir = freshTempDir("presets_own");
  writeTextFile(
      dir, "yard.json",
      R"({"pluvia": 1, "extends": "hard", "description": "the yard", "rain": {"rate_mm_h": 22}})");
  const pluvia::ProcessResult own = pluvia::runProcess(
      {"env", "PLUVIA_PRESET_DIR=" + dir.string(), pluviaBinary().string(), "presets"});
  ASSERT_EQ(own.exitCode, 0) << own.output;
  EXPECT_LT(own.output.find("hard "), own.output.find("yard "));
  EXPECT_LT(own.output.find("yard "), own.output.find("heavy "));
  EXPECT_NE(own.output.find("    the yard"), std::string::npos) << own.output;
}

TEST(CliChoosingPresets, PreviewPresetsDrawsARowPerPresetAtTheSameFrame) {
  const stdfs::path dir = freshTempDir("preview_presets");
  const std::string plate = writeTexturedPlate(dir, 1, 3, 64, 48);
  const stdfs::path sheetPath = dir / "sheet.png";
  auto r = runPluvia({"preview", plate, "--presets", "drizzle,storm", "-o", sheetPath.string(),
                      "--set", "rain.seed=4"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("wrote " + sheetPath.string() + " (2 rows at 64x48)"), std::string::npos)
      << r.output;
  const pluvia::Image sheet = readImageFile(sheetPath);
  const int band = 16, rowHeight = band + 48;
  ASSERT_EQ(sheet.width, 4 * 64);
  ASSERT_EQ(sheet.height, 2 * rowHeight);
  // Both rows show the same plate frame (the middle one, 2); storm's rain layer holds more light
  // than drizzle's (100 against 1.5 mm/h).
  double plateDifference = 0.0, rainLight[2] = {0.0, 0.0};
  for (int y = band; y < rowHeight; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 3; ++c) {
        const auto at = [&](int row, int column) {
          return sheet.rgba[(size_t(row * rowHeight + y) * sheet.width + column * 64 + x) * 4 + c];
        };
        plateDifference = std::max(plateDifference, double(std::abs(at(0, 0) - at(1, 0))));
        for (int row = 0; row < 2; ++row) rainLight[row] += at(row, 2);
      }
  EXPECT_EQ(plateDifference, 0.0);
  EXPECT_GT(rainLight[1], 3.0 * rainLight[0])
      << "storm " << rainLight[1] << " drizzle " << rainLight[0];
  // A mistake in any preset is said before a frame is rendered, and no sheet is written.
  const stdfs::path badSheet = dir / "bad.png";
  r = runPluvia({"preview", plate, "--presets", "drizzle,stomr", "-o", badSheet.string()});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  expectOutputHas(r.output, {"stomr", "did you mean 'storm'?"});
  EXPECT_FALSE(stdfs::exists(badSheet));
  r = runPluvia({"preview", plate, "-o", badSheet.string()});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  expectOutputHas(r.output, {"give -p PRESET, or --presets"});
  r = runPluvia({"preview", plate, "-p", "heavy", "--presets", "storm", "-o", badSheet.string()});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_FALSE(stdfs::exists(badSheet));
}

TEST(CliChoosingPresets, TheManPageHasEveryCommandAndOptionAndRendersCleanly) {
  const auto page = runPluvia({"man"});
  ASSERT_EQ(page.exitCode, 0) << page.output;
  for (const std::string& needle :
       {".TH PLUVIA 1", ".SS \"pluvia render\"", ".SS \"pluvia farm resubmit\"",
        ".SS \"pluvia report realism\"", ".B \\-\\-exr\\-compression", ".B \\-\\-presets",
        ".SH EXIT STATUS", "2 usage error", ".SH ENVIRONMENT", "PLUVIA_RAIN_BACKEND"})
    EXPECT_NE(page.output.find(needle), std::string::npos) << needle;
  // man formats it without a warning (groff's -ww warnings on stderr).
  const stdfs::path dir = freshTempDir("man_page");
  const stdfs::path file = writeTextFile(dir, "pluvia.1", page.output);
  const pluvia::ProcessResult formatted =
      pluvia::runProcess({"sh", "-c", "groff -ww -z -man '" + file.string() + "' 2>&1"});
  EXPECT_EQ(formatted.exitCode, 0);
  EXPECT_EQ(formatted.output, "") << formatted.output;
}

TEST(CliChoosingPresets, BashCompletionOffersCommandsOptionsAndPresets) {
  const auto script = runPluvia({"completion"});
  ASSERT_EQ(script.exitCode, 0) << script.output;
  const stdfs::path dir = freshTempDir("completion");
  const stdfs::path file = writeTextFile(dir, "pluvia.bash", script.output);
  // What bash offers after each command line (the last word is the one being completed).
  const auto offered = [&](const std::string& words) {
    const pluvia::ProcessResult r = pluvia::runProcess(
        {"bash", "-c",
         "cd '" + dir.string() + "' && source '" + file.string() + "' && COMP_WORDS=(" + words +
             ") && COMP_CWORD=$((${#COMP_WORDS[@]} - 1)) && _pluvia && echo \"${COMPREPLY[*]}\""});
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return r.output.substr(0, r.output.find('\n'));
  };
  EXPECT_EQ(offered("pluvia re"), "render report");
  EXPECT_EQ(offered("pluvia farm s"), "slurm status");
  EXPECT_EQ(offered("pluvia farm slurm --sb"), "--sbatch-arg");
  EXPECT_EQ(offered("pluvia -q render x.mp4 --exr-c"), "--exr-compression");
  EXPECT_EQ(offered("pluvia render x.mp4 -p h"), "hard heavy");
  EXPECT_EQ(offered("pluvia render pluvia.b"), "pluvia.bash");  // files for INPUT
}

TEST(CliChoosingPresets, AnOcioUriSaysWhichOpenColorIoItNeeds) {
  // --version names the OpenColorIO pluvia runs with: "pluvia 0.1.0 (OpenColorIO 2.1.2)".
  const auto version = runPluvia({"--version"});
  ASSERT_EQ(version.exitCode, 0) << version.output;
  const size_t at = version.output.find("(OpenColorIO ");
  ASSERT_NE(at, std::string::npos) << version.output;
  const std::string ocio = version.output.substr(at + 13, version.output.find(')', at) - at - 13);
  int major = 0, minor = 0;
  ASSERT_EQ(std::sscanf(ocio.c_str(), "%d.%d", &major, &minor), 2) << ocio;
  if (major > 2 || (major == 2 && minor >= 2))
    GTEST_SKIP() << "OpenColorIO " << ocio << " has built-in configs";
  const stdfs::path dir = freshTempDir("ocio_uri");
  const std::string plate = writeTexturedPlate(dir, 1, 1);
  const auto r = runPluvia({"plan", plate, "-p", "moderate", "--ocio", "ocio://default"});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  expectOutputHas(r.output, {"ocio://default", "need OpenColorIO 2.2 or later",
                             "runs with OpenColorIO " + ocio});
}
