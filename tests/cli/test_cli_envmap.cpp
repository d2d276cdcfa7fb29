// `pluvia envmap` and lighting.source "stitch" end to end: the real weir photos stitched as a
// pan, an HDR projected onto SH, a locked-off plate taken as static, and the stitched
// environment cached so a second render does not stitch again.
#include <cmath>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_support.h"
#include "util/fs.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

TEST(CliEnvmap, WeirPhotosStitchAsAPanIntoSixteenCoefficients) {
  if (sharedData().empty()) GTEST_SKIP() << "../shared/data absent";
  const auto dir = freshTempDir("cli_envmap_weir");
  const CommandResult r =
      runPluvia({"-q", "envmap", (sharedData() / "stitching/weir/weir_%d.jpg").string(), "-o",
                 (dir / "env.json").string(), "--panorama-out", (dir / "pano.exr").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto env = nlohmann::json::parse(fs::readTextFile(dir / "env.json"));
  EXPECT_EQ(env.at("motion"), "pan");
  ASSERT_EQ(env.at("keys").size(), 1u);
  EXPECT_TRUE(env.at("keys")[0].at("from_features").get<bool>());
  EXPECT_EQ(env.at("keys")[0].at("sh").size(), 16u);
  // Three overlapping photos of about 30 deg: a few percent of the sphere.
  const double covered = env.at("keys")[0].at("covered_fraction").get<double>();
  EXPECT_GT(covered, 0.01);
  EXPECT_LT(covered, 0.1);
  EXPECT_EQ(env.at("frames").size(), 3u);
  const Image pano = readImageFile(dir / "pano.exr");
  EXPECT_EQ(pano.width, 2 * pano.height);
}

TEST(CliEnvmap, UniformHdrProjectsOntoTheConstantCoefficient) {
  const auto dir = freshTempDir("cli_envmap_hdr");
  Image uniform(64, 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) std::fill(uniform.pixel(x, y), uniform.pixel(x, y) + 3, 0.5f);
  writeImageFile(dir / "uniform.exr", uniform);
  // The panorama goes into a folder that does not exist yet, made as -o's is (adversarial S27:
  // it failed after the work).
  const CommandResult r =
      runPluvia({"-q", "envmap", "--hdr", (dir / "uniform.exr").string(), "-o",
                 (dir / "env.json").string(), "--panorama-out", (dir / "new" / "p.exr").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(stdfs::exists(dir / "new" / "p.exr"));
  const auto sh = nlohmann::json::parse(fs::readTextFile(dir / "env.json")).at("keys")[0].at("sh");
  // L = 0.5 everywhere: c00 = 0.5 * Y00 * 4 pi = 0.5 * sqrt(4 pi), every other coefficient 0.
  EXPECT_NEAR(sh[0][0].get<double>(), 0.5 * std::sqrt(4.0 * M_PI), 1e-3);
  // (to the texel-centre quadrature of a 64 x 32 map: about 1e-3 of c00 leaks into band 2)
  for (size_t i = 1; i < sh.size(); ++i) EXPECT_NEAR(sh[i][1].get<double>(), 0.0, 2e-3) << i;
}

TEST(CliEnvmap, LockedOffPlateIsStaticAndTheStitchedEnvironmentIsCached) {
  const auto dir = freshTempDir("cli_envmap_static");
  const CommandResult r = runPluvia({"-q", "envmap", exampleClip().string(), "-o",
                                     (dir / "env.json").string(), "--frames", "0-11"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto env = nlohmann::json::parse(fs::readTextFile(dir / "env.json"));
  EXPECT_EQ(env.at("motion"), "static");
  EXPECT_EQ(env.at("keys").size(), 1u);

  const std::vector<std::string> render = {"-q",
                                           "render",
                                           exampleClip().string(),
                                           "-p",
                                           "moderate",
                                           "-o",
                                           (dir / "f.####.png").string(),
                                           "--frames",
                                           "3-3",
                                           "--set",
                                           "lighting.source=stitch",
                                           "--cache",
                                           (dir / "cache").string()};
  ASSERT_EQ(runPluvia(render).exitCode, 0);
  const CommandResult plan =
      runPluvia({"plan", exampleClip().string(), "-p", "moderate", "--set",
                 "lighting.source=stitch", "--cache", (dir / "cache").string()});
  EXPECT_NE(plan.output.find("cached  lighting"), std::string::npos) << plan.output;
  EXPECT_TRUE(stdfs::exists(dir / "f.0003.png"));
}

TEST(CliEnvmap, BadLightsNameTheItem) {
  const auto dir = freshTempDir("cli_envmap_lights");
  fs::writeTextFile(
      dir / "lights.json",
      R"([{"type": "direction", "yaw_deg": 0, "pitch_deg": 30, "radiance": [1, -2, 1]}])");
  const CommandResult r =
      runPluvia({"envmap", exampleClip().string(), "-o", (dir / "env.json").string(), "--lights",
                 (dir / "lights.json").string()});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  expectOutputHas(r.output, {"light 0", "lights.json"});
  EXPECT_FALSE(stdfs::exists(dir / "env.json"));
}

TEST(CliEnvmap, RefusesToOverwriteTheFootage) {
  const auto dir = freshTempDir("cli_envmap_overwrite");
  Image plate(48, 32);
  writeImageFile(dir / "plate.png", plate);
  const std::string before = fs::readTextFile(dir / "plate.png");
  for (const std::vector<std::string>& outputs :
       {std::vector<std::string>{"-o", (dir / "plate.png").string()},
        std::vector<std::string>{"-o", (dir / "env.json").string(), "--panorama-out",
                                 (dir / "plate.png").string()}}) {
    std::vector<std::string> args = {"envmap", (dir / "plate.png").string()};
    args.insert(args.end(), outputs.begin(), outputs.end());
    const CommandResult r = runPluvia(args);
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("refusing to overwrite"), std::string::npos) << r.output;
    EXPECT_EQ(fs::readTextFile(dir / "plate.png"), before);
  }
}
