#include <gtest/gtest.h>

#include <stdexcept>

#include "preset/settings_table.h"
#include "test_support.h"

using namespace pluvia;

namespace {

enum class Shape { Round, Square };

struct ToySettings {
  bool enabled = false;
  double widthM = -1.0;
  int count = -1;
  int truncated = -1;  // an int member of a Number row
  uint64_t seed = 0;
  std::string mode;
  std::array<float, 3> rgb{0, 0, 0};
  nlohmann::json items;
  Ramp speed{-1.0};
  struct Inner {
    double gain = -1.0;
  } inner;
  std::string unboundMode = "untouched";
  Shape shape = Shape::Square;  // an enum row: its default is this one
};

const SettingsTable<ToySettings>& toyTable() {
  using S = ToySettings;
  static const SettingsTable<ToySettings> table(
      {.name = "toy", .help = "a table for the test", .outputs = {"toy_out"}},
      {
          bind(&S::enabled, enabledParam()),
          bind(&S::widthM, numberParam("width_m", 2.5, {0, 10}, "m", "width")),
          bind(&S::count, integerParam("count", 7, {0, 100}, "", "count")),
          bind(&S::truncated, numberParam("truncated", 3.9, {0, 10}, "", "truncated")),
          bind(&S::seed, integerParam("seed", 4000000000, {0, 4294967295.0}, "", "seed")),
          bind(&S::mode, enumParam("mode", "b", {"a", "b"}, "mode")),
          bind(&S::rgb, colorParam("rgb", nlohmann::json::array({0.25, 0.5, 1.0}), "", "rgb")),
          bind(&S::items,
               listParam("items", nlohmann::json::array({{{"type", "x"}}}), {{"x", {}}}, "items")),
          bind(&S::speed, numberParam("speed", 5.0, {0, 60}, "m/s", "speed")),
          bind(&S::inner, &S::Inner::gain, numberParam("inner.gain", 0.125, {0, 1}, "", "gain")),
          unbound<S>(enumParam("unbound_mode", "p", {"p", "q"}, "read by hand")),
          bind(&S::shape, "shape", {{"round", Shape::Round}, {"square", Shape::Square}}, "shape"),
      });
  return table;
}

Preset resolveToy(const std::vector<std::string>& sets) {
  auto dir = test::freshTempDir("settings_table");
  auto path = test::writeTextFile(dir, "toy.json", R"({"pluvia": 1})");
  return Preset::resolve(path.string(), sets, {toyTable().section()});
}

}  // namespace

// The section keeps its name, help and order of rows; a Ramp row is keyframable and no other is.
TEST(SettingsTable, SectionListsTheRowsInOrder) {
  const SectionSpec& s = toyTable().section();
  EXPECT_EQ(s.name, "toy");
  EXPECT_EQ(s.help, "a table for the test");
  EXPECT_EQ(s.outputs, std::vector<std::string>{"toy_out"});
  std::vector<std::string> keys;
  for (const auto& p : s.params) keys.push_back(p.key);
  EXPECT_EQ(keys, (std::vector<std::string>{"enabled", "width_m", "count", "truncated", "seed",
                                            "mode", "rgb", "items", "speed", "inner.gain",
                                            "unbound_mode", "shape"}));
  for (const auto& p : s.params) EXPECT_EQ(p.keyframes, p.key == "speed") << p.key;
}

TEST(SettingsTable, DefaultsFillEveryBoundMember) {
  const ToySettings s = toyTable().read(resolveToy({}));
  EXPECT_TRUE(s.enabled);
  EXPECT_DOUBLE_EQ(s.widthM, 2.5);
  EXPECT_EQ(s.count, 7);
  EXPECT_EQ(s.truncated, 3);  // truncated toward zero, as int(3.9)
  EXPECT_EQ(s.seed, 4000000000u);
  EXPECT_EQ(s.mode, "b");
  EXPECT_EQ(s.rgb, (std::array<float, 3>{0.25f, 0.5f, 1.0f}));
  EXPECT_EQ(s.items, nlohmann::json::array({{{"type", "x"}}}));
  EXPECT_DOUBLE_EQ(s.speed.valueAt(100.0), 5.0);
  EXPECT_DOUBLE_EQ(s.inner.gain, 0.125);
  EXPECT_EQ(s.unboundMode, "untouched");  // an unbound row is the section's own code's
}

TEST(SettingsTable, OverridesAndKeyframesReachTheMembers) {
  const ToySettings s = toyTable().read(resolveToy(
      {"toy.enabled=false", "toy.width_m=7", "toy.count=42", "toy.mode=a", "toy.rgb=[1,2,3]",
       "toy.speed=[[0,0],[10,20]]", "toy.inner.gain=0.5", "toy.unbound_mode=q"}));
  EXPECT_FALSE(s.enabled);
  EXPECT_DOUBLE_EQ(s.widthM, 7.0);
  EXPECT_EQ(s.count, 42);
  EXPECT_EQ(s.mode, "a");
  EXPECT_EQ(s.rgb, (std::array<float, 3>{1.0f, 2.0f, 3.0f}));
  // Linear between the keys: 10 at frame 5.
  EXPECT_DOUBLE_EQ(s.speed.valueAt(5.0), 10.0);
  EXPECT_DOUBLE_EQ(s.speed.valueAt(10.0), 20.0);
  EXPECT_DOUBLE_EQ(s.inner.gain, 0.5);
  EXPECT_EQ(s.unboundMode, "untouched");
}

// An enum row gets its choices and its default (the struct's value, by name) from one table of
// names, and reads a name into its C++ value.
TEST(SettingsTable, EnumRowsReadNamesIntoTheirValues) {
  const ParamSpec& spec = toyTable().section().params.back();
  EXPECT_EQ(spec.type, ParamType::Enum);
  EXPECT_EQ(spec.choices, (std::vector<std::string>{"round", "square"}));
  EXPECT_EQ(spec.defaultValue, "square");
  EXPECT_EQ(toyTable().read(resolveToy({})).shape, Shape::Square);
  EXPECT_EQ(toyTable().read(resolveToy({"toy.shape=round"})).shape, Shape::Round);
  EXPECT_THROW(resolveToy({"toy.shape=oval"}), PresetError);
}

// The toy's struct defaults are placeholders (-1) that the rows' defaults replace: the check that
// a default written twice is one value names exactly those rows.
TEST(SettingsTable, StructDefaultsThatDifferFromTheRowsAreNamed) {
  EXPECT_EQ(toyTable().keysWhoseStructDefaultDiffers(resolveToy({})),
            (std::vector<std::string>{"toy.enabled", "toy.width_m", "toy.count", "toy.truncated",
                                      "toy.seed", "toy.mode", "toy.rgb", "toy.items", "toy.speed",
                                      "toy.inner.gain"}));
}

// A row bound to a member that cannot hold it is a programming error, caught when the table is
// built.
TEST(SettingsTable, MismatchedMemberThrows) {
  using S = ToySettings;
  EXPECT_THROW(bind(&S::widthM, booleanParam("flag", true, "")), std::logic_error);
  EXPECT_THROW(bind(&S::enabled, numberParam("x", 1.0, {}, "", "")), std::logic_error);
  EXPECT_THROW(bind(&S::mode, numberParam("x", 1.0, {}, "", "")), std::logic_error);
  EXPECT_THROW(bind(&S::rgb, stringParam("x", "", "")), std::logic_error);
  EXPECT_THROW(bind(&S::speed, stringParam("x", "", "")), std::logic_error);
  EXPECT_NO_THROW(bind(&S::count, numberParam("x", 1.0, {}, "", "")));
}

// A fraction is the Number row of [0, 1] without units, its default written as a float.
TEST(SettingsTable, FractionIsAUnitlessNumberFromZeroToOne) {
  const ParamSpec f = fractionParam("blend", 0, "how much");
  EXPECT_EQ(f.key, "blend");
  EXPECT_EQ(f.type, ParamType::Number);
  EXPECT_EQ(f.minValue, 0.0);
  EXPECT_EQ(f.maxValue, 1.0);
  EXPECT_EQ(f.units, "");
  EXPECT_EQ(f.help, "how much");
  EXPECT_TRUE(f.defaultValue.is_number_float());
  EXPECT_EQ(f.defaultValue.dump(), "0.0");
}
