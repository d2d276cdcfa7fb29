// --skip-existing keeps a frame only when this render would write it alike (adversarial S10):
// a proxy frame, a frame of another plate, of another AOV set or colour config is rendered again
// and named. The cache knows a plate replaced in place with the same size and time (S9), and a
// malformed cache entry is measured again instead of crashing the render (S6).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_support.h"
#include "util/fs.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

std::vector<std::string> render(const std::string& plate, const stdfs::path& out,
                                std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {"render", plate,        "-p",       "gentle",
                                   "-o",     out.string(), "--frames", "1-2"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// A facility's OCIO config (linear and an sRGB-encoded space) as dir/facility.ocio.
stdfs::path writeFacilityConfig(const stdfs::path& dir) {
  return writeTextFile(dir, "facility.ocio", R"(ocio_profile_version: 2
roles: {default: lin, scene_linear: lin, texture_paint: srgb}
file_rules:
  - !<Rule> {name: Default, colorspace: lin}
colorspaces:
  - !<ColorSpace> {name: lin, encoding: scene-linear}
  - !<ColorSpace>
    name: srgb
    encoding: sdr-video
    to_scene_reference: !<ExponentWithLinearTransform> {gamma: 2.4, offset: 0.055}
)");
}

}  // namespace

TEST(CliResumeIdentity, SkipExistingRendersAgainWhatThisRenderWouldWriteOtherwise) {
  const stdfs::path dir = freshTempDir("resume_identity");
  for (const char* sub : {"p", "q"}) stdfs::create_directories(dir / sub);
  const std::string plate = writeTexturedPlate(dir / "p", 1, 2, 64, 48);
  const stdfs::path out = dir / "o" / "r.####.png";

  ASSERT_EQ(runPluvia(render(plate, out, {"--proxy", "0.5"})).exitCode, 0);
  auto r = runPluvia(render(plate, out, {"--skip-existing"}));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  expectOutputHas(r.output, {"2 existing frames rendered again", "pluvia:size '32x24'"});
  EXPECT_EQ(readImageFile(dir / "o" / "r.0001.png").width, 64);

  // The same render again keeps both.
  r = runPluvia(render(plate, out, {"--skip-existing"}));
  expectOutputHas(r.output, {"every frame exists, nothing to do"});

  // Another plate of the same size and names.
  const std::string other = writePixelPlate(dir / "q", 1, 2, 64, 48, [](float* p, int x, int, int) {
    p[0] = p[1] = p[2] = float(x) / 64.0f;
  });
  r = runPluvia(render(other, out, {"--skip-existing"}));
  expectOutputHas(r.output, {"2 existing frames rendered again", "from another plate"});

  // A facility's OCIO config from $OCIO in place of the built-in one: the preset (and its hash)
  // is the same, the frames are not.
  const stdfs::path config = writeFacilityConfig(dir);
  std::vector<std::string> withOcio = {"env", "OCIO=" + config.string(), pluviaBinary().string()};
  for (const std::string& arg : render(other, out, {"--skip-existing"})) withOcio.push_back(arg);
  const auto facility = runProcess(withOcio);
  ASSERT_EQ(facility.exitCode, 0) << facility.output;
  expectOutputHas(facility.output, {"2 existing frames rendered again", "pluvia:colour"});
  r = runPluvia(render(other, out, {"--skip-existing"}));
  expectOutputHas(r.output, {"2 existing frames rendered again", "pluvia:colour"});

  // Another AOV set (the rain AOV's own files are wanted now).
  r = runPluvia(render(other, out, {"--skip-existing", "--aov", "rain"}));
  expectOutputHas(r.output, {"2 existing frames rendered again", "pluvia:aovs 'none'"});
  EXPECT_TRUE(stdfs::exists(dir / "o" / "r.rain.0002.png"));
}

// A local resume over a farm's frames: the farm spelled the plate and the colour config
// absolute, the artist relative (and through a link). One plate, one config: nothing to redo.
TEST(CliResumeIdentity, SpellingsOfOnePlateAndConfigAreOneIdentity) {
  const stdfs::path dir = freshTempDir("resume_spelling");
  stdfs::create_directories(dir / "p");
  const std::string plate = writeTexturedPlate(dir / "p", 1, 2, 64, 48);
  const stdfs::path config = writeFacilityConfig(dir);
  stdfs::create_symlink(config, dir / "link.ocio");
  const stdfs::path out = dir / "o" / "r.####.png";
  ASSERT_EQ(runPluvia(render(plate, out, {"--ocio", config.string()})).exitCode, 0);
  const ProcessResult r = runProcess(
      {"sh", "-c", "cd \"$1\" && shift && exec \"$@\"", "sh", dir.string(), pluviaBinary().string(),
       "render", "p/plate.####.png", "-p", "gentle", "-o", "./o/../o/r.####.png", "--frames", "1-2",
       "--ocio", "link.ocio", "--skip-existing"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  expectOutputHas(r.output, {"every frame exists, nothing to do"});
}

TEST(CliResumeIdentity, APlateReplacedInPlaceIsNotLitFromTheOldCache) {
  const stdfs::path dir = freshTempDir("resume_cache");
  for (const char* sub : {"a", "b"}) stdfs::create_directories(dir / sub);
  const std::string plate = writeTexturedPlate(dir / "a", 1, 3, 64, 48);
  writePixelPlate(dir / "b", 1, 3, 64, 48, [](float* p, int x, int y, int) {
    p[0] = float(y) / 48.0f;
    p[1] = 0.9f;
    p[2] = float(x) / 64.0f;
  });
  const stdfs::path cache = dir / "cache";
  ASSERT_EQ(runPluvia({"prepare", plate, "-p", "moderate", "--cache", cache.string()}).exitCode, 0);
  // Each frame replaced by another of the same size, its time set back to the old one's.
  for (int f = 1; f <= 3; ++f) {
    const std::string name = "plate.000" + std::to_string(f) + ".png";
    const auto time = stdfs::last_write_time(dir / "a" / name);
    stdfs::copy_file(dir / "b" / name, dir / "a" / name, stdfs::copy_options::overwrite_existing);
    stdfs::last_write_time(dir / "a" / name, time);
  }
  const auto r =
      runPluvia({"render", plate, "-p", "moderate", "-o", (dir / "o" / "r.####.png").string(),
                 "--cache", cache.string(), "--require-cache", "--frames", "1"});
  // The old entry is not this plate's: --require-cache finds none for it.
  EXPECT_NE(r.exitCode, 0) << r.output;
  EXPECT_FALSE(stdfs::exists(dir / "o" / "r.0001.png"));
}

TEST(CliResumeIdentity, AMalformedCacheEntryIsMeasuredAgain) {
  const stdfs::path dir = freshTempDir("resume_malformed");
  const std::string plate = writeTexturedPlate(dir, 1, 3, 64, 48);
  const stdfs::path cache = dir / "cache";
  ASSERT_EQ(runPluvia({"prepare", plate, "-p", "moderate", "--cache", cache.string()}).exitCode, 0);
  stdfs::path entry;
  for (const auto& file : stdfs::directory_iterator(cache))
    if (file.path().filename().string().rfind("lighting-", 0) == 0) entry = file.path();
  ASSERT_FALSE(entry.empty());
  // A crash (an empty stitch) and an allocation of 240 GB (sizes its samples do not match); a
  // missing or mistyped field takes the json error path the test of the first one covers.
  for (const std::string& bad :
       {R"({"stitched": []})",
        R"({"frame":{"width":200000,"height":100000,"rgb":[],"horizon_rgb":[0,0,0]}})"}) {
    std::ofstream(entry, std::ios::trunc) << bad;
    const stdfs::path out = dir / "o" / "r.####.png";
    stdfs::remove_all(dir / "o");
    const auto r = runPluvia({"render", plate, "-p", "moderate", "-o", out.string(), "--cache",
                              cache.string(), "--frames", "1"});
    EXPECT_EQ(r.exitCode, 0) << bad << "\n" << r.output;
    EXPECT_NE(r.output.find("ignoring the malformed cache entry"), std::string::npos) << bad << "\n"
                                                                                      << r.output;
    EXPECT_TRUE(stdfs::exists(dir / "o" / "r.0001.png")) << bad;
  }
}
