#pragma once

#include <Eigen/Geometry>
#include <functional>
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

// Which wall a piece maps: a stretch of a straight section, or one of the two cylinders of a
// T-intersection between its straight sections (001 §IV-B maps the Ts too).
enum class DenseMapPart { kStraight, kTRed, kTBlue };

// One piece of a straight section's or a T's dense map.
struct DenseMapPiece {
  int section = 0;
  DenseMapPart part = DenseMapPart::kStraight;
  int first_keyframe = 0;
  int last_keyframe = 0;
  DenseMapCylinder cylinder;
  double fit_median_m = 0.0;  // the cylinder fit's median distance of the points from the wall
  int keyframes_used = 0;
  DenseAppearanceMap map;
};

// An adjusted T-intersection (001 §III-D): its centre I and its two axes, each pointing from I
// towards its camera's side (pipeline/t_intersection_pass.h).
struct MappedT {
  int section = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d red_direction = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d blue_direction = Eigen::Vector3d::UnitX();
};

// The view of the mapped route the pass needs: per key frame its frame index, section and pose;
// per section whether it is straight; the map's sparse points; the adjusted Ts.
struct MappedRoute {
  std::vector<int> frame_index;
  std::vector<int> section_of;
  std::vector<Eigen::Isometry3d> world_from_cam;
  std::vector<bool> section_straight;
  std::vector<SparsePoint> points;
  std::vector<MappedT> t_intersections;
};

// The dense 3D appearance map of 001 §IV-B over the straight sections of a mapped route: the
// wall of each piece's fitted cylinder, sampled every `spacing_m`, each cell the mean grey value
// of the key frames that see it at colatitude 50 to 90 degrees. Each adjusted T adds two pieces
// on its model's cylinders: the red one from the red section's last key frame to I, the blue
// one from I to the blue section's first, each without the cells inside the other cylinder. On
// the side the robot turned to, those cells are the opening into the other pipe; on the far
// side they are open only when the other pipe runs through the T, which the model does not say,
// so they are left out too. The T's third arm, which the robot did not drive, is not mapped. The
// frames are read again, one at a time (the images are not held), after the poses are final.
//
// With `on_finished`, each piece is handed to it (with its index in the returned list) as soon
// as its last frame is read, and its map is then released: the returned pieces keep only
// their description, so a long route's map can be written piece by piece.
using DenseMapPieceSink = std::function<void(int index, const DenseMapPiece& piece)>;
std::vector<DenseMapPiece> BuildDenseMap(const DatasetManifest& manifest, const Camera& camera,
                                         const MappedRoute& route, double radius_m,
                                         const DenseMapPassOptions& options,
                                         const DenseMapPieceSink& on_finished = {});

}  // namespace pipescope
