// A plate shot in rain already holds its veil: `heavy` on NTURain's real rain leaves darken, blur
// and fog out (saying why), adds them when over_rain asks, and the dry street plate keeps them.
// `plan` says what happens on a rained plate. Skipped without ../shared/data.
#include <gtest/gtest.h>

#include "test_support.h"

using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

bool haveClips() {
  return stdfs::exists(sharedData() / "rain_real/nturain_ra1_real_rain_panning/00001.jpg") &&
         stdfs::exists(sharedData() / "plate_static/opencv_vtest.avi");
}

}  // namespace

TEST(CliRainedPlate, ARainedPlateGetsNoSecondVeilUnlessAsked) {
  if (!haveClips()) GTEST_SKIP() << "../shared/data is absent";
  const stdfs::path dir = freshTempDir("rained_plate");
  const std::string nturain =
      (sharedData() / "rain_real/nturain_ra1_real_rain_panning/%05d.jpg").string();
  const auto rained = runPluvia(
      {"render", nturain, "-p", "heavy", "-o", (dir / "a.####.png").string(), "--frames", "5-5"});
  ASSERT_EQ(rained.exitCode, 0) << rained.output;
  expectOutputHas(
      rained.output,
      {"plate: shot in rain: streaks over", "darken: left out: the plate was shot in rain",
       "blur: left out: the plate was shot in rain", "fog: left out: the plate was shot in rain"});

  // The check runs ahead on its own reader and thread (2 threads and more) or on first use (1
  // thread): the same frames measured alike.
  const auto oneThread =
      runPluvia({"render", nturain, "-p", "heavy", "-o", (dir / "d.####.png").string(), "--frames",
                 "5-5", "--threads", "1"});
  ASSERT_EQ(oneThread.exitCode, 0) << oneThread.output;
  auto findingIn = [](const std::string& output) {
    const size_t at = output.find("plate: shot in rain:");
    return at == std::string::npos ? std::string()
                                   : output.substr(at, output.find(", in ", at) - at);
  };
  EXPECT_FALSE(findingIn(rained.output).empty());
  EXPECT_EQ(findingIn(oneThread.output), findingIn(rained.output));

  const auto asked =
      runPluvia({"render", nturain, "-p", "heavy", "-o", (dir / "b.####.png").string(), "--frames",
                 "5-5", "--set", "fog.over_rain=true"});
  ASSERT_EQ(asked.exitCode, 0) << asked.output;
  EXPECT_EQ(asked.output.find("fog: left out"), std::string::npos) << asked.output;
  EXPECT_NE(asked.output.find("darken: left out"), std::string::npos) << asked.output;

  const auto dry =
      runPluvia({"render", (sharedData() / "plate_static/opencv_vtest.avi").string(), "-p", "heavy",
                 "-o", (dir / "c.####.png").string(), "--frames", "100-100"});
  ASSERT_EQ(dry.exitCode, 0) << dry.output;
  EXPECT_NE(dry.output.find("plate: not shot in rain"), std::string::npos) << dry.output;
  EXPECT_EQ(dry.output.find("left out: the plate was shot in rain"), std::string::npos)
      << dry.output;

  const auto plan = runPluvia({"plan", nturain, "-p", "heavy"});
  ASSERT_EQ(plan.exitCode, 0) << plan.output;
  EXPECT_NE(plan.output.find("fog.over_rain = true adds it anyway"), std::string::npos)
      << plan.output;
}
