#include "pipescope/synthetic/presets.h"

#include <gtest/gtest.h>

#include <cmath>

#include "pipescope/synthetic/scene_layouts.h"
#include "pipescope/synthetic/simulated_camera.h"
#include "pipescope/synthetic/simulation.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

TEST(Presets, EveryPresetIsValidAndHasItsCameraAndRoute) {
  for (const std::string& name : PresetNames()) {
    SCOPED_TRACE(name);
    const SimulationConfig config = PresetConfig(name);
    EXPECT_EQ(config.preset, name);
    EXPECT_FALSE(config.description.empty());
    EXPECT_NO_THROW(ValidateConfig(config));
    const Camera camera = MakeSimulatedCamera(config);
    EXPECT_EQ(camera.Width(), config.width);
    EXPECT_EQ(camera.ModelName(), config.camera_model);
    const Layout layout = BuildLayout(config);
    EXPECT_GT(layout.travel_m, 0.0);
    EXPECT_LE(layout.start_s_m + layout.travel_m, layout.route.Length() + 1e-9);
    // Every point of the route lies inside the pipe.
    for (double s = 0.0; s <= layout.route.Length(); s += 0.05) {
      Eigen::Vector3d point, tangent;
      layout.route.Evaluate(s, &point, &tangent);
      EXPECT_TRUE(layout.scene.Contains(point)) << "s = " << s;
    }
  }
}

TEST(Presets, PapersGeometry) {
  const SimulationConfig six = PresetConfig("steel-6in");
  EXPECT_DOUBLE_EQ(2.0 * six.radius_m, 0.15332);
  EXPECT_NEAR(BuildLayout(six).travel_m, 5.8444, 1e-9);  // 000 Table 1 ground truth
  EXPECT_NEAR(six.speed_m_s * six.frames / six.fps / six.frames, 0.00137, 0.00001);
  const SimulationConfig sixteen = PresetConfig("steel-16in");
  EXPECT_DOUBLE_EQ(2.0 * sixteen.radius_m, 0.38756);
  EXPECT_NEAR(BuildLayout(sixteen).travel_m, 3.391, 1e-9);
  EXPECT_TRUE(sixteen.out_and_back);
  // A 190-degree lens reaches past 95 degrees from the axis.
  const Camera fisheye = MakeSimulatedCamera(PresetConfig("fiberglass-network"));
  EXPECT_GE(fisheye.MaxAngle(), 95.0 * M_PI / 180.0);
  Eigen::Vector3d bearing;
  const double rim = 95.0 * M_PI / 180.0;
  Eigen::Vector2d pixel;
  EXPECT_EQ(fisheye.Project(Eigen::Vector3d(std::sin(rim), 0, std::cos(rim)), &pixel),
            ProjectionStatus::kValid);
}

TEST(Presets, SquareLoopFollowsTableOneDistances) {
  const std::vector<Eigen::Vector3d> t = SquareLoopCorners(false);
  // 001 Table I laser distances, fitted by least squares: each within 3 cm (the table's own
  // figures disagree by that much with any planar quadrilateral).
  const double table[4][4] = {{0, 8.150, 11.468, 8.110},
                              {8.150, 0, 8.174, 11.493},
                              {11.468, 8.174, 0, 8.159},
                              {8.110, 11.493, 8.159, 0}};
  double sum_squares = 0.0;
  for (int a = 0; a < 4; ++a) {
    for (int b = a + 1; b < 4; ++b) {
      const double error = (t[a] - t[b]).norm() - table[a][b];
      EXPECT_LT(std::abs(error), 0.03) << "T" << a + 1 << "-T" << b + 1;
      sum_squares += error * error;
    }
  }
  // Better than the five-distance construction, whose T2-T4 is 8.5 cm off.
  EXPECT_LT(std::sqrt(sum_squares / 6.0), 0.02);
  EXPECT_NEAR(t[0].norm(), 0.0, 1e-12);
  EXPECT_NEAR(t[1].x(), 0.0, 1e-12);
  for (const Eigen::Vector3d& corner : t) EXPECT_EQ(corner.y(), 0.0);  // a horizontal network
  const Layout layout = BuildLayout(PresetConfig("fiberglass-network"));
  ASSERT_EQ(layout.scene.junctions().size(), 4u);
  for (int i = 0; i < 4; ++i) {
    const auto& junction = layout.scene.junctions()[i];
    const int index = junction.name[1] - '1';
    EXPECT_LT((junction.center - t[index]).norm(), 1e-12) << junction.name;
  }
}

// The order in which a square-loop route passes its Ts (within the turning radius of a T's
// centre, counted once per pass).
std::vector<std::string> TeesPassed(const Layout& layout, double within_m) {
  std::vector<std::string> passed;
  std::string near;
  for (double s = 0.0; s <= layout.route.Length(); s += 0.01) {
    Eigen::Vector3d point, tangent;
    layout.route.Evaluate(s, &point, &tangent);
    std::string here;
    for (const auto& junction : layout.scene.junctions()) {
      if ((point - junction.center).norm() < within_m) here = junction.name;
    }
    if (!here.empty() && here != near) passed.push_back(here);
    near = here;
  }
  return passed;
}

TEST(Presets, SquareLoopRoutes) {
  SimulationConfig config = PresetConfig("fiberglass-network");
  const Layout a = BuildLayout(config);
  EXPECT_EQ(TeesPassed(a, config.radius_m), (std::vector<std::string>{"T1", "T2", "T3", "T4"}));
  config.route = "B";
  ASSERT_NO_THROW(ValidateConfig(config));
  const Layout b = BuildLayout(config);
  EXPECT_EQ(TeesPassed(b, config.radius_m),
            (std::vector<std::string>{"T1", "T4", "T3", "T2", "T1", "T4"}));
  // Inside the pipe all the way, and longer by one side and the arm: the loop, T1-T4 again and
  // T4's arm, against A's loop without its last metre.
  for (double s = 0.0; s <= b.route.Length(); s += 0.05) {
    Eigen::Vector3d point, tangent;
    b.route.Evaluate(s, &point, &tangent);
    EXPECT_TRUE(b.scene.Contains(point)) << "s = " << s;
  }
  EXPECT_GT(b.travel_m, a.travel_m + 8.0);
  config.route = "C";
  EXPECT_THROW(ValidateConfig(config), InputError);
}

TEST(SimulationConfig, SetParsesAndValidatesKeys) {
  SimulationConfig config = PresetConfig("culvert");
  SetConfigValue(&config, "fov_deg=150");
  SetConfigValue(&config, "out_and_back=true");
  SetConfigValue(&config, "frames=12");
  SetConfigValue(&config, "camera_model=fisheye-poly");
  EXPECT_DOUBLE_EQ(config.fov_deg, 150.0);
  EXPECT_TRUE(config.out_and_back);
  EXPECT_EQ(config.frames, 12);
  EXPECT_EQ(GetConfigValue(config, "camera_model"), "fisheye-poly");
  EXPECT_NO_THROW(ValidateConfig(config));
  EXPECT_NE(
      InputErrorMessage([&] { SetConfigValue(&config, "no_such_key=1"); }).find("no_such_key"),
      std::string::npos);
  EXPECT_NE(InputErrorMessage([&] { SetConfigValue(&config, "fps=fast"); }).find("fps"),
            std::string::npos);
  EXPECT_NE(InputErrorMessage([&] { SetConfigValue(&config, "fps"); }).find("key=value"),
            std::string::npos);
  EXPECT_EQ(GetConfigValue(config, "white_card_finish"), "wall");
  SetConfigValue(&config, "white_card_finish=matte");
  EXPECT_NO_THROW(ValidateConfig(config));
  SetConfigValue(&config, "white_card_finish=glossy");
  EXPECT_NE(InputErrorMessage([&] { ValidateConfig(config); }).find("white_card_finish"),
            std::string::npos);
  SetConfigValue(&config, "white_card_finish=wall");
  SetConfigValue(&config, "radius_m=-1");
  EXPECT_NE(InputErrorMessage([&] { ValidateConfig(config); }).find("radius_m"), std::string::npos);
  EXPECT_NE(InputErrorMessage([] { PresetConfig("sewer"); }).find("--preset"), std::string::npos);
  // Every key listed reads back.
  for (const ConfigKey& key : SimulationConfigKeys()) {
    EXPECT_FALSE(GetConfigValue(config, key.name).empty()) << key.name;
  }
}

TEST(SimulationConfig, EveryKeyRoundTripsThroughItsText) {
  // simulation.yaml records each key as GetConfigValue prints it; --set reads it back exactly.
  for (const std::string& preset : PresetNames()) {
    const SimulationConfig original = PresetConfig(preset);
    SimulationConfig read_back;  // the defaults, not the preset
    for (const ConfigKey& key : SimulationConfigKeys()) {
      SetConfigValue(&read_back, std::string(key.name) + "=" + GetConfigValue(original, key.name));
    }
    for (const ConfigKey& key : SimulationConfigKeys()) {
      EXPECT_EQ(GetConfigValue(read_back, key.name), GetConfigValue(original, key.name))
          << preset << " " << key.name;
    }
    EXPECT_EQ(SimulationOptionTable().ToJson(read_back), SimulationOptionTable().ToJson(original))
        << preset;
  }
  SimulationConfig config;
  EXPECT_NE(InputErrorMessage([&] { SetConfigValue(&config, "seed=-1"); }).find("seed"),
            std::string::npos);
  EXPECT_NE(InputErrorMessage([&] { SetConfigValue(&config, "fps=.nan"); }).find("fps"),
            std::string::npos);
  EXPECT_NE(InputErrorMessage([&] { SetConfigValue(&config, "frames=1.5"); }).find("frames"),
            std::string::npos);
  SetConfigValue(&config, "out_and_back=1");
  EXPECT_TRUE(config.out_and_back);
}

TEST(SimulatedCamera, ReferenceScaleMatchesProjectedWallSpacing) {
  // Through the whole chain: the camera mounted 1 cm above the body centre on the nominal path,
  // its optical axis cast into the scene, and two wall points 1 mm apart along the pipe axis
  // around that hit projected back into the image.
  SimulationConfig config = PresetConfig("steel-6in");
  config.mount_offset_m = 0.01;
  config.lateral_offset_m = 0.0;
  const Simulation simulation(config);
  const std::optional<double> zeta = ReferenceScalePxPerM(config, simulation.camera());
  ASSERT_TRUE(zeta.has_value());
  const Eigen::Isometry3d world_from_cam = simulation.motion().NominalWorldFromCam(1.0);
  const std::optional<WallHit> hit = simulation.layout().scene.Intersect(
      {world_from_cam.translation(), world_from_cam.linear().col(2)});
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->distance, config.radius_m + config.mount_offset_m, 1e-12);
  const Eigen::Isometry3d cam_from_world = world_from_cam.inverse();
  Eigen::Vector2d a, b;
  const Eigen::Vector3d along_axis(0, 0, 0.0005);
  ASSERT_EQ(simulation.camera().Project(cam_from_world * (hit->point - along_axis), &a),
            ProjectionStatus::kValid);
  ASSERT_EQ(simulation.camera().Project(cam_from_world * (hit->point + along_axis), &b),
            ProjectionStatus::kValid);
  // Near the principal point the radial distortion changes the scale by k1 r^2, under 3e-6.
  EXPECT_NEAR((b - a).norm() / 0.001, *zeta, 1e-5 * *zeta);
  config.view = "forward";
  EXPECT_FALSE(ReferenceScalePxPerM(config, simulation.camera()).has_value());
}

}  // namespace
}  // namespace pipescope
