// COLMAP's camera for a pipescope dataset (bench/fisheye_colmap.sh): the OPENCV_FISHEYE
// parameters fitted to camera.yaml up to MAX_ANGLE_DEG, their residual, and a mask that hides
// the pixels beyond that angle, which OPENCV_FISHEYE cannot unproject.
// Usage: fisheye_colmap_camera CAMERA_YAML MAX_ANGLE_DEG MASK_PNG
#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <exception>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "pipescope/camera/camera_fit.h"
#include "pipescope/camera/camera_io.h"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s CAMERA_YAML MAX_ANGLE_DEG MASK_PNG\n", argv[0]);
    return 2;
  }
  try {
    const pipescope::Camera camera = pipescope::ReadCamera(argv[1]);
    pipescope::KannalaBrandtFitOptions options;
    options.max_angle = std::stod(argv[2]) * M_PI / 180.0;
    const pipescope::KannalaBrandtFit fit = pipescope::FitKannalaBrandt(camera, options);

    // COLMAP ignores features where the mask is 0.
    cv::Mat mask(camera.Height(), camera.Width(), CV_8U, cv::Scalar(0));
    const double min_cos = std::cos(options.max_angle);
    for (int y = 0; y < camera.Height(); ++y) {
      for (int x = 0; x < camera.Width(); ++x) {
        Eigen::Vector3d bearing;
        if (camera.Unproject(Eigen::Vector2d(x, y), &bearing) && bearing.z() >= min_cos) {
          mask.at<unsigned char>(y, x) = 255;
        }
      }
    }
    if (!cv::imwrite(argv[3], mask))
      throw std::runtime_error(std::string("cannot write ") + argv[3]);

    const std::vector<double>& p = fit.camera.Params();
    std::printf("opencv_fisheye_params %.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", p[0],
                p[1], p[2], p[3], p[4], p[5], p[6], p[7]);
    std::printf("fit_max_angle_deg %s\nfit_samples %d\nfit_rms_px %.3g\nfit_max_px %.3g\n", argv[2],
                fit.num_samples, fit.rms_px, fit.max_px);
    std::printf("mask_fraction %.4f\n", cv::countNonZero(mask) / double(mask.total()));
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "fisheye_colmap_camera: %s\n", error.what());
    return 1;
  }
}
