#include "pipescope/mapping/tube_centreline.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

Eigen::Vector3d FootOnAxis(const TubeSection& section, const Eigen::Vector3d& point) {
  return section.CentrelinePoint(section.ArcCoordinate(point));
}

// The arc of a bending section is drawn as chords of this angle (their length falls short of the
// arc's by a 30 000th).
constexpr double kArcStepRad = 2.0 * M_PI / 180.0;

// The segment index and parameter (metres from its first vertex, unclamped at the two ends) of
// the point's foot on the polyline.
void NearestSegment(const TubeCentreline& centreline, const Eigen::Vector3d& point, int* segment,
                    double* along) {
  const int segments = static_cast<int>(centreline.points.size()) - 1;
  double best = std::numeric_limits<double>::infinity();
  *segment = 0;
  *along = 0.0;
  for (int i = 0; i < segments; ++i) {
    const Eigen::Vector3d& a = centreline.points[i];
    const double length = centreline.arc_m[i + 1] - centreline.arc_m[i];
    if (length <= 0.0) continue;
    const Eigen::Vector3d direction = (centreline.points[i + 1] - a) / length;
    double t = (point - a).dot(direction);
    const double lower = i == 0 ? -std::numeric_limits<double>::infinity() : 0.0;
    const double upper = i == segments - 1 ? std::numeric_limits<double>::infinity() : length;
    t = std::clamp(t, lower, upper);
    const double distance = (a + t * direction - point).squaredNorm();
    if (distance < best) {
      best = distance;
      *segment = i;
      *along = t;
    }
  }
}

}  // namespace

TubeCentreline BuildTubeCentreline(const std::vector<TubeSection>& sections,
                                   const Eigen::Vector3d& first_position,
                                   const Eigen::Vector3d& last_position,
                                   const Eigen::Vector3d& phi_zero) {
  if (sections.empty()) throw InputError("BuildTubeCentreline: no sections");
  TubeCentreline centreline;
  auto add = [&](const Eigen::Vector3d& point, int section) {
    if (!centreline.points.empty() && (point - centreline.points.back()).norm() < 1e-9) {
      centreline.section.back() = section;
      centreline.radius_m.back() = sections[section].Radius();
      return;
    }
    centreline.arc_m.push_back(centreline.points.empty()
                                   ? 0.0
                                   : centreline.arc_m.back() +
                                         (point - centreline.points.back()).norm());
    centreline.points.push_back(point);
    centreline.section.push_back(section);
    centreline.radius_m.push_back(sections[section].Radius());
  };
  // Vertices along a bending section's arc, after its first vertex, up to `to`.
  auto add_arc = [&](int i, const Eigen::Vector3d& to) {
    const TubeSection& section = sections[i];
    if (!section.Curved() || centreline.points.empty()) return;
    const double from_s = section.ArcCoordinate(centreline.points.back());
    const double to_s = section.ArcCoordinate(to);
    const double step = kArcStepRad / section.curvature.norm();
    const int steps = static_cast<int>(std::abs(to_s - from_s) / step);
    for (int k = 1; k <= steps; ++k) {
      add(section.CentrelinePoint(from_s + (to_s - from_s) * k / (steps + 1.0)), i);
    }
  };
  add(FootOnAxis(sections.front(), first_position), 0);
  for (std::size_t i = 1; i < sections.size(); ++i) {
    const Eigen::Vector3d junction = SectionJunction(sections[i - 1], sections[i]);
    add_arc(static_cast<int>(i) - 1, junction);
    add(junction, static_cast<int>(i));
  }
  const TubeSection& last = sections.back();
  const Eigen::Vector3d end =
      last.CentrelinePoint(std::max(0.0, last.ArcCoordinate(last_position)));
  add_arc(static_cast<int>(sections.size()) - 1, end);
  add(end, static_cast<int>(sections.size()) - 1);
  if (centreline.points.size() < 2) {
    // A run that did not move: one vertex a radius further along, so the frame is defined.
    add(centreline.points.back() + last.Radius() * last.axis,
        static_cast<int>(sections.size()) - 1);
  }

  // The sections' tangents at the vertices: a vertex leaves along its own section and arrives
  // along the section of the vertex before.
  const std::size_t vertices = centreline.points.size();
  for (std::size_t i = 0; i < vertices; ++i) {
    const Eigen::Vector3d& point = centreline.points[i];
    const TubeSection& leaving = sections[centreline.section[i]];
    const TubeSection& arriving = sections[centreline.section[i > 0 ? i - 1 : 0]];
    centreline.tangents_out.push_back(leaving.TangentAt(leaving.ArcCoordinate(point)));
    centreline.tangents_in.push_back(arriving.TangentAt(arriving.ArcCoordinate(point)));
  }
  // Parallel transport of phi = 0: turn the previous normal by the rotation taking the previous
  // tangent to the next.
  Eigen::Vector3d tangent = (centreline.points[1] - centreline.points[0]).normalized();
  Eigen::Vector3d normal = phi_zero - phi_zero.dot(tangent) * tangent;
  if (normal.norm() < 1e-6) normal = tangent.unitOrthogonal();
  normal.normalize();
  for (std::size_t i = 0; i + 1 < centreline.points.size(); ++i) {
    const Eigen::Vector3d next = (centreline.points[i + 1] - centreline.points[i]).normalized();
    normal = Eigen::Quaterniond::FromTwoVectors(tangent, next) * normal;
    normal = (normal - normal.dot(next) * next).normalized();
    tangent = next;
    centreline.normals.push_back(normal);
  }
  return centreline;
}

double ArcLengthAlong(const TubeCentreline& centreline, const Eigen::Vector3d& point) {
  int segment = 0;
  double along = 0.0;
  NearestSegment(centreline, point, &segment, &along);
  return centreline.arc_m[segment] + along;
}

CentrelineFrame CentrelineFrameAt(const TubeCentreline& centreline, double arc_m) {
  const int segments = static_cast<int>(centreline.points.size()) - 1;
  int segment =
      static_cast<int>(std::upper_bound(centreline.arc_m.begin(), centreline.arc_m.end(), arc_m) -
                       centreline.arc_m.begin() - 1);
  segment = std::clamp(segment, 0, segments - 1);
  while (segment > 0 && centreline.arc_m[segment + 1] - centreline.arc_m[segment] <= 0.0) --segment;
  CentrelineFrame frame;
  const double length = centreline.arc_m[segment + 1] - centreline.arc_m[segment];
  const Eigen::Vector3d direction =
      (centreline.points[segment + 1] - centreline.points[segment]) / length;
  const double t = arc_m - centreline.arc_m[segment];
  frame.point = centreline.points[segment] + t * direction;
  frame.radius_m = centreline.radius_m[segment];
  // Along the segment the sections' tangent turns from its start to its end (a bending
  // section's chord; constant on a straight one).
  const Eigen::Vector3d& start = centreline.tangents_out[segment];
  const Eigen::Vector3d& end = centreline.tangents_in[segment + 1];
  const double share = std::clamp(t / length, 0.0, 1.0);
  Eigen::Vector3d tangent =
      Eigen::Quaterniond::Identity().slerp(share, Eigen::Quaterniond::FromTwoVectors(start, end)) *
      start;
  // Near a vertex where the sections meet at an angle, towards its bisector: half the angle
  // within `reach` of the vertex, as a mitred joint's rings turn.
  const double reach = std::min(frame.radius_m, 0.5 * length);
  auto towards_bisector = [&](int vertex, double distance, const Eigen::Vector3d& own) {
    if (vertex <= 0 || vertex >= static_cast<int>(centreline.points.size()) - 1) return;
    if (distance >= reach) return;
    const Eigen::Vector3d sum = centreline.tangents_in[vertex] + centreline.tangents_out[vertex];
    // A camera that turned back starts a section the other way: no bisector, no mitre.
    if (sum.norm() < 1e-6) return;
    tangent += (1.0 - distance / reach) * (sum.normalized() - own);
  };
  towards_bisector(segment, t, start);
  towards_bisector(segment + 1, length - t, end);
  frame.tangent = tangent.normalized();
  const Eigen::Vector3d& normal = centreline.normals[segment];
  frame.normal = (normal - normal.dot(frame.tangent) * frame.tangent).normalized();
  frame.binormal = frame.tangent.cross(frame.normal);
  return frame;
}

void WriteCentrelineCsv(const std::filesystem::path& path, const TubeCentreline& centreline) {
  std::ostringstream out;
  out << std::setprecision(9) << "arc_m,x_m,y_m,z_m,radius_m,section\n";
  for (std::size_t i = 0; i < centreline.points.size(); ++i) {
    const Eigen::Vector3d& p = centreline.points[i];
    out << centreline.arc_m[i] << ',' << p.x() << ',' << p.y() << ',' << p.z() << ','
        << centreline.radius_m[i] << ',' << centreline.section[i] << '\n';
  }
  WriteTextFileAtomically(path, out.str());
}

void WriteCentrelinePly(const std::filesystem::path& path, const TubeCentreline& centreline) {
  const std::size_t n = centreline.points.size();
  std::ostringstream out;
  out << std::setprecision(9) << "ply\nformat ascii 1.0\n"
      << "comment pipescope tube centreline (metres), radius per vertex\n"
      << "element vertex " << n << "\nproperty double x\nproperty double y\nproperty double z\n"
      << "property double radius\nelement edge " << (n > 0 ? n - 1 : 0)
      << "\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = centreline.points[i];
    out << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << centreline.radius_m[i] << '\n';
  }
  for (std::size_t i = 0; i + 1 < n; ++i) out << i << ' ' << i + 1 << '\n';
  WriteTextFileAtomically(path, out.str());
}

}  // namespace pipescope
