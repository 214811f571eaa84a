#include "pipescope/synthetic/scale_target.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "pipescope/camera/camera_io.h"
#include "pipescope/image/reference_scale.h"
#include "pipescope/image/undistortion.h"
#include "pipescope/io/dataset.h"
#include "pipescope/synthetic/dataset_writer.h"
#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/simulation.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

constexpr double kCircumference = 2.0 * M_PI * 0.07666;

TEST(ScaleTarget, PaintsInkOnACardOverTheWall) {
  ScaleTargetOptions options;  // 5 x 4 circles, 10 mm apart, 4 mm across
  // Centred near s = 0 so the card wraps round the seam of the s coordinate.
  const ScaleTarget target(options, 0, 0.5, 0.002, kCircumference);
  const auto paint = [&](int section, double h, double s, double footprint = 1e-5) {
    float albedo = 0.3f, specularity = 0.5f;
    target.Paint(section, h, s, footprint, &albedo, &specularity);
    return std::pair{albedo, specularity};
  };
  const Eigen::Vector2d corner = target.CircleCentre(0, 0);
  EXPECT_NEAR(corner.x(), 0.5 - 0.02, 1e-12);
  EXPECT_NEAR(corner.y(), 0.002 - 0.015, 1e-12);
  // Ink at a circle centre, white card between circles, both matte.
  EXPECT_NEAR(paint(0, corner.x(), corner.y() + kCircumference).first, options.ink_albedo, 1e-6);
  EXPECT_NEAR(paint(0, corner.x() + 0.005, corner.y()).first, options.card_albedo, 1e-6);
  EXPECT_FLOAT_EQ(paint(0, corner.x() + 0.005, corner.y()).second, 0.0f);
  // Off the card (0.75 spacings beyond the outer circles) and on other sections: the wall.
  EXPECT_FLOAT_EQ(paint(0, 0.5 + 0.03, 0.002).first, 0.3f);
  EXPECT_FLOAT_EQ(paint(0, 0.5, 0.002 + 0.0226).second, 0.5f);
  EXPECT_FLOAT_EQ(paint(1, corner.x(), corner.y()).first, 0.3f);
  // A pixel centred on a circle's edge is half ink, half card (box-filtered anti-aliasing).
  const Eigen::Vector2d centre = target.CircleCentre(3, 2);
  EXPECT_NEAR(paint(0, centre.x() + 0.002, centre.y(), 1e-4).first,
              0.5 * (options.ink_albedo + options.card_albedo), 1e-6);
  EXPECT_THROW(ScaleTarget({.cols = 1}, 0, 0.0, 0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(ScaleTarget({.spacing_m = 0.004, .diameter_m = 0.004}, 0, 0.0, 0.0, 1.0),
               std::invalid_argument);
}

TEST(ScaleTarget, PresetCentresTheTargetOnTheMiddleFramesImage) {
  SimulationConfig config = PresetConfig("scale-target");
  config.width = 256;
  config.height = 192;
  const Simulation simulation(config);
  ASSERT_NE(simulation.scale_target(), nullptr);
  const ScaleTarget& target = *simulation.scale_target();
  EXPECT_EQ(target.options().cols, config.target_cols);
  EXPECT_DOUBLE_EQ(target.options().spacing_m, config.target_spacing_m);
  // The wall point under the grid's centre images at the principal point of the middle frame;
  // on a straight pipe along Z, h is the Z coordinate and s = r phi with phi from +X to +Y.
  const double phi = target.centre_s_m() / config.radius_m;
  const Eigen::Vector3d point_world(config.radius_m * std::cos(phi),
                                    config.radius_m * std::sin(phi), target.centre_h_m());
  const Eigen::Vector3d point_cam = simulation.FramePose(2).inverse() * point_world;
  Eigen::Vector2d pixel;
  ASSERT_EQ(simulation.camera().Project(point_cam, &pixel), ProjectionStatus::kValid);
  EXPECT_NEAR(pixel.x(), 127.5, 1e-6);
  EXPECT_NEAR(pixel.y(), 95.5, 1e-6);
  // Other layouts have no target; a forward-looking camera cannot be pointed at one.
  EXPECT_EQ(Simulation(PresetConfig("steel-6in")).scale_target(), nullptr);
  config.view = "forward";
  EXPECT_NE(InputErrorMessage([&] { ValidateConfig(config); }).find("view"), std::string::npos);
}

// One set-up of the accuracy test: a name and --set overrides of the scale-target preset.
struct SetUp {
  const char* name;
  std::vector<std::string> settings;
};

class RefscaleOnSimulatedTarget : public testing::TestWithParam<SetUp> {};

// The whole chain of 000 §3.3 against the simulator's truth f / (distance to the wall): render
// the target into a dataset, detect the circles, take their centroids in the perspective image
// and fit the scale at the image centre. Target: 0.2 % (issue 4); the chain reaches about
// 0.02 % (docs/reference_scale.md).
TEST_P(RefscaleOnSimulatedTarget, MatchesTheTrueScaleWithinTwoTenthsOfAPercent) {
  SimulationConfig config = PresetConfig("scale-target");
  for (const std::string& setting : GetParam().settings) SetConfigValue(&config, setting);
  config.frames = 3;
  config.white_card_count = 1;
  const auto dir = MakeTestDirectory(std::string("refscale_") + GetParam().name);
  SimulateDataset(config, dir / "ds");

  const YAML::Node target = YAML::LoadFile((dir / "ds" / "target.yaml").string());
  const int cols = target["cols"].as<int>();
  const int rows = target["rows"].as<int>();
  const double spacing = target["spacing_m"].as<double>();
  EXPECT_EQ(cols, 5);
  EXPECT_EQ(rows, 4);
  EXPECT_DOUBLE_EQ(target["diameter_m"].as<double>(), config.target_diameter_m);
  const DatasetManifest manifest = ReadDatasetManifest(dir / "ds" / "dataset.yaml");
  ASSERT_TRUE(manifest.reference_scale_px_per_m.has_value());
  const double truth = *manifest.reference_scale_px_per_m;
  const Camera camera = ReadCamera(manifest.camera_path);
  EXPECT_NEAR(truth, CentralFocalLengthPx(camera) / config.radius_m, 1e-6 * truth);

  const cv::Point2d c = PrincipalPoint(camera);
  for (int frame = 0; frame < config.frames; ++frame) {
    SCOPED_TRACE(frame);
    char name[32];
    std::snprintf(name, sizeof(name), "%06d.png", frame);
    const cv::Mat image = cv::imread((manifest.images_dir / name).string(), cv::IMREAD_UNCHANGED);
    const auto centres = DetectCircleGrid(image, cols, rows);
    ASSERT_TRUE(centres.has_value());
    const auto undistorted = UndistortedCircleCentroids(image, camera, *centres, cols, rows);
    ASSERT_TRUE(undistorted.has_value());
    const ReferenceScale scale =
        EstimateReferenceScale(*undistorted, cols, rows, spacing, Eigen::Vector2d(c.x, c.y));
    EXPECT_TRUE(scale.principal_point_on_target);
    EXPECT_NEAR(scale.px_per_m / truth - 1.0, 0.0, 0.002)
        << "zeta " << scale.px_per_m << " truth " << truth;
    // The camera looks squarely at the wall, so the scale around the pipe agrees too.
    EXPECT_NEAR(scale.across_px_per_m / truth - 1.0, 0.0, 0.005);
  }
  std::filesystem::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(
    SetUps, RefscaleOnSimulatedTarget,
    testing::Values(
        // 000 Table 1 pipe 1 (steel-6in's camera at half size: 48 px spacing).
        SetUp{"steel6in", {"width=512", "height=384"}},
        // 000 Table 1 pipe 2 (steel-16in's 640x480 25 degree camera in the 387.56 mm pipe).
        SetUp{"steel16in",
              {"radius_m=0.19378", "width=640", "height=480", "fov_deg=25",
               "led_ring_radius_m=0.03"}},
        // Fisheye models: the centroids must be taken in the perspective image.
        SetUp{"kannala_brandt", {"width=512", "height=384", "camera_model=kannala-brandt"}},
        SetUp{"fisheye_poly_190",
              {"width=640", "height=480", "camera_model=fisheye-poly", "fov_deg=190"}}),
    [](const testing::TestParamInfo<SetUp>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace pipescope
