// What a render refuses, `pluvia validate` refuses too, and values no shot has are refused
// where they are read (adversarial pass, issue 59): each case below exited 0 from validate (or
// rendered) before.
#include <gtest/gtest.h>

#include "test_support.h"
#include "util/subprocess.h"

using namespace pluvia::test;
namespace stdfs = std::filesystem;

TEST(CliValidateChecks, ValidateSaysWhatTheRenderWouldRefuse) {
  struct Case {
    std::vector<std::string> sets;
    std::string says;
  };
  const std::vector<Case> cases{
      {{"lighting.source=hdr"}, "lighting.hdr names no file"},
      {{"fog.skylight_table=63"}, "fog.skylight_table must be even"},
      {{"depth.source=file", "depth.file=z.####.exr", "depth.file_encoding=normalized",
        "depth.file_near_m=10", "depth.file_far_m=5"},
       "depth.file_far_m (5) must be beyond depth.file_near_m (10)"},
      {{R"(lights.list=[{"type": "spot", "dir_x": 0, "dir_y": 0, "dir_z": 0}])"},
       "lights.list[0]: a spot's axis (dir_x, dir_y, dir_z) = (0, 0, 0) has no length"},
      {{"camera.fps=1e-300"}, "camera.fps 1e-300 is under 1 frame a second"},
      {{"camera.fps=24", "camera.exposure_s=1"},
       "camera.exposure_s 1 s is longer than a frame at 24 fps"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args{"validate", "moderate"};
    for (const std::string& set : c.sets) args.insert(args.end(), {"--set", set});
    const auto r = runPluvia(args);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("valid (hash"), std::string::npos) << r.output;
  }
  EXPECT_EQ(runPluvia({"validate", "moderate"}).exitCode, 0);
}

TEST(CliValidateChecks, ARenderRefusesAnExposureLongerThanThePlatesFrame) {
  const stdfs::path dir = freshTempDir("validate_exposure");
  const std::string plate = writeTexturedPlate(dir, 1, 1);  // 24 fps
  const auto r = runPluvia({"render", plate, "-p", "moderate", "-o", (dir / "o.####.png").string(),
                            "--set", "camera.exposure_s=0.5"});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  expectOutputHas(r.output, {"camera.exposure_s 0.5 s is longer than a frame at 24 fps"});
  EXPECT_FALSE(stdfs::exists(dir / "o.0001.png"));
}

TEST(CliValidateChecks, EmptyFramesNanFovAndHugeStartFramesAreUsageErrors) {
  const stdfs::path dir = freshTempDir("validate_usage");
  const std::string plate = writeTexturedPlate(dir, 1, 2);
  const std::string out = (dir / "o.####.png").string();
  const auto empty = runPluvia({"render", plate, "-p", "moderate", "-o", out, "--frames", ""});
  EXPECT_EQ(empty.exitCode, 2) << empty.output;
  expectOutputHas(empty.output, {"--frames", "is empty"});
  EXPECT_FALSE(stdfs::exists(dir / "o.0001.png"));
  const auto fov = runPluvia({"envmap", plate, "-o", (dir / "env.json").string(), "--fov", "nan"});
  EXPECT_EQ(fov.exitCode, 2) << fov.output;
  expectOutputHas(fov.output, {"'nan' is not a finite number"});
  EXPECT_FALSE(stdfs::exists(dir / "env.json"));
  const auto start = runPluvia({"render", exampleClip().string(), "-p", "moderate", "-o", out,
                                "--start-frame", "9223372036854775807"});
  EXPECT_EQ(start.exitCode, 2) << start.output;
  expectOutputHas(start.output, {"--start-frame"});
}

// An option that does nothing for the output asked for was ignored without a word.
TEST(CliValidateChecks, OptionsThatDoNothingForTheOutputAreUsageErrors) {
  const stdfs::path dir = freshTempDir("validate_output_options");
  const std::string plate = writeTexturedPlate(dir, 1, 1);
  const auto exr = runPluvia({"render", plate, "-p", "moderate", "-o", (dir / "o.mp4").string(),
                              "--exr-type", "float", "--exr-compression", "dwaa"});
  EXPECT_EQ(exr.exitCode, 2) << exr.output;
  expectOutputHas(exr.output, {"--exr-type applies to EXR output", "o.mp4 is not EXR"});
  const auto tiff = runPluvia({"render", plate, "-p", "moderate", "-o",
                               (dir / "o.####.exr").string(), "--tiff-type", "float"});
  EXPECT_EQ(tiff.exitCode, 2) << tiff.output;
  expectOutputHas(tiff.output, {"--tiff-type applies to TIFF output", "o.####.exr is not TIFF"});
  const auto codec = runPluvia({"render", plate, "-p", "moderate", "-o",
                                (dir / "o.####.png").string(), "--codec", "prores_4444"});
  EXPECT_EQ(codec.exitCode, 2) << codec.output;
  expectOutputHas(codec.output, {"--codec applies to a movie"});
  EXPECT_FALSE(stdfs::exists(dir / "o.mp4"));
  EXPECT_FALSE(stdfs::exists(dir / "o.0001.png"));
}

// A broken colour config from $OCIO fails `plan` as it fails `render`: a plan that says all is
// well would send a farm job to fail on every node.
TEST(CliValidateChecks, ABrokenOcioConfigFailsThePlanAsTheRender) {
  const stdfs::path dir = freshTempDir("validate_ocio");
  const std::string plate = writeTexturedPlate(dir, 1, 1);
  const stdfs::path config = writeTextFile(dir, "bad.ocio", "garbage: [\n");
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{"plan", plate, "-p", "moderate"},
        std::vector<std::string>{"render", plate, "-p", "moderate", "-o",
                                 (dir / "o.####.png").string()}}) {
    std::vector<std::string> argv{"env", "OCIO=" + config.string(), pluviaBinary().string()};
    argv.insert(argv.end(), command.begin(), command.end());
    const pluvia::ProcessResult r = pluvia::runProcess(argv);
    EXPECT_EQ(r.exitCode, 1) << command[0] << "\n" << r.output;
    expectOutputHas(r.output, {"cannot load the OpenColorIO config", "bad.ocio (from $OCIO)"});
  }
  EXPECT_FALSE(stdfs::exists(dir / "o.0001.png"));
}
