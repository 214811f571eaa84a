#include "pipescope/pipeline/dense_map_pass.h"

#include <cmath>
#include <map>
#include <memory>

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

}  // namespace

std::vector<DenseMapPiece> BuildDenseMap(const DatasetManifest& manifest, const Camera& camera,
                                         const MappedRoute& route, double radius_m,
                                         const DenseMapPassOptions& options) {
  std::vector<DenseMapPiece> pieces;
  if (!options.enabled) return pieces;
  // Each piece: its cylinder, the wall between its first and last camera's feet on the axis,
  // with phi = 0 towards its section's first camera's upright (-y).
  std::vector<std::unique_ptr<DenseAppearanceAccumulator>> accumulators;
  // The key frames that see a piece's wall in the band: from a little behind its start (a
  // wall point is seen from r / tan(50 deg) = 0.84 r behind it down to beside it) to its end.
  const double behind_m = radius_m / std::tan(options.appearance.min_colatitude_deg * M_PI / 180);
  std::map<int, std::vector<int>> pieces_of_keyframe;
  std::map<int, Eigen::Vector3d> section_up;
  for (DenseMapPiece& piece : CutPieces(route, options.piece_length_m)) {
    const Eigen::Isometry3d& origin = route.world_from_cam[piece.first_keyframe];
    const Eigen::Vector3d far = route.world_from_cam[piece.last_keyframe].translation();
    const std::optional<SectionCylinderFit> fit =
        FitSectionCylinder(route.points, piece.section, origin, far, radius_m, radius_m);
    if (!fit || fit->median_distance_m > 0.05 * radius_m) continue;
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
    if (piece.cylinder.end_m - piece.cylinder.begin_m < options.appearance.spacing_m) continue;
    const int index = static_cast<int>(pieces.size());
    for (int k = 0; k < static_cast<int>(route.world_from_cam.size()); ++k) {
      // Cameras inside this stretch of pipe only: one in the pipe across a T projects onto
      // the axis near the T too.
      const Eigen::Vector3d v = route.world_from_cam[k].translation() - axis.point;
      const double s = v.dot(axis.direction);
      if (s >= piece.cylinder.begin_m - behind_m && s <= piece.cylinder.end_m &&
          (v - s * axis.direction).norm() < radius_m) {
        pieces_of_keyframe[k].push_back(index);
      }
    }
    accumulators.push_back(
        std::make_unique<DenseAppearanceAccumulator>(piece.cylinder, options.appearance));
    pieces.push_back(piece);
  }
  if (pieces.empty()) return pieces;

  // The key frames used: every one at least keyframe_spacing_m along the path from the last.
  std::map<int, int> keyframe_of_frame;
  Eigen::Vector3d last_used = Eigen::Vector3d::Constant(1e300);
  for (const auto& [k, of] : pieces_of_keyframe) {
    const Eigen::Vector3d centre = route.world_from_cam[k].translation();
    if ((centre - last_used).norm() < options.keyframe_spacing_m) continue;
    last_used = centre;
    keyframe_of_frame[route.frame_index[k]] = k;
  }
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
      accumulators[p]->AddKeyFrame(camera, cam_from_world, grey);
    }
  }
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    pieces[p].keyframes_used = accumulators[p]->num_key_frames();
    pieces[p].map = accumulators[p]->Result();
  }
  return pieces;
}

}  // namespace pipescope
