// End-to-end: `pluvia preview` (the contact sheet) and `pluvia render --proxy`, on a few small
// frames the tests write.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "image/color.h"
#include "image/contact_sheet.h"
#include "image/resize.h"
#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

constexpr int kPlateWidth = 160;
constexpr int kPlateHeight = 120;
constexpr int kBand = ContactSheet::kLabelBandPx;
const std::string kExamplePreset = (sourceDir() / "examples/street/street.json").string();

// Frames first..last of a 160x120 plate: smooth gradients with a few hard-edged blocks, so a
// resize has edges to get wrong, written as 8-bit sRGB PNG.
std::string writePlate(const stdfs::path& dir, int first, int last) {
  return writePixelPlate(dir, first, last, kPlateWidth, kPlateHeight,
                         [](float* p, int x, int y, int f) {
                           const bool block = ((x + 2 * f) / 20 + y / 20) % 3 == 0;
                           p[0] = 0.2f + 0.6f * float(x) / kPlateWidth;
                           p[1] = block ? 0.8f : 0.3f;
                           p[2] = 0.2f + 0.5f * float(y) / kPlateHeight;
                         });
}

// An 8-bit sRGB picture shrunk to `size` the way a proxy render does it: in linear light, with
// the area filter.
Image shrinkDisplayImage(Image image, cv::Size size) {
  ColorConverter("sRGB", "linear-rec709").apply(image);
  Image small = resizeArea(image, size);
  ColorConverter("linear-rec709", "sRGB").apply(small);
  return small;
}

// The contact sheet's tile in `row`, `column` (tiles of tileSize, each under a label band).
Image sheetTile(const Image& sheet, cv::Size tileSize, int row, int column) {
  Image tile(tileSize.width, tileSize.height);
  const int left = column * tileSize.width, top = row * (kBand + tileSize.height) + kBand;
  for (int y = 0; y < tileSize.height; ++y)
    for (int x = 0; x < tileSize.width; ++x)
      for (int c = 0; c < 4; ++c) tile.pixel(x, y)[c] = sheet.pixel(left + x, top + y)[c];
  return tile;
}

// Mean and largest absolute RGB difference.
std::pair<double, double> rgbDifference(const Image& a, const Image& b) {
  double sum = 0, largest = 0;
  for (size_t i = 0; i < a.pixelCount(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = std::fabs(a.rgba[i * 4 + c] - b.rgba[i * 4 + c]);
      sum += d;
      largest = std::max(largest, d);
    }
  return {sum / (3.0 * double(a.pixelCount())), largest};
}

std::string fileBytes(const stdfs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

}  // namespace

TEST(CliPreview, SheetHasPlateRainedRainAndDepthForEachSampledFrame) {
  auto dir = freshTempDir("preview_sheet");
  auto plate = writePlate(dir, 1, 5);
  auto sheetPath = dir / "sheet.png";
  auto r = runPluvia({"preview", plate, "-p", "heavy", "-o", sheetPath.string(), "--count", "3",
                      "--proxy", "0.5", "--set", "rain.seed=3", "--set", "blur.sigma_px=1"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("proxy render (not a final): 80x60"), std::string::npos) << r.output;
  // Blur is in pixels: at half size, half as many.
  EXPECT_NE(r.output.find("proxy: blur.sigma_px 1 -> 0.5"), std::string::npos) << r.output;
  const cv::Size tileSize(kPlateWidth / 2, kPlateHeight / 2);
  Image sheet = readImageFile(sheetPath);
  EXPECT_EQ(sheet.width, 4 * tileSize.width);
  EXPECT_EQ(sheet.height, 3 * (kBand + tileSize.height));
  EXPECT_NE(fileBytes(sheetPath).find("pluvia:proxy"), std::string::npos);
  for (const auto& e : stdfs::directory_iterator(dir))
    EXPECT_EQ(e.path().string().find("pluvia-tmp"), std::string::npos) << e.path();

  // Rows are frames 1, 3 and 5 (spread over 1-5). Row 2's plate is frame 5 at half size: the
  // same as shrinking it here but for the sheet's 8-bit rounding (measured: 0.33 codes on
  // average, 0.5 at most).
  Image expected = shrinkDisplayImage(readImageFile(dir / "plate.0005.png"), tileSize);
  Image plateTile = sheetTile(sheet, tileSize, 2, 0);
  auto [plateMean, plateLargest] = rgbDifference(plateTile, expected);
  EXPECT_LT(plateMean, 0.5 / 255) << "plate column against the shrunk input frame";
  EXPECT_LT(plateLargest, 1.0 / 255);

  // The rained frame differs from the plate on a good share of its pixels, the rain layer shows
  // rain over black, and the depth column shows the ground
  // (grey) below the horizon, not only sky.
  Image rained = sheetTile(sheet, tileSize, 2, 1), rain = sheetTile(sheet, tileSize, 2, 2);
  Image depth = sheetTile(sheet, tileSize, 2, 3);
  size_t changed = 0, rainy = 0, ground = 0;
  for (size_t i = 0; i < rained.pixelCount(); ++i) {
    if (std::fabs(rained.rgba[i * 4 + 1] - plateTile.rgba[i * 4 + 1]) > 2.5 / 255) ++changed;
    if (rain.rgba[i * 4 + 1] > 2.5 / 255) ++rainy;
    if (std::fabs(depth.rgba[i * 4] - depth.rgba[i * 4 + 2]) < 0.5 / 255)
      ++ground;  // grey, not sky blue
  }
  EXPECT_GT(changed, rained.pixelCount() / 50);
  EXPECT_GT(rainy, rained.pixelCount() / 50);
  EXPECT_GT(ground, rained.pixelCount() / 4);  // the ground plane: the lower half
}

TEST(CliPreview, RowsAreTheFramesARenderGives) {
  // The sheet's rained column is a render of that frame: same session, same simulation.
  auto dir = freshTempDir("preview_matches_render");
  auto plate = writePlate(dir, 1, 4);
  auto r = runPluvia({"preview", plate, "-p", "heavy", "-o", (dir / "sheet.png").string(),
                      "--count", "1", "--frames", "2-4"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  r = runPluvia(
      {"render", plate, "-p", "heavy", "-o", (dir / "out.####.png").string(), "--frames", "3-3"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const cv::Size tileSize(kPlateWidth, kPlateHeight);  // 160 px wide: no proxy by default
  Image sheet = readImageFile(dir / "sheet.png");
  ASSERT_EQ(sheet.width, 4 * kPlateWidth);
  Image rendered = readImageFile(dir / "out.0003.png");  // the middle of 2-4
  Image rained = sheetTile(sheet, tileSize, 0, 1);
  // Below the label band the two are the same 8-bit codes.
  EXPECT_EQ(rgbDifference(rained, rendered).second, 0.0);
}

TEST(CliPreview, WithoutProxyTheColumnsAreAtMost480PxWide) {
  // The bundled 768x576 movie: shrunk by 0.625 to 480x360.
  auto dir = freshTempDir("preview_default_proxy");
  auto r = runPluvia({"preview", exampleClip().string(), "-p", kExamplePreset, "-o",
                      (dir / "sheet.png").string(), "--count", "2"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("proxy render (not a final): 480x360"), std::string::npos) << r.output;
  Image sheet = readImageFile(dir / "sheet.png");
  EXPECT_EQ(sheet.width, 4 * 480);
  EXPECT_EQ(sheet.height, 2 * (kBand + 360));
}

TEST(CliRender, ProxyRendersAtHalfSizeWhatTheFullRenderGivesShrunk) {
  auto dir = freshTempDir("render_proxy");
  auto plate = writePlate(dir, 1, 3);
  // The depth from the camera's geometry (the ground plane), not guessed from the picture; no
  // blur, which does not commute exactly with the shrink (its scaling is checked on the sheet).
  // Rain drawn to 8 m: the 160 px camera's own depth (rain.far_m 0: 0.666 m, checked below) holds
  // too few drops to compare the two renders by. A 1/600 s shutter: at this one-frame plate's own
  // (the 180-degree shutter, 1/48 s) the streaks are so faint that the proxy loses 41 % of their
  // light under the alpha floor (below).
  const std::vector<std::string> common{"-p",       "heavy",
                                        "--frames", "3-3",
                                        "--set",    "rain.seed=7",
                                        "--set",    "depth.source=layers",
                                        "--set",    "blur.sigma_px=0",
                                        "--set",    "rain.far_m=8",
                                        "--set",    "camera.exposure_s=0.0016667"};
  auto render = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args{"render", plate, "-o", (dir / out).string()};
    args.insert(args.end(), common.begin(), common.end());
    args.insert(args.end(), extra.begin(), extra.end());
    auto r = runPluvia(args);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return r.output;
  };
  render("full.####.png", {});
  render("fullDry.####.png", {"--set", "rain.enabled=false"});
  const std::string log = render("proxy.####.png", {"--proxy", "0.5"});
  EXPECT_NE(log.find("proxy render (not a final): 80x60"), std::string::npos) << log;
  render("proxyDry.####.png", {"--proxy", "0.5", "--set", "rain.enabled=false"});
  render("proxy.####.exr", {"--proxy", "0.5"});
  EXPECT_NE(fileBytes(dir / "proxy.0003.exr").find("pluvia:proxy"), std::string::npos);

  Image proxy = readImageFile(dir / "proxy.0003.png");
  ASSERT_EQ(proxy.width, kPlateWidth / 2);
  ASSERT_EQ(proxy.height, kPlateHeight / 2);
  const cv::Size half(proxy.width, proxy.height);
  Image proxyDry = readImageFile(dir / "proxyDry.0003.png");
  Image full = shrinkDisplayImage(readImageFile(dir / "full.0003.png"), half);
  Image fullDry = shrinkDisplayImage(readImageFile(dir / "fullDry.0003.png"), half);

  // Without rain every stage (darken, depth, fog, lighting) does at the proxy size what it does
  // on the full frame: the proxy is the full render shrunk, within the 8-bit rounding and the
  // edge of the sky found in the plate, where darken's weight by depth jumps from the ground's to
  // the sky's within a proxy pixel (measured: 0.3 codes on average, 10 at most).
  const auto [dryMean, dryLargest] = rgbDifference(proxyDry, fullDry);
  EXPECT_LT(dryMean, 0.5 / 255);
  EXPECT_LT(dryLargest, 12.0 / 255);
  // The rain adds about as much light at the proxy size as on the full frame: the same drops,
  // rasterised at half the resolution (measured: 31 % less at the 1/600 s day shutter, 22 % at
  // 1/1000 s: the faintest far drops, thinner than the 1.5 px drawn width at half size, fall under
  // the 1/1024 alpha floor), ...
  auto meanGain = [](const Image& wet, const Image& dry) {
    double sum = 0;
    for (size_t i = 0; i < wet.rgba.size(); ++i)
      if (i % 4 != 3) sum += wet.rgba[i] - dry.rgba[i];
    return sum / (3.0 * double(wet.pixelCount()));
  };
  const double proxyRain = meanGain(proxy, proxyDry), fullRain = meanGain(full, fullDry);
  EXPECT_LT(std::fabs(proxyRain / fullRain - 1.0), 0.4) << proxyRain << " against " << fullRain;
  // ... in the same places: pixel by pixel the proxy is off the full render shrunk by a small
  // part of what the rain changes (measured: 43 %; rain in other places would make it 200 %).
  const double proxyToFull = rgbDifference(proxy, full).first;
  const double rainEffect = rgbDifference(full, fullDry).first;
  EXPECT_LT(proxyToFull, 0.6 * rainEffect) << proxyToFull << " against " << rainEffect;

  // rain.far_m 0 counts the full frame's pixels, not the proxy's: both draw the rain as deep.
  const auto drawnDepth = [](const std::string& log) {
    const size_t at = log.find("rain: drops from");
    return at == std::string::npos ? std::string() : log.substr(at, log.find(',', at) - at);
  };
  const std::string fullDepth = drawnDepth(render("autoFull.####.png", {"--set", "rain.far_m=0"}));
  EXPECT_NE(fullDepth.find("to 0.666 m"), std::string::npos) << fullDepth;
  EXPECT_EQ(drawnDepth(render("autoProxy.####.png", {"--proxy", "0.5", "--set", "rain.far_m=0"})),
            fullDepth);
}

TEST(CliPreview, BadValuesAreUsageErrors) {
  auto dir = freshTempDir("preview_usage");
  auto plate = writePlate(dir, 1, 2);
  const std::string sheet = (dir / "sheet.png").string();
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  const std::vector<Case> cases{
      {{"preview", plate, "-p", "heavy", "-o", sheet, "--proxy", "0"}, "--proxy 0: the scale"},
      {{"preview", plate, "-p", "heavy", "-o", sheet, "--proxy", "2"}, "--proxy 2: the scale"},
      {{"preview", plate, "-p", "heavy", "-o", sheet, "--count", "0"}, "--count 0"},
      {{"preview", plate, "-p", "heavy", "-o", (dir / "sheet.jpg").string()}, "is a PNG"},
      {{"preview", plate, "-p", "heavy", "-o", (dir / "plate.0002.png").string()},
       "refusing to overwrite"},
      {{"render", plate, "-p", "heavy", "-o", (dir / "o.####.png").string(), "--proxy", "0"},
       "--proxy 0: the scale"},
      {{"render", plate, "-p", "heavy", "-o", (dir / "o.####.png").string(), "--proxy", "2"},
       "--proxy 2: the scale"},
  };
  for (const Case& c : cases) {
    auto r = runPluvia(c.args);
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << r.output;
  }
  EXPECT_FALSE(stdfs::exists(sheet));
  EXPECT_FALSE(stdfs::exists(dir / "o.0001.png"));
}
