// Per-frame SH between a looming camera's key panoramas, and the light sources' JSON.
#include <gtest/gtest.h>

#include "envmap/clip_environment.h"
#include "util/error.h"

namespace pluvia::envmap {
namespace {

EnvironmentKey key(int64_t frame, double value) {
  EnvironmentKey k;
  k.frame = frame;
  k.sh = optics::ShCoefficients(16, {value, 2 * value, 3 * value});
  return k;
}

TEST(ClipEnvironment, ShIsLinearBetweenKeysAndHeldBeyondThem) {
  ClipEnvironment env;
  env.keys = {key(10, 1.0), key(15, 2.0), key(20, 4.0)};
  EXPECT_DOUBLE_EQ(shAtFrame(env, 0)[3][0], 1.0);
  EXPECT_DOUBLE_EQ(shAtFrame(env, 10)[3][0], 1.0);
  EXPECT_DOUBLE_EQ(shAtFrame(env, 12)[3][1], 2.0 * 1.4);
  EXPECT_DOUBLE_EQ(shAtFrame(env, 15)[0][2], 6.0);
  EXPECT_DOUBLE_EQ(shAtFrame(env, 18)[5][0], 3.2);
  EXPECT_DOUBLE_EQ(shAtFrame(env, 99)[15][0], 4.0);
}

TEST(ClipEnvironment, LightsFromJson) {
  const auto lights = parseLights(nlohmann::json::parse(R"([
      {"type": "direction", "yaw_deg": 90, "pitch_deg": 0, "radius_deg": 2, "radiance": [100, 90, 80]},
      {"type": "region", "frame": 1, "x": 10, "y": 20, "width": 5, "height": 6, "radiance": [7, 7, 7]}])"),
                                  "test");
  ASSERT_EQ(lights.size(), 2u);
  ASSERT_TRUE(lights[0].direction);
  EXPECT_NEAR((*lights[0].direction)[0], 1.0, 1e-12);  // yaw 90: to the right, +X
  EXPECT_NEAR((*lights[0].direction)[2], 0.0, 1e-12);
  EXPECT_EQ(lights[0].radiusDeg, 2.0);
  EXPECT_EQ(lights[1].frame, 1);
  EXPECT_EQ(lights[1].region, cv::Rect(10, 20, 5, 6));
  for (
      const char* bad :
      {R"([{"type": "direction", "yaw_deg": 0, "pitch_deg": 0, "radiance": [1, -1, 1]}])",
       R"([{"type": "region", "frame": 0, "x": 0, "y": 0, "width": 0, "height": 3, "radiance": [1, 1, 1]}])",
       R"([{"type": "lamp", "radiance": [1, 1, 1]}])", R"([{"type": "direction"}])"}) {
    try {
      parseLights(nlohmann::json::parse(bad), "lights.json");
      FAIL() << bad;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("light 0"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace pluvia::envmap
