#include "pipescope/feature/descriptor_matching.h"

#include <Eigen/Core>
#include <cmath>
#include <limits>

namespace pipescope {

std::vector<IndexMatch> MatchDescriptors(const cv::Mat& first, const cv::Mat& second,
                                         const DescriptorMatchingOptions& options) {
  std::vector<IndexMatch> matches;
  if (first.rows < 2 || second.rows < 2) return matches;
  CV_Assert(first.type() == CV_32F && second.type() == CV_32F && first.cols == second.cols);
  using RowMajor = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const cv::Mat a = first.isContinuous() ? first : first.clone();
  const cv::Mat b = second.isContinuous() ? second : second.clone();
  const Eigen::Map<const RowMajor> A(a.ptr<float>(), a.rows, a.cols);
  const Eigen::Map<const RowMajor> B(b.ptr<float>(), b.rows, b.cols);
  // Squared L2 distances |a|^2 + |b|^2 - 2 a.b from one matrix product, used for both
  // directions (the mutual check needs the best row for every column as well).
  const Eigen::VectorXf a_norms = A.rowwise().squaredNorm();
  const Eigen::RowVectorXf b_norms = B.rowwise().squaredNorm().transpose();
  const RowMajor products = A * B.transpose();
  std::vector<float> column_best(b.rows, std::numeric_limits<float>::infinity());
  std::vector<int> column_best_row(b.rows, -1);
  std::vector<int> row_best(a.rows, -1);
  std::vector<float> row_ratio(a.rows, 1.f);
  for (int i = 0; i < a.rows; ++i) {
    float best = std::numeric_limits<float>::infinity(), second_best = best;
    int best_j = -1;
    for (int j = 0; j < b.rows; ++j) {
      const float d = std::max(0.f, a_norms[i] + b_norms[j] - 2.f * products(i, j));
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
  for (int i = 0; i < a.rows; ++i) {
    const int j = row_best[i];
    if (j < 0 || !(row_ratio[i] < options.max_ratio)) continue;
    if (options.mutual_check && column_best_row[j] != i) continue;
    matches.push_back({i, j});
  }
  return matches;
}

}  // namespace pipescope
