#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "pipescope/camera/camera.h"
#include "pipescope/estimation/keyframe_odometry.h"
#include "pipescope/io/dataset.h"
#include "pipescope/mapping/dense_appearance_map.h"

namespace pipescope {

struct DenseMapPassOptions {
  bool enabled = true;
  // 2 mm apart, the colatitude band 50-90 deg, and the views tapered towards the band's edges:
  // with 001's plain mean, each cell's set of views changes a view at a time along the pipe
  // and the views' different lighting shows as bands across the map (docs/fisheye_mapping.md).
  DenseAppearanceOptions appearance = [] {
    DenseAppearanceOptions tapered;
    tapered.colatitude_taper = true;
    return tapered;
  }();
  // Each straight section is mapped in pieces of about this much travel, each on a cylinder
  // fitted to its own points: 001 fits cylinders locally, since a long run is not one straight
  // cylinder (pipes sag, joints are not aligned; 001 §IV-A).
  double piece_length_m = 1.0;
  // Key frames closer than this along the path to the last one used are skipped: every key
  // frame of a crawler 1 cm a frame would multiply the work, not the map.
  double keyframe_spacing_m = 0.02;
};

// One piece of a straight section's dense map.
struct DenseMapPiece {
  int section = 0;
  int first_keyframe = 0;
  int last_keyframe = 0;
  DenseMapCylinder cylinder;
  double fit_median_m = 0.0;  // the cylinder fit's median distance of the points from the wall
  int keyframes_used = 0;
  DenseAppearanceMap map;
};

// The view of the mapped route the pass needs: per key frame its frame index, section and pose;
// per section whether it is straight; the map's sparse points.
struct MappedRoute {
  std::vector<int> frame_index;
  std::vector<int> section_of;
  std::vector<Eigen::Isometry3d> world_from_cam;
  std::vector<bool> section_straight;
  std::vector<SparsePoint> points;
};

// The dense 3D appearance map of 001 §IV-B over the straight sections of a mapped route: the
// wall of each piece's fitted cylinder, sampled every `spacing_m`, each cell the mean grey value
// of the key frames that see it at colatitude 50 to 90 degrees. The frames are read again, one
// at a time (the images are not held), after the poses are final.
std::vector<DenseMapPiece> BuildDenseMap(const DatasetManifest& manifest, const Camera& camera,
                                         const MappedRoute& route, double radius_m,
                                         const DenseMapPassOptions& options);

}  // namespace pipescope
