#include "pipescope/feature/region_harris.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

namespace pipescope {
namespace {

// A smooth image of Gaussian blobs whose centres are shifted by `offset`, sampled exactly (no
// interpolation), so corners of the two renderings are offset by exactly `offset`.
cv::Mat BlobImage(cv::Size size, cv::Point2d offset, int count = 400) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> x(0, size.width), y(0, size.height), a(-80, 80);
  std::vector<cv::Point3d> blobs;
  for (int i = 0; i < count; ++i) blobs.emplace_back(x(random), y(random), a(random));
  cv::Mat image(size, CV_32F, cv::Scalar(100));
  const double s = 3.0;
  for (int r = 0; r < size.height; ++r) {
    for (int c = 0; c < size.width; ++c) {
      double value = 100.0;
      for (const cv::Point3d& b : blobs) {
        const double dx = c - b.x - offset.x, dy = r - b.y - offset.y;
        const double d2 = dx * dx + dy * dy;
        if (d2 < 100.0) value += b.z * std::exp(-0.5 * d2 / (s * s));
      }
      image.at<float>(r, c) = static_cast<float>(value);
    }
  }
  return image;
}

// Eq. 28-31 evaluated literally, pixel by pixel, with a mirrored border (cv::BORDER_REFLECT):
// the oracle for the separable, fused HarrisResponse.
cv::Mat NaiveHarrisResponse(const cv::Mat& image, double sigma_d, double sigma_w, double k) {
  auto reflect = [](int i, int n) {
    while (i < 0 || i >= n) i = i < 0 ? -i - 1 : 2 * n - i - 1;
    return i;
  };
  auto at = [&](const cv::Mat& m, int r, int c) {
    return static_cast<double>(m.at<float>(reflect(r, m.rows), reflect(c, m.cols)));
  };
  const int hd = static_cast<int>(std::ceil(3.0 * sigma_d));
  double norm_d = 0.0;
  for (int i = -hd; i <= hd; ++i) norm_d += std::exp(-0.5 * i * i / (sigma_d * sigma_d));
  // G(u) G(v) and dG/du (u) G(v), normalised so that the Gaussian sums to 1 in each axis.
  auto g = [&](int u) { return std::exp(-0.5 * u * u / (sigma_d * sigma_d)) / norm_d; };
  cv::Mat ix(image.size(), CV_32F), iy(image.size(), CV_32F);
  for (int r = 0; r < image.rows; ++r) {
    for (int c = 0; c < image.cols; ++c) {
      double sx = 0.0, sy = 0.0;
      for (int v = -hd; v <= hd; ++v) {
        for (int u = -hd; u <= hd; ++u) {
          const double value = at(image, r + v, c + u);
          // Convolution with dG/dx = -x / sigma^2 G(x): the image at c + u weighs u / sigma^2 G(u).
          sx += value * (u / (sigma_d * sigma_d)) * g(u) * g(v);
          sy += value * (v / (sigma_d * sigma_d)) * g(u) * g(v);
        }
      }
      ix.at<float>(r, c) = static_cast<float>(sx);
      iy.at<float>(r, c) = static_cast<float>(sy);
    }
  }
  const int hw = static_cast<int>(std::ceil(3.0 * sigma_w));
  double norm_w = 0.0;
  for (int v = -hw; v <= hw; ++v) {
    for (int u = -hw; u <= hw; ++u)
      norm_w += std::exp(-0.5 * (u * u + v * v) / (sigma_w * sigma_w));
  }
  cv::Mat response(image.size(), CV_32F);
  for (int r = 0; r < image.rows; ++r) {
    for (int c = 0; c < image.cols; ++c) {
      double a = 0.0, b = 0.0, d = 0.0;
      for (int v = -hw; v <= hw; ++v) {
        for (int u = -hw; u <= hw; ++u) {
          const double w = std::exp(-0.5 * (u * u + v * v) / (sigma_w * sigma_w)) / norm_w;
          const double gx = at(ix, r + v, c + u), gy = at(iy, r + v, c + u);
          a += w * gx * gx;
          b += w * gy * gy;
          d += w * gx * gy;
        }
      }
      response.at<float>(r, c) = static_cast<float>(a * b - d * d - k * (a + b) * (a + b));
    }
  }
  return response;
}

TEST(HarrisResponse, MatchesEquations28To31EvaluatedPixelByPixel) {
  const cv::Mat image = BlobImage({64, 48}, {0.3, -0.2}, 30);
  RegionHarrisOptions options;
  options.sigma_window_px = 2.0;
  const cv::Mat fast = HarrisResponse(image, options);
  const cv::Mat naive =
      NaiveHarrisResponse(image, options.sigma_derivative_px, options.sigma_window_px, options.k);
  double peak = 0.0;
  cv::minMaxLoc(cv::abs(naive), nullptr, &peak);
  ASSERT_GT(peak, 1.0);
  EXPECT_LT(cv::norm(fast, naive, cv::NORM_INF), 1e-4 * peak);
}

TEST(QuadraticPeakOffset, RecoversThePeakOfAQuadraticExactly) {
  // Eq. 32-34 are exact for a quadratic: C = -(x - 10.3)^2 - 2 (y - 7.8)^2 + 0.5 (x-10.3)(y-7.8).
  cv::Mat response(20, 20, CV_32F);
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 20; ++x) {
      const double dx = x - 10.3, dy = y - 7.8;
      response.at<float>(y, x) = static_cast<float>(-dx * dx - 2 * dy * dy + 0.5 * dx * dy);
    }
  }
  const cv::Point2f offset = QuadraticPeakOffset(response, 10, 8);
  EXPECT_NEAR(offset.x, 0.3, 1e-4);
  EXPECT_NEAR(offset.y, -0.2, 1e-4);
}

TEST(QuadraticPeakOffset, RejectsASaddle) {
  cv::Mat response(5, 5, CV_32F);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x)
      response.at<float>(y, x) = static_cast<float>((x - 2) * (x - 2) - (y - 2) * (y - 2));
  const cv::Point2f offset = QuadraticPeakOffset(response, 2, 2);
  EXPECT_EQ(offset.x, 0.f);
  EXPECT_EQ(offset.y, 0.f);
}

TEST(DetectRegionHarris, KeepsAtMostPerCellInEveryCellOfTheGrid) {
  const cv::Mat image = BlobImage({320, 240}, {0, 0}, 2000);
  RegionHarrisOptions options;
  options.per_cell = 5;
  const std::vector<Keypoint> keypoints = DetectRegionHarris(image, options);
  std::vector<int> per_cell(options.grid_rows * options.grid_cols, 0);
  for (const Keypoint& k : keypoints) {
    const int row = static_cast<int>(k.position.y + 0.5f) * options.grid_rows / 240;
    const int col = static_cast<int>(k.position.x + 0.5f) * options.grid_cols / 320;
    ++per_cell[row * options.grid_cols + col];
  }
  for (int count : per_cell) {
    EXPECT_LE(count, 5);
    EXPECT_GE(count, 1) << ::testing::PrintToString(per_cell);  // texture in every cell
  }
  EXPECT_GE(keypoints.size(), 3u * per_cell.size());
}

TEST(RegionCell, CutsTheImageIntoEqualCellsRowByRow) {
  RegionHarrisOptions options;    // 6 rows x 8 columns
  const cv::Size size(320, 240);  // cells of 40 x 40 pixels
  EXPECT_EQ(RegionCell(options, size, 0, 0), 0);
  EXPECT_EQ(RegionCell(options, size, 39, 39), 0);
  EXPECT_EQ(RegionCell(options, size, 40, 0), 1);
  EXPECT_EQ(RegionCell(options, size, 0, 40), 8);
  EXPECT_EQ(RegionCell(options, size, 319, 239), 47);
  // An odd size: pixel x lies in column floor(x * columns / width), and so for rows.
  options.grid_rows = 2;
  options.grid_cols = 2;
  const cv::Size odd(5, 3);
  EXPECT_EQ(RegionCell(options, odd, 2, 1), 0);
  EXPECT_EQ(RegionCell(options, odd, 3, 1), 1);
  EXPECT_EQ(RegionCell(options, odd, 4, 2), 3);
}

TEST(DetectRegionHarris, SubPixelPositionsFollowAShiftOfTheScene) {
  const cv::Point2d shift(0.4, -0.3);
  const cv::Mat first = BlobImage({240, 180}, {0, 0});
  const cv::Mat second = BlobImage({240, 180}, shift);
  RegionHarrisOptions options;
  const std::vector<Keypoint> a = DetectRegionHarris(first, options);
  const std::vector<Keypoint> b = DetectRegionHarris(second, options);
  std::vector<double> errors;
  for (const Keypoint& p : a) {
    for (const Keypoint& q : b) {
      const cv::Point2f d = q.position - p.position;
      if (std::hypot(d.x - shift.x, d.y - shift.y) < 0.6) {
        errors.push_back(std::hypot(d.x - shift.x, d.y - shift.y));
        break;
      }
    }
  }
  ASSERT_GT(errors.size(), 50u);
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  // Integer positions alone would be off by 0.5 px here.
  EXPECT_LT(errors[errors.size() / 2], 0.1);
}

TEST(DetectRegionHarris, BoxWindowFindsCornerHarrisMaximaOnlyInsideTheMask) {
  // 001's settings: OpenCV's cv::cornerHarris response, integer positions, a detection mask.
  const cv::Mat image = BlobImage({240, 180}, {0, 0});
  RegionHarrisOptions options;
  options.grid_rows = 2;
  options.grid_cols = 2;
  options.per_cell = 50;
  options.box_window_px = 7;
  options.subpixel = false;
  cv::Mat mask(image.size(), CV_8U, cv::Scalar(0));
  mask.colRange(120, 240).setTo(255);
  cv::Mat opencv;
  cv::cornerHarris(image, opencv, 7, 3, options.k);
  const std::vector<Keypoint> corners = DetectRegionHarris(image, options, mask);
  ASSERT_GT(corners.size(), 20u);
  for (const Keypoint& corner : corners) {
    EXPECT_GE(corner.position.x, 120.f);
    EXPECT_EQ(corner.position.x, std::round(corner.position.x));
    const int x = static_cast<int>(corner.position.x), y = static_cast<int>(corner.position.y);
    EXPECT_FLOAT_EQ(corner.response, opencv.at<float>(y, x));
    // A local maximum of OpenCV's response over the 7 x 7 window.
    for (int dy = -3; dy <= 3; ++dy) {
      for (int dx = -3; dx <= 3; ++dx) EXPECT_LE(opencv.at<float>(y + dy, x + dx), corner.response);
    }
  }
}

}  // namespace
}  // namespace pipescope
