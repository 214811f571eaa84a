#include "pipescope/mapping/unrolled_mosaic_pass.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>

#include "pipescope/image/gain_mask.h"
#include "pipescope/io/image_source.h"
#include "pipescope/mapping/unrolled_mosaic.h"
#include "pipescope/util/progress.h"

namespace pipescope {

UnrolledMosaicMap MosaicAtPoses(
    const DatasetManifest& manifest, const Camera& camera, const cv::Mat& gain_mask,
    const std::map<std::size_t, Eigen::Isometry3d>& world_from_cam_by_frame, double radius_m,
    double pixel_m, double reach_m, double spacing_m) {
  UnrolledMosaicMap map;
  if (world_from_cam_by_frame.empty()) return map;
  double h_min = INFINITY, h_max = -INFINITY;
  for (const auto& [index, pose] : world_from_cam_by_frame) {
    h_min = std::min(h_min, pose.translation().z());
    h_max = std::max(h_max, pose.translation().z());
  }
  UnrolledMosaic mosaic(camera, radius_m, pixel_m, h_min - reach_m, h_max + reach_m);
  // The frames at least spacing_m along the pipe from the last one taken, chosen before reading
  // so that the others are not decoded.
  std::set<std::size_t> taken;
  double last_h = -INFINITY;
  for (const auto& [index, pose] : world_from_cam_by_frame) {
    if (std::abs(pose.translation().z() - last_h) < spacing_m) continue;
    last_h = pose.translation().z();
    taken.insert(index);
  }
  ImageSourceOptions source_options{camera.Width(), camera.Height()};
  source_options.wanted = [&taken](std::size_t index) { return taken.count(index) > 0; };
  auto source = ImageSource::Open(manifest, source_options);
  ProgressBar progress("mosaic", source->FrameCount());
  while (std::optional<Frame> frame = source->Next()) {
    progress.Update(frame->index + 1);
    const auto pose = world_from_cam_by_frame.find(frame->index);
    mosaic.Add(gain_mask.empty() ? frame->grey : ApplyGainMask(frame->grey, gain_mask),
               pose->second);
  }
  progress.Finish();
  // Only the band the camera saw: a wall-looking camera covers a fraction of the circumference.
  const cv::Rect covered = mosaic.CoveredRegion();
  map.image = mosaic.Render(covered);
  map.pixel_m = pixel_m;
  map.origin_m = {mosaic.grid().h0_m + covered.x * pixel_m,
                  mosaic.grid().s0_m + covered.y * pixel_m};
  return map;
}

}  // namespace pipescope
