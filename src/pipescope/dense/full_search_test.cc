#include "pipescope/dense/full_search.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "pipescope/dense/dense_image.h"
#include "pipescope/dense/testing.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

// Eq. 13-17 written out: one pass over the overlap per shift, in double.
double NaiveCost(const cv::Mat& reference, const cv::Mat& next, FullSearchCost cost, int tx, int ty,
                 double min_overlap_fraction) {
  double n = 0, sad = 0, ssd = 0, sr = 0, si = 0;
  for (int y = 0; y < reference.rows; ++y) {
    for (int x = 0; x < reference.cols; ++x) {
      if (x + tx < 0 || x + tx >= next.cols || y + ty < 0 || y + ty >= next.rows) continue;
      const double r = reference.at<float>(y, x), i = next.at<float>(y + ty, x + tx);
      n += 1;
      sad += std::abs(r - i);
      ssd += (r - i) * (r - i);
      sr += r;
      si += i;
    }
  }
  if (n == 0 || n < min_overlap_fraction * reference.rows * reference.cols) {
    return std::numeric_limits<double>::infinity();
  }
  if (cost == FullSearchCost::kSad) return sad / n;
  if (cost == FullSearchCost::kSsd) return ssd / n;
  const double mu_r = sr / n, mu_i = si / n;
  double covariance = 0, var_r = 0, var_i = 0;
  for (int y = 0; y < reference.rows; ++y) {
    for (int x = 0; x < reference.cols; ++x) {
      if (x + tx < 0 || x + tx >= next.cols || y + ty < 0 || y + ty >= next.rows) continue;
      const double r = reference.at<float>(y, x) - mu_r;
      const double i = next.at<float>(y + ty, x + tx) - mu_i;
      covariance += r * i;
      var_r += r * r;
      var_i += i * i;
    }
  }
  return -covariance / std::sqrt(var_r * var_i);
}

class FullSearchCostTest : public ::testing::TestWithParam<FullSearchCost> {};

TEST_P(FullSearchCostTest, CostSurfaceEqualsNaiveReference) {
  // Arbitrary range: a large offset and scale, as gain-corrected frames can have; the FFT path
  // must not lose the small SSD at the match to cancellation.
  RegistrationPair pair = MakeRegistrationPair({72, 52}, {3.0, -2.0}, 0.0, 2.0, 11);
  pair.reference = pair.reference * 7.5 + 4000.0;
  pair.next = pair.next * 7.5 + 4000.0;
  FullSearchOptions options;
  options.cost = GetParam();
  options.max_shift_x_px = 9;
  options.max_shift_y_px = 7;
  options.min_overlap_fraction = 0.8;  // some shifts of the window fall below it
  const FullSearchResult result = RegisterFullSearch(pair.reference, pair.next, options);
  ASSERT_EQ(result.cost_surface.rows, 15);
  ASSERT_EQ(result.cost_surface.cols, 19);
  int infinite = 0;
  for (int ty = -7; ty <= 7; ++ty) {
    for (int tx = -9; tx <= 9; ++tx) {
      const double expected = NaiveCost(pair.reference, pair.next, options.cost, tx, ty, 0.8);
      const double actual = result.cost_surface.at<double>(ty + 7, tx + 9);
      if (std::isinf(expected)) {
        EXPECT_TRUE(std::isinf(actual)) << tx << " " << ty;
        ++infinite;
        continue;
      }
      EXPECT_NEAR(actual, expected, 1e-4 * std::abs(expected)) << tx << " " << ty;
    }
  }
  EXPECT_GT(infinite, 0);
  EXPECT_EQ(result.shift, cv::Point(3, -2));
  EXPECT_EQ(result.cost, result.cost_surface.at<double>(-2 + 7, 3 + 9));
}

TEST_P(FullSearchCostTest, FindsKnownIntegerShifts) {
  FullSearchOptions options;
  options.cost = GetParam();
  for (const cv::Point shift : {cv::Point(0, 0), cv::Point(17, -4), cv::Point(-29, 11),
                                cv::Point(5, 15), cv::Point(-1, -16)}) {
    const RegistrationPair pair = MakeRegistrationPair({256, 192}, cv::Point2d(shift), 0.0, 2.0,
                                                       static_cast<std::uint64_t>(shift.x + 100));
    const FullSearchResult result = RegisterFullSearch(pair.reference, pair.next, options);
    EXPECT_EQ(result.shift, shift) << FullSearchCostName(GetParam());
  }
}

TEST_P(FullSearchCostTest, CoarseToFineFindsLargeShift) {
  FullSearchOptions options;
  options.cost = GetParam();
  options.max_shift_x_px = 48;
  options.pyramid_levels = 2;
  const RegistrationPair pair = MakeRegistrationPair({256, 192}, {-37.0, 9.0}, 0.0, 2.0, 5);
  const FullSearchResult result = RegisterFullSearch(pair.reference, pair.next, options);
  EXPECT_EQ(result.shift, cv::Point(-37, 9));
  // Only the last level's two small windows, around the coarse estimate and around zero, were
  // evaluated at full resolution.
  const cv::Mat evaluated = result.cost_surface < std::numeric_limits<double>::infinity();
  EXPECT_EQ(cv::countNonZero(evaluated), 50);
  EXPECT_EQ(cv::countNonZero(evaluated(cv::Rect(48 - 2, 16 - 2, 5, 5))), 25);
}

// A false minimum on the coarse levels must not hide a better shift near zero at full
// resolution. Fine texture F (pixel noise, averaged away by the pyramid) moves 1 px while a
// smooth pattern L (a lighting-like field that survives it) moves 24 px: the coarse levels match
// L, the finest level matches F, whose mismatch costs more.
TEST_P(FullSearchCostTest, CoarseToFineKeepsZeroAsACandidate) {
  const int width = 192, height = 64, far = 24;
  cv::Mat fine(height, width + far, CV_32F), smooth(height, width + far, CV_32F);
  cv::RNG rng(7);
  rng.fill(fine, cv::RNG::NORMAL, 0.0, 40.0);
  rng.fill(smooth, cv::RNG::NORMAL, 0.0, 400.0);
  cv::GaussianBlur(smooth, smooth, cv::Size(), 6.0);
  // reference(x) = F(x + 24) + L(x + 24), next(x) = F(x + 23) + L(x): next(x + 1) matches F,
  // next(x + 24) matches L.
  const cv::Mat reference =
      fine(cv::Rect(far, 0, width, height)) + smooth(cv::Rect(far, 0, width, height));
  const cv::Mat next =
      fine(cv::Rect(far - 1, 0, width, height)) + smooth(cv::Rect(0, 0, width, height));
  FullSearchOptions options;
  options.cost = GetParam();
  options.max_shift_x_px = 40;
  options.max_shift_y_px = 4;
  // Exhaustive search at full resolution: the oracle that 1 px is the better match there.
  options.pyramid_levels = 0;
  ASSERT_EQ(RegisterFullSearch(reference, next, options).shift, cv::Point(1, 0));
  options.pyramid_levels = 2;
  EXPECT_EQ(RegisterFullSearch(reference, next, options).shift, cv::Point(1, 0));
}

TEST_P(FullSearchCostTest, SubPixelShiftRoundsToNearest) {
  FullSearchOptions options;
  options.cost = GetParam();
  const RegistrationPair pair = MakeRegistrationPair({160, 120}, {6.3, -2.8}, 0.0, 1.0, 3);
  EXPECT_EQ(RegisterFullSearch(pair.reference, pair.next, options).shift, cv::Point(6, -3));
}

TEST_P(FullSearchCostTest, RoundingResidualPointsToTheTrueShift) {
  // The residual is a fit to three costs, not an interpolation of the true shift.
  FullSearchOptions options;
  options.cost = GetParam();
  const double tolerance = 0.1;
  for (const cv::Point2d shift : {cv::Point2d(6.3, -2.8), cv::Point2d(-3.1, 4.45),
                                  cv::Point2d(2.0, 1.0), cv::Point2d(-7.4, -0.15)}) {
    const RegistrationPair pair = MakeRegistrationPair({160, 120}, shift, 0.0, 1.0, 3);
    const FullSearchResult result = RegisterFullSearch(pair.reference, pair.next, options);
    const cv::Point2d expected = shift - cv::Point2d(result.shift);
    const cv::Point2d residual = RoundingResidual(result);
    EXPECT_NEAR(residual.x, expected.x, tolerance) << shift;
    EXPECT_NEAR(residual.y, expected.y, tolerance) << shift;
  }
}

INSTANTIATE_TEST_SUITE_P(AllCosts, FullSearchCostTest,
                         ::testing::Values(FullSearchCost::kSad, FullSearchCost::kSsd,
                                           FullSearchCost::kZncc),
                         [](const ::testing::TestParamInfo<FullSearchCost>& info) {
                           return std::string(FullSearchCostName(info.param));
                         });

TEST(FullSearch, StillPairIsExactlyZero) {
  const RegistrationPair pair = MakeRegistrationPair({160, 120}, {0.0, 0.0}, 0.0, 1.0, 9);
  for (FullSearchCost cost : {FullSearchCost::kSad, FullSearchCost::kSsd, FullSearchCost::kZncc}) {
    FullSearchOptions options;
    options.cost = cost;
    EXPECT_EQ(RegisterFullSearch(pair.reference, pair.next, options).shift, cv::Point(0, 0));
    // Identical images: the zero shift has cost exactly 0 for SAD.
    if (cost == FullSearchCost::kSad) {
      EXPECT_EQ(RegisterFullSearch(pair.reference, pair.reference, options).cost, 0.0);
    }
  }
}

TEST(FullSearch, ZnccIgnoresGainAndBias) {
  const RegistrationPair pair =
      MakeRegistrationPair({160, 120}, {-8.0, 5.0}, 0.0, 1.0, 4, /*gain=*/0.6, /*bias=*/40.0);
  FullSearchOptions options;
  options.cost = FullSearchCost::kZncc;
  const FullSearchResult result = RegisterFullSearch(pair.reference, pair.next, options);
  EXPECT_EQ(result.shift, cv::Point(-8, 5));
  EXPECT_LT(result.cost, -0.95);
}

TEST(FullSearch, RoundingResidualIsZeroWithoutBothNeighbours) {
  FullSearchResult result;
  result.metric = FullSearchCost::kSsd;
  result.max_shift_x_px = 1;
  result.max_shift_y_px = 1;
  const double inf = std::numeric_limits<double>::infinity();
  // Best at the window's right edge (no right neighbour), in a column that is not convex.
  result.cost_surface = (cv::Mat_<double>(3, 3) << 5, 4, 1.5,  //
                         inf, 2, 1,                            //
                         5, 6, 0.5);
  result.shift = cv::Point(1, 0);
  EXPECT_EQ(RoundingResidual(result), cv::Point2d(0.0, 0.0));
  // At the centre: x from (4, 2, 1), vertex 0.5 (4 - 1) / 1 clamped to 0.5; y from (4, 2, 6).
  result.cost_surface.at<double>(1, 0) = 4.0;
  result.shift = cv::Point(0, 0);
  const cv::Point2d residual = RoundingResidual(result);
  EXPECT_DOUBLE_EQ(residual.x, 0.5);
  EXPECT_DOUBLE_EQ(residual.y, 0.5 * (4.0 - 6.0) / (4.0 - 4.0 + 6.0));
}

TEST(FullSearch, SadRoundingResidualIsTheVertexOfAV) {
  // Costs 2 |t - r| + 1 at t = -1, 0, 1 for r = 0.3 along x and r = -0.2 along y: the V's
  // vertex is r exactly; the parabola through the same costs would say 0.3 / 1.4 and -0.2 / 1.6.
  FullSearchResult result;
  result.metric = FullSearchCost::kSad;
  result.max_shift_x_px = 1;
  result.max_shift_y_px = 1;
  const auto cost = [](double t, double r) { return 2.0 * std::abs(t - r) + 1.0; };
  result.cost_surface = cv::Mat(3, 3, CV_64F, cv::Scalar(10.0));
  result.cost_surface.at<double>(1, 0) = cost(-1, 0.3);
  result.cost_surface.at<double>(1, 1) = cost(0, 0.3);
  result.cost_surface.at<double>(1, 2) = cost(1, 0.3);
  result.cost_surface.at<double>(0, 1) = cost(-1, -0.2) + cost(0, 0.3) - cost(0, -0.2);
  result.cost_surface.at<double>(2, 1) = cost(1, -0.2) + cost(0, 0.3) - cost(0, -0.2);
  result.shift = cv::Point(0, 0);
  const cv::Point2d residual = RoundingResidual(result);
  EXPECT_NEAR(residual.x, 0.3, 1e-12);
  EXPECT_NEAR(residual.y, -0.2, 1e-12);
  result.metric = FullSearchCost::kSsd;
  EXPECT_NEAR(RoundingResidual(result).x, 0.3 / 1.4, 1e-12);
}

TEST(FullSearch, ClampsWindowToImage) {
  const RegistrationPair pair = MakeRegistrationPair({20, 10}, {1.0, 1.0}, 0.0, 1.0, 2);
  FullSearchOptions options;
  options.max_shift_x_px = 100;
  options.max_shift_y_px = 100;
  const FullSearchResult result = RegisterFullSearch(pair.reference, pair.next, options);
  EXPECT_EQ(result.max_shift_x_px, 19);
  EXPECT_EQ(result.max_shift_y_px, 9);
  EXPECT_EQ(result.cost_surface.size(), cv::Size(39, 19));
  EXPECT_EQ(result.shift, cv::Point(1, 1));
}

TEST(FullSearch, AcceptsEightBitImages) {
  const RegistrationPair pair = MakeRegistrationPair({96, 64}, {4.0, 2.0}, 0.0, 1.0, 8);
  cv::Mat reference8, next8;
  pair.reference.convertTo(reference8, CV_8U);
  pair.next.convertTo(next8, CV_8U);
  EXPECT_EQ(RegisterFullSearch(reference8, next8).shift, cv::Point(4, 2));
}

TEST(FullSearch, RejectsBadPairs) {
  const cv::Mat a = cv::Mat::zeros(10, 12, CV_32F);
  EXPECT_NE(InputErrorMessage([&] {
              RegisterFullSearch(a, cv::Mat::zeros(10, 13, CV_32F));
            }).find("12x10 and 13x10"),
            std::string::npos);
  EXPECT_NE(InputErrorMessage([&] {
              RegisterFullSearch(a, cv::Mat::zeros(10, 12, CV_32FC3));
            }).find("one channel"),
            std::string::npos);
  EXPECT_NE(InputErrorMessage([&] { RegisterFullSearch(cv::Mat(), a); }).find("empty"),
            std::string::npos);
}

// The overlap at a shift: the reference pixels x with x + t inside the next image, by closed
// form for each sign of the shift.
TEST(OverlapAtShift, IsTheReferencePixelsThatLandInsideTheNextImage) {
  const cv::Size size(40, 30);
  EXPECT_EQ(OverlapAtShift(size, {0, 0}), cv::Rect(0, 0, 40, 30));
  EXPECT_EQ(OverlapAtShift(size, {7, -4}), cv::Rect(0, 4, 33, 26));
  EXPECT_EQ(OverlapAtShift(size, {-7, 4}), cv::Rect(7, 0, 33, 26));
  EXPECT_TRUE(OverlapAtShift(size, {40, 0}).empty());
}

}  // namespace
}  // namespace pipescope
