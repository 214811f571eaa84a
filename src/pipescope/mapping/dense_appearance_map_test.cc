// The dense appearance map of 001 §IV-B: the colatitude band, the averaging over key frames, a
// rendered wall texture read back, the grid's geometry, bad input and the binary PLY file.
#include "pipescope/mapping/dense_appearance_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>

#include "pipescope/estimation/straight_window_testing.h"
#include "pipescope/geometry/pipe_cylinder.h"
#include "pipescope/mapping/dense_appearance_ply.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

constexpr double kDegPerRad = 180.0 / M_PI;

// A pipe along world Z through the origin, phi = 0 towards +X, so phi = 90° is +Y.
DenseMapCylinder PipeAlongZ(double radius_m, double begin_m, double end_m) {
  DenseMapCylinder cylinder;
  cylinder.radius_m = radius_m;
  cylinder.begin_m = begin_m;
  cylinder.end_m = end_m;
  cylinder.reference_direction = Eigen::Vector3d::UnitX();
  return cylinder;
}

// cam_from_world of a camera at `position` whose optical axis +Z is the world's +Z turned by
// `tilt_rad` about the world X axis.
Eigen::Isometry3d CameraAt(const Eigen::Vector3d& position, double tilt_rad = 0.0) {
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
  world_from_cam.linear() =
      Eigen::AngleAxisd(tilt_rad, Eigen::Vector3d::UnitX()).toRotationMatrix();
  world_from_cam.translation() = position;
  return world_from_cam.inverse();
}

cv::Mat ConstantImage(const Camera& camera, int type, double value) {
  return cv::Mat(camera.Height(), camera.Width(), type, cv::Scalar(value));
}

// The test's own account of where cell (row, col) of a pipe along Z lies: row centres every
// extent / rows from begin_m, columns every 2 pi / cols from +X towards +Y.
Eigen::Vector3d PipeAlongZCell(const DenseMapCylinder& cylinder, int rows, int cols, int row,
                               int col) {
  const double s = cylinder.begin_m + (row + 0.5) * (cylinder.end_m - cylinder.begin_m) / rows;
  const double phi = 2.0 * M_PI * col / cols;
  return Eigen::Vector3d(cylinder.radius_m * std::cos(phi), cylinder.radius_m * std::sin(phi), s);
}

double ColatitudeDeg(const Eigen::Isometry3d& cam_from_world, const Eigen::Vector3d& point) {
  const Eigen::Vector3d point_cam = cam_from_world * point;
  return std::acos(point_cam.z() / point_cam.norm()) * kDegPerRad;
}

TEST(DenseAppearanceMap, OnlyCellsSeenBetween50And90DegreesColatitudeCount) {
  const Camera camera = FisheyeTestCamera();  // r(90°) = 440 px: the whole band is on the image
  const DenseMapCylinder cylinder = PipeAlongZ(0.2, -0.4, 1.0);
  // Looking down the axis, then off the axis and tilted so the band is no longer a ring.
  for (const Eigen::Isometry3d& cam_from_world :
       {CameraAt(Eigen::Vector3d(0.0, 0.0, 0.1)),
        CameraAt(Eigen::Vector3d(0.03, -0.02, 0.1), 20.0 / kDegPerRad)}) {
    DenseAppearanceOptions options;
    options.spacing_m = 0.005;
    DenseAppearanceAccumulator accumulator(cylinder, options);
    const int added =
        accumulator.AddKeyFrame(camera, cam_from_world, ConstantImage(camera, CV_8UC1, 77));
    const DenseAppearanceMap map = accumulator.Result();
    const int rows = accumulator.grid().rows(), cols = accumulator.grid().cols();
    ASSERT_EQ(map.mean_grey.rows, rows);
    ASSERT_EQ(map.mean_grey.cols, cols);
    int in_band = 0, too_central = 0, behind = 0;
    for (int row = 0; row < rows; ++row) {
      for (int col = 0; col < cols; ++col) {
        const double theta =
            ColatitudeDeg(cam_from_world, PipeAlongZCell(cylinder, rows, cols, row, col));
        if (std::abs(theta - 50.0) < 1e-6 || std::abs(theta - 90.0) < 1e-6) continue;
        const bool expected = theta > 50.0 && theta < 90.0;
        const float mean = map.mean_grey.at<float>(row, col);
        const int count = map.count.at<int>(row, col);
        if (expected) {
          ++in_band;
          ASSERT_EQ(count, 1) << "theta " << theta << " at " << row << ", " << col;
          ASSERT_NEAR(mean, 77.0f, 1e-4f);
        } else {
          theta <= 50.0 ? ++too_central : ++behind;
          ASSERT_EQ(count, 0) << "theta " << theta << " at " << row << ", " << col;
          ASSERT_TRUE(std::isnan(mean));
        }
      }
    }
    // Every side of the gate is exercised.
    EXPECT_GT(in_band, 1000);
    EXPECT_GT(too_central, 1000);
    EXPECT_GT(behind, 1000);
    EXPECT_EQ(added, in_band);
    EXPECT_EQ(static_cast<int>(map.points.size()), in_band);
  }
}

TEST(DenseAppearanceMap, BandIsConfigurableAndPixelsOffTheImageDoNotCount) {
  // A pinhole on a small image (half-angles 47° x 39°): with a 20°..60° band, part of the band
  // falls off the image.
  const Camera camera(CameraModelId::kPinholeRadtan, 320, 240,
                      {150.0, 150.0, 159.5, 119.5, 0.0, 0.0, 0.0, 0.0, 0.0});
  const DenseMapCylinder cylinder = PipeAlongZ(0.2, 0.0, 1.5);
  DenseAppearanceOptions options;
  options.spacing_m = 0.005;
  options.min_colatitude_deg = 20.0;
  options.max_colatitude_deg = 60.0;
  DenseAppearanceAccumulator accumulator(cylinder, options);
  const Eigen::Isometry3d cam_from_world = CameraAt(Eigen::Vector3d(0.01, 0.0, 0.05));
  accumulator.AddKeyFrame(camera, cam_from_world, ConstantImage(camera, CV_32FC1, 50.0));
  const DenseAppearanceMap map = accumulator.Result();
  const int rows = accumulator.grid().rows(), cols = accumulator.grid().cols();
  int seen = 0, off_image = 0;
  for (int row = 0; row < rows; ++row) {
    for (int col = 0; col < cols; ++col) {
      const Eigen::Vector3d point = PipeAlongZCell(cylinder, rows, cols, row, col);
      const double theta = ColatitudeDeg(cam_from_world, point);
      if (std::abs(theta - 20.0) < 1e-6 || std::abs(theta - 60.0) < 1e-6) continue;
      const Eigen::Vector3d point_cam = cam_from_world * point;
      const Eigen::Vector2d pixel(150.0 * point_cam.x() / point_cam.z() + 159.5,
                                  150.0 * point_cam.y() / point_cam.z() + 119.5);
      const bool in_band = theta > 20.0 && theta < 60.0;
      const bool on_image =
          pixel.x() >= -0.5 && pixel.x() <= 319.5 && pixel.y() >= -0.5 && pixel.y() <= 239.5;
      if (in_band && !on_image) ++off_image;
      const bool expected = in_band && on_image;
      seen += expected;
      ASSERT_EQ(map.count.at<int>(row, col), expected ? 1 : 0) << theta << " " << pixel.transpose();
    }
  }
  EXPECT_GT(seen, 1000);
  EXPECT_GT(off_image, 1000);
}

TEST(DenseAppearanceMap, CellsSeenByTwoKeyFramesTakeTheirMean) {
  const Camera camera = FisheyeTestCamera();
  const DenseMapCylinder cylinder = PipeAlongZ(0.2, 0.0, 1.0);
  DenseAppearanceOptions options;
  options.spacing_m = 0.004;
  DenseAppearanceAccumulator accumulator(cylinder, options);
  // Each sees a band about 0.17 m long ahead of it; the bands overlap by about 0.07 m. One image
  // is 8-bit, the other float.
  const Eigen::Isometry3d first = CameraAt(Eigen::Vector3d(0.0, 0.01, 0.2));
  const Eigen::Isometry3d second = CameraAt(Eigen::Vector3d(0.01, 0.0, 0.3), 0.05);
  accumulator.AddKeyFrame(camera, first, ConstantImage(camera, CV_8UC1, 100));
  accumulator.AddKeyFrame(camera, second, ConstantImage(camera, CV_32FC1, 200));
  EXPECT_EQ(accumulator.num_key_frames(), 2);
  const DenseAppearanceMap map = accumulator.Result();
  const int rows = accumulator.grid().rows(), cols = accumulator.grid().cols();
  const auto in_band = [](double theta) { return theta > 50.0 && theta < 90.0; };
  int by_both = 0, by_first = 0, by_second = 0, seen = 0;
  for (int row = 0; row < rows; ++row) {
    for (int col = 0; col < cols; ++col) {
      const Eigen::Vector3d point = PipeAlongZCell(cylinder, rows, cols, row, col);
      const double theta_first = ColatitudeDeg(first, point);
      const double theta_second = ColatitudeDeg(second, point);
      const bool first_sees = in_band(theta_first), second_sees = in_band(theta_second);
      const float mean = map.mean_grey.at<float>(row, col);
      ASSERT_EQ(map.count.at<int>(row, col), first_sees + second_sees);
      if (first_sees && second_sees) {
        ++by_both;
        ASSERT_NEAR(mean, 150.0f, 1e-4f);
      } else if (first_sees) {
        ++by_first;
        ASSERT_NEAR(mean, 100.0f, 1e-4f);
      } else if (second_sees) {
        ++by_second;
        ASSERT_NEAR(mean, 200.0f, 1e-4f);
      } else {
        ASSERT_TRUE(std::isnan(mean));
      }
      seen += first_sees || second_sees;
    }
  }
  EXPECT_GT(by_both, 1000);
  EXPECT_GT(by_first, 1000);
  EXPECT_GT(by_second, 1000);
  // The points are the seen cells, on the grid, with their means.
  ASSERT_EQ(static_cast<int>(map.points.size()), seen);
  for (const DenseMapPoint& point : map.points) {
    EXPECT_EQ(point.grey, map.mean_grey.at<float>(point.row, point.col));
    EXPECT_LT((point.position - PipeAlongZCell(cylinder, rows, cols, point.row, point.col)).norm(),
              1e-12);
  }
}

// A wall texture in the pipe frame (axis along z from the axis point, phi from +x towards +y):
// 3 cm waves along the axis plus 31 waves around, odd in phi so a mirrored phi would show.
double WallTexture(double s_m, double phi_rad) {
  return 128.0 + 50.0 * std::sin(2.0 * M_PI * s_m / 0.03) + 50.0 * std::sin(31.0 * phi_rad);
}

// Renders what a camera at `pipe_from_cam` sees of WallTexture on a pipe of radius `radius_m`:
// each pixel's ray is followed to the wall; pixels off the lens, or along the axis, are 0.
cv::Mat RenderWall(const Camera& camera, const Eigen::Isometry3d& pipe_from_cam, double radius_m) {
  cv::Mat image(camera.Height(), camera.Width(), CV_32F, cv::Scalar(0.0));
  Eigen::Vector3d bearing;
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      if (!camera.Unproject(Eigen::Vector2d(x, y), &bearing)) continue;
      const Eigen::Vector3d direction = pipe_from_cam.linear() * bearing;
      const std::optional<double> t = RayToWall(pipe_from_cam.translation(), direction, radius_m);
      if (!t) continue;
      const Eigen::Vector3d wall = pipe_from_cam.translation() + *t * direction;
      image.at<float>(y, x) =
          static_cast<float>(WallTexture(wall.z(), std::atan2(wall.y(), wall.x())));
    }
  }
  return image;
}

TEST(DenseAppearanceMap, ReadsBackAWallTextureRenderedThroughTheFisheye) {
  const Camera camera = FisheyeTestCamera();
  // A pipe on a tilted axis away from the world origin.
  DenseMapCylinder cylinder;
  cylinder.axis_point = Eigen::Vector3d(0.3, -0.1, 0.5);
  cylinder.axis_direction = Eigen::Vector3d(0.2, -0.1, 1.0).normalized();
  cylinder.radius_m = 0.2;
  cylinder.begin_m = 0.2;
  cylinder.end_m = 0.6;
  cylinder.reference_direction = Eigen::Vector3d(1.0, 0.3, 0.0);
  // The pipe frame: the reference direction made perpendicular to the axis, then axis x it.
  const Eigen::Vector3d& axis = cylinder.axis_direction;
  const Eigen::Vector3d phi_zero =
      (*cylinder.reference_direction - cylinder.reference_direction->dot(axis) * axis).normalized();
  Eigen::Isometry3d world_from_pipe = Eigen::Isometry3d::Identity();
  world_from_pipe.linear() << phi_zero, axis.cross(phi_zero), axis;
  world_from_pipe.translation() = cylinder.axis_point;

  DenseAppearanceAccumulator accumulator(cylinder);  // 2 mm cells, 50°..90°
  for (int k = 0; k < 2; ++k) {
    // Wobbling key frames 6 cm apart down the pipe, from s = 0.25 m.
    Eigen::Isometry3d pipe_from_cam = WobblingCamFromWorld(k + 1, 0.06).inverse();
    pipe_from_cam.translation().z() += 0.19;
    const cv::Mat image = RenderWall(camera, pipe_from_cam, cylinder.radius_m);
    accumulator.AddKeyFrame(camera, (world_from_pipe * pipe_from_cam).inverse(), image);
  }
  const DenseAppearanceMap map = accumulator.Result();
  const DenseMapGrid& grid = accumulator.grid();

  // Correlation of the map with the texture at the cell centres, over the cells seen.
  double sum_map = 0, sum_texture = 0, sum_map2 = 0, sum_texture2 = 0, sum_product = 0;
  double sum_error2 = 0;
  int n = 0;
  for (int row = 0; row < grid.rows(); ++row) {
    for (int col = 0; col < grid.cols(); ++col) {
      const double value = map.mean_grey.at<float>(row, col);
      if (std::isnan(value)) continue;
      const double s =
          cylinder.begin_m + (row + 0.5) * (cylinder.end_m - cylinder.begin_m) / grid.rows();
      const double texture = WallTexture(s, 2.0 * M_PI * col / grid.cols());
      sum_map += value;
      sum_texture += texture;
      sum_map2 += value * value;
      sum_texture2 += texture * texture;
      sum_product += value * texture;
      sum_error2 += (value - texture) * (value - texture);
      ++n;
    }
  }
  ASSERT_GT(n, 10000);
  const double covariance = sum_product / n - (sum_map / n) * (sum_texture / n);
  const double variance_map = sum_map2 / n - (sum_map / n) * (sum_map / n);
  const double variance_texture = sum_texture2 / n - (sum_texture / n) * (sum_texture / n);
  const double correlation = covariance / std::sqrt(variance_map * variance_texture);
  const double rms = std::sqrt(sum_error2 / n);
  std::cout << "dense map vs texture over " << n << " of " << grid.rows() * grid.cols()
            << " cells: correlation " << correlation << ", rms " << rms << " grey levels\n";
  EXPECT_GT(correlation, 0.95);
  EXPECT_LT(rms, 2.0);  // a 1 mm shift along the axis would give about 7
}

TEST(DenseAppearanceMap, GridCellsLieOnTheWallAtTheirAxialPositionAndAngle) {
  DenseMapCylinder cylinder;
  cylinder.axis_point = Eigen::Vector3d(1.0, 2.0, 3.0);
  cylinder.axis_direction = Eigen::Vector3d(1.0, 1.0, 0.0);  // not unit: the grid normalises
  cylinder.radius_m = 0.15;
  cylinder.begin_m = -0.1;
  cylinder.end_m = 0.3;
  const DenseMapGrid grid(cylinder, 0.002);
  EXPECT_EQ(grid.rows(), 200);  // 0.4 m / 2 mm
  EXPECT_EQ(grid.cols(), 471);  // round(2 pi 0.15 / 0.002)
  EXPECT_NEAR(grid.axial_step_m(), 0.002, 1e-15);
  EXPECT_NEAR(grid.angular_step_rad() * 0.15, 0.002, 0.002 * 0.002);  // arc within 0.2 %
  // No reference given: world Z, the world axis least aligned with the pipe's.
  EXPECT_LT((grid.reference_direction() - Eigen::Vector3d::UnitZ()).norm(), 1e-12);

  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, 1.0, 0.0).normalized();
  const Eigen::Vector3d phi_zero = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d phi_quarter = axis.cross(phi_zero);
  for (const auto& [row, col] : {std::pair{0, 0}, std::pair{0, 470}, std::pair{199, 0},
                                 std::pair{100, 117}, std::pair{57, 300}, std::pair{199, 470}}) {
    const Eigen::Vector3d offset = grid.CellPoint(row, col) - cylinder.axis_point;
    const double s = offset.dot(axis);
    EXPECT_NEAR((offset - s * axis).norm(), 0.15, 1e-12) << row << ", " << col;
    EXPECT_NEAR(s, -0.1 + (row + 0.5) * 0.002, 1e-12) << row << ", " << col;
    const double phi = std::atan2(offset.dot(phi_quarter), offset.dot(phi_zero));
    EXPECT_NEAR(std::remainder(phi - 2.0 * M_PI * col / 471, 2.0 * M_PI), 0.0, 1e-12)
        << row << ", " << col;
  }
  // Neighbours are a spacing apart along the axis and about one around it.
  EXPECT_NEAR((grid.CellPoint(10, 5) - grid.CellPoint(11, 5)).norm(), 0.002, 1e-12);
  EXPECT_NEAR((grid.CellPoint(10, 5) - grid.CellPoint(10, 6)).norm(), 0.002, 1e-5);

  // A given reference direction keeps only its part across the axis.
  cylinder.reference_direction = Eigen::Vector3d(1.0, 1.0, 1.0);
  EXPECT_LT((DenseMapGrid(cylinder, 0.002).reference_direction() - phi_zero).norm(), 1e-12);
}

TEST(DenseAppearanceMap, BadInputIsAnInputError) {
  const DenseMapCylinder good = PipeAlongZ(0.2, 0.0, 1.0);
  EXPECT_NO_THROW(DenseMapGrid(good, 0.002));
  EXPECT_THROW(DenseMapGrid(good, 0.0), InputError);
  EXPECT_THROW(DenseMapGrid(good, -0.002), InputError);
  EXPECT_THROW(DenseMapGrid(good, std::nan("")), InputError);
  DenseMapCylinder empty = good;
  empty.end_m = empty.begin_m;
  EXPECT_THROW(DenseMapGrid(empty, 0.002), InputError);
  empty.end_m = empty.begin_m - 0.5;
  EXPECT_THROW(DenseMapGrid(empty, 0.002), InputError);
  DenseMapCylinder flat = good;
  flat.radius_m = 0.0;
  EXPECT_THROW(DenseMapGrid(flat, 0.002), InputError);
  DenseMapCylinder no_axis = good;
  no_axis.axis_direction = Eigen::Vector3d::Zero();
  EXPECT_THROW(DenseMapGrid(no_axis, 0.002), InputError);
  DenseMapCylinder reference_along_axis = good;
  reference_along_axis.reference_direction = Eigen::Vector3d(0.0, 0.0, -2.0);
  EXPECT_THROW(DenseMapGrid(reference_along_axis, 0.002), InputError);

  DenseAppearanceOptions options;
  options.spacing_m = -1.0;
  EXPECT_THROW(DenseAppearanceAccumulator(good, options), InputError);
  options = DenseAppearanceOptions();
  options.min_colatitude_deg = 90.0;
  options.max_colatitude_deg = 50.0;
  EXPECT_THROW(DenseAppearanceAccumulator(good, options), InputError);

  const Camera camera = FisheyeTestCamera();
  DenseAppearanceAccumulator accumulator(good);
  const Eigen::Isometry3d pose = CameraAt(Eigen::Vector3d(0.0, 0.0, 0.5));
  EXPECT_THROW(accumulator.AddKeyFrame(camera, pose, ConstantImage(camera, CV_8UC3, 1)),
               InputError);
  EXPECT_THROW(accumulator.AddKeyFrame(camera, pose, cv::Mat(10, 10, CV_8UC1, cv::Scalar(1))),
               InputError);
  EXPECT_EQ(accumulator.num_key_frames(), 0);
}

float LittleEndianFloat(const std::string& bytes, std::size_t at) {
  std::uint32_t bits = 0;
  for (int k = 0; k < 4; ++k)
    bits |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + k])) << (8 * k);
  float value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}

TEST(DenseAppearancePly, WritesBinaryLittleEndianFloatsAndGreyAsEqualColours) {
  const std::filesystem::path dir = MakeTestDirectory("dense_appearance_ply");
  const std::vector<DenseMapPoint> points = {{Eigen::Vector3d(1.5, -0.25, 3.0), 99.6f, 0, 0},
                                             {Eigen::Vector3d(0.0, 2.0, -1.0), 300.0f, 0, 1},
                                             {Eigen::Vector3d(0.5, 0.5, 0.5), -4.0f, 1, 0}};
  WriteDenseAppearancePly(dir / "points_dense.ply", points);
  const std::string file = ReadTextFile(dir / "points_dense.ply");
  const std::string end = "end_header\n";
  const std::size_t body = file.find(end) + end.size();
  ASSERT_NE(file.find(end), std::string::npos);
  const std::string header = file.substr(0, body);
  EXPECT_EQ(header.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u) << header;
  for (const char* line : {"element vertex 3\n",
                           "property float x\nproperty float y\n"
                           "property float z\nproperty uchar red\n"
                           "property uchar green\nproperty uchar blue\n"}) {
    EXPECT_NE(header.find(line), std::string::npos) << line;
  }
  ASSERT_EQ(file.size() - body, 3u * 15u);
  const std::uint8_t expected_grey[] = {100, 255, 0};  // rounded, clamped
  for (int i = 0; i < 3; ++i) {
    const std::size_t at = body + 15 * i;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(LittleEndianFloat(file, at + 4 * k), static_cast<float>(points[i].position[k]));
    }
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(static_cast<unsigned char>(file[at + 12 + k]), expected_grey[i]) << i;
    }
  }
}

// Written in pieces, the file holds the same vertices as written at once, and its header's
// count (padded with spaces) reads as the total.
TEST(DenseAppearancePly, APieceByPieceWriterGivesTheSameCloud) {
  const std::filesystem::path dir = MakeTestDirectory("dense_appearance_ply_stream");
  const std::vector<DenseMapPoint> first = {{Eigen::Vector3d(1.5, -0.25, 3.0), 99.6f, 0, 0},
                                            {Eigen::Vector3d(0.0, 2.0, -1.0), 300.0f, 0, 1}};
  const std::vector<DenseMapPoint> second = {{Eigen::Vector3d(0.5, 0.5, 0.5), -4.0f, 1, 0}};
  DenseAppearancePlyWriter writer(dir / "streamed.ply", "test");
  writer.Append(first);
  writer.Append({});
  writer.Append(second);
  writer.Close();
  EXPECT_EQ(writer.points(), 3);
  std::vector<DenseMapPoint> all = first;
  all.insert(all.end(), second.begin(), second.end());
  WriteDenseAppearancePly(dir / "whole.ply", all, "test");
  const std::string streamed = ReadTextFile(dir / "streamed.ply");
  const std::string whole = ReadTextFile(dir / "whole.ply");
  const std::string end = "end_header\n";
  const std::size_t streamed_body = streamed.find(end) + end.size();
  const std::size_t whole_body = whole.find(end) + end.size();
  EXPECT_EQ(streamed.substr(streamed_body), whole.substr(whole_body));
  std::istringstream header(streamed.substr(0, streamed_body));
  std::vector<std::string> words;
  for (std::string word; header >> word;) words.push_back(word);
  std::istringstream whole_header(whole.substr(0, whole_body));
  std::vector<std::string> whole_words;
  for (std::string word; whole_header >> word;) whole_words.push_back(word);
  EXPECT_EQ(words, whole_words);  // the same header word for word: "element vertex 3"
  EXPECT_THROW(DenseAppearancePlyWriter(dir / "missing" / "x.ply"), InputError);
}

}  // namespace
}  // namespace pipescope
