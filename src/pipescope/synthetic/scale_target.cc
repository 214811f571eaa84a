#include "pipescope/synthetic/scale_target.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "pipescope/util/atomic_file.h"

namespace pipescope {
namespace {

// Fraction of a pixel of footprint `footprint` covered by a half-plane whose edge lies `inside`
// metres from the pixel centre (positive towards the covered side): a box filter across a
// straight edge, exact for edges much larger than a pixel.
double EdgeCoverage(double inside, double footprint) {
  return std::clamp(0.5 + inside / footprint, 0.0, 1.0);
}

}  // namespace

ScaleTarget::ScaleTarget(const ScaleTargetOptions& options, int section, double centre_h_m,
                         double centre_s_m, double circumference_m)
    : options_(options),
      section_(section),
      centre_h_m_(centre_h_m),
      centre_s_m_(centre_s_m),
      circumference_m_(circumference_m) {
  if (options.cols < 2 || options.rows < 2) {
    throw std::invalid_argument("ScaleTarget: the grid needs at least 2 x 2 circles");
  }
  if (!(options.diameter_m > 0.0) || !(options.spacing_m > options.diameter_m)) {
    throw std::invalid_argument("ScaleTarget: need spacing_m > diameter_m > 0");
  }
  if (!(circumference_m > 0.0) || options.margin_spacings < 0.0) {
    throw std::invalid_argument("ScaleTarget: bad circumference or margin");
  }
}

ScaleTarget ScaleTarget::AtOpticalAxis(const ScaleTargetOptions& options, const Scene& scene,
                                       const Eigen::Isometry3d& world_from_cam) {
  const Ray axis{world_from_cam.translation(), world_from_cam.linear().col(2).normalized()};
  const std::optional<WallHit> hit = scene.Intersect(axis);
  if (!hit) throw std::invalid_argument("ScaleTarget: the optical axis does not meet the wall");
  const double circumference = 2.0 * M_PI * scene.sections()[hit->section].radius;
  return ScaleTarget(options, hit->section, hit->h_m, hit->s_m, circumference);
}

Eigen::Vector2d ScaleTarget::CircleCentre(int col, int row) const {
  return {centre_h_m_ + (col - 0.5 * (options_.cols - 1)) * options_.spacing_m,
          centre_s_m_ + (row - 0.5 * (options_.rows - 1)) * options_.spacing_m};
}

void ScaleTarget::Paint(int section, double h_m, double s_m, double footprint_m, float* albedo,
                        float* specularity) const {
  if (section != section_) return;
  const double spacing = options_.spacing_m;
  const double dh = h_m - centre_h_m_;
  // s is periodic: take the offset from the centre the short way round.
  const double ds = std::remainder(s_m - centre_s_m_, circumference_m_);
  const double half_h = (0.5 * (options_.cols - 1) + options_.margin_spacings) * spacing;
  const double half_s = (0.5 * (options_.rows - 1) + options_.margin_spacings) * spacing;
  const double footprint = std::max(footprint_m, 1e-9);
  const double card = EdgeCoverage(half_h - std::abs(dh), footprint) *
                      EdgeCoverage(half_s - std::abs(ds), footprint);
  if (card <= 0.0) return;
  // Circles are farther apart than their diameter, so only the nearest one can cover the pixel.
  const double col =
      std::clamp(std::round(dh / spacing + 0.5 * (options_.cols - 1)), 0.0, options_.cols - 1.0);
  const double row =
      std::clamp(std::round(ds / spacing + 0.5 * (options_.rows - 1)), 0.0, options_.rows - 1.0);
  const double distance = std::hypot(dh - (col - 0.5 * (options_.cols - 1)) * spacing,
                                     ds - (row - 0.5 * (options_.rows - 1)) * spacing);
  // A circle's edge is locally straight at pixel scale, so the half-plane coverage applies.
  const double ink = EdgeCoverage(0.5 * options_.diameter_m - distance, footprint);
  const double card_albedo =
      options_.card_albedo + ink * (options_.ink_albedo - options_.card_albedo);
  *albedo = static_cast<float>(*albedo + card * (card_albedo - *albedo));
  *specularity = static_cast<float>(*specularity * (1.0 - card));
}

void WriteScaleTargetYaml(const std::filesystem::path& path, const ScaleTarget& target) {
  const ScaleTargetOptions& options = target.options();
  YAML::Emitter out;
  out.SetDoublePrecision(15);  // 0.004 stays 0.004
  out << YAML::BeginMap;
  out << YAML::Key << "cols" << YAML::Value << options.cols;
  out << YAML::Key << "rows" << YAML::Value << options.rows;
  out << YAML::Key << "spacing_m" << YAML::Value << options.spacing_m;
  out << YAML::Key << "diameter_m" << YAML::Value << options.diameter_m;
  out << YAML::Key << "section" << YAML::Value << target.section();
  out << YAML::Key << "centre_h_m" << YAML::Value << target.centre_h_m();
  out << YAML::Key << "centre_s_m" << YAML::Value << target.centre_s_m();
  out << YAML::EndMap;
  WriteTextFileAtomically(path,
                          "# pipescope simulate: reference-scale target (000 §3.3); cols "
                          "run along the pipe axis, rows around it\n" +
                              std::string(out.c_str()) + "\n");
}

}  // namespace pipescope
