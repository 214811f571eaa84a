#include "pipescope/feature/guided_zncc.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace pipescope {

BearingTable::BearingTable(const Camera& camera, double max_view_angle_rad)
    : bearings_(camera.Height(), camera.Width(), CV_32FC3, cv::Scalar::all(0)),
      valid_(camera.Height(), camera.Width(), CV_8U, cv::Scalar(0)) {
  Eigen::Vector3d bearing;
  for (int y = 0; y < camera.Height(); ++y) {
    for (int x = 0; x < camera.Width(); ++x) {
      if (!camera.Unproject(Eigen::Vector2d(x, y), &bearing) ||
          bearing.z() < std::cos(max_view_angle_rad)) {
        continue;
      }
      bearings_.at<cv::Vec3f>(y, x) =
          cv::Vec3f(static_cast<float>(bearing.x()), static_cast<float>(bearing.y()),
                    static_cast<float>(bearing.z()));
      valid_.at<uchar>(y, x) = 255;
    }
  }
  run_begin_.assign(camera.Height(), 0);
  run_end_.assign(camera.Height(), 0);
  max_column_step_ = cv::Vec3f(0.f, 0.f, 0.f);
  for (int y = 0; y < camera.Height(); ++y) {
    const uchar* valid_row = valid_.ptr<uchar>(y);
    const cv::Vec3f* eta_row = bearings_.ptr<cv::Vec3f>(y);
    int runs = 0;
    for (int x = 0; x < camera.Width(); ++x) {
      if (!valid_row[x]) continue;
      if (x == 0 || !valid_row[x - 1]) {
        ++runs;
        run_begin_[y] = x;
      }
      run_end_[y] = x + 1;
      if (x > 0 && valid_row[x - 1]) {
        for (int c = 0; c < 3; ++c) {
          max_column_step_[c] =
              std::max(max_column_step_[c], std::abs(eta_row[x][c] - eta_row[x - 1][c]));
        }
      }
    }
    if (runs > 1) run_begin_[y] = -1;
  }
}

void BearingTable::EpipolarBandColumns(int y, int x0, int x1, const cv::Vec3f& normal,
                                       float threshold, std::vector<int>* band) const {
  band->clear();
  const cv::Vec3f* eta_row = bearings_.ptr<cv::Vec3f>(y);
  const uchar* valid_row = valid_.ptr<uchar>(y);
  const auto distance = [&](int x) {
    const cv::Vec3f& eta = eta_row[x];
    return std::abs(eta[0] * normal[0] + eta[1] * normal[1] + eta[2] * normal[2]);
  };
  const bool one_run = run_begin_[y] >= 0;
  const int first = one_run ? std::max(x0, run_begin_[y]) : x0;
  const int last = one_run ? std::min(x1, run_end_[y] - 1) : x1;
  // Along the run |eta . normal| changes by at most `slope` a column; the margin covers the
  // float rounding of the products (a few 1e-8 of |normal|), so no skipped pixel is in the band.
  const float slope = std::abs(normal[0]) * max_column_step_[0] +
                      std::abs(normal[1]) * max_column_step_[1] +
                      std::abs(normal[2]) * max_column_step_[2];
  const float margin =
      1e-5f * (std::abs(normal[0]) + std::abs(normal[1]) + std::abs(normal[2])) + 1e-7f;
  // Chunks of columns, each skipped when its middle column is farther off the band than the
  // chunk's ends can come back: most of the search box is far from the band.
  constexpr int kChunk = 8;
  for (int begin = first; begin <= last; begin += kChunk) {
    const int end = std::min(last, begin + kChunk - 1);
    const int middle = (begin + end) / 2;
    if (one_run &&
        distance(middle) - static_cast<float>(end - middle) * slope >= threshold + margin) {
      continue;
    }
    for (int x = begin; x <= end; ++x) {
      if (valid_row[x] && distance(x) < threshold) band->push_back(x);
    }
  }
}

namespace {

// Zero-mean, unit-norm copy of a template; false when it is flat.
bool NormaliseTemplate(const cv::Mat& patch, cv::Mat* normalised) {
  cv::Scalar mean, stddev;
  cv::meanStdDev(patch, mean, stddev);
  if (stddev[0] < 1e-3) return false;
  cv::subtract(patch, mean, *normalised);
  *normalised /= cv::norm(*normalised);
  return true;
}

}  // namespace

GuidedMatch GuidedZnccSearch(const cv::Mat& grey_i, const cv::Mat& grey_j,
                             const cv::Point2f& point_i, const Eigen::Vector3d& bearing_i,
                             const Eigen::Matrix3d& essential, const BearingTable& bearings,
                             const GuidedZnccOptions& options) {
  GuidedMatch match;
  const int half = options.template_size_px / 2;
  const int side = 2 * half + 1;
  cv::Mat template_i;
  cv::getRectSubPix(grey_i, cv::Size(side, side), point_i, template_i, CV_32F);
  cv::Mat normalised_i;
  if (!NormaliseTemplate(template_i, &normalised_i)) return match;
  // Epipolar plane normal in image j; |eta_j . n| < threshold bounds the search region.
  const Eigen::Vector3d normal = essential * bearing_i;
  const int r = options.search_radius_px;
  const int x0 = std::max(half, static_cast<int>(std::lround(point_i.x)) - r);
  const int x1 = std::min(grey_j.cols - 1 - half, static_cast<int>(std::lround(point_i.x)) + r);
  const int y0 = std::max(half, static_cast<int>(std::lround(point_i.y)) - r);
  const int y1 = std::min(grey_j.rows - 1 - half, static_cast<int>(std::lround(point_i.y)) + r);
  if (x1 < x0 || y1 < y0) return match;
  // The scored pixels (a band a few pixels wide across the box, in row order): the peak tests
  // and the sub-pixel refinement look them up instead of a box of scores filled with -2.
  struct Scored {
    int x, y;
    float score;
  };
  std::vector<Scored> scored;
  scored.reserve(4 * (x1 - x0 + y1 - y0 + 2));
  const float n0 = static_cast<float>(normal.x());
  const float n1 = static_cast<float>(normal.y());
  const float n2 = static_cast<float>(normal.z());
  const float threshold = static_cast<float>(options.epipolar_threshold);
  const int area = side * side;
  // Window sums of the search box from its integral images, so that each candidate costs only
  // the cross term.
  const cv::Rect box(x0 - half, y0 - half, x1 - x0 + side, y1 - y0 + side);
  cv::Mat sums, square_sums;
  cv::integral(grey_j(box), sums, square_sums, CV_64F, CV_64F);
  const auto window_sum = [&](const cv::Mat& integral, int x, int y) {
    const int u = x - x0, v = y - y0;  // window top-left in the box
    return integral.at<double>(v + side, u + side) - integral.at<double>(v, u + side) -
           integral.at<double>(v + side, u) + integral.at<double>(v, u);
  };
  float best = -2.f;
  int best_x = -1, best_y = -1;
  const auto take = [&](int x, int y, float cross) {
    // ZNCC against the zero-mean unit template: sum(t p) / sqrt(sum p^2 - (sum p)^2 / n).
    const double sum = window_sum(sums, x, y);
    const double sum_sq = window_sum(square_sums, x, y);
    const double variance = sum_sq - sum * sum / area;
    if (variance <= 1e-6) return;
    const float score = cross / static_cast<float>(std::sqrt(variance));
    scored.push_back({x, y, score});
    if (score > best) {
      best = score;
      best_x = x;
      best_y = y;
    }
  };
  std::vector<int> band;  // the band's columns in one row, ascending
  band.reserve(x1 - x0 + 1);
  for (int y = y0; y <= y1; ++y) {
    bearings.EpipolarBandColumns(y, x0, x1, cv::Vec3f(n0, n1, n2), threshold, &band);
    // The cross terms sum(t p), four adjacent columns at a time where the band has them: each
    // lane adds its products in the order one column alone does, so the floats are the same.
    for (std::size_t i = 0; i < band.size();) {
      const int x = band[i];
      if (i + 3 < band.size() && band[i + 3] == x + 3) {
        float cross[4] = {0.f, 0.f, 0.f, 0.f};
        for (int v = -half; v <= half; ++v) {
          const float* row = grey_j.ptr<float>(y + v) + x - half;
          const float* t = normalised_i.ptr<float>(v + half);
          for (int u = 0; u < side; ++u) {
            for (int lane = 0; lane < 4; ++lane) cross[lane] += t[u] * row[u + lane];
          }
        }
        for (int lane = 0; lane < 4; ++lane) take(x + lane, y, cross[lane]);
        i += 4;
      } else {
        float cross = 0.f;
        for (int v = -half; v <= half; ++v) {
          const float* row = grey_j.ptr<float>(y + v) + x - half;
          const float* t = normalised_i.ptr<float>(v + half);
          for (int u = 0; u < side; ++u) cross += t[u] * row[u];
        }
        take(x, y, cross);
        ++i;
      }
    }
  }
  if (best_x < 0 || best < options.min_zncc) return match;
  float runner_up = -2.f;
  for (const Scored& candidate : scored) {
    if (std::abs(candidate.x - best_x) <= 1 && std::abs(candidate.y - best_y) <= 1) continue;
    runner_up = std::max(runner_up, candidate.score);
  }
  // Neighbouring pixels of a smooth peak score almost as high; only a distinct second peak
  // counts, so compare with the best outside a 5x5 block instead when the 3x3 ring is high.
  if (best - runner_up < options.min_peak_margin) {
    float distinct = -2.f;
    for (const Scored& candidate : scored) {
      if (std::abs(candidate.x - best_x) <= 3 && std::abs(candidate.y - best_y) <= 3) continue;
      distinct = std::max(distinct, candidate.score);
    }
    if (best - distinct < options.min_peak_margin) return match;
  }
  // Parabolic sub-pixel refinement where the neighbours were scored (-2: not scored).
  const auto score_at = [&](int x, int y) {
    for (const Scored& candidate : scored) {
      if (candidate.x == x && candidate.y == y) return candidate.score;
    }
    return -2.f;
  };
  const auto parabola = [](float left, float centre, float right) {
    const float denominator = left - 2.f * centre + right;
    if (left < -1.5f || right < -1.5f || denominator >= 0.f) return 0.f;
    return std::clamp(0.5f * (left - right) / denominator, -0.5f, 0.5f);
  };
  match.found = true;
  match.zncc = best;
  match.point_j = cv::Point2f(
      best_x + parabola(score_at(best_x - 1, best_y), best, score_at(best_x + 1, best_y)),
      best_y + parabola(score_at(best_x, best_y - 1), best, score_at(best_x, best_y + 1)));
  return match;
}

}  // namespace pipescope
