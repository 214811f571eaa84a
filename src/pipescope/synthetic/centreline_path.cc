#include "pipescope/synthetic/centreline_path.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pipescope {
namespace {

void AddLine(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
             std::vector<CentrelinePath::Piece>* pieces, double* length) {
  const double piece_length = (to - from).norm();
  if (piece_length <= 1e-12) return;
  CentrelinePath::Piece piece;
  piece.start_s = *length;
  piece.length = piece_length;
  piece.start = from;
  piece.direction = (to - from) / piece_length;
  pieces->push_back(piece);
  *length += piece_length;
}

}  // namespace

CentrelinePath::CentrelinePath(const std::vector<Eigen::Vector3d>& points, double corner_radius) {
  if (points.size() < 2) throw std::invalid_argument("a path needs at least two points");
  Eigen::Vector3d cursor = points.front();
  for (std::size_t i = 1; i + 1 < points.size(); ++i) {
    const Eigen::Vector3d in = (points[i] - points[i - 1]).normalized();
    const Eigen::Vector3d out = (points[i + 1] - points[i]).normalized();
    const double turn = std::acos(std::clamp(in.dot(out), -1.0, 1.0));
    if (turn < 1e-9) continue;  // collinear: no corner
    // The arc's tangent points lie R tan(turn / 2) before and after the corner.
    const double setback = corner_radius * std::tan(turn / 2.0);
    const Eigen::Vector3d arc_start = points[i] - setback * in;
    const Eigen::Vector3d arc_end = points[i] + setback * out;
    if ((arc_start - cursor).dot(in) < -1e-9 ||
        setback > (points[i + 1] - points[i]).norm() + 1e-9) {
      throw std::invalid_argument("path leg too short for its corner radius");
    }
    AddLine(cursor, arc_start, &pieces_, &length_);
    Piece arc;
    arc.is_arc = true;
    arc.start_s = length_;
    arc.start = arc_start;
    arc.direction = in;
    arc.axis = in.cross(out).normalized();
    arc.radius = corner_radius;
    arc.angle = turn;
    arc.center = arc_start + corner_radius * arc.axis.cross(in);
    arc.length = corner_radius * turn;
    pieces_.push_back(arc);
    length_ += arc.length;
    cursor = arc_end;
  }
  AddLine(cursor, points.back(), &pieces_, &length_);
}

void CentrelinePath::Evaluate(double s, Eigen::Vector3d* point, Eigen::Vector3d* tangent) const {
  s = std::clamp(s, 0.0, length_);
  // Pieces are few (a handful per route); a linear scan is cheaper than anything cleverer.
  auto it = std::find_if(pieces_.begin(), pieces_.end(),
                         [s](const Piece& p) { return s <= p.start_s + p.length; });
  const Piece& piece = it == pieces_.end() ? pieces_.back() : *it;
  const double local = std::clamp(s - piece.start_s, 0.0, piece.length);
  if (!piece.is_arc) {
    *point = piece.start + local * piece.direction;
    *tangent = piece.direction;
    return;
  }
  const Eigen::AngleAxisd rotation(local / piece.radius, piece.axis);
  *point = piece.center + rotation * (piece.start - piece.center);
  *tangent = rotation * piece.direction;
}

}  // namespace pipescope
