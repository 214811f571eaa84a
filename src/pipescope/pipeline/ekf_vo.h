#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/tubular_ekf.h"
#include "pipescope/feature/klt_tracker.h"
#include "pipescope/io/dataset.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/mapping/tube_centreline.h"
#include "pipescope/mapping/tube_mosaic.h"
#include "pipescope/pipeline/travel_direction.h"
#include "pipescope/util/stage_times.h"

namespace pipescope {

// 004: tubular EKF SLAM with a dewarped mosaic, for a camera carried through straight and bent
// tubes.
struct EkfVoOptions {
  KltTrackerOptions tracker;
  TubularEkfOptions filter;
  // The camera axis that runs along the tube at the start: "z" for a camera looking down the
  // tube (004's set-up), "x", "y" for a camera looking at the wall (000's; the sign does not
  // matter to a cylinder); "auto": the one nearest the camera's direction of travel over the
  // first frames (pipeline/travel_direction.h), "z" when that cannot be measured (said in
  // EkfVoResult::travel).
  std::string axis_along_tube = "auto";
  // Lucas-Kanade tracks each frame divided by its blur of this sigma, as a share of the image
  // width (KltTrackerOptions::flat_field_sigma_px); -1 = by the view: for a camera looking down
  // the tube, whose gain mask (made in a straight tube, on the axis) leaves the shading of a bend
  // or an offset camera, 0.1 rad at the image centre's scale (a twentieth of the width for
  // tube-bend's pinhole camera, 0.023 of it, 15 px, for 001's 190-degree fisheye at 146 px a
  // radian); none for a wall-looking camera, whose gain mask
  // cancels the shading and whose narrow view's coarse texture needs the low frequencies
  // (docs/ekf.md).
  double flat_field_width_share = -1.0;
  // Sections may bend (TubularEkfOptions::curvature_sigma_radii) when >= 0; -1 = by the view: as
  // the filter's default for a camera looking down the tube, straight sections only for a
  // wall-looking camera, whose narrow patch of wall cannot show a bend (on steel-16in's 25-degree
  // view a spurious bend took the run from 0.019 to 0.276 % off; docs/ekf.md).
  double curvature_sigma_radii = -1.0;
  // How far ahead of the camera a new section starts at the least
  // (TubularEkfOptions::spawn_lookahead_radii) when >= 0; -1 = by the view: as the filter's
  // default looking down the tube, 2 radii for a wall-looking camera, whose view spans about a
  // radius of wall either side of it: a junction inside the view splits its tracks over two
  // sections (steel-16in's spurious sections at 1 radius: +0.213 % against +0.003 %; docs/ekf.md).
  double spawn_lookahead_radii = -1.0;
  // Use the dataset's radius as the prior on the first section's log rho (metric run); false:
  // the run is up to scale (radius 1).
  bool metric = true;
  bool build_mosaic = true;
  TubeMosaicOptions mosaic;
  // Frames painted into the mosaic are at least this far apart along the centreline (radii).
  double mosaic_frame_spacing_radii = 0.1;
  double max_saturated_fraction = 0.2;
  double saturation_level = 250.0;
};

struct EkfFrameRecord {
  std::size_t index = 0;
  double timestamp = 0.0;
  std::string name;
  int tracked = 0;  // feature pairs from the previous frame
  TubularEkfUpdate update;
  int section = 0;      // the newest section at this frame
  std::string failure;  // why the frame kept its prediction; empty when updated
};

struct EkfSectionRecord {
  TubeSection geometry;      // in the output frame
  int first_frame = 0;       // frame index at which the filter started it
  double start_arc_m = 0.0;  // along the centreline
  double end_arc_m = 0.0;
  std::string reason;
};

struct EkfVoResult {
  // The camera axis along the tube the filter started with ("z", "x" or "y"); with
  // axis_along_tube "auto", the direction of travel measured.
  std::string axis_along_tube;
  Eigen::Vector3d axis_in_camera = Eigen::Vector3d::UnitZ();  // that axis, unit
  std::optional<TravelDirection> travel;
  // What the options left at -1 ("by the view") came to for this camera and mount.
  struct ChosenByTheView {
    double curvature_sigma_radii = 0.0;
    double spawn_lookahead_radii = 0.0;
    double flat_field_sigma_px = 0.0;
  } chosen;
  // Every frame the filter went through, world_from_cam, in the first section's frame: Z along
  // its axis, the origin the first camera's foot on it, X towards phi = 0 (the pipe's up when the
  // dataset gives it, else the first camera's -y).
  Trajectory trajectory;
  std::vector<EkfFrameRecord> frames;
  std::vector<std::string> skipped_frames;
  std::vector<EkfSectionRecord> sections;
  TubeCentreline centreline;
  std::vector<double> frame_arc_m;  // each trajectory pose's distance along the centreline
  bool metric = true;
  cv::Mat mosaic;  // CV_32F, NaN unseen; rows around the tube (r phi), columns along it
  double mosaic_pixel_m = 0.0;
  double mosaic_begin_m = 0.0;
  StageTimes stage_times;  // "read", "track", "filter"
  double odometry_seconds = 0.0;
  double odometry_cpu_seconds = 0.0;
  double mosaic_seconds = 0.0;
};

// Whether a camera whose tube runs along `axis_in_camera` looks down it (the axis nearer the
// optical axis than across it) rather than at its wall.
bool LooksDownTube(const Eigen::Vector3d& axis_in_camera);

// Runs the filter over the dataset's frames. Throws InputError for an unknown axis_along_tube
// or, when metric, a dataset without pipe.inner_radius_m.
EkfVoResult RunEkfVo(const DatasetManifest& manifest, const Camera& camera,
                     const EkfVoOptions& options);

// The rigid transform from the filter's world (the first camera's frame) to the output frame.
Eigen::Isometry3d TubeFrameFromWorld(const TubeSection& first_section,
                                     const Eigen::Vector3d& first_position,
                                     const Eigen::Vector3d& phi_zero);

}  // namespace pipescope
