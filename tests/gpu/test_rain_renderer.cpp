// RainRenderer against analytic expectations: the compositing equation on one streak, the
// depth test, the white furnace, the radiance map term, read-back orientation, determinism,
// input checks, and steady memory over a long run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <numbers>
#include <string>

#include "gpu/rain_renderer.h"
#include "image/equirect.h"
#include "test_support.h"
#include "util/error.h"

namespace pluvia::gpu {
namespace {

// Every test runs on both backends (EGL and the CPU streak rasteriser), one renderer each for
// the whole suite: creating an EGL context costs more than all the renders here.
class RainRendererTest : public ::testing::TestWithParam<RainBackend> {
 protected:
  static void SetUpTestSuite() {
    renderers_[0] = new RainRenderer(32, 24, RainBackend::Egl);
    renderers_[1] = new RainRenderer(32, 24, RainBackend::Cpu);
  }
  static void TearDownTestSuite() {
    for (RainRenderer*& renderer : renderers_) {
      delete renderer;
      renderer = nullptr;
    }
  }
  RainRenderer& renderer() { return *renderers_[GetParam() == RainBackend::Egl ? 0 : 1]; }

  static RainRenderer* renderers_[2];
};
RainRenderer* RainRendererTest::renderers_[2] = {nullptr, nullptr};

// A 2x2 atlas of ones: bilinear sampling anywhere gives exactly 1.
rain::StrokeAtlas solidAtlas() {
  return {2, 2, {1, 1, 1, 1}, {{0, 0, 2, 2}}};
}

rain::ShadingParams constantShading(std::array<float, 3> l0, float backgroundWeight) {
  rain::ShadingParams shading;
  shading.shOrder = 0;
  shading.envSh = {l0};
  shading.transferZonal = {1.0f};
  shading.backgroundWeight = backgroundWeight;
  return shading;
}

Image uniformFrame(int width, int height, std::array<float, 4> rgba) {
  Image frame(width, height);
  for (size_t i = 0; i < frame.pixelCount(); ++i) {
    std::memcpy(frame.rgba.data() + i * 4, rgba.data(), sizeof(rgba));
  }
  return frame;
}

rain::StreakInstance verticalStreak(float x, float headY, float tailY, float width, float alpha,
                                    float depth) {
  return {x, headY, x, tailY, width, alpha, depth, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f};
}

TEST_P(RainRendererTest, SingleStreakFollowsTheCompositingEquation) {
  renderer().setStrokeAtlas(solidAtlas());
  const std::array<float, 4> b{0.2f, 0.4f, 0.8f, 0.75f};
  const std::array<float, 3> l0{1.0f, 2.0f, 3.0f};
  const float c = 0.7f, alpha = 0.6f;
  Image frame = uniformFrame(32, 24, b);
  // Axis-aligned quad: x in [14, 18], y in [3, 19]; no pixel centre is near an edge.
  renderer().render(frame, {verticalStreak(16.0f, 5.0f, 17.0f, 4.0f, alpha, 10.0f)},
                    constantShading(l0, c));

  const float y00 = 0.28209479177387814f;
  for (int ch = 0; ch < 3; ++ch) {
    const float shaded = y00 * l0[ch] + c * b[ch];
    EXPECT_NEAR(frame.pixel(16, 10)[ch], alpha * shaded + (1 - alpha) * b[ch], 1e-6f);
    EXPECT_NEAR(frame.plane("rain." + std::string(1, "RGB"[ch]))[10 * 32 + 16], alpha * shaded,
                1e-6f);
  }
  EXPECT_EQ(frame.pixel(16, 10)[3], b[3]) << "the composite keeps the background's alpha";
  EXPECT_NEAR(frame.plane("rain.A")[10 * 32 + 16], alpha, 1e-7f);
  EXPECT_EQ(frame.plane("matte"), frame.plane("rain.A"));
  // Off the streak: untouched, bit for bit.
  for (auto [x, y] : {std::pair{13, 10}, {18, 10}, {16, 2}, {16, 19}, {0, 0}, {31, 23}}) {
    EXPECT_EQ(std::memcmp(frame.pixel(x, y), b.data(), sizeof(b)), 0) << x << "," << y;
    EXPECT_EQ(frame.plane("rain.A")[y * 32 + x], 0.0f) << x << "," << y;
  }
  // On the streak's boundary rows/columns inside the quad.
  EXPECT_GT(frame.plane("rain.A")[3 * 32 + 14], 0.0f);
  EXPECT_GT(frame.plane("rain.A")[18 * 32 + 17], 0.0f);
}

TEST_P(RainRendererTest, StreakBehindTheSceneLeavesTheFrameUnchanged) {
  renderer().setStrokeAtlas(solidAtlas());
  Image frame = uniformFrame(32, 24, {0.3f, 0.3f, 0.3f, 1.0f});
  frame.plane("depth").assign(frame.pixelCount(), 5.0f);
  const Image before = frame;
  renderer().render(frame, {verticalStreak(16.0f, 4.0f, 18.0f, 4.0f, 1.0f, 6.0f)},
                    constantShading({5, 5, 5}, 0.7f));
  EXPECT_EQ(frame.rgba, before.rgba);
  EXPECT_EQ(frame.plane("rain.A"), std::vector<float>(frame.pixelCount(), 0.0f));

  // The same streak in front of the scene is drawn; an infinite depth counts as far away.
  frame.plane("depth")[10 * 32 + 16] = INFINITY;
  renderer().render(frame,
                    {verticalStreak(16.0f, 4.0f, 18.0f, 4.0f, 1.0f, 4.0f),
                     verticalStreak(16.0f, 4.0f, 18.0f, 4.0f, 0.5f, 1e30f)},
                    constantShading({5, 5, 5}, 0.7f));
  EXPECT_EQ(frame.plane("rain.A")[10 * 32 + 16], 1.0f);
  EXPECT_EQ(frame.plane("rain.A")[11 * 32 + 16], 1.0f);
}

TEST_P(RainRendererTest, ConstantEnvironmentIsAWhiteFurnace) {
  // envSh = 2 sqrt(pi) E in L0 only: C = Y00 * 2 sqrt(pi) * E = E for every view, whatever
  // the higher-order transfer.
  const std::array<float, 3> e{0.25f, 1.5f, 4.0f};
  const float scale = 2.0f * std::sqrt(std::numbers::pi_v<float>);
  rain::ShadingParams shading;
  shading.shOrder = 3;
  shading.envSh.assign(16, {0, 0, 0});
  shading.envSh[0] = {scale * e[0], scale * e[1], scale * e[2]};
  shading.transferZonal = {1.0f, 0.8f, -0.4f, 0.3f};
  shading.backgroundWeight = 0.0f;
  std::vector<rain::StreakInstance> drops;
  const float views[][3] = {{0, 0, 1},  {0, 0, -1},         {1, 0, 0},
                            {0, -1, 0}, {0.6f, 0.0f, 0.8f}, {0.48f, -0.6f, 0.64f}};
  for (int k = 0; k < 6; ++k) {
    const float x = 3.0f + 5.0f * k;
    drops.push_back(
        {x, 8.0f, x, 8.0f, 3.0f, 1.0f, 1.0f, 0.0f, views[k][0], views[k][1], views[k][2], 0.0f});
  }
  renderer().setStrokeAtlas(solidAtlas());
  Image frame = uniformFrame(32, 24, {0, 0, 0, 1});
  renderer().render(frame, drops, shading);
  for (int k = 0; k < 6; ++k) {
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_NEAR(frame.pixel(3 + 5 * k, 8)[ch], e[ch], 1e-6f * e[ch]) << "view " << k;
    }
  }
}

// Radiance that varies smoothly with direction, differently per channel, and stays > 0.2.
EquirectMap smoothRadianceMap(int width, int height) {
  return test::equirectOf(width, height, [](const std::array<double, 3>& d) {
    return std::array<double, 3>{1.0 + 0.6 * d[0], 0.8 + 0.5 * d[1] * d[1] - 0.3 * d[2],
                                 2.0 + d[1] + 0.5 * d[0] * d[2]};
  });
}

TEST_P(RainRendererTest, OpaqueStreakShowsTheRadianceMap) {
  // The map term alone, alpha 1 over black: C' = C = the map's value for the view. c must
  // default to 0, the physically based choice.
  EXPECT_EQ(rain::ShadingParams{}.backgroundWeight, 0.0f);
  rain::ShadingParams shading;
  shading.radianceMap = smoothRadianceMap(128, 64);
  renderer().setStrokeAtlas(solidAtlas());
  // A general view, the map's centre (-Z), near both poles, both sides of the u seam (+Z).
  const float views[][3] = {{0.3f, -0.5f, 0.8f},      {0.0f, 0.0f, -1.0f},  {0.02f, 0.999f, 0.04f},
                            {-0.05f, -0.999f, 0.01f}, {1e-3f, 0.2f, 0.98f}, {-1e-3f, 0.2f, 0.98f}};
  for (const auto& [x, y, z] : views) {
    const float n = std::sqrt(x * x + y * y + z * z);
    rain::StreakInstance streak = verticalStreak(16.0f, 5.0f, 17.0f, 8.0f, 1.0f, 10.0f);
    streak.viewX = x / n;
    streak.viewY = y / n;
    streak.viewZ = z / n;
    Image frame = uniformFrame(32, 24, {0, 0, 0, 1});
    renderer().render(frame, {streak}, shading);
    const std::array<float, 3> expected =
        sampleEquirect(shading.radianceMap, streak.viewX, streak.viewY, streak.viewZ);
    for (auto [px, py] : {std::pair{16, 10}, {13, 2}, {19, 19}}) {
      for (int ch = 0; ch < 3; ++ch) {
        EXPECT_NEAR(frame.pixel(px, py)[ch], expected[ch], 1e-4f * expected[ch])
            << "view " << x << "," << y << "," << z << " at " << px << "," << py;
      }
    }
  }
}

TEST_P(RainRendererTest, ShAndMapTermsAdd) {
  // C = max(SH term, 0) + map: the negative green SH term is clamped before the map adds in.
  renderer().setStrokeAtlas(solidAtlas());
  const std::array<float, 4> b{0.2f, 0.4f, 0.8f, 1.0f};
  const std::array<float, 3> l0{1.0f, -2.0f, 3.0f}, map{0.5f, 0.25f, 2.0f};
  const float c = 0.3f, alpha = 0.6f;
  rain::ShadingParams shading = constantShading(l0, c);
  shading.radianceMap = uniformEquirect(16, 8, map);
  Image frame = uniformFrame(32, 24, b);
  renderer().render(frame, {verticalStreak(16.0f, 5.0f, 17.0f, 4.0f, alpha, 10.0f)}, shading);
  const float y00 = 0.28209479177387814f;
  for (int ch = 0; ch < 3; ++ch) {
    const float shaded = std::max(y00 * l0[ch], 0.0f) + map[ch] + c * b[ch];
    EXPECT_NEAR(frame.pixel(16, 10)[ch], alpha * shaded + (1 - alpha) * b[ch], 1e-6f) << ch;
  }
}

TEST_P(RainRendererTest, FollowsAChangeOfRadianceMap) {
  // Uploads happen only when the map differs from the resident one; a map edited in place
  // or resized must still show.
  renderer().setStrokeAtlas(solidAtlas());
  const std::vector<rain::StreakInstance> streak{
      verticalStreak(16.0f, 5.0f, 17.0f, 4.0f, 1.0f, 1.0f)};
  rain::ShadingParams shading;
  shading.radianceMap = uniformEquirect(16, 8, {1.0f, 2.0f, 3.0f});
  auto centre = [&] {
    Image frame = uniformFrame(32, 24, {0, 0, 0, 1});
    renderer().render(frame, streak, shading);
    return std::array<float, 3>{frame.pixel(16, 10)[0], frame.pixel(16, 10)[1],
                                frame.pixel(16, 10)[2]};
  };
  EXPECT_EQ(centre(), (std::array<float, 3>{1.0f, 2.0f, 3.0f}));
  EXPECT_EQ(centre(), (std::array<float, 3>{1.0f, 2.0f, 3.0f})) << "unchanged map";
  shading.radianceMap.rgb.assign(shading.radianceMap.rgb.size(), 0.5f);
  EXPECT_EQ(centre(), (std::array<float, 3>{0.5f, 0.5f, 0.5f})) << "edited in place";
  shading.radianceMap = uniformEquirect(32, 16, {4.0f, 5.0f, 6.0f});
  EXPECT_EQ(centre(), (std::array<float, 3>{4.0f, 5.0f, 6.0f})) << "resized";
  shading = constantShading({0, 0, 0}, 0.0f);
  EXPECT_EQ(centre(), (std::array<float, 3>{0.0f, 0.0f, 0.0f})) << "map term off";
}

// Rendering with `shading` must throw a pluvia::Error (stage "rain") whose message holds
// `needle`.
void expectShadingError(RainRenderer& renderer, const rain::ShadingParams& shading,
                        const std::string& needle) {
  Image frame(32, 24);
  try {
    renderer.render(frame, {verticalStreak(8, 2, 9, 2, 1, 1)}, shading);
    ADD_FAILURE() << "expected an error about " << needle;
  } catch (const Error& error) {
    EXPECT_EQ(error.context().stage, "rain");
    EXPECT_NE(std::string(error.what()).find(needle), std::string::npos) << error.what();
  }
}

TEST_P(RainRendererTest, RejectsBadRadianceMaps) {
  renderer().setStrokeAtlas(solidAtlas());
  expectShadingError(renderer(), rain::ShadingParams{},
                     "neither SH environment coefficients nor a radiance map");

  rain::ShadingParams shortMap;
  shortMap.radianceMap = uniformEquirect(16, 8, {1, 1, 1});
  shortMap.radianceMap.rgb.pop_back();
  expectShadingError(renderer(), shortMap, "16x8 texels holds 383 floats instead of 384");

  rain::ShadingParams sizeless;
  sizeless.radianceMap.rgb.assign(24, 1.0f);
  expectShadingError(renderer(), sizeless, "0x0 texels holds 24 floats");

  rain::ShadingParams nan;
  nan.radianceMap = uniformEquirect(16, 8, {1, 1, 1});
  nan.radianceMap.texel(3, 2)[1] = NAN;
  expectShadingError(renderer(), nan, "texel (3, 2) has a non-finite G value");
  rain::ShadingParams inf = constantShading({1, 1, 1}, 0.0f);  // an SH term does not excuse the map
  inf.radianceMap = uniformEquirect(16, 8, {1, 1, 1});
  inf.radianceMap.texel(15, 7)[2] = -INFINITY;
  expectShadingError(renderer(), inf, "texel (15, 7) has a non-finite B value");

  // The CPU twin rejects the same.
  Image frame(32, 24);
  EXPECT_THROW(renderRainCpu(frame, {}, nan, solidAtlas()), Error);
}

TEST_P(RainRendererTest, ReadBackPutsTheTopOfThePictureInRowZero) {
  renderer().setStrokeAtlas(solidAtlas());
  Image frame = uniformFrame(32, 24, {0, 0, 0, 1});
  // A horizontal streak across rows 1..2 and a still drop near the bottom-left corner.
  renderer().render(frame,
                    {{4.0f, 2.0f, 28.0f, 2.0f, 2.0f, 1.0f, 1.0f, 0.0f, 0, 0, 1, 0},
                     {2.0f, 21.0f, 2.0f, 21.0f, 2.0f, 1.0f, 1.0f, 0.0f, 0, 0, 1, 0}},
                    constantShading({1, 1, 1}, 0.0f));
  const std::vector<float>& matte = frame.plane("matte");
  for (int y = 0; y < 24; ++y) {
    for (int x = 0; x < 32; ++x) {
      const bool onTopStreak = (y == 1 || y == 2) && x >= 3 && x <= 28;
      const bool onDrop = (y == 20 || y == 21) && (x == 1 || x == 2);
      EXPECT_EQ(matte[y * 32 + x], onTopStreak || onDrop ? 1.0f : 0.0f) << x << "," << y;
    }
  }
}

TEST_P(RainRendererTest, MatteCoordinatesRunAcrossLeftToRightAndAlongHeadToTail) {
  // Atlas 2 x 4: the left column is 0.25, the right 1; rows grow downward by +0 .. (uniform in
  // the right column). Sampled through a wide streak falling down the screen (head at the
  // bottom, tail above), u runs left to right on screen and v from the head (bottom) up.
  rain::StrokeAtlas atlas{
      2, 4, {0.25f, 1.0f, 0.25f, 1.0f, 0.25f, 1.0f, 0.25f, 1.0f}, {{0, 0, 2, 4}}};
  renderer().setStrokeAtlas(atlas);
  Image frame = uniformFrame(32, 24, {0, 0, 0, 1});
  renderer().render(frame, {verticalStreak(16.0f, 18.0f, 6.0f, 8.0f, 1.0f, 1.0f)},
                    constantShading({1, 1, 1}, 0.0f));
  const std::vector<float>& matte = frame.plane("matte");
  EXPECT_EQ(matte[12 * 32 + 12], 0.25f) << "u = 0 on the left of the screen";
  EXPECT_EQ(matte[12 * 32 + 19], 1.0f) << "u = 1 on the right of the screen";

  // Rows: the top atlas row 0.2, the bottom rows 1: the head end (bottom on screen) is faint.
  renderer().setStrokeAtlas({1, 4, {0.2f, 1.0f, 1.0f, 1.0f}, {{0, 0, 1, 4}}});
  renderer().render(frame, {verticalStreak(16.0f, 18.0f, 2.0f, 2.0f, 1.0f, 1.0f)},
                    constantShading({1, 1, 1}, 0.0f));
  EXPECT_EQ(frame.plane("matte")[18 * 32 + 16], 0.2f) << "v = 0 at the head";
  EXPECT_EQ(frame.plane("matte")[4 * 32 + 16], 1.0f) << "v = 1 at the tail";
}

std::vector<rain::StreakInstance> crossingStreaks() {
  std::vector<rain::StreakInstance> streaks;
  for (int i = 0; i < 40; ++i) {
    const float x = 2.0f + (i * 7) % 28, y = 1.0f + (i * 5) % 20;
    const float angle = 0.3f * i;
    streaks.push_back({x, y, x + 9.0f * std::cos(angle), y + 9.0f * std::sin(angle), 1.0f + i % 5,
                       0.2f + 0.02f * i, 1.0f + i % 4, 0.0f, std::sin(angle), 0.3f, std::cos(angle),
                       0.0f});
  }
  return streaks;
}

TEST_P(RainRendererTest, RenderingTwiceIsByteIdentical) {
  renderer().setStrokeAtlas(
      {3, 3, {0.1f, 0.5f, 0.1f, 0.4f, 1.0f, 0.4f, 0.1f, 0.5f, 0.1f}, {{0, 0, 3, 3}}});
  rain::ShadingParams shading = constantShading({0.9f, 1.1f, 1.3f}, 0.7f);
  Image first = uniformFrame(32, 24, {0.3f, 0.2f, 0.1f, 1.0f});
  first.plane("depth").assign(first.pixelCount(), 2.5f);
  Image second = first;
  renderer().render(first, crossingStreaks(), shading);
  renderer().render(second, crossingStreaks(), shading);
  EXPECT_EQ(std::memcmp(first.rgba.data(), second.rgba.data(), first.rgba.size() * 4), 0);
  for (const char* name : {"rain.R", "rain.G", "rain.B", "rain.A", "matte"}) {
    EXPECT_EQ(
        std::memcmp(first.plane(name).data(), second.plane(name).data(), first.pixelCount() * 4), 0)
        << name;
  }
}

TEST_P(RainRendererTest, NoStreaksGivesZeroPlanesAndLeavesTheFrame) {
  Image frame = uniformFrame(32, 24, {0.3f, 0.2f, 0.1f, 0.5f});
  const std::vector<float> before = frame.rgba;
  frame.plane("rain.A").assign(frame.pixelCount(), 7.0f);  // stale values must go
  renderer().render(frame, {}, constantShading({1, 1, 1}, 0.7f));
  EXPECT_EQ(frame.rgba, before);
  for (const char* name : {"rain.R", "rain.G", "rain.B", "rain.A", "matte"}) {
    EXPECT_EQ(frame.plane(name), std::vector<float>(frame.pixelCount(), 0.0f)) << name;
  }
}

TEST_P(RainRendererTest, FollowsAChangeOfFrameSize) {
  renderer().setStrokeAtlas(solidAtlas());
  for (auto [w, h] : {std::pair{48, 20}, {32, 24}, {7, 5}}) {
    Image frame = uniformFrame(w, h, {0, 0, 0, 1});
    renderer().render(frame, {verticalStreak(w - 1.5f, 1.0f, h - 2.0f, 1.0f, 1.0f, 1.0f)},
                      constantShading({1, 1, 1}, 0.0f));
    EXPECT_EQ(frame.plane("matte")[1 * w + (w - 2)], 1.0f) << w << "x" << h;
    EXPECT_EQ(frame.plane("matte")[1 * w + (w - 3)], 0.0f) << w << "x" << h;
  }
}

TEST_P(RainRendererTest, RejectsInconsistentInputs) {
  renderer().setStrokeAtlas(solidAtlas());
  Image frame(32, 24);
  const std::vector<rain::StreakInstance> one{verticalStreak(8, 2, 9, 2, 1, 1)};
  rain::ShadingParams tooHigh = constantShading({1, 1, 1}, 0.7f);
  tooHigh.shOrder = 4;
  EXPECT_THROW(renderer().render(frame, one, tooHigh), Error);
  rain::ShadingParams shortEnv = constantShading({1, 1, 1}, 0.7f);
  shortEnv.shOrder = 2;
  shortEnv.transferZonal = {1, 1, 1};
  EXPECT_THROW(renderer().render(frame, one, shortEnv), Error);
  std::vector<rain::StreakInstance> badStroke = one;
  badStroke[0].strokeIndex = 1.0f;  // the atlas has one stroke
  try {
    renderer().render(frame, badStroke, constantShading({1, 1, 1}, 0.7f));
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_EQ(error.context().stage, "rain");
    EXPECT_NE(std::string(error.what()).find("stroke"), std::string::npos) << error.what();
  }
  EXPECT_THROW(renderer().setStrokeAtlas({4, 4, {1, 1}, {{0, 0, 4, 4}}}), Error);
}

TEST_P(RainRendererTest, DescribesItsDevice) {
  const std::string description = renderer().deviceDescription();
  EXPECT_EQ(renderer().backend(), GetParam());
  if (GetParam() == RainBackend::Egl) {
    EXPECT_NE(description.find("OpenGL 4."), std::string::npos) << description;
  } else {
    EXPECT_NE(description.find("CPU streak rasteriser"), std::string::npos) << description;
  }
}

TEST_P(RainRendererTest, SeveralRenderersShareTheDisplay) {
  // Renderers on one thread switch contexts as they go, and destroying one must not
  // terminate the EGL display under the others.
  const rain::ShadingParams shading = constantShading({1, 1, 1}, 0.0f);
  const std::vector<rain::StreakInstance> streak{
      verticalStreak(4.0f, 1.0f, 6.0f, 2.0f, 1.0f, 1.0f)};
  auto second = std::make_unique<RainRenderer>(8, 8, GetParam());
  second->setStrokeAtlas(solidAtlas());
  renderer().setStrokeAtlas(solidAtlas());
  for (int round = 0; round < 2; ++round) {
    Image small(8, 8), large(32, 24);
    second->render(small, streak, shading);
    renderer().render(large, streak, shading);
    EXPECT_EQ(small.plane("matte")[3 * 8 + 4], 1.0f);
    EXPECT_EQ(large.plane("matte")[3 * 32 + 4], 1.0f);
  }
  second.reset();
  Image frame(32, 24);
  renderer().render(frame, streak, shading);
  EXPECT_EQ(frame.plane("matte")[3 * 32 + 4], 1.0f);
}

TEST_P(RainRendererTest, MemoryStaysFlatOverAThousandFrames) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's quarantine grows resident memory by design";
#endif
  renderer().setStrokeAtlas(solidAtlas());
  const rain::ShadingParams shading = constantShading({1, 1, 1}, 0.7f);
  std::vector<rain::StreakInstance> streaks = crossingStreaks();
  Image frame = uniformFrame(32, 24, {0.1f, 0.1f, 0.1f, 1.0f});
  size_t warm = 0;
  for (int i = 0; i < 1000; ++i) {
    // Alternate the count so the instance buffer sees both shrinking and regrowing.
    streaks.resize(i % 2 ? 40 : 25, streaks.front());
    renderer().render(frame, streaks, shading);
    if (i == 99) warm = test::residentBytes();
  }
  EXPECT_LT(test::residentBytes(), warm + 2 * 1024 * 1024);
}

INSTANTIATE_TEST_SUITE_P(Backends, RainRendererTest,
                         ::testing::Values(RainBackend::Egl, RainBackend::Cpu),
                         [](const auto& info) {
                           return std::string(info.param == RainBackend::Egl ? "Egl" : "Cpu");
                         });

}  // namespace
}  // namespace pluvia::gpu
