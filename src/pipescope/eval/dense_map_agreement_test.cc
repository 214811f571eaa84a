#include "pipescope/eval/dense_map_agreement.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "pipescope/synthetic/presets.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// fiberglass-network's straight layout: one pipe of radius 0.2 m along +Z from the origin, phi
// = atan2(Y, X) (scene.h), so the albedo of a wall point has a closed form to check against.
class DenseMapAgreementTest : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    SimulationConfig config = PresetConfig("fiberglass-network");
    SetConfigValue(&config, "layout=straight");
    SetConfigValue(&config, "length_m=2");
    simulation_ = new Simulation(config);
  }
  static void TearDownTestSuite() { delete simulation_; }

  static DenseMapCylinder Cylinder() {
    DenseMapCylinder cylinder;
    cylinder.axis_point = Eigen::Vector3d(0, 0, 0.5);
    cylinder.axis_direction = Eigen::Vector3d::UnitZ();
    cylinder.radius_m = 0.2;
    cylinder.begin_m = 0.0;
    cylinder.end_m = 0.3;
    cylinder.reference_direction = Eigen::Vector3d::UnitX();
    return cylinder;
  }

  // Every row in place, looked at from `viewpoint`.
  static std::vector<GridRowPlacement> Placements(const DenseMapGrid& grid,
                                                  const Eigen::Vector3d& viewpoint) {
    return std::vector<GridRowPlacement>(
        grid.rows(), GridRowPlacement{Eigen::Isometry3d::Identity(), viewpoint});
  }

  // The albedo as a camera's grey values would carry it: gain, offset and a ramp of light
  // along the pipe, which the high-pass removes.
  static cv::Mat AsGrey(const cv::Mat& albedo) {
    cv::Mat grey(albedo.size(), CV_32F);
    for (int row = 0; row < albedo.rows; ++row) {
      for (int col = 0; col < albedo.cols; ++col) {
        grey.at<float>(row, col) =
            static_cast<float>(20 + 150 * albedo.at<float>(row, col) + 40.0 * row / albedo.rows);
      }
    }
    return grey;
  }

  static Simulation* simulation_;
};
Simulation* DenseMapAgreementTest::simulation_ = nullptr;

TEST_F(DenseMapAgreementTest, TheAlbedoUnderTheGridIsTheWallsAtTheCellsPoint) {
  const DenseMapGrid grid(Cylinder(), 0.002);
  const cv::Mat albedo = SimulatedAlbedoUnderGrid(
      grid, Placements(grid, Eigen::Vector3d(0.01, -0.02, 0.6)), *simulation_, 0.02);
  ASSERT_EQ(albedo.rows, grid.rows());
  double largest = 0;
  for (int row = 0; row < grid.rows(); row += 7) {
    for (int col = 0; col < grid.cols(); col += 11) {
      const Eigen::Vector3d p = grid.CellPoint(row, col);
      double phi = std::atan2(p.y(), p.x());
      if (phi < 0) phi += 2 * M_PI;
      const double expected =
          simulation_->texture().Albedo(0, p.z(), 0.2 * phi, 2 * M_PI * 0.2, 0.002);
      largest = std::max(largest, std::abs(albedo.at<float>(row, col) - expected));
    }
  }
  EXPECT_LT(largest, 1e-4);
}

// Each row goes into the scene through its own placement: rows placed 1 cm further along the
// pipe read the albedo of the rows 5 cells (2 mm each) on.
TEST_F(DenseMapAgreementTest, EachRowIsPlacedByItsOwnPose) {
  const DenseMapGrid grid(Cylinder(), 0.002);
  const Eigen::Vector3d viewpoint(0, 0, 0.65);
  const cv::Mat albedo =
      SimulatedAlbedoUnderGrid(grid, Placements(grid, viewpoint), *simulation_, 0.02);
  std::vector<GridRowPlacement> moved = Placements(grid, viewpoint);
  for (int row = 0; row < grid.rows(); row += 2) {
    moved[row].scene_from_map = Eigen::Translation3d(0, 0, 0.01) * Eigen::Isometry3d::Identity();
  }
  const cv::Mat shifted = SimulatedAlbedoUnderGrid(grid, moved, *simulation_, 0.02);
  double largest = 0;
  for (int row = 0; row + 5 < grid.rows(); ++row) {
    for (int col = 0; col < grid.cols(); ++col) {
      const float expected = albedo.at<float>(row % 2 == 0 ? row + 5 : row, col);
      largest =
          std::max(largest, static_cast<double>(std::abs(shifted.at<float>(row, col) - expected)));
    }
  }
  EXPECT_LT(largest, 1e-4);
  EXPECT_THROW(SimulatedAlbedoUnderGrid(grid, {}, *simulation_, 0.02), InputError);

  // A grid 5 cm inside the wall meets it 5 cm or more from its cells: not the map's wall.
  DenseMapCylinder inside = Cylinder();
  inside.radius_m = 0.15;
  const DenseMapGrid narrow(inside, 0.002);
  const cv::Mat none =
      SimulatedAlbedoUnderGrid(narrow, Placements(narrow, viewpoint), *simulation_, 0.02);
  EXPECT_EQ(cv::countNonZero(none == none), 0);
  const cv::Mat all =
      SimulatedAlbedoUnderGrid(narrow, Placements(narrow, viewpoint), *simulation_, 1.0);
  EXPECT_EQ(cv::countNonZero(all == all), narrow.rows() * narrow.cols());
}

TEST_F(DenseMapAgreementTest, AMapOfTheAlbedoAgreesAndItsShiftIsFound) {
  const DenseMapGrid grid(Cylinder(), 0.002);
  const cv::Mat albedo = SimulatedAlbedoUnderGrid(
      grid, Placements(grid, Eigen::Vector3d(0, 0, 0.65)), *simulation_, 0.02);
  // Seen only in a band of rows, the rest black, as a piece's map is at its ends.
  cv::Mat grey = AsGrey(albedo);
  grey.rowRange(0, 20).setTo(0);
  const DenseMapAgreement same = CorrelateWithAlbedo(grey, albedo, grid);
  EXPECT_GT(same.correlation, 0.99);
  EXPECT_EQ(same.shift_rows, 0);
  EXPECT_EQ(same.shift_cols, 0);
  EXPECT_FALSE(same.shift_at_limit);
  EXPECT_GT(same.cells, (grid.rows() - 20) * grid.cols() / 2);

  // Map cell (r, c) showing the albedo of (r + 3, c - 2): the map was placed 3 rows short and 2
  // columns the other way; the columns wrap around the pipe.
  cv::Mat shifted = cv::Mat::zeros(grey.size(), CV_32F);
  const cv::Mat full = AsGrey(albedo);
  for (int row = 0; row + 3 < grid.rows(); ++row) {
    for (int col = 0; col < grid.cols(); ++col) {
      shifted.at<float>(row, col) = full.at<float>(row + 3, (col - 2 + grid.cols()) % grid.cols());
    }
  }
  const DenseMapAgreement found = CorrelateWithAlbedo(shifted, albedo, grid);
  EXPECT_GT(found.correlation, 0.99);
  EXPECT_EQ(found.shift_rows, 3);
  EXPECT_EQ(found.shift_cols, -2);

  // Mirrored around the pipe (phi turned the wrong way): no shift brings it back.
  cv::Mat mirrored;
  cv::flip(full, mirrored, 1);
  EXPECT_LT(CorrelateWithAlbedo(mirrored, albedo, grid).correlation, 0.3);

  // Noise as strong as the texture halves the agreement, about as the closed form says
  // (correlation 1 / sqrt(1 + noise / signal variance) after the same high-pass).
  cv::Mat noisy = AsGrey(albedo), noise(grey.size(), CV_32F);
  cv::Mat high = albedo.clone(), low;
  cv::GaussianBlur(albedo, low, cv::Size(0, 0), 10.0);
  high -= low;
  cv::Scalar mean, deviation;
  cv::meanStdDev(high, mean, deviation);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, 150.0 * deviation[0]);
  noisy += noise;
  const double c = CorrelateWithAlbedo(noisy, albedo, grid).correlation;
  EXPECT_GT(c, 0.55);
  EXPECT_LT(c, 0.85);
}

TEST_F(DenseMapAgreementTest, MisfitInputIsRefused) {
  const DenseMapGrid grid(Cylinder(), 0.002);
  const cv::Mat albedo(grid.rows(), grid.cols(), CV_32F, cv::Scalar(0.5));
  EXPECT_THROW(CorrelateWithAlbedo(cv::Mat(3, 3, CV_32F), albedo, grid), InputError);
  EXPECT_THROW(CorrelateWithAlbedo(cv::Mat(grid.rows(), grid.cols(), CV_16U), albedo, grid),
               InputError);
  DenseMapAgreementOptions options;
  options.high_pass_sigma_m = 0;
  EXPECT_THROW(CorrelateWithAlbedo(albedo, albedo, grid, options), InputError);
}

}  // namespace
}  // namespace pipescope
