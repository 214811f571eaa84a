#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace pipescope {

// Synthetic registration pairs for the dense kernels' tests and benchmarks: a procedural texture
// evaluated at exactly known shifted (and rotated) coordinates, so the ground truth is exact,
// unlike a resampled image.

// A texture of Gaussian blobs, the kind of broadband pattern (spots, stains, rust) a pipe wall
// shows: centres uniform over the plane at one per 25 px^2, standard deviations log-uniform in
// [1.2, 8] px, amplitudes uniform in [-38, 38]; standard deviation about 30 around 128. Blobs are
// cut off at 4 sigma.
struct BlobTexture {
  struct Blob {
    double x, y, sigma, amplitude;
  };
  static constexpr double kMaxSigma = 8.0;
  std::vector<Blob> blobs;

  // Blobs covering the rectangle [x0, x1] x [y0, y1] of the texture plane.
  BlobTexture(std::uint64_t seed, double x0, double y0, double x1, double y1) {
    cv::RNG rng(seed);
    const double margin = 4.0 * kMaxSigma;
    x0 -= margin, y0 -= margin, x1 += margin, y1 += margin;
    const int count = static_cast<int>((x1 - x0) * (y1 - y0) / 25.0);
    for (int k = 0; k < count; ++k) {
      blobs.push_back({rng.uniform(x0, x1), rng.uniform(y0, y1),
                       1.2 * std::pow(kMaxSigma / 1.2, rng.uniform(0.0, 1.0)),
                       rng.uniform(-38.0, 38.0)});
    }
  }

  // Renders image(p) = 128 + gain * texture(to_texture(p)) for a rigid map to_texture
  // (2x3, rotation and translation), blob by blob: a blob at texture position b lands on image
  // position to_texture^-1(b).
  cv::Mat Render(cv::Size size, const cv::Matx23d& to_texture, double gain) const {
    cv::Mat image(size, CV_32F, cv::Scalar(128.0));
    cv::Matx23d to_image;
    cv::invertAffineTransform(to_texture, to_image);
    for (const Blob& blob : blobs) {
      const double cx = to_image(0, 0) * blob.x + to_image(0, 1) * blob.y + to_image(0, 2);
      const double cy = to_image(1, 0) * blob.x + to_image(1, 1) * blob.y + to_image(1, 2);
      const double radius = 4.0 * blob.sigma;
      const int xa = std::max(0, static_cast<int>(std::ceil(cx - radius)));
      const int xb = std::min(size.width - 1, static_cast<int>(std::floor(cx + radius)));
      const int ya = std::max(0, static_cast<int>(std::ceil(cy - radius)));
      const int yb = std::min(size.height - 1, static_cast<int>(std::floor(cy + radius)));
      const double inverse_two_variance = 0.5 / (blob.sigma * blob.sigma);
      for (int y = ya; y <= yb; ++y) {
        float* row = image.ptr<float>(y);
        for (int x = xa; x <= xb; ++x) {
          const double u = to_texture(0, 0) * x + to_texture(0, 1) * y + to_texture(0, 2) - blob.x;
          const double v = to_texture(1, 0) * x + to_texture(1, 1) * y + to_texture(1, 2) - blob.y;
          row[x] += static_cast<float>(gain * blob.amplitude *
                                       std::exp(-(u * u + v * v) * inverse_two_variance));
        }
      }
    }
    return image;
  }
};

// Euclidean distance between two shifts, in pixels.
inline double Distance(cv::Point2d a, cv::Point2d b) { return std::hypot(a.x - b.x, a.y - b.y); }

struct RegistrationPair {
  cv::Mat reference;  // CV_32F
  cv::Mat next;       // CV_32F
};

// reference(x) = T(x) + noise and next(A(x)) = gain T(x) + bias + noise with
// A(x) = R(rotation) (x - c) + c + shift (c the image centre): the motion convention of
// phase_correlation.h, next(x + shift) = reference(x) without rotation. T is a BlobTexture
// (128 + blobs; the gain applies to the whole of T). Independent Gaussian noise of standard
// deviation noise_sigma in each image.
inline RegistrationPair MakeRegistrationPair(cv::Size size, cv::Point2d shift,
                                             double rotation_rad = 0.0, double noise_sigma = 1.0,
                                             std::uint64_t seed = 1, double gain = 1.0,
                                             double bias = 0.0) {
  const double cx = 0.5 * (size.width - 1), cy = 0.5 * (size.height - 1);
  const double cos_a = std::cos(rotation_rad), sin_a = std::sin(rotation_rad);
  // A^-1(p) = R(-rotation) (p - c - shift) + c.
  const double ux = cx + shift.x, uy = cy + shift.y;
  const cv::Matx23d next_to_texture(cos_a, sin_a, cx - (cos_a * ux + sin_a * uy),  //
                                    -sin_a, cos_a, cy - (-sin_a * ux + cos_a * uy));
  const double reach =
      std::hypot(shift.x, shift.y) + std::abs(rotation_rad) * std::hypot(cx, cy) + 2.0;
  const BlobTexture texture(seed, -reach, -reach, size.width + reach, size.height + reach);
  RegistrationPair pair;
  pair.reference = texture.Render(size, cv::Matx23d(1, 0, 0, 0, 1, 0), 1.0);
  pair.next = texture.Render(size, next_to_texture, gain);
  // The gain applies to the whole texture, its mean level included.
  pair.next += 128.0 * (gain - 1.0) + bias;
  if (noise_sigma > 0.0) {
    cv::RNG rng(seed * 7919 + 17);
    cv::Mat noise(size, CV_32F);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, noise_sigma);
    pair.reference += noise;
    rng.fill(noise, cv::RNG::NORMAL, 0.0, noise_sigma);
    pair.next += noise;
  }
  return pair;
}

}  // namespace pipescope
