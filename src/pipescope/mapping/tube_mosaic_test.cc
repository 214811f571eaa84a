// The tube centreline and the dewarping of 004 §3: the chain's geometry against closed forms,
// and a frame rendered by the simulator, dewarped onto the true cylinder, against the
// simulator's own wall texture.
#include "pipescope/mapping/tube_mosaic.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/simulation.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

TubeSection Section(const Eigen::Vector3d& start, const Eigen::Vector3d& axis, double radius) {
  TubeSection section;
  section.start = start;
  section.axis = axis.normalized();
  section.log_radius = std::log(radius);
  return section;
}

TEST(TubeCentreline, RunsThroughTheCornersOfTheChain) {
  // Two sections meeting at (0, 0, 1), the second turned 30 degrees towards +x.
  const Eigen::Vector3d turned(std::sin(M_PI / 6), 0.0, std::cos(M_PI / 6));
  const std::vector<TubeSection> sections = {
      Section(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.1),
      Section(Eigen::Vector3d(0, 0, 1) + 0.2 * turned, turned, 0.11)};
  // The junction is the corner where the axes meet, not the second start.
  EXPECT_LT((SectionJunction(sections[0], sections[1]) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-12);
  const TubeCentreline centreline =
      BuildTubeCentreline(sections, Eigen::Vector3d(0.02, 0.01, 0.1),
                          Eigen::Vector3d(0, 0, 1) + 0.5 * turned, Eigen::Vector3d::UnitX());
  ASSERT_EQ(centreline.points.size(), 3u);
  EXPECT_NEAR(centreline.arc_m[1], 0.9, 1e-12);
  EXPECT_NEAR(centreline.Length(), 1.4, 1e-12);
  EXPECT_EQ(centreline.section[1], 1);
  EXPECT_DOUBLE_EQ(centreline.radius_m[1], 0.11);
  // Arc lengths of points beside the line, before its start and past its end.
  EXPECT_NEAR(ArcLengthAlong(centreline, Eigen::Vector3d(0.05, 0, 0.5)), 0.4, 1e-12);
  EXPECT_NEAR(ArcLengthAlong(centreline, Eigen::Vector3d(0, 0, 0.0)), -0.1, 1e-12);
  EXPECT_NEAR(ArcLengthAlong(centreline, Eigen::Vector3d(0, 0, 1) + 0.7 * turned), 1.6, 1e-12);
  // phi = 0 is carried through the turn: +x turns with the axis about y.
  const CentrelineFrame after = CentrelineFrameAt(centreline, 1.2);
  EXPECT_LT((after.tangent - turned).norm(), 1e-12);
  EXPECT_LT((after.normal - Eigen::Vector3d(std::cos(M_PI / 6), 0, -std::sin(M_PI / 6))).norm(),
            1e-12);
  EXPECT_LT((after.binormal - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(after.radius_m, 0.11);

  const std::filesystem::path dir = MakeTestDirectory("tube_centreline");
  WriteCentrelineCsv(dir / "c.csv", centreline);
  std::istringstream csv(ReadTextFile(dir / "c.csv"));
  std::string header, first, second;
  std::getline(csv, header);
  std::getline(csv, first);
  std::getline(csv, second);
  EXPECT_EQ(header, "arc_m,x_m,y_m,z_m,radius_m,section");
  double values[6];
  std::istringstream fields(second);
  for (double& value : values) {
    std::string field;
    std::getline(fields, field, ',');
    value = std::stod(field);
  }
  EXPECT_NEAR(values[0], 0.9, 1e-9);
  EXPECT_NEAR(values[3], 1.0, 1e-9);
  EXPECT_NEAR(values[4], 0.11, 1e-12);
  EXPECT_EQ(values[5], 1.0);
  WriteCentrelinePly(dir / "c.ply", centreline);
  const std::string ply = ReadTextFile(dir / "c.ply");
  EXPECT_NE(ply.find("element vertex 3"), std::string::npos);
  EXPECT_NE(ply.find("element edge 2"), std::string::npos);
  EXPECT_NE(ply.find("\n1 2\n"), std::string::npos);
  std::filesystem::remove_all(dir);
}

// A bend (2 /m, 0.4 m) and a straight section whose start the filter moved 8 mm off the bend's
// end and whose axis leaves 9 degrees off the bend's end tangent: the short segment bridging
// the two is tilted far more than either. The rings of wall across the tube (the mosaic's
// columns) must still follow one another without folding back: each ring's wall points lie
// ahead of the ring before it, at every clock angle.
TEST(TubeCentreline, RingsDoNotFoldBackAtAnOffsetKinkedJunction) {
  const double radius = 0.1;
  TubeSection bend = Section(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), radius);
  bend.curvature = Eigen::Vector3d(0, 2.0, 0);
  const double bend_length = 0.4;
  const Eigen::Vector3d end_tangent = bend.TangentAt(bend_length);
  const Eigen::Vector3d turn_axis = end_tangent.cross(Eigen::Vector3d::UnitY()).normalized();
  const Eigen::Vector3d kinked =
      Eigen::AngleAxisd(-9.0 * M_PI / 180.0, turn_axis.cross(end_tangent)) * end_tangent;
  const Eigen::Vector3d offset = 0.008 * turn_axis;
  TubeSection straight = Section(bend.CentrelinePoint(bend_length) + offset, kinked, radius);
  const std::vector<TubeSection> sections = {bend, straight};
  const TubeCentreline centreline = BuildTubeCentreline(
      sections, Eigen::Vector3d::Zero(), straight.start + 0.3 * kinked, Eigen::Vector3d::UnitX());
  ASSERT_GE(centreline.points.size(), 4u);
  const double junction_arc = centreline.arc_m[centreline.points.size() - 2];

  auto ring = [&](const CentrelineFrame& frame, double phi) {
    return Eigen::Vector3d(frame.point + frame.radius_m * (std::cos(phi) * frame.normal -
                                                           std::sin(phi) * frame.binormal));
  };
  // The worst step ahead (metres along the earlier ring's tangent) from one ring to the next,
  // 0.5 mm apart, over 5 cm either side of the junction and 72 clock angles.
  auto worst_step = [&](auto frame_at) {
    double worst = std::numeric_limits<double>::infinity();
    for (double s = junction_arc - 0.05; s < junction_arc + 0.05; s += 0.0005) {
      const CentrelineFrame here = frame_at(s), next = frame_at(s + 0.0005);
      for (int k = 0; k < 72; ++k) {
        const double phi = 2.0 * M_PI * k / 72;
        worst = std::min(worst, (ring(next, phi) - here.point).dot(here.tangent));
      }
    }
    return worst;
  };
  const double worst = worst_step([&](double s) { return CentrelineFrameAt(centreline, s); });
  // The same rings squared to each segment's own direction fold back by centimetres (the
  // bridging segment's tilt over the radius): the case is one that can fail.
  const double worst_by_segments = worst_step([&](double s) {
    CentrelineFrame frame = CentrelineFrameAt(centreline, s);
    const int i =
        static_cast<int>(std::upper_bound(centreline.arc_m.begin(), centreline.arc_m.end(), s) -
                         centreline.arc_m.begin() - 1);
    frame.tangent = (centreline.points[i + 1] - centreline.points[i]).normalized();
    frame.normal = centreline.normals[i];
    frame.binormal = frame.tangent.cross(frame.normal);
    return frame;
  });
  std::printf("worst step %.2f mm (rings squared to the segments: %.2f mm)\n", 1000 * worst,
              1000 * worst_by_segments);
  EXPECT_LT(worst_by_segments, -0.005);
  EXPECT_GT(worst, 0.0);
  // Away from the junction the frame is the sections' own: on the straight section, its axis.
  EXPECT_LT((CentrelineFrameAt(centreline, junction_arc + 0.15).tangent - kinked).norm(), 1e-9);
}

// A camera that turned back in a straight pipe: the second section runs the other way. The
// frames near the junction stay defined (the two tangents have no bisector).
TEST(TubeCentreline, FramesStayDefinedWhereTheCameraTurnedBack) {
  const std::vector<TubeSection> sections = {
      Section(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.1),
      Section(Eigen::Vector3d(0, 0, 1), -Eigen::Vector3d::UnitZ(), 0.1)};
  const TubeCentreline centreline = BuildTubeCentreline(
      sections, Eigen::Vector3d(0, 0, 0.1), Eigen::Vector3d(0, 0, 0.5), Eigen::Vector3d::UnitX());
  std::vector<double> arcs = centreline.arc_m;  // the junction itself, where the two meet
  for (double s = 0.0; s <= centreline.Length(); s += 0.01) arcs.push_back(s);
  for (const double s : arcs) {
    const CentrelineFrame frame = CentrelineFrameAt(centreline, s);
    EXPECT_TRUE(frame.tangent.allFinite() && frame.normal.allFinite()) << "at " << s;
    EXPECT_NEAR(frame.tangent.norm(), 1.0, 1e-9) << "at " << s;
    EXPECT_NEAR(frame.normal.dot(frame.tangent), 0.0, 1e-9) << "at " << s;
  }
}

cv::Mat HighPass(const cv::Mat& image) {
  cv::Mat blurred;
  cv::GaussianBlur(image, blurred, cv::Size(), 4.0);
  return image - blurred;
}

TEST(TubeMosaic, DewarpedFrameMatchesTheSimulatorsTexture) {
  // 004's forward camera in a straight tube of radius 0.1 m.
  SimulationConfig config = PresetConfig("tube-bend");
  config.layout = "straight";
  config.length_m = 1.0;
  config.frames = 2;
  config.width = 320;
  config.height = 240;
  config.marking_spacing_m = 0.0;
  const Simulation simulation(config);
  const Camera& camera = simulation.camera();
  const Eigen::Isometry3d pose = simulation.FramePose(0);
  const cv::Mat radiance = simulation.RenderFrameRadiance(0);
  const double radius = config.radius_m;

  // The true cylinder: the pipe's axis is Z, phi = 0 along +X (the scene's reference).
  const std::vector<TubeSection> truth = {
      Section(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), radius)};
  const TubeCentreline centreline = BuildTubeCentreline(
      truth, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1.0), Eigen::Vector3d::UnitX());
  const double camera_arc = ArcLengthAlong(centreline, pose.translation());
  TubeMosaicOptions options;
  options.pixel_m = 0.001;
  TubeMosaic mosaic(centreline, 0.0, 1.0, options);
  mosaic.AddFrame(radiance, camera, pose, camera_arc);

  // The albedo at each cell the frame saw, from the texture the renderer used.
  const cv::Mat& image = mosaic.image();
  cv::Mat albedo(image.size(), CV_32F, cv::Scalar(0));
  cv::Mat seen(image.size(), CV_8U, cv::Scalar(0));
  const double circumference = 2.0 * M_PI * radius;
  for (int row = 0; row < image.rows; ++row) {
    for (int col = 0; col < image.cols; ++col) {
      if (std::isnan(image.at<float>(row, col))) continue;
      const double h = mosaic.begin_m() + (col + 0.5) * mosaic.pixel_m();
      // Rows turn from +X towards -Y: the scene's phi (from +X towards +Y) runs the other way.
      const double s = circumference * (1.0 - (row + 0.5) / image.rows);
      albedo.at<float>(row, col) = simulation.texture().Albedo(0, h, s, circumference, 0.002);
      seen.at<uchar>(row, col) = 255;
    }
  }
  const int seen_cells = cv::countNonZero(seen);
  ASSERT_GT(seen_cells, image.rows * 100) << "the frame shows at least 10 cm of the whole ring";
  // Compare the texture (high-passed: the LEDs' fall-off is not in the albedo) away from the
  // edge of what the frame saw.
  cv::Mat filled = image.clone();
  filled.setTo(0, seen == 0);
  const cv::Mat a = HighPass(filled), b = HighPass(albedo);
  cv::Mat inner;
  cv::erode(seen, inner, cv::Mat(), cv::Point(-1, -1), 12);
  // Where the frame resolves the wall best: one to two radii ahead (farther, a pixel spans
  // several millimetres of wall seen at a grazing angle).
  for (int col = 0; col < image.cols; ++col) {
    const double ahead = mosaic.begin_m() + (col + 0.5) * mosaic.pixel_m() - camera_arc;
    if (ahead < radius || ahead > 2.0 * radius) inner.col(col).setTo(0);
  }
  ASSERT_GT(cv::countNonZero(inner), image.rows * 50);
  cv::Scalar mean_a, std_a, mean_b, std_b;
  cv::meanStdDev(a, mean_a, std_a, inner);
  cv::meanStdDev(b, mean_b, std_b, inner);
  cv::Mat product = (a - mean_a[0]).mul(b - mean_b[0]);
  const double correlation = cv::mean(product, inner)[0] / (std_a[0] * std_b[0]);
  EXPECT_GT(correlation, 0.8);
  // Control: the same texture a quarter turn off does not match.
  cv::Mat rolled;
  cv::vconcat(b.rowRange(image.rows / 4, image.rows), b.rowRange(0, image.rows / 4), rolled);
  cv::meanStdDev(rolled, mean_b, std_b, inner);
  product = (a - mean_a[0]).mul(rolled - mean_b[0]);
  EXPECT_LT(std::abs(cv::mean(product, inner)[0] / (std_a[0] * std_b[0])), 0.2);
}

}  // namespace
}  // namespace pipescope
