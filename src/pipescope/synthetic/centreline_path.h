#pragma once

#include <Eigen/Core>
#include <vector>

namespace pipescope {

// The robot's route along the pipe: straight pieces joined by circular arcs, a C1 curve
// parameterised by arc length. Built from a polyline whose corners are rounded with a radius, so
// one description serves a bent tube (the radius is the bend's) and a turn at a T (a radius that
// keeps the robot inside the junction).
class CentrelinePath {
 public:
  // `points` are the polyline's vertices (at least two); each interior corner is replaced by an
  // arc of `corner_radius` tangent to both legs. Throws std::invalid_argument when a leg is too
  // short for its arcs.
  CentrelinePath(const std::vector<Eigen::Vector3d>& points, double corner_radius);

  struct Piece {
    bool is_arc = false;
    double start_s = 0.0;  // arc length at the piece's start
    double length = 0.0;
    Eigen::Vector3d start;
    Eigen::Vector3d direction;  // unit tangent at the start
    // Arcs only: centre, unit normal of the turn plane (tangent rotates about it), radius, angle.
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    double radius = 0.0;
    double angle = 0.0;
  };

  double Length() const { return length_; }
  const std::vector<Piece>& pieces() const { return pieces_; }

  // Point and unit tangent at arc length s (clamped to [0, Length()]).
  void Evaluate(double s, Eigen::Vector3d* point, Eigen::Vector3d* tangent) const;

 private:
  std::vector<Piece> pieces_;
  double length_ = 0.0;
};

}  // namespace pipescope
