#include "pipescope/pipeline/pipe_plan_yaml.h"

#include <gtest/gtest.h>

#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/scene_layouts.h"
#include "pipescope/synthetic/scene_yaml.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

const Eigen::Vector3d kPipeUp(0.0, -1.0, 0.0);  // the simulator's pipe.up (gravity +Y)

// The simulator's scene.yaml of a route, written as `simulate` writes it.
std::filesystem::path WriteRouteScene(const std::string& route, const std::string& name) {
  SimulationConfig config = PresetConfig("fiberglass-network");
  config.route = route;
  const Layout layout = BuildLayout(config);
  RouteStart start;
  layout.route.Evaluate(layout.start_s_m, &start.position, &start.heading);
  const std::filesystem::path path = MakeTestDirectory(name) / "scene.yaml";
  WriteSceneYaml(path, layout.scene, start);
  return path;
}

// The turns of the simulated route at its junctions, counted from the route itself: the
// direction 1 m before and after each point where the route passes within 10 cm of a tee (its
// corners are rounded).
std::vector<int> TrueTurns(const std::string& route) {
  SimulationConfig config = PresetConfig("fiberglass-network");
  config.route = route;
  const Layout layout = BuildLayout(config);
  std::vector<int> turns;
  double last_s = -10.0;
  for (double s = 1.0; s + 1.0 < layout.route.Length(); s += 0.01) {
    Eigen::Vector3d point, tangent;
    layout.route.Evaluate(s, &point, &tangent);
    for (const Scene::Junction& junction : layout.scene.junctions()) {
      if ((point - junction.center).norm() > 0.1 || s - last_s < 2.0) continue;
      Eigen::Vector3d before, after, unused;
      layout.route.Evaluate(s - 1.0, &before, &unused);
      layout.route.Evaluate(s + 1.0, &after, &unused);
      turns.push_back(TurnDirection(point - before, after - point, kPipeUp));
      last_s = s;
    }
  }
  return turns;
}

TEST(PipePlanYaml, TheSimulatorsRoutesAreNamedOnItsPlan) {
  for (const std::string route : {"A", "B"}) {
    SCOPED_TRACE("route " + route);
    std::string why_not;
    const std::optional<PipePlan> plan =
        ReadPipePlan(WriteRouteScene(route, "plan_" + route), kPipeUp, &why_not);
    ASSERT_TRUE(plan) << why_not;
    EXPECT_EQ(plan->tees.size(), 4u);
    const PlannedNetwork planned = BuildPlannedNetwork(*plan);
    const std::vector<int> turns = TrueTurns(route);
    // Route A turns at T1..T4; route B passes T1 straight, then turns at T4, T3, T2, T1, T4.
    ASSERT_EQ(turns.size(), route == "A" ? 4u : 6u);
    const std::vector<SectionPass> passes =
        NameSectionPasses(planned.network, planned.start, turns);
    if (route == "B") {
      // The T1-T4 side is driven twice, the same way: the second pass and the second-to-last.
      EXPECT_EQ(passes[1].section, passes[5].section);
      EXPECT_EQ(passes[1].toward_end, passes[5].toward_end);
    } else {
      for (std::size_t a = 0; a < passes.size(); ++a) {
        for (std::size_t b = a + 1; b < passes.size(); ++b) {
          EXPECT_NE(passes[a].section, passes[b].section);
        }
      }
    }
  }
}

TEST(PipePlanYaml, SaysWhyAFileHoldsNoPlan) {
  const std::filesystem::path dir = MakeTestDirectory("plan_without");
  WriteTextFileAtomically(dir / "a.yaml",
                          "sections:\n  - {type: straight, start: [0, 0, 0], end: [0, 0, 1]}\n");
  std::string why_not;
  EXPECT_FALSE(ReadPipePlan(dir / "a.yaml", kPipeUp, &why_not));
  EXPECT_NE(why_not.find("route_start"), std::string::npos) << why_not;
  WriteTextFileAtomically(
      dir / "b.yaml",
      "radius: 0.1\nroute_start: {position: [0, 0, 0], heading: [0, 0, 1]}\nsections:\n"
      "  - {type: straight, start: [0, 0, 0], end: [0, 0, 1]}\n  - {type: bend}\n");
  EXPECT_FALSE(ReadPipePlan(dir / "b.yaml", kPipeUp, &why_not));
  EXPECT_NE(why_not.find("bend"), std::string::npos) << why_not;
  WriteTextFileAtomically(dir / "c.yaml",
                          "route_start: {position: [0, 0], heading: [0, 0, 1]}\nsections: []\n");
  const std::string message =
      InputErrorMessage([&] { ReadPipePlan(dir / "c.yaml", kPipeUp, &why_not); });
  EXPECT_NE(message.find("route_start.position"), std::string::npos) << message;
}

}  // namespace
}  // namespace pipescope
