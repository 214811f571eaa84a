#include "pipescope/feature/guided_zncc.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace pipescope {
namespace {

Camera SmallFisheye() {
  return Camera(CameraModelId::kFisheyePoly, 320, 240, {90.0, -1.0, 0.0, 0.0, 159.5, 119.5});
}

// The oracle: cv::matchTemplate's TM_CCOEFF_NORMED of the template at (150, 110) in grey_i over
// the search box around the same place in grey_j; score (v, u) is pixel (150 - r + u, 110 - r + v).
cv::Mat OpenCvScoresAround150x110(const cv::Mat& grey_i, const cv::Mat& grey_j,
                                  const GuidedZnccOptions& options) {
  const int half = options.template_size_px / 2;
  const int r = options.search_radius_px;
  const cv::Mat templ = grey_i(cv::Rect(150 - half, 110 - half, 2 * half + 1, 2 * half + 1));
  const cv::Mat box =
      grey_j(cv::Rect(150 - r - half, 110 - r - half, 2 * r + 2 * half + 1, 2 * r + 2 * half + 1));
  cv::Mat scores;
  cv::matchTemplate(box, templ, scores, cv::TM_CCOEFF_NORMED);
  return scores;
}

// A blurred noise texture (320x240) and the same shifted by (4, -3) px.
void ShiftedTexturePair(cv::Mat* grey_i, cv::Mat* grey_j) {
  cv::Mat noise(240, 320, CV_32F);
  cv::randu(noise, 0.0, 255.0);
  cv::GaussianBlur(noise, *grey_i, cv::Size(5, 5), 1.5);
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 4, 0, 1, -3);
  cv::warpAffine(*grey_i, *grey_j, shift, grey_i->size(), cv::INTER_LINEAR);
}

TEST(GuidedZncc, FindsTheBestPlaceOfOpenCvsNormalisedCorrelation) {
  // With an epipolar threshold every bearing passes, the guided search is a plain ZNCC search
  // over its box: its best pixel and score must be those of cv::matchTemplate
  // (TM_CCOEFF_NORMED) over the same box, the independent oracle.
  const Camera camera = SmallFisheye();
  const BearingTable bearings(camera);
  cv::Mat grey_i, grey_j;
  ShiftedTexturePair(&grey_i, &grey_j);
  cv::Mat disturbance(240, 320, CV_32F);
  cv::randn(disturbance, 0.0, 8.0);
  grey_j += disturbance;

  GuidedZnccOptions options;
  options.epipolar_threshold = 10.0;
  options.search_radius_px = 12;
  options.min_zncc = 0.0;
  const cv::Point2f point_i(150.f, 110.f);
  Eigen::Vector3d bearing_i;
  ASSERT_TRUE(camera.Unproject(Eigen::Vector2d(point_i.x, point_i.y), &bearing_i));
  const GuidedMatch match = GuidedZnccSearch(grey_i, grey_j, point_i, bearing_i,
                                             Eigen::Matrix3d::Identity(), bearings, options);
  ASSERT_TRUE(match.found);

  const int r = options.search_radius_px;
  const cv::Mat scores = OpenCvScoresAround150x110(grey_i, grey_j, options);
  double best;
  cv::Point best_at;
  cv::minMaxLoc(scores, nullptr, &best, nullptr, &best_at);
  EXPECT_EQ(std::lround(match.point_j.x), 150 - r + best_at.x);
  EXPECT_EQ(std::lround(match.point_j.y), 110 - r + best_at.y);
  EXPECT_NEAR(match.zncc, best, 1e-4);
  // And that is the true shift.
  EXPECT_NEAR(match.point_j.x, 154.f, 0.5f);
  EXPECT_NEAR(match.point_j.y, 107.f, 0.5f);
}

// With a real epipolar band the search scores only the pixels whose bearing lies within the
// threshold of the epipolar plane: here the true shift (4, -3) lies outside a horizontal band,
// and the match must be cv::matchTemplate's best over the band's pixels (the band taken from
// the bearing table's float bearings, as the search takes it).
TEST(GuidedZncc, ScoresOnlyTheEpipolarBand) {
  const Camera camera = SmallFisheye();
  const BearingTable bearings(camera);
  cv::Mat grey_i, grey_j;
  ShiftedTexturePair(&grey_i, &grey_j);

  GuidedZnccOptions options;
  options.search_radius_px = 12;
  options.min_zncc = -1.0;
  options.min_peak_margin = -1.0;  // every band keeps its best
  const cv::Point2f point_i(150.f, 110.f);
  Eigen::Vector3d bearing_i;
  ASSERT_TRUE(camera.Unproject(Eigen::Vector2d(point_i.x, point_i.y), &bearing_i));
  Eigen::Matrix3d essential;  // pure sideways motion along x: E = [t]x
  essential << 0, 0, 0, 0, 0, -1, 0, 1, 0;
  const GuidedMatch match =
      GuidedZnccSearch(grey_i, grey_j, point_i, bearing_i, essential, bearings, options);
  ASSERT_TRUE(match.found);

  const int r = options.search_radius_px;
  const cv::Mat scores = OpenCvScoresAround150x110(grey_i, grey_j, options);
  const Eigen::Vector3d normal = essential * bearing_i;
  const float n0 = static_cast<float>(normal.x()), n1 = static_cast<float>(normal.y()),
              n2 = static_cast<float>(normal.z());
  float best = -2.f;
  int best_x = -1, best_y = -1, in_band = 0;
  for (int v = 0; v < scores.rows; ++v) {
    for (int u = 0; u < scores.cols; ++u) {
      const int x = 150 - r + u, y = 110 - r + v;
      const cv::Vec3f eta = bearings.bearing_mat().at<cv::Vec3f>(y, x);
      if (!bearings.Valid(x, y) || std::abs(eta[0] * n0 + eta[1] * n1 + eta[2] * n2) >=
                                       static_cast<float>(options.epipolar_threshold)) {
        continue;
      }
      ++in_band;
      if (scores.at<float>(v, u) > best) {
        best = scores.at<float>(v, u);
        best_x = x;
        best_y = y;
      }
    }
  }
  ASSERT_GT(in_band, 10);
  ASSERT_LT(in_band, scores.rows * scores.cols / 3);  // a band, not the box
  EXPECT_EQ(std::lround(match.point_j.x), best_x);
  EXPECT_EQ(std::lround(match.point_j.y), best_y);
  EXPECT_NEAR(match.zncc, best, 1e-4);
  EXPECT_GT(std::abs(match.point_j.y - 107.f), 1.5f);  // not the true shift, outside the band
}

// The band's columns found with the skips are exactly those a test of every pixel finds, for
// random epipolar normals (E eta_i has norm up to 1 with |E|_F = sqrt(2)), rows and spans, on
// the small test lens and on the benchmark's 1280x960 190-degree lens cut at 70 degrees.
TEST(GuidedZncc, BandColumnsEqualTestingEveryPixel) {
  const Camera benchmark_lens(CameraModelId::kFisheyePoly, 1280, 960,
                              {291.72458689307223, -2.9172458689307228, 0, 0, 639.5, 479.5});
  const std::vector<BearingTable> tables = {BearingTable(SmallFisheye()),
                                            BearingTable(benchmark_lens, 70.0 * M_PI / 180.0)};
  cv::RNG rng(5);
  std::vector<int> band;
  long band_pixels = 0;
  for (const BearingTable& bearings : tables) {
    for (int trial = 0; trial < 3000; ++trial) {
      const cv::Vec3f normal(rng.uniform(-1.f, 1.f), rng.uniform(-1.f, 1.f),
                             rng.uniform(-1.f, 1.f));
      const float threshold = trial % 3 == 0 ? 0.001f : (trial % 3 == 1 ? 0.006f : 0.05f);
      const int y = rng.uniform(0, bearings.height());
      const int x0 = rng.uniform(0, bearings.width());
      const int x1 = std::min(bearings.width() - 1, x0 + rng.uniform(0, 200));
      bearings.EpipolarBandColumns(y, x0, x1, normal, threshold, &band);
      std::vector<int> every_pixel;
      const cv::Vec3f* eta_row = bearings.bearing_mat().ptr<cv::Vec3f>(y);
      for (int x = x0; x <= x1; ++x) {
        const cv::Vec3f& eta = eta_row[x];
        if (bearings.Valid(x, y) &&
            std::abs(eta[0] * normal[0] + eta[1] * normal[1] + eta[2] * normal[2]) < threshold) {
          every_pixel.push_back(x);
        }
      }
      ASSERT_EQ(band, every_pixel) << "trial " << trial << " row " << y;
      band_pixels += static_cast<long>(band.size());
    }
  }
  EXPECT_GT(band_pixels, 1000);
}

}  // namespace
}  // namespace pipescope
