// Bad input gets a clear error, a non-zero exit code, and loses nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "test_support.h"
#include "util/fs.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {
Image gradient(int w, int h) {
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = image.pixel(x, y);
      p[0] = float(x + 1) / float(w + 1);
      p[1] = float(y + 1) / float(h + 1);
      p[2] = 0.25f;
    }
  return image;
}

void expectError(const CommandResult& r, int code, const std::string& mentions) {
  EXPECT_EQ(r.exitCode, code) << r.output;
  EXPECT_NE(r.output.find(mentions), std::string::npos) << "expected '" << mentions << "' in:\n"
                                                        << r.output;
  EXPECT_EQ(r.output.find("terminate called"), std::string::npos) << r.output;
}

std::vector<std::string> renderArgs(const std::string& input, const std::string& output) {
  return {"render", input, "-p", "moderate", "-o", output};
}
}  // namespace

TEST(CliErrors, MissingCorruptAndTruncatedInputs) {
  auto dir = freshTempDir("errors_inputs");
  expectError(runPluvia(renderArgs((dir / "nope.mp4").string(), (dir / "o.####.png").string())), 1,
              "nope.mp4");
  std::ofstream(dir / "garbage.png") << "this is not a png at all";
  expectError(runPluvia(renderArgs((dir / "garbage.png").string(), (dir / "o.####.png").string())),
              1, "garbage.png");
  std::ofstream(dir / "empty.exr");
  expectError(runPluvia(renderArgs((dir / "empty.exr").string(), (dir / "o.####.png").string())), 1,
              "empty.exr");
  // Truncated: the first half of a real PNG.
  writeImageFile(dir / "whole.png", gradient(64, 48));
  std::string bytes = fs::readTextFile(dir / "whole.png");
  std::ofstream(dir / "cut.png", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  expectError(runPluvia(renderArgs((dir / "cut.png").string(), (dir / "o.####.png").string())), 1,
              "cut.png");
  // Nothing was written for any of them.
  for (const auto& e : stdfs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().rfind("o.", 0), std::string::npos);
}

TEST(CliErrors, SequenceWithAMissingFrameNamesIt) {
  auto dir = freshTempDir("errors_gap");
  for (int f : {1, 2, 4})
    writeImageFile(dir / ("plate.000" + std::to_string(f) + ".png"), gradient(32, 24));
  expectError(
      runPluvia(renderArgs((dir / "plate.####.png").string(), (dir / "o.####.png").string())), 1,
      "plate.0003.png");
  EXPECT_FALSE(stdfs::exists(dir / "o.0001.png"));
}

TEST(CliErrors, OutputEqualToInputIsRefusedAndTheInputUntouched) {
  auto dir = freshTempDir("errors_overwrite");
  writeImageFile(dir / "plate.0001.png", gradient(32, 24));
  const std::string before = fs::readTextFile(dir / "plate.0001.png");
  auto r =
      runPluvia(renderArgs((dir / "plate.####.png").string(), (dir / "plate.%04d.png").string()));
  expectError(r, 2, "refusing to overwrite");
  EXPECT_EQ(fs::readTextFile(dir / "plate.0001.png"), before);
  auto movie = runPluvia(renderArgs(exampleClip().string(), exampleClip().string()));
  expectError(movie, 2, "refusing to overwrite");
}

TEST(CliErrors, UnwritableOutputAndUsageMistakes) {
  auto dir = freshTempDir("errors_usage");
  writeImageFile(dir / "in.png", gradient(16, 16));
  std::ofstream(dir / "afile") << "x";
  // A folder under a regular file cannot be created, even by root.
  expectError(
      runPluvia(renderArgs((dir / "in.png").string(), (dir / "afile/out.####.png").string())), 1,
      "afile");
  expectError(runPluvia({"render", (dir / "in.png").string(), "-p", "moderate"}), 2, "--output");
  expectError(runPluvia({"render", (dir / "in.png").string(), "-p", "moderate", "-o",
                         (dir / "o.####.png").string(), "--frames", "ten"}),
              2, "--frames 'ten'");
  expectError(runPluvia({"render", (dir / "in.png").string(), "-p", "moderate", "-o",
                         (dir / "o.####.png").string(), "--aov", "sparkle"}),
              2, "sparkle");
  expectError(runPluvia({"render", exampleClip().string(), "-p", "moderate", "-o",
                         (dir / "o.####.png").string(), "--frames", "100-200"}),
              2, "selects no frame");
  expectError(runPluvia({"render", (dir / "in.png").string(), "-p", "moderate", "-o",
                         (dir / "o.####.xyz").string()}),
              1, "xyz");
  expectError(runPluvia({"frobnicate"}), 2, "frobnicate");
  // A missing output folder is made when the folder above it exists; two missing levels are a
  // mistyped path unless --mkdir asks for them, refused before any work and leaving nothing.
  auto r = runPluvia(renderArgs((dir / "in.png").string(), (dir / "new/o.####.png").string()));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(stdfs::exists(dir / "new/o.0000.png"));
  expectError(
      runPluvia(renderArgs((dir / "in.png").string(), (dir / "typo/deeper/o.####.png").string())),
      1,
      "the output folder " + (dir / "typo/deeper").string() +
          " does not exist, nor the folder above it");
  EXPECT_FALSE(stdfs::exists(dir / "typo"));
  std::vector<std::string> args =
      renderArgs((dir / "in.png").string(), (dir / "typo/deeper/o.####.png").string());
  args.push_back("--mkdir");
  r = runPluvia(args);
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(stdfs::exists(dir / "typo/deeper/o.0000.png"));
}

TEST(CliErrors, InvalidPresetRendersNothing) {
  auto dir = freshTempDir("errors_preset");
  writeImageFile(dir / "in.png", gradient(16, 16));
  auto r = runPluvia({"render", (dir / "in.png").string(), "-p", "moderate", "-o",
                      (dir / "o.####.png").string(), "--set", "fog.densty=3", "--set",
                      "rain.rate_mm_h=-1"});
  expectError(r, 2,
              "--set fog.densty=3: /fog/densty: unknown key 'densty' (did you mean 'density'?)");
  EXPECT_NE(r.output.find("/rain/rate_mm_h: must be between 0 and 500"), std::string::npos);
  EXPECT_FALSE(stdfs::exists(dir / "o.0000.png"));
}

TEST(CliErrors, OddTinyGrayAlphaAndDeepInputsRender) {
  auto dir = freshTempDir("errors_formats");
  struct Case {
    std::string name;
    int w, h, channels;
  };
  for (const Case& c :
       {Case{"one.png", 1, 1, 3}, Case{"odd.png", 3, 5, 3}, Case{"gray.png", 17, 9, 1},
        Case{"alpha.png", 20, 10, 4}, Case{"half.exr", 15, 11, 3}, Case{"deep.tif", 12, 8, 3}}) {
    writeImageFile(dir / c.name, gradient(c.w, c.h), c.channels);
    auto out = (dir / (c.name + ".out.####.exr")).string();
    auto r = runPluvia(renderArgs((dir / c.name).string(), out));
    EXPECT_EQ(r.exitCode, 0) << c.name << "\n" << r.output;
    Image image = readImageFile(dir / (c.name + ".out.0000.exr"));
    EXPECT_EQ(image.width, c.w);
    EXPECT_EQ(image.height, c.h);
    for (float v : image.rgba) EXPECT_TRUE(std::isfinite(v)) << c.name;
  }
}

TEST(CliErrors, NanAndInfPixelsAreReplacedNotSpread) {
  auto dir = freshTempDir("errors_nan");
  Image image = gradient(24, 16);
  image.pixel(5, 5)[0] = std::numeric_limits<float>::quiet_NaN();
  image.pixel(6, 5)[1] = std::numeric_limits<float>::infinity();
  writeImageFile(dir / "nan.exr", image);
  auto r = runPluvia({"render", (dir / "nan.exr").string(), "-p", "moderate", "-o",
                      (dir / "o.####.exr").string(), "--set", "rain.rate_mm_h=0", "--set",
                      "fog.density=0", "--set", "darken.amount=0"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("NaN/Inf values"), std::string::npos) << r.output;
  Image out = readImageFile(dir / "o.0000.exr");
  for (float v : out.rgba) EXPECT_TRUE(std::isfinite(v));
  // The blur (moderate keeps sigma 0.6) spreads the replacement 0, never a NaN; far pixels keep
  // their value.
  EXPECT_NEAR(out.pixel(20, 12)[2], 0.25f, 1e-3);
}

// The environment pluvia reads is read once, at the start (cli/process_variables.h): a backend
// it does not know fails the command before any work, naming the variable and its value, and a
// known one draws the rain.
TEST(CliErrors, ARainBackendVariableIsReadAtTheStart) {
  const auto dir = test::freshTempDir("cli_rain_backend_variable");
  auto render = [&](const std::string& backend, const std::string& name) {
    return runProcess({"env", "PLUVIA_RAIN_BACKEND=" + backend, test::pluviaBinary().string(),
                       "render", test::exampleClip().string(), "-p", "moderate", "--proxy", "0.25",
                       "--frames", "0-0", "-o", (dir / name).string(), "-q"});
  };
  const ProcessResult wrong = render("vulkan", "wrong.png");
  EXPECT_EQ(wrong.exitCode, 1) << wrong.output;
  test::expectOutputHas(wrong.output, {"PLUVIA_RAIN_BACKEND is 'vulkan': use auto, egl or cpu"});
  EXPECT_FALSE(std::filesystem::exists(dir / "wrong.png"));
  const ProcessResult cpu = render("CPU", "cpu.png");
  EXPECT_EQ(cpu.exitCode, 0) << cpu.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "cpu.png"));
}
