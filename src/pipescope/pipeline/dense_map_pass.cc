#include "pipescope/pipeline/dense_map_pass.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>

#include "pipescope/image/gain_mask.h"
#include "pipescope/io/image_source.h"
#include "pipescope/pipeline/section_cylinder.h"

namespace pipescope {
namespace {

// The key-frame ranges of the pieces: each straight section cut every `piece_length_m` of
// travel (a rest shorter than half a piece joins the piece before it); consecutive pieces
// share their boundary key frame.
std::vector<DenseMapPiece> CutPieces(const MappedRoute& route, double piece_length_m) {
  std::vector<DenseMapPiece> pieces;
  const int num_keyframes = static_cast<int>(route.world_from_cam.size());
  int k = 0;
  while (k < num_keyframes) {
    const int section = route.section_of[k];
    int end = k;
    while (end + 1 < num_keyframes && route.section_of[end + 1] == section) ++end;
    if (route.section_straight[section]) {
      int first = k;
      double travelled = 0.0;
      for (int j = k + 1; j <= end; ++j) {
        travelled +=
            (route.world_from_cam[j].translation() - route.world_from_cam[j - 1].translation())
                .norm();
        if (j == end && travelled < 0.5 * piece_length_m && !pieces.empty() &&
            pieces.back().section == section) {
          pieces.back().last_keyframe = end;  // a short rest joins the piece before it
        } else if (travelled >= piece_length_m || j == end) {
          DenseMapPiece piece;
          piece.section = section;
          piece.first_keyframe = first;
          piece.last_keyframe = j;
          pieces.push_back(piece);
          first = j;
          travelled = 0.0;
        }
      }
    }
    k = end + 1;
  }
  return pieces;
}

// The two pieces of each adjusted T, on its model's cylinders through I (phi = 0 towards the
// upright of the camera at the piece's far end from I).
std::vector<DenseMapPiece> TPieces(const MappedRoute& route, double radius_m) {
  std::vector<DenseMapPiece> pieces;
  const int num_keyframes = static_cast<int>(route.world_from_cam.size());
  for (const MappedT& t : route.t_intersections) {
    int first = num_keyframes, last = -1;
    for (int k = 0; k < num_keyframes; ++k) {
      if (route.section_of[k] != t.section) continue;
      first = std::min(first, k);
      last = std::max(last, k);
    }
    if (last < 0 || first == 0 || last + 1 >= num_keyframes) continue;
    const int red = first - 1, blue = last + 1;  // the straight sections' key frames at the T
    for (const DenseMapPart part : {DenseMapPart::kTRed, DenseMapPart::kTBlue}) {
      const bool is_red = part == DenseMapPart::kTRed;
      const int outer = is_red ? red : blue;
      DenseMapPiece piece;
      piece.section = t.section;
      piece.part = part;
      piece.first_keyframe = red;
      piece.last_keyframe = blue;
      // Each axis in the direction of travel: towards I on the red side, away from it on the
      // blue.
      piece.cylinder.axis_point = t.centre;
      piece.cylinder.axis_direction = is_red ? -t.red_direction : t.blue_direction;
      piece.cylinder.radius_m = radius_m;
      const double outer_m =
          (route.world_from_cam[outer].translation() - t.centre).dot(piece.cylinder.axis_direction);
      piece.cylinder.begin_m = is_red ? outer_m : 0.0;
      piece.cylinder.end_m = is_red ? 0.0 : outer_m;
      piece.cylinder.reference_direction = -route.world_from_cam[outer].linear().col(1);
      pieces.push_back(piece);
    }
  }
  return pieces;
}

// Takes out of a T piece's map the cells inside the T's other cylinder: there the wall is open.
void RemoveCellsInside(const DenseMapCylinder& other, DenseAppearanceMap* map) {
  const Eigen::Vector3d direction = other.axis_direction.normalized();
  std::vector<DenseMapPoint> kept;
  for (const DenseMapPoint& point : map->points) {
    const Eigen::Vector3d v = point.position - other.axis_point;
    if ((v - v.dot(direction) * direction).norm() >= other.radius_m) {
      kept.push_back(point);
      continue;
    }
    map->mean_grey.at<float>(point.row, point.col) = std::numeric_limits<float>::quiet_NaN();
    map->count.at<int>(point.row, point.col) = 0;
  }
  map->points = std::move(kept);
}

}  // namespace

std::vector<DenseMapPiece> BuildDenseMap(const DatasetManifest& manifest, const Camera& camera,
                                         const MappedRoute& route, double radius_m,
                                         const DenseMapPassOptions& options,
                                         const DenseMapPieceSink& on_finished) {
  std::vector<DenseMapPiece> pieces;
  if (!options.enabled) return pieces;
  // Each straight piece: its cylinder, the wall between its first and last camera's feet on the
  // axis, with phi = 0 towards its section's first camera's upright (-y). The key frames that see a
  // piece's wall in the band: from a little behind its start (a wall point is seen from r / tan(50
  // deg) = 0.84 r behind it down to beside it) to its end.
  const double behind_m = radius_m / std::tan(options.appearance.min_colatitude_deg * M_PI / 180);
  std::map<int, std::vector<int>> pieces_of_keyframe;
  std::map<int, Eigen::Vector3d> section_up;
  std::vector<DenseMapPiece> planned = CutPieces(route, options.piece_length_m);
  for (DenseMapPiece& piece : planned) {
    const Eigen::Isometry3d& origin = route.world_from_cam[piece.first_keyframe];
    const Eigen::Vector3d far = route.world_from_cam[piece.last_keyframe].translation();
    const std::optional<SectionCylinderFit> fit =
        FitSectionCylinder(route.points, piece.section, origin, far, radius_m, radius_m);
    if (!fit || fit->median_distance_m > 0.05 * radius_m) {
      piece.cylinder.radius_m = 0.0;  // not mapped
      continue;
    }
    const PipeAxis axis = SectionCylinderAxis(*fit, origin, far);
    if (!section_up.count(piece.section)) {
      section_up[piece.section] = -origin.linear().col(1);
    }
    piece.fit_median_m = fit->median_distance_m;
    piece.cylinder.axis_point = axis.point;
    piece.cylinder.axis_direction = axis.direction;
    piece.cylinder.radius_m = radius_m;
    piece.cylinder.begin_m = (origin.translation() - axis.point).dot(axis.direction);
    piece.cylinder.end_m = (far - axis.point).dot(axis.direction);
    piece.cylinder.reference_direction = section_up[piece.section];
  }
  for (const DenseMapPiece& piece : TPieces(route, radius_m)) planned.push_back(piece);
  for (DenseMapPiece& piece : planned) {
    if (piece.cylinder.radius_m <= 0.0) continue;
    if (piece.cylinder.end_m - piece.cylinder.begin_m < options.appearance.spacing_m) continue;
    const Eigen::Vector3d& axis_point = piece.cylinder.axis_point;
    const Eigen::Vector3d& axis_direction = piece.cylinder.axis_direction;
    const int index = static_cast<int>(pieces.size());
    for (int k = 0; k < static_cast<int>(route.world_from_cam.size()); ++k) {
      // Cameras inside this stretch of pipe only: one in the pipe across a T projects onto
      // the axis near the T too.
      const Eigen::Vector3d v = route.world_from_cam[k].translation() - axis_point;
      const double s = v.dot(axis_direction);
      if (s >= piece.cylinder.begin_m - behind_m && s <= piece.cylinder.end_m &&
          (v - s * axis_direction).norm() < radius_m) {
        pieces_of_keyframe[k].push_back(index);
      }
    }
    pieces.push_back(piece);
  }
  if (pieces.empty()) return pieces;
  // A T's two pieces follow each other; each loses the cells inside the other's cylinder.
  std::vector<std::optional<DenseMapCylinder>> open_inside(pieces.size());
  for (std::size_t p = 0; p + 1 < pieces.size(); ++p) {
    if (pieces[p].part == DenseMapPart::kTRed && pieces[p + 1].part == DenseMapPart::kTBlue &&
        pieces[p].section == pieces[p + 1].section) {
      open_inside[p] = pieces[p + 1].cylinder;
      open_inside[p + 1] = pieces[p].cylinder;
    }
  }

  // The key frames used: every one at least keyframe_spacing_m along the path from the last.
  std::map<int, int> keyframe_of_frame;
  Eigen::Vector3d last_used = Eigen::Vector3d::Constant(1e300);
  for (const auto& [k, of] : pieces_of_keyframe) {
    const Eigen::Vector3d centre = route.world_from_cam[k].translation();
    if ((centre - last_used).norm() < options.keyframe_spacing_m) continue;
    last_used = centre;
    keyframe_of_frame[route.frame_index[k]] = k;
  }
  // Each piece's accumulator lives from its first frame read to its last, so a long route holds
  // only the few pieces around the camera.
  std::vector<int> last_frame(pieces.size(), -1);
  for (const auto& [frame, k] : keyframe_of_frame) {
    for (const int p : pieces_of_keyframe[k]) last_frame[p] = std::max(last_frame[p], frame);
  }
  std::vector<std::unique_ptr<DenseAppearanceAccumulator>> accumulators(pieces.size());
  std::vector<bool> finished(pieces.size(), false);
  // A piece's accumulator, made when first needed (a piece no frame was read for: an empty map).
  const auto accumulator = [&](int p) -> DenseAppearanceAccumulator& {
    if (!accumulators[p]) {
      accumulators[p] =
          std::make_unique<DenseAppearanceAccumulator>(pieces[p].cylinder, options.appearance);
    }
    return *accumulators[p];
  };
  const auto finish = [&](int p) {
    pieces[p].keyframes_used = accumulator(p).num_key_frames();
    pieces[p].map = accumulator(p).Result();
    accumulators[p].reset();
    if (open_inside[p]) RemoveCellsInside(*open_inside[p], &pieces[p].map);
    finished[p] = true;
    if (on_finished) {
      on_finished(p, pieces[p]);
      pieces[p].map = DenseAppearanceMap{};
    }
  };
  // The gain mask (000 §3.2) takes out the light's and the lens's fall-off, which is the same
  // in every frame of a pipe: without it each cell's mean carries the shading of the image
  // places it was seen at. Scaled by the mask's mean, the map keeps about the frames' grey range.
  cv::Mat factors;
  const cv::Mat mask =
      ReadDatasetGainMask(manifest.gain_mask_path, camera.Width(), camera.Height());
  if (!mask.empty()) factors = GainCorrectionFactors(mask) * cv::mean(mask)[0];
  auto source = ImageSource::Open(manifest, {camera.Width(), camera.Height()});
  cv::Mat grey;
  while (std::optional<Frame> frame = source->Next()) {
    const auto found = keyframe_of_frame.find(static_cast<int>(frame->index));
    if (found == keyframe_of_frame.end()) continue;
    const int k = found->second;
    if (factors.empty()) {
      grey = frame->grey;
    } else {
      frame->grey.convertTo(grey, CV_32F);
      grey = grey.mul(factors);
    }
    const Eigen::Isometry3d cam_from_world = route.world_from_cam[k].inverse();
    for (const int p : pieces_of_keyframe[k]) {
      accumulator(p).AddKeyFrame(camera, cam_from_world, grey);
      if (last_frame[p] == static_cast<int>(frame->index)) finish(p);
    }
  }
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    if (!finished[p]) finish(static_cast<int>(p));  // a frame it waited for was not read
  }
  return pieces;
}

}  // namespace pipescope
