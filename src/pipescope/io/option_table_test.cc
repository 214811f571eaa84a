// OptionTable: each key declared once reads YAML with range checks, writes JSON and lists itself.
#include "pipescope/io/option_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

struct Inner {
  int count = 3;
};

struct TestOptions {
  Inner inner;
  double angle_rad = 0.1;
  double twin_a = 1.0;
  double twin_b = 1.0;
  bool on = true;
  std::string axis = "x";
};

const OptionTable<TestOptions>& Table() {
  using O = TestOptions;
  static const OptionTable<O> table({
      Number<O>(
          "count", [](O& o) -> int& { return o.inner.count; }, 1, 10, "", "a count"),
      ScaledNumber<O>(
          "angle_deg", [](O& o) -> double& { return o.angle_rad; }, 0.0, 90.0, "deg", "an angle",
          std::numbers::pi / 180.0),
      Number<O>(
          "twin", [](O& o) -> double& { return o.twin_a; }, 0.0, 5.0, "m", "two options",
          [](O& o) -> double& { return o.twin_b; }),
      Flag<O>(
          "on", [](O& o) -> bool& { return o.on; }, "a switch"),
      Choice<O>(
          "axis", [](O& o) -> std::string& { return o.axis; }, {"x", "-x"}, "an axis"),
  });
  return table;
}

TEST(OptionTable, AppliesEveryKindOfKey) {
  TestOptions options;
  Table().ApplyYaml(YAML::Load("{count: 7, angle_deg: 45, twin: 2.5, on: false, axis: -x}"),
                    "config.yaml", &options);
  EXPECT_EQ(options.inner.count, 7);
  EXPECT_NEAR(options.angle_rad, M_PI / 4.0, 1e-15);
  EXPECT_EQ(options.twin_a, 2.5);
  EXPECT_EQ(options.twin_b, 2.5);
  EXPECT_FALSE(options.on);
  EXPECT_EQ(options.axis, "-x");
  const nlohmann::json json = Table().ToJson(options);
  EXPECT_EQ(json["count"], 7);
  EXPECT_NEAR(json["angle_deg"].get<double>(), 45.0, 1e-12);
  EXPECT_EQ(json["axis"], "-x");
  EXPECT_EQ(json.size(), 5u);
}

TEST(OptionTable, ErrorsNameTheFileAndTheKeyAndChangeNothing) {
  const struct {
    const char* yaml;
    const char* key;
  } cases[] = {{"{count: 11}", "'count'"},
               {"{count: 2.5}", "'count'"},
               {"{angle_deg: .nan}", "'angle_deg'"},
               {"{on: maybe}", "'on'"},
               {"{axis: y}", "'axis'"},
               {"{count: 2, colour: red}", "'colour'"},
               {"{[a, b]: 1}", "a key must be a name"}};
  for (const auto& c : cases) {
    TestOptions options;
    const std::string message = InputErrorMessage(
        [&] { Table().ApplyYaml(YAML::Load(c.yaml), "dir/config.yaml", &options); });
    EXPECT_NE(message.find("dir/config.yaml"), std::string::npos) << message;
    EXPECT_NE(message.find(c.key), std::string::npos) << message;
    if (std::string(c.key) == "'colour'") EXPECT_EQ(options.inner.count, 3);  // nothing applied
  }
}

TEST(OptionTable, ListsEachKeyWithItsDefaultRangeAndUnit) {
  const std::string listing = Table().ListKeys(TestOptions{});
  EXPECT_NE(listing.find("count"), std::string::npos);
  EXPECT_NE(listing.find("[1, 10]"), std::string::npos);
  EXPECT_NE(listing.find("5.72958 deg"), std::string::npos) << listing;  // 0.1 rad
  EXPECT_NE(listing.find("x | -x"), std::string::npos);
  EXPECT_NE(listing.find("two options"), std::string::npos);
}

}  // namespace
}  // namespace pipescope
