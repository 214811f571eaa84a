#include "pipescope/feature/template_descriptor.h"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

namespace pipescope {

cv::Mat ComputeTemplateDescriptors(const cv::Mat& grey, const std::vector<cv::Point2f>& points,
                                   const TemplateDescriptorOptions& options) {
  const int dim = options.descriptor_size * options.descriptor_size;
  cv::Mat descriptors(static_cast<int>(points.size()), dim, CV_32F);
  // Each row depends on its point alone: rows are filled on all cores.
  cv::parallel_for_(cv::Range(0, static_cast<int>(points.size())), [&](const cv::Range& range) {
    cv::Mat region, small;
    for (int k = range.start; k < range.end; ++k) {
      cv::getRectSubPix(grey, cv::Size(options.region_size_px, options.region_size_px), points[k],
                        region, CV_32F);
      cv::resize(region, small, cv::Size(options.descriptor_size, options.descriptor_size), 0, 0,
                 cv::INTER_AREA);
      cv::Mat row = descriptors.row(k);
      small.reshape(1, 1).copyTo(row);
      if (options.subtract_mean) row -= cv::mean(row)[0];
      const double norm = cv::norm(row);
      if (norm > 0) row /= norm;
    }
  });
  return descriptors;
}

std::vector<FeatureMatch> MatchByCosineSimilarity(const cv::Mat& descriptors_a,
                                                  const std::vector<cv::Point2f>& points_a,
                                                  const cv::Mat& descriptors_b,
                                                  const std::vector<cv::Point2f>& points_b,
                                                  const CosineMatchOptions& options) {
  const int na = descriptors_a.rows;
  const int nb = descriptors_b.rows;
  std::vector<int> best_b(na, -1);
  std::vector<float> best_ab(na, -2.f);
  std::vector<int> best_a(nb, -1);
  std::vector<float> best_ba(nb, -2.f);
  const float max_d2 =
      static_cast<float>(options.max_displacement_px * options.max_displacement_px);
  const int dim = descriptors_a.cols;
  for (int a = 0; a < na; ++a) {
    const float* da = descriptors_a.ptr<float>(a);
    for (int b = 0; b < nb; ++b) {
      const cv::Point2f d = points_a[a] - points_b[b];
      if (d.x * d.x + d.y * d.y > max_d2) continue;
      const float* db = descriptors_b.ptr<float>(b);
      float dot = 0.f;
      for (int k = 0; k < dim; ++k) dot += da[k] * db[k];
      if (dot > best_ab[a]) {
        best_ab[a] = dot;
        best_b[a] = b;
      }
      if (dot > best_ba[b]) {
        best_ba[b] = dot;
        best_a[b] = a;
      }
    }
  }
  std::vector<FeatureMatch> matches;
  for (int a = 0; a < na; ++a) {
    const int b = best_b[a];
    if (b < 0 || best_ab[a] < options.min_similarity) continue;
    if (options.mutual && best_a[b] != a) continue;
    matches.push_back({a, b, best_ab[a]});
  }
  return matches;
}

}  // namespace pipescope
