#include "pipescope/geometry/camera_mount.h"

#include <gtest/gtest.h>

#include <cmath>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

TEST(MountedStartPose, WallLookingCameraFacesTheFloorWithImageXDownThePipe) {
  const Eigen::Isometry3d pose = MountedStartPose({"x"}, 0.2, 0.15);
  // Camera x down the pipe (+Z), optical axis at the wall phi = 90 deg (+Y).
  EXPECT_TRUE(pose.linear().col(0).isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(pose.linear().col(2).isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_NEAR(pose.linear().determinant(), 1.0, 1e-12);
  // 0.15 m from the wall at Y = 0.2.
  EXPECT_TRUE(pose.translation().isApprox(Eigen::Vector3d(0, 0.05, 0)));
  for (const char* axis : {"-x", "y", "-y"}) {
    const Eigen::Isometry3d other = MountedStartPose({axis}, 0.2, 0.15);
    EXPECT_NEAR(other.linear().determinant(), 1.0, 1e-12) << axis;
    const int column = axis[std::string(axis).size() - 1] == 'x' ? 0 : 1;
    const double sign = axis[0] == '-' ? -1.0 : 1.0;
    EXPECT_TRUE(other.linear().col(column).isApprox(sign * Eigen::Vector3d::UnitZ())) << axis;
  }
  EXPECT_THROW(MountedStartPose({"z"}, 0.2, 0.15), InputError);
}

// A camera facing a plane: the pixel of a plane point, for a pinhole camera with focal length f
// and principal point p.
Eigen::Vector2d ProjectPlanePoint(const Eigen::Isometry3d& world_from_cam,
                                  const Eigen::Vector3d& point, double f, Eigen::Vector2d p) {
  const Eigen::Vector3d in_cam = world_from_cam.inverse() * point;
  return f * in_cam.head<2>() / in_cam.z() + p;
}

// Checks ApplyImageMotion against the projective geometry it inverts: the image motion of a
// known camera motion over a plane is measured from projected points, turned back into a pose
// and compared with the true one.
TEST(ApplyImageMotion, RecoversTheCameraMotionOverAPlane) {
  const double f = 400.0, distance = 0.25, zeta = f / distance;
  const Eigen::Vector2d p(161.3, 118.2);  // principal point, off the image centre
  const cv::Point2d centre(159.5, 119.5);
  const Eigen::Isometry3d start = MountedStartPose({"x"}, 0.3, distance);
  for (const double psi : {0.0, 0.03, -0.07}) {
    Eigen::Isometry3d moved = start;
    moved.translation() += start.linear() * Eigen::Vector3d(0.004, -0.0015, 0.0);
    moved.linear() = start.linear() * Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()).matrix();
    // Two plane points: the one seen at the image centre, and another, give the rotation and
    // the shift of x -> R(a)(x - c) + c + shift.
    auto plane_point = [&](Eigen::Vector2d pixel) {
      const Eigen::Vector3d bearing((pixel - p).x() / f, (pixel - p).y() / f, 1.0);
      return Eigen::Vector3d(start * (distance * bearing));
    };
    const Eigen::Vector2d c(centre.x, centre.y), other(40.0, 200.0);
    const Eigen::Vector2d c_next = ProjectPlanePoint(moved, plane_point(c), f, p);
    const Eigen::Vector2d other_next = ProjectPlanePoint(moved, plane_point(other), f, p);
    const Eigen::Vector2d before = other - c, after = other_next - c_next;
    const double rotation = std::atan2(after.y(), after.x()) - std::atan2(before.y(), before.x());
    const cv::Point2d shift(c_next.x() - c.x(), c_next.y() - c.y());
    const Eigen::Isometry3d estimate =
        ApplyImageMotion(start, shift, rotation, zeta, {p.x(), p.y()}, centre);
    EXPECT_NEAR((estimate.translation() - moved.translation()).norm(), 0.0, 1e-12) << psi;
    EXPECT_TRUE(estimate.linear().isApprox(moved.linear(), 1e-12)) << psi;
  }
}

TEST(ApplyImageMotion, ContentMovingLeftMeansTheCameraMovedDownThePipe) {
  const Eigen::Isometry3d start = MountedStartPose({"x"}, 0.2, 0.15);
  const Eigen::Isometry3d next =
      ApplyImageMotion(start, {-5.0, 0.0}, 0.0, 1000.0, {80, 60}, {79.5, 59.5});
  EXPECT_TRUE((next.translation() - start.translation()).isApprox(Eigen::Vector3d(0, 0, 0.005)));
}

}  // namespace
}  // namespace pipescope
