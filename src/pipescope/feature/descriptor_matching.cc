#include "pipescope/feature/descriptor_matching.h"

#include <cmath>
#include <limits>

namespace pipescope {

std::vector<IndexMatch> MatchDescriptors(const cv::Mat& first, const cv::Mat& second,
                                         const DescriptorMatchingOptions& options) {
  std::vector<IndexMatch> matches;
  if (first.rows < 2 || second.rows < 2) return matches;
  CV_Assert(first.type() == CV_32F && second.type() == CV_32F && first.cols == second.cols);
  // Squared L2 distances |a|^2 + |b|^2 - 2 a.b from one matrix product, used for both
  // directions (the mutual check needs the best row for every column as well). cv::gemm (BLAS)
  // is faster here than Eigen built for the baseline x86-64 instruction set.
  cv::Mat products;
  cv::gemm(first, second, 1.0, cv::noArray(), 0.0, products, cv::GEMM_2_T);
  cv::Mat a_norms, b_norms;
  cv::reduce(first.mul(first), a_norms, 1, cv::REDUCE_SUM, CV_32F);
  cv::reduce(second.mul(second), b_norms, 1, cv::REDUCE_SUM, CV_32F);
  const float* b_norm = b_norms.ptr<float>();  // a continuous column
  std::vector<float> column_best(second.rows, std::numeric_limits<float>::infinity());
  std::vector<int> column_best_row(second.rows, -1);
  std::vector<int> row_best(first.rows, -1);
  std::vector<float> row_ratio(first.rows, 1.f);
  for (int i = 0; i < first.rows; ++i) {
    float best = std::numeric_limits<float>::infinity(), second_best = best;
    int best_j = -1;
    const float* product = products.ptr<float>(i);
    const float a_norm = a_norms.at<float>(i);
    for (int j = 0; j < second.rows; ++j) {
      const float d = std::max(0.f, a_norm + b_norm[j] - 2.f * product[j]);
      if (d < best) {
        second_best = best;
        best = d;
        best_j = j;
      } else if (d < second_best) {
        second_best = d;
      }
      if (d < column_best[j]) {
        column_best[j] = d;
        column_best_row[j] = i;
      }
    }
    row_best[i] = best_j;
    // Lowe's ratio on distances, not squared distances.
    row_ratio[i] = second_best > 0.f ? std::sqrt(best / second_best) : 1.f;
  }
  for (int i = 0; i < first.rows; ++i) {
    const int j = row_best[i];
    if (j < 0 || !(row_ratio[i] < options.max_ratio)) continue;
    if (options.mutual_check && column_best_row[j] != i) continue;
    matches.push_back({i, j});
  }
  return matches;
}

}  // namespace pipescope
