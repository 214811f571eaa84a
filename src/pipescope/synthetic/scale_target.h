#pragma once

#include <Eigen/Geometry>
#include <filesystem>

#include "pipescope/synthetic/scene.h"

namespace pipescope {

// The reference-scale target of 000 §3.3 (Fig. 7): a matte white card printed with a grid of
// black circles, fixed to the inner wall so that the wall-looking camera sees it. Its metric
// spacing is what `pipescope refscale` turns into pixels per metre.
struct ScaleTargetOptions {
  int cols = 5;               // circles along the pipe axis (h)
  int rows = 4;               // circles around the pipe (s = r phi)
  double spacing_m = 0.01;    // centre to centre, measured on the wall surface
  double diameter_m = 0.004;  // circle diameter, smaller than spacing_m
  // The card reaches this many spacings beyond the outer circle centres, so every circle has a
  // white surround for the blob detector.
  double margin_spacings = 0.75;
  float card_albedo = 0.85f;  // matte white paper
  float ink_albedo = 0.04f;   // matte black print
};

// A target lying in one section's surface coordinates (h along the centre line, s = r phi
// around it), so it bends with the wall like a sheet stuck to it: spacing along s is arc length,
// as a caliper run along the sheet would measure it. Immutable and thread-safe.
class ScaleTarget {
 public:
  // Centred at (centre_h_m, centre_s_m) of `section`, whose circumference is circumference_m.
  // Throws std::invalid_argument for a grid under 2 x 2, a non-positive size or circles that
  // touch.
  ScaleTarget(const ScaleTargetOptions& options, int section, double centre_h_m, double centre_s_m,
              double circumference_m);

  // The target centred where the optical axis of a camera at `world_from_cam` meets the wall of
  // `scene`: the middle of the image, as an operator would place the camera over the target.
  // Throws std::invalid_argument when the axis leaves the scene without hitting a wall.
  static ScaleTarget AtOpticalAxis(const ScaleTargetOptions& options, const Scene& scene,
                                   const Eigen::Isometry3d& world_from_cam);

  // Paints the target over a wall sample at (h_m, s_m) of `section`: where the card covers the
  // wall, `albedo` becomes the card's (white or ink) and `specularity` fades to 0 (matte print).
  // Edges are box-filtered over `footprint_m`, the pixel's size on the wall, so circles and the
  // card border are anti-aliased and their centroids are not snapped to pixels.
  void Paint(int section, double h_m, double s_m, double footprint_m, float* albedo,
             float* specularity) const;

  // Surface coordinates (h, s) of circle (col, row); s may lie outside [0, circumference).
  Eigen::Vector2d CircleCentre(int col, int row) const;

  const ScaleTargetOptions& options() const { return options_; }
  int section() const { return section_; }
  double centre_h_m() const { return centre_h_m_; }
  double centre_s_m() const { return centre_s_m_; }

 private:
  ScaleTargetOptions options_;
  int section_;
  double centre_h_m_;
  double centre_s_m_;
  double circumference_m_;
};

// Writes `target.yaml` atomically: cols, rows, spacing_m, diameter_m (what `pipescope refscale`
// needs: --grid COLSxROWS --spacing-m S) and, for provenance, where the target lies (section,
// centre_h_m, centre_s_m).
void WriteScaleTargetYaml(const std::filesystem::path& path, const ScaleTarget& target);

}  // namespace pipescope
